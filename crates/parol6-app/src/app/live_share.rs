//! Live sharing in the window: File → *Share live* and the status bar's toggle start the
//! Foxglove WebSocket server ([`crate::live::foxglove`]) on the active backend's recorder, at
//! [`Settings::share_live_address`](crate::panels::Settings::share_live_address) (localhost
//! unless another address is given), and stop it. Sharing is off at every start. When the
//! active backend changes (a robot connected or disconnected) the server is started again on
//! the new one's recorder, at the same address; clients reconnect.
//!
//! The remote-control switch (File → *Allow remote control*, off at start) is the one
//! [`RemoteControl`] every live server of the window shares; while it is on the status bar
//! shows a banner, and every change is logged to `/events`.

use crate::live::{LiveServer, LiveSource, RemoteControl};
use crate::panels::LiveStatus;

use super::Parol6App;

/// The window's live sharing.
pub(super) struct LiveShare {
    /// The running server, and whether it serves the robot (else the simulation).
    server: Option<(Box<dyn LiveServer>, bool)>,
    /// The remote-control switch.
    pub(super) remote: RemoteControl,
    /// What the panels show (refreshed each frame).
    pub(super) status: LiveStatus,
}

impl LiveShare {
    pub(super) fn new() -> Self {
        Self { server: None, remote: RemoteControl::new(false, None), status: LiveStatus::default() }
    }
}

impl Parol6App {
    /// Starts (`on`) or stops sharing live; the outcome is a notice.
    pub(super) fn share_live(&mut self, on: bool) {
        if let Some((server, _)) = self.live.server.take() {
            let stats = server.stop();
            if !on {
                let sent = stats["messages_sent"].as_u64().unwrap_or(0);
                let clients = stats["clients_seen"].as_u64().unwrap_or(0);
                self.notice(format!("stopped sharing live ({clients} clients, {sent} messages sent)"), false);
            }
        }
        if on {
            match self.start_live_server() {
                Ok(server) => {
                    self.notice(format!("sharing live at {} (Foxglove WebSocket)", server.address()), false);
                    self.live.server = Some((server, self.hw.is_some()));
                }
                Err(e) => self.notice(format!("Share live: {e}"), true),
            }
        }
        self.refresh_live_status();
    }

    fn start_live_server(&mut self) -> Result<Box<dyn LiveServer>, String> {
        let addr =
            crate::live::bind_address(Some(&self.settings.share_live_address), crate::live::FOXGLOVE_DEFAULT_PORT)?;
        let backend = self.backend();
        let recorder = self.active_recorder().ok_or("no telemetry recorder for the active backend")?;
        // the window's recordings carry the URDF text; the embedded PAROL6's when none was given
        let urdf_text = match self.recording_info.urdf_text.as_str() {
            "" if self.model.is_parol6 => parol6_core::model::PAROL6_URDF,
            text => text,
        };
        let source = LiveSource {
            model: &self.model,
            urdf_text,
            recorder,
            remote: self.live.remote.logging_to(Some(recorder.events())),
            backend,
        };
        start_foxglove(&source, addr)
    }

    /// Turns remote control on or off (logged to `/events`).
    pub(super) fn set_remote_control(&mut self, on: bool) {
        self.live.remote = self.live.remote.logging_to(self.active_recorder().map(|r| r.events()));
        self.live.remote.set_allowed(on);
        let text = if on {
            "remote control ON: commands from the network can move the arm (STOP and the dead-man still win)"
        } else {
            "remote control off: commands from the network are refused"
        };
        self.notice(text, on);
        self.refresh_live_status();
    }

    /// Each frame: a server follows the active backend; the panels' view of the sharing.
    pub(super) fn live_share_frame(&mut self) {
        let on_robot = self.hw.is_some();
        if self.live.server.as_ref().is_some_and(|(_, robot)| *robot != on_robot) {
            self.share_live(true);
        }
        self.refresh_live_status();
    }

    fn refresh_live_status(&mut self) {
        let status = LiveStatus {
            sharing: self.live.server.as_ref().map(|(s, _)| s.address()),
            remote_control: self.live.remote.allowed(),
        };
        if status != self.live.status {
            self.live.status = status;
        }
    }

    /// Where clients connect while the window shares live (`None`: not sharing).
    pub fn sharing_live(&self) -> Option<String> {
        self.live.status.sharing.clone()
    }

    /// The remote-control switch the window's live servers share.
    pub fn remote_control(&self) -> &RemoteControl {
        &self.live.remote
    }
}

#[cfg(feature = "foxglove")]
fn start_foxglove(source: &LiveSource<'_>, addr: std::net::SocketAddr) -> Result<Box<dyn LiveServer>, String> {
    crate::live::foxglove::FoxgloveServer::start(source, addr)
        .map(|s| Box::new(s) as Box<dyn LiveServer>)
        .map_err(|e| format!("{addr}: {e}"))
}

#[cfg(not(feature = "foxglove"))]
fn start_foxglove(_source: &LiveSource<'_>, _addr: std::net::SocketAddr) -> Result<Box<dyn LiveServer>, String> {
    Err("this parol6 was built without the `foxglove` feature".into())
}

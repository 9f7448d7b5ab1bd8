//! Live sharing in the window: File → *Share live* and the status bar's toggle start the
//! Foxglove WebSocket server ([`crate::live::foxglove`]) on the active backend's recorder, at
//! [`Settings::share_live_address`](crate::panels::Settings::share_live_address) (localhost
//! unless another address is given), and stop it. Sharing is off at every start. When the
//! active backend changes (a robot connected or disconnected) the server is started again on
//! the new one's recorder, at the same address; clients reconnect.
//!
//! File → *Share over ROS 2* and the status bar's *ROS 2* toggle start the ROS 2 node over
//! Zenoh ([`crate::live::ros2`], as `parol6 serve --ros2` does) at
//! [`Settings::ros2_router`](crate::panels::Settings::ros2_router); its session opens on a
//! thread of its own (the window never waits on the network), and the status bar says
//! "ROS 2 starting…" meanwhile. It follows the active backend as sharing does.
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
    /// The running ROS 2 node, and whether it serves the robot.
    ros2: Option<(Box<dyn LiveServer>, bool)>,
    /// The ROS 2 node being started, and whether it will serve the robot.
    #[cfg(feature = "ros2")]
    ros2_pending: Option<(crate::live::ros2::PendingRos2, bool)>,
    /// The remote-control switch.
    pub(super) remote: RemoteControl,
    /// What the panels show (refreshed each frame).
    pub(super) status: LiveStatus,
}

impl LiveShare {
    pub(super) fn new() -> Self {
        Self {
            server: None,
            ros2: None,
            #[cfg(feature = "ros2")]
            ros2_pending: None,
            remote: RemoteControl::new(false, None),
            status: LiveStatus::default(),
        }
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
        start_foxglove(&self.live_source()?, addr)
    }

    /// Starts (`on`: in the background) or stops the ROS 2 node; the outcome is a notice.
    pub(super) fn share_ros2(&mut self, on: bool) {
        #[cfg(feature = "ros2")]
        let starting = self.live.ros2_pending.take().is_some();
        #[cfg(not(feature = "ros2"))]
        let starting = false;
        if let Some((server, _)) = self.live.ros2.take() {
            let stats = server.stop();
            if !on {
                let sent = stats["joint_states_sent"].as_u64().unwrap_or(0);
                let got = stats["trajectories_received"].as_u64().unwrap_or(0);
                self.notice(
                    format!("ROS 2 node stopped ({sent} joint states sent, {got} trajectories received)"),
                    false,
                );
            }
        } else if starting && !on {
            self.notice("ROS 2 start cancelled", false);
        }
        if on && let Err(e) = self.start_ros2() {
            self.notice(format!("Share over ROS 2: {e}"), true);
        }
        self.refresh_live_status();
    }

    #[cfg(feature = "ros2")]
    fn start_ros2(&mut self) -> Result<(), String> {
        let opts = crate::live::ros2::Ros2Options {
            connect: crate::live::tcp_endpoints("router", std::slice::from_ref(&self.settings.ros2_router))?,
            domain_id: self.settings.ros2_domain,
            ..Default::default()
        };
        let pending = crate::live::ros2::Ros2Server::start_in_background(&self.live_source()?, &opts)?;
        self.live.ros2_pending = Some((pending, self.hw.is_some()));
        Ok(())
    }

    #[cfg(not(feature = "ros2"))]
    fn start_ros2(&mut self) -> Result<(), String> {
        Err("this parol6 was built without the `ros2` feature".into())
    }

    /// Each frame: a ROS 2 start that ended becomes the running node or a notice.
    #[cfg(feature = "ros2")]
    fn poll_ros2_start(&mut self) {
        let Some(result) = self.live.ros2_pending.as_ref().and_then(|(p, _)| p.try_take()) else {
            return;
        };
        let Some((_, on_robot)) = self.live.ros2_pending.take() else {
            return;
        };
        match result {
            Ok(server) => {
                self.notice(format!("ROS 2 node parol6 up: {}", server.address()), false);
                self.live.ros2 = Some((Box::new(server), on_robot));
            }
            Err(e) => self.notice(format!("Share over ROS 2: {e}"), true),
        }
        self.refresh_live_status();
    }

    /// What a live server serves: the active backend, its recorder and the URDF.
    fn live_source(&self) -> Result<LiveSource<'_>, String> {
        let backend = self.backend();
        let recorder = self.active_recorder().ok_or("no telemetry recorder for the active backend")?;
        // the window's recordings carry the URDF text; the embedded PAROL6's when none was given
        let urdf_text = match self.recording_info.urdf_text.as_str() {
            "" if self.model.is_parol6 => parol6_core::model::PAROL6_URDF,
            text => text,
        };
        Ok(LiveSource {
            model: &self.model,
            urdf_text,
            recorder,
            remote: self.live.remote.logging_to(Some(recorder.events())),
            backend,
        })
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

    /// Each frame: a server follows the active backend. The panels' view of the sharing is
    /// refreshed where it changes (start, stop, a ROS 2 start ending, the remote switch), not
    /// per frame.
    pub(super) fn live_share_frame(&mut self) {
        let on_robot = self.hw.is_some();
        if self.live.server.as_ref().is_some_and(|(_, robot)| *robot != on_robot) {
            self.share_live(true);
        }
        #[cfg(feature = "ros2")]
        {
            self.poll_ros2_start();
            let pending_on = self.live.ros2_pending.as_ref().map(|(_, robot)| *robot);
            if self.live.ros2.as_ref().map(|(_, robot)| *robot).or(pending_on).is_some_and(|robot| robot != on_robot) {
                self.share_ros2(true);
            }
        }
    }

    fn refresh_live_status(&mut self) {
        let status = LiveStatus {
            sharing: self.live.server.as_ref().map(|(s, _)| s.address()),
            ros2: self.live.ros2.as_ref().map(|(s, _)| s.address()),
            #[cfg(feature = "ros2")]
            ros2_starting: self.live.ros2_pending.is_some(),
            #[cfg(not(feature = "ros2"))]
            ros2_starting: false,
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

    /// The ROS 2 node's address while it runs (`None`: off or still starting).
    pub fn sharing_ros2(&self) -> Option<String> {
        self.live.status.ros2.clone()
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

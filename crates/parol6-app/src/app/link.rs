//! The serial link to a controller (a real port or the built-in emulator): opening it, and the
//! connection panel's view of it. Motion goes through the session's `RobotBackend` like the
//! simulation's; only link operations (enable, disable, the homing routine) are link-specific.

use std::sync::Arc;
use std::time::Instant;

use eframe::egui;
use parol6_core::RobotModel;
use parol6_core::motion::RobotBackend as _;

use super::ConnectTarget;

/// How long the built-in emulator's homing takes, s.
const EMULATED_HOMING_S: f64 = 3.0;
/// Frames the built-in emulator logs until a test takes them (a minute of the 100 Hz loop,
/// 88 bytes each: 0.5 MB). Its default, 200 000 frames (17.6 MB), filled over the first 33
/// minutes of a window left running: the one-hour soak's growth after the live ring was full.
const EMULATOR_LOG_FRAMES: usize = 6_000;

/// Where a homing stands, in the operator's words ("" before any was asked for).
pub(super) fn homing_text(h: &parol6_hw::HomingState, homed: &[bool]) -> String {
    use parol6_hw::HomingState as H;
    match h {
        H::NotRequested => String::new(),
        H::Sending => "homing: HOME sent…".to_string(),
        H::Waiting => {
            let done: Vec<String> =
                homed.iter().enumerate().filter(|(_, h)| **h).map(|(i, _)| format!("J{}", i + 1)).collect();
            let done = if done.is_empty() { "none yet".to_string() } else { done.join(" ") };
            format!("homing: waiting for the joints (homed: {done})")
        }
        H::Done => "homing done: all joints homed".to_string(),
        H::Failed(why) => format!("homing failed: {why}"),
    }
}

/// A backend's sample tap.
type Tap = crossbeam_channel::Sender<parol6_core::motion::MotionSample>;
use crate::panels::connection::LinkView;

/// An open serial session (real port or the built-in emulator).
pub(super) struct HwLink {
    pub(super) session: Arc<parol6_hw::Session>,
    /// Kept alive while connected; dropping it stops the emulator.
    pub(super) emulator: Option<parol6_hw::EmulatorHandle>,
    pub(super) emulated: bool,
    pub(super) last_fault: Option<String>,
    /// When the port was opened (to say when no controller answers).
    pub(super) opened_at: Instant,
    /// The link state the operator was last told about.
    pub(super) told: Option<parol6_hw::LinkState>,
    /// The homing outcome the operator was last told about.
    pub(super) told_homing: parol6_hw::HomingState,
    /// Telemetry of the link (fed by the session's sample tap).
    pub(super) recorder: Option<parol6_core::telemetry::Recorder>,
    /// The tracking mode the session streams in (chosen at connection).
    pub(super) tracking: parol6_core::motion::tracking::TrackingMode,
}

impl HwLink {
    pub(super) fn connect(
        target: &ConnectTarget,
        model: &RobotModel,
        tracking: parol6_core::motion::tracking::TrackingMode,
    ) -> anyhow::Result<Self> {
        if !model.is_parol6 {
            anyhow::bail!("the serial link drives a PAROL6 only; this model is \"{}\"", model.name);
        }
        // the tool's TCP: the robot's read-outs and jogs are the tool tip's, as the simulation's
        let config =
            parol6_hw::SessionConfig { tracking, tool_in_flange: model.tool, ..parol6_hw::SessionConfig::default() };
        let recorder = super::telemetry::start_recorder(model);
        let tap = recorder.as_ref().map(parol6_core::telemetry::Recorder::tap);
        let mut link = match target {
            ConnectTarget::Port(p) => {
                let session = parol6_hw::Session::open_with_tap(p, config, tap)?;
                Self::new(session, None)
            }
            ConnectTarget::Emulator => Self::connect_emulator(config, tap)?,
        };
        link.recorder = recorder;
        link.tracking = tracking;
        Ok(link)
    }

    fn new(session: parol6_hw::Session, emulator: Option<parol6_hw::EmulatorHandle>) -> Self {
        Self {
            recorder: None,
            tracking: parol6_core::motion::tracking::TrackingMode::default(),
            session: Arc::new(session),
            emulated: emulator.is_some(),
            emulator,
            last_fault: None,
            opened_at: Instant::now(),
            told: None,
            told_homing: parol6_hw::HomingState::NotRequested,
        }
    }

    #[cfg(unix)]
    fn connect_emulator(config: parol6_hw::SessionConfig, tap: Option<Tap>) -> anyhow::Result<Self> {
        // homing takes a few seconds, as on a board (its progress shows in the panel)
        let config_emu = parol6_hw::EmulatorConfig {
            home_duration_s: EMULATED_HOMING_S,
            log_frames_max: EMULATOR_LOG_FRAMES,
            ..parol6_hw::EmulatorConfig::homed_at_standby()
        };
        // on a local socket, not a pty: a busy host delays a pty's bytes (issue 32)
        let emu = parol6_hw::EmulatorHandle::spawn_socket(config_emu)?;
        let session = parol6_hw::Session::open_with_tap(emu.path(), config, tap)?;
        Ok(Self::new(session, Some(emu)))
    }

    #[cfg(not(unix))]
    fn connect_emulator(_config: parol6_hw::SessionConfig, _tap: Option<Tap>) -> anyhow::Result<Self> {
        anyhow::bail!("the built-in emulator needs a Unix-domain socket (Unix only)")
    }

    pub(super) fn view(&self, snap: &parol6_hw::Snapshot) -> LinkView {
        LinkView {
            port: snap.port.clone(),
            emulated: self.emulated,
            link_ok: snap.link == parol6_hw::LinkState::Connected,
            link_state: format!("{:?}", snap.link),
            enabled: snap.status.is_some() && snap.enabled.unwrap_or(true) && !snap.needs_enable,
            estop: snap.estop_pressed,
            homing: matches!(snap.homing, parol6_hw::HomingState::Sending | parol6_hw::HomingState::Waiting),
            homing_text: homing_text(&snap.homing, &snap.homed),
            homed: snap.homed.to_vec(),
            loop_rate_hz: snap.loop_rate_hz,
            jitter_ms: snap.period_jitter_p99_ms,
            dropped_frames: snap.invalid_frames + snap.missing_replies,
            implausible_frames: snap.implausible_frames,
            last_error: snap.fault.clone(),
        }
    }
}

impl super::Parol6App {
    /// The state shown this frame: the active backend's, computed on its own thread. Until the
    /// controller has sent a first status there is no measured pose: the simulation's is shown
    /// (not the board's zeros).
    pub(super) fn robot_state(&self) -> Arc<parol6_core::motion::RobotState> {
        let state = match &self.hw {
            Some(link) if link.session.snapshot().status.is_some() => link.session.state(),
            _ => self.sim.state(),
        };
        if !self.estop {
            return state;
        }
        // the latched E-stop is why motion is refused, whatever the backend says
        let mut latched = (*state).clone();
        latched.blocked = Some(crate::panels::io_gripper::ESTOP_LATCHED.to_string());
        Arc::new(latched)
    }
}

/// The window's title while the simulation is shown.
pub const TITLE_SIMULATION: &str = "PAROL6 Studio — simulation";

impl super::Parol6App {
    /// Robot or simulation, impossible to miss: the window's title names it ("— ROBOT on PORT",
    /// "— ROBOT (built-in emulator)"),
    /// and while the robot is shown a frame in the robot colour runs round the whole window.
    pub(super) fn source_marks(&mut self, ctx: &egui::Context, source: parol6_core::motion::StateSource) {
        let title = match source {
            parol6_core::motion::StateSource::Robot => match &self.hw {
                // the built-in emulator's port is a socket path, which says nothing to a user
                Some(link) if link.emulated => "PAROL6 Studio — ROBOT (built-in emulator)".to_string(),
                Some(link) => format!("PAROL6 Studio — ROBOT on {}", link.session.snapshot().port),
                None => "PAROL6 Studio — ROBOT".to_string(),
            },
            parol6_core::motion::StateSource::Simulation => TITLE_SIMULATION.to_string(),
        };
        if self.window_title.as_deref() != Some(title.as_str()) {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.window_title = Some(title);
        }
        if source == parol6_core::motion::StateSource::Robot {
            let layer = egui::LayerId::new(egui::Order::Foreground, egui::Id::unique("parol6_robot_frame"));
            let stroke = egui::Stroke::new(3.0, crate::palette::rgb(crate::palette::SOURCE_ROBOT));
            ctx.layer_painter(layer).rect_stroke(ctx.content_rect(), 0.0, stroke, egui::StrokeKind::Inside);
        }
    }
}

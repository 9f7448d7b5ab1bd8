//! Operator panels. One panel = one file implementing [`Panel`]; the app ([`crate::app`]) owns
//! them, hands each a [`PanelContext`] per frame and executes the [`AppCommand`]s they queue.
//!
//! Panels never talk to the simulation or the serial session directly: they read the
//! [`RobotState`] of this frame and queue commands, so the same panel drives the simulation or
//! the real robot.

use eframe::egui;
use std::time::Instant;

use parol6_core::RobotModel;
pub use parol6_core::angles::{AbcConvention, AngleConvention};
use parol6_core::limits::LimitZone;
use parol6_core::motion::MotionCommand;
use serde::{Deserialize, Serialize};

pub mod angle_text;
pub mod cartesian_jog;
pub mod cartesian_target;
pub mod connection;
pub mod dynamics;
pub mod entry;
pub mod fixed_box;
pub mod help;
pub mod io_gripper;
pub mod joints;
pub mod measure;
pub mod plot_axis;
pub mod plot_cache;
pub mod plot_export;
pub mod plot_line;
pub mod plot_stretches;
pub mod plots;
pub mod program;
pub mod registry;
pub mod replace_ask;
pub mod shortcuts;
pub mod status_bar;
pub mod step_fields;
pub mod tcp;
pub mod timeline;
pub mod torque_form;

/// A panel of the operator UI.
pub trait Panel {
    /// Heading shown above the panel.
    fn title(&self) -> &'static str;
    /// Draws the panel for this frame.
    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>);
    /// Draws what must stay on screen whatever the column's scroll (default: nothing), above
    /// the scrolled part of a side column: the joints panel's HOME, STOP and E-STOP.
    fn pinned_ui(&mut self, _ui: &mut egui::Ui, _ctx: &mut PanelContext<'_>) {}
    /// Whether the panel is shown now (default: always), from the settings and the app's state.
    fn shown(&self, _ctx: &PanelContext<'_>) -> bool {
        true
    }
}

/// Angle display unit, chosen once for the whole UI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum AngleUnit {
    /// Degrees.
    #[default]
    Deg,
    /// Radians.
    Rad,
}

impl AngleUnit {
    /// Radians → display unit.
    pub fn from_rad(self, rad: f64) -> f64 {
        let v = match self {
            AngleUnit::Deg => rad.to_degrees(),
            AngleUnit::Rad => rad,
        };
        // No "-0.00" for values that round to zero.
        if v.abs() < 5e-7 { 0.0 } else { v }
    }

    /// Display unit → radians.
    pub fn to_rad(self, v: f64) -> f64 {
        match self {
            AngleUnit::Deg => v.to_radians(),
            AngleUnit::Rad => v,
        }
    }

    /// Unit suffix (`°` or ` rad`).
    pub fn suffix(self) -> &'static str {
        match self {
            AngleUnit::Deg => "°",
            AngleUnit::Rad => " rad",
        }
    }

    /// Decimals shown for this unit.
    pub fn decimals(self) -> usize {
        match self {
            AngleUnit::Deg => 2,
            AngleUnit::Rad => 4,
        }
    }

    /// Formats an angle given in radians, with its unit.
    pub fn fmt(self, rad: f64) -> String {
        format!("{}{}", entry::fmt_fixed(self.from_rad(rad), self.decimals()), self.suffix())
    }
}

pub use crate::app::settings::{LOWER_DEFAULT_HEIGHT, ProfileKindSetting, RECENT_PROGRAMS, Settings};
pub use parol6_core::motion::{RobotState, StateSource};
pub use parol6_core::program::runner::{RunOptions, RunProgress, RunnerControl};

/// Something a panel asks the app to do after the UI pass.
#[derive(Debug, Clone, PartialEq)]
pub enum AppCommand {
    /// A motion command for the active backend (simulation or robot; the same meaning on
    /// both). STOP also ends a running program.
    Motion(MotionCommand),
    /// A motion from a value typed into a field, committed by Enter, Tab or focus loss. It runs
    /// as [`AppCommand::Motion`], unless a click in the same frame (the click that took the field's
    /// keyboard) set the arm moving otherwise: then it is dropped, with a notice.
    TypedMotion(MotionCommand),
    /// Hold-to-run jog of joint `joint` (0-based) in `direction` (±1) while `Some`; `None`
    /// releases. The app repeats the jog command within the dead-man time while held.
    Jog(Option<(usize, i8)>),
    /// Hold-to-run Cartesian jog (frame, axis, signed speed fraction) while `Some`; `None`
    /// releases. The app repeats it within the dead-man time while held.
    CartesianJog(Option<(parol6_core::motion::JogFrame, parol6_core::motion::CartesianAxis, f64)>),
    /// Run a program off the UI thread on the active backend (pre-flight first, unless its
    /// check is given and holds for where the arm stands).
    RunProgram {
        /// The program.
        program: std::sync::Arc<parol6_core::program::Program>,
        /// Its check (of this program at this speed), reused by the runner from the same start.
        checked: Option<std::sync::Arc<parol6_core::program::check::CheckedProgram>>,
        /// Speed override, single step, loop.
        opts: RunOptions,
    },
    /// Pause, resume, single-step or stop the running program.
    Program(RunnerControl),
    /// Start the ISO 9283 pose test on the active backend (the measurement panel follows it).
    StartMeasurement(parol6_core::measure::PoseTestPlan),
    /// Abort the running ISO 9283 pose test (STOP and the E-stop abort it too).
    AbortMeasurement,
    /// Clear the TCP trail of the 3D view.
    ClearTrail,
    /// Reset the 3D camera.
    ResetView,
    /// Hardware link command (connection panel).
    Link(LinkCommand),
    /// Open a recording (MCAP) for replay.
    OpenRecording(std::path::PathBuf),
    /// Close the open recording (back to live).
    CloseRecording,
    /// Move the replay cursor to this motion time, s, and pause.
    SeekReplay(f64),
    /// Play, pause, change the speed of or scrub the open recording.
    Replay(timeline::ReplayControl),
    /// Start writing the active backend to this MCAP file (`None`: stop writing).
    Record(Option<std::path::PathBuf>),
    /// Start (`true`) or stop sharing the active backend live (Foxglove WebSocket at
    /// [`Settings::share_live_address`]).
    ShareLive(bool),
    /// Start (`true`) or stop the ROS 2 node over Zenoh (at [`Settings::ros2_router`]).
    ShareRos2(bool),
    /// Turn remote control (commands from the network) on or off; a banner shows while it is on.
    RemoteControl(bool),
    /// Forward dynamics: run these joint torques on the simulation (refused on the robot).
    RunTorques(parol6_core::sim::TorqueRun),
    /// An output, the gripper, CLEAR ERROR or the drives, on the active backend (the same
    /// `RobotBackend::io` for the simulation and the robot).
    Io(parol6_core::motion::IoCommand),
    /// The E-stop button: `true` sends STOP and DISABLE and latches (every motion command is
    /// refused, naming [`io_gripper::ESTOP_LATCHED`]); `false` releases it with ENABLE.
    EStop(bool),
}

/// Commands of the connection panel, executed by the app against the serial session.
#[derive(Debug, Clone, PartialEq)]
pub enum LinkCommand {
    /// Connect to a serial port.
    Connect(String),
    /// Start the built-in controller emulator and connect to it.
    ConnectEmulator,
    /// Close the link.
    Disconnect,
    /// Enable the drives.
    Enable,
    /// Disable the drives.
    Disable,
    /// Run the controller's homing routine.
    Home,
}

/// `v`, or exactly 0 when `|v| < eps`: values that print as zero then print without a sign
/// (no "-0.00").
pub fn zero_if_below(v: f64, eps: f64) -> f64 {
    if v.abs() < eps { 0.0 } else { v }
}

/// Refresh rate of numeric readouts while the arm moves, Hz.
pub const READOUT_HZ: f64 = 15.0;

/// Performance figures shown in the status bar.
#[derive(Debug, Clone, Default)]
pub struct PerfStats {
    /// Frames per second (smoothed over the last second).
    pub fps: f64,
    /// CPU time of the last UI pass, ms.
    pub ui_cpu_ms: f64,
    /// Physics step rate, Hz.
    pub physics_rate_hz: f64,
    /// Last physics step duration, µs.
    pub physics_step_us: f64,
    /// Last command latency (send → applied), ms.
    pub command_latency_ms: Option<f64>,
}

/// A message shown to the operator (banner at the top of the 3D view).
#[derive(Debug, Clone)]
pub struct Notice {
    /// Text.
    pub text: String,
    /// True for errors (red), false for information.
    pub error: bool,
    /// When it was raised.
    pub at: Instant,
}

impl Notice {
    /// Adds a notice raised now to `list`. The same message already shown is not stacked again
    /// (a jog held against the workspace edge raises it on every key repeat): it is renewed and
    /// moved to the end.
    pub fn raise(list: &mut Vec<Notice>, text: String, error: bool) {
        list.retain(|n| n.text != text || n.error != error);
        list.push(Notice { text, error, at: Instant::now() });
    }

    /// Takes back the information notices (not errors) that `stale` picks: what a later notice
    /// answers ("waiting for it to answer" once it answered, "opening FILE" once it replays) no
    /// longer stands beside the answer (trial 21 m3).
    pub fn withdraw(list: &mut Vec<Notice>, stale: impl Fn(&str) -> bool) {
        list.retain(|n| n.error || !stale(&n.text));
    }
}

/// The per-frame context handed to every panel.
pub struct PanelContext<'a> {
    /// The robot.
    pub model: &'a RobotModel,
    /// Shown state (sliders, LEDs, bars, the 3D view): the live backend's, or during replay
    /// the recording at the cursor (`AppState::replayed_robot`).
    pub robot: &'a RobotState,
    /// The live backend's state, also during replay: the arm that a program would move, so a
    /// program's pre-flight starts from it (moving the replay cursor checks nothing again).
    pub live_robot: &'a RobotState,
    /// The state for numeric readouts: `robot`, refreshed at [`READOUT_HZ`] while the arm
    /// moves and at once when it stops. Text that changes every frame costs a fresh text layout
    /// every frame; nobody reads digits faster than this anyway.
    pub readout: &'a RobotState,
    /// Persistent settings.
    pub settings: &'a mut Settings,
    /// Commands to execute after the UI pass.
    pub commands: &'a mut Vec<AppCommand>,
    /// Notices to show.
    pub notices: &'a mut Vec<Notice>,
    /// Performance figures (refreshed with [`PanelContext::readout`]).
    pub perf: &'a PerfStats,
    /// Ghost pose to preview in the 3D view (e.g. an IK solution); the app shows it this frame.
    pub preview: &'a mut Option<Vec<f64>>,
    /// What the app owns (the open recording, the program run, the file being written, the
    /// serial link): read here, changed only through [`AppCommand`]s.
    pub app: &'a crate::app::state::AppState,
    /// Live sharing: where clients connect while it is on, and whether remote control is on.
    pub live: &'a LiveStatus,
}

/// The window's live sharing, as the panels show it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LiveStatus {
    /// Where clients connect (`ws://127.0.0.1:8765`) while sharing is on.
    pub sharing: Option<String>,
    /// The ROS 2 node while it runs (its Zenoh peer and router).
    pub ros2: Option<String>,
    /// The ROS 2 node is being started (its session opens on a thread of its own).
    pub ros2_starting: bool,
    /// Commands from the network are carried out (the banner shows).
    pub remote_control: bool,
}

impl PanelContext<'_> {
    /// Why motion commands are refused now and the controls that send them are off (the
    /// latched E-stop or an open recording), `None` when they are accepted.
    pub fn motion_refused(&self) -> Option<&'static str> {
        match self.robot.blocked.as_deref() {
            Some(io_gripper::ESTOP_LATCHED) => Some(io_gripper::ESTOP_LATCHED),
            _ if self.app.replaying() => Some(crate::app::state::REPLAY_OPEN),
            _ => None,
        }
    }

    /// Why a jog by hand is refused now: [`Self::motion_refused`], or a program runs (not paused),
    /// an ISO 9283 test drives the arm or a torque run the simulation (the app refuses the
    /// command too; the jog panel greys its buttons and keys with the reason instead of
    /// reporting a jog that never ran).
    pub fn manual_motion_refused(&self) -> Option<&'static str> {
        use crate::app::state::{MEASUREMENT_RUNNING, PROGRAM_RUNNING, TORQUE_RUNNING};
        use parol6_core::program::runner::RunState;
        self.motion_refused().or_else(|| {
            if self.app.program.as_ref().is_some_and(|p| matches!(p.state, RunState::Preparing | RunState::Running)) {
                Some(PROGRAM_RUNNING)
            } else if self.app.measurement.running() {
                Some(MEASUREMENT_RUNNING)
            } else {
                self.app.torque_run.then_some(TORQUE_RUNNING)
            }
        })
    }

    /// Why Run torques is refused now (the app refuses the command for the same reasons): the
    /// latched E-stop or an open recording, the robot connected, a program not finished (paused
    /// too) or an ISO 9283 test running. A torque run under way is not a reason: a new run
    /// replaces it.
    pub fn torque_run_refused(&self) -> Option<&'static str> {
        use crate::app::state::{MEASUREMENT_RUNNING, PROGRAM_UNFINISHED, TORQUE_ON_ROBOT};
        self.motion_refused().or_else(|| {
            if self.app.link.is_some() {
                Some(TORQUE_ON_ROBOT)
            } else if self.app.program.as_ref().is_some_and(|p| !p.state.is_finished()) {
                Some(PROGRAM_UNFINISHED)
            } else {
                self.app.measurement.running().then_some(MEASUREMENT_RUNNING)
            }
        })
    }

    /// Queues a command.
    pub fn send(&mut self, command: AppCommand) {
        self.commands.push(command);
    }

    /// Shows an error to the operator.
    pub fn error(&mut self, text: impl Into<String>) {
        Notice::raise(self.notices, text.into(), true);
    }

    /// Shows information to the operator.
    pub fn info(&mut self, text: impl Into<String>) {
        Notice::raise(self.notices, text.into(), false);
    }

    /// Queues a motion command for the active backend.
    pub fn motion(&mut self, command: MotionCommand) {
        self.send(AppCommand::Motion(command));
    }

    /// A profiled move to `goal` with the current speed and profile settings.
    pub fn move_to(&mut self, goal: Vec<f64>) {
        let cmd = self.move_to_command(goal);
        self.motion(cmd);
    }

    /// [`Self::move_to`] for a goal typed into a field ([`AppCommand::TypedMotion`]).
    pub fn typed_move_to(&mut self, goal: Vec<f64>) {
        let cmd = self.move_to_command(goal);
        self.send(AppCommand::TypedMotion(cmd));
    }

    fn move_to_command(&self, goal: Vec<f64>) -> MotionCommand {
        MotionCommand::MoveJoints {
            goal_rad: goal,
            speed_fraction: self.settings.speed_fraction,
            profile: self.settings.profile.kind(),
        }
    }

    /// STOP: hold the commanded position now (also ends a running program).
    pub fn stop(&mut self) {
        self.motion(MotionCommand::Stop);
    }

    /// HOME: the profiled move to standby with the current speed and profile settings.
    pub fn home(&mut self) {
        let cmd =
            MotionCommand::Home { speed_fraction: self.settings.speed_fraction, profile: self.settings.profile.kind() };
        self.motion(cmd);
    }
}

/// The LED colour of a zone (from the core's one colour table).
pub fn zone_color(zone: LimitZone) -> egui::Color32 {
    let [r, g, b, a] = zone.rgba();
    egui::Color32::from_rgba_unmultiplied(r, g, b, a)
}

/// Paints a round LED of `color` and returns its response (hover it for `tooltip`).
pub fn led(ui: &mut egui::Ui, color: egui::Color32, tooltip: impl Into<egui::WidgetText>) -> egui::Response {
    let size = egui::vec2(14.0, 14.0);
    let (rect, response) = ui.allocate_exact_size(size, egui::Sense::hover());
    if ui.is_rect_visible(rect) {
        let p = ui.painter();
        p.circle_filled(rect.center(), 6.0, color);
        p.circle_stroke(rect.center(), 6.0, egui::Stroke::new(1.0, crate::palette::rgba(crate::palette::LED_RIM)));
    }
    response.on_hover_text(tooltip)
}

/// An LED that is on (`on_color`) or off (grey).
pub fn on_off_led(ui: &mut egui::Ui, on: bool, on_color: egui::Color32, label: &str) -> egui::Response {
    let c = if on { on_color } else { crate::palette::rgb(crate::palette::LED_OFF) };
    let r = led(ui, c, format!("{label}: {}", if on { "yes" } else { "no" }));
    ui.label(label);
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (issue 32): holding a jog against the workspace edge stacked one identical
    /// toast per key repeat; four covered the 3D view.
    #[test]
    fn the_same_notice_raised_again_is_renewed_not_stacked() {
        let mut list = Vec::new();
        for _ in 0..30 {
            Notice::raise(&mut list, "outside the workspace".into(), true);
        }
        Notice::raise(&mut list, "saved".into(), false);
        Notice::raise(&mut list, "outside the workspace".into(), true);
        let texts: Vec<&str> = list.iter().map(|n| n.text.as_str()).collect();
        assert_eq!(texts, ["saved", "outside the workspace"]);
        // the same words as information and as an error are two notices
        Notice::raise(&mut list, "saved".into(), true);
        assert_eq!(list.len(), 3);
    }
}

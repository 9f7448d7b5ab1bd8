//! What the app owns and the panels only read ([`AppState`], handed to every panel as
//! `PanelContext::app`): the open recording and its cursor, the program run's progress, the
//! measurement, the file being written, the serial link's figures. A panel changes it only by queuing an
//! [`AppCommand`](crate::panels::AppCommand), which `app/execute.rs` carries out after the UI pass.
//!
//! During replay the app hands the panels the recording at the cursor as the shown robot state
//! ([`AppState::replayed_robot`]), so every read-out that reads `PanelContext::robot` (joints,
//! TCP, limit LEDs, …) follows replay without knowing about it, and motion is refused with
//! [`REPLAY_OPEN`] until the recording is closed.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use parol6_core::RobotModel;
use parol6_core::motion::{RobotState, StateSource};
use parol6_core::telemetry::ReplayData;

use crate::panels::RunProgress;
use crate::panels::connection::LinkView;

/// Why a manual motion is refused while a program runs (not paused): the runner's next step would
/// start where the arm no longer is.
pub const PROGRAM_RUNNING: &str = "a program is running: pause (F6) or stop it first";

/// Why a manual motion is refused while an ISO 9283 test drives the arm: a pose would be measured
/// off its target.
pub const MEASUREMENT_RUNNING: &str = "an ISO 9283 test is moving the arm: Abort it (or STOP) first";

/// Why a manual motion (or a program, a measurement) is refused while a forward-dynamics torque
/// run drives the simulation: the motion would end the run half-way without a word (trial9).
pub const TORQUE_RUNNING: &str =
    "a forward-dynamics torque run is driving the arm: wait for its end or press Stop torques (or STOP) first";

/// Why a program run or a torque run is refused while a program runs or is paused.
pub const PROGRAM_UNFINISHED: &str = "a program is running: stop it first";

/// Why Run torques is refused while the robot is connected.
pub const TORQUE_ON_ROBOT: &str = "torque runs drive the simulation only: disconnect the robot first";

/// Why motion is refused while a recording is open: the shown state's `blocked` during replay,
/// and every refusal names it.
pub const REPLAY_OPEN: &str = "REPLAY: the read-outs show the recording; motion refused until the recording is closed";

/// The state the app owns and the panels read.
#[derive(Debug, Default)]
pub struct AppState {
    /// The open recording (replay), if any.
    pub replay: Option<Replay>,
    /// Progress of the running (or last) program, kept after it ends.
    pub program: Option<RunProgress>,
    /// The MCAP file being written, if any.
    pub recording: Option<FileRecording>,
    /// Serial link status, when a hardware session is open (refreshed every frame).
    pub link: Option<LinkView>,
    /// The ISO 9283 pose test: the running one and the last finished run on each backend.
    pub measurement: super::measurement::MeasurementState,
    /// A forward-dynamics torque run drives the simulation, and the simulation is shown (not
    /// the robot): manual motion is refused with [`TORQUE_RUNNING`] until it ends.
    pub torque_run: bool,
    /// How many motions other than a Cartesian step were set going (a program run, HOME, a joint
    /// move, a jog, a measurement, a torque run, the controller's homing), plus each Connect and
    /// Disconnect (the shown arm changes): the Cartesian jog panel's line and row of steps end
    /// when this changes (trial 29 m9: "+Y released after 41.64 mm" stayed over a fresh robot).
    pub other_motions: u64,
    /// How many STOPs and E-STOPs were given (Esc, the buttons): a jog they ended says so.
    pub stops: u64,
}

/// A file being written.
#[derive(Debug, Clone)]
pub struct FileRecording {
    /// The file.
    pub path: PathBuf,
    /// True when it records the serial link (it ends when the link closes).
    pub on_robot: bool,
    /// When it started (the status bar shows the time since).
    pub started: std::time::Instant,
}

impl AppState {
    /// The robot state to show this frame: the recording at the cursor while one is open
    /// (measured joints and velocities, the commanded pose as the target, moving while it plays, motion blocked with
    /// [`REPLAY_OPEN`]), else `None` (the live backend's). This is the one place a read-out is
    /// made to follow replay.
    pub fn replayed_robot(&self, model: &RobotModel, live: &RobotState) -> Option<RobotState> {
        let r = self.replay.as_ref()?;
        let (q, cmd) = r.joints_at_cursor()?;
        if q.len() != model.dof() {
            return None;
        }
        let mut s = RobotState::at_rest(model, live.source, &format!("replay of {}", r.file_name()), &q);
        s.time_s = r.cursor_s;
        s.qd = r.velocities_at_cursor().filter(|v| v.len() == q.len()).unwrap_or_else(|| vec![0.0; q.len()]);
        s.commanded.q.clone_from(&cmd);
        s.target_q = cmd;
        s.homed = true;
        // the recorded arm moves while the replay plays: the panels re-check (pre-flight,
        // dynamics) where it comes to rest, as for a live arm, and the read-outs refresh at their rate
        s.moving = r.playing;
        s.io = live.io;
        s.update_kinematics(model, &parol6_core::limits::ZoneThresholds::default());
        s.blocked = Some(REPLAY_OPEN.to_string());
        Some(s)
    }

    /// The serial link's health the open recording holds at the cursor (robot recordings;
    /// `None` live, for a simulation recording, or before the first record).
    pub fn replayed_link(&self) -> Option<&parol6_core::telemetry::LinkHealth> {
        let r = self.replay.as_ref()?;
        r.data.link_at(r.cursor_s)
    }

    /// True while a recording is open (the status bar says REPLAY, motion is refused).
    pub fn replaying(&self) -> bool {
        self.replay.is_some()
    }
}

/// How the shown state's source reads in the status bar and the window: SIM, ROBOT or REPLAY.
pub fn source_label(state: &AppState, source: StateSource) -> &'static str {
    match (state.replaying(), source) {
        (true, _) => "REPLAY",
        (false, StateSource::Simulation) => "SIM",
        (false, StateSource::Robot) => "ROBOT",
    }
}

/// An open recording and where its cursor is.
#[derive(Debug, Clone)]
pub struct Replay {
    /// The file.
    pub path: PathBuf,
    /// What it holds.
    pub data: Arc<ReplayData>,
    /// Cursor, motion time, s.
    pub cursor_s: f64,
    /// Playing (else paused).
    pub playing: bool,
    /// Playback speed (1 = real time).
    pub speed: f64,
    last_tick: Option<Instant>,
}

impl Replay {
    /// A replay of `data` with the cursor at its start, paused.
    pub fn new(path: PathBuf, data: Arc<ReplayData>) -> Self {
        let cursor_s = data.store.time_range_s().map_or(0.0, |(t0, _)| t0);
        Self { path, data, cursor_s, playing: false, speed: 1.0, last_tick: None }
    }

    /// First and last sample time, s (0, 0 when empty).
    pub fn span_s(&self) -> (f64, f64) {
        self.data.store.time_range_s().unwrap_or((0.0, 0.0))
    }

    /// Moves the cursor to `t_s` (clamped to the recording).
    pub fn seek(&mut self, t_s: f64) {
        let (t0, t1) = self.span_s();
        if t_s.is_finite() {
            self.cursor_s = t_s.clamp(t0, t1.max(t0));
        }
    }

    /// Starts playing (from the start when the cursor is at the end) or pauses.
    pub fn play(&mut self, playing: bool) {
        let (t0, t1) = self.span_s();
        if playing && !self.playing && self.cursor_s >= t1 {
            self.cursor_s = t0;
        }
        self.playing = playing;
    }

    /// Advances the cursor by the wall time since the last call × speed while playing; stops
    /// at the end. Returns true while playing (the window keeps repainting).
    pub fn advance(&mut self, now: Instant) -> bool {
        let last = self.last_tick.replace(now);
        if !self.playing {
            return false;
        }
        let dt_s = last.map_or(0.0, |l| now.duration_since(l).as_secs_f64().min(0.25));
        let (_, t1) = self.span_s();
        self.cursor_s = (self.cursor_s + dt_s * self.speed).min(t1);
        if self.cursor_s >= t1 {
            self.playing = false;
        }
        self.playing
    }

    /// Measured and commanded joint positions at the cursor, rad.
    pub fn joints_at_cursor(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        let store = &self.data.store;
        let (_, row) = store.row_at(self.cursor_s)?;
        let n = store.joints();
        let q: Vec<f64> = row.iter().take(n).map(|&v| f64::from(v)).collect();
        let err_col = 4 * n;
        let cmd = q.iter().enumerate().map(|(j, q)| q + row.get(err_col + j).map_or(0.0, |&e| f64::from(e))).collect();
        Some((q, cmd))
    }

    /// Measured joint velocities at the cursor, rad/s.
    pub fn velocities_at_cursor(&self) -> Option<Vec<f64>> {
        let store = &self.data.store;
        let (_, row) = store.row_at(self.cursor_s)?;
        let n = store.joints();
        Some(row.iter().skip(n).take(n).map(|&v| f64::from(v)).collect())
    }

    /// File name for headings.
    pub fn file_name(&self) -> String {
        self.path.file_name().map_or_else(|| self.path.display().to_string(), |n| n.to_string_lossy().into_owned())
    }
}

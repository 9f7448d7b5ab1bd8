//! The controller session: a dedicated thread that sends one command frame per period
//! (default 100 Hz), parses the status replies and publishes a [`Snapshot`] lock-free.
//!
//! The firmware has no CRC, no timeout and no limit checks, so this thread is the safety layer:
//! - every position target passes [`JointLimits::enforce`] and then a last check in steps
//!   ([`guard_frame`]), which also caps the speed the firmware's MOVE law would derive from it;
//! - motion is only ever streamed as MOVE targets with zero feed-forward (never JOG), so a lost
//!   host leaves the arm holding still; every frame carries zero speed fields;
//! - jogging needs refreshing within the dead-man time (200 ms) or it stops;
//! - no valid status for 50 ms → link loss: motion is cancelled and the port is re-opened
//!   every second;
//! - E-stop pressed → motion cancelled, DISABLE sent every period; after release motion needs
//!   an explicit [`Session::enable`];
//! - closing the session leaves the board with an IDLE frame (no stepping, zero speeds).

use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use arc_swap::ArcSwap;
use crossbeam_channel::{Receiver, Sender, TrySendError};
use parol6_core::limits::{JointLimits, LimitPolicy};
use parol6_core::parol6::{JOINT_COUNT, max_accel_rad_s2, rad_per_step};
use parol6_core::profile::{JointMove, ProfileKind};

use crate::HwError;
use crate::frame::{CommandCode, CommandFields, CommandFrame, GripperCommand, IO_OUT1, IO_OUT2, StatusFrame};
use crate::parser::StatusParser;
use crate::units::{
    jog_speed_steps_s, joints_rad_to_steps, joints_steps_to_rad, limits_steps, max_speed_steps_s, steps_to_rad,
};

/// Gripper command bits: activate.
pub const GRIPPER_ACTIVATE: u8 = 0x80;
/// Gripper command bits: action / move active.
pub const GRIPPER_MOVE: u8 = 0x40;
/// Gripper command bits: E-stop (set while the E-stop is pressed).
pub const GRIPPER_ESTOP: u8 = 0x20;
/// Gripper command bits: forwarded bit the API always sets ("grip enable").
pub const GRIPPER_ENABLE: u8 = 0x10;

/// The firmware MOVE law's gain: `v ≈ 50 · error` steps/s.
const FW_MOVE_GAIN_PER_S: i32 = 50;
/// Tick intervals kept for the rate / jitter statistics.
const TIMING_WINDOW: usize = 256;
/// Final IDLE frames sent when the session closes.
const CLOSING_FRAMES: u32 = 3;

/// Session settings.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionConfig {
    /// Command rate, Hz (50–500; default 100, which the firmware's MOVE law assumes).
    pub rate_hz: f64,
    /// No valid status for this long → link loss (default 50 ms).
    pub status_timeout: Duration,
    /// Re-open the port this often while the link is down (default 1 s).
    pub reconnect_interval: Duration,
    /// A jog stops unless refreshed within this time (default 200 ms).
    pub jog_deadman: Duration,
    /// Homing fails after this long (default 45 s).
    pub home_timeout: Duration,
    /// HOME frames sent before switching to IDLE (default 10, as the API does).
    pub home_frames: u32,
    /// Joint limits every target must pass.
    pub limits: JointLimits,
    /// Keep up to this many frame write times for [`Session::take_write_times`] (0 = off;
    /// used by `parol6 bench serial`).
    pub write_log_capacity: usize,
    /// Busy-wait this long before each deadline instead of sleeping, to cut wake-up latency on
    /// a loaded machine (costs that fraction of one core; default zero: off).
    pub spin_before_deadline: Duration,
}

impl Default for SessionConfig {
    fn default() -> Self {
        Self {
            rate_hz: 100.0,
            status_timeout: Duration::from_millis(50),
            reconnect_interval: Duration::from_secs(1),
            jog_deadman: Duration::from_millis(200),
            home_timeout: Duration::from_secs(45),
            home_frames: 10,
            limits: JointLimits::parol6(),
            write_log_capacity: 0,
            spin_before_deadline: Duration::ZERO,
        }
    }
}

impl SessionConfig {
    /// Checks the settings.
    pub fn validate(&self) -> Result<(), HwError> {
        if !(self.rate_hz.is_finite() && (50.0..=500.0).contains(&self.rate_hz)) {
            return Err(HwError::BadConfig(format!("rate {} Hz is outside 50–500 Hz", self.rate_hz)));
        }
        if self.limits.len() != JOINT_COUNT {
            return Err(HwError::BadConfig(format!("limits have {} joints, expected 6", self.limits.len())));
        }
        if self.status_timeout.is_zero() || self.jog_deadman.is_zero() || self.home_frames == 0 {
            return Err(HwError::BadConfig("timeouts and home_frames must be > 0".into()));
        }
        Ok(())
    }

    /// The command period.
    pub fn period(&self) -> Duration {
        Duration::from_secs_f64(1.0 / self.rate_hz)
    }
}

/// State of the serial link.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum LinkState {
    /// Port open, waiting for the first valid status.
    Connecting,
    /// Valid status frames arriving.
    Connected,
    /// No valid status for longer than the status timeout, or the port failed; retrying.
    Lost,
    /// The session has ended.
    Closed,
}

/// What the session is streaming.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum MotionState {
    /// IDLE frames: no stepping.
    Idle,
    /// MOVE frames holding a fixed target.
    Holding,
    /// Jogging one joint (0-based) at a speed fraction.
    Jogging {
        /// 0-based joint.
        joint: usize,
        /// Speed fraction −1…1.
        fraction: f64,
    },
    /// Streaming a planned move.
    Moving {
        /// Time since the move started, s.
        elapsed_s: f64,
        /// Planned duration, s.
        duration_s: f64,
    },
    /// Homing (HOME, then IDLE frames).
    Homing,
}

/// Progress of the last homing request.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum HomingState {
    /// No homing requested in this session.
    NotRequested,
    /// Sending HOME frames.
    Sending,
    /// Waiting for all homed bits.
    Waiting,
    /// All six joints homed.
    Done,
    /// Homing failed; the reason.
    Failed(String),
}

/// What the session knows, published after every period.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Snapshot {
    /// Port path.
    pub port: String,
    /// Link state.
    pub link: LinkState,
    /// Latest valid status frame.
    pub status: Option<StatusFrame>,
    /// Joint positions, steps.
    pub joint_steps: [i32; JOINT_COUNT],
    /// Joint positions, rad.
    pub joint_rad: [f64; JOINT_COUNT],
    /// Joint speed set points, steps/s.
    pub joint_speed_steps_s: [i32; JOINT_COUNT],
    /// Joint speed set points, rad/s.
    pub joint_speed_rad_s: [f64; JOINT_COUNT],
    /// Homed flags.
    pub homed: [bool; JOINT_COUNT],
    /// E-stop input pressed.
    pub estop_pressed: bool,
    /// INPUT1, INPUT2, OUTPUT1, OUTPUT2 levels as reported.
    pub io: [bool; 4],
    /// Gripper position 0–255 as reported.
    pub gripper_position: i16,
    /// Gripper current, mA, as reported.
    pub gripper_current_ma: i16,
    /// Raw gripper status byte.
    pub gripper_status: u8,
    /// Enabled as last commanded in this session (`None`: not commanded yet; the board powers
    /// up enabled).
    pub enabled: Option<bool>,
    /// True after an E-stop until [`Session::enable`] is called.
    pub needs_enable: bool,
    /// What is being streamed.
    pub motion: MotionState,
    /// Homing progress.
    pub homing: HomingState,
    /// Last MOVE target sent, steps.
    pub target_steps: Option<[i32; JOINT_COUNT]>,
    /// Last command code sent.
    pub last_command: Option<CommandCode>,
    /// Configured rate, Hz.
    pub rate_hz: f64,
    /// Achieved loop rate over the last ~256 periods, Hz.
    pub loop_rate_hz: f64,
    /// 99th percentile of |period − nominal| over the last ~256 periods, ms.
    pub period_jitter_p99_ms: f64,
    /// Largest |period − nominal| over the last ~256 periods, ms.
    pub period_jitter_max_ms: f64,
    /// Command frames written.
    pub frames_sent: u64,
    /// Valid status frames received.
    pub status_frames: u64,
    /// Status candidates rejected by the parser (bad end bytes).
    pub invalid_frames: u64,
    /// Bytes discarded while resynchronising.
    pub discarded_bytes: u64,
    /// Frames sent that got no reply (sent − received).
    pub missing_replies: u64,
    /// Frames the last-line guard had to alter or replace.
    pub guard_trips: u64,
    /// Successful re-opens of the port.
    pub reconnects: u64,
    /// Last fault (link loss, E-stop, refused request, homing failure …).
    pub fault: Option<String>,
    /// Age of the latest valid status when this snapshot was published, ms.
    pub status_age_ms: Option<f64>,
    #[serde(skip)]
    /// When the latest valid status arrived.
    pub last_status_at: Option<Instant>,
    #[serde(skip)]
    /// When this snapshot was published.
    pub published_at: Instant,
}

impl Snapshot {
    fn new(port: &str, rate_hz: f64) -> Self {
        Self {
            port: port.to_string(),
            link: LinkState::Connecting,
            status: None,
            joint_steps: [0; JOINT_COUNT],
            joint_rad: [0.0; JOINT_COUNT],
            joint_speed_steps_s: [0; JOINT_COUNT],
            joint_speed_rad_s: [0.0; JOINT_COUNT],
            homed: [false; JOINT_COUNT],
            estop_pressed: false,
            io: [false; 4],
            gripper_position: 0,
            gripper_current_ma: 0,
            gripper_status: 0,
            enabled: None,
            needs_enable: false,
            motion: MotionState::Idle,
            homing: HomingState::NotRequested,
            target_steps: None,
            last_command: None,
            rate_hz,
            loop_rate_hz: 0.0,
            period_jitter_p99_ms: 0.0,
            period_jitter_max_ms: 0.0,
            frames_sent: 0,
            status_frames: 0,
            invalid_frames: 0,
            discarded_bytes: 0,
            missing_replies: 0,
            guard_trips: 0,
            reconnects: 0,
            fault: None,
            status_age_ms: None,
            last_status_at: None,
            published_at: Instant::now(),
        }
    }

    /// Age of the latest valid status now.
    pub fn status_age(&self) -> Option<Duration> {
        self.last_status_at.map(|t| t.elapsed())
    }

    /// True when all six joints are homed.
    pub fn all_homed(&self) -> bool {
        self.homed.iter().all(|&h| h)
    }

    /// True when motion requests would currently be accepted (link up, no E-stop, enabled).
    pub fn motion_allowed(&self) -> Result<(), HwError> {
        if self.link != LinkState::Connected {
            return Err(HwError::Refused(format!("link is {:?}", self.link)));
        }
        if self.estop_pressed {
            return Err(HwError::Refused("E-stop is pressed".into()));
        }
        if self.needs_enable {
            return Err(HwError::Refused("E-stop was pressed: enable the controller first".into()));
        }
        if self.enabled == Some(false) {
            return Err(HwError::Refused("controller is disabled: enable it first".into()));
        }
        if matches!(self.homing, HomingState::Sending | HomingState::Waiting) {
            return Err(HwError::Refused("homing is in progress".into()));
        }
        Ok(())
    }

    /// The snapshot as JSON (what `parol6 hw status` prints).
    pub fn to_json(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).unwrap_or(serde_json::Value::Null);
        if let Some(obj) = v.as_object_mut() {
            obj.insert(
                "joint_deg".into(),
                serde_json::json!(self.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>()),
            );
            obj.insert("all_homed".into(), serde_json::json!(self.all_homed()));
        }
        v
    }
}

/// Requests from the API to the session thread.
#[derive(Debug, Clone)]
enum Request {
    OneShot(CommandCode),
    Home,
    Jog { joint: usize, fraction: f64, at: Instant },
    JogRelease,
    MoveTo { goal_rad: Vec<f64>, speed_fraction: f64, kind: ProfileKind },
    Stop,
    Gripper { position: i16, speed: i16, current_ma: i16 },
    GripperMode(u8),
    Output { index: u8, level: bool },
    Shutdown,
}

/// A running controller session. Cheap calls: each request is queued to the session thread
/// (bounded channel) and takes effect at the next period. Dropping it closes the session.
pub struct Session {
    tx: Sender<Request>,
    write_times: Option<Receiver<Instant>>,
    shared: Arc<ArcSwap<Snapshot>>,
    thread: Option<JoinHandle<()>>,
    config: SessionConfig,
}

impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Session").field("port", &self.snapshot().port).finish()
    }
}

impl Session {
    /// Opens `port` and starts the session thread.
    pub fn open(port: &str, config: SessionConfig) -> Result<Session, HwError> {
        config.validate()?;
        let serial = crate::ports::open_port(port)?;
        let (tx, rx) = crossbeam_channel::bounded(256);
        let (write_tx, write_times) = if config.write_log_capacity > 0 {
            let (t, r) = crossbeam_channel::bounded(config.write_log_capacity);
            (Some(t), Some(r))
        } else {
            (None, None)
        };
        let shared = Arc::new(ArcSwap::from_pointee(Snapshot::new(port, config.rate_hz)));
        let mut worker = Worker::new(port.to_string(), serial, config.clone(), rx, Arc::clone(&shared));
        worker.write_log = write_tx;
        let thread = std::thread::Builder::new()
            .name("parol6-session".into())
            .spawn(move || worker.run())
            .map_err(|e| HwError::PortOpen { port: port.to_string(), reason: e.to_string() })?;
        Ok(Session { tx, write_times, shared, thread: Some(thread), config })
    }

    /// Finds the PAROL6 by USB VID:PID 0483:5740 and opens it.
    pub fn open_auto(config: SessionConfig) -> Result<Session, HwError> {
        let port = crate::ports::find_parol6_port()?;
        Self::open(&port, config)
    }

    /// The settings in use.
    pub fn config(&self) -> &SessionConfig {
        &self.config
    }

    /// Times at which command frames were written since the last call (needs
    /// [`SessionConfig::write_log_capacity`] > 0; older entries are dropped when it is full).
    pub fn take_write_times(&self) -> Vec<Instant> {
        self.write_times.as_ref().map(|r| r.try_iter().collect()).unwrap_or_default()
    }

    /// The latest snapshot (lock-free).
    pub fn snapshot(&self) -> Arc<Snapshot> {
        self.shared.load_full()
    }

    fn send(&self, r: Request) -> Result<(), HwError> {
        match self.tx.try_send(r) {
            Ok(()) => Ok(()),
            Err(TrySendError::Full(_)) => Err(HwError::Refused("session command queue is full".into())),
            Err(TrySendError::Disconnected(_)) => Err(HwError::Closed),
        }
    }

    /// Sends ENABLE (101): clears the disabled latch (refused while the E-stop is pressed).
    pub fn enable(&self) -> Result<(), HwError> {
        if self.snapshot().estop_pressed {
            return Err(HwError::Refused("E-stop is pressed: release it before enabling".into()));
        }
        self.send(Request::OneShot(CommandCode::Enable))
    }

    /// Sends DISABLE (102) and stops any motion.
    pub fn disable(&self) -> Result<(), HwError> {
        self.send(Request::OneShot(CommandCode::Disable))
    }

    /// Sends CLEAR ERROR (103) and clears the session's fault message.
    pub fn clear_error(&self) -> Result<(), HwError> {
        self.send(Request::OneShot(CommandCode::ClearError))
    }

    /// Starts homing: HOME for a few frames, then IDLE until all homed bits are set (see
    /// [`Snapshot::homing`]; fails after the home timeout, 45 s by default).
    pub fn home(&self) -> Result<(), HwError> {
        let s = self.snapshot();
        if s.link != LinkState::Connected {
            return Err(HwError::Refused(format!("link is {:?}", s.link)));
        }
        if s.estop_pressed || s.needs_enable || s.enabled == Some(false) {
            return Err(HwError::Refused("E-stop pressed or controller disabled: enable it first".into()));
        }
        self.send(Request::Home)
    }

    /// [`Session::home`] and wait for the outcome.
    pub fn home_blocking(&self) -> Result<(), HwError> {
        self.home()?;
        let started = Instant::now();
        // Wait for the request to be picked up, then for its outcome.
        let limit = self.config.home_timeout + Duration::from_secs(2);
        let s = self.wait_until(limit, |s| {
            (s.published_at > started && matches!(s.homing, HomingState::Done | HomingState::Failed(_)))
                || s.link == LinkState::Closed
        })?;
        match &s.homing {
            HomingState::Done => Ok(()),
            HomingState::Failed(r) => Err(HwError::Homing(r.clone())),
            _ => Err(HwError::Closed),
        }
    }

    /// Jogs joint `joint` (0-based) at `fraction` of its jog speed (−1…1). Motion stops when
    /// [`Session::jog_release`] is called or no new `jog` call arrives within the dead-man
    /// time (200 ms): call it again at least every ~100 ms while the button is held.
    pub fn jog(&self, joint: usize, fraction: f64) -> Result<(), HwError> {
        if joint >= JOINT_COUNT {
            return Err(HwError::Refused(format!("joint index {joint} out of range 0..6")));
        }
        if !fraction.is_finite() {
            return Err(HwError::Refused("jog fraction must be a finite number".into()));
        }
        self.motion_preconditions()?;
        self.send(Request::Jog { joint, fraction: fraction.clamp(-1.0, 1.0), at: Instant::now() })
    }

    /// The latest snapshot, when motion may start: the link allows it and the arm is inside its
    /// joint limits (the counters read 0 before homing, which is outside J2/J3's ranges).
    fn motion_preconditions(&self) -> Result<Arc<Snapshot>, HwError> {
        let s = self.snapshot();
        s.motion_allowed()?;
        self.config
            .limits
            .check(&s.joint_rad)
            .map_err(|e| HwError::Refused(format!("arm is outside its joint limits ({e}); home it first")))?;
        Ok(s)
    }

    /// Releases the jog: the arm holds where the jog target is.
    pub fn jog_release(&self) -> Result<(), HwError> {
        self.send(Request::JogRelease)
    }

    /// Moves to `goal_rad` along the synchronised speed- and acceleration-limited profile.
    /// The goal must lie within the joint limits (it is rejected, not clamped).
    pub fn move_to(&self, goal_rad: &[f64], speed_fraction: f64, kind: ProfileKind) -> Result<(), HwError> {
        let goal = self.config.limits.enforce(goal_rad, LimitPolicy::Reject)?;
        let s = self.motion_preconditions()?;
        // Plan once here to report bad input synchronously; the thread re-plans from where the
        // arm is when the request arrives.
        JointMove::parol6(&s.joint_rad, &goal, speed_fraction, kind)?;
        self.send(Request::MoveTo { goal_rad: goal, speed_fraction, kind })
    }

    /// [`Session::move_to`] and wait until the move has been streamed and the arm is within
    /// `tolerance_steps` of the goal on every joint.
    pub fn move_to_blocking(
        &self,
        goal_rad: &[f64],
        speed_fraction: f64,
        kind: ProfileKind,
        timeout: Duration,
    ) -> Result<Arc<Snapshot>, HwError> {
        let goal_steps = joints_rad_to_steps(goal_rad)?;
        let sent_at = Instant::now();
        self.move_to(goal_rad, speed_fraction, kind)?;
        let tol = 3;
        let s = self.wait_until(timeout, |s| {
            let started = s.published_at > sent_at && s.frames_sent > 0;
            let settled = s.motion == MotionState::Holding
                && s.target_steps == Some(goal_steps)
                && s.joint_steps.iter().zip(goal_steps).all(|(a, b)| (a - b).abs() <= tol);
            (started && settled) || s.link != LinkState::Connected || s.estop_pressed
        })?;
        if s.link != LinkState::Connected {
            return Err(HwError::Refused(format!("link is {:?} ({})", s.link, s.fault.clone().unwrap_or_default())));
        }
        if s.estop_pressed {
            return Err(HwError::Refused("E-stop pressed during the move".into()));
        }
        Ok(s)
    }

    /// Stops any motion or homing: IDLE frames, the arm stops where it is.
    pub fn stop(&self) -> Result<(), HwError> {
        self.send(Request::Stop)
    }

    /// Electric gripper: go to `position` (0–255) at `speed` (0–255) with `current_ma`
    /// (100–2800 mA).
    pub fn set_gripper(&self, position: u8, speed: u8, current_ma: u16) -> Result<(), HwError> {
        if !(100..=2800).contains(&current_ma) {
            return Err(HwError::Refused(format!("gripper current {current_ma} mA is outside 100–2800 mA")));
        }
        self.send(Request::Gripper {
            position: i16::from(position),
            speed: i16::from(speed),
            current_ma: current_ma as i16,
        })
    }

    /// Electric gripper: calibrate (mode 1 for one frame).
    pub fn gripper_calibrate(&self) -> Result<(), HwError> {
        self.send(Request::GripperMode(1))
    }

    /// Electric gripper: clear its error (mode 2 for one frame).
    pub fn gripper_clear_error(&self) -> Result<(), HwError> {
        self.send(Request::GripperMode(2))
    }

    /// Sets digital output 1 or 2.
    pub fn set_output(&self, output: u8, level: bool) -> Result<(), HwError> {
        if !(output == 1 || output == 2) {
            return Err(HwError::Refused(format!("output {output} does not exist (1 or 2)")));
        }
        self.send(Request::Output { index: output, level })
    }

    /// Polls the snapshot until `pred` holds or `timeout` passes.
    pub fn wait_until(
        &self,
        timeout: Duration,
        mut pred: impl FnMut(&Snapshot) -> bool,
    ) -> Result<Arc<Snapshot>, HwError> {
        let end = Instant::now() + timeout;
        loop {
            let s = self.snapshot();
            if pred(&s) {
                return Ok(s);
            }
            if s.link == LinkState::Closed {
                return Err(HwError::Closed);
            }
            if Instant::now() >= end {
                return Err(HwError::Timeout(format!("condition not met within {:.1} s", timeout.as_secs_f64())));
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// Waits for the first valid status frame.
    pub fn wait_connected(&self, timeout: Duration) -> Result<Arc<Snapshot>, HwError> {
        self.wait_until(timeout, |s| s.link == LinkState::Connected)
    }

    /// Stops motion, leaves the board with IDLE (zero-speed) frames and ends the thread.
    pub fn close(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        // A blocking send: the thread drains every period, so this returns quickly.
        let _ = self.tx.send_timeout(Request::Shutdown, Duration::from_secs(1));
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// Why the last-line guard refused a frame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GuardViolation {
    /// A position field is outside the joint's step limits.
    #[error("joint {joint} target {steps} steps is outside {min}..{max}")]
    Position {
        /// 1-based joint.
        joint: usize,
        /// Target, steps.
        steps: i32,
        /// Lower limit.
        min: i32,
        /// Upper limit.
        max: i32,
    },
    /// A speed field exceeds the joint's max speed.
    #[error("joint {joint} speed {steps_s} steps/s exceeds {max}")]
    Speed {
        /// 1-based joint.
        joint: usize,
        /// Speed, steps/s.
        steps_s: i32,
        /// Max speed.
        max: i32,
    },
    /// MOVE without a measured position to bound it.
    #[error("MOVE without a measured position")]
    NoPosition,
}

/// Last line of defence, right before encoding. Checks every position field against the step
/// limits and every speed field against the max speeds; for MOVE it also pulls each target to
/// within `max_speed / 50` steps of the measured position, so the speed the firmware derives
/// (`≈ 50 · error`) never exceeds the max speed. Returns true when it had to pull a target.
pub fn guard_frame(
    frame: &mut CommandFrame,
    measured_steps: Option<&[i32; JOINT_COUNT]>,
) -> Result<bool, GuardViolation> {
    let lim = limits_steps();
    let vmax = max_speed_steps_s();
    let mut pulled = false;
    if frame.command == CommandCode::Move {
        let m = measured_steps.ok_or(GuardViolation::NoPosition)?;
        for i in 0..JOINT_COUNT {
            let reach = vmax[i] / FW_MOVE_GAIN_PER_S;
            let t = frame.fields.positions_steps[i];
            let c = t.clamp(m[i].saturating_sub(reach), m[i].saturating_add(reach));
            if c != t {
                frame.fields.positions_steps[i] = c;
                pulled = true;
            }
        }
    }
    for i in 0..JOINT_COUNT {
        let p = frame.fields.positions_steps[i];
        if !(lim[i].0..=lim[i].1).contains(&p) {
            return Err(GuardViolation::Position { joint: i + 1, steps: p, min: lim[i].0, max: lim[i].1 });
        }
        let v = frame.fields.speeds_steps_s[i];
        if v.unsigned_abs() > vmax[i].unsigned_abs() {
            return Err(GuardViolation::Speed { joint: i + 1, steps_s: v, max: vmax[i] });
        }
    }
    Ok(pulled)
}

/// Position fields for frames that carry no target: the measured position clamped into the
/// step limits (the firmware ignores them; they are kept in range anyway).
fn placeholder_positions(measured: Option<&[i32; JOINT_COUNT]>) -> [i32; JOINT_COUNT] {
    let lim = limits_steps();
    let base = measured.copied().unwrap_or(crate::units::STANDBY_STEPS);
    std::array::from_fn(|i| base[i].clamp(lim[i].0, lim[i].1))
}

#[derive(Debug, Clone)]
enum Motion {
    Idle,
    Hold { target_rad: Vec<f64> },
    Jog { joint: usize, fraction: f64, q_cmd: Vec<f64>, vel_rad_s: f64, refreshed: Instant },
    Move { plan: JointMove, started: Instant },
}

#[derive(Debug, Clone)]
enum Homing {
    None,
    Sending { left: u32, started: Instant, seen_unhomed: bool },
    Waiting { started: Instant, seen_unhomed: bool },
}

struct Worker {
    port_name: String,
    port: Option<Box<dyn serialport::SerialPort>>,
    cfg: SessionConfig,
    rx: Receiver<Request>,
    shared: Arc<ArcSwap<Snapshot>>,
    parser: StatusParser,
    snap: Snapshot,
    motion: Motion,
    homing: Homing,
    one_shots: Vec<CommandCode>,
    io_bits: u8,
    gripper: GripperCommand,
    gripper_mode_once: Option<u8>,
    link_since: Instant,
    last_open_attempt: Instant,
    connected_at: Instant,
    intervals_s: Vec<f64>,
    interval_pos: usize,
    last_tick: Option<Instant>,
    read_buf: Vec<u8>,
    write_log: Option<Sender<Instant>>,
}

impl Worker {
    fn new(
        port_name: String,
        port: Box<dyn serialport::SerialPort>,
        cfg: SessionConfig,
        rx: Receiver<Request>,
        shared: Arc<ArcSwap<Snapshot>>,
    ) -> Self {
        let now = Instant::now();
        Self {
            snap: Snapshot::new(&port_name, cfg.rate_hz),
            port_name,
            port: Some(port),
            cfg,
            rx,
            shared,
            parser: StatusParser::new(),
            motion: Motion::Idle,
            homing: Homing::None,
            one_shots: Vec::new(),
            io_bits: 0,
            gripper: GripperCommand::default(),
            gripper_mode_once: None,
            link_since: now,
            last_open_attempt: now,
            connected_at: now,
            intervals_s: Vec::with_capacity(TIMING_WINDOW),
            interval_pos: 0,
            last_tick: None,
            read_buf: vec![0u8; 4096],
            write_log: None,
        }
    }

    fn measured_steps(&self) -> Option<[i32; JOINT_COUNT]> {
        self.snap.status.map(|s| s.positions_steps)
    }

    fn measured_rad(&self) -> Option<Vec<f64>> {
        self.snap.status.map(|s| joints_steps_to_rad(&s.positions_steps).to_vec())
    }

    fn set_fault(&mut self, msg: impl Into<String>) {
        let msg = msg.into();
        tracing::warn!("parol6 session: {msg}");
        self.snap.fault = Some(msg);
    }

    fn cancel_motion(&mut self) {
        self.motion = Motion::Idle;
    }

    fn fail_homing(&mut self, reason: &str) {
        if !matches!(self.homing, Homing::None) {
            self.homing = Homing::None;
            self.snap.homing = HomingState::Failed(reason.to_string());
        }
    }

    fn run(&mut self) {
        let period = self.cfg.period();
        let mut next_tick = Instant::now();
        let mut closing: Option<u32> = None;
        loop {
            // Wait for the deadline, reading status bytes as they arrive.
            let spin_from = next_tick.checked_sub(self.cfg.spin_before_deadline).unwrap_or(next_tick);
            loop {
                let now = Instant::now();
                if now >= next_tick {
                    break;
                }
                if now < spin_from {
                    self.read_until(spin_from);
                } else {
                    self.read_available();
                    std::hint::spin_loop();
                }
            }
            let now = Instant::now();
            self.record_tick(now);
            if closing.is_none() && self.drain_requests(now) {
                closing = Some(CLOSING_FRAMES);
                self.cancel_motion();
                self.homing = Homing::None;
            }
            self.check_link(now);
            let frame = match closing {
                Some(_) => self.idle_frame(),
                None => self.next_frame(now),
            };
            self.write_frame(frame);
            if let Some(n) = closing.as_mut() {
                *n -= 1;
                if *n == 0 {
                    break;
                }
            }
            self.publish(now);
            next_tick += period;
            let after = Instant::now();
            if after > next_tick + period {
                // Fell more than a period behind (stalled machine): resynchronise.
                next_tick = after;
            }
        }
        self.port = None;
        self.snap.link = LinkState::Closed;
        self.snap.motion = MotionState::Idle;
        self.publish(Instant::now());
    }

    fn record_tick(&mut self, now: Instant) {
        if let Some(prev) = self.last_tick {
            let dt = now.duration_since(prev).as_secs_f64();
            if self.intervals_s.len() < TIMING_WINDOW {
                self.intervals_s.push(dt);
            } else {
                self.intervals_s[self.interval_pos] = dt;
                self.interval_pos = (self.interval_pos + 1) % TIMING_WINDOW;
            }
        }
        self.last_tick = Some(now);
    }

    /// Reads and parses until `deadline` (or returns early after an error / when no port).
    fn read_until(&mut self, deadline: Instant) {
        let Some(port) = self.port.as_mut() else {
            std::thread::sleep(deadline.saturating_duration_since(Instant::now()));
            return;
        };
        let wait = deadline.saturating_duration_since(Instant::now());
        if wait.is_zero() {
            return;
        }
        if let Err(e) = port.set_timeout(wait) {
            self.port_failed(&format!("serial port error: {e}"));
            return;
        }
        match port.read(&mut self.read_buf) {
            Ok(0) => {
                // EOF on a tty means hang-up.
                self.port_failed("serial port closed (end of file)");
            }
            Ok(n) => {
                self.parser.push(&self.read_buf[..n]);
                let now = Instant::now();
                while let Some(frame) = self.parser.next_frame() {
                    self.on_status(frame, now);
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut || e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => self.port_failed(&format!("serial port closed or failed: {e}")),
        }
    }

    /// Reads and parses whatever is buffered, without waiting.
    fn read_available(&mut self) {
        let Some(port) = self.port.as_mut() else { return };
        match port.bytes_to_read() {
            Ok(0) => {}
            Ok(n) => {
                let n = (n as usize).min(self.read_buf.len());
                match port.read(&mut self.read_buf[..n]) {
                    Ok(got) => {
                        self.parser.push(&self.read_buf[..got]);
                        let now = Instant::now();
                        while let Some(frame) = self.parser.next_frame() {
                            self.on_status(frame, now);
                        }
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                    Err(e) => self.port_failed(&format!("serial port closed or failed: {e}")),
                }
            }
            Err(e) => self.port_failed(&format!("serial port error: {e}")),
        }
    }

    fn port_failed(&mut self, msg: &str) {
        self.port = None;
        self.parser.clear();
        if self.snap.link != LinkState::Lost {
            self.link_since = Instant::now();
        }
        self.snap.link = LinkState::Lost;
        self.cancel_motion();
        self.fail_homing("link lost during homing");
        self.set_fault(msg.to_string());
    }

    fn on_status(&mut self, s: StatusFrame, now: Instant) {
        let was_pressed = self.snap.estop_pressed;
        self.snap.status = Some(s);
        self.snap.last_status_at = Some(now);
        self.snap.joint_steps = s.positions_steps;
        self.snap.joint_rad = joints_steps_to_rad(&s.positions_steps);
        self.snap.joint_speed_steps_s = s.speeds_steps_s;
        self.snap.joint_speed_rad_s = std::array::from_fn(|i| steps_to_rad(i, s.speeds_steps_s[i]));
        self.snap.homed = s.homed_joints();
        self.snap.estop_pressed = s.estop_pressed();
        self.snap.io = [s.in1(), s.in2(), s.out1(), s.out2()];
        self.snap.gripper_position = s.gripper_position;
        self.snap.gripper_current_ma = s.gripper_current_ma;
        self.snap.gripper_status = s.gripper_status;
        if self.snap.link != LinkState::Connected {
            self.snap.link = LinkState::Connected;
            self.connected_at = now;
        }
        if s.estop_pressed() && !was_pressed {
            self.cancel_motion();
            self.fail_homing("E-stop pressed during homing");
            self.snap.needs_enable = true;
            self.snap.enabled = Some(false);
            self.set_fault("E-stop pressed: motion stopped, DISABLE sent; enable after release");
        }
        // Homing progress.
        let all = s.all_homed();
        match &mut self.homing {
            Homing::Sending { seen_unhomed, .. } | Homing::Waiting { seen_unhomed, .. } => {
                if !all {
                    *seen_unhomed = true;
                }
            }
            Homing::None => {}
        }
        if let Homing::Waiting { seen_unhomed: true, .. } = self.homing
            && all
        {
            self.homing = Homing::None;
            self.snap.homing = HomingState::Done;
        }
    }

    fn check_link(&mut self, now: Instant) {
        if self.port.is_none() {
            if now.duration_since(self.last_open_attempt) >= self.cfg.reconnect_interval {
                self.last_open_attempt = now;
                match crate::ports::open_port(&self.port_name) {
                    Ok(p) => {
                        self.port = Some(p);
                        self.parser.clear();
                        self.snap.reconnects += 1;
                        self.snap.link = LinkState::Connecting;
                        self.link_since = now;
                        self.connected_at = now;
                        tracing::info!("parol6 session: re-opened {}", self.port_name);
                    }
                    Err(e) => self.snap.fault = Some(format!("link lost; re-open failed: {e}")),
                }
            }
            return;
        }
        let last_valid = self.snap.last_status_at.unwrap_or(self.connected_at).max(self.connected_at);
        let silent = now.duration_since(last_valid);
        if silent > self.cfg.status_timeout && self.snap.link != LinkState::Lost {
            self.snap.link = LinkState::Lost;
            self.link_since = now;
            self.cancel_motion();
            self.fail_homing("link lost during homing");
            self.set_fault(format!(
                "link lost: no valid status for {:.0} ms; motion stopped",
                silent.as_secs_f64() * 1e3
            ));
        }
        if self.snap.link == LinkState::Lost
            && now.duration_since(self.link_since) >= self.cfg.reconnect_interval
            && now.duration_since(self.last_open_attempt) >= self.cfg.reconnect_interval
        {
            // Still silent: close and re-open the port (every reconnect interval).
            self.port = None;
            self.last_open_attempt = now.checked_sub(self.cfg.reconnect_interval).unwrap_or(now);
        }
    }

    fn motion_refusal(&self) -> Option<String> {
        self.snap.motion_allowed().err().map(|e| e.to_string())
    }

    /// Handles queued requests; true on shutdown.
    fn drain_requests(&mut self, now: Instant) -> bool {
        while let Ok(r) = self.rx.try_recv() {
            match r {
                Request::Shutdown => return true,
                Request::OneShot(code) => {
                    match code {
                        CommandCode::Enable => {
                            if self.snap.estop_pressed {
                                self.set_fault("enable refused: E-stop is pressed");
                                continue;
                            }
                            self.snap.enabled = Some(true);
                            self.snap.needs_enable = false;
                            self.fail_homing("homing cancelled by ENABLE");
                        }
                        CommandCode::Disable => {
                            self.snap.enabled = Some(false);
                            self.cancel_motion();
                            self.fail_homing("homing cancelled by DISABLE");
                        }
                        CommandCode::ClearError => {
                            self.snap.fault = None;
                            self.fail_homing("homing cancelled by CLEAR ERROR");
                        }
                        _ => {}
                    }
                    self.one_shots.push(code);
                }
                Request::Home => {
                    if self.snap.estop_pressed || self.snap.needs_enable || self.snap.enabled == Some(false) {
                        self.set_fault("home refused: E-stop pressed or controller disabled");
                        continue;
                    }
                    self.cancel_motion();
                    self.homing = Homing::Sending { left: self.cfg.home_frames, started: now, seen_unhomed: false };
                    self.snap.homing = HomingState::Sending;
                }
                Request::Jog { joint, fraction, at } => self.start_or_refresh_jog(joint, fraction, at),
                Request::JogRelease => {
                    if let Motion::Jog { q_cmd, .. } = &self.motion {
                        self.motion = Motion::Hold { target_rad: q_cmd.clone() };
                    }
                }
                Request::MoveTo { goal_rad, speed_fraction, kind } => {
                    self.start_move(goal_rad, speed_fraction, kind, now)
                }
                Request::Stop => {
                    if !matches!(self.homing, Homing::None) {
                        self.one_shots.push(CommandCode::ClearError);
                        self.fail_homing("homing stopped");
                    }
                    self.cancel_motion();
                }
                Request::Gripper { position, speed, current_ma } => {
                    self.gripper.position = position;
                    self.gripper.speed = speed;
                    self.gripper.current_ma = current_ma;
                    self.gripper.command_bits = GRIPPER_ACTIVATE | GRIPPER_MOVE | GRIPPER_ENABLE;
                }
                Request::GripperMode(m) => self.gripper_mode_once = Some(m),
                Request::Output { index, level } => {
                    let bit = if index == 1 { IO_OUT1 } else { IO_OUT2 };
                    if level {
                        self.io_bits |= bit;
                    } else {
                        self.io_bits &= !bit;
                    }
                }
            }
        }
        false
    }

    /// Start position for a new motion: the held target, else the measured position; it must
    /// lie within the limits.
    fn motion_start(&self) -> Result<Vec<f64>, String> {
        let start = match &self.motion {
            Motion::Hold { target_rad } => target_rad.clone(),
            Motion::Jog { q_cmd, .. } => q_cmd.clone(),
            Motion::Move { plan, started } => plan.sample(started.elapsed().as_secs_f64()).q,
            Motion::Idle => self.measured_rad().ok_or("no status received yet")?,
        };
        self.cfg.limits.check(&start).map_err(|e| format!("arm is outside its joint limits ({e}); home it first"))?;
        Ok(start)
    }

    fn start_or_refresh_jog(&mut self, joint: usize, fraction: f64, at: Instant) {
        if let Some(why) = self.motion_refusal() {
            self.set_fault(format!("jog refused: {why}"));
            return;
        }
        if let Motion::Jog { joint: j, fraction: f, refreshed, .. } = &mut self.motion
            && *j == joint
        {
            *f = fraction;
            *refreshed = at;
            return;
        }
        match self.motion_start() {
            Ok(q_cmd) => self.motion = Motion::Jog { joint, fraction, q_cmd, vel_rad_s: 0.0, refreshed: at },
            Err(e) => self.set_fault(format!("jog refused: {e}")),
        }
    }

    fn start_move(&mut self, goal_rad: Vec<f64>, speed_fraction: f64, kind: ProfileKind, now: Instant) {
        if let Some(why) = self.motion_refusal() {
            self.set_fault(format!("move refused: {why}"));
            return;
        }
        let goal = match self.cfg.limits.enforce(&goal_rad, LimitPolicy::Reject) {
            Ok(g) => g,
            Err(e) => return self.set_fault(format!("move refused: {e}")),
        };
        let start = match self.motion_start() {
            Ok(s) => s,
            Err(e) => return self.set_fault(format!("move refused: {e}")),
        };
        match JointMove::parol6(&start, &goal, speed_fraction, kind) {
            Ok(plan) => self.motion = Motion::Move { plan, started: now },
            Err(e) => self.set_fault(format!("move refused: {e}")),
        }
    }

    fn base_fields(&self) -> CommandFields {
        let mut gripper = self.gripper;
        if let Some(m) = self.gripper_mode_once {
            gripper.mode = m;
        }
        if self.snap.estop_pressed {
            gripper.command_bits |= GRIPPER_ESTOP;
        }
        CommandFields {
            positions_steps: placeholder_positions(self.measured_steps().as_ref()),
            speeds_steps_s: [0; JOINT_COUNT],
            affected_joints: 0,
            io_bits: self.io_bits,
            timeout: 0,
            gripper,
        }
    }

    fn idle_frame(&self) -> CommandFrame {
        CommandFrame { command: CommandCode::Idle, fields: self.base_fields() }
    }

    /// The MOVE frame for a target in rad (limits enforced, clamped), or IDLE if it fails.
    fn move_frame(&mut self, target_rad: &[f64]) -> CommandFrame {
        let clamped = match self.cfg.limits.enforce(target_rad, LimitPolicy::Clamp) {
            Ok(q) => q,
            Err(e) => {
                self.set_fault(format!("target refused: {e}"));
                self.cancel_motion();
                return self.idle_frame();
            }
        };
        match joints_rad_to_steps(&clamped) {
            Ok(steps) => {
                let mut fields = self.base_fields();
                fields.positions_steps = steps;
                CommandFrame { command: CommandCode::Move, fields }
            }
            Err(e) => {
                self.set_fault(format!("target refused: {e}"));
                self.cancel_motion();
                self.idle_frame()
            }
        }
    }

    fn next_frame(&mut self, now: Instant) -> CommandFrame {
        // E-stop: DISABLE every period while pressed.
        if self.snap.estop_pressed {
            self.cancel_motion();
            return CommandFrame { command: CommandCode::Disable, fields: self.base_fields() };
        }
        if self.snap.link == LinkState::Lost {
            self.cancel_motion();
        }
        if !self.one_shots.is_empty() {
            let code = self.one_shots.remove(0);
            return CommandFrame { command: code, fields: self.base_fields() };
        }
        match &mut self.homing {
            Homing::Sending { left, started, seen_unhomed } => {
                let (started, seen) = (*started, *seen_unhomed);
                *left = left.saturating_sub(1);
                if *left == 0 {
                    self.homing = Homing::Waiting { started, seen_unhomed: seen };
                    self.snap.homing = HomingState::Waiting;
                }
                return CommandFrame { command: CommandCode::Home, fields: self.base_fields() };
            }
            Homing::Waiting { started, .. } => {
                if now.duration_since(*started) > self.cfg.home_timeout {
                    let homed: Vec<String> = self
                        .snap
                        .homed
                        .iter()
                        .enumerate()
                        .filter(|(_, h)| **h)
                        .map(|(i, _)| format!("J{}", i + 1))
                        .collect();
                    let reason = format!(
                        "not all joints homed after {:.0} s (homed: {})",
                        self.cfg.home_timeout.as_secs_f64(),
                        if homed.is_empty() { "none".to_string() } else { homed.join(" ") }
                    );
                    self.fail_homing(&reason);
                    self.set_fault(format!("homing failed: {reason}"));
                    // Reset the board's homing state.
                    return CommandFrame { command: CommandCode::ClearError, fields: self.base_fields() };
                }
                return self.idle_frame();
            }
            Homing::None => {}
        }
        let period_s = self.cfg.period().as_secs_f64();
        let deadman = self.cfg.jog_deadman;
        let motion = std::mem::replace(&mut self.motion, Motion::Idle);
        let (next_motion, target) = match motion {
            Motion::Idle => (Motion::Idle, None),
            Motion::Hold { target_rad } => {
                let t = target_rad.clone();
                (Motion::Hold { target_rad }, Some(t))
            }
            Motion::Move { plan, started } => {
                let t = now.duration_since(started).as_secs_f64();
                let q = plan.sample(t).q;
                if plan.is_finished(t) {
                    (Motion::Hold { target_rad: plan.goal().to_vec() }, Some(q))
                } else {
                    (Motion::Move { plan, started }, Some(q))
                }
            }
            Motion::Jog { joint, fraction, mut q_cmd, mut vel_rad_s, refreshed } => {
                if now.duration_since(refreshed) > deadman {
                    // Dead-man: not refreshed in time → hold the current jog target.
                    let t = q_cmd.clone();
                    (Motion::Hold { target_rad: q_cmd }, Some(t))
                } else {
                    let v_target = jog_speed_steps_s(joint, fraction).unwrap_or(0.0) * rad_per_step(joint);
                    let a = max_accel_rad_s2()[joint];
                    let dv = (v_target - vel_rad_s).clamp(-a * period_s, a * period_s);
                    vel_rad_s += dv;
                    q_cmd[joint] += vel_rad_s * period_s;
                    if let Some(l) = self.cfg.limits.get(joint) {
                        let c = l.clamp(q_cmd[joint]);
                        if c != q_cmd[joint] {
                            q_cmd[joint] = c;
                            vel_rad_s = 0.0;
                        }
                    }
                    let t = q_cmd.clone();
                    (Motion::Jog { joint, fraction, q_cmd, vel_rad_s, refreshed }, Some(t))
                }
            }
        };
        self.motion = next_motion;
        match target {
            Some(t) => self.move_frame(&t),
            None => self.idle_frame(),
        }
    }

    fn write_frame(&mut self, mut frame: CommandFrame) {
        let measured = self.measured_steps();
        match guard_frame(&mut frame, measured.as_ref()) {
            Ok(false) => {}
            Ok(true) => self.snap.guard_trips += 1,
            Err(v) => {
                self.snap.guard_trips += 1;
                self.set_fault(format!("frame blocked by the limit guard: {v}"));
                self.cancel_motion();
                frame = self.idle_frame();
                if guard_frame(&mut frame, measured.as_ref()).is_err() {
                    return;
                }
            }
        }
        let bytes = match frame.encode() {
            Ok(b) => b,
            Err(e) => {
                self.set_fault(format!("cannot encode frame: {e}"));
                return;
            }
        };
        let Some(port) = self.port.as_mut() else { return };
        match port.write_all(&bytes) {
            Ok(()) => {
                if let Some(log) = &self.write_log {
                    let _ = log.try_send(Instant::now());
                }
                self.snap.frames_sent += 1;
                self.snap.last_command = Some(frame.command);
                self.gripper_mode_once = None;
                self.snap.target_steps =
                    if frame.command == CommandCode::Move { Some(frame.fields.positions_steps) } else { None };
            }
            Err(e) => self.port_failed(&format!("serial port closed or failed while writing: {e}")),
        }
    }

    fn publish(&mut self, now: Instant) {
        let st = self.parser.stats();
        self.snap.status_frames = st.frames;
        self.snap.invalid_frames = st.invalid_frames;
        self.snap.discarded_bytes = st.discarded_bytes;
        self.snap.missing_replies = self.snap.frames_sent.saturating_sub(st.frames);
        self.snap.motion = match &self.motion {
            _ if !matches!(self.homing, Homing::None) => MotionState::Homing,
            Motion::Idle => MotionState::Idle,
            Motion::Hold { .. } => MotionState::Holding,
            Motion::Jog { joint, fraction, .. } => MotionState::Jogging { joint: *joint, fraction: *fraction },
            Motion::Move { plan, started } => MotionState::Moving {
                elapsed_s: now.duration_since(*started).as_secs_f64(),
                duration_s: plan.duration_s(),
            },
        };
        if !self.intervals_s.is_empty() {
            let nominal = self.cfg.period().as_secs_f64();
            let mean = self.intervals_s.iter().sum::<f64>() / self.intervals_s.len() as f64;
            self.snap.loop_rate_hz = if mean > 0.0 { 1.0 / mean } else { 0.0 };
            let mut dev: Vec<f64> = self.intervals_s.iter().map(|d| (d - nominal).abs()).collect();
            dev.sort_by(f64::total_cmp);
            let idx = ((dev.len() as f64 - 1.0) * 0.99).round() as usize;
            self.snap.period_jitter_p99_ms = dev.get(idx).copied().unwrap_or(0.0) * 1e3;
            self.snap.period_jitter_max_ms = dev.last().copied().unwrap_or(0.0) * 1e3;
        }
        self.snap.status_age_ms =
            self.snap.last_status_at.map(|t| now.saturating_duration_since(t).as_secs_f64() * 1e3);
        self.snap.published_at = now;
        self.shared.store(Arc::new(self.snap.clone()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::STANDBY_STEPS;

    #[test]
    fn config_rate_is_checked() {
        let mut c = SessionConfig::default();
        assert!(c.validate().is_ok());
        c.rate_hz = 40.0;
        assert!(c.validate().is_err());
        c.rate_hz = 501.0;
        assert!(c.validate().is_err());
        c.rate_hz = f64::NAN;
        assert!(c.validate().is_err());
        c.rate_hz = 500.0;
        assert!(c.validate().is_ok());
    }

    #[test]
    fn guard_blocks_out_of_limit_positions_and_speeds() {
        let mut f = CommandFrame::new(CommandCode::Idle);
        f.fields.positions_steps = STANDBY_STEPS;
        assert_eq!(guard_frame(&mut f, None), Ok(false));
        f.fields.positions_steps[2] = 0; // J3 min is 34700
        assert!(matches!(guard_frame(&mut f, None), Err(GuardViolation::Position { joint: 3, .. })));
        f.fields.positions_steps = STANDBY_STEPS;
        f.fields.speeds_steps_s[3] = 10_001;
        assert!(matches!(guard_frame(&mut f, None), Err(GuardViolation::Speed { joint: 4, .. })));
    }

    #[test]
    fn guard_caps_the_implied_move_speed() {
        let mut f = CommandFrame::new(CommandCode::Move);
        f.fields.positions_steps = STANDBY_STEPS;
        f.fields.positions_steps[0] += 5000;
        assert_eq!(guard_frame(&mut f, Some(&STANDBY_STEPS)), Ok(true));
        // J1 max 15 000 steps/s → at most 300 steps of error.
        assert_eq!(f.fields.positions_steps[0], STANDBY_STEPS[0] + 300);
        let mut f = CommandFrame::new(CommandCode::Move);
        f.fields.positions_steps = STANDBY_STEPS;
        assert_eq!(guard_frame(&mut f, None), Err(GuardViolation::NoPosition));
    }

    #[test]
    fn placeholder_positions_stay_in_limits() {
        let p = placeholder_positions(Some(&[0; JOINT_COUNT]));
        let lim = limits_steps();
        for i in 0..JOINT_COUNT {
            assert!((lim[i].0..=lim[i].1).contains(&p[i]));
        }
    }

    #[test]
    fn refusals_explain_why() {
        let mut s = Snapshot::new("x", 100.0);
        assert!(s.motion_allowed().is_err());
        s.link = LinkState::Connected;
        assert!(s.motion_allowed().is_ok());
        s.needs_enable = true;
        let msg = s.motion_allowed().unwrap_err().to_string();
        assert!(msg.contains("enable"), "{msg}");
    }
}

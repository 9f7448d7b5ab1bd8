//! The controller session: a dedicated thread that sends one command frame per period
//! (default 100 Hz), parses the status replies and publishes a [`Snapshot`] and a
//! [`RobotState`] lock-free.
//!
//! Motion is the core [`MotionPlanner`](parol6_core::motion::MotionPlanner), the same as the
//! simulation's: [`RobotBackend::submit`](parol6_core::motion::RobotBackend::submit) queues a
//! [`MotionCommand`]; the thread samples the planner on its motion clock
//! (`t = tick × period`) and streams the setpoint as MOVE targets with zero feed-forward
//! (never JOG, except for the operator's confirmed [`Session::jog_back_inside`] of a joint
//! beyond its limit), so a lost host leaves the arm holding still.
//!
//! The firmware has no CRC, no timeout and no limit checks, so this thread is the safety layer:
//! - limits are enforced by the planner, and a last-line guard ([`guard`]) right before
//!   encoding refuses any frame with a position field outside the step limits (the session
//!   holds with IDLE instead) and keeps every MOVE target within the joint's API speed limit ×
//!   period of the previous target; motion never starts from a measured position outside the
//!   limits, and impossible positions (far outside) hold the arm with IDLE and a fault;
//! - measured positions that jump impossibly are rejected and counted, never used; five in a
//!   row, or commanded and measured apart by more than 2000 steps for 0.5 s, stop motion;
//! - no valid status for 80 ms (`SessionConfig::status_timeout`) → link loss: motion is stopped (IDLE) and the port re-opened
//!   every 2 s; nothing answering within 3 s of opening → [`LinkState::NoAnswer`]; the rule is
//!   the same for every port (the built-in emulator's link is a local socket rather than a pty,
//!   so a busy host's kernel tty worker no longer delays its replies: issue 32);
//! - E-stop pressed → motion stopped, DISABLE sent every period; after release motion needs
//!   an explicit [`Session::enable`];
//! - closing the session leaves the board with an IDLE frame (no stepping, zero speeds).

use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use arc_swap::ArcSwap;
use crossbeam_channel::{Receiver, Sender, TrySendError};
use parol6_core::RobotModel;
use parol6_core::motion::{
    BackendError, JogKinematics, MotionCaps, MotionCommand, MotionSample, RobotState, StateSource, home_position,
};
use parol6_core::profile::ProfileKind;

use crate::HwError;
use crate::frame::CommandCode;
use crate::units::joints_rad_to_steps;

mod config;
pub mod guard;
mod motion;
mod snapshot;
mod worker;

pub use config::SessionConfig;
pub use snapshot::impossible_answers;
pub use snapshot::{HomingState, LinkState, MotionState, Snapshot};
pub use worker::{GRIPPER_ACTIVATE, GRIPPER_ENABLE, GRIPPER_ESTOP, GRIPPER_MOVE, RECOVERY_SPEED_SHARE, TIMING_WINDOW};

use worker::{Request, Shared, Worker};

/// Capacity of the request queue.
pub const REQUEST_QUEUE: usize = 256;

/// A running controller session. Cheap calls: each request is queued to the session thread
/// (bounded channel) and takes effect at the next period. Dropping it closes the session.
pub struct Session {
    tx: Sender<Request>,
    write_times: Option<Receiver<Instant>>,
    shared: Arc<Shared>,
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
        Self::open_with_tap(port, config, None)
    }

    /// [`Session::open`] with a tap that receives a [`MotionSample`] of every frame
    /// (commanded setpoint and measured joints; dropped, never waited for, when full).
    pub fn open_with_tap(
        port: &str,
        config: SessionConfig,
        tap: Option<Sender<MotionSample>>,
    ) -> Result<Session, HwError> {
        config.validate()?;
        let serial = crate::ports::open_port(port)?;
        let mut model = RobotModel::parol6();
        model.set_tool_transform(config.tool_in_flange);
        // Cartesian jogs and steps: IK within the session's limits; of the collision model only
        // the floor on the robot (it stops at limits, singularities, the workspace edge and
        // before the floor, as pre-flight's floor rule)
        let mut jog_model = model.clone();
        jog_model.limits = config.limits.clone();
        let floor = parol6_core::collision::FloorGuard(parol6_core::collision::CollisionGuard::new(&model));
        let kinematics = JogKinematics { model: Arc::new(jog_model), obstacles: Some(Arc::new(floor)) };
        let streamer = motion::Streamer::new(
            config.limits.clone(),
            MotionCaps::of(&model),
            home_position(&model),
            config.period_s(),
            config.tracking,
        )
        .with_kinematics(kinematics)
        .with_start_tolerance(config.disagreement_steps);
        let (tx, rx) = crossbeam_channel::bounded(REQUEST_QUEUE);
        let (write_tx, write_times) = if config.write_log_capacity > 0 {
            let (t, r) = crossbeam_channel::bounded(config.write_log_capacity);
            (Some(t), Some(r))
        } else {
            (None, None)
        };
        let first = snapshot::Snapshot::new(port, config.rate_hz);
        let mut state = RobotState::at_rest(&model, StateSource::Robot, &format!("robot on {port}"), &first.joint_rad);
        state.blocked = first.motion_allowed().err().map(|e| e.to_string());
        let shared = Arc::new(Shared { snapshot: ArcSwap::from_pointee(first), state: ArcSwap::from_pointee(state) });
        let mut worker =
            Worker::new(port.to_string(), serial, config.clone(), rx, Arc::clone(&shared), model, streamer);
        worker.write_log = write_tx;
        worker.tap = tap;
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
        self.shared.snapshot.load_full()
    }

    /// The latest robot state, computed on the session thread (lock-free).
    pub fn robot_state(&self) -> Arc<RobotState> {
        self.shared.state.load_full()
    }

    fn send(&self, r: Request) -> Result<(), HwError> {
        match self.tx.try_send(r) {
            Ok(()) => Ok(()),
            Err(TrySendError::Full(_)) => Err(HwError::Refused("session command queue is full".into())),
            Err(TrySendError::Disconnected(_)) => Err(HwError::Closed),
        }
    }

    /// Queues a motion command (what [`RobotBackend::submit`] does): checked against the
    /// limits and the link's state first.
    ///
    /// [`RobotBackend::submit`]: parol6_core::motion::RobotBackend::submit
    pub(crate) fn submit_motion(&self, cmd: MotionCommand, at_s: Option<f64>) -> Result<(), BackendError> {
        cmd.validate(&self.config.limits)?;
        if let Some(t) = at_s
            && !t.is_finite()
        {
            return Err(BackendError::Refused(format!("schedule time {t} is not a finite number")));
        }
        if cmd.starts_motion() {
            self.snapshot().motion_allowed().map_err(|e| match e {
                HwError::Refused(why) => BackendError::Refused(why),
                other => BackendError::Refused(other.to_string()),
            })?;
            if let MotionCommand::JogJoint { joint, fraction } = cmd {
                self.check_jog_direction(joint, fraction)?;
            }
        }
        match self.tx.try_send(Request::Motion { cmd, at_s }) {
            Ok(()) => Ok(()),
            Err(TrySendError::Full(_)) => Err(BackendError::QueueFull),
            Err(TrySendError::Disconnected(_)) => Err(BackendError::Closed),
        }
    }

    /// From at or beyond a limit only a jog back inside is allowed.
    fn check_jog_direction(&self, joint: usize, fraction: f64) -> Result<(), BackendError> {
        let state = self.robot_state();
        match parol6_core::motion::jog_refusal(&self.config.limits, &state.commanded.q, joint, fraction) {
            Some(why) => Err(BackendError::Refused(why)),
            None => Ok(()),
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

    /// Starts the controller's homing routine: HOME for a few frames, then IDLE until all
    /// homed bits are set (see [`Snapshot::homing`]; fails after the home timeout, 45 s by
    /// default).
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

    /// Jogs joint `joint` (0-based) at `fraction` (−1…1) of its speed cap. Motion stops when
    /// [`Session::jog_release`] is called or no new `jog` call arrives within the dead-man
    /// time (200 ms of motion clock): call it again at least every ~100 ms while held.
    pub fn jog(&self, joint: usize, fraction: f64) -> Result<(), HwError> {
        self.device_ready()?;
        self.submit_motion(MotionCommand::JogJoint { joint, fraction }, None).map_err(HwError::from)
    }

    /// The operator's confirmed jog back inside: joint `joint` (0-based), measured a little
    /// beyond one of its limits (after a crash), steps back toward the inside with JOG (speed)
    /// frames at [`RECOVERY_SPEED_SHARE`] × `fraction` of its jog speed, until it is within its
    /// limits (MOVE cannot move it: its first target would lie outside them). Only inward:
    /// `fraction` < 0 beyond the upper limit, > 0 beyond the lower one. The same dead-man as
    /// [`Session::jog`]: call it again at least every ~100 ms. Refused for a joint within its
    /// limits and for impossible positions ([`HwError::Device`]).
    pub fn jog_back_inside(&self, joint: usize, fraction: f64) -> Result<(), HwError> {
        let s = self.snapshot();
        if let Some(b) = s.limit_breach.filter(|b| b.impossible) {
            return Err(HwError::Device(impossible_answers(&b)));
        }
        if s.link != LinkState::Connected {
            return Err(HwError::Device(format!("link is {:?}", s.link)));
        }
        if joint >= parol6_core::parol6::JOINT_COUNT || !fraction.is_finite() || fraction.abs() > 1.0 {
            return Err(HwError::Refused(format!("jog back inside: joint {joint} / speed {fraction} out of range")));
        }
        match s.limit_breach {
            Some(b) if b.joint == joint + 1 && (fraction < 0.0) == b.above() && fraction != 0.0 => {}
            Some(b) if b.joint == joint + 1 => {
                return Err(HwError::Refused(format!("{b}: only a jog back inside is allowed")));
            }
            _ => return Err(HwError::Refused(format!("J{} is within its limits: jog it as usual", joint + 1))),
        }
        self.send(Request::JogBackInside { joint, fraction })
    }

    /// Releases the jog: the arm holds where the jog is.
    pub fn jog_release(&self) -> Result<(), HwError> {
        self.submit_motion(MotionCommand::JogRelease, None).map_err(HwError::from)
    }

    /// Moves to `goal_rad` along the synchronised speed- and acceleration-limited profile.
    /// The goal must lie within the joint limits (it is rejected, not clamped).
    pub fn move_to(&self, goal_rad: &[f64], speed_fraction: f64, kind: ProfileKind) -> Result<(), HwError> {
        self.device_ready()?;
        let cmd = MotionCommand::MoveJoints { goal_rad: goal_rad.to_vec(), speed_fraction, profile: kind };
        self.submit_motion(cmd, None).map_err(HwError::from)
    }

    /// [`HwError::Device`] when the link is down or the board's positions are impossible.
    fn device_ready(&self) -> Result<(), HwError> {
        match self.snapshot().motion_allowed() {
            Err(HwError::Device(why)) => Err(HwError::Device(why)),
            _ => Ok(()),
        }
    }

    /// [`Session::move_to`] and wait until the move has been streamed and the arm is within
    /// 3 steps of the goal on every joint. Ends at once, naming the cause, when the move is
    /// refused or stops before the goal ([`HwError::Device`] for a device or link event: link
    /// lost, E-stop, impossible positions, an arm that does not follow); after `timeout`
    /// [`HwError::Timeout`] says where each joint is against the goal.
    pub fn move_to_blocking(
        &self,
        goal_rad: &[f64],
        speed_fraction: f64,
        kind: ProfileKind,
        timeout: Duration,
    ) -> Result<Arc<Snapshot>, HwError> {
        self.move_to_blocking_or(goal_rad, speed_fraction, kind, timeout, &|| false)
    }

    /// [`Session::move_to_blocking`] that also returns as soon as `give_up()` is true (polled
    /// every 2 ms; a Ctrl-C): `Ok` with the snapshot of that instant, the move still under way
    /// (the caller stops it, e.g. with [`Session::stop`]).
    pub fn move_to_blocking_or(
        &self,
        goal_rad: &[f64],
        speed_fraction: f64,
        kind: ProfileKind,
        timeout: Duration,
        give_up: &dyn Fn() -> bool,
    ) -> Result<Arc<Snapshot>, HwError> {
        let goal_steps = joints_rad_to_steps(goal_rad)?;
        let refusal_before = self.robot_state().last_refusal.as_ref().map(|r| r.0);
        let implausible_before = self.snapshot().implausible_frames;
        let sent_at = Instant::now();
        self.move_to(goal_rad, speed_fraction, kind)?;
        let tol = 3;
        let end = sent_at + timeout;
        let mut moving_seen = false;
        loop {
            let s = self.snapshot();
            let after = s.published_at > sent_at && s.frames_sent > 0;
            let settled = s.motion == MotionState::Holding
                && s.target_steps == Some(goal_steps)
                && s.joint_steps.iter().zip(goal_steps).all(|(a, b)| (a - b).abs() <= tol);
            if (after && settled) || give_up() {
                return Ok(s);
            }
            if s.link == LinkState::Closed {
                return Err(HwError::Closed);
            }
            if s.link != LinkState::Connected {
                let why = s.fault.clone().unwrap_or_else(|| format!("link is {:?}", s.link));
                return Err(HwError::Device(format!("link lost during the move: {why}")));
            }
            if s.estop_pressed {
                return Err(HwError::Device("E-stop pressed during the move: motion stopped".into()));
            }
            if let Some(b) = s.limit_breach.filter(|b| b.impossible) {
                return Err(HwError::Device(impossible_answers(&b)));
            }
            let refusal = self.robot_state().last_refusal.clone();
            if let Some((_, why)) = refusal.filter(|r| Some(r.0) != refusal_before) {
                let implausible = s.implausible_frames.saturating_sub(implausible_before);
                return Err(if implausible > 0 {
                    HwError::Device(format!(
                        "{why}: the controller's answers are impossible ({implausible} status frames with positions \
                         no arm can reach since the move was sent)"
                    ))
                } else {
                    HwError::Refused(why)
                });
            }
            moving_seen |= after && s.motion != MotionState::Idle;
            if moving_seen && s.motion == MotionState::Idle {
                let why = s.fault.clone().unwrap_or_else(|| "motion was stopped".into());
                return Err(HwError::Device(format!(
                    "the move stopped before the goal: {why} (joints at {:?} steps, goal {goal_steps:?})",
                    s.joint_steps
                )));
            }
            if Instant::now() >= end {
                let why = s.fault.clone().map(|f| format!("; {f}")).unwrap_or_default();
                return Err(HwError::Timeout(format!(
                    "the arm did not reach the goal within {:.1} s (joints at {:?} steps, goal {goal_steps:?}, \
                     motion {:?}){why}",
                    timeout.as_secs_f64(),
                    s.joint_steps,
                    s.motion
                )));
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// Stops any motion (the arm holds the commanded position of this instant) or homing.
    pub fn stop(&self) -> Result<(), HwError> {
        self.submit_motion(MotionCommand::Stop, None).map_err(HwError::from)
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
        let _ = self.tx.send_timeout(Request::Shutdown, worker::CLOSE_WAIT);
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

//! What the session streams: the core [`MotionPlanner`] sampled on the motion clock
//! (`t = tick × period`, exact, never wall time), converted to steps for MOVE frames, and the
//! controller's homing routine (HOME frames, then IDLE until the homed bits are set).
//!
//! Motion starts from IDLE (after connecting, homing, an E-stop or a link loss) with the
//! planner reset to the *measured* position, so the first MOVE target is where the arm is.
//! Stopping streaming (E-stop, link loss, DISABLE, faults) resets the planner and sends IDLE;
//! no motion resumes by itself.

use std::time::Instant;

use parol6_core::limits::JointLimits;
use parol6_core::motion::stepper::StepperCommand;
use parol6_core::motion::tracking::{Tracker, TrackingMode};
use parol6_core::motion::{JogKinematics, MotionCaps, MotionCommand, MotionPlanner, PlannerMode, Setpoint};
use parol6_core::parol6::JOINT_COUNT;

use super::guard::limit_breach;
use super::snapshot::MotionState;
use crate::units::joints_rad_to_steps;

/// A MOVE frame's target and feed-forward, steps and steps/s.
pub(super) type MoveFields = ([i32; JOINT_COUNT], [i32; JOINT_COUNT]);

/// A MOVE target sent this recently (s) must agree with the measured position before a new
/// motion starts from it.
pub(super) const RECENT_TARGET_S: f64 = 1.0;

/// Progress of the controller's homing routine.
#[derive(Debug, Clone)]
pub(super) enum Homing {
    None,
    Sending { left: u32, started: Instant, seen_unhomed: bool },
    Waiting { started: Instant, seen_unhomed: bool },
}

/// The commanded trajectory of the session.
#[derive(Debug)]
pub(super) struct Streamer {
    planner: MotionPlanner,
    period_s: f64,
    tick: u64,
    streaming: bool,
    jog: Option<(usize, f64)>,
    setpoint: Option<Setpoint>,
    /// The setpoint of the tick before (what the status read at this tick answers).
    answered: Option<Setpoint>,
    /// Which targets the MOVE frames carry (`parol6_core::motion::tracking`, as the simulation).
    tracker: Tracker,
    /// The previous MOVE target sent and how many frames ago (the guard's reference).
    reference: Option<([i32; JOINT_COUNT], u32)>,
    /// The last MOVE target sent and its tick, kept across stops.
    last_sent: Option<([i32; JOINT_COUNT], u64)>,
    /// A new motion may not start from a measured position further than this from a MOVE
    /// target sent within [`RECENT_TARGET_S`] (the disagreement tolerance).
    start_tolerance_steps: i32,
    pub(super) homing: Homing,
    refusal_seq: u64,
    last_refusal: Option<(u64, String)>,
    planner_refusal_seen: u64,
}

impl Streamer {
    pub(super) fn new(
        limits: JointLimits,
        caps: MotionCaps,
        home: Vec<f64>,
        period_s: f64,
        tracking: TrackingMode,
    ) -> Self {
        let q0 = home.clone();
        Self {
            answered: None,
            tracker: Tracker::new(tracking, period_s),
            planner: MotionPlanner::new(limits, caps, home, &q0),
            period_s,
            tick: 0,
            streaming: false,
            jog: None,
            setpoint: None,
            reference: None,
            last_sent: None,
            start_tolerance_steps: i32::MAX,
            homing: Homing::None,
            refusal_seq: 0,
            last_refusal: None,
            planner_refusal_seen: 0,
        }
    }

    /// Refuses a new motion from a measured position further than `steps` from a recent MOVE
    /// target.
    pub(super) fn with_start_tolerance(mut self, steps: i32) -> Self {
        self.start_tolerance_steps = steps;
        self
    }

    /// Gives the planner the kinematics of Cartesian jogs and steps.
    pub(super) fn with_kinematics(mut self, kinematics: JogKinematics) -> Self {
        self.planner = self.planner.with_kinematics(kinematics);
        self
    }

    /// The motion clock of the coming frame, s.
    pub(super) fn time_s(&self) -> f64 {
        self.tick as f64 * self.period_s
    }

    /// Frames sent so far (the tick index).
    pub(super) fn tick(&self) -> u64 {
        self.tick
    }

    /// True while MOVE frames are streamed.
    pub(super) fn is_streaming(&self) -> bool {
        self.streaming
    }

    pub(super) fn planner(&self) -> &MotionPlanner {
        &self.planner
    }

    /// The setpoint of the tick before the last: the instant the latest status reply describes
    /// (the board answers frame k with its counters as frame k arrived, read at tick k + 1).
    pub(super) fn answered_setpoint(&self) -> Option<&Setpoint> {
        self.answered.as_ref().or(self.setpoint.as_ref())
    }

    pub(super) fn last_refusal(&self) -> Option<&(u64, String)> {
        self.last_refusal.as_ref()
    }

    pub(super) fn refuse(&mut self, msg: String) {
        self.refusal_seq += 1;
        self.last_refusal = Some((self.refusal_seq, msg));
    }

    /// Starts streaming from the measured position (planner reset there).
    fn start(&mut self, measured_rad: &[f64], measured_steps: &[i32; JOINT_COUNT]) {
        self.planner.reset(measured_rad);
        self.tracker.reset(measured_rad);
        self.streaming = true;
        self.jog = None;
        self.reference = Some((*measured_steps, 1));
    }

    /// Stops streaming: IDLE from now on, planner reset, scheduled commands dropped.
    pub(super) fn stop_streaming(&mut self) {
        if let Some(sp) = self.setpoint.take() {
            self.planner.reset(&sp.q);
        }
        self.streaming = false;
        self.jog = None;
        self.reference = None;
        self.answered = None;
    }

    /// Applies a motion command (immediately, or scheduled for `at_s`) at the current tick.
    /// `measured` is the last plausible measurement; `blocked` why motion is refused now.
    pub(super) fn apply(
        &mut self,
        cmd: MotionCommand,
        at_s: Option<f64>,
        measured: Option<([f64; JOINT_COUNT], [i32; JOINT_COUNT])>,
        blocked: Option<String>,
    ) -> Result<(), String> {
        let t = self.time_s();
        if at_s.is_some() {
            self.planner.note_scheduled();
        }
        if !cmd.starts_motion() && at_s.is_none() {
            if self.streaming {
                self.planner.apply(&cmd, t).map_err(|e| format!("{} refused: {e}", cmd.name()))?;
                self.jog = None;
            }
            return Ok(());
        }
        if let Some(why) = blocked {
            return Err(format!("{} refused: {why}", cmd.name()));
        }
        let was_streaming = self.streaming;
        if !was_streaming {
            let (q, steps) = measured.ok_or_else(|| {
                format!("{} refused: no steady status from the board yet (the arm is settling): try again", cmd.name())
            })?;
            // The first MOVE target is the measured position: never one outside the limits.
            if let Some(b) = limit_breach(&steps) {
                return Err(format!("{} refused: {b}: a MOVE target there would lie outside the limits", cmd.name()));
            }
            self.check_recent_target(&steps).map_err(|why| format!("{} refused: {why}", cmd.name()))?;
            self.start(&q, &steps);
        }
        let res = match at_s {
            None => self.planner.apply(&cmd, t),
            Some(at) => self.planner.schedule_arriving(cmd.clone(), at, t),
        };
        if let Err(e) = res {
            if !was_streaming {
                self.streaming = false;
                self.reference = None;
            }
            return Err(format!("{} refused: {e}", cmd.name()));
        }
        if at_s.is_none() {
            self.jog = match cmd {
                MotionCommand::JogJoint { joint, fraction } => Some((joint, fraction.clamp(-1.0, 1.0))),
                _ => None,
            };
        }
        Ok(())
    }

    /// Samples the trajectory at this tick's time (scheduled commands due by then are applied
    /// at their exact times) and returns the MOVE target and feed-forward in steps, in the
    /// tracking mode; `None` while IDLE. A target that cannot be expressed in steps stops
    /// streaming and is returned as the error.
    pub(super) fn sample_target(&mut self) -> Result<Option<MoveFields>, String> {
        if !self.streaming {
            self.setpoint = None;
            self.answered = None;
            return Ok(None);
        }
        let t = self.time_s();
        let sp = self.planner.sample(t);
        if let Some((id, msg)) = self.planner.last_refusal()
            && *id != self.planner_refusal_seen
        {
            self.planner_refusal_seen = *id;
            let msg = msg.clone();
            self.refuse(msg);
        }
        if self.planner.mode() != PlannerMode::Jog {
            self.jog = None;
        }
        let (target, stop) = self.tracker.targets(&self.planner, t, &sp);
        let fields = match (joints_rad_to_steps(target), stop.map(joints_rad_to_steps).transpose()) {
            (Ok(_), Ok(_)) => parol6_core::motion::stepper::move_fields(target, stop),
            (Err(e), _) | (_, Err(e)) => {
                self.stop_streaming();
                return Err(format!("commanded target cannot be sent: {e}"));
            }
        };
        self.answered = self.setpoint.replace(sp);
        match fields {
            Some(StepperCommand::Move { target_steps, speed_steps_s }) => Ok(Some((target_steps, speed_steps_s))),
            _ => {
                self.stop_streaming();
                Err("commanded target cannot be sent: not a finite number".into())
            }
        }
    }

    /// The guard's reference for this tick's MOVE frame.
    pub(super) fn reference(&self) -> Option<(&[i32; JOINT_COUNT], u32)> {
        self.reference.as_ref().map(|(r, n)| (r, *n))
    }

    /// A MOVE target sent within [`RECENT_TARGET_S`] far from `measured` means the board's
    /// answers do not follow its motion (stale status) or the arm was stopped by force: a first
    /// target at the measured position would make the arm jump back at full speed.
    fn check_recent_target(&self, measured: &[i32; JOINT_COUNT]) -> Result<(), String> {
        let Some((last, tick)) = self.last_sent else { return Ok(()) };
        let ago_s = self.tick.saturating_sub(tick) as f64 * self.period_s;
        if ago_s > RECENT_TARGET_S {
            return Ok(());
        }
        let far = (0..JOINT_COUNT)
            .map(|i| (i, (i64::from(measured[i]) - i64::from(last[i])).abs()))
            .find(|(_, d)| *d > i64::from(self.start_tolerance_steps));
        match far {
            Some((i, d)) => Err(format!(
                "J{} measured {d} steps from the target sent {:.0} ms ago: the board's position does not follow \
                 its motion (stale answers, or the arm was stopped); try again in {RECENT_TARGET_S:.0} s",
                i + 1,
                ago_s * 1e3
            )),
            None => Ok(()),
        }
    }

    /// Ends the tick: `sent_target` is the MOVE target actually written (after the guard).
    pub(super) fn end_tick(&mut self, sent_target: Option<[i32; JOINT_COUNT]>) {
        if let Some(t) = sent_target {
            self.last_sent = Some((t, self.tick));
        }
        match (sent_target, self.reference.as_mut()) {
            (Some(t), _) => self.reference = Some((t, 1)),
            (None, Some((_, n))) => *n = n.saturating_add(1),
            (None, None) => {}
        }
        self.tick += 1;
    }

    /// What is being streamed, for the snapshot.
    pub(super) fn motion_state(&self) -> MotionState {
        if !matches!(self.homing, Homing::None) {
            return MotionState::Homing;
        }
        if !self.streaming {
            return MotionState::Idle;
        }
        let t = self.time_s();
        match (self.planner.mode(), self.jog) {
            (PlannerMode::Jog, Some((joint, fraction))) => MotionState::Jogging { joint, fraction },
            (PlannerMode::Hold, _) => MotionState::Holding,
            _ => MotionState::Moving { remaining_s: (self.planner.path_end_s() - t).max(0.0) },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use parol6_core::RobotModel;
    use parol6_core::motion::home_position;

    fn streamer() -> Streamer {
        let model = RobotModel::parol6();
        Streamer::new(
            JointLimits::parol6(),
            MotionCaps::of(&model),
            home_position(&model),
            0.01,
            TrackingMode::Official,
        )
    }

    #[test]
    fn first_target_is_the_measured_position() {
        let mut s = streamer();
        let steps = crate::units::STANDBY_STEPS;
        let q = crate::units::joints_steps_to_rad(&steps);
        assert_eq!(s.sample_target().map(|t| t.map(|(p, _)| p)), Ok(None));
        s.end_tick(None);
        s.apply(MotionCommand::JogJoint { joint: 3, fraction: 0.5 }, None, Some((q, steps)), None).unwrap();
        assert_eq!(s.sample_target().map(|t| t.map(|(p, _)| p)), Ok(Some(steps)), "the jog starts where the arm is");
        s.end_tick(Some(steps));
        let next = s.sample_target().map(|t| t.map(|(p, _)| p)).unwrap().unwrap();
        assert!(next[3] > steps[3]);
        assert_eq!(next[..3], steps[..3]);
        assert!(matches!(s.motion_state(), MotionState::Jogging { joint: 3, .. }));
    }

    #[test]
    fn refusals_name_the_reason_and_stops_never_start_motion() {
        let mut s = streamer();
        let steps = crate::units::STANDBY_STEPS;
        let q = crate::units::joints_steps_to_rad(&steps);
        let e = s.apply(MotionCommand::home(), None, Some((q, steps)), Some("E-stop is pressed".into()));
        assert!(e.unwrap_err().contains("E-stop"));
        s.apply(MotionCommand::Stop, None, None, None).unwrap();
        assert!(!s.is_streaming());
        assert_eq!(s.motion_state(), MotionState::Idle);
    }

    /// Issue 29 item 11: streaming started from the measured position, so a board reporting
    /// J1 = 100 000 got MOVE targets there. From beyond a limit no MOVE starts (only a confirmed
    /// JOG back inside does, see `Session::jog_back_inside`).
    #[test]
    fn motion_never_starts_from_beyond_a_limit() {
        let mut s = streamer();
        for (joint, at) in [(0, 14_050), (0, 100_000), (2, -200_000)] {
            let mut steps = crate::units::STANDBY_STEPS;
            steps[joint] = at;
            let q = crate::units::joints_steps_to_rad(&steps);
            for fraction in [0.5, -0.5] {
                let out = s.apply(MotionCommand::JogJoint { joint, fraction }, None, Some((q, steps)), None);
                assert!(out.unwrap_err().contains("beyond its"), "J{} at {at}", joint + 1);
                assert!(!s.is_streaming());
                assert_eq!(s.sample_target(), Ok(None));
            }
        }
    }
}

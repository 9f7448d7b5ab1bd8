//! The planner's schedule: commands waiting for their time on the motion clock, and how the
//! schedule slips as a whole when a step is handed over late.
//!
//! A program runner schedules its steps back to back (each at the instant the one before it
//! ends). A step that reaches the backend after its time cannot start then: it starts when it
//! arrives, and every step after it would come too early (its trajectory starts where the late
//! one ends, which the arm has not reached yet). Instead of refusing those, the whole schedule
//! slips: the planner keeps a delay ([`ScheduleState::delay_s`]) added to every scheduled
//! time, raised when a command arrives late ([`MotionPlanner::schedule_arriving`]) and when a
//! trajectory that continues the running one falls due before that one ends. Nothing in the
//! schedule changes its timing relative to the rest (dwells keep their length) and every
//! trajectory still starts exactly where the commanded position is. A schedule that keeps its
//! time is applied exactly as before (the delay stays 0).

use super::{Motion, MotionPlanner, Scheduled, TRAJECTORY_START_TOLERANCE_RAD};
use crate::motion::{MotionCommand, MotionError, ScheduleState};

impl MotionPlanner {
    /// Schedules `cmd` for `at_s` on the motion clock (plus the schedule's delay, 0 unless it
    /// slipped); it is applied at exactly that time during the first
    /// [`MotionPlanner::sample`] at or after it (refusals then show in
    /// [`MotionPlanner::last_refusal`]). Checked against the limits now.
    pub fn schedule(&mut self, cmd: MotionCommand, at_s: f64) -> Result<(), MotionError> {
        if !at_s.is_finite() {
            return Err(MotionError::Invalid(format!("schedule time {at_s} is not a finite number")));
        }
        self.validate(&cmd)?;
        self.order += 1;
        let s = Scheduled { at_s, order: self.order, cmd };
        let pos = self.pending.partition_point(|p| (p.at_s, p.order) <= (s.at_s, s.order));
        self.pending.insert(pos, s);
        Ok(())
    }

    /// [`MotionPlanner::schedule`] for a command that arrives at `now_s`: one that comes after
    /// its time (delay included) starts now, and the whole schedule slips by as much (see the
    /// module's documentation), so the steps scheduled after it keep their place.
    pub fn schedule_arriving(&mut self, cmd: MotionCommand, at_s: f64, now_s: f64) -> Result<(), MotionError> {
        self.schedule(cmd, at_s)?;
        if at_s + self.delay_s < now_s {
            self.delay_s = now_s - at_s;
        }
        Ok(())
    }

    /// Counts a scheduled command as received (before anything can refuse it), so a client
    /// can tell a state that has seen its commands ([`ScheduleState::received`]).
    pub fn note_scheduled(&mut self) {
        self.received += 1;
    }

    /// How the schedule stands: commands received and its delay.
    pub fn schedule_state(&self) -> ScheduleState {
        ScheduleState { received: self.received, delay_s: self.delay_s }
    }

    /// Applies `cmd` at `t_s` as a scheduled command does (scheduled commands are kept).
    pub fn apply_scheduled(&mut self, cmd: &MotionCommand, t_s: f64) -> Result<(), MotionError> {
        self.apply_at(cmd, t_s)
    }

    /// Takes the earliest scheduled command due by `t_s`, with the time it is due at, for a
    /// backend that checks more before applying it (the simulation's collision guard); the
    /// backend then calls [`MotionPlanner::apply_scheduled`] with that time.
    pub fn pop_due(&mut self, t_s: f64) -> Option<(f64, MotionCommand)> {
        let at = self.head_due_by(t_s)?;
        let s = self.pending.remove(0);
        Some((at, s.cmd))
    }

    /// Number of scheduled commands not yet applied.
    pub fn pending(&self) -> usize {
        self.pending.len()
    }

    /// Applies the scheduled commands due by `t_s` in order; refusals are recorded.
    pub(super) fn apply_due(&mut self, t_s: f64) {
        while let Some(at) = self.head_due_by(t_s) {
            let s = self.pending.remove(0);
            if let Err(e) = self.apply_at(&s.cmd, at) {
                self.refusal_seq += 1;
                self.last_refusal = Some((self.refusal_seq, format!("{} at t = {at:.3} s refused: {e}", s.cmd.name())));
            }
        }
    }

    /// Forgets the schedule's delay (with its commands: a reset, STOP, PAUSE).
    pub(super) fn clear_schedule(&mut self) {
        self.pending.clear();
        self.delay_s = 0.0;
    }

    /// When the first scheduled command is due, if by `t_s`. A trajectory that continues the
    /// running one (it starts at that one's goal) is due no earlier than that one's end: the
    /// schedule slips by the difference.
    fn head_due_by(&mut self, t_s: f64) -> Option<f64> {
        let first = self.pending.first()?;
        let mut due = first.at_s + self.delay_s;
        if due > t_s {
            return None;
        }
        if let (MotionCommand::Trajectory(next), Motion::Trajectory { t0, traj, warp }) = (&first.cmd, &self.motion)
            && let Some(end) = warp.end_clock(*t0, traj.duration_s())
            && end > due
            && next.samples().first().is_some_and(|start| {
                start.len() == traj.goal().len()
                    && start.iter().zip(traj.goal()).all(|(a, b)| (a - b).abs() <= TRAJECTORY_START_TOLERANCE_RAD)
            })
        {
            // `at + delay` may fall a rounding short of `end`: the command is applied at `end`
            self.delay_s = self.delay_s.max(end - first.at_s);
            due = end;
            if due > t_s {
                return None;
            }
        }
        Some(due)
    }
}

//! The runner's waits: pausing on the path, idling until the operator decides, finishing a
//! paused step, and waiting for a digital input.

use std::collections::VecDeque;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use super::{Halt, POLL, Run, RunState, RunnerControl, SETTLE_BETWEEN_PASSES, Slot};
use crate::motion::{MotionCommand, PlannerMode, RobotState, TRAJECTORY_START_TOLERANCE_RAD, stop_best_effort};
use crate::profile::ProfileKind;
use crate::program::compile::{CompiledStep, StepAction};

/// Fraction of the joint speed and acceleration caps of the move that takes the arm back to
/// where a paused program left off, when the operator moved it meanwhile ([`Run::regain`]).
pub const REGAIN_SPEED_FRACTION: f64 = 0.2;
/// The longest the move back to the program's path may take, s of wall time.
const REGAIN_TIMEOUT: Duration = Duration::from_secs(120);

/// Where a run plans from: the hold position when the planner holds, the point a trajectory
/// handed to it must start from. A robot's `commanded` is the setpoint of the frame the board
/// answered, one frame late: just after a move ends it can lie a fraction of a motor step short
/// of the hold, and a pass planned from there was refused ("the trajectory starts 0.0001° away
/// from the commanded position"), ending a looping run between passes.
pub(super) fn hold_position(s: &RobotState) -> Vec<f64> {
    if s.mode == PlannerMode::Hold && !s.moving && s.target_q.len() == s.commanded.q.len() {
        s.target_q.clone()
    } else {
        s.commanded.q.clone()
    }
}

impl Run<'_> {
    /// Between the passes of a looping run: waits until the arm is at rest (a robot's measured
    /// joints lag the commanded ones and settle after the last step ends), at most
    /// [`SETTLE_BETWEEN_PASSES`]; STOP, an abort or a blocked backend end the wait, PAUSE
    /// pauses it.
    pub(super) fn settle_between_passes(&mut self) -> Result<(), Halt> {
        let started = std::time::Instant::now();
        loop {
            let s = self.backend.state();
            if let Some(b) = &s.blocked {
                return Err(Halt::Failed(format!("halted between passes: {b}")));
            }
            if !s.moving && s.mode == PlannerMode::Hold {
                return Ok(());
            }
            if started.elapsed() > SETTLE_BETWEEN_PASSES {
                return Err(Halt::Failed(format!(
                    "the arm did not come to rest within {:.0} s after the pass",
                    SETTLE_BETWEEN_PASSES.as_secs_f64()
                )));
            }
            match self.poll_control() {
                Some(RunnerControl::Stop) => {
                    self.stop_arm("stopped between passes");
                    return Err(Halt::Stopped);
                }
                Some(RunnerControl::Pause) => self.idle_until_control()?,
                Some(RunnerControl::Step) => self.single = true,
                Some(RunnerControl::Resume) | None => {}
            }
            if self.abort.load(Ordering::SeqCst) {
                return Err(Halt::Aborted);
            }
            std::thread::sleep(POLL);
        }
    }

    /// The backend's state after one poll period; a refusal or an abort of the run ends the wait.
    fn next_state(&self) -> Result<std::sync::Arc<RobotState>, Halt> {
        std::thread::sleep(POLL);
        let s = self.backend.state();
        if let Some(b) = &s.blocked {
            return Err(Halt::Failed(format!("halted: {b}")));
        }
        if self.abort.load(Ordering::SeqCst) {
            return Err(Halt::Aborted);
        }
        Ok(s)
    }

    /// Sends STOP ([`stop_best_effort`]); a refused one is recorded in the progress
    /// ([`RunProgress::stop_failed`](super::RunProgress::stop_failed)), where the window and
    /// `parol6 program run` show it.
    pub(super) fn stop_arm(&self, during: &str) {
        if let Some(failure) = stop_best_effort(self.backend, during) {
            self.publish(|p| p.stop_failed = Some(failure));
        }
    }

    /// Pauses on the path (the backend drops the steps scheduled after the one under way) and
    /// waits until the arm has stopped. Returns the first step not finished: the one paused
    /// mid-way, or the next one.
    pub(super) fn pause_now(
        &mut self,
        compiled: &[CompiledStep],
        slots: &mut VecDeque<Slot>,
        next: usize,
    ) -> Result<usize, Halt> {
        self.backend.send(MotionCommand::Pause).map_err(|e| Halt::Failed(format!("pause: {e}")))?;
        let t0 = Instant::now();
        loop {
            let s = self.next_state()?;
            if s.moving && t0.elapsed() < Duration::from_secs(5) {
                continue;
            }
            // the planner's goal is the end of the trajectory that holds the arm
            let holding = slots.iter().position(|sl| {
                matches!(compiled[sl.index].action, StepAction::Motion(_)) && compiled[sl.index].end_q == s.target_q
            });
            let done = match holding {
                Some(k) if s.mode == PlannerMode::Paused => k,
                Some(k) => k + 1,
                // nothing of the schedule has moved yet (a dwell or I/O at the head)
                None => 0,
            };
            for _ in 0..done.min(slots.len()) {
                self.finish_slot(slots, compiled);
            }
            return Ok(slots.front().map_or(next, |sl| sl.index));
        }
    }

    /// Waits while paused until Resume, Step or Stop.
    pub(super) fn idle_until_control(&mut self) -> Result<(), Halt> {
        self.publish(|p| p.state = RunState::Paused);
        loop {
            match self.control.recv_timeout(Duration::from_millis(20)) {
                Ok(RunnerControl::Resume) => {
                    self.single = false;
                    break;
                }
                Ok(RunnerControl::Step) => {
                    self.single = true;
                    break;
                }
                Ok(RunnerControl::Stop) => {
                    self.stop_arm("stopped while paused");
                    return Err(Halt::Stopped);
                }
                Ok(RunnerControl::Pause) | Err(crossbeam_channel::RecvTimeoutError::Timeout) => {}
                Err(crossbeam_channel::RecvTimeoutError::Disconnected) => return Err(Halt::Stopped),
            }
            if let Some(b) = &self.backend.state().blocked {
                return Err(Halt::Failed(format!("halted while paused: {b}")));
            }
            if self.abort.load(Ordering::SeqCst) {
                return Err(Halt::Aborted);
            }
        }
        self.publish(|p| p.state = RunState::Running);
        Ok(())
    }

    /// Where step `k` of `compiled` starts: where the step before it ends (the run's start for
    /// the first). `None` past the last step.
    pub(super) fn start_of(&self, compiled: &[CompiledStep], k: usize) -> Option<Vec<f64>> {
        match k {
            0 => Some(self.start_q.clone()),
            _ if k < compiled.len() => Some(compiled[k - 1].end_q.clone()),
            _ => None,
        }
    }

    /// After the run waited for the operator (paused, a pause step, single step): where the
    /// operator moved the arm meanwhile (a jog, a typed joint, HOME), the paused trajectory is
    /// gone and step `k` would start away from the arm (its trajectory was refused, and the
    /// run failed). A profiled joint move at [`REGAIN_SPEED_FRACTION`] first takes the arm back
    /// to where step `k` starts, shown as what the run waits for. Nothing moves where the arm
    /// is there already, or where the paused trajectory is still held (resume finishes it).
    pub(super) fn regain(&mut self, compiled: &[CompiledStep], k: usize) -> Result<(), Halt> {
        let Some(want) = self.start_of(compiled, k) else { return Ok(()) };
        let s = self.backend.state();
        let off = |q: &[f64]| q.iter().zip(&want).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        if s.mode == PlannerMode::Paused
            || s.commanded.q.len() != want.len()
            || off(&s.commanded.q) <= TRAJECTORY_START_TOLERANCE_RAD
        {
            return Ok(());
        }
        let step = compiled[k].steps.start + 1;
        let away_deg = off(&s.commanded.q).to_degrees();
        self.publish(|p| {
            p.waiting_for =
                Some(format!("the arm to return to where step {step} starts (moved {away_deg:.1}° while paused)"))
        });
        let back = MotionCommand::MoveJoints {
            goal_rad: want.clone(),
            speed_fraction: REGAIN_SPEED_FRACTION,
            profile: ProfileKind::Trapezoidal,
        };
        self.backend.send(back).map_err(|e| Halt::Failed(format!("the return to where step {step} starts: {e}")))?;
        let t0 = Instant::now();
        loop {
            let s = self.next_state()?;
            match self.poll_control() {
                Some(RunnerControl::Stop) => {
                    self.stop_arm("stopped while returning to the program's path");
                    return Err(Halt::Stopped);
                }
                Some(RunnerControl::Pause) => {
                    self.stop_arm("paused while returning to the program's path");
                    self.idle_until_control()?;
                    return self.regain(compiled, k);
                }
                Some(RunnerControl::Step) => self.single = true,
                Some(RunnerControl::Resume) | None => {}
            }
            if !s.moving && s.mode == PlannerMode::Hold && off(&s.commanded.q) <= TRAJECTORY_START_TOLERANCE_RAD {
                break;
            }
            if t0.elapsed() > REGAIN_TIMEOUT {
                return Err(Halt::Failed(format!(
                    "the arm did not return to where step {step} starts within {:.0} s",
                    REGAIN_TIMEOUT.as_secs_f64()
                )));
            }
        }
        self.publish(|p| p.waiting_for = None);
        Ok(())
    }

    /// Finishes the trajectory of step `k` if it was paused mid-way; returns the step to
    /// schedule next.
    pub(super) fn resume_from(&mut self, compiled: &[CompiledStep], k: usize) -> Result<usize, Halt> {
        if self.backend.state().mode != PlannerMode::Paused {
            return Ok(k);
        }
        self.backend.send(MotionCommand::Resume).map_err(|e| Halt::Failed(format!("resume: {e}")))?;
        loop {
            std::thread::sleep(POLL);
            let s = self.backend.state();
            if let Some(b) = &s.blocked {
                return Err(Halt::Failed(format!("halted: {b}")));
            }
            if let Some(RunnerControl::Stop) = self.poll_control() {
                self.stop_arm("stopped while resuming");
                return Err(Halt::Stopped);
            }
            if s.mode == PlannerMode::Hold && !s.moving {
                self.last_end_s = s.time_s;
                break;
            }
        }
        if let Some(c) = compiled.get(k) {
            self.publish(|p| {
                p.steps_done = c.steps.end;
                p.step = c.steps.end.min(p.steps.saturating_sub(1));
            });
        }
        Ok(k + 1)
    }

    pub(super) fn wait_input(&self, input: u8, on: bool, timeout_s: f64) -> Result<(), Halt> {
        let what = format!("input {input} {}", if on { "high" } else { "low" });
        self.publish(|p| p.waiting_for = Some(what.clone()));
        let start = self.backend.state().time_s;
        loop {
            let s = self.backend.state();
            if s.io.inputs.get(usize::from(input).saturating_sub(1)).copied() == Some(on) {
                self.publish(|p| p.waiting_for = None);
                return Ok(());
            }
            if let Some(b) = &s.blocked {
                return Err(Halt::Failed(format!("halted while waiting for {what}: {b}")));
            }
            if s.time_s - start > timeout_s {
                return Err(Halt::Failed(format!("{what} did not come within {timeout_s:.1} s")));
            }
            if let Some(RunnerControl::Stop) = self.poll_control() {
                return Err(Halt::Stopped);
            }
            std::thread::sleep(POLL);
        }
    }
}

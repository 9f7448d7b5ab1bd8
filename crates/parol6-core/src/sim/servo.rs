//! The simulated PAROL6 board: each 10 ms frame instant the planner's target in the tracking
//! mode ([`crate::motion::tracking`]) becomes a MOVE command held for the period, and the drives
//! step by the firmware's law ([`crate::motion::stepper`], the emulated board's own).

use crate::motion::stepper::{StepperCommand, Steppers};
use crate::motion::tracking::{Tracker, TrackingMode};
use crate::motion::{MotionPlanner, Setpoint};
use crate::parol6::JOINT_COUNT;

/// The board's frame period, s.
const FRAME_S: f64 = 0.01;

/// The simulated drives and the target stream that feeds them.
#[derive(Debug, Clone)]
pub(super) struct SimServo {
    steppers: Steppers,
    tracker: Tracker,
    /// Simulation steps per frame.
    frame_steps: u64,
}

impl SimServo {
    /// Drives at rest at `q_rad`, frames every 10 ms of steps of `dt_s`.
    pub(super) fn new(q_rad: &[f64], mode: TrackingMode, dt_s: f64) -> Self {
        Self {
            steppers: Steppers::at_rad(q_rad),
            tracker: Tracker::new(mode, FRAME_S),
            frame_steps: ((FRAME_S / dt_s).round() as u64).max(1),
        }
    }

    pub(super) fn set_mode(&mut self, mode: TrackingMode) {
        self.tracker.set_mode(mode);
    }

    pub(super) fn mode(&self) -> TrackingMode {
        self.tracker.mode()
    }

    /// At rest at the whole steps nearest `q_rad`, holding there.
    pub(super) fn teleport(&mut self, q_rad: &[f64]) {
        self.steppers.teleport_rad(q_rad);
        self.tracker.reset(q_rad);
    }

    /// One simulation step from step index `step` (time `t_s`, the planner sampled there as
    /// `commanded`): a new frame on the 10 ms grid, then `dt_s` of firmware loop.
    pub(super) fn step(&mut self, step: u64, t_s: f64, dt_s: f64, planner: &MotionPlanner, commanded: &Setpoint) {
        if step.is_multiple_of(self.frame_steps) {
            let cmd = self.tracker.command(planner, t_s, commanded);
            self.steppers.set_command(cmd.unwrap_or(StepperCommand::Hold));
        }
        self.steppers.advance(dt_s);
    }

    /// The step counters (rad) and speeds (rad/s), as the board reports them.
    pub(super) fn read(&self, q: &mut [f64], qd: &mut [f64]) {
        for j in 0..JOINT_COUNT.min(q.len()).min(qd.len()) {
            q[j] = self.steppers.q_rad(j);
            qd[j] = self.steppers.qd_rad_s(j);
        }
    }

    /// True while the drives step.
    pub(super) fn moving(&self) -> bool {
        self.steppers.speed_steps_s().iter().any(|v| *v != 0.0)
    }
}

//! The PAROL6 firmware's stepper law (PROTOCOL.md §5), the one copy of it: the emulated board
//! (`parol6_hw::emulator`) and the simulation ([`crate::sim`]) both step their joints with it,
//! so the two can never diverge.
//!
//! - MOVE: `v = trunc((ff + trunc((target − round(pos)) / 0.01)) / 2)` steps/s, clamped to
//!   ±[`FW_MAX_SPEED_STEPS_S`]: a first-order lag of time constant [`MOVE_TIME_CONSTANT_S`]
//!   (20 ms) toward the target, plus half the feed-forward speed.
//! - JOG: the commanded speed, clamped the same way.
//! - The firmware loop recomputes the speed far faster than the host's 10 ms frames; it is
//!   integrated here in sub-steps of [`SUBSTEP_S`], the speed recomputed before each, and the
//!   step counter the board reports is the position rounded to whole steps.
//!
//! Units: steps and steps/s of each joint's motor ([`crate::parol6::rad_per_step`]);
//! [`steps_of_rad`] is the one rad → steps rounding (the serial session's too).

use crate::parol6::{JOINT_COUNT, MAX_SPEED_STEPS_S, rad_per_step};

/// The firmware's hard-coded MOVE period, s (the `/ 0.01` of the law).
pub const FW_MOVE_PERIOD_S: f64 = 0.01;
/// Time constant of the MOVE law with zero feed-forward, s: `v ≈ (err / 0.01) / 2`.
pub const MOVE_TIME_CONSTANT_S: f64 = 2.0 * FW_MOVE_PERIOD_S;
/// Integration sub-step, s (the firmware loop runs much faster than the host rate).
pub const SUBSTEP_S: f64 = 0.0005;
/// Firmware speed clamp for JOG and MOVE, steps/s (AccelStepper max speed, ROBOT.md §1).
pub const FW_MAX_SPEED_STEPS_S: f64 = 50_000.0;

/// What the board's drives are told to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepperCommand {
    /// MOVE: go to `target_steps` with feed-forward `speed_steps_s`.
    Move {
        /// Target step counters.
        target_steps: [i32; JOINT_COUNT],
        /// Feed-forward speeds, steps/s (zero: the official API's way).
        speed_steps_s: [i32; JOINT_COUNT],
    },
    /// JOG at `speed_steps_s`.
    Jog {
        /// Speeds, steps/s.
        speed_steps_s: [i32; JOINT_COUNT],
    },
    /// Not stepping (IDLE, disabled, no command yet).
    Hold,
}

/// The MOVE law's speed for one joint, steps/s.
pub fn move_speed_steps_s(position_steps: f64, target_steps: i32, ff_steps_s: i32) -> f64 {
    let err = f64::from(target_steps) - position_steps.round();
    let p = (err / FW_MOVE_PERIOD_S).trunc();
    ((f64::from(ff_steps_s) + p) / 2.0).trunc().clamp(-FW_MAX_SPEED_STEPS_S, FW_MAX_SPEED_STEPS_S)
}

/// The JOG law's speed for one joint, steps/s.
pub fn jog_speed_steps_s(speed_steps_s: i32) -> f64 {
    f64::from(speed_steps_s).clamp(-FW_MAX_SPEED_STEPS_S, FW_MAX_SPEED_STEPS_S)
}

/// The sub-steps `dt_s` is integrated in (at most 1 s; nothing for a bad or non-positive time).
pub fn substeps(dt_s: f64) -> impl Iterator<Item = f64> {
    let mut left = if dt_s.is_finite() && dt_s > 0.0 { dt_s.min(1.0) } else { 0.0 };
    std::iter::from_fn(move || {
        (left > 0.0).then(|| {
            let h = left.min(SUBSTEP_S);
            left -= h;
            h
        })
    })
}

/// Joint angle (rad) → steps, rounded half to even (the official API's `np.rint`); not range
/// checked (the wire's 24-bit check is `parol6_hw::units`).
pub fn steps_of_rad(joint: usize, rad: f64) -> f64 {
    (rad / rad_per_step(joint)).round_ties_even()
}

/// The six drives of the board: step counters (fractional between whole steps) and speeds.
#[derive(Debug, Clone, PartialEq)]
pub struct Steppers {
    position_steps: [f64; JOINT_COUNT],
    speed_steps_s: [f64; JOINT_COUNT],
    command: StepperCommand,
}

impl Steppers {
    /// Drives at rest at these step counters.
    pub fn at(position_steps: [i32; JOINT_COUNT]) -> Self {
        Self {
            position_steps: position_steps.map(f64::from),
            speed_steps_s: [0.0; JOINT_COUNT],
            command: StepperCommand::Hold,
        }
    }

    /// Drives at rest at the whole steps nearest these joint angles, rad.
    pub fn at_rad(q_rad: &[f64]) -> Self {
        let mut s = Self::at([0; JOINT_COUNT]);
        s.teleport_rad(q_rad);
        s
    }

    /// Puts the drives at rest at the whole steps nearest `q_rad` (joints beyond six ignored).
    pub fn teleport_rad(&mut self, q_rad: &[f64]) {
        for (j, q) in q_rad.iter().take(JOINT_COUNT).enumerate() {
            self.position_steps[j] = steps_of_rad(j, *q);
        }
        self.speed_steps_s = [0.0; JOINT_COUNT];
        self.command = StepperCommand::Hold;
    }

    /// Step counters as the board reports them (rounded).
    pub fn position_steps(&self) -> [i32; JOINT_COUNT] {
        self.position_steps.map(|p| p.round() as i32)
    }

    /// Step counters, unrounded.
    pub fn position_steps_f64(&self) -> &[f64; JOINT_COUNT] {
        &self.position_steps
    }

    /// Sets the step counters (the emulator's homing writes the standby pose).
    pub fn set_position_steps(&mut self, steps: [f64; JOINT_COUNT]) {
        self.position_steps = steps;
    }

    /// Speed set points, steps/s.
    pub fn speed_steps_s(&self) -> &[f64; JOINT_COUNT] {
        &self.speed_steps_s
    }

    /// Overrides the speed set points (what IDLE and homing show; they do not step).
    pub fn set_speeds_steps_s(&mut self, speeds: [f64; JOINT_COUNT]) {
        self.speed_steps_s = speeds;
    }

    /// The command being executed.
    pub fn command(&self) -> StepperCommand {
        self.command
    }

    /// Takes a new command and sets the speeds it implies now.
    pub fn set_command(&mut self, command: StepperCommand) {
        self.command = command;
        self.update_speeds();
    }

    /// Sets the speeds the current command implies at the current position.
    pub fn update_speeds(&mut self) {
        match self.command {
            StepperCommand::Move { target_steps, speed_steps_s } => {
                for j in 0..JOINT_COUNT {
                    self.speed_steps_s[j] =
                        move_speed_steps_s(self.position_steps[j], target_steps[j], speed_steps_s[j]);
                }
            }
            StepperCommand::Jog { speed_steps_s } => self.speed_steps_s = speed_steps_s.map(jog_speed_steps_s),
            StepperCommand::Hold => self.speed_steps_s = [0.0; JOINT_COUNT],
        }
    }

    /// One sub-step of `h_s` at the current speeds (set them first with
    /// [`Steppers::update_speeds`]).
    pub fn integrate(&mut self, h_s: f64) {
        for j in 0..JOINT_COUNT {
            self.position_steps[j] += self.speed_steps_s[j] * h_s;
        }
    }

    /// Lets `dt_s` of firmware loop pass under the current command.
    pub fn advance(&mut self, dt_s: f64) {
        for h in substeps(dt_s) {
            self.update_speeds();
            if self.command != StepperCommand::Hold {
                self.integrate(h);
            }
        }
    }

    /// Joint angle of drive `joint` (rad), unrounded counter.
    pub fn q_rad(&self, joint: usize) -> f64 {
        self.position_steps[joint].round() * rad_per_step(joint)
    }

    /// Joint speed of drive `joint`, rad/s.
    pub fn qd_rad_s(&self, joint: usize) -> f64 {
        self.speed_steps_s[joint].trunc() * rad_per_step(joint)
    }
}

/// The MOVE frame's fields for a target (rad) and, with feed-forward, the point (rad) the
/// drives would settle on if the link were lost now: speed = (stop − target) / 10 ms in whole
/// steps, clamped to the joint's API max speed. `None` when an angle is not finite.
pub fn move_fields(target_rad: &[f64], stop_rad: Option<&[f64]>) -> Option<StepperCommand> {
    let mut target_steps = [0; JOINT_COUNT];
    let mut speed_steps_s = [0; JOINT_COUNT];
    for j in 0..JOINT_COUNT {
        let t = steps_of_rad(j, *target_rad.get(j)?);
        if !t.is_finite() {
            return None;
        }
        target_steps[j] = t as i32;
        if let Some(stop) = stop_rad {
            let s = steps_of_rad(j, *stop.get(j)?);
            if !s.is_finite() {
                return None;
            }
            let v = ((s - t) / FW_MOVE_PERIOD_S).round();
            speed_steps_s[j] = v.clamp(-MAX_SPEED_STEPS_S[j], MAX_SPEED_STEPS_S[j]) as i32;
        }
    }
    Some(StepperCommand::Move { target_steps, speed_steps_s })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn move_law_is_half_the_error_per_period() {
        assert_eq!(move_speed_steps_s(0.0, 100, 0), 5000.0);
        assert_eq!(move_speed_steps_s(0.0, -100, 0), -5000.0);
        assert_eq!(move_speed_steps_s(0.0, 100, 1000), 5500.0);
        assert_eq!(move_speed_steps_s(0.0, 100_000, 0), FW_MAX_SPEED_STEPS_S);
        assert_eq!(jog_speed_steps_s(-90_000), -FW_MAX_SPEED_STEPS_S);
    }

    #[test]
    fn substeps_cover_the_time() {
        let s: Vec<f64> = substeps(0.001).collect();
        assert_eq!(s.len(), 2);
        assert!((substeps(0.01).sum::<f64>() - 0.01).abs() < 1e-15);
        assert_eq!(substeps(f64::NAN).count(), 0);
        assert_eq!(substeps(-1.0).count(), 0);
    }

    #[test]
    fn feedforward_settles_on_its_stop_point_when_the_link_is_lost() {
        let mut s = Steppers::at([0; JOINT_COUNT]);
        s.set_command(StepperCommand::Move { target_steps: [1000; JOINT_COUNT], speed_steps_s: [5000; JOINT_COUNT] });
        s.advance(1.0);
        for p in s.position_steps() {
            assert!((p - 1050).abs() <= 1, "settled at {p}, stop point 1050");
        }
    }
}

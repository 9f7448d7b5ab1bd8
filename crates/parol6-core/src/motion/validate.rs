//! Argument and limit checks of every [`MotionCommand`] (what each backend runs before
//! queueing a command, and the planner again when it applies one).

use crate::limits::JointLimits;

use super::MotionCommand;
use super::MotionError;
use super::trajectory::SampledTrajectory;

fn check_fraction(what: &str, f: f64) -> Result<(), MotionError> {
    if f.is_finite() && f > 0.0 && f <= 1.0 {
        Ok(())
    } else {
        Err(MotionError::Invalid(format!("{what} speed fraction must lie in (0, 1], got {f}")))
    }
}

/// Checks a command's arguments and targets against `limits`.
pub(super) fn validate(limits: &JointLimits, cmd: &MotionCommand) -> Result<(), MotionError> {
    match cmd {
        MotionCommand::Follow { target_rad, speed_fraction } => {
            check_fraction("follow", *speed_fraction)?;
            limits.check(target_rad)?;
        }
        MotionCommand::MoveJoints { goal_rad, speed_fraction, .. } => {
            check_fraction("move", *speed_fraction)?;
            limits.check(goal_rad)?;
        }
        MotionCommand::Home { speed_fraction, .. } => check_fraction("home", *speed_fraction)?,
        MotionCommand::JogJoint { joint, fraction } => {
            if *joint >= limits.len() {
                return Err(MotionError::Invalid(format!(
                    "joint index {joint} out of range (the robot has {} joints)",
                    limits.len()
                )));
            }
            if !fraction.is_finite() {
                return Err(MotionError::Invalid("jog fraction must be a finite number".into()));
            }
        }
        MotionCommand::JogCartesian { fraction, .. } => {
            if !fraction.is_finite() {
                return Err(MotionError::Invalid("Cartesian jog fraction must be a finite number".into()));
            }
        }
        MotionCommand::CartesianStep { axis, distance, speed_fraction, .. } => {
            super::cartesian_step::check_step(*axis, *distance, *speed_fraction)?;
        }
        MotionCommand::JogRelease | MotionCommand::Stop | MotionCommand::Pause | MotionCommand::Resume => {}
        MotionCommand::Trajectory(traj) => validate_trajectory(limits, traj)?,
    }
    Ok(())
}

/// Every sample of a trajectory within the limits (with the right number of joints).
pub(super) fn validate_trajectory(limits: &JointLimits, traj: &SampledTrajectory) -> Result<(), MotionError> {
    if traj.samples().is_empty() {
        return Err(MotionError::Invalid("the trajectory has no samples".into()));
    }
    for (k, q) in traj.samples().iter().enumerate() {
        limits.check(q).map_err(|e| {
            MotionError::Invalid(format!("trajectory sample {k} (t = {:.3} s): {e}", k as f64 * traj.dt_s()))
        })?;
    }
    Ok(())
}

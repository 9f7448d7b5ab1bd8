//! A `FollowJointTrajectory` goal → the same [`plan_trajectory`] as a trajectory on
//! `/parol6/joint_trajectory` (its checks and the program pre-flight), after the checks that only
//! a goal has, or a refusal with control_msgs' error code.
//!
//! The goal's own checks: the multi-DOF trajectory and both component tolerance lists empty (we
//! have no multi-DOF joints; else [`INVALID_GOAL`], or [`INVALID_JOINTS`] for component
//! tolerances naming joints); every tolerance names a robot joint ([`INVALID_JOINTS`]) and is
//! finite and either -1 (none) or not negative ([`INVALID_GOAL`]); `goal_time_tolerance` valid;
//! a header stamp of zero starts on arrival, a stamp whose trajectory has ended before `now` is
//! [`OLD_HEADER_TIMESTAMP`], one more than [`MAX_START_DELAY_S`] ahead is refused (a delayed
//! start is not supported). The tolerances kept ([`Tolerances`]) are enforced while the goal
//! runs ([`super::tolerance`]). The trajectory's refusals are [`INVALID_JOINTS`] for its joint names
//! and [`INVALID_GOAL`] for the rest.

use super::action::{FollowJointTrajectoryGoal, INVALID_GOAL, INVALID_JOINTS, JointTolerance, OLD_HEADER_TIMESTAMP};
use super::tolerance::{JointTolerances, goal_time_tolerance_s};
use super::trajectory::{TrajectoryError, TrajectoryPlan, plan_trajectory};
use crate::model::RobotModel;
use crate::program::Step;

/// A header stamp may lie this far ahead of the arrival (clock offsets), s.
pub const MAX_START_DELAY_S: f64 = 0.5;

/// Why a goal is refused: control_msgs' error code and the reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{message} (error_code {error_code})")]
pub struct GoalRefusal {
    /// [`INVALID_GOAL`], [`INVALID_JOINTS`] or [`OLD_HEADER_TIMESTAMP`].
    pub error_code: i32,
    /// What is wrong.
    pub message: String,
}

fn refuse(error_code: i32, message: impl Into<String>) -> GoalRefusal {
    GoalRefusal { error_code, message: message.into() }
}

/// An accepted goal: its program and what its end is checked against.
#[derive(Debug, Clone)]
pub struct GoalPlan {
    /// The trajectory's plan (program, pre-flight report, points, duration).
    pub plan: TrajectoryPlan,
    /// Where the arm must end, rad, robot joint order.
    pub final_q: Vec<f64>,
    /// Its tolerances.
    pub tolerances: Tolerances,
}

/// A goal's tolerances per robot joint and its leeway after the trajectory's end
/// ([`super::tolerance`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Tolerances {
    /// While moving, from the commanded position and velocity.
    pub path: JointTolerances,
    /// At the end, from the last point, at rest.
    pub goal: JointTolerances,
    /// How long after the trajectory's end the goal tolerance may still be reached, s (the
    /// goal's `goal_time_tolerance`, 0 made
    /// [`DEFAULT_GOAL_TIME_TOLERANCE_S`](super::tolerance::DEFAULT_GOAL_TIME_TOLERANCE_S)).
    pub goal_time_s: f64,
}

/// Checks `goal` for `model` with the arm at `current_q` (rad) at `now_ns` (ns since the Unix
/// epoch), and plans its trajectory.
pub fn check_goal(
    model: &RobotModel,
    goal: &FollowJointTrajectoryGoal,
    current_q: &[f64],
    now_ns: u64,
) -> Result<GoalPlan, GoalRefusal> {
    let tolerances = goal_checks(model, goal, now_ns)?;
    let plan = plan_trajectory(model, &goal.trajectory, current_q).map_err(|e| {
        let code = if matches!(e, TrajectoryError::JointNames { .. }) { INVALID_JOINTS } else { INVALID_GOAL };
        refuse(code, format!("trajectory: {e}"))
    })?;
    let final_q = match plan.program.steps.last().map(|s| &s.step) {
        Some(Step::MoveJoints { joints_deg, .. }) => joints_deg.iter().map(|d| d.to_radians()).collect(),
        _ => current_q.to_vec(),
    };
    Ok(GoalPlan { plan, final_q, tolerances })
}

/// The checks only a goal has (everything but its trajectory's); its tolerances.
pub fn goal_checks(
    model: &RobotModel,
    goal: &FollowJointTrajectoryGoal,
    now_ns: u64,
) -> Result<Tolerances, GoalRefusal> {
    let multi = &goal.multi_dof_trajectory;
    if !multi.joint_names.is_empty() || !multi.points.is_empty() {
        return Err(refuse(
            INVALID_GOAL,
            format!(
                "multi_dof_trajectory has {} joints and {} points; this arm has no multi-DOF joints",
                multi.joint_names.len(),
                multi.points.len()
            ),
        ));
    }
    for (field, list) in [
        ("component_path_tolerance", &goal.component_path_tolerance),
        ("component_goal_tolerance", &goal.component_goal_tolerance),
    ] {
        if let Some(t) = list.first() {
            return Err(refuse(
                INVALID_JOINTS,
                format!("{field}: {:?} is not a multi-DOF joint of this arm", t.joint_name),
            ));
        }
    }
    let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
    let path = tolerances("path_tolerance", &goal.path_tolerance, &names)?;
    let goal_list = tolerances("goal_tolerance", &goal.goal_tolerance, &names)?;
    let gtt = &goal.goal_time_tolerance;
    if gtt.as_secs_f64().is_none_or(|s| s < 0.0) {
        return Err(refuse(
            INVALID_GOAL,
            format!("goal_time_tolerance {}.{:09} s is not a valid duration", gtt.sec, gtt.nanosec),
        ));
    }
    check_stamp(goal, now_ns)?;
    Ok(Tolerances { path, goal: goal_list, goal_time_s: goal_time_tolerance_s(gtt) })
}

/// Each robot joint's position and velocity tolerances from `list` (positive: checked), after
/// checking them.
fn tolerances(field: &str, list: &[JointTolerance], names: &[&str]) -> Result<JointTolerances, GoalRefusal> {
    let mut out = JointTolerances::none(names.len());
    for (i, t) in list.iter().enumerate() {
        let Some(j) = names.iter().position(|n| *n == t.name) else {
            return Err(refuse(
                INVALID_JOINTS,
                format!("{field}[{i}].name {:?} is not one of the joints {names:?}", t.name),
            ));
        };
        for (what, v) in [("position", t.position), ("velocity", t.velocity), ("acceleration", t.acceleration)] {
            if !v.is_finite() || (v < 0.0 && v != -1.0) {
                return Err(refuse(
                    INVALID_GOAL,
                    format!("{field}[{i}].{what} is {v}: a tolerance is -1 (none), 0 (default) or positive"),
                ));
            }
        }
        out.position_rad[j] = (t.position > 0.0).then_some(t.position);
        out.velocity_rad_s[j] = (t.velocity > 0.0).then_some(t.velocity);
    }
    Ok(out)
}

/// The trajectory's header stamp against the arrival time.
fn check_stamp(goal: &FollowJointTrajectoryGoal, now_ns: u64) -> Result<(), GoalRefusal> {
    let stamp = goal.trajectory.header.stamp;
    if stamp.sec == 0 && stamp.nanosec == 0 {
        return Ok(());
    }
    if stamp.sec < 0 || stamp.nanosec >= 1_000_000_000 {
        return Err(refuse(
            INVALID_GOAL,
            format!("trajectory.header.stamp {}.{:09} is not a time", stamp.sec, stamp.nanosec),
        ));
    }
    let start_s = f64::from(stamp.sec) + f64::from(stamp.nanosec) * 1e-9;
    let now_s = now_ns as f64 * 1e-9;
    let last_s = goal
        .trajectory
        .points
        .last()
        .and_then(|p| p.time_from_start.as_secs_f64())
        .filter(|s| s.is_finite())
        .unwrap_or(0.0);
    if start_s + last_s < now_s {
        return Err(refuse(
            OLD_HEADER_TIMESTAMP,
            format!(
                "the trajectory starting at {start_s:.3} s ended {:.3} s before it arrived",
                now_s - start_s - last_s
            ),
        ));
    }
    if start_s > now_s + MAX_START_DELAY_S {
        return Err(refuse(
            INVALID_GOAL,
            format!(
                "the trajectory starts {:.3} s after it arrived; a delayed start (more than {MAX_START_DELAY_S} s) is not supported",
                start_s - now_s
            ),
        ));
    }
    Ok(())
}

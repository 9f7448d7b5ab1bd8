//! An incoming `trajectory_msgs/msg/JointTrajectory` → a [`Program`] that runs through the same
//! pre-flight ([`check_program`]) as every program, or a refusal that says why.
//!
//! The checks, before the pre-flight: the joint names are exactly the robot's URDF joints (in
//! any order: the values are reordered), at least one point and at most
//! [`MAX_POINTS`](super::cdr::MAX_POINTS); every position, velocity, acceleration and effort
//! finite, one per joint (the last three may be empty); every position within the joint
//! limits; `time_from_start` valid (nanoseconds below 10⁹, not negative) and strictly
//! increasing, the whole at most [`MAX_TRAJECTORY_S`]; a point at time 0 lies within
//! [`START_TOLERANCE_RAD`] of where the arm is (MoveIt's first point is the start state); the
//! speed between points (the joint's change over the time between them) and every given
//! velocity within the joint's speed cap.
//!
//! Each point after the start becomes a `move_joints` step with `duration_s` = its time less the
//! previous one's: the arm moves to each point in a synchronised, jerk-limited joint move and
//! is there at its time (a segment the acceleration caps cannot make in time is stretched, and
//! the pre-flight says so in a warning). The path between points is the straight line in joint
//! space, as MoveIt plans it between its densely spaced points.

use super::msgs::{JointTrajectory, JointTrajectoryPoint};
use crate::model::RobotModel;
use crate::motion::MotionCaps;
use crate::program::check::{CheckOptions, CheckReport, check_program};
use crate::program::{Program, SourcedStep, Step};

/// A point at time 0 must lie this close to the arm's position (per joint), rad (MoveIt's
/// default start-state tolerance).
pub const START_TOLERANCE_RAD: f64 = 0.01;
/// The longest trajectory accepted, s.
pub const MAX_TRAJECTORY_S: f64 = 3600.0;
/// Speeds between points may exceed the caps by this factor of rounding, relative.
const SPEED_SLACK: f64 = 1e-6;

/// Why a trajectory is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrajectoryError {
    /// The joint names are not the robot's joints.
    #[error("joint_names {got:?} must be exactly the robot's joints {expected:?} (in any order)")]
    JointNames {
        /// What came.
        got: Vec<String>,
        /// The robot's URDF joint names.
        expected: Vec<String>,
    },
    /// No points.
    #[error("the trajectory has no points")]
    Empty,
    /// A point is wrong: which one, which field, what.
    #[error("points[{index}].{field}: {reason}")]
    Point {
        /// 0-based point.
        index: usize,
        /// Field (`positions`, `time_from_start`, …).
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The pre-flight refused the program.
    #[error("pre-flight: {0}")]
    Preflight(String),
}

/// A trajectory accepted for running.
#[derive(Debug, Clone)]
pub struct TrajectoryPlan {
    /// The program to run (one `move_joints` step per point after the start).
    pub program: Program,
    /// Its pre-flight (no errors; warnings possible).
    pub report: CheckReport,
    /// Number of points received.
    pub points: usize,
    /// The trajectory's own duration (its last `time_from_start`), s.
    pub duration_s: f64,
}

/// Checks `traj` for `model` with the arm at `current_q` (rad, the backend's commanded
/// position), converts it and runs the pre-flight.
pub fn plan_trajectory(
    model: &RobotModel,
    traj: &JointTrajectory,
    current_q: &[f64],
) -> Result<TrajectoryPlan, TrajectoryError> {
    let (program, duration_s) = to_program(model, traj, current_q)?;
    let report = check_program(model, &program, current_q, CheckOptions::default()).report;
    if let Some(first) = report.first_error() {
        return Err(TrajectoryError::Preflight(first));
    }
    Ok(TrajectoryPlan { program, report, points: traj.points.len(), duration_s })
}

/// The checks before the pre-flight and the conversion: the program and the trajectory's
/// duration, s.
pub fn to_program(
    model: &RobotModel,
    traj: &JointTrajectory,
    current_q: &[f64],
) -> Result<(Program, f64), TrajectoryError> {
    let order = joint_order(model, &traj.joint_names)?;
    if traj.points.is_empty() {
        return Err(TrajectoryError::Empty);
    }
    if traj.points.len() > super::cdr::MAX_POINTS {
        return Err(TrajectoryError::Point {
            index: super::cdr::MAX_POINTS,
            field: "positions",
            reason: format!("more than {} points", super::cdr::MAX_POINTS),
        });
    }
    let caps = MotionCaps::of(model);
    let mut steps = Vec::with_capacity(traj.points.len());
    let mut prev_q = current_q.to_vec();
    let mut prev_t = 0.0;
    for (index, point) in traj.points.iter().enumerate() {
        let err = |field, reason: String| TrajectoryError::Point { index, field, reason };
        let q = reordered(point, &order, index)?;
        if let Err(e) = model.limits.check(&q) {
            return Err(err("positions", e.to_string()));
        }
        // within the limits' rounding tolerance: onto the limit, so degrees and back stay inside
        let q: Vec<f64> = q.iter().zip(model.limits.iter()).map(|(&v, l)| l.clamp(v)).collect();
        let t = point.time_from_start.as_secs_f64().ok_or_else(|| {
            err("time_from_start", format!("nanosec {} is not below 10⁹", point.time_from_start.nanosec))
        })?;
        if t < 0.0 {
            return Err(err("time_from_start", format!("{t} s is negative")));
        }
        if t > MAX_TRAJECTORY_S {
            return Err(err("time_from_start", format!("{t} s is longer than {MAX_TRAJECTORY_S} s")));
        }
        if index > 0 && t <= prev_t {
            return Err(err("time_from_start", format!("{t} s is not after the previous point's {prev_t} s")));
        }
        if t == 0.0 {
            if let Some(j) = (0..q.len()).find(|&j| (q[j] - current_q[j]).abs() > START_TOLERANCE_RAD) {
                return Err(err(
                    "positions",
                    format!(
                        "the point at time 0 must be where the arm is: {} is {:.4} rad, the arm is at {:.4} rad \
                         (tolerance {START_TOLERANCE_RAD} rad)",
                        model.joints[j].name, q[j], current_q[j]
                    ),
                ));
            }
            prev_q = q;
            continue;
        }
        for (j, cap) in caps.speed_rad_s.iter().enumerate() {
            let v = (q[j] - prev_q[j]).abs() / (t - prev_t);
            if v > cap * (1.0 + SPEED_SLACK) {
                return Err(err(
                    "positions",
                    format!(
                        "{} moves {:.4} rad in {:.4} s ({v:.3} rad/s) from the previous point; its speed cap is \
                         {cap:.3} rad/s",
                        model.joints[j].name,
                        (q[j] - prev_q[j]).abs(),
                        t - prev_t
                    ),
                ));
            }
            if let Some(&v) = point.velocities.get(order[j])
                && v.abs() > cap * (1.0 + SPEED_SLACK)
            {
                return Err(err(
                    "velocities",
                    format!("{} velocity {v:.3} rad/s is above its speed cap {cap:.3} rad/s", model.joints[j].name),
                ));
            }
        }
        steps.push(SourcedStep {
            step: Step::MoveJoints {
                joints_deg: q.iter().map(|r| r.to_degrees()).collect(),
                speed_fraction: None,
                duration_s: Some(t - prev_t),
            },
            line: 0,
        });
        prev_q = q;
        prev_t = t;
    }
    let program =
        Program { name: format!("ROS 2 JointTrajectory ({} points)", traj.points.len()), steps, ..Program::default() };
    Ok((program, prev_t))
}

/// For each of the robot's joints, its index in `names`.
fn joint_order(model: &RobotModel, names: &[String]) -> Result<Vec<usize>, TrajectoryError> {
    let expected: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
    let refuse = || TrajectoryError::JointNames { got: names.to_vec(), expected: expected.clone() };
    if names.len() != expected.len() {
        return Err(refuse());
    }
    let mut order = Vec::with_capacity(expected.len());
    for want in &expected {
        let mut found = names.iter().enumerate().filter(|(_, n)| *n == want).map(|(i, _)| i);
        match (found.next(), found.next()) {
            (Some(i), None) => order.push(i),
            _ => return Err(refuse()),
        }
    }
    Ok(order)
}

/// The point's positions in the robot's joint order, after checking every array's length and
/// that every value is finite.
fn reordered(point: &JointTrajectoryPoint, order: &[usize], index: usize) -> Result<Vec<f64>, TrajectoryError> {
    let n = order.len();
    let arrays: [(&'static str, &[f64], bool); 4] = [
        ("positions", &point.positions, false),
        ("velocities", &point.velocities, true),
        ("accelerations", &point.accelerations, true),
        ("effort", &point.effort, true),
    ];
    for (field, values, may_be_empty) in arrays {
        if values.len() != n && !(may_be_empty && values.is_empty()) {
            let what = if may_be_empty { format!("0 or {n}") } else { n.to_string() };
            return Err(TrajectoryError::Point {
                index,
                field,
                reason: format!("{} values; {what} expected (one per joint)", values.len()),
            });
        }
        if let Some((k, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(TrajectoryError::Point {
                index,
                field,
                reason: format!("value {k} is {v}, not a finite number"),
            });
        }
    }
    Ok(order.iter().map(|&i| point.positions[i]).collect())
}

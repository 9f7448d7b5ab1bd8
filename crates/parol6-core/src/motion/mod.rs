//! The motion layer: one command type and one planner for every backend.
//!
//! A [`MotionCommand`] means the same thing whether it drives the simulation or the robot:
//! - [`MotionCommand::Follow`]: slew toward a target at each joint's speed cap × fraction (a
//!   slider being dragged);
//! - [`MotionCommand::MoveJoints`]: a synchronised, profiled point-to-point move (a typed value,
//!   a demo step);
//! - [`MotionCommand::Home`]: the same profiled move to the home pose (PAROL6 standby);
//! - [`MotionCommand::JogJoint`] / [`MotionCommand::JogRelease`]: hold-to-run jog with a
//!   dead-man ([`DEADMAN_S`]);
//! - [`MotionCommand::JogCartesian`]: hold-to-run jog of the TCP along / about an axis of the
//!   world or tool frame, planned at jog start up to where it must stop (limit, workspace edge,
//!   singularity, collision in the simulation) so it stops before, never after
//!   ([`cartesian_jog`]); [`MotionCommand::CartesianStep`] moves exactly a typed increment as
//!   a planned MoveL ([`cartesian_step`]);
//! - [`MotionCommand::Stop`]: hold the commanded position of this instant;
//! - [`MotionCommand::Pause`] / [`MotionCommand::Resume`]: slow a planned trajectory to a stop
//!   on its path and pick it up again (program pause).
//!
//! [`MotionPlanner`] turns commands into the commanded joint trajectory. It is a pure function
//! of the commands and the times they apply at: the simulation samples it every 1 ms step, the
//! serial session every 10 ms frame, and both get the same numbers at the same instants.
//! Commands may be scheduled for an exact time on the backend's motion clock
//! ([`RobotBackend::submit`]), so a scripted sequence gives identical commanded trajectories on
//! both backends.
//!
//! Joint limits are enforced here, once, for every command (policy *reject*: the error names
//! the joint and the limit). From at or beyond a limit, motion back toward the inside is always
//! allowed. The serial session keeps its last-line check in motor steps.
//!
//! [`RobotBackend`] is the one trait the app, the program runner and the tests talk to;
//! the simulation handle and the serial session implement it and publish a [`RobotState`]
//! computed on their own threads.

use serde::{Deserialize, Serialize};

use crate::limits::LimitViolation;
use crate::model::RobotModel;
use crate::profile::{JointMove, ProfileError, ProfileKind};

mod backend;
pub mod cartesian;
pub mod cartesian_jog;
pub mod cartesian_step;
mod io;
pub mod path;
mod planner;
pub mod preflight;
pub mod stepper;
pub mod tracking;
pub mod trajectory;
mod validate;
mod warp;

pub use backend::{
    BackendError, JointDrive, MotionSample, RobotBackend, RobotState, ScheduleState, StateSource, stop_best_effort,
};
pub use cartesian_jog::{CartesianAxis, JogFrame, JogKinematics, JogStop};
pub use io::{DIGITAL_PORTS, GRIPPER_CURRENT_MA, GripperStatus, IoCommand, IoState};
pub use planner::{MotionPlanner, PlannerMode, TRAJECTORY_START_TOLERANCE_RAD, jog_refusal};

/// A jog stops unless refreshed within this time of its motion clock, s.
pub const DEADMAN_S: f64 = 0.2;

/// A command to a robot backend (simulation or real robot). Joint vectors are in chain order,
/// rad.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum MotionCommand {
    /// Slew toward `target_rad`, each joint at `speed_fraction` × its speed cap, without an
    /// acceleration phase (what a dragged slider does).
    Follow {
        /// Target joint values, rad.
        target_rad: Vec<f64>,
        /// Fraction of each joint's speed cap (0 < f ≤ 1).
        speed_fraction: f64,
    },
    /// A synchronised, speed- and acceleration-limited move to `goal_rad`.
    MoveJoints {
        /// Goal joint values, rad.
        goal_rad: Vec<f64>,
        /// Fraction of the speed / acceleration caps (0 < f ≤ 1).
        speed_fraction: f64,
        /// Profile shape.
        profile: ProfileKind,
    },
    /// The same profiled move to the home pose (PAROL6 standby). Not the controller's homing
    /// routine, which is a link operation of the serial session.
    Home {
        /// Fraction of the speed / acceleration caps (0 < f ≤ 1).
        speed_fraction: f64,
        /// Profile shape.
        profile: ProfileKind,
    },
    /// Jog one joint (0-based) at `fraction` (−1…1) of its speed cap while held: repeat the
    /// command at least every [`DEADMAN_S`] or the joint stops. Stops at the limit.
    JogJoint {
        /// 0-based joint index.
        joint: usize,
        /// Signed fraction of the joint's speed cap, −1…1.
        fraction: f64,
    },
    /// Jog the TCP along (X, Y, Z) or about (Rx, Ry, Rz) an axis of `frame` while held:
    /// `fraction` (−1…1, sign = direction) of the Cartesian jog speed range (1–160 mm/s,
    /// 1–80 °/s). Repeat at least every [`DEADMAN_S`] or it stops; it also stops, decelerated,
    /// before the first joint limit, workspace edge, singularity or (simulation) collision.
    /// Needs a planner with kinematics ([`MotionPlanner::with_kinematics`]).
    JogCartesian {
        /// World or tool frame (the tool frame at jog start).
        frame: JogFrame,
        /// Axis.
        axis: CartesianAxis,
        /// Signed fraction of the jog speed range, −1…1.
        fraction: f64,
    },
    /// Move the TCP by exactly `distance` (m, or rad for Rx/Ry/Rz; signed) along / about an
    /// axis of `frame`, as a planned straight-line move (the jog's step mode).
    CartesianStep {
        /// World or tool frame.
        frame: JogFrame,
        /// Axis.
        axis: CartesianAxis,
        /// Signed increment, m (translations) or rad (rotations).
        distance: f64,
        /// Fraction of the Cartesian jog speed caps (0 < f ≤ 1).
        speed_fraction: f64,
    },
    /// Release a jog: hold where the jog is now.
    JogRelease,
    /// Stop: hold the commanded position of this instant.
    Stop,
    /// Pause a planned trajectory on its path: slow it to a stop (a ramp that uses half of
    /// the acceleration caps) without leaving the path. Any other motion holds at once.
    /// Scheduled commands are dropped (the program runner schedules the rest again).
    Pause,
    /// Resume a paused trajectory from where it stopped (the same ramp up).
    Resume,
    /// Follow a planned joint trajectory (a Cartesian move or a program segment planned off
    /// the control threads, see [`cartesian::plan`]). It must start where the commanded
    /// position is when it applies; every sample is checked against the limits and speed caps.
    #[serde(skip)]
    Trajectory(std::sync::Arc<trajectory::SampledTrajectory>),
}

impl MotionCommand {
    /// Follow `target_rad` at each joint's full speed cap (a dragged slider).
    pub fn follow(target_rad: Vec<f64>) -> Self {
        MotionCommand::Follow { target_rad, speed_fraction: 1.0 }
    }

    /// The profiled move home at half speed, trapezoidal (the HOME button's defaults).
    pub fn home() -> Self {
        MotionCommand::Home { speed_fraction: 0.5, profile: ProfileKind::Trapezoidal }
    }

    /// Short name for logs and refusals.
    pub fn name(&self) -> &'static str {
        match self {
            MotionCommand::Follow { .. } => "follow",
            MotionCommand::MoveJoints { .. } => "move",
            MotionCommand::Home { .. } => "home",
            MotionCommand::JogJoint { .. } => "jog",
            MotionCommand::JogCartesian { .. } => "Cartesian jog",
            MotionCommand::CartesianStep { .. } => "Cartesian step",
            MotionCommand::JogRelease => "jog release",
            MotionCommand::Stop => "stop",
            MotionCommand::Pause => "pause",
            MotionCommand::Resume => "resume",
            MotionCommand::Trajectory(_) => "trajectory",
        }
    }

    /// Checks the arguments and targets against `limits` (what every backend does before
    /// queueing a command).
    pub fn validate(&self, limits: &crate::limits::JointLimits) -> Result<(), MotionError> {
        validate::validate(limits, self)
    }

    /// True for commands that start motion (everything but stop and jog release).
    pub fn starts_motion(&self) -> bool {
        !matches!(self, MotionCommand::Stop | MotionCommand::JogRelease | MotionCommand::Pause)
    }
}

/// The commanded state of every joint at one instant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Setpoint {
    /// Positions, rad.
    pub q: Vec<f64>,
    /// Velocities, rad/s.
    pub qd: Vec<f64>,
    /// Accelerations, rad/s².
    pub qdd: Vec<f64>,
}

impl Setpoint {
    /// At rest at `q`.
    pub fn at_rest(q: &[f64]) -> Self {
        Self { q: q.to_vec(), qd: vec![0.0; q.len()], qdd: vec![0.0; q.len()] }
    }

    /// Sets this setpoint to rest at `q`, reusing its storage.
    pub fn set_rest(&mut self, q: &[f64]) {
        self.resize(q.len());
        self.q.copy_from_slice(q);
        self.qd.fill(0.0);
        self.qdd.fill(0.0);
    }

    /// Makes every vector `n` long (no allocation when it already is).
    pub fn resize(&mut self, n: usize) {
        self.q.resize(n, 0.0);
        self.qd.resize(n, 0.0);
        self.qdd.resize(n, 0.0);
    }
}

/// Per-joint speed (rad/s) and acceleration (rad/s²) caps of profiled motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MotionCaps {
    /// Speed caps, rad/s.
    pub speed_rad_s: Vec<f64>,
    /// Acceleration caps, rad/s².
    pub accel_rad_s2: Vec<f64>,
    /// Jerk caps of jerk-limited profiles, rad/s³.
    pub jerk_rad_s3: Vec<f64>,
}

impl MotionCaps {
    /// The caps of a model: the PAROL6 API caps (ROBOT.md §5), or for other robots the URDF
    /// velocity (2 rad/s when absent), 3 × that per second, and a jerk of 10 × the acceleration.
    pub fn of(model: &RobotModel) -> Self {
        if model.is_parol6 && model.dof() == crate::parol6::JOINT_COUNT {
            return Self {
                speed_rad_s: crate::parol6::max_speed_rad_s().to_vec(),
                accel_rad_s2: crate::parol6::max_accel_rad_s2().to_vec(),
                jerk_rad_s3: crate::parol6::max_jerk_rad_s3().to_vec(),
            };
        }
        let v: Vec<f64> = model
            .limits
            .iter()
            .map(|l| if l.max_velocity.is_finite() && l.max_velocity > 0.0 { l.max_velocity } else { 2.0 })
            .collect();
        let a: Vec<f64> = v.iter().map(|v| 3.0 * v).collect();
        let j = a.iter().map(|a| 10.0 * a).collect();
        Self { speed_rad_s: v, accel_rad_s2: a, jerk_rad_s3: j }
    }

    /// A synchronised joint move from `start` to `goal` (rad) under these caps scaled by
    /// `speed_fraction`: the one place the caps meet the profile planner (jog, programs, bench).
    pub fn plan_joint_move(
        &self,
        start: &[f64],
        goal: &[f64],
        speed_fraction: f64,
        kind: ProfileKind,
    ) -> Result<JointMove, ProfileError> {
        JointMove::plan_with_jerk(
            start,
            goal,
            &self.speed_rad_s,
            &self.accel_rad_s2,
            &self.jerk_rad_s3,
            speed_fraction,
            kind,
        )
    }
}

/// Why a motion command was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    /// The target breaks a joint limit, or has the wrong length or a non-finite value.
    #[error(transparent)]
    Limit(#[from] LimitViolation),
    /// The move cannot be planned.
    #[error(transparent)]
    Profile(#[from] ProfileError),
    /// A bad argument (joint index, fraction, a time that is not finite).
    #[error("{0}")]
    Invalid(String),
}

/// The home pose of a model: the PAROL6 standby for the PAROL6, else each joint's mid-range (0
/// for unbounded joints).
pub fn home_position(model: &RobotModel) -> Vec<f64> {
    if model.is_parol6 && model.dof() == crate::parol6::JOINT_COUNT {
        return crate::parol6::standby_rad().to_vec();
    }
    model.limits.iter().map(|l| if l.is_bounded() { 0.5 * (l.min + l.max) } else { 0.0 }).collect()
}

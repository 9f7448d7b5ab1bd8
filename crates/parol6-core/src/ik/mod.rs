//! Inverse kinematics.
//!
//! * [`solve_parol6`]: closed form for the PAROL6 chain (ROBOT.md §6.1). The wrist axes J4–J6
//!   meet at the L4/L5 origin (the wrist centre), 37 mm behind the flange along its z axis, so
//!   J1–J3 place the wrist centre (shoulder front/back × elbow up/down) and J4–J6 are a ZYZ Euler
//!   decomposition (wrist no-flip/flip): up to 8 branches, each labelled.
//! * [`solve_numeric`]: Levenberg–Marquardt (damped least squares with adaptive damping) for
//!   any URDF chain, limits-aware (every step is clamped into the limits), seeded, with random
//!   restarts.
//!
//! Both return solutions sorted by joint-space distance to the seed, and typed [`IkError`]s.

//!
//! Jobs: `closed_form` (PAROL6), `numeric` (any chain); this file holds the shared types.

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use crate::model::RobotModel;

mod closed_form;
pub mod config;
mod numeric;

/// Chain recognition lives with the model (it runs while loading); re-exported here where
/// callers of the closed form look for it.
pub use crate::model::is_parol6_chain;
pub use closed_form::{REACH_SLACK_M, solve_parol6, solve_parol6_in};
pub use config::{ConfigRule, configuration_of, solve_nearest};
pub use numeric::solve_numeric;

/// Pose tolerance a solution must meet (m for position, rad for orientation).
pub const IK_TOLERANCE: f64 = 1e-9;

/// Shoulder branch: wrist centre in front of / behind the J1 axis (relative to the J2 offset).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ShoulderBranch {
    /// J2 offset points toward the wrist centre.
    Front,
    /// J1 turned by π: reaching over the shoulder.
    Back,
}

/// Elbow branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ElbowBranch {
    /// Elbow above the shoulder–wrist line.
    Up,
    /// Elbow below it.
    Down,
}

/// Wrist branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum WristBranch {
    /// J5 ≥ 0.
    NoFlip,
    /// J5 < 0 (J4 and J6 turned by π).
    Flip,
}

/// Which closed-form branch a solution belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Branch {
    /// Shoulder branch.
    pub shoulder: ShoulderBranch,
    /// Elbow branch.
    pub elbow: ElbowBranch,
    /// Wrist branch.
    pub wrist: WristBranch,
}

impl Branch {
    /// Short label, e.g. `front/up/no-flip`.
    pub fn label(&self) -> String {
        let s = match self.shoulder {
            ShoulderBranch::Front => "front",
            ShoulderBranch::Back => "back",
        };
        let e = match self.elbow {
            ElbowBranch::Up => "up",
            ElbowBranch::Down => "down",
        };
        let w = match self.wrist {
            WristBranch::NoFlip => "no-flip",
            WristBranch::Flip => "flip",
        };
        format!("{s}/{e}/{w}")
    }
}

/// One IK solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IkSolution {
    /// Joint values, chain order.
    pub joints_rad: Vec<f64>,
    /// Closed-form branch (None for numeric solutions).
    pub branch: Option<Branch>,
    /// Euclidean joint-space distance to the seed.
    pub distance_to_seed: f64,
    /// True when the solution is at or near a singularity.
    pub singular: bool,
}

/// Why IK found no solution.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IkError {
    /// The target lies outside the workspace.
    #[error("target is unreachable: {0}")]
    Unreachable(String),
    /// Solutions exist, but every one breaks a joint limit.
    #[error("no solution within the joint limits (the pose is reached by {} but a limit is broken: {detail})", crate::plural::count(*.branches, "branch"))]
    NoSolutionWithinLimits {
        /// Branches that reach the pose.
        branches: usize,
        /// The first limit broken.
        detail: String,
    },
    /// The solver stalled at a singular configuration.
    #[error("singular configuration: the solver stalled {residual_m:.2e} m / {residual_rad:.2e} rad from the target")]
    Singular {
        /// Remaining position error.
        residual_m: f64,
        /// Remaining orientation error.
        residual_rad: f64,
    },
    /// The numeric solver did not converge.
    #[error("no convergence after {}: best residual {residual_m:.2e} m / {residual_rad:.2e} rad", crate::plural::count(*.attempts, "attempt"))]
    NotConverged {
        /// Attempts made.
        attempts: usize,
        /// Best position error.
        residual_m: f64,
        /// Best orientation error.
        residual_rad: f64,
    },
    /// Bad input (seed length, non-finite target).
    #[error("invalid IK input: {0}")]
    InvalidInput(String),
    /// The pose is reachable within the limits, but not in the configuration asked for.
    #[error(
        "the pose is not reachable in configuration {wanted}; it is reachable in {}",
        reachable.join(", ")
    )]
    OtherConfiguration {
        /// The configuration asked for (`front/up/no-flip`, `any` for a free part).
        wanted: String,
        /// The configurations that reach it within the limits, nearest the seed first.
        reachable: Vec<String>,
    },
    /// Closed form asked for a chain that is not the PAROL6.
    #[error("the closed-form solver applies to the PAROL6 chain only")]
    NotParol6,
}

/// Options of the numeric solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NumericIkOptions {
    /// Iterations per attempt.
    pub max_iterations: usize,
    /// Attempts (the first from the seed, the rest from random configurations).
    pub max_attempts: usize,
    /// Convergence tolerance (m and rad).
    pub tolerance: f64,
    /// Seed of the restart generator (deterministic results).
    pub rng_seed: u64,
}

impl Default for NumericIkOptions {
    fn default() -> Self {
        Self { max_iterations: 80, max_attempts: 80, tolerance: IK_TOLERANCE, rng_seed: 0x5eed_7a21 }
    }
}

/// Position and orientation error between two poses (m, rad).
pub fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let dp = (a.translation.vector - b.translation.vector).norm();
    let dr = a.rotation.angle_to(&b.rotation);
    (dp, dr)
}

/// Solves with the closed form when the chain is the PAROL6, else numerically.
pub fn solve(model: &RobotModel, target: &Isometry3<f64>, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
    if model.is_parol6 {
        solve_parol6(model, target, seed)
    } else {
        solve_numeric(model, target, seed, &NumericIkOptions::default()).map(|s| vec![s])
    }
}

pub(super) fn check_input(model: &RobotModel, target: &Isometry3<f64>, seed: &[f64]) -> Result<(), IkError> {
    if seed.len() != model.dof() {
        return Err(IkError::InvalidInput(format!(
            "seed has {} values, the robot has {} joints",
            seed.len(),
            model.dof()
        )));
    }
    if !seed.iter().all(|v| v.is_finite()) {
        return Err(IkError::InvalidInput("seed contains a non-finite value".into()));
    }
    let t = target.translation.vector;
    let r = target.rotation;
    if !(t.iter().all(|v| v.is_finite()) && r.coords.iter().all(|v| v.is_finite())) {
        return Err(IkError::InvalidInput("target pose contains a non-finite value".into()));
    }
    Ok(())
}

#[cfg(test)]
mod tests;

//! Pre-flight validation: every planned move of a program is checked before anything moves.
//!
//! A program compiles to [`PlannedMove`]s (joint trajectories sampled every `dt`, typically
//! 10 ms, see [`super::trajectory::SampledTrajectory`]); [`Preflight::check`] walks them and
//! reports every problem with the move index, the source line, the joint / motor / link pair
//! / keep-out shape, the time along the move and the TCP position there
//! ([`PreflightReport`]). Consecutive samples with the same problem in one move make one issue
//! (its first occurrence).
//!
//! Checks and where they run:
//! - **every sample**: values finite and of the model's length (else one
//!   [`IssueKind::InvalidTrajectory`] for the move), joint limits ([`JointLimits::check`]'s
//!   rule), joint speed from sample differences against [`MotionCaps::speed_rad_s`], and for
//!   the PAROL6 the motor-6 rate of ROBOT.md §5 (`(|ω6|·10 + |ω4|·4) / (2π/6400)` steps/s
//!   ≤ 27 000: the API's differential-wrist rule); a move that does not start where the
//!   previous one ends (faster than the speed caps allow in one sample) is a
//!   [`IssueKind::Discontinuity`];
//! - **singularity** ([`singularity`]): every [`SINGULARITY_STEP_RAD`] of joint travel, at
//!   the ends of each move, and at every sample of a TCP-path move inside the warning band;
//! - **collision** (self-collision, floor, keep-out shapes; `clearance`): at the start of
//!   each move and then only when needed. Between checkpoints the trajectory is the straight
//!   joint-space line between samples (what the controller interpolates); the walk adds up
//!   each joint's travel since the last checkpoint and the bound on how far each collision
//!   piece can have moved (`Σ reach × travel`). The next checkpoint is placed exactly where
//!   some piece would exhaust its clearance budget (inside a segment if need be), so no
//!   contact can be passed between two checkpoints. Checkpoints are at least
//!   [`MIN_COLLISION_STEP_RAD`] of joint travel apart (a contact shallower than what that
//!   travel moves a piece, ≤ 0.5 mm on the PAROL6, may be missed); while in contact the next
//!   checkpoint is the next sample.
//!
//! The TCP path for the 3D view gets a point at each move's ends and whenever the TCP may have
//! moved [`PATH_SPACING_M`] (same reach bound), coloured by the worst problem active since the
//! previous point.

use std::sync::Arc;

use crate::limits::JointLimits;
use crate::model::RobotModel;
use crate::scene::{KeepOut, SceneError};

use super::MotionCaps;
use super::trajectory::SampledTrajectory;

pub mod bench_program;
mod clearance;
mod problem;
mod report;
pub mod singularity;
mod walk;

pub use clearance::EXACT_DISTANCE_BELOW_M;
pub use report::{CheckStatus, CheckedPoint, IssueKind, PreflightIssue, PreflightReport, Severity};
pub use singularity::{SINGULARITY_ERROR_RATIO, SINGULARITY_STEP_RAD, SINGULARITY_WARN_RATIO};

/// Smallest joint travel (largest joint) between two collision checkpoints, rad.
pub const MIN_COLLISION_STEP_RAD: f64 = 1e-3;

/// Largest TCP travel between two points of the checked path, m.
pub const PATH_SPACING_M: f64 = 0.01;

/// Relative slack on speed caps (sampling and rounding of planned trajectories).
pub const SPEED_TOLERANCE: f64 = 1e-6;

/// Motor 6 of the PAROL6, 0-based: it turns with J6 and, through the differential wrist, J4.
pub const PAROL6_COUPLED_MOTOR: usize = 5;

/// How a move was interpolated; decides how bad a singular pose on it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MoveKind {
    /// Joint-space interpolation (joint move, home): a singular pose only warns.
    Joint,
    /// Along a TCP path (MoveL, MoveC, spline): a pose below
    /// [`SINGULARITY_ERROR_RATIO`] is an error.
    Cartesian,
}

/// One planned move of a program.
#[derive(Debug, Clone)]
pub struct PlannedMove {
    /// 0-based move index.
    pub index: usize,
    /// 1-based line of the program source.
    pub line: usize,
    /// Short description for messages ("MoveL to P3").
    pub label: String,
    /// Joint or Cartesian interpolation.
    pub kind: MoveKind,
    /// The joint trajectory.
    pub trajectory: Arc<SampledTrajectory>,
}

/// Why a checker cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PreflightError {
    /// A keep-out shape is unusable.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The caps do not fit the model.
    #[error("{0}")]
    Caps(String),
}

/// The checker of one robot model, motion caps and scene; build once, check many programs.
pub struct Preflight {
    model: RobotModel,
    limits: JointLimits,
    speed_cap_rad_s: Vec<f64>,
    /// PAROL6: the motor-6 coupling of ROBOT.md §5 applies.
    motor6_coupling: bool,
    world: clearance::ClearanceWorld,
    /// Reach of the TCP from each joint axis, m per rad.
    tcp_reach_m: Vec<f64>,
    /// Reference manipulability ([`singularity::reference_manipulability`]).
    reference_manipulability: Option<f64>,
    link_names: Vec<String>,
    keep_out_names: Vec<String>,
}

impl std::fmt::Debug for Preflight {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Preflight")
            .field("model", &self.model.name)
            .field("keep_out", &self.keep_out_names)
            .field("reference_manipulability", &self.reference_manipulability)
            .finish()
    }
}

impl Preflight {
    /// The checker of `model` (its limits, tool and collision geometry) under `caps`, with
    /// the keep-out shapes `keep_out` (validated here; the error names the shape).
    pub fn new(model: &RobotModel, caps: &MotionCaps, keep_out: &[KeepOut]) -> Result<Self, PreflightError> {
        crate::scene::validate_keep_out(keep_out)?;
        let dof = model.dof();
        if caps.speed_rad_s.len() != dof {
            return Err(PreflightError::Caps(format!(
                "speed caps have {} joints, the robot {dof}",
                caps.speed_rad_s.len()
            )));
        }
        if let Some(j) = caps.speed_rad_s.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(PreflightError::Caps(format!(
                "speed cap of joint {} must be a positive finite number, got {}",
                j + 1,
                caps.speed_rad_s[j]
            )));
        }
        let tcp_extent_m = (model.tip_offset * model.tool).translation.vector.norm();
        Ok(Self {
            model: model.clone(),
            limits: model.limits.clone(),
            speed_cap_rad_s: caps.speed_rad_s.clone(),
            motor6_coupling: model.is_parol6 && dof == crate::parol6::JOINT_COUNT,
            world: clearance::ClearanceWorld::new(model, keep_out),
            tcp_reach_m: clearance::reach_per_joint(model, dof, tcp_extent_m),
            reference_manipulability: singularity::reference_manipulability(model),
            link_names: model.links.iter().map(|l| l.name.clone()).collect(),
            keep_out_names: keep_out.iter().map(|k| k.name.clone()).collect(),
        })
    }

    /// The model checked against.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// The reference manipulability singular poses are measured against (`None`: the arm is
    /// singular everywhere and no singularity checks run).
    pub fn reference_manipulability(&self) -> Option<f64> {
        self.reference_manipulability
    }

    /// Checks `moves` in order (each should start where the previous one ends).
    pub fn check(&self, moves: &[PlannedMove]) -> PreflightReport {
        self.check_stream(moves, &mut |_| true).unwrap_or_default()
    }

    /// [`Self::check`] of moves as they come (a program's check walks each move while the next
    /// ones are still being compiled), telling `observe` each move checked; it returns false to
    /// stop (`None`: stopped).
    pub fn check_stream<M: std::borrow::Borrow<PlannedMove>>(
        &self,
        moves: impl IntoIterator<Item = M>,
        observe: &mut dyn FnMut(&PlannedMove) -> bool,
    ) -> Option<PreflightReport> {
        let mut report = PreflightReport::default();
        let mut walk = walk::Walk::new(self);
        // the last move, when its samples were usable
        let mut previous: Option<M> = None;
        for m in moves {
            let mv = m.borrow();
            report.moves += 1;
            report.duration_s += mv.trajectory.duration_s().max(0.0);
            let previous_end = previous.as_ref().map(|p| p.borrow().trajectory.goal());
            let valid = walk.check_move(mv, previous_end, &mut report);
            if !observe(mv) {
                return None;
            }
            previous = valid.then_some(m);
        }
        Some(report)
    }
}

#[cfg(test)]
mod tests;

//! Singularity measure of pre-flight: Yoshikawa's manipulability `w = sqrt(det(J·Jᵀ))` of the
//! TCP Jacobian ([`RobotModel::jacobian_from_frames`]; `sqrt(det(Jᵀ·J))` for arms with fewer
//! than six joints), divided by the model's *reference* manipulability: the median of `w`
//! over [`REFERENCE_POSES`] joint configurations spread evenly through the joint ranges.
//! The ratio is unit-free, so the same thresholds serve any URDF.
//!
//! Thresholds (PAROL6 figures, checked by `thresholds_match_the_parol6_wrist`): the
//! reference is about 0.0017 m³; at the bench program's working poses `w` is about
//! 4.7 × reference × |sin J5| near the wrist singularity (J5 = 0, J4 and J6 aligned). So:
//! - [`SINGULARITY_WARN_RATIO`] = 0.4: a warning within about ±5° of the wrist singularity
//!   (or as close to the elbow / shoulder ones), where a Cartesian move needs J4 / J6 more
//!   than 10× faster than the TCP turns;
//! - [`SINGULARITY_ERROR_RATIO`] = 0.04: within about ±0.5°. An error only on moves along a
//!   TCP path (MoveL / MoveC / spline): there the IK has to spin J4 / J6 by up to 180° as the
//!   path passes the singular pose. A joint move through a singular pose is harmless (its
//!   joint speeds are profiled) and only warns; the PAROL6 standby (J5 = 0) is such a pose.
//!
//! The measure is sampled every [`SINGULARITY_STEP_RAD`] of joint travel (largest joint) and
//! at each move's ends: J5 cannot cross the ±5° band (0.17 rad) unseen. On a TCP path, once
//! inside the warning band, every sample of the trajectory is measured, so the ±0.5° error
//! band is seen unless J5 crosses it within one sample (faster than 100°/s at 10 ms). On a
//! joint move the error band does not apply.

use nalgebra::{Isometry3, Matrix6, Vector3};

use crate::model::RobotModel;

/// Warning below this fraction of the reference manipulability.
pub const SINGULARITY_WARN_RATIO: f64 = 0.4;

/// Error (moves along a TCP path) below this fraction of the reference manipulability.
pub const SINGULARITY_ERROR_RATIO: f64 = 0.04;

/// Largest joint travel between two singularity samples, rad (about 2.9°).
pub const SINGULARITY_STEP_RAD: f64 = 0.05;

/// Number of configurations the reference manipulability is the median of.
pub const REFERENCE_POSES: usize = 1024;

/// Yoshikawa's manipulability at chain frames `frames` ([`RobotModel::chain_frames`]).
pub fn manipulability_from_frames(model: &RobotModel, frames: &[Isometry3<f64>], tcp: &Vector3<f64>) -> f64 {
    let jac = model.jacobian_from_frames(frames, tcp);
    match jac.ncols() {
        // square: sqrt(det(J·Jᵀ)) = |det J|, on the stack
        6 => Matrix6::from_column_slice(jac.as_slice()).determinant().abs(),
        n if n > 6 => {
            let jjt: Matrix6<f64> = &jac * jac.transpose();
            jjt.determinant().max(0.0).sqrt()
        }
        _ => (jac.transpose() * &jac).determinant().max(0.0).sqrt(),
    }
}

/// Yoshikawa's manipulability at joint values `q`.
pub fn manipulability(model: &RobotModel, q: &[f64]) -> f64 {
    let frames = model.chain_frames(q);
    let tcp = tcp_from_frames(model, &frames);
    manipulability_from_frames(model, &frames, &tcp)
}

/// TCP position from chain frames, m.
pub(super) fn tcp_from_frames(model: &RobotModel, frames: &[Isometry3<f64>]) -> Vector3<f64> {
    let last = frames.last().copied().unwrap_or_else(Isometry3::identity);
    (last * model.tip_offset * model.tool).translation.vector
}

/// Van der Corput radical inverse of `i` in base `b` (low-discrepancy spread in [0, 1)).
fn radical_inverse(mut i: usize, b: usize) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f /= b as f64;
        r += f * (i % b) as f64;
        i /= b;
    }
    r
}

const PRIMES: [usize; 12] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37];

/// The model's reference manipulability: the median over [`REFERENCE_POSES`] Halton-spread
/// configurations inside the joint limits (±π for unbounded joints). `None` when the arm is
/// singular everywhere (fewer than one independent direction), then no singularity checks.
pub fn reference_manipulability(model: &RobotModel) -> Option<f64> {
    let dof = model.dof();
    let mut values: Vec<f64> = (1..=REFERENCE_POSES)
        .map(|i| {
            let q: Vec<f64> = (0..dof)
                .map(|j| {
                    let u = radical_inverse(i, PRIMES[j % PRIMES.len()] + 2 * (j / PRIMES.len()) * 41);
                    match model.limits.get(j) {
                        Some(l) if l.is_bounded() => l.min + u * l.range(),
                        _ => -std::f64::consts::PI + u * std::f64::consts::TAU,
                    }
                })
                .collect();
            manipulability(model, &q)
        })
        .filter(|w| w.is_finite())
        .collect();
    values.sort_by(f64::total_cmp);
    let median = *values.get(values.len() / 2)?;
    (median > 0.0).then_some(median)
}

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

use std::f64::consts::{PI, TAU};

use nalgebra::{Isometry3, Matrix3, Vector6};
use serde::{Deserialize, Serialize};

use crate::model::{ChainJoint, JointKind, RobotModel};

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
    #[error("no solution within the joint limits ({branches} branch(es) reach the pose but break a limit: {detail})")]
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
    #[error("no convergence after {attempts} attempt(s): best residual {residual_m:.2e} m / {residual_rad:.2e} rad")]
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

fn check_input(model: &RobotModel, target: &Isometry3<f64>, seed: &[f64]) -> Result<(), IkError> {
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

const PAROL6_ORIGINS: [([f64; 3], [f64; 3]); 5] = [
    ([0.0234207210610375, 0.0, 0.0], [-PI / 2.0, 0.0, 0.0]),
    ([0.18, 0.0, 0.0], [PI, 0.0, 0.0]),
    ([-0.0435, 0.17635, 0.0], [PI / 2.0, 0.0, 0.0]),
    ([0.0, 0.0, 0.0], [-PI / 2.0, 0.0, 0.0]),
    ([0.0, 0.037, 0.0], [PI / 2.0, 0.0, 0.0]),
];

/// True when `joints` (+ `tip_offset`) form the PAROL6 chain of ROBOT.md §6.1 (any base
/// placement: J1's origin may be anything).
pub fn is_parol6_chain(joints: &[ChainJoint], tip_offset: &Isometry3<f64>) -> bool {
    if joints.len() != 6 || joints.iter().any(|j| j.kind == JointKind::Prismatic || !j.axis_is_z) {
        return false;
    }
    let tip_ok = tip_offset.translation.vector.norm() < 1e-9 && tip_offset.rotation.angle() < 1e-9;
    tip_ok
        && joints[1..].iter().zip(PAROL6_ORIGINS.iter()).all(|(j, (xyz, rpy))| {
            let want = crate::kinematics::iso_from_xyz_rpy(*xyz, *rpy);
            pose_error(&j.origin, &want).0 < 1e-6 && pose_error(&j.origin, &want).1 < 1e-6
        })
}

/// Picks `q + 2πk` inside `[min, max]` nearest to `seed`; None when no wrap fits.
fn wrap_into(q: f64, min: f64, max: f64, seed: f64) -> Option<f64> {
    let eps = 1e-9;
    let mut best: Option<f64> = None;
    for k in -3..=3 {
        let v = q + TAU * k as f64;
        if v >= min - eps && v <= max + eps {
            let v = v.clamp(min, max);
            if best.is_none_or(|b| (v - seed).abs() < (b - seed).abs()) {
                best = Some(v);
            }
        }
    }
    best
}

fn rot_z(q: f64) -> Matrix3<f64> {
    let (s, c) = q.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Closed-form IK of the PAROL6: every branch within the limits, best (nearest `seed`) first.
pub fn solve_parol6(model: &RobotModel, target: &Isometry3<f64>, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
    check_input(model, target, seed)?;
    if !model.is_parol6 {
        return Err(IkError::NotParol6);
    }
    let j = &model.joints;
    // flange pose in the J1 base frame (before the J1 rotation)
    let flange = target * model.tool.inverse();
    let f = j[0].origin.inverse() * flange;
    let d6 = j[5].origin.translation.y;
    let r_f = f.rotation.to_rotation_matrix().into_inner();
    let z6 = r_f.column(2).into_owned();
    let wc = f.translation.vector + z6 * d6;
    let a1 = j[1].origin.translation.x;
    let a2 = j[2].origin.translation.x;
    let (ox, oy) = (j[3].origin.translation.x, j[3].origin.translation.y);
    let l3 = ox.hypot(oy);
    let psi = oy.atan2(ox);
    let r1 = j[1].origin.rotation.to_rotation_matrix().into_inner();
    let r2 = j[2].origin.rotation.to_rotation_matrix().into_inner();
    let r3 = j[3].origin.rotation.to_rotation_matrix().into_inner();

    let rho = wc.x.hypot(wc.y);
    let shoulder_singular = rho < 1e-9;
    let mut raw: Vec<(Vec<f64>, Branch, bool)> = Vec::with_capacity(8);
    let mut any_reach = false;
    let mut reach_detail = String::new();
    for shoulder in [ShoulderBranch::Front, ShoulderBranch::Back] {
        if shoulder_singular && shoulder == ShoulderBranch::Back {
            continue;
        }
        let (q1, x) = match (shoulder, shoulder_singular) {
            (_, true) => (seed[0], 0.0),
            (ShoulderBranch::Front, false) => (wc.y.atan2(wc.x), rho),
            (ShoulderBranch::Back, false) => ((-wc.y).atan2(-wc.x), -rho),
        };
        let px = x - a1;
        let pz = wc.z;
        let d2 = px * px + pz * pz;
        let k = (d2 - a2 * a2 - l3 * l3) / (2.0 * a2 * l3);
        if k.abs() > 1.0 + 1e-12 {
            reach_detail = format!(
                "wrist centre is {:.1} mm from the shoulder axis; reachable range {:.1}…{:.1} mm",
                d2.sqrt() * 1e3,
                (a2 - l3).abs() * 1e3,
                (a2 + l3) * 1e3
            );
            continue;
        }
        any_reach = true;
        let k = k.clamp(-1.0, 1.0);
        let elbow_singular = (1.0 - k.abs()) < 1e-12;
        for elbow in [ElbowBranch::Up, ElbowBranch::Down] {
            if elbow_singular && elbow == ElbowBranch::Down {
                continue;
            }
            let sign = if elbow == ElbowBranch::Up { 1.0 } else { -1.0 };
            let q3 = sign * k.acos() - psi;
            let (s3, c3) = q3.sin_cos();
            let ux = a2 + ox * c3 - oy * s3;
            let uy = -(ox * s3 + oy * c3);
            let q2 = (-pz).atan2(px) - uy.atan2(ux);
            let r03 = rot_z(q1) * r1 * rot_z(q2) * r2 * rot_z(q3) * r3;
            let m = r03.transpose() * r_f;
            let sb = m[(0, 2)].hypot(m[(1, 2)]);
            let wrist_singular = sb < 1e-9;
            for wrist in [WristBranch::NoFlip, WristBranch::Flip] {
                let (q4, q5, q6) = if wrist_singular {
                    if wrist == WristBranch::Flip {
                        continue;
                    }
                    let b = if m[(2, 2)] > 0.0 { 0.0 } else { PI };
                    let sum = if b == 0.0 { m[(1, 0)].atan2(m[(0, 0)]) } else { (-m[(1, 0)]).atan2(-m[(0, 0)]) };
                    let q4 = seed[3];
                    let q6 = if b == 0.0 { sum - q4 } else { q4 - sum };
                    (q4, b, q6)
                } else if wrist == WristBranch::NoFlip {
                    (m[(1, 2)].atan2(m[(0, 2)]), sb.atan2(m[(2, 2)]), m[(2, 1)].atan2(-m[(2, 0)]))
                } else {
                    ((-m[(1, 2)]).atan2(-m[(0, 2)]), (-sb).atan2(m[(2, 2)]), (-m[(2, 1)]).atan2(m[(2, 0)]))
                };
                raw.push((
                    vec![q1, q2, q3, q4, q5, q6],
                    Branch { shoulder, elbow, wrist },
                    shoulder_singular || elbow_singular || wrist_singular,
                ));
            }
        }
    }
    if !any_reach {
        return Err(IkError::Unreachable(reach_detail));
    }
    let branches_reaching = raw.len();
    let mut out = Vec::with_capacity(raw.len());
    let mut first_violation = String::new();
    for (q, branch, singular) in raw {
        let mut wrapped = Vec::with_capacity(6);
        for (i, &v) in q.iter().enumerate() {
            let Some(l) = model.limits.get(i) else { break };
            match wrap_into(v, l.min, l.max, seed[i]) {
                Some(w) => wrapped.push(w),
                None => {
                    if first_violation.is_empty() {
                        first_violation =
                            format!("{} branch needs {} = {:.2}°", branch.label(), l.name, v.to_degrees());
                    }
                    break;
                }
            }
        }
        if wrapped.len() != 6 {
            continue;
        }
        let (ep, er) = pose_error(&model.tcp_isometry(&wrapped), target);
        if ep > 1e-7 || er > 1e-7 {
            continue;
        }
        let distance_to_seed = wrapped.iter().zip(seed).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
        out.push(IkSolution { joints_rad: wrapped, branch: Some(branch), distance_to_seed, singular });
    }
    if out.is_empty() {
        return Err(IkError::NoSolutionWithinLimits { branches: branches_reaching, detail: first_violation });
    }
    out.sort_by(|a, b| a.distance_to_seed.total_cmp(&b.distance_to_seed));
    Ok(out)
}

/// Small deterministic generator for restarts (xorshift64*).
#[derive(Debug, Clone)]
struct Restarts(u64);

impl Restarts {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn error_twist(current: &Isometry3<f64>, target: &Isometry3<f64>) -> Vector6<f64> {
    let dp = target.translation.vector - current.translation.vector;
    let dr = (target.rotation * current.rotation.inverse()).scaled_axis();
    Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z)
}

/// Numeric IK (Levenberg–Marquardt) for any chain. Returns one solution within the limits.
pub fn solve_numeric(
    model: &RobotModel,
    target: &Isometry3<f64>,
    seed: &[f64],
    opts: &NumericIkOptions,
) -> Result<IkSolution, IkError> {
    check_input(model, target, seed)?;
    let n = model.dof();
    // quick reach bound: sum of all joint offsets + tip + tool
    let reach: f64 = model.joints.iter().skip(1).map(|j| j.origin.translation.vector.norm()).sum::<f64>()
        + model.tip_offset.translation.vector.norm()
        + model.tool.translation.vector.norm()
        + model
            .joints
            .iter()
            .zip(model.limits.iter())
            .filter(|(j, _)| j.kind == JointKind::Prismatic)
            .map(|(_, l)| l.min.abs().max(l.max.abs()))
            .sum::<f64>();
    let base = model.joints[0].origin.translation.vector;
    let dist = (target.translation.vector - base).norm();
    if dist > reach + 1e-9 {
        return Err(IkError::Unreachable(format!(
            "target is {:.1} mm from the first joint; the chain reaches at most {:.1} mm",
            dist * 1e3,
            reach * 1e3
        )));
    }
    let lims: Vec<(f64, f64)> = model
        .limits
        .iter()
        .map(|l| {
            let lo = if l.min.is_finite() { l.min } else { -PI };
            let hi = if l.max.is_finite() { l.max } else { PI };
            (lo, hi)
        })
        .collect();
    let clamp = |q: &mut [f64]| {
        for (v, l) in q.iter_mut().zip(model.limits.iter()) {
            *v = v.clamp(l.min, l.max);
        }
    };
    let mut rng = Restarts(opts.rng_seed | 1);
    let mut best = (f64::INFINITY, f64::INFINITY, seed.to_vec());
    let mut q = seed.to_vec();
    clamp(&mut q);
    for attempt in 0..opts.max_attempts.max(1) {
        if attempt > 0 {
            for (v, (lo, hi)) in q.iter_mut().zip(&lims) {
                *v = lo + (hi - lo) * rng.next_f64();
            }
        }
        let mut lambda = 1e-3;
        let mut frames = model.chain_frames(&q);
        let mut tcp = frames[n] * model.tip_offset * model.tool;
        let mut e = error_twist(&tcp, target);
        let mut cost = e.norm_squared();
        for _ in 0..opts.max_iterations {
            let (ep, er) = (e.fixed_rows::<3>(0).norm(), e.fixed_rows::<3>(3).norm());
            if ep < opts.tolerance && er < opts.tolerance {
                let distance_to_seed = q.iter().zip(seed).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
                let singular = crate::kinematics::Manipulability::of(&model.jacobian(&q)).singular;
                return Ok(IkSolution { joints_rad: q, branch: None, distance_to_seed, singular });
            }
            let jac = model.jacobian_from_frames(&frames, &tcp.translation.vector);
            let jt = jac.transpose();
            let jtj = &jt * &jac;
            let g = &jt * e;
            let mut improved = false;
            for _ in 0..8 {
                let mut a = jtj.clone();
                for d in 0..n {
                    a[(d, d)] += lambda * (1.0 + jtj[(d, d)]);
                }
                let Some(dq) = a.cholesky().map(|c| c.solve(&g)) else {
                    lambda *= 10.0;
                    continue;
                };
                let mut qn: Vec<f64> = q.iter().zip(dq.iter()).map(|(a, b)| a + b).collect();
                clamp(&mut qn);
                let fr = model.chain_frames(&qn);
                let tc = fr[n] * model.tip_offset * model.tool;
                let en = error_twist(&tc, target);
                let cn = en.norm_squared();
                if cn < cost {
                    q = qn;
                    frames = fr;
                    tcp = tc;
                    e = en;
                    cost = cn;
                    lambda = (lambda * 0.1).max(1e-12);
                    improved = true;
                    break;
                }
                lambda *= 10.0;
            }
            if !improved {
                break;
            }
        }
        let (ep, er) = (e.fixed_rows::<3>(0).norm(), e.fixed_rows::<3>(3).norm());
        if ep < opts.tolerance && er < opts.tolerance {
            let distance_to_seed = q.iter().zip(seed).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
            let singular = crate::kinematics::Manipulability::of(&model.jacobian(&q)).singular;
            return Ok(IkSolution { joints_rad: q, branch: None, distance_to_seed, singular });
        }
        if ep + er < best.0 + best.1 {
            best = (ep, er, q.clone());
        }
    }
    let (residual_m, residual_rad, q_best) = best;
    if crate::kinematics::Manipulability::of(&model.jacobian(&q_best)).singular {
        return Err(IkError::Singular { residual_m, residual_rad });
    }
    let at_limit =
        q_best.iter().zip(model.limits.iter()).any(|(v, l)| (v - l.min).abs() < 1e-9 || (v - l.max).abs() < 1e-9);
    if at_limit {
        return Err(IkError::NoSolutionWithinLimits {
            branches: 0,
            detail: format!(
                "best attempt pinned at a joint limit, {residual_m:.2e} m / {residual_rad:.2e} rad from the target"
            ),
        });
    }
    Err(IkError::NotConverged { attempts: opts.max_attempts, residual_m, residual_rad })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn in_limits() -> impl Strategy<Value = Vec<f64>> {
        let l = crate::parol6::LIMITS_RAD;
        (l[0].0..l[0].1, l[1].0..l[1].1, l[2].0..l[2].1, l[3].0..l[3].1, l[4].0..l[4].1, l[5].0..l[5].1)
            .prop_map(|(a, b, c, d, e, f)| vec![a, b, c, d, e, f])
    }

    fn dist(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
    }

    #[test]
    fn standby_round_trip_lists_labelled_branches() {
        let m = RobotModel::parol6();
        let q = crate::parol6::standby_rad().to_vec();
        let sols = solve_parol6(&m, &m.tcp_isometry(&q), &q).expect("standby is reachable");
        assert!(dist(&sols[0].joints_rad, &q) < 1e-9, "best first: {:?}", sols[0]);
        let labels: std::collections::HashSet<String> =
            sols.iter().filter_map(|s| s.branch.map(|b| b.label())).collect();
        assert_eq!(labels.len(), sols.len(), "branches are distinct");
    }

    #[test]
    fn far_target_is_unreachable() {
        let m = RobotModel::parol6();
        let t = crate::kinematics::iso_from_xyz_rpy([1.0, 0.0, 0.3], [0.0, 0.0, 0.0]);
        let seed = crate::parol6::standby_rad();
        assert!(matches!(solve_parol6(&m, &t, &seed), Err(IkError::Unreachable(_))));
        assert!(matches!(solve_numeric(&m, &t, &seed, &NumericIkOptions::default()), Err(IkError::Unreachable(_))));
    }

    #[test]
    fn pose_behind_the_base_breaks_the_limits() {
        let m = RobotModel::parol6();
        // J1 = 180° is outside ±123°, and every other branch needs J2/J3 outside their ranges.
        let mut q = crate::parol6::standby_rad().to_vec();
        q[0] = PI;
        let t = m.tcp_isometry(&q);
        let r = solve_parol6(&m, &t, &crate::parol6::standby_rad());
        assert!(matches!(r, Err(IkError::NoSolutionWithinLimits { .. })), "{r:?}");
    }

    #[test]
    fn bad_input_is_a_typed_error() {
        let m = RobotModel::parol6();
        let t = m.tcp_isometry(&crate::parol6::standby_rad());
        assert!(matches!(solve_parol6(&m, &t, &[0.0; 3]), Err(IkError::InvalidInput(_))));
        assert!(matches!(solve_parol6(&m, &t, &[f64::NAN; 6]), Err(IkError::InvalidInput(_))));
    }

    #[test]
    fn wrist_singularity_keeps_seed_j4() {
        let m = RobotModel::parol6();
        let mut q = crate::parol6::standby_rad().to_vec();
        q[3] = 0.4;
        q[4] = 0.0;
        q[5] = 2.0;
        let sols = solve_parol6(&m, &m.tcp_isometry(&q), &q).expect("reachable");
        assert!(sols[0].singular);
        assert!(dist(&sols[0].joints_rad, &q) < 1e-9, "{:?}", sols[0]);
    }

    #[test]
    fn j6_wrap_prefers_the_seed_side() {
        let m = RobotModel::parol6();
        let mut q = crate::parol6::standby_rad().to_vec();
        q[5] = 0.0;
        let t = m.tcp_isometry(&q);
        let mut seed = q.clone();
        seed[5] = 6.2;
        let sols = solve_parol6(&m, &t, &seed).expect("reachable");
        assert!((sols[0].joints_rad[5] - TAU).abs() < 1e-9, "{:?}", sols[0].joints_rad);
    }

    #[test]
    fn numeric_success_rate_on_random_poses() {
        use rand::{Rng, SeedableRng};
        let m = RobotModel::parol6();
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let n = 400;
        let mut ok = 0;
        for _ in 0..n {
            let q: Vec<f64> = crate::parol6::LIMITS_RAD.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
            let t = m.tcp_isometry(&q);
            if let Ok(s) = solve_numeric(&m, &t, &crate::parol6::standby_rad(), &NumericIkOptions::default()) {
                let (ep, er) = pose_error(&m.tcp_isometry(&s.joints_rad), &t);
                assert!(ep < 1e-6 && er < 1e-6);
                ok += 1;
            }
        }
        assert!(ok as f64 >= 0.98 * n as f64, "numeric IK solved {ok}/{n}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        #[test]
        fn closed_form_reproduces_pose_and_contains_generator(q in in_limits(), tool_idx in 0usize..6) {
            let mut m = RobotModel::parol6();
            m.set_tool(crate::parol6::Tool::ALL[tool_idx]);
            let target = m.tcp_isometry(&q);
            let seed = crate::parol6::standby_rad();
            let sols = solve_parol6(&m, &target, &seed);
            prop_assert!(sols.is_ok(), "{:?} for {:?}", sols, q);
            let sols = sols.unwrap_or_default();
            for s in &sols {
                let (ep, er) = pose_error(&m.tcp_isometry(&s.joints_rad), &target);
                prop_assert!(ep < 1e-6 && er < 1e-6, "{:?}: {} {}", s, ep, er);
                prop_assert!(m.limits.contains(&s.joints_rad));
            }
            for w in sols.windows(2) {
                prop_assert!(w[0].distance_to_seed <= w[1].distance_to_seed);
            }
            let near_singular = q[4].abs() < 1e-6;
            if !near_singular {
                prop_assert!(sols.iter().any(|s| dist(&s.joints_rad, &q) < 1e-6), "generator {:?} not in {:?}", q, sols);
            }
        }

        #[test]
        fn numeric_reproduces_pose(q in in_limits()) {
            let m = RobotModel::parol6();
            let target = m.tcp_isometry(&q);
            let s = solve_numeric(&m, &target, &crate::parol6::standby_rad(), &NumericIkOptions::default());
            if let Ok(s) = s {
                let (ep, er) = pose_error(&m.tcp_isometry(&s.joints_rad), &target);
                prop_assert!(ep < 1e-6 && er < 1e-6);
                prop_assert!(m.limits.contains(&s.joints_rad));
            }
        }
    }
}

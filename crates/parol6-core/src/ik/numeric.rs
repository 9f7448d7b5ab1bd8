//! Numeric IK for any URDF chain: Levenberg–Marquardt (damped least squares with adaptive
//! damping), every step clamped into the joint limits, deterministic random restarts.

use std::f64::consts::PI;

use nalgebra::{Isometry3, Vector6};

use super::{IkError, IkSolution, NumericIkOptions, check_input};
use crate::kinematics::Manipulability;
use crate::model::{JointKind, RobotModel};

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
                let singular = Manipulability::of(&model.jacobian(&q)).singular;
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
            let singular = Manipulability::of(&model.jacobian(&q)).singular;
            return Ok(IkSolution { joints_rad: q, branch: None, distance_to_seed, singular });
        }
        if ep + er < best.0 + best.1 {
            best = (ep, er, q.clone());
        }
    }
    let (residual_m, residual_rad, q_best) = best;
    if Manipulability::of(&model.jacobian(&q_best)).singular {
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

//! Closed-form IK of the PAROL6 (ROBOT.md §6.1): J1–J3 place the wrist centre, J4–J6 are a
//! ZYZ Euler decomposition; up to 8 labelled branches, wrapped into the joint limits.

use std::f64::consts::{PI, TAU};

use nalgebra::{Isometry3, Matrix3};

use super::{Branch, ElbowBranch, IkError, IkSolution, ShoulderBranch, WristBranch, check_input, pose_error};
use crate::model::RobotModel;

/// How far (m) a target may lie beyond the arm's full stretch or full fold and still be solved,
/// at that boundary, with at most this position error. A pose read to 3 decimals, or from a
/// table whose offsets differ from ours by 0.7 µm (the commander's), can land a fraction of a
/// micrometre outside the reach of joints that are within their limits; refusing it as
/// unreachable would refuse the pose those joints show.
pub const REACH_SLACK_M: f64 = 1e-6;

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

/// At a wrist singularity only J4 + J6 (J5 = 0) or J4 − J6 (J5 = π) is fixed, to `sum` up to
/// whole turns: the split nearest `seed` (least squares in J4 and J6) within their limits,
/// over the turns of J6 that fit. Without limits for J4 / J6, or when no split fits, J4 keeps
/// the seed's value (the limit check then names the joint).
fn singular_wrist_split(model: &RobotModel, sum: f64, plus: bool, seed: &[f64]) -> (f64, f64) {
    let (s4, s6) = (seed[3], seed[5]);
    let fallback = (s4, if plus { sum - s4 } else { s4 - sum });
    let (Some(l4), Some(l6)) = (model.limits.get(3), model.limits.get(5)) else {
        return fallback;
    };
    let mut best: Option<(f64, f64, f64)> = None;
    for k in -3..=3 {
        let c = sum + TAU * k as f64;
        // J4 = t; J6 = c − t (J5 = 0) or t − c (J5 = π)
        let (t_star, lo, hi) = if plus {
            ((s4 + c - s6) / 2.0, l4.min.max(c - l6.max), l4.max.min(c - l6.min))
        } else {
            ((s4 + c + s6) / 2.0, l4.min.max(l6.min + c), l4.max.min(l6.max + c))
        };
        if lo > hi {
            continue;
        }
        let t = t_star.clamp(lo, hi);
        let q6 = if plus { c - t } else { t - c };
        let d = (t - s4).powi(2) + (q6 - s6).powi(2);
        if best.is_none_or(|(_, _, bd)| d < bd) {
            best = Some((t, q6, d));
        }
    }
    best.map_or(fallback, |(q4, q6, _)| (q4, q6))
}

fn rot_z(q: f64) -> Matrix3<f64> {
    let (s, c) = q.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Closed-form IK of the PAROL6: every branch within the limits, best (nearest `seed`) first.
pub fn solve_parol6(model: &RobotModel, target: &Isometry3<f64>, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
    solve_parol6_in(model, target, seed, None)
}

/// A closed-form candidate before the limits: joints, branch, singular, allowed position error (m).
type Candidate = ([f64; 6], Branch, bool, f64);

/// [`solve_parol6`] restricted to one branch when `only` is given (the Cartesian planner, which
/// keeps the start pose's branch, solves only that one: an eighth of the work).
pub fn solve_parol6_in(
    model: &RobotModel,
    target: &Isometry3<f64>,
    seed: &[f64],
    only: Option<Branch>,
) -> Result<Vec<IkSolution>, IkError> {
    let found = solutions_in(model, target, seed, only)?;
    let mut out: Vec<IkSolution> = found.iter().map(Found::solution).collect();
    out.sort_by(|a, b| a.distance_to_seed.total_cmp(&b.distance_to_seed));
    Ok(out)
}

/// The solution [`solve_parol6_in`] would list first among those `admits` takes (`None` when
/// it takes none), without building the list: the Cartesian planner asks this once per sample.
pub(crate) fn nearest_parol6_in(
    model: &RobotModel,
    target: &Isometry3<f64>,
    seed: &[f64],
    only: Option<Branch>,
    admits: impl Fn(Branch, &[f64]) -> bool,
) -> Result<Option<IkSolution>, IkError> {
    let found = solutions_in(model, target, seed, only)?;
    // the first of the least distance: what a stable sort by distance puts first
    let mut best: Option<&Found> = None;
    for f in found.iter().filter(|f| admits(f.branch, &f.joints_rad)) {
        if best.is_none_or(|b| f.distance_to_seed.total_cmp(&b.distance_to_seed).is_lt()) {
            best = Some(f);
        }
    }
    Ok(best.map(Found::solution))
}

/// A solution within the limits, before it becomes an [`IkSolution`] (on the stack).
#[derive(Debug, Clone, Copy)]
struct Found {
    joints_rad: [f64; 6],
    branch: Branch,
    distance_to_seed: f64,
    singular: bool,
}

impl Found {
    fn solution(&self) -> IkSolution {
        IkSolution {
            joints_rad: self.joints_rad.to_vec(),
            branch: Some(self.branch),
            distance_to_seed: self.distance_to_seed,
            singular: self.singular,
        }
    }
}

/// Every branch (or only `only`) within the limits that reaches `target`, in the order the
/// branches are solved (at most eight, on the stack).
struct FoundList {
    items: [Option<Found>; 8],
}

impl FoundList {
    fn iter(&self) -> impl Iterator<Item = &Found> {
        self.items.iter().flatten()
    }
}

/// The closed form's solutions within the limits ([`solve_parol6_in`], unsorted).
fn solutions_in(
    model: &RobotModel,
    target: &Isometry3<f64>,
    seed: &[f64],
    only: Option<Branch>,
) -> Result<FoundList, IkError> {
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
    // (joints, branch, singular, allowed position error m): at most the eight branches, on
    // the stack (the Cartesian planner solves one per 1 ms sample)
    let mut raw: [Option<Candidate>; 8] = [None; 8];
    let mut raw_len = 0;
    let mut any_reach = false;
    let mut reach_detail = String::new();
    for shoulder in [ShoulderBranch::Front, ShoulderBranch::Back] {
        if (shoulder_singular && shoulder == ShoulderBranch::Back) || only.is_some_and(|b| b.shoulder != shoulder) {
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
        let d = d2.sqrt();
        let beyond_reach_m = (d - (a2 + l3)).max((a2 - l3).abs() - d);
        if k.abs() > 1.0 + 1e-12 && beyond_reach_m > REACH_SLACK_M {
            reach_detail = format!(
                "wrist centre is {:.1} mm from the shoulder axis; reachable range {:.1}…{:.1} mm",
                d * 1e3,
                (a2 - l3).abs() * 1e3,
                (a2 + l3) * 1e3
            );
            continue;
        }
        any_reach = true;
        // a target within the slack beyond the reach is solved at the boundary, this far off
        let allowed_error_m = if k.abs() > 1.0 { beyond_reach_m + 1e-7 } else { 1e-7 };
        let k = k.clamp(-1.0, 1.0);
        let elbow_singular = (1.0 - k.abs()) < 1e-12;
        for elbow in [ElbowBranch::Up, ElbowBranch::Down] {
            if (elbow_singular && elbow == ElbowBranch::Down) || only.is_some_and(|b| b.elbow != elbow) {
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
                if only.is_some_and(|b| b.wrist != wrist) && !wrist_singular {
                    continue;
                }
                let (q4, q5, q6) = if wrist_singular {
                    if wrist == WristBranch::Flip {
                        continue;
                    }
                    let b = if m[(2, 2)] > 0.0 { 0.0 } else { PI };
                    let sum = if b == 0.0 { m[(1, 0)].atan2(m[(0, 0)]) } else { (-m[(1, 0)]).atan2(-m[(0, 0)]) };
                    let (q4, q6) = singular_wrist_split(model, sum, b == 0.0, seed);
                    (q4, b, q6)
                } else if wrist == WristBranch::NoFlip {
                    (m[(1, 2)].atan2(m[(0, 2)]), sb.atan2(m[(2, 2)]), m[(2, 1)].atan2(-m[(2, 0)]))
                } else {
                    ((-m[(1, 2)]).atan2(-m[(0, 2)]), (-sb).atan2(m[(2, 2)]), (-m[(2, 1)]).atan2(m[(2, 0)]))
                };
                if let Some(slot) = raw.get_mut(raw_len) {
                    *slot = Some((
                        [q1, q2, q3, q4, q5, q6],
                        Branch { shoulder, elbow, wrist },
                        shoulder_singular || elbow_singular || wrist_singular,
                        allowed_error_m,
                    ));
                    raw_len += 1;
                }
            }
        }
    }
    if !any_reach {
        return Err(IkError::Unreachable(reach_detail));
    }
    let branches_reaching = raw_len;
    let mut out = FoundList { items: [None; 8] };
    let mut out_len = 0;
    let mut first_violation = String::new();
    for (q, branch, singular, allowed_error_m) in raw.into_iter().flatten() {
        let mut wrapped = [0.0; 6];
        let mut wrapped_len = 0;
        for (i, &v) in q.iter().enumerate() {
            let Some(l) = model.limits.get(i) else { break };
            match wrap_into(v, l.min, l.max, seed[i]) {
                Some(w) => {
                    wrapped[i] = w;
                    wrapped_len += 1;
                }
                None => {
                    if first_violation.is_empty() {
                        first_violation =
                            format!("{} branch needs {} = {:.2}°", branch.label(), l.name, v.to_degrees());
                    }
                    break;
                }
            }
        }
        if wrapped_len != 6 {
            continue;
        }
        let (ep, er) = pose_error(&model.tcp_isometry(&wrapped), target);
        if ep > allowed_error_m || er > 1e-7 {
            continue;
        }
        let distance_to_seed = wrapped.iter().zip(seed).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
        if let Some(slot) = out.items.get_mut(out_len) {
            *slot = Some(Found { joints_rad: wrapped, branch, distance_to_seed, singular });
            out_len += 1;
        }
    }
    if out_len == 0 {
        return Err(IkError::NoSolutionWithinLimits { branches: branches_reaching, detail: first_violation });
    }
    Ok(out)
}

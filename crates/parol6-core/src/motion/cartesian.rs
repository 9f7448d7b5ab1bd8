//! Cartesian motion: a [`TcpPath`] timed under TCP speed / acceleration / jerk caps and the
//! joint caps (whichever binds), then turned into joint values at the control rate by IK that
//! keeps the branch of the start pose (no branch flip, no J6 wrap jump mid-move). A path on
//! which a joint would turn faster than the swing bound ([`crate::limits::swing`]) per mm or
//! degree of TCP motion, near a singular pose, is refused ([`CartesianError::SingularSwing`]).

use std::sync::Arc;

use crate::ik::{self, Branch, ConfigRule, IkError};
use crate::limits::swing::swing_over_bound;
use crate::model::RobotModel;
use crate::profile::{JointMove, ProfileKind};

use super::MotionCaps;
use super::path::TcpPath;
use super::trajectory::SampledTrajectory;

/// TCP caps of a Cartesian move.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CartesianCaps {
    /// TCP speed, m/s.
    pub speed_m_s: f64,
    /// TCP acceleration, m/s².
    pub accel_m_s2: f64,
    /// TCP jerk, m/s³.
    pub jerk_m_s3: f64,
}

impl Default for CartesianCaps {
    /// 100 mm/s, 500 mm/s², 5 000 mm/s³.
    fn default() -> Self {
        Self { speed_m_s: 0.1, accel_m_s2: 0.5, jerk_m_s3: 5.0 }
    }
}

/// Why a Cartesian move cannot be planned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CartesianError {
    /// A cap that is not a positive finite number.
    #[error("{0}")]
    Invalid(String),
    /// A point of the path has no IK solution in the start pose's configuration.
    #[error(
        "TCP ({x_mm:.1}, {y_mm:.1}, {z_mm:.1}) mm at t = {t_s:.3} s is not reachable in the start's configuration: {reason}"
    )]
    Unreachable {
        /// Time along the move, s.
        t_s: f64,
        /// TCP position, mm.
        x_mm: f64,
        /// TCP position, mm.
        y_mm: f64,
        /// TCP position, mm.
        z_mm: f64,
        /// The IK error.
        reason: String,
    },
    /// A joint would turn faster than the swing bound ([`crate::limits::swing`]) per mm or
    /// degree of TCP motion: the path passes close to a singular pose.
    #[error("TCP ({x_mm:.1}, {y_mm:.1}, {z_mm:.1}) mm at t = {t_s:.3} s: {reason}")]
    SingularSwing {
        /// Time along the move, s.
        t_s: f64,
        /// TCP position, mm.
        x_mm: f64,
        /// TCP position, mm.
        y_mm: f64,
        /// TCP position, mm.
        z_mm: f64,
        /// Which joint, how fast, the bound ([`crate::limits::swing::SwingOverBound::message`]).
        reason: String,
    },
    /// The joints would jump between two samples (a singularity or a branch change).
    #[error("joint {joint} jumps {jump_deg:.2}° in one step at t = {t_s:.3} s (a singularity on the path)")]
    Discontinuous {
        /// 1-based joint.
        joint: usize,
        /// The jump, deg.
        jump_deg: f64,
        /// Time along the move, s.
        t_s: f64,
    },
}

/// The planned joint trajectory of a Cartesian move, and the branch it keeps.
#[derive(Debug, Clone, PartialEq)]
pub struct CartesianMove {
    /// The joint trajectory at the sample rate.
    pub trajectory: Arc<SampledTrajectory>,
    /// The closed-form configuration held at the end (PAROL6; a move that starts on the wrist
    /// border keeps the wrist it leaves the border in), `None` for numeric IK or a move that
    /// stays on the border.
    pub branch: Option<Branch>,
    /// The configuration rule of the start joints ([`ConfigRule::of_start`]), which the move
    /// keeps: a caller that needs the configuration of those joints reuses it.
    pub start_rule: ConfigRule,
}

/// The most samples one Cartesian move may plan to (1 000 s at 1 kHz): a bound on memory and
/// planning time when joint caps stretch a path near a singularity.
pub const MAX_MOVE_SAMPLES: usize = 1_000_000;

/// A joint may move at most this multiple of its speed cap × dt between two samples before
/// the path counts as discontinuous (a singularity or a branch change).
const JUMP_FACTOR: f64 = 3.0;

/// Plans `path` from the joints `start_q` (which must put the TCP at the path's start):
/// time-scaled (jerk-limited) under `tcp` caps and `joint` caps, sampled every `dt_s`.
pub fn plan(
    model: &RobotModel,
    start_q: &[f64],
    path: &TcpPath,
    tcp: &CartesianCaps,
    joint: &MotionCaps,
    speed_fraction: f64,
    dt_s: f64,
) -> Result<CartesianMove, CartesianError> {
    for (what, v) in [("TCP speed", tcp.speed_m_s), ("TCP acceleration", tcp.accel_m_s2), ("TCP jerk", tcp.jerk_m_s3)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(CartesianError::Invalid(format!("{what} cap must be > 0, got {v}")));
        }
    }
    if !(speed_fraction.is_finite() && speed_fraction > 0.0 && speed_fraction <= 1.0) {
        return Err(CartesianError::Invalid(format!("speed fraction must lie in (0, 1], got {speed_fraction}")));
    }
    if !(dt_s.is_finite() && dt_s > 0.0) {
        return Err(CartesianError::Invalid(format!("sample period must be > 0, got {dt_s}")));
    }
    let start_rule = start_branch(model, start_q);
    let length = path.parameter_length_m();
    // time scaling along the path; stretched while a joint cap binds
    let mut stretch = 1.0;
    for _ in 0..4 {
        let timing = JointMove::plan_with_jerk(
            &[0.0],
            &[length],
            &[tcp.speed_m_s],
            &[tcp.accel_m_s2],
            &[tcp.jerk_m_s3],
            speed_fraction,
            ProfileKind::JerkLimited,
        )
        .map_err(|e| CartesianError::Invalid(e.to_string()))?;
        let duration = timing.duration_s() * stretch;
        let n = (duration / dt_s).ceil().max(1.0);
        if n > MAX_MOVE_SAMPLES as f64 {
            return Err(CartesianError::Invalid(format!(
                "the move would take {duration:.0} s at the joint speed caps (more than {MAX_MOVE_SAMPLES} samples): \
                 the path passes too close to a singularity or is too long"
            )));
        }
        let n = n as usize;
        let mut samples = Vec::with_capacity(n + 1);
        let mut seed = start_q.to_vec();
        let mut rule = start_rule;
        // the path parameter and its derivatives at each sample, without allocating
        let (mut s_at, mut sd, mut sdd) = ([0.0], [0.0], [0.0]);
        let mut prev_pose = path.pose(0.0);
        for k in 0..=n {
            let t = (k as f64 * dt_s).min(duration);
            timing.sample_into(t / stretch, &mut s_at, &mut sd, &mut sdd);
            let s = s_at[0];
            let pose = path.pose(s);
            if k == 0 {
                // exactly where the arm is, so the trajectory is accepted from there
                samples.push(start_q.to_vec());
                continue;
            }
            let q = solve_in_branch(model, &pose, &seed, &mut rule).map_err(|reason| {
                let p = pose.translation.vector * 1000.0;
                CartesianError::Unreachable { t_s: t, x_mm: p.x, y_mm: p.y, z_mm: p.z, reason }
            })?;
            // near a singular pose: refused rather than swing a joint round (the swing bound)
            let travel_m = (pose.translation.vector - prev_pose.translation.vector).norm();
            let rotation_rad = pose.rotation.angle_to(&prev_pose.rotation);
            if let Some(swing) = swing_over_bound(&seed, &q, travel_m, rotation_rad) {
                let p = pose.translation.vector * 1000.0;
                return Err(CartesianError::SingularSwing {
                    t_s: t,
                    x_mm: p.x,
                    y_mm: p.y,
                    z_mm: p.z,
                    reason: swing.message(),
                });
            }
            prev_pose = pose;
            seed.clone_from(&q);
            samples.push(q);
        }
        // how much faster than its cap does any joint go?
        let mut worst: f64 = 0.0;
        for w in samples.windows(2) {
            for (j, (a, b)) in w[0].iter().zip(&w[1]).enumerate() {
                let cap = joint.speed_rad_s.get(j).copied().unwrap_or(f64::INFINITY) * speed_fraction;
                worst = worst.max((b - a).abs() / dt_s / cap);
            }
        }
        if worst <= 1.0 + 1e-9 {
            check_continuity(&samples, joint, dt_s)?;
            let branch = rule.branch();
            return Ok(CartesianMove {
                trajectory: Arc::new(SampledTrajectory::new(dt_s, samples)),
                branch,
                start_rule,
            });
        }
        stretch *= worst * 1.02;
    }
    Err(CartesianError::Invalid("the joint speed caps cannot be met along this path".into()))
}

/// The configuration a Cartesian move from `q` keeps ([`ConfigRule::of_start`]).
pub(crate) fn start_branch(model: &RobotModel, q: &[f64]) -> ConfigRule {
    ConfigRule::of_start(model, q)
}

/// IK nearest `seed` in a configuration `rule` allows; the rule's free parts are then fixed by
/// the solution where it leaves their border. A pose reachable only in another configuration
/// is refused saying what to do instead.
pub(crate) fn solve_in_branch(
    model: &RobotModel,
    pose: &nalgebra::Isometry3<f64>,
    seed: &[f64],
    rule: &mut ConfigRule,
) -> Result<Vec<f64>, String> {
    match ik::solve_nearest(model, pose, seed, *rule) {
        Ok(sol) => {
            *rule = rule.settled_by(&sol);
            Ok(sol.joints_rad)
        }
        Err(e @ IkError::OtherConfiguration { .. }) => Err(format!(
            "{e}. A Cartesian move keeps the configuration of its start: insert a joint move to the pose \
             (move_pose, G-code G0, commander MovePose) before this move"
        )),
        Err(e) => Err(e.to_string()),
    }
}

fn check_continuity(samples: &[Vec<f64>], joint: &MotionCaps, dt_s: f64) -> Result<(), CartesianError> {
    for (k, w) in samples.windows(2).enumerate() {
        for (j, (a, b)) in w[0].iter().zip(&w[1]).enumerate() {
            let cap = joint.speed_rad_s.get(j).copied().unwrap_or(f64::INFINITY);
            if (b - a).abs() > JUMP_FACTOR * cap * dt_s {
                return Err(CartesianError::Discontinuous {
                    joint: j + 1,
                    jump_deg: (b - a).abs().to_degrees(),
                    t_s: (k + 1) as f64 * dt_s,
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Point3, Vector3};

    fn setup() -> (RobotModel, Vec<f64>, MotionCaps) {
        let model = RobotModel::parol6();
        let mut q = crate::parol6::standby_rad().to_vec();
        // away from the standby wrist singularity
        q[1] += 0.2;
        q[2] -= 0.3;
        q[4] = 0.6;
        let caps = MotionCaps::of(&model);
        (model, q, caps)
    }

    /// The commanded TCP stays within 0.05 mm and 0.05° of the ideal line, without a branch
    /// change, and every joint stays under its speed cap.
    #[test]
    fn a_straight_line_is_straight_within_tolerance() {
        let (model, q0, caps) = setup();
        let a = model.tcp_isometry(&q0);
        let mut b = a;
        b.translation.vector += Vector3::new(0.05, -0.04, 0.03);
        b.rotation = nalgebra::UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.2) * a.rotation;
        let path = TcpPath::line(&a, &b);
        let mv = plan(&model, &q0, &path, &CartesianCaps::default(), &caps, 1.0, 0.001).expect("plans");
        let traj = &mv.trajectory;
        assert!(mv.branch.is_some());
        let dir = (b.translation.vector - a.translation.vector).normalize();
        let mut t = 0.0;
        while t <= traj.duration_s() {
            let q = traj.sample(t).q;
            let p = model.tcp_isometry(&q);
            let d = p.translation.vector - a.translation.vector;
            let off_line = (d - dir * d.dot(&dir)).norm();
            assert!(off_line < 0.05e-3, "{:.4} mm off the line at t = {t:.4}", off_line * 1e3);
            // orientation: the slerp at the same fraction of the way
            let frac = (d.dot(&dir) / (b.translation.vector - a.translation.vector).norm()).clamp(0.0, 1.0);
            let ideal = a.rotation.slerp(&b.rotation, frac);
            assert!(p.rotation.angle_to(&ideal).to_degrees() < 0.05, "orientation at t = {t:.4}");
            t += 0.0007;
        }
        let end = model.tcp_isometry(traj.goal());
        assert!((end.translation.vector - b.translation.vector).norm() < 1e-9);
        for w in traj.samples().windows(2) {
            for ((a, b), cap) in w[0].iter().zip(&w[1]).zip(&caps.speed_rad_s) {
                assert!((b - a).abs() / 0.001 <= cap * (1.0 + 1e-6));
            }
        }
    }

    #[test]
    fn a_circle_is_round() {
        let (model, q0, caps) = setup();
        let a = model.tcp_isometry(&q0);
        let center = Point3::from(a.translation.vector + Vector3::new(0.03, 0.0, 0.0));
        let path = TcpPath::arc_about(&a, &center, &Vector3::z(), std::f64::consts::TAU).expect("circle");
        let mv = plan(&model, &q0, &path, &CartesianCaps::default(), &caps, 1.0, 0.001).expect("plans");
        for q in mv.trajectory.samples() {
            let p = model.tcp_isometry(q).translation.vector;
            let r = ((p.x - center.x).powi(2) + (p.y - center.y).powi(2)).sqrt();
            assert!((r - 0.03).abs() < 0.05e-3 && (p.z - center.z).abs() < 0.05e-3);
        }
    }

    #[test]
    fn an_unreachable_line_names_where() {
        let (model, q0, caps) = setup();
        let a = model.tcp_isometry(&q0);
        let mut b = a;
        b.translation.vector += Vector3::new(0.0, 0.0, 1.0);
        let e = plan(&model, &q0, &TcpPath::line(&a, &b), &CartesianCaps::default(), &caps, 1.0, 0.001)
            .expect_err("out of reach");
        assert!(e.to_string().contains("mm at t ="), "{e}");
    }
}

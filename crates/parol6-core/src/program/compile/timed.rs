//! Moves whose time is given rather than their speed: joint and Cartesian moves with a
//! `duration_s` (planned as fast as the caps allow, then stretched uniformly in time to that
//! duration, so every speed and acceleration only gets lower), relative tool-frame goals, and
//! time functions (timed TCP points followed at the sample period, IK in the start branch).
//!
//! The speed override stretches these in time too: a move of `duration_s` takes
//! `duration_s / speed_override`, a time function runs that much slower.

use std::sync::Arc;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::{MAX_TCP_SPEED_MM_S, StepAction, StepError, cartesian_move};
use crate::model::RobotModel;
use crate::motion::MotionCaps;
use crate::motion::cartesian::{self, CartesianError, MAX_MOVE_SAMPLES};
use crate::motion::path::TcpPath;
use crate::motion::trajectory::SampledTrajectory;
use crate::profile::ProfileKind;
use crate::program::SpeedSettings;
use crate::program::timefn::{JOIN_TOLERANCE_DEG, JOIN_TOLERANCE_MM, TimedPose};

/// The longest `duration_s` a move may ask for, s.
pub const MAX_MOVE_DURATION_S: f64 = 3600.0;

/// How much shorter than the fastest possible move a `duration_s` may be and still count as
/// that move (rounding of the planned duration to samples), s.
const DURATION_SLACK_S: f64 = 1e-6;

fn checked_duration(duration_s: f64) -> Result<f64, String> {
    if duration_s.is_finite() && duration_s > 0.0 && duration_s <= MAX_MOVE_DURATION_S {
        Ok(duration_s)
    } else {
        Err(format!("duration_s must lie in 0–{MAX_MOVE_DURATION_S} s (above 0), got {duration_s}"))
    }
}

/// The goal of a move given in the tool frame of `from`: `from · Trans(offset) · Rx·Ry·Rz`.
pub(crate) fn tool_frame_goal(from: &Isometry3<f64>, offset_mm: &[f64; 3], rotation_deg: &[f64; 3]) -> Isometry3<f64> {
    let [rx, ry, rz] = rotation_deg.map(f64::to_radians);
    let rotation = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), rx)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), ry)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), rz);
    let offset = Translation3::from(Vector3::from(*offset_mm) / 1000.0);
    from * Isometry3::from_parts(offset, rotation)
}

/// `traj` (as fast as allowed, `fastest_s` long) slowed uniformly to last `duration_s` at the
/// wall-clock `dt_s`.
fn stretch(traj: &SampledTrajectory, duration_s: f64, dt_s: f64) -> Result<SampledTrajectory, String> {
    let n = (duration_s / dt_s).ceil().max(1.0);
    if n > MAX_MOVE_SAMPLES as f64 {
        return Err(format!("the move would take {duration_s:.0} s (more than {MAX_MOVE_SAMPLES} samples)"));
    }
    let n = n as usize;
    let scale = traj.duration_s() / duration_s;
    let mut samples = Vec::with_capacity(n + 1);
    for k in 0..=n {
        let t = (k as f64 * dt_s).min(duration_s) * scale;
        samples.push(if k == 0 { traj.samples()[0].clone() } else { traj.sample(t).q });
    }
    Ok(SampledTrajectory::new(dt_s, samples))
}

/// The time a move takes: `duration_s`, or the fastest the caps allow when that is shorter
/// (stretched, with a warning naming both times: official programs ask for times our caps
/// cannot meet, and a user expects them to run, slower and safely).
fn feasible_duration(fastest_s: f64, duration_s: f64, what: &str, warnings: &mut Vec<String>) -> f64 {
    if duration_s + DURATION_SLACK_S < fastest_s {
        warnings.push(format!(
            "{duration_s} s is too short for the {what}: stretched to {fastest_s:.3} s, the fastest they allow"
        ));
        fastest_s
    } else {
        duration_s
    }
}

/// A synchronised joint move from `start` to `goal` that takes `duration_s` (÷ the speed
/// override): the fastest jerk-limited move under the joint caps, slowed to that time.
pub(super) fn joint_move_in(
    start: &[f64],
    goal: &[f64],
    caps: &MotionCaps,
    duration_s: f64,
    opts: super::CompileOptions,
    warnings: &mut Vec<String>,
) -> Result<StepAction, StepError> {
    let duration_s = checked_duration(duration_s)?;
    let mv = caps.plan_joint_move(start, goal, 1.0, ProfileKind::JerkLimited).map_err(|e| e.to_string())?;
    let fastest_s = mv.duration_s();
    let duration_s = feasible_duration(fastest_s, duration_s, "joint speed caps", warnings);
    let run_s = duration_s / opts.speed_override;
    let n = (run_s / opts.dt_s).ceil().max(1.0);
    if n > MAX_MOVE_SAMPLES as f64 {
        return Err(format!("the move would take {run_s:.0} s (more than {MAX_MOVE_SAMPLES} samples)").into());
    }
    let n = n as usize;
    let scale = fastest_s / run_s;
    let samples = (0..=n)
        .map(|k| {
            if k == 0 {
                start.to_vec()
            } else {
                mv.sample(((k as f64 * opts.dt_s).min(run_s) * scale).min(fastest_s)).q
            }
        })
        .collect();
    Ok(StepAction::Motion(Arc::new(SampledTrajectory::new(opts.dt_s, samples))))
}

/// A Cartesian move along `path` that takes `duration_s` (÷ the speed override): planned at
/// the PAROL6's top TCP speed under the program's acceleration and jerk and the joint caps,
/// then slowed to that time.
#[expect(clippy::too_many_arguments, reason = "the move, its caps and where its warnings go; one call site each")]
pub(super) fn cartesian_move_in(
    model: &RobotModel,
    q: &[f64],
    path: &TcpPath,
    speed: &SpeedSettings,
    duration_s: f64,
    caps: &MotionCaps,
    opts: super::CompileOptions,
    notes: &mut super::StepNotes,
) -> Result<StepAction, StepError> {
    let duration_s = checked_duration(duration_s)?;
    let fastest = match cartesian_move(
        model,
        q,
        path,
        speed,
        Some(MAX_TCP_SPEED_MM_S),
        caps,
        super::CompileOptions { speed_override: 1.0, ..opts },
        notes,
    )? {
        StepAction::Motion(t) => t,
        _ => return Err(StepError::Message("a Cartesian move gave no motion".into())),
    };
    let fastest_s = fastest.duration_s();
    let duration_s = feasible_duration(fastest_s, duration_s, "TCP and joint caps", &mut notes.warnings);
    let traj = stretch(&fastest, duration_s / opts.speed_override, opts.dt_s)?;
    Ok(StepAction::Motion(Arc::new(traj)))
}

/// Follows timed TCP points from joints `q`: the first point must be where the TCP is; the
/// pose between points is interpolated (position linearly, orientation by slerp) at the sample
/// period, solved by IK in the start branch, and refused where the TCP would go faster than
/// the PAROL6's Cartesian limit or a joint faster than its speed cap.
pub(super) fn follow(
    model: &RobotModel,
    q: &[f64],
    points: &[TimedPose],
    caps: &MotionCaps,
    opts: super::CompileOptions,
    notes: &mut super::StepNotes,
) -> Result<StepAction, StepError> {
    let Some((_, first)) = points.first() else {
        return Err(StepError::Message("the time function has no points".into()));
    };
    let here = model.tcp_isometry(q);
    let gap_mm = (first.translation.vector - here.translation.vector).norm() * 1000.0;
    let turn_deg = first.rotation.angle_to(&here.rotation).to_degrees();
    if gap_mm > JOIN_TOLERANCE_MM || turn_deg > JOIN_TOLERANCE_DEG {
        let p = first.translation.vector * 1000.0;
        return Err(StepError::Message(format!(
            "the function starts at ({:.1}, {:.1}, {:.1}) mm, {gap_mm:.2} mm and {turn_deg:.2}° from where the TCP is \
             when the step starts; move there first (no approach move is added)",
            p.x, p.y, p.z
        )));
    }
    for w in points.windows(2) {
        let (dt, d_mm) = (w[1].0 - w[0].0, (w[1].1.translation.vector - w[0].1.translation.vector).norm() * 1000.0);
        if dt > 0.0 && d_mm / dt > MAX_TCP_SPEED_MM_S * (1.0 + 1e-9) {
            return Err(StepError::Message(format!(
                "the TCP would move at {:.1} mm/s at t = {:.3} s, over the PAROL6's {MAX_TCP_SPEED_MM_S} mm/s",
                d_mm / dt,
                w[0].0
            )));
        }
    }
    let total_s = points.last().map_or(0.0, |p| p.0);
    let run_s = total_s / opts.speed_override;
    let n = (run_s / opts.dt_s).ceil().max(1.0);
    if n > MAX_MOVE_SAMPLES as f64 {
        return Err(format!("the function would take {run_s:.0} s (more than {MAX_MOVE_SAMPLES} samples)").into());
    }
    let n = n as usize;
    let mut rule = cartesian::start_branch(model, q);
    notes.start_config = Some(rule);
    let mut samples = Vec::with_capacity(n + 1);
    samples.push(q.to_vec());
    let mut seed = q.to_vec();
    let mut seg = 0;
    for k in 1..=n {
        let t = (k as f64 * opts.dt_s * opts.speed_override).min(total_s);
        while seg + 2 < points.len() && points[seg + 1].0 <= t {
            seg += 1;
        }
        let pose = between(points, seg, t);
        let goal = cartesian::solve_in_branch(model, &pose, &seed, &mut rule).map_err(|reason| {
            let p = pose.translation.vector * 1000.0;
            StepError::Cartesian(CartesianError::Unreachable { t_s: t, x_mm: p.x, y_mm: p.y, z_mm: p.z, reason })
        })?;
        for (j, ((a, b), cap)) in seed.iter().zip(&goal).zip(&caps.speed_rad_s).enumerate() {
            let v = (b - a).abs() / opts.dt_s;
            if v > cap * (1.0 + 1e-6) {
                return Err(StepError::Message(format!(
                    "joint {} would turn at {:.1}°/s at t = {t:.3} s, over its speed cap {:.1}°/s: make the function \
                     slower there",
                    j + 1,
                    v.to_degrees(),
                    cap.to_degrees()
                )));
            }
        }
        seed.clone_from(&goal);
        samples.push(goal);
    }
    Ok(StepAction::Motion(Arc::new(SampledTrajectory::new(opts.dt_s, samples))))
}

/// The pose at time `t` between points `seg` and `seg + 1`.
fn between(points: &[TimedPose], seg: usize, t: f64) -> Isometry3<f64> {
    let (t0, a) = &points[seg];
    let Some((t1, b)) = points.get(seg + 1) else { return *a };
    let f = if t1 > t0 { ((t - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 1.0 };
    let position = a.translation.vector.lerp(&b.translation.vector, f);
    let rotation = a.rotation.try_slerp(&b.rotation, f, 1e-9).unwrap_or(b.rotation);
    Isometry3::from_parts(Translation3::from(position), rotation)
}

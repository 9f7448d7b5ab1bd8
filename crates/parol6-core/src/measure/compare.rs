//! Simulation against robot: the same test run on two backends, compared over time (path
//! tests: per-joint and TCP difference at the same instant since each cycle's start; both runs
//! schedule the same trajectories on their motion clocks) and per pose (pose tests: the
//! distance between the barycentres of the attained positions).

use nalgebra::Vector3;
use serde::Serialize;

use super::driver::{PathRecording, TrackSample};
use super::pose_figures::PoseSample;
use crate::model::RobotModel;

/// The difference of two runs at one instant: `a − b`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiffSample {
    /// 1-based cycle.
    pub cycle: usize,
    /// Time since the cycle's path started, s.
    pub t_s: f64,
    /// Measured joints of `a` minus those of `b`, deg.
    pub joint_deg: Vec<f64>,
    /// Distance between the two attained TCP positions, mm.
    pub tcp_mm: f64,
}

/// Summary of a comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiffSummary {
    /// Largest |joint difference| per joint, deg.
    pub max_joint_deg: Vec<f64>,
    /// Largest TCP distance, mm.
    pub max_tcp_mm: f64,
    /// RMS TCP distance, mm.
    pub rms_tcp_mm: f64,
}

/// The measured joints of `samples` (sorted by time) at `t_s`, linearly interpolated
/// (clamped to the ends); `None` when there are no samples.
pub fn measured_at(samples: &[TrackSample], t_s: f64) -> Option<Vec<f64>> {
    let first = samples.first()?;
    let i = samples.partition_point(|s| s.t_s < t_s);
    if i == 0 {
        return Some(first.measured_q.clone());
    }
    let Some(b) = samples.get(i) else {
        return samples.last().map(|s| s.measured_q.clone());
    };
    let a = &samples[i - 1];
    let span = b.t_s - a.t_s;
    let f = if span > 0.0 { ((t_s - a.t_s) / span).clamp(0.0, 1.0) } else { 0.0 };
    Some(a.measured_q.iter().zip(&b.measured_q).map(|(x, y)| x + (y - x) * f).collect())
}

/// `a − b` at every sample of `a`, cycle by cycle (the cycles both have).
pub fn path_difference(model: &RobotModel, a: &PathRecording, b: &PathRecording) -> Vec<DiffSample> {
    let mut out = Vec::new();
    for (k, (ca, cb)) in a.cycles.iter().zip(&b.cycles).enumerate() {
        for s in ca {
            let Some(qb) = measured_at(cb, s.t_s) else { continue };
            let joint_deg = s.measured_q.iter().zip(&qb).map(|(x, y)| (x - y).to_degrees()).collect();
            let pa = model.tcp_isometry(&s.measured_q).translation.vector;
            let pb = model.tcp_isometry(&qb).translation.vector;
            out.push(DiffSample { cycle: k + 1, t_s: s.t_s, joint_deg, tcp_mm: (pa - pb).norm() * 1000.0 });
        }
    }
    out
}

/// The summary of a comparison; `None` when it is empty.
pub fn summarize(diff: &[DiffSample]) -> Option<DiffSummary> {
    let n = diff.first()?.joint_deg.len();
    let mut max_joint_deg = vec![0.0f64; n];
    for d in diff {
        for (m, v) in max_joint_deg.iter_mut().zip(&d.joint_deg) {
            *m = m.max(v.abs());
        }
    }
    let max_tcp_mm = diff.iter().map(|d| d.tcp_mm).fold(0.0, f64::max);
    let rms_tcp_mm = (diff.iter().map(|d| d.tcp_mm * d.tcp_mm).sum::<f64>() / diff.len() as f64).sqrt();
    Some(DiffSummary { max_joint_deg, max_tcp_mm, rms_tcp_mm })
}

/// Per test pose (0 = P1) present in both: the distance between the barycentres of the
/// attained positions of `a` and of `b`, mm.
pub fn pose_difference(a: &[PoseSample], b: &[PoseSample]) -> Vec<(usize, f64)> {
    let mean = |s: &[PoseSample], pose: usize| {
        let v: Vec<Vector3<f64>> =
            s.iter().filter(|x| x.pose == pose).map(|x| Vector3::from(x.attained.position_mm)).collect();
        (!v.is_empty()).then(|| v.iter().sum::<Vector3<f64>>() / v.len() as f64)
    };
    (0..5).filter_map(|pose| Some((pose, (mean(a, pose)? - mean(b, pose)?).norm()))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::{PathKind, PathTestPlan, TestCube};
    use crate::program::PoseMm;

    fn track(t: &[f64], q0: &[f64]) -> Vec<TrackSample> {
        t.iter()
            .zip(q0)
            .map(|(&t_s, &q)| TrackSample { t_s, commanded_q: vec![q; 6], measured_q: vec![q; 6] })
            .collect()
    }

    #[test]
    fn measured_joints_are_interpolated_in_time_and_clamped() {
        let s = track(&[0.0, 1.0], &[0.0, 2.0]);
        assert_eq!(measured_at(&s, 0.25).unwrap()[0], 0.5);
        assert_eq!(measured_at(&s, -1.0).unwrap()[0], 0.0);
        assert_eq!(measured_at(&s, 5.0).unwrap()[0], 2.0);
        assert!(measured_at(&[], 0.0).is_none());
    }

    #[test]
    fn a_run_against_itself_differs_by_nothing_and_an_offset_joint_shows() {
        let model = RobotModel::parol6();
        let cube = TestCube { center_mm: [0.0, 250.0, 250.0], edge_mm: 50.0, orientation_rpy_deg: [180.0, 0.0, 0.0] };
        let plan = PathTestPlan::new(cube, PathKind::Line);
        let q = crate::parol6::standby_rad().to_vec();
        let a = PathRecording {
            plan,
            cycles: vec![vec![
                TrackSample { t_s: 0.0, commanded_q: q.clone(), measured_q: q.clone() },
                TrackSample { t_s: 0.1, commanded_q: q.clone(), measured_q: q.clone() },
            ]],
        };
        let same = summarize(&path_difference(&model, &a, &a)).unwrap();
        assert_eq!(same.max_tcp_mm, 0.0);
        let mut b = a.clone();
        for s in &mut b.cycles[0] {
            s.measured_q[0] += 1f64.to_radians();
        }
        let d = summarize(&path_difference(&model, &a, &b)).unwrap();
        assert!((d.max_joint_deg[0] - 1.0).abs() < 1e-9 && d.max_joint_deg[1] == 0.0, "{d:?}");
        assert!(d.max_tcp_mm > 1.0, "one degree of J1 moves the TCP: {d:?}");
    }

    #[test]
    fn pose_difference_is_between_barycentres() {
        let p = |x: f64| PoseMm { position_mm: [x, 0.0, 0.0], rpy_deg: [0.0; 3] };
        let s = |cycle, x| PoseSample { cycle, pose: 2, commanded: p(0.0), attained: p(x) };
        let d = pose_difference(&[s(1, 1.0), s(2, 3.0)], &[s(1, 5.0)]);
        assert_eq!(d, vec![(2, 3.0)]);
    }
}

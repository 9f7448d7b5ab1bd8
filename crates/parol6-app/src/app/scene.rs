//! The 3D view's frame: the recorded arm at the cursor during replay (the commanded pose as the
//! ghost), else the shown pose with its limit zones, the ghost of a previewed or moving target,
//! the planned path and the trail's colour sample.

use parol6_core::limits::LimitZone;

use super::{GHOST_MIN_DIFF_RAD, Parol6App};
use crate::panels::{RobotState, StateSource};
use crate::viewport::SceneFrame;

impl Parol6App {
    /// The scene of this frame for `robot` (the shown state) and the ghost a panel asked for.
    pub(super) fn scene(&self, robot: &RobotState, preview: Option<Vec<f64>>) -> SceneFrame {
        let ghost: Option<Vec<f64>> = preview.or_else(|| {
            let differs = robot.target_q.len() == robot.q.len()
                && robot.target_q.iter().zip(&robot.q).any(|(t, q)| (t - q).abs() > GHOST_MIN_DIFF_RAD);
            differs.then(|| robot.target_q.clone())
        });
        let recorded = self.state.replay.as_ref().and_then(|r| r.joints_at_cursor());
        let planned_path = self.panels.planned_path(recorded.is_some());
        match &recorded {
            Some((q, cmd)) => {
                let differs = cmd.iter().zip(q).any(|(c, q)| (c - q).abs() > GHOST_MIN_DIFF_RAD);
                let mut scene = SceneFrame::from_joints(&self.model, q, differs.then_some(cmd.as_slice()));
                scene.trail_sample.tracking_error_rad = max_abs_diff(cmd, q);
                // the loaded program's planned path stays, to compare with the recorded motion
                scene.planned_path = planned_path;
                scene
            }
            None => {
                let zones: Vec<LimitZone> = robot.zones.iter().map(|z| z.zone).collect();
                let mut scene = SceneFrame::with_zones(&self.model, &robot.q, &zones, ghost.as_deref());
                scene.planned_path = planned_path;
                scene.trail_sample = crate::viewport::trail_color::TrailSample {
                    tcp_speed_m_s: tcp_speed_m_s(&self.model, &robot.q, &robot.qd),
                    tracking_error_rad: max_abs_diff(&robot.commanded.q, &robot.q),
                };
                let snap = self.sim.snapshot();
                if robot.source == StateSource::Simulation && snap.link_poses.len() == scene.link_poses.len() {
                    scene.link_poses = snap.link_poses.clone();
                }
                scene
            }
        }
    }
}

/// Largest |a − b| over the joints (0 for empty or mismatched vectors).
fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return 0.0;
    }
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// TCP linear speed from joint velocities (the Jacobian's linear rows), m/s.
fn tcp_speed_m_s(model: &parol6_core::RobotModel, q: &[f64], qd: &[f64]) -> f64 {
    if q.len() != model.dof() || qd.len() != model.dof() {
        return 0.0;
    }
    let j = model.jacobian(q);
    let v = j.fixed_rows::<3>(0) * parol6_core::na::DVector::from_column_slice(qd);
    v.norm()
}

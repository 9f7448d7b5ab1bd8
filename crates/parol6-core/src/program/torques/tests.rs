use std::sync::Arc;

use super::*;
use crate::dynamics::GRAVITY_M_S2;
use crate::model::LoadOptions;
use crate::motion::trajectory::SampledTrajectory;
use crate::program::compile::{CompileOptions, compile};

/// One revolute joint about `axis`, a 2 kg link whose COM is 0.3 m along x, inertia 0.01 about
/// every axis at the COM.
fn pendulum(axis: &str) -> RobotModel {
    let xml = format!(
        r#"<robot name="pendulum">
  <link name="base"/>
  <link name="arm"><inertial><origin xyz="0.3 0 0"/><mass value="2"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="{axis}"/><limit lower="-3" upper="3" effort="1" velocity="2"/></joint>
</robot>"#
    );
    RobotModel::from_urdf_str(&xml, &LoadOptions::default()).expect("pendulum loads")
}

fn motion_step(dt_s: f64, q: Vec<Vec<f64>>) -> CompiledStep {
    let end_q = q.last().cloned().unwrap_or_default();
    CompiledStep {
        steps: 0..1,
        line: 7,
        kind: "move_j",
        action: StepAction::Motion(Arc::new(SampledTrajectory::new(dt_s, q))),
        end_q,
        warnings: Vec::new(),
        start_config: None,
    }
}

#[test]
fn a_link_held_still_under_gravity_needs_m_g_l() {
    // axis y, COM along +x: gravity (−z) pulls the COM down, a torque of m·g·L about y
    let model = pendulum("0 1 0");
    let steps = [motion_step(0.01, vec![vec![0.0]; 11])];
    let out = program_torques(&model, &steps, &[0.0], Some(vec![1.0]));
    let expected = 2.0 * GRAVITY_M_S2 * 0.3;
    for &v in &out.torques_nm[0] {
        assert!((v.abs() - expected).abs() < 1e-9, "{v} vs {expected}");
    }
    assert!((out.peak_abs_nm[0] - expected).abs() < 1e-9);
    // 5.886 N·m against a 1 N·m limit: one warning covering the whole hold, naming the line
    assert_eq!(out.warnings.len(), 1, "{:?}", out.warnings);
    let w = &out.warnings[0];
    assert_eq!((w.joint, w.line, w.step_kind), (1, 7, "start"));
    assert!((w.end_s - 0.1).abs() < 1e-12 && (w.peak_nm.abs() - expected).abs() < 1e-9);
    // a generous limit: no warning
    assert!(program_torques(&model, &steps, &[0.0], Some(vec![10.0])).warnings.is_empty());
}

#[test]
fn a_constant_acceleration_about_a_vertical_axis_needs_i_alpha() {
    // axis z: no gravity torque; q = a t²/2 ⇒ τ = (Izz + m L²)·a inside the move
    let model = pendulum("0 0 1");
    let (a, dt) = (2.0, 0.01);
    let q: Vec<Vec<f64>> = (0..=50).map(|k| vec![0.5 * a * (k as f64 * dt).powi(2)]).collect();
    let out = program_torques(&model, &[motion_step(dt, q)], &[0.0], None);
    let expected = (0.01 + 2.0 * 0.3 * 0.3) * a;
    // samples 2..49 of the move are inside it (index 0 is the start pose)
    for k in 3..50 {
        let v = out.torques_nm[0][k];
        assert!((v - expected).abs() < 1e-6, "sample {k}: {v} vs {expected}");
    }
    assert!(out.limits_nm.is_none() && out.warnings.is_empty());
    assert!(out.time_s.windows(2).all(|w| w[0] <= w[1]));
    assert!((out.time_s.last().copied().unwrap_or(0.0) - 0.5).abs() < 1e-12);
}

#[test]
fn a_dwell_holds_gravity_and_extends_the_time_axis() {
    let model = pendulum("0 1 0");
    let dwell = CompiledStep {
        steps: 1..2,
        line: 9,
        kind: "dwell",
        action: StepAction::Dwell(2.0),
        end_q: vec![0.0],
        warnings: Vec::new(),
        start_config: None,
    };
    let out = program_torques(&model, &[dwell], &[0.0], Some(vec![1.0]));
    assert!((out.time_s.last().copied().unwrap_or(0.0) - 2.0).abs() < 1e-12);
    assert_eq!(out.warnings.len(), 1);
    assert!((out.warnings[0].end_s - 2.0).abs() < 1e-12);
}

#[test]
fn the_parol6_demo_programs_stay_finite_and_sample_every_motion() {
    let model = RobotModel::parol6();
    let start = crate::parol6::standby_rad();
    let limits = torque_limits_nm(&model).expect("the PAROL6 has documented limits");
    assert_eq!(limits.len(), 6);
    for program in crate::program::builtin::programs(&model) {
        let steps = compile(&model, &program, &start, CompileOptions::PREFLIGHT).expect("demo compiles");
        let total_s: f64 = steps.iter().map(CompiledStep::duration_s).sum();
        let out = program_torques(&model, &steps, &start, Some(limits.clone()));
        assert!(out.torques_nm.iter().flatten().all(|v| v.is_finite()), "{}", program.name);
        assert!((out.time_s.last().copied().unwrap_or(0.0) - total_s).abs() < 1e-6, "{}", program.name);
        // J2 carries the arm against gravity somewhere in every demo
        assert!(out.peak_abs_nm[1] > 0.1, "{}: {:?}", program.name, out.peak_abs_nm);
        for w in &out.warnings {
            assert!(w.peak_nm.abs() > w.limit_nm && w.start_s <= w.peak_s && w.peak_s <= w.end_s);
        }
    }
}

#[test]
fn a_robot_without_documented_limits_gets_none() {
    assert!(torque_limits_nm(&pendulum("0 0 1")).is_none());
}

/// A recording's torques (replay's Dynamics panel): the same inverse dynamics at every sample
/// given, no start sample at rest added, and a stretch over the limit named by its sample.
#[test]
fn motion_torques_are_the_inverse_dynamics_of_every_recorded_sample() {
    let model = pendulum("0 1 0");
    let samples: Vec<(f64, f64, f64, f64)> = (0..50).map(|k| (k as f64 * 0.01, 0.02 * k as f64, 2.0, 0.0)).collect();
    let mut it = samples.iter();
    let t = motion_torques(&model, Some(vec![5.0]), |q, qd, qdd| {
        let &(t_s, a, b, c) = it.next()?;
        (q[0], qd[0], qdd[0]) = (a, b, c);
        Some(t_s)
    });
    assert_eq!(t.time_s.len(), samples.len(), "one torque per sample");
    let mut id = InverseDynamics::new(&model);
    for (k, &(t_s, a, b, c)) in samples.iter().enumerate() {
        let mut tau = [0.0];
        id.compute_into(&model, &[a], &[b], &[c], &mut tau);
        assert_eq!((t.time_s[k], t.torques_nm[0][k]), (t_s, tau[0]), "sample {k}");
    }
    // 2 kg at 0.3 m: ~5.9 N·m at q = 0, over the 5 N·m limit until cos(q) < 5 / 5.88
    let w = t.warnings.first().expect("the stretch over the limit");
    assert_eq!((w.joint, w.line, w.step, w.step_kind, w.start_s), (1, 0, 0, "recording", 0.0), "{w:?}");
    assert!(w.end_s > 0.0 && w.end_s < 0.49, "{w:?}");
}

//! Unit tests of the simulation's dynamics: inverse dynamics against an independent Lagrange
//! formulation, rapier's forward dynamics, applied torques and torque runs.

use nalgebra::{DMatrix, DVector, Matrix3};
use rand::{Rng, SeedableRng};

use super::tests::{max_abs_diff, parol6, random_free_config, run_s, sim};
use super::*;
use crate::dynamics::body_inertials;
use crate::model::JointKind;
use crate::motion::MotionCommand;
use crate::parol6::standby_rad;
use crate::profile::ProfileKind;

/// Independent inverse dynamics: Lagrange's equations with the mass matrix from COM Jacobians,
/// gravity from the potential energy, Coriolis terms by central differences of the mass matrix.
fn lagrange_torques(model: &RobotModel, q: &[f64], qd: &[f64], qdd: &[f64]) -> Vec<f64> {
    let n = model.dof();
    let bodies = body_inertials(model);
    let jacobians = |q: &[f64]| {
        let frames = model.chain_frames(q);
        let mut out = Vec::new();
        for k in 1..=n {
            let Some(b) = &bodies[k] else { continue };
            let p = frames[k] * b.com_m;
            let r = frames[k].rotation.to_rotation_matrix().into_inner();
            let mut jv = DMatrix::zeros(3, n);
            let mut jw = DMatrix::zeros(3, n);
            for j in 0..k {
                let a = frames[j + 1].rotation * model.joints[j].axis.into_inner();
                if model.joints[j].kind == JointKind::Prismatic {
                    jv.fixed_view_mut::<3, 1>(0, j).copy_from(&a);
                } else {
                    let o = frames[j + 1].translation.vector;
                    jv.fixed_view_mut::<3, 1>(0, j).copy_from(&a.cross(&(p.coords - o)));
                    jw.fixed_view_mut::<3, 1>(0, j).copy_from(&a);
                }
            }
            out.push((b.mass_kg, jv, jw, r * b.inertia_kg_m2 * r.transpose()));
        }
        out
    };
    let mass_matrix = |q: &[f64]| {
        let mut m = DMatrix::zeros(n, n);
        for (mass, jv, jw, i_w) in jacobians(q) {
            let i_w = DMatrix::from_iterator(3, 3, Matrix3::iter(&i_w).copied());
            m += jv.transpose() * &jv * mass + jw.transpose() * i_w * &jw;
        }
        m
    };
    let g_vec = DVector::from_column_slice(&[0.0, 0.0, 9.81]);
    let mut gravity = DVector::zeros(n);
    for (mass, jv, _, _) in jacobians(q) {
        gravity += jv.transpose() * &g_vec * mass;
    }
    let qd_v = DVector::from_column_slice(qd);
    let h = 1e-6;
    let shifted =
        |dir: &DVector<f64>, s: f64| -> Vec<f64> { q.iter().zip(dir.iter()).map(|(a, d)| a + s * d).collect() };
    let m_dot = (mass_matrix(&shifted(&qd_v, h)) - mass_matrix(&shifted(&qd_v, -h))) / (2.0 * h);
    let mut half_grad = DVector::zeros(n);
    for k in 0..n {
        let e = DVector::from_fn(n, |i, _| if i == k { 1.0 } else { 0.0 });
        let plus = (qd_v.transpose() * mass_matrix(&shifted(&e, h)) * &qd_v)[(0, 0)];
        let minus = (qd_v.transpose() * mass_matrix(&shifted(&e, -h)) * &qd_v)[(0, 0)];
        half_grad[k] = 0.5 * (plus - minus) / (2.0 * h);
    }
    let tau = mass_matrix(q) * DVector::from_column_slice(qdd) + m_dot * &qd_v - half_grad + gravity;
    tau.iter().copied().collect()
}

#[test]
fn newton_euler_matches_lagrange_within_1_percent() {
    let model = parol6();
    let mut id = InverseDynamics::new(&model);
    let mut rng = rand::rngs::StdRng::seed_from_u64(3);
    for _ in 0..100 {
        let q: Vec<f64> = model.limits.iter().map(|l| rng.random_range(l.min..=l.max)).collect();
        let qd: Vec<f64> = (0..6).map(|_| rng.random_range(-2.0..2.0)).collect();
        let qdd: Vec<f64> = (0..6).map(|_| rng.random_range(-10.0..10.0)).collect();
        let rnea = id.compute(&model, &q, &qd, &qdd).expect("valid").total_nm;
        let lag = lagrange_torques(&model, &q, &qd, &qdd);
        let scale = lag.iter().map(|t| t.abs()).fold(0.0, f64::max);
        for j in 0..6 {
            assert!(
                (rnea[j] - lag[j]).abs() <= 0.01 * scale.max(1e-3),
                "J{}: {} vs {} at {q:?}",
                j + 1,
                rnea[j],
                lag[j]
            );
        }
    }
}

#[test]
fn gravity_torques_of_a_single_known_case() {
    // Only J2 and J3 carry gravity at standby with the arm up; J1's axis is vertical.
    let model = parol6();
    let mut id = InverseDynamics::new(&model);
    let t = id.compute(&model, &standby_rad(), &[0.0; 6], &[0.0; 6]).expect("valid");
    assert!(t.gravity_nm[0].abs() < 1e-9, "J1 gravity torque {}", t.gravity_nm[0]);
    assert_eq!(t.total_nm, t.gravity_nm);
    assert!(t.inertial_coriolis_nm.iter().all(|v| v.abs() < 1e-12));
    // the mass of the whole arm: a pure vertical acceleration of the base is not possible here,
    // but scaling gravity scales the gravity torques linearly
    let mut half = vec![0.0; 6];
    id.compute_scaled_into(&model, &standby_rad(), &[0.0; 6], &[0.0; 6], 0.5, &mut half);
    for (h, g) in half.iter().zip(&t.gravity_nm) {
        assert!((2.0 * h - g).abs() < 1e-12);
    }
    assert!(id.compute(&model, &[0.0; 5], &[0.0; 6], &[0.0; 6]).is_err());
    assert!(id.compute(&model, &[f64::NAN; 6], &[0.0; 6], &[0.0; 6]).is_err());
}

/// Forward dynamics in rapier: the inverse-dynamics torques of an acceleration, applied with
/// the motors off, produce that acceleration (the multibody and the RNEA agree).
#[test]
fn rapier_forward_dynamics_agrees_with_newton_euler() {
    let model = parol6();
    let guard = CollisionGuard::new(&model);
    let mut id = InverseDynamics::new(&model);
    let mut p = Physics::build(&model, 1e-3).expect("builds");
    let mut rng = rand::rngs::StdRng::seed_from_u64(5);
    for _ in 0..20 {
        let q0 = random_free_config(&model, &guard, &mut rng, 0.2);
        let qdd: Vec<f64> = (0..6).map(|_| rng.random_range(-5.0..5.0)).collect();
        let mut tau = vec![0.0; 6];
        id.compute_into(&model, &q0, &[0.0; 6], &qdd, &mut tau);
        p.teleport(&q0);
        p.set_motors_enabled(false);
        p.set_joint_torques(&tau);
        p.step();
        let (mut q, mut qd) = (vec![0.0; 6], vec![0.0; 6]);
        p.read_state(&mut q, &mut qd);
        let measured: Vec<f64> = qd.iter().map(|v| v / 1e-3).collect();
        // compare in torque space: the torques that the measured acceleration needs
        let mut tau_measured = vec![0.0; 6];
        id.compute_into(&model, &q0, &[0.0; 6], &measured, &mut tau_measured);
        let scale = tau.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for j in 0..6 {
            assert!(
                (tau_measured[j] - tau[j]).abs() <= 0.01 * scale,
                "J{}: {} vs {} N·m (qdd {:?} vs {qdd:?})",
                j + 1,
                tau_measured[j],
                tau[j],
                measured
            );
        }
        // and the heavy proximal joints reach the commanded acceleration itself within 1 %
        let acc_scale = qdd.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for j in 0..3 {
            assert!((measured[j] - qdd[j]).abs() <= 0.01 * acc_scale, "J{}: {} vs {}", j + 1, measured[j], qdd[j]);
        }
        p.set_motors_enabled(true);
    }
}

#[test]
fn applied_torques_move_the_arm_and_gravity_compensation_holds_it() {
    let mut s = sim(SimMode::Dynamic);
    let q0 = vec![0.5, -1.2, 2.8, 0.2, 0.3, 1.0];
    s.apply(SimCommand::Teleport(q0.clone())).expect("free");
    let mut id = InverseDynamics::new(s.model());
    let hold = id.compute(s.model(), &q0, &[0.0; 6], &[0.0; 6]).expect("valid").total_nm;
    s.apply(SimCommand::ApplyJointTorques(hold.clone())).expect("dynamic mode");
    run_s(&mut s, 0.05);
    assert!(max_abs_diff(s.q(), &q0) < 2e-3, "gravity compensation drifts: {:?}", s.q());
    assert_eq!(s.snapshot().torques_nm, hold);
    // an extra 0.05 N·m on J1 (vertical axis, no gravity) spins it up
    let mut push = hold.clone();
    push[0] += 0.05;
    s.apply(SimCommand::ApplyJointTorques(push)).expect("dynamic mode");
    run_s(&mut s, 0.2);
    assert!(s.qd()[0] > 0.05, "J1 speed {}", s.qd()[0]);
    assert!(s.q()[0] > q0[0] + 0.005);
    // a move planned now starts where the arm is, not where the motors last were
    let here = s.q().to_vec();
    s.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: q0.clone(),
        speed_fraction: 0.5,
        profile: ProfileKind::Trapezoidal,
    }))
    .expect("move");
    s.step();
    assert!(max_abs_diff(s.q(), &here) < 0.01, "jumped from {here:?} to {:?}", s.q());
    // a position command takes the motors back
    s.apply(SimCommand::Motion(MotionCommand::Stop)).expect("stop");
    let here = s.q().to_vec();
    run_s(&mut s, 0.5);
    assert!(max_abs_diff(s.q(), &here) < 0.05);
    assert!(s.qd().iter().all(|v| v.abs() < 1e-2), "{:?}", s.qd());
}

#[test]
fn snapshot_torques_equal_the_inverse_dynamics_when_holding() {
    for mode in [SimMode::Kinematic, SimMode::Dynamic] {
        let mut s = sim(mode);
        run_s(&mut s, 0.5);
        let mut id = InverseDynamics::new(s.model());
        let g = id.compute(s.model(), &standby_rad(), &[0.0; 6], &[0.0; 6]).expect("valid").gravity_nm;
        let snap = s.snapshot();
        let scale = g.iter().map(|v| v.abs()).fold(0.0, f64::max);
        assert!(max_abs_diff(&snap.torques_nm, &g) <= 0.01 * scale, "{mode:?}: {:?} vs {g:?}", snap.torques_nm);
    }
}

#[test]
fn stepping_is_deterministic() {
    let run = || {
        let mut s = sim(SimMode::Dynamic);
        s.apply(SimCommand::Motion(MotionCommand::MoveJoints {
            goal_rad: vec![1.0, -1.2, 2.8, 0.3, -0.4, 2.0],
            speed_fraction: 1.0,
            profile: ProfileKind::JerkLimited,
        }))
        .expect("move");
        run_s(&mut s, 0.4);
        s.snapshot()
    };
    let (a, b) = (run(), run());
    assert_eq!(a.q, b.q);
    assert_eq!(a.qd, b.qd);
    assert_eq!(a.seq, 400);
    assert!((a.sim_time_s - 0.4).abs() < 1e-12);
}

#[test]
fn inertials_merge_links_on_the_same_frame() {
    let model = parol6();
    let b = body_inertials(&model);
    let total: f64 = b.iter().flatten().map(|i| i.mass_kg).sum();
    let urdf: f64 = model.links.iter().filter_map(|l| l.inertial.as_ref()).map(|i| i.mass_kg).sum();
    assert!((total - urdf).abs() < 1e-12);
}

fn j1_push(torque_nm: f64, duration_s: f64) -> TorqueRun {
    let mut joints = vec![TorqueProfile::default(); 6];
    joints[0] = TorqueProfile::Step { before_nm: torque_nm, after_nm: -torque_nm, at_s: duration_s / 2.0 };
    TorqueRun { joints, duration_s, gravity_compensation: true, hold_others: false }
}

#[test]
fn a_torque_run_moves_the_arm_then_the_motors_hold_it() {
    let mut s = sim(SimMode::Dynamic);
    let q0 = vec![0.5, -1.2, 2.8, 0.2, 0.3, 1.0];
    s.apply(SimCommand::Teleport(q0.clone())).expect("free");
    s.apply(SimCommand::RunJointTorques(j1_push(0.05, 0.4))).expect("dynamic mode");
    assert!(s.is_moving());
    run_s(&mut s, 0.2);
    assert!(s.qd()[0] > 0.02, "J1 accelerates under +0.05 N·m: {}", s.qd()[0]);
    // the heavy joints held by gravity compensation alone (the wrist swings with J1)
    assert!(max_abs_diff(&s.q()[1..3], &q0[1..3]) < 5e-3, "{:?}", s.q());
    run_s(&mut s, 0.25);
    // the run is over: motors on, holding where the arm is
    assert!(!s.is_moving());
    assert!(s.q()[0] > q0[0] + 0.002, "J1 moved: {} → {}", q0[0], s.q()[0]);
    let here = s.q().to_vec();
    run_s(&mut s, 0.5);
    assert!(max_abs_diff(s.q(), &here) < 0.02, "{here:?} → {:?}", s.q());
}

#[test]
fn stop_ends_a_torque_run_and_bad_runs_are_refused() {
    let mut s = sim(SimMode::Dynamic);
    s.apply(SimCommand::RunJointTorques(j1_push(0.05, 10.0))).expect("dynamic mode");
    run_s(&mut s, 0.1);
    s.apply(SimCommand::Motion(MotionCommand::Stop)).expect("stop");
    assert!(!s.is_moving());
    run_s(&mut s, 0.5);
    assert!(s.qd().iter().all(|v| v.abs() < 1e-2), "{:?}", s.qd());
    let mut bad = j1_push(0.05, 1.0);
    bad.duration_s = f64::NAN;
    assert!(matches!(s.apply(SimCommand::RunJointTorques(bad)), Err(SimError::InvalidCommand(_))));
    let mut k = sim(SimMode::Kinematic);
    assert!(matches!(k.apply(SimCommand::RunJointTorques(j1_push(0.05, 1.0))), Err(SimError::InvalidCommand(_))));
}

#[test]
fn a_torque_run_cannot_drive_a_joint_past_its_limit() {
    let mut s = sim(SimMode::Dynamic);
    let mut joints = vec![TorqueProfile::default(); 6];
    joints[0] = TorqueProfile::Constant { torque_nm: 2.0 };
    s.apply(SimCommand::RunJointTorques(TorqueRun {
        joints,
        duration_s: 3.0,
        gravity_compensation: true,
        hold_others: false,
    }))
    .expect("dynamic mode");
    let max = s.model().limits.iter().next().map(|l| l.max).unwrap_or(0.0);
    for _ in 0..30 {
        run_s(&mut s, 0.1);
        assert!(s.q()[0] <= max + 0.02, "J1 {} past its limit {max}", s.q()[0]);
    }
}

/// Issue 32 major 10: 0.2 N·m on J1 with the other joints free whips them about; with
/// `hold_others` they stay on their motors where they were and only J1 turns.
#[test]
fn a_torque_run_holding_the_other_joints_moves_only_the_driven_one() {
    let q0 = vec![0.5, -1.2, 2.8, 0.2, 0.3, 1.0];
    let mut joints = vec![TorqueProfile::default(); 6];
    joints[0] = TorqueProfile::Constant { torque_nm: 0.2 };
    let mut moved = Vec::new();
    for hold_others in [false, true] {
        let mut s = sim(SimMode::Dynamic);
        s.apply(SimCommand::Teleport(q0.clone())).expect("free");
        let run = TorqueRun { joints: joints.clone(), duration_s: 0.6, gravity_compensation: true, hold_others };
        assert_eq!(run.held_joints(), vec![false, hold_others, hold_others, hold_others, hold_others, hold_others]);
        s.apply(SimCommand::RunJointTorques(run)).expect("dynamic mode");
        run_s(&mut s, 0.5);
        assert!(s.q()[0] > q0[0] + 0.05, "J1 turns under 0.2 N·m (hold {hold_others}): {}", s.q()[0]);
        moved.push(max_abs_diff(&s.q()[1..], &q0[1..]));
    }
    assert!(moved[1] < 0.01, "held joints stay within 0.01 rad: {:.4} rad", moved[1]);
    assert!(moved[0] > 5.0 * moved[1].max(0.002), "free joints swing: {:.4} rad vs held {:.4}", moved[0], moved[1]);
}

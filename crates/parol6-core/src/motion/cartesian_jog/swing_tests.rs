//! The swing bound ([`crate::limits::swing`]) on Cartesian jogs and steps from singular poses.

use super::*;
use crate::limits::swing::{MAX_SWING_DEG_PER_MM, swing_over_bound};
use crate::motion::{MotionCommand, MotionPlanner, home_position};

fn kin() -> JogKinematics {
    JogKinematics { model: Arc::new(RobotModel::parol6()), obstacles: None }
}

fn caps() -> MotionCaps {
    MotionCaps::of(&RobotModel::parol6())
}

/// Every knot interval of `plan` (joints interpolate linearly between knots, so this is every
/// streamed setpoint) keeps within the swing bound.
fn assert_within_bound(plan: &CartesianJogPlan, axis: CartesianAxis, what: &str) {
    for k in 0..plan.s.len() - 1 {
        let ds = plan.s[k + 1] - plan.s[k];
        let (travel_m, rotation_rad) = if axis.is_rotation() { (0.0, ds) } else { (ds, 0.0) };
        if let Some(s) = swing_over_bound(&plan.q[k], &plan.q[k + 1], travel_m, rotation_rad) {
            panic!("{what}: knot {k} at s = {:.4}: {}", plan.s[k], s.message());
        }
    }
}

/// The reproduction: from the standby pose (J5 = 0, the wrist singular), a held world
/// +X jog moved the TCP 1.47 mm while J4 went 0 → −90° and J6 180 → 270°. Now it is refused
/// (or stops) with the reason, and no joint turns more than the bound per mm.
#[test]
fn a_world_x_jog_from_standby_does_not_swing_the_wrist() {
    let q0 = crate::parol6::standby_rad().to_vec();
    for f in [0.05, 0.5, 1.0] {
        match CartesianJogPlan::plan(&kin(), &caps(), &q0, JogFrame::World, CartesianAxis::X, f) {
            Ok(plan) => {
                assert_within_bound(&plan, CartesianAxis::X, "standby +X");
                let travel_mm = plan.travel().abs() * 1000.0;
                for (j, (a, b)) in q0.iter().zip(plan.end_q()).enumerate() {
                    let turn_deg = (b - a).abs().to_degrees();
                    assert!(
                        turn_deg <= MAX_SWING_DEG_PER_MM * travel_mm + 1e-6,
                        "J{} turned {turn_deg:.1}° over {travel_mm:.2} mm",
                        j + 1
                    );
                }
            }
            Err(e) => {
                let e = e.to_string();
                assert!(e.contains("singular wrist") && e.contains("joint move"), "{e}");
            }
        }
    }
    // through the planner, as the window sends it: refused with the reason, nothing moves
    let model = RobotModel::parol6();
    let mut p = MotionPlanner::new(model.limits.clone(), caps(), home_position(&model), &q0).with_kinematics(kin());
    let jog = MotionCommand::JogCartesian { frame: JogFrame::World, axis: CartesianAxis::X, fraction: 0.5 };
    if let Ok(()) = p.apply(&jog, 0.0) {
        let end = p.sample(2.0).q;
        let travel_mm =
            (model.tcp_isometry(&end).translation.vector - model.tcp_isometry(&q0).translation.vector).norm() * 1000.0;
        let j4 = (end[3] - q0[3]).abs().to_degrees();
        assert!(j4 <= MAX_SWING_DEG_PER_MM * travel_mm + 1e-6, "J4 turned {j4:.1}° over {travel_mm:.2} mm");
    }
}

/// A step (a planned straight move) from the standby pose that needs a wrist swing is refused
/// with the reason.
#[test]
fn a_world_x_step_from_standby_is_refused_near_the_singular_wrist() {
    let q0 = crate::parol6::standby_rad().to_vec();
    let e =
        crate::motion::cartesian_step::plan_step(&kin(), &caps(), &q0, JogFrame::World, CartesianAxis::X, 0.005, 0.5)
            .expect_err("a wrist swing");
    assert!(e.to_string().contains("singular wrist"), "{e}");
}

/// The joint value in `range` of joint `j` (others as in `q`) where σ_min is least.
fn most_singular(model: &RobotModel, q: &[f64], j: usize) -> Vec<f64> {
    let Some(l) = model.limits.get(j) else { return q.to_vec() };
    let mut best = (f64::INFINITY, q.to_vec());
    for k in 0..=2000 {
        let mut x = q.to_vec();
        x[j] = l.min + (l.max - l.min) * f64::from(k) / 2000.0;
        let s = model.manipulability(&x).sigma_min;
        if s < best.0 {
            best = (s, x);
        }
    }
    best.1
}

/// From every singular pose type (wrist J5 ≈ 0, elbow stretched or folded, the wrist centre
/// over the base axis) with every jog direction in both frames, no knot interval of a jog and
/// no sample of a step turns a joint beyond the bound: each stops (or is refused) with a reason.
#[test]
fn every_jog_from_a_singular_pose_keeps_the_swing_bound() {
    let model = RobotModel::parol6();
    let standby = crate::parol6::standby_rad().to_vec();
    let mut worked = crate::parol6::standby_rad().to_vec();
    worked[1] += 0.3;
    worked[2] -= 0.4;
    let mut poses: Vec<(String, Vec<f64>)> = vec![("standby (J5 = 0)".into(), standby.clone())];
    for (name, base) in [("standby", &standby), ("worked", &worked)] {
        let mut wrist = base.clone();
        wrist[4] = 0.3f64.to_radians();
        poses.push((format!("{name} wrist J5 = 0.3°"), wrist));
        poses.push((format!("{name} elbow (J3 scan)"), most_singular(&model, base, 2)));
        poses.push((format!("{name} shoulder / overhead (J2 scan)"), most_singular(&model, base, 1)));
    }
    let mut refused = 0;
    let mut runs = 0;
    for (name, q0) in &poses {
        assert!(model.limits.contains(q0), "{name}: {q0:?}");
        for frame in [JogFrame::World, JogFrame::Tool] {
            for axis in CartesianAxis::ALL {
                for f in [-1.0, 1.0] {
                    let what = format!("{name} {frame:?} {}{}", if f > 0.0 { "+" } else { "−" }, axis.label());
                    runs += 1;
                    match CartesianJogPlan::plan(&kin(), &caps(), q0, frame, axis, f) {
                        Ok(plan) => assert_within_bound(&plan, axis, &what),
                        Err(e) => {
                            refused += 1;
                            assert!(!e.to_string().is_empty(), "{what}");
                        }
                    }
                    let d = if axis.is_rotation() { 2f64.to_radians() } else { 0.002 };
                    let step = crate::motion::cartesian_step::plan_step(&kin(), &caps(), q0, frame, axis, f * d, 0.5);
                    if let Ok(traj) = step {
                        for w in traj.samples().windows(2) {
                            let (a, b) = (model.tcp_isometry(&w[0]), model.tcp_isometry(&w[1]));
                            let travel = (b.translation.vector - a.translation.vector).norm();
                            let rot = b.rotation.angle_to(&a.rotation);
                            // the chord of one sample: 1 % slack on the bound for its curvature
                            let s = swing_over_bound(&w[0], &w[1], travel * 1.01, rot * 1.01);
                            assert!(s.is_none(), "{what} step: {}", s.map(|s| s.message()).unwrap_or_default());
                        }
                    }
                }
            }
        }
    }
    assert!(runs == poses.len() * 24 && refused > 0, "{refused} of {runs} refused");
}

use super::*;
use crate::motion::{MotionCommand, MotionPlanner, PlannerMode, home_position};
use proptest::prelude::*;

fn kin() -> JogKinematics {
    JogKinematics { model: Arc::new(RobotModel::parol6()), obstacles: None }
}

/// A pose away from the standby wrist singularity (J5 = 34°).
fn start_q() -> Vec<f64> {
    let mut q = crate::parol6::standby_rad().to_vec();
    q[1] += 0.2;
    q[2] -= 0.3;
    q[4] = 0.6;
    q
}

fn planner(q0: &[f64]) -> MotionPlanner {
    let model = RobotModel::parol6();
    MotionPlanner::new(model.limits.clone(), MotionCaps::of(&model), home_position(&model), q0).with_kinematics(kin())
}

fn caps() -> MotionCaps {
    MotionCaps::of(&RobotModel::parol6())
}

fn tcp_at(plan: &CartesianJogPlan, t: f64) -> Isometry3<f64> {
    let mut sp = Setpoint::at_rest(&[]);
    plan.sample_into(t, &mut sp);
    kin().model.tcp_isometry(&sp.q)
}

/// The commanded TCP of a world +X jog stays within 0.05 mm of the line and keeps its
/// orientation within 0.05°, at every 1 ms sample to the stop.
#[test]
fn a_linear_jog_is_straight_within_tolerance() {
    for (frame, axis, f) in [
        (JogFrame::World, CartesianAxis::X, 0.5),
        (JogFrame::Tool, CartesianAxis::Y, -1.0),
        (JogFrame::World, CartesianAxis::Z, 0.3),
    ] {
        let q0 = start_q();
        let plan = CartesianJogPlan::plan(&kin(), &caps(), &q0, frame, axis, f).expect("plans");
        let a = kin().model.tcp_isometry(&q0);
        let dir = (displaced_pose(&a, frame, axis, 1.0).translation.vector - a.translation.vector).normalize();
        let mut t = 0.0;
        let mut worst: f64 = 0.0;
        while t <= plan.duration_s() + 0.001 {
            let p = tcp_at(&plan, t);
            let d = p.translation.vector - a.translation.vector;
            worst = worst.max((d - dir * d.dot(&dir)).norm());
            assert!(p.rotation.angle_to(&a.rotation).to_degrees() < 0.05, "orientation at t = {t:.3}");
            // on the line at the signed travel the plan reports
            let (s, _) = plan.progress(t);
            assert!((d.dot(&dir) - s).abs() < 0.05e-3, "travel at t = {t:.3}");
            t += 0.001;
        }
        assert!(worst < 0.05e-3, "{frame:?} {axis:?}: {:.4} mm off the line", worst * 1e3);
        assert!(
            plan.travel().abs() > 0.02,
            "{frame:?} {axis:?} moved only {:.1} mm ({})",
            plan.travel() * 1e3,
            plan.stop_reason()
        );
    }
}

/// A rotation jog turns about the TCP: the TCP point stays put.
#[test]
fn a_rotation_jog_turns_about_the_tcp() {
    let q0 = start_q();
    let plan = CartesianJogPlan::plan(&kin(), &caps(), &q0, JogFrame::World, CartesianAxis::Ry, 0.4).expect("plans");
    let a = kin().model.tcp_isometry(&q0);
    let mut t = 0.0;
    while t <= plan.duration_s() {
        let p = tcp_at(&plan, t);
        assert!((p.translation.vector - a.translation.vector).norm() < 0.05e-3, "TCP moved at t = {t:.3}");
        let (s, _) = plan.progress(t);
        let ideal = displaced_pose(&a, JogFrame::World, CartesianAxis::Ry, s);
        assert!(p.rotation.angle_to(&ideal.rotation).to_degrees() < 0.05);
        t += 0.002;
    }
    assert!(plan.travel() > 5f64.to_radians());
}

/// Tool +Z follows the start TCP's own Z axis; world +Z follows the base Z axis.
#[test]
fn tool_and_world_frames_move_along_their_own_axes() {
    let q0 = start_q();
    let a = kin().model.tcp_isometry(&q0);
    let tool_z = a.rotation * Vector3::z();
    assert!(tool_z.dot(&Vector3::z()).abs() < 0.9, "the test pose must tilt the tool");
    for (frame, want) in [(JogFrame::Tool, tool_z), (JogFrame::World, Vector3::z())] {
        let plan = CartesianJogPlan::plan(&kin(), &caps(), &q0, frame, CartesianAxis::Z, 0.5).expect("plans");
        let t = plan.duration_s().min(0.3);
        let d = tcp_at(&plan, t).translation.vector - a.translation.vector;
        assert!(d.norm() > 1e-3, "{frame:?} moved {:.3} mm", d.norm() * 1e3);
        assert!(d.normalize().dot(&want) > 0.999_999, "{frame:?} moved along {d:?}");
    }
}

/// A tool Rz jog turns J6 toward its limit: the plan stops at the limit, inside it, named.
#[test]
fn a_jog_stops_at_the_limit_not_beyond() {
    let q0 = start_q();
    for f in [1.0, -1.0] {
        let plan = CartesianJogPlan::plan(&kin(), &caps(), &q0, JogFrame::Tool, CartesianAxis::Rz, f).expect("plans");
        let JogStop::Limit { joint, upper, .. } = plan.stop_reason().clone() else {
            panic!("stopped for {}", plan.stop_reason())
        };
        assert_eq!(joint, 5);
        assert_eq!(upper, f > 0.0);
        let lim = &kin().model.limits;
        let end = plan.end_q().to_vec();
        assert!(lim.contains(&end));
        let bound = if upper { lim.get(5).expect("J6").max } else { lim.get(5).expect("J6").min };
        assert!(
            (end[5] - bound).abs() < 0.01f64.to_radians(),
            "stopped {:.4}° short",
            (end[5] - bound).abs().to_degrees()
        );
        // the setpoint comes to rest at the computed stop and stays there, within the limits
        let mut sp = Setpoint::at_rest(&[]);
        let mut t = 0.0;
        while t < plan.duration_s() + 0.5 {
            plan.sample_into(t, &mut sp);
            assert!(lim.contains(&sp.q), "t = {t:.3}: {:?}", sp.q);
            t += 0.001;
        }
        assert_eq!(sp.q, end);
        assert!(sp.qd.iter().all(|v| *v == 0.0));
        // it decelerates into the stop: the last interval's speed is small
        let (_, v_end) = plan.progress(plan.duration_s() - 0.001);
        assert!(v_end.abs() < 0.01, "still {v_end} rad/s 1 ms before the stop");
    }
}

/// From a limit a jog further out is refused, naming why; the other way is allowed.
#[test]
fn a_jog_from_the_stop_further_out_is_refused() {
    let q0 = start_q();
    let plan = CartesianJogPlan::plan(&kin(), &caps(), &q0, JogFrame::Tool, CartesianAxis::Rz, 1.0).expect("plans");
    let at_limit = plan.end_q().to_vec();
    let e = CartesianJogPlan::plan(&kin(), &caps(), &at_limit, JogFrame::Tool, CartesianAxis::Rz, 1.0)
        .expect_err("further out");
    assert!(e.to_string().contains("cannot jog +Rz"), "{e}");
    CartesianJogPlan::plan(&kin(), &caps(), &at_limit, JogFrame::Tool, CartesianAxis::Rz, -1.0).expect("back inside");
}

/// Near the wrist singularity the same jog runs slower, and stops before σ_min gets tiny.
#[test]
fn the_jog_slows_down_near_the_wrist_singularity() {
    let mut near = start_q();
    near[4] = 3f64.to_radians();
    let far = start_q();
    let speed = |q: &[f64]| {
        let plan = CartesianJogPlan::plan(&kin(), &caps(), q, JogFrame::Tool, CartesianAxis::Rz, 0.5).expect("plans");
        plan.progress(0.5).1.abs()
    };
    let (v_near, v_far) = (speed(&near), speed(&far));
    assert!((v_far - jog_speed(CartesianAxis::Rz, 0.5)).abs() < 1e-9, "away from it the full jog speed: {v_far}");
    assert!(v_near < 0.7 * v_far, "near {v_near} rad/s, away {v_far} rad/s");
    // jogging toward J5 = 0 stops before σ_min falls below the threshold
    let mut toward = start_q();
    toward[4] = 8f64.to_radians();
    let model = &kin().model;
    for axis in [CartesianAxis::Rx, CartesianAxis::Ry] {
        for f in [1.0, -1.0] {
            let Ok(plan) = CartesianJogPlan::plan(&kin(), &caps(), &toward, JogFrame::Tool, axis, f) else { continue };
            assert!(model.manipulability(plan.end_q()).sigma_min >= STOP_SIGMA * 0.999);
        }
    }
}

/// From the standby pose (J5 = 0, exactly singular) a jog that needs no wrist swing moves out
/// of the singularity; world +X, which would swing J4 and J6 round (issue 32), is refused
/// saying why.
#[test]
fn a_jog_leaves_the_standby_singularity() {
    let q0 = crate::parol6::standby_rad().to_vec();
    let mut moving = Vec::new();
    for frame in [JogFrame::World, JogFrame::Tool] {
        for axis in CartesianAxis::ALL {
            for f in [-0.5, 0.5] {
                if let Ok(plan) = CartesianJogPlan::plan(&kin(), &caps(), &q0, frame, axis, f)
                    && plan.travel().abs() > 0.01
                {
                    moving.push(format!("{frame:?} {f} {}", axis.label()));
                }
            }
        }
    }
    assert!(!moving.is_empty(), "no jog leaves the standby singularity");
    let e = CartesianJogPlan::plan(&kin(), &caps(), &q0, JogFrame::World, CartesianAxis::X, 0.5).expect_err("a swing");
    assert!(e.to_string().contains("singular wrist"), "{e}");
}

/// Through the planner: hold-to-run with the dead-man, refresh, release.
#[test]
fn the_dead_man_stops_an_unrefreshed_jog() {
    let q0 = start_q();
    let mut p = planner(&q0);
    let jog = MotionCommand::JogCartesian { frame: JogFrame::World, axis: CartesianAxis::X, fraction: 0.5 };
    p.apply(&jog, 0.0).expect("starts");
    assert_eq!(p.mode(), PlannerMode::CartesianJog);
    let at_deadman = p.setpoint_at(crate::motion::DEADMAN_S).q;
    let later = p.sample(1.0);
    assert_eq!(later.q, at_deadman, "no refresh: it stopped at the dead-man time");
    assert!(later.qd.iter().all(|v| *v == 0.0));
    assert_eq!(p.mode(), PlannerMode::Hold);
    assert!(at_deadman != q0);
    // refreshed every 0.1 s it keeps going
    let mut p = planner(&q0);
    for k in 0..10 {
        p.apply(&jog, 0.1 * f64::from(k)).expect("refresh");
    }
    let x = |q: &[f64]| kin().model.tcp_isometry(q).translation.x;
    let moving = p.sample(1.0);
    assert!(x(&moving.q) - x(&at_deadman) > 0.05, "kept going");
    assert!(moving.qd.iter().any(|v| *v != 0.0));
    p.apply(&MotionCommand::JogRelease, 1.0).expect("release");
    assert_eq!(p.sample(2.0).q, moving.q);
}

#[test]
fn without_kinematics_cartesian_commands_are_refused() {
    let model = RobotModel::parol6();
    let q0 = start_q();
    let mut p = MotionPlanner::new(model.limits.clone(), MotionCaps::of(&model), q0.clone(), &q0);
    let e = p.apply(&MotionCommand::JogCartesian { frame: JogFrame::Tool, axis: CartesianAxis::Z, fraction: 0.2 }, 0.0);
    assert!(e.expect_err("refused").to_string().contains("kinematic model"));
}

/// Step mode moves exactly the typed increment, in either frame, linear or angular.
#[test]
fn a_step_moves_exactly_the_increment() {
    let q0 = start_q();
    let model = &kin().model;
    let a = model.tcp_isometry(&q0);
    for (frame, axis, d) in [
        (JogFrame::World, CartesianAxis::X, 0.0025),
        (JogFrame::Tool, CartesianAxis::Y, -0.0125),
        (JogFrame::World, CartesianAxis::Rz, 10f64.to_radians()),
        (JogFrame::Tool, CartesianAxis::Rx, -2.5f64.to_radians()),
    ] {
        let mut p = planner(&q0);
        p.apply(&MotionCommand::CartesianStep { frame, axis, distance: d, speed_fraction: 0.5 }, 0.0).expect("plans");
        let end = p.sample(30.0).q;
        let b = model.tcp_isometry(&end);
        let want = displaced_pose(&a, frame, axis, d);
        let (dp, dr) = ik::pose_error(&b, &want);
        assert!(dp < 1e-9 && dr < 1e-9, "{frame:?} {axis:?} {d}: off by {dp:e} m / {dr:e} rad");
    }
    let mut p = planner(&q0);
    let e = p.apply(
        &MotionCommand::CartesianStep {
            frame: JogFrame::World,
            axis: CartesianAxis::X,
            distance: 0.0,
            speed_fraction: 0.5,
        },
        0.0,
    );
    assert!(e.is_err());
}

/// A step that would cross a limit is refused before anything moves.
#[test]
fn a_step_past_a_limit_is_refused() {
    let q0 = start_q();
    let mut p = planner(&q0);
    let big = MotionCommand::CartesianStep {
        frame: JogFrame::World,
        axis: CartesianAxis::Z,
        distance: 0.3,
        speed_fraction: 1.0,
    };
    assert!(p.apply(&big, 0.0).is_err());
    assert_eq!(p.mode(), PlannerMode::Hold);
}

fn axis_strategy() -> impl Strategy<Value = CartesianAxis> {
    (0usize..6).prop_map(|k| CartesianAxis::ALL[k])
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// From random poses, along random axes and frames at random speeds, no setpoint leaves the
    /// joint limits or exceeds a joint speed cap.
    #[test]
    fn no_setpoint_leaves_the_limits_or_exceeds_the_caps(
        u in prop::array::uniform6(0.02f64..0.98),
        axis in axis_strategy(),
        tool in any::<bool>(),
        f in prop_oneof![-1.0f64..-0.05, 0.05f64..1.0],
    ) {
        let model = &kin().model;
        let q0: Vec<f64> = model.limits.iter().zip(u).map(|(l, u)| l.min + (l.max - l.min) * u).collect();
        let frame = if tool { JogFrame::Tool } else { JogFrame::World };
        let caps = caps();
        let Ok(plan) = CartesianJogPlan::plan(&kin(), &caps, &q0, frame, axis, f) else { return Ok(()) };
        let mut sp = Setpoint::at_rest(&[]);
        let n = 3000;
        let knot_times = plan.t.clone();
        let times = (0..=n).map(|k| plan.duration_s() * f64::from(k) / f64::from(n)).chain(knot_times);
        for t in times {
            plan.sample_into(t, &mut sp);
            prop_assert!(model.limits.contains(&sp.q), "t = {t}: {:?}", sp.q);
            for (j, (v, cap)) in sp.qd.iter().zip(&caps.speed_rad_s).enumerate() {
                prop_assert!(v.abs() <= cap * (1.0 + 1e-9), "J{} at {v} rad/s (cap {cap}) at t = {t}", j + 1);
            }
        }
        // and between samples: the speed within an interval peaks at one of its ends
        for k in 0..plan.s.len() - 1 {
            let ds = plan.s[k + 1] - plan.s[k];
            let v = plan.v[k].max(plan.v[k + 1]);
            for ((a, b), cap) in plan.q[k].iter().zip(&plan.q[k + 1]).zip(&caps.speed_rad_s) {
                prop_assert!((b - a).abs() / ds * v <= cap * (1.0 + 1e-9));
            }
        }
    }
}

/// With the simulation's collision guard, a jog toward a contact stops before it: no sample
/// of the plan touches, and the reason names the pair.
#[test]
fn a_jog_stops_before_a_collision() {
    let guard = crate::collision::CollisionGuard::new(&kin().model);
    let model = kin().model;
    let with_guard = JogKinematics { model: Arc::clone(&model), obstacles: Some(Arc::new(guard.clone())) };
    let mut found = 0;
    for (j2, j3) in [(0.2, -0.3), (0.5, -0.6), (0.7, 0.2), (0.9, -0.2)] {
        let mut q0 = start_q();
        q0[1] += j2 - 0.2;
        q0[2] += j3 + 0.3;
        if !model.limits.contains(&q0) || guard.check(&model, &q0).is_some() {
            continue;
        }
        for axis in [CartesianAxis::Z, CartesianAxis::X, CartesianAxis::Y] {
            for f in [-1.0, 1.0] {
                let Ok(plan) = CartesianJogPlan::plan(&with_guard, &caps(), &q0, JogFrame::World, axis, f) else {
                    continue;
                };
                if !matches!(plan.stop_reason(), JogStop::Collision { .. }) {
                    continue;
                }
                found += 1;
                let mut sp = Setpoint::at_rest(&[]);
                let mut t = 0.0;
                while t <= plan.duration_s() + 0.01 {
                    plan.sample_into(t, &mut sp);
                    assert!(guard.check(&model, &sp.q).is_none(), "contact at t = {t:.3} ({})", plan.stop_reason());
                    t += 0.005;
                }
                // without the guard the same jog goes further
                let free = CartesianJogPlan::plan(&kin(), &caps(), &q0, JogFrame::World, axis, f).expect("plans");
                assert!(free.travel().abs() > plan.travel().abs());
            }
        }
    }
    assert!(found > 0, "no test jog ran into a collision");
}

/// Issue 32 minor: "a Shift+letter orientation jog moved the TCP position by 0.11 mm". An
/// orientation jog turns about the TCP: at every 1 ms setpoint to the stop, from a general pose
/// and from standby, about each axis of both frames, either way, the commanded TCP stays within
/// 0.01 mm of where it started; the joints rounded to whole motor steps (what the board and the
/// simulated drives hold) within 0.03 mm.
#[test]
fn an_orientation_jog_keeps_the_tcp_position() {
    use crate::motion::stepper::steps_of_rad;
    let model = kin().model.clone();
    let whole_steps = |q: &[f64]| -> Vec<f64> {
        q.iter().enumerate().map(|(j, v)| steps_of_rad(j, *v) * crate::parol6::rad_per_step(j)).collect()
    };
    let mut planned = 0;
    for q0 in [start_q(), crate::parol6::standby_rad().to_vec()] {
        let a = model.tcp_isometry(&q0).translation.vector;
        for frame in [JogFrame::World, JogFrame::Tool] {
            for axis in [CartesianAxis::Rx, CartesianAxis::Ry, CartesianAxis::Rz] {
                for f in [-1.0, 0.3] {
                    // at standby (J5 = 0) some axes are refused: nothing moves
                    let Ok(plan) = CartesianJogPlan::plan(&kin(), &caps(), &q0, frame, axis, f) else { continue };
                    planned += 1;
                    let (mut worst, mut worst_steps) = (0.0f64, 0.0f64);
                    let mut sp = Setpoint::at_rest(&[]);
                    let mut t = 0.0;
                    while t <= plan.duration_s() + 0.001 {
                        plan.sample_into(t, &mut sp);
                        worst = worst.max((model.tcp_isometry(&sp.q).translation.vector - a).norm());
                        let rounded = model.tcp_isometry(&whole_steps(&sp.q)).translation.vector;
                        worst_steps = worst_steps.max((rounded - a).norm());
                        t += 0.001;
                    }
                    let what = format!("{frame:?} {axis:?} {f} from {q0:?}");
                    assert!(worst < 0.01e-3, "{what}: the TCP moved {:.4} mm", worst * 1e3);
                    assert!(worst_steps < 0.03e-3, "{what}: in whole steps {:.4} mm", worst_steps * 1e3);
                    assert!(plan.travel().abs() > 0.1, "{what}: it turned {:.3} rad", plan.travel());
                }
            }
        }
    }
    assert!(planned >= 18, "{planned} jogs planned");
}

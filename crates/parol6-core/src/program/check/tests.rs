//! Pre-flight of whole programs: configurations (issue 28), stretched moves as warnings, the
//! planned-step list.

use super::*;
use crate::ik::Branch;
use crate::program::Step;

fn standby() -> Vec<f64> {
    crate::parol6::standby_rad().to_vec()
}

fn pose(position_mm: [f64; 3], rpy_deg: [f64; 3]) -> PoseMm {
    PoseMm { position_mm, rpy_deg }
}

fn program(steps: Vec<Step>) -> Program {
    let mut p = Program::from_steps("test", steps);
    for (i, s) in p.steps.iter_mut().enumerate() {
        s.line = 20 + i;
    }
    p
}

fn move_pose(p: PoseMm, config: Option<Branch>) -> Step {
    Step::MovePose { pose: p, config, speed_fraction: None, duration_s: None }
}

/// Regression (issue 28): `G28` then `G0 X220 Y0 Z200 A0 B0 C0` was refused ("front/down/no-flip
/// branch needs J4 = 180.00°"): joint moves to a pose were pinned to the start's branch label.
/// Tool-down poses at the front, the sides and the back are reached from standby and after a
/// home step, each in the configuration nearest the start.
#[test]
fn tool_down_poses_are_reached_from_standby_and_after_home() {
    let model = RobotModel::parol6();
    for p in [
        [220.0, 0.0, 200.0],
        [0.0, 220.0, 200.0],
        [0.0, -220.0, 200.0],
        [-100.0, 200.0, 150.0],
        [-100.0, -200.0, 150.0],
    ] {
        for rpy in [[0.0, 0.0, 0.0]] {
            for steps in [
                vec![move_pose(pose(p, rpy), None)],
                vec![Step::Home { speed_fraction: None }, move_pose(pose(p, rpy), None)],
            ] {
                let r = check_program(&model, &program(steps), &standby(), CheckOptions::default());
                assert!(r.ok, "{p:?} {rpy:?}: {:?}", r.issues);
                let last = r.plan.last().expect("a planned step");
                assert_eq!(last.kind, "move_pose");
                let reached = last.end_tcp.position_mm.iter().zip(&p).all(|(a, b)| (a - b).abs() < 1e-4);
                assert!(reached, "{:?}", last.end_tcp);
                assert!(last.config.as_deref().is_some_and(|c| c.split('/').count() == 3), "{last:?}");
            }
        }
    }
}

/// A step that names its configuration is reached in it, or refused naming the others.
#[test]
fn a_named_configuration_is_used_or_refused() {
    let model = RobotModel::parol6();
    let goal = [0.4, -1.2, 3.4, 0.6, -0.8, 2.5];
    let target = PoseMm::from_isometry(&model.tcp_isometry(&goal));
    let config = crate::ik::configuration_of(&model, &goal).expect("closed form");
    let r = check_program(&model, &program(vec![move_pose(target, Some(config))]), &standby(), CheckOptions::default());
    assert!(r.ok, "{:?}", r.issues);
    assert_eq!(r.plan[0].config.as_deref(), Some(config.label().as_str()));
    // the same pose in the opposite shoulder is out of J1's range
    let mut other = config;
    other.shoulder = match config.shoulder {
        crate::ik::ShoulderBranch::Front => crate::ik::ShoulderBranch::Back,
        crate::ik::ShoulderBranch::Back => crate::ik::ShoulderBranch::Front,
    };
    let r = check_program(&model, &program(vec![move_pose(target, Some(other))]), &standby(), CheckOptions::default());
    assert!(!r.ok);
    let e = &r.issues[0];
    assert_eq!((e.line, e.move_index), (20, 0));
    assert!(e.message.contains(&format!("not reachable in configuration {}", other.label())), "{}", e.message);
    assert!(e.message.contains(&config.label()), "{}", e.message);
}

/// A line whose end is reachable only in another wrist configuration is refused, saying which
/// and what to insert.
#[test]
fn a_line_into_another_configuration_says_what_to_insert() {
    let model = RobotModel::parol6();
    let start = [1.5, -1.3, 2.9, 0.0, 0.8, 3.0];
    // J5 < 0 with J4 = 0.2: the no-flip twin needs J4 = 0.2 − π, beyond ±105°
    let goal = [1.5, -1.3, 2.9, 0.2, -0.8, 3.0];
    let target = PoseMm::from_isometry(&model.tcp_isometry(&goal));
    let line = Step::MoveL { pose: target, speed_mm_s: None, blend_mm: None, duration_s: None };
    let r = check_program(&model, &program(vec![line]), &start, CheckOptions::default());
    assert!(!r.ok);
    let e = &r.issues[0];
    assert_eq!(e.line, 20);
    // the line crosses the wrist border (J5 0.8 → −0.8): it is refused either where the wrist
    // would swing beyond the swing bound near J5 = 0 (issue 32) or, past it, in the other
    // configuration; both say to use a joint move
    if e.message.contains("near a singular") {
        assert!(e.message.contains("use a joint move"), "{}", e.message);
    } else {
        assert!(e.message.contains("not reachable in configuration front/"), "{}", e.message);
        assert!(e.message.contains("insert a joint move to the pose"), "{}", e.message);
    }
    // the joint move the message asks for, then the line, pass
    let r = check_program(&model, &program(vec![move_pose(target, None)]), &start, CheckOptions::default());
    assert!(r.ok, "{:?}", r.issues);
}

/// Stretched moves are warnings naming the line; the plan lists every step with both ends.
#[test]
fn stretched_moves_are_warnings_and_every_step_is_planned() {
    let model = RobotModel::parol6();
    // off the wrist singularity, so the only warnings are the stretched move's
    let mut q0 = standby();
    q0[4] = 0.6;
    let mut far: Vec<f64> = q0.iter().map(|v| v.to_degrees()).collect();
    far[0] -= 40.0;
    let steps = vec![
        Step::MoveJoints { joints_deg: far, speed_fraction: None, duration_s: Some(0.2) },
        Step::Dwell { seconds: 0.5 },
        Step::Home { speed_fraction: None },
    ];
    let r = check_program(&model, &program(steps), &q0, CheckOptions::default());
    assert!(r.ok, "a stretched move is not an error: {:?}", r.issues);
    // (the home step ends on the standby wrist singularity: a warning of its own)
    let w: Vec<_> = r.issues.iter().filter(|i| i.severity == Severity::Warning && i.move_index == 0).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!((w[0].line, w[0].move_index), (20, 0));
    assert!(w[0].message.contains("0.2 s is too short"), "{}", w[0].message);
    assert_eq!(r.plan.len(), 3);
    assert_eq!(r.plan.iter().map(|p| p.kind).collect::<Vec<_>>(), ["move_joints", "dwell", "home"]);
    assert_eq!(r.plan[1].start_tcp, r.plan[1].end_tcp);
    assert_eq!(r.plan[0].end_tcp, r.plan[1].start_tcp);
    assert!((r.plan[1].duration_s - 0.5).abs() < 1e-12);
    assert!((r.plan.iter().map(|p| p.duration_s).sum::<f64>() - r.duration_s).abs() < 1e-9);
    let json = serde_json::to_value(&r).expect("serialises");
    assert_eq!(json["plan"][0]["line"], 20);
    assert!(json["plan"][0]["end_tcp"]["position_mm"].is_array());
}

/// Regression (issue 28): the commander's `MoveJoint` to standby then `MoveCart` to the pose it
/// shows there is a no-op in the commander; here the line of no length at the standby wrist
/// singularity was a pre-flight error ("error on a TCP path"). A move whose joints hold still is
/// checked as the joint move it is: a warning.
#[test]
fn a_line_of_no_length_at_a_singular_pose_is_a_warning() {
    let model = RobotModel::parol6();
    let q0 = standby();
    let here = PoseMm::from_isometry(&model.tcp_isometry(&q0));
    let line = Step::MoveL { pose: here, speed_mm_s: None, blend_mm: None, duration_s: Some(3.6) };
    let r = check_program(&model, &program(vec![line]), &q0, CheckOptions::default());
    assert!(r.ok, "{:?}", r.issues);
    assert!(r.issues.iter().all(|i| i.severity == Severity::Warning));
    // a real line away from the singular pose is still an error there
    let mut away = here;
    away.position_mm[2] -= 20.0;
    let line = Step::MoveL { pose: away, speed_mm_s: None, blend_mm: None, duration_s: None };
    let r = check_program(&model, &program(vec![line]), &q0, CheckOptions::default());
    assert!(!r.ok, "{:?}", r.issues);
}

/// Issue 32: a linear step that would swing a joint beyond the swing bound (from standby, J5 =
/// 0, a world +X line needs J4 and J6 to turn 90°) is a pre-flight error naming its step and
/// line and saying what to do.
#[test]
fn a_linear_step_past_the_swing_bound_is_a_pre_flight_error() {
    let model = RobotModel::parol6();
    let start = model.tcp_isometry(&standby());
    let mut goal = start;
    goal.translation.vector.x += 0.005;
    let p = PoseMm::from_isometry(&goal);
    let steps = vec![Step::MoveL { pose: p, speed_mm_s: None, blend_mm: None, duration_s: None }];
    let r = check_program(&model, &program(steps), &standby(), CheckOptions::default());
    assert!(!r.ok, "{:?}", r.issues);
    let e = r.issues.iter().find(|i| i.severity == Severity::Error).expect("an error");
    assert_eq!((e.line, e.move_index), (20, 0), "{e:?}");
    assert!(e.message.contains("singular wrist") && e.message.contains("joint move"), "{}", e.message);
}

/// Issue 32: joint torque over the motor limits is a pre-flight warning naming the step and
/// line (here a PAROL6 with links four times as heavy holding a pose); the bare PAROL6 has none.
#[test]
fn joint_torque_over_the_motor_limits_is_a_pre_flight_warning() {
    let mut heavy = RobotModel::parol6();
    for l in &mut heavy.links {
        if let Some(i) = &mut l.inertial {
            i.mass_kg *= 4.0;
            i.inertia_kg_m2 *= 4.0;
        }
    }
    let mut q = standby();
    q[1] += 0.6;
    let steps = vec![
        Step::MoveJoints {
            joints_deg: q.iter().map(|v| v.to_degrees()).collect(),
            speed_fraction: None,
            duration_s: None,
        },
        Step::Dwell { seconds: 0.5 },
    ];
    let r = check_program(&heavy, &program(steps.clone()), &standby(), CheckOptions::default());
    assert!(r.ok, "warnings only: {:?}", r.issues);
    assert!(r.torque_warnings > 0, "{:?}", r.issues);
    let w = r.issues.iter().find(|i| i.message.contains("exceeds its motor limit")).expect("a torque warning");
    assert_eq!(w.severity, Severity::Warning);
    assert!(w.line >= 20 && w.message.contains("J2 torque"), "{w:?}");
    let bare = check_program(&RobotModel::parol6(), &program(steps), &standby(), CheckOptions::default());
    assert_eq!(bare.torque_warnings, 0, "{:?}", bare.issues);
}

/// Issue 33 item 1: the torque pass runs on its own thread beside the compile, fed step by
/// step through a bounded channel; its warnings are those of the pass over the whole compiled
/// program after it, to the bit.
#[test]
fn the_torque_pass_beside_the_compile_finds_the_same_warnings_as_after_it() {
    let mut heavy = RobotModel::parol6();
    for l in &mut heavy.links {
        if let Some(i) = &mut l.inertial {
            i.mass_kg *= 4.0;
            i.inertia_kg_m2 *= 4.0;
        }
    }
    let start = standby();
    let deg = |q: &[f64]| q.iter().map(|v| v.to_degrees()).collect::<Vec<_>>();
    let mut steps = Vec::new();
    for k in 0..300 {
        let mut q = start.clone();
        q[1] += if k % 2 == 0 { 0.6 } else { 0.1 };
        q[0] += 0.01 * (k % 7) as f64;
        steps.push(Step::MoveJoints { joints_deg: deg(&q), speed_fraction: None, duration_s: None });
        if k % 3 == 0 {
            steps.push(Step::Dwell { seconds: 0.05 });
        }
    }
    let r = check_program(&heavy, &program(steps), &start, CheckOptions::default());
    assert!(r.ok, "warnings only: {:?}", r.issues.iter().find(|i| i.severity == Severity::Error));
    let (warnings, dropped) = crate::program::torques::torque_warnings(&heavy, &r.compiled, &start);
    assert!(warnings.len() > 100, "many stretches over the limit: {}", warnings.len());
    let after = torque_issues(&warnings, dropped);
    let beside: Vec<_> = r.issues.iter().filter(|i| i.message.contains("torque")).cloned().collect();
    assert_eq!(beside.len(), r.torque_warnings);
    assert_eq!(beside, after);
}

/// A G-code raster like `parol6 bench program-load`'s: exact stops (`G61`) or corners rounded
/// with `G64 P…`, a joint move to its start first.
fn raster_gcode(lines: usize, blend_mm: Option<f64>) -> Program {
    let mut text = String::from("G21 G90\nG0 X0 Y220 Z250 A90 B0 C90\n");
    text.push_str(&blend_mm.map_or("G61\n".to_string(), |b| format!("G64 P{b}\n")));
    text.push_str("G1 F6000\nG4 P100\n");
    let (mut x, mut y, mut dir) = (0.0f64, 220.0f64, 1.0f64);
    for _ in 0..lines {
        x += dir * 0.2;
        if x.abs() >= 2.0 {
            dir = -dir;
            y += 0.5;
        }
        text.push_str(&format!("G1 X{x:.3} Y{y:.3}\n"));
    }
    text.push_str("G4 P100\nG0 X100 Y200 Z200\nM30\n");
    let home = tcp_of(&RobotModel::parol6(), &standby());
    let opts = crate::program::gcode::GcodeImportOptions::new(home, home);
    crate::program::gcode::parse_gcode(&text, &opts).expect("the raster parses")
}

/// The plan's configurations reuse what the compile worked out (a Cartesian step's
/// `start_config`, the start of a step that does not move) instead of solving them again: each
/// is the configuration solved afresh from the step's end joints, as before, on the built-in
/// programs and G-code rasters.
#[test]
fn the_plan_configurations_equal_those_solved_afresh() {
    let model = RobotModel::parol6();
    let mut programs = crate::program::builtin::programs(&model);
    programs.push(raster_gcode(60, None));
    programs.push(raster_gcode(60, Some(0.1)));
    let mut reused = 0;
    for p in &programs {
        let checked = check_program(&model, p, &standby(), CheckOptions::default());
        assert!(!checked.compiled.is_empty(), "{}: {:?}", p.name, checked.report.issues);
        assert_eq!(checked.compiled.len(), checked.report.plan.len());
        let mut from = standby();
        for (c, planned) in checked.compiled.iter().zip(&checked.report.plan) {
            if let Some(rule) = c.start_config {
                assert_eq!(rule, ConfigRule::of_start(&model, &from), "{}: step {}", p.name, c.steps.start);
                reused += 1;
            }
            let afresh = ConfigRule::of_start(&model, &c.end_q).to_string();
            assert_eq!(planned.config.as_deref(), Some(afresh.as_str()), "{}: step {}", p.name, c.steps.start);
            from.clone_from(&c.end_q);
        }
    }
    assert!(reused >= 60, "the Cartesian steps carry their start configuration ({reused})");
}

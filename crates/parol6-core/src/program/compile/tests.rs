use super::*;
use crate::program::{PoseMm, SourcedStep};

fn start() -> (RobotModel, Vec<f64>) {
    let model = RobotModel::parol6();
    let mut q = crate::parol6::standby_rad().to_vec();
    q[1] += 0.2;
    q[2] -= 0.3;
    q[4] = 0.6;
    (model, q)
}

fn offset(model: &RobotModel, q: &[f64], d_mm: [f64; 3]) -> PoseMm {
    let mut p = PoseMm::from_isometry(&model.tcp_isometry(q));
    for (v, d) in p.position_mm.iter_mut().zip(d_mm) {
        *v += d;
    }
    p
}

fn program(steps: Vec<Step>) -> Program {
    let mut p = Program::from_steps("test", steps);
    for (i, s) in p.steps.iter_mut().enumerate() {
        s.line = 10 + i;
    }
    p
}

#[test]
fn every_step_type_compiles_and_each_motion_starts_where_the_last_ended() {
    let (model, q0) = start();
    let here = offset(&model, &q0, [0.0; 3]);
    let a = offset(&model, &q0, [30.0, 0.0, 0.0]);
    let b = offset(&model, &q0, [30.0, 30.0, 0.0]);
    let c = offset(&model, &q0, [0.0, 30.0, 0.0]);
    let steps = vec![
        Step::MoveL { pose: a, speed_mm_s: Some(80.0), blend_mm: None, duration_s: None },
        Step::MoveC {
            via_mm: [here.position_mm[0] + 30.0 + 15.0, here.position_mm[1] + 15.0, here.position_mm[2]],
            pose: b,
            speed_mm_s: None,
        },
        Step::MoveL { pose: c, speed_mm_s: None, blend_mm: Some(5.0), duration_s: None },
        Step::MoveL { pose: here, speed_mm_s: None, blend_mm: Some(5.0), duration_s: None },
        Step::MoveL { pose: a, speed_mm_s: None, blend_mm: None, duration_s: None },
        Step::MoveCircle {
            center_mm: [here.position_mm[0] + 15.0, here.position_mm[1], here.position_mm[2]],
            normal: [0.0, 0.0, 1.0],
            angle_deg: 360.0,
            speed_mm_s: Some(50.0),
        },
        Step::Spline { waypoints: vec![b, c, here], speed_mm_s: None },
        Step::MoveJoints {
            joints_deg: q0.iter().map(|v| v.to_degrees() + 5.0).collect(),
            speed_fraction: Some(0.8),
            duration_s: None,
        },
        Step::MovePose { pose: here, config: None, speed_fraction: None, duration_s: None },
        Step::Dwell { seconds: 0.25 },
        Step::Gripper { action: GripperAction::Close, position: None, speed: None, current_ma: None },
        Step::SetOutput { output: 2, on: true },
        Step::WaitInput { input: 1, on: true, timeout_s: Some(2.0) },
        Step::Home { speed_fraction: None },
    ];
    let n = steps.len();
    let p = program(steps);
    let compiled = compile(&model, &p, &q0, CompileOptions::RUN).expect("compiles");
    // the blended chain (steps 2, 3, 4) is one compiled step
    assert_eq!(compiled.len(), n - 2);
    assert_eq!(compiled[2].steps, 2..5);
    assert_eq!(compiled[2].line, 12);
    let mut q = q0.clone();
    for c in &compiled {
        if let StepAction::Motion(t) = &c.action {
            assert_eq!(t.samples()[0], q, "step {:?} starts where the last ended", c.steps);
            assert_eq!(t.dt_s(), 0.001);
            q = t.goal().to_vec();
        }
        assert_eq!(c.end_q, q);
    }
    // the line ends on its pose; the circle comes back to where it started
    let end_a = model.tcp_isometry(&compiled[0].end_q);
    assert!((end_a.translation.vector - a.isometry().translation.vector).norm() < 1e-6);
    let circle_start = model.tcp_isometry(&compiled[2].end_q);
    let circle_end = model.tcp_isometry(&compiled[3].end_q);
    assert!((circle_start.translation.vector - circle_end.translation.vector).norm() < 1e-6);
    assert_eq!(compiled[8].action, StepAction::Io(IoCommand::Gripper { position: 255, speed: 128, current_ma: 500 }));
    assert_eq!(compiled[10].action, StepAction::WaitInput { input: 1, on: true, timeout_s: 2.0 });
    assert_eq!(compiled.last().map(|c| c.end_q.clone()), Some(home_position(&model)));
    assert!((compiled[7].duration_s() - 0.25).abs() < 1e-12);
}

#[test]
fn an_unreachable_line_names_the_step_line_time_and_tcp() {
    let (model, q0) = start();
    let far = offset(&model, &q0, [0.0, 0.0, 900.0]);
    let p = program(vec![
        Step::Dwell { seconds: 0.1 },
        Step::MoveL { pose: far, speed_mm_s: None, blend_mm: None, duration_s: None },
    ]);
    let e = compile(&model, &p, &q0, CompileOptions::PREFLIGHT).expect_err("out of reach");
    assert_eq!((e.index, e.line, e.kind), (1, 11, "move_l"));
    assert!(e.t_s.is_some() && e.tcp_mm.is_some(), "{e:?}");
    assert!(e.to_string().starts_with("step 2 (line 11, move_l): TCP ("), "{e}");
}

#[test]
fn bad_arguments_name_the_step() {
    let (model, q0) = start();
    let cases = vec![
        (Step::MoveJoints { joints_deg: vec![0.0; 5], speed_fraction: None, duration_s: None }, "5 values"),
        (
            Step::MoveJoints {
                joints_deg: vec![0.0, -90.0, 180.0, 0.0, 0.0, 400.0],
                speed_fraction: None,
                duration_s: None,
            },
            "joint 6",
        ),
        (
            Step::MoveJoints {
                joints_deg: vec![90.0, -90.0, 180.0, 0.0, 0.0, 180.0],
                speed_fraction: Some(1.5),
                duration_s: None,
            },
            "speed_fraction",
        ),
        (
            Step::MoveL {
                pose: offset(&model, &q0, [1.0, 0.0, 0.0]),
                speed_mm_s: Some(1.0),
                blend_mm: None,
                duration_s: None,
            },
            "200",
        ),
        (Step::Dwell { seconds: -1.0 }, "seconds"),
        (Step::Dwell { seconds: f64::NAN }, "seconds"),
        (Step::SetOutput { output: 3, on: true }, "output 3"),
        (Step::WaitInput { input: 0, on: true, timeout_s: None }, "input 0"),
        (Step::Gripper { action: GripperAction::Position, position: None, speed: None, current_ma: None }, "position"),
        (Step::Gripper { action: GripperAction::Open, position: None, speed: None, current_ma: Some(9000) }, "current"),
        (
            Step::MoveCircle { center_mm: [0.0, 0.0, 0.0], normal: [0.0, 0.0, 0.0], angle_deg: 90.0, speed_mm_s: None },
            "normal",
        ),
    ];
    for (step, needle) in cases {
        let p = program(vec![step.clone()]);
        let e = compile(&model, &p, &q0, CompileOptions::PREFLIGHT).expect_err("refused");
        assert_eq!((e.index, e.line), (0, 10));
        assert!(e.to_string().contains(needle), "{step:?}: {e}");
    }
}

#[test]
fn the_speed_override_slows_every_move() {
    let (model, q0) = start();
    let p = program(vec![
        Step::MoveL { pose: offset(&model, &q0, [40.0, 0.0, 0.0]), speed_mm_s: None, blend_mm: None, duration_s: None },
        Step::Home { speed_fraction: None },
    ]);
    let full = compile(&model, &p, &q0, CompileOptions::PREFLIGHT).expect("compiles");
    let half = compile(&model, &p, &q0, CompileOptions { speed_override: 0.5, ..CompileOptions::PREFLIGHT })
        .expect("compiles");
    for (a, b) in full.iter().zip(&half) {
        assert!(b.duration_s() > a.duration_s() * 1.3, "{} vs {}", b.duration_s(), a.duration_s());
        assert_eq!(a.end_q.len(), b.end_q.len());
    }
    let _ = SourcedStep { step: Step::Dwell { seconds: 0.0 }, line: 0 };
}

/// Regression (found by the `program_file` fuzzer): a spline whose orientation turns through a
/// near-singular wrist was stretched by the joint caps to days of motion and planned until the
/// fuzzer ran out of memory. A move is now bounded and refused with the reason.
#[test]
fn a_spline_near_a_singularity_ran_out_of_memory() {
    let text = include_str!("../../../../../fuzz/regressions/program_file/spline_stretched_out_of_memory.json");
    let p = crate::program::json::parse(text).expect("valid file");
    let model = RobotModel::parol6();
    let e = compile(&model, &p, &home_position(&model), CompileOptions::PREFLIGHT).expect_err("refused");
    assert_eq!(e.index, 1);
    // refused at the first sample past the swing bound (issue 32), or by the move's length
    assert!(e.message.contains("near a singular") || e.message.contains("would take"), "{e}");
}

/// Regression (found by the `program_file` fuzzer): an arc through a via point 1e110 mm away
/// overflowed the circle's radius and panicked in `f64::clamp` with NaN. Positions are now
/// bounded and a degenerate arc is refused.
#[test]
fn an_arc_through_a_far_point_panicked() {
    let text = include_str!("../../../../../fuzz/regressions/program_file/arc_through_a_far_point_panicked.json");
    let p = crate::program::json::parse(text).expect("valid file");
    let model = RobotModel::parol6();
    let e = compile(&model, &p, &home_position(&model), CompileOptions::PREFLIGHT).expect_err("refused");
    assert_eq!(e.index, 2);
    assert!(e.message.contains("via_mm"), "{e}");
    // the path itself refuses the overflowing circle (without the position bound)
    let from = model.tcp_isometry(&home_position(&model));
    let mut to = from;
    to.translation.vector.x += 0.005;
    to.translation.vector.z += 0.29;
    let via = nalgebra::Point3::new(-0.01, 2.8e110, 0.292);
    assert!(matches!(TcpPath::arc_through(&from, &via, &to), Err(crate::motion::path::PathError::DegenerateArc)));
}

fn motion(c: &CompiledStep) -> &SampledTrajectory {
    match &c.action {
        StepAction::Motion(t) => t,
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_move_with_a_duration_takes_that_long_and_ends_on_its_goal() {
    let (model, q0) = start();
    let goal_deg: Vec<f64> = q0.iter().map(|v| v.to_degrees() + 10.0).collect();
    let a = offset(&model, &q0, [40.0, 0.0, 0.0]);
    let p = program(vec![
        Step::MoveJoints { joints_deg: goal_deg.clone(), speed_fraction: Some(0.1), duration_s: Some(2.5) },
        Step::MoveL { pose: a, speed_mm_s: Some(10.0), blend_mm: None, duration_s: Some(1.5) },
        Step::MovePose {
            pose: offset(&model, &q0, [0.0; 3]),
            config: None,
            speed_fraction: None,
            duration_s: Some(3.0),
        },
    ]);
    let c = compile(&model, &p, &q0, CompileOptions::RUN).expect("compiles");
    for (step, want_s) in c.iter().zip([2.5, 1.5, 3.0]) {
        assert!((step.duration_s() - want_s).abs() <= 0.001, "{}: {}", step.kind, step.duration_s());
    }
    assert!(motion(&c[0]).goal().iter().zip(&goal_deg).all(|(q, d)| (q - d.to_radians()).abs() < 1e-9));
    let end = model.tcp_isometry(motion(&c[1]).goal());
    assert!((end.translation.vector - a.isometry().translation.vector).norm() < 1e-6);
    // the speed override stretches it
    let slow = compile(&model, &p, &q0, CompileOptions { speed_override: 0.5, ..CompileOptions::RUN }).expect("ok");
    assert!((slow[0].duration_s() - 5.0).abs() <= 0.001);
}

/// Official programs ask for times (commander `t=`) and feeds (G-code `F`) the caps cannot
/// meet: the move is stretched to the fastest the caps allow, with a warning naming both times
/// (issue 28; it was an error), and never runs faster than the caps.
#[test]
fn a_duration_or_speed_the_caps_cannot_make_is_stretched_with_a_warning() {
    let (model, q0) = start();
    let far: Vec<f64> = q0.iter().map(|v| v.to_degrees() + 10.0).collect();
    let fastest =
        program(vec![Step::MoveJoints { joints_deg: far.clone(), speed_fraction: Some(1.0), duration_s: None }]);
    let fastest_s = compile(&model, &fastest, &q0, CompileOptions::PREFLIGHT).expect("ok")[0].duration_s();
    let p = program(vec![
        Step::Dwell { seconds: 0.1 },
        Step::MoveJoints { joints_deg: far, speed_fraction: None, duration_s: Some(0.05) },
    ]);
    let c = compile(&model, &p, &q0, CompileOptions::PREFLIGHT).expect("stretched, not refused");
    assert!(c[0].warnings.is_empty());
    assert_eq!(c[1].warnings.len(), 1, "{:?}", c[1].warnings);
    let w = &c[1].warnings[0];
    assert!(w.starts_with("0.05 s is too short for the joint speed caps: stretched to"), "{w}");
    // the fastest move, to within one 10 ms sample (the compiled one ends on a sample)
    let stretched_s: f64 = w["0.05 s is too short for the joint speed caps: stretched to ".len()..]
        .split(' ')
        .next()
        .and_then(|v| v.parse().ok())
        .expect("a time");
    assert!((stretched_s - fastest_s).abs() <= 0.011, "{w} ({fastest_s})");
    assert!((c[1].duration_s() - fastest_s).abs() <= 0.011, "{} vs {fastest_s}", c[1].duration_s());
    let line = Step::MoveL {
        pose: offset(&model, &q0, [80.0, 0.0, 0.0]),
        speed_mm_s: None,
        blend_mm: None,
        duration_s: Some(0.1),
    };
    let c = compile(&model, &program(vec![line]), &q0, CompileOptions::PREFLIGHT).expect("stretched");
    assert!(c[0].warnings[0].contains("too short for the TCP and joint caps: stretched to"), "{:?}", c[0].warnings);
    // 80 mm at no more than 200 mm/s
    assert!(c[0].duration_s() >= 0.4, "{}", c[0].duration_s());
    let fast = Step::MoveL {
        pose: offset(&model, &q0, [80.0, 0.0, 0.0]),
        speed_mm_s: Some(500.0),
        blend_mm: None,
        duration_s: None,
    };
    let c = compile(&model, &program(vec![fast]), &q0, CompileOptions::PREFLIGHT).expect("capped");
    assert!(c[0].warnings[0].contains("500 mm/s is above the PAROL6's 200 mm/s"), "{:?}", c[0].warnings);
    assert!(c[0].duration_s() >= 0.4, "{}", c[0].duration_s());
    let bad = Step::MoveJoints {
        joints_deg: q0.iter().map(|v| v.to_degrees()).collect(),
        speed_fraction: None,
        duration_s: Some(-1.0),
    };
    let e = compile(&model, &program(vec![bad]), &q0, CompileOptions::PREFLIGHT).expect_err("negative");
    assert!(e.message.contains("duration_s must lie in"), "{e}");
}

#[test]
fn a_relative_tool_move_ends_offset_along_the_tool_axes() {
    let (model, q0) = start();
    let p = program(vec![Step::MoveRelTool {
        offset_mm: [0.0, 0.0, 20.0],
        rotation_deg: [0.0, 0.0, 30.0],
        speed_mm_s: Some(50.0),
        duration_s: None,
    }]);
    let c = compile(&model, &p, &q0, CompileOptions::PREFLIGHT).expect("compiles");
    let from = model.tcp_isometry(&q0);
    let to = model.tcp_isometry(motion(&c[0]).goal());
    let rel = from.inverse() * to;
    assert!((rel.translation.vector - Vector3::new(0.0, 0.0, 0.02)).norm() < 1e-6, "{rel:?}");
    let want = nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 30f64.to_radians());
    assert!(rel.rotation.angle_to(&want) < 1e-6);
}

#[test]
fn a_time_function_is_followed_in_time_from_where_the_tcp_is() {
    use crate::program::timefn::TimePiece;
    let (model, q0) = start();
    let here = offset(&model, &q0, [0.0; 3]).position_mm;
    let [x, y, z] = here.map(|v| format!("{v}"));
    let pieces = vec![
        TimePiece::position(1.0, &format!("{x} + 20*t"), &y, &z),
        TimePiece::position(1.0, &format!("{x} + 20"), &format!("{y} + 20*t"), &z),
        TimePiece::position(1.0, &format!("{x} + 20 - 20*t"), &format!("{y} + 20 - 20*t"), &z),
    ];
    let p = program(vec![Step::TimeFunction { sample_rate_hz: 50.0, pieces: pieces.clone() }]);
    let c = compile(&model, &p, &q0, CompileOptions::RUN).expect("compiles");
    let traj = motion(&c[0]);
    assert!((traj.duration_s() - 3.0).abs() < 1e-9);
    // at t = 1.5 s the TCP is halfway up the second side
    let at = model.tcp_isometry(&traj.sample(1.5).q).translation.vector * 1000.0;
    assert!((at - Vector3::new(here[0] + 20.0, here[1] + 10.0, here[2])).norm() < 0.05, "{at:?}");
    let end = model.tcp_isometry(traj.goal()).translation.vector * 1000.0;
    assert!((end - Vector3::from(here)).norm() < 0.05);

    // a function that starts elsewhere is refused (no approach move)
    let mut away = pieces.clone();
    away[0].z_mm = format!("{z} + 5");
    away[1].z_mm = away[0].z_mm.clone();
    away[2].z_mm = away[0].z_mm.clone();
    let e = compile(
        &model,
        &program(vec![Step::TimeFunction { sample_rate_hz: 50.0, pieces: away }]),
        &q0,
        CompileOptions::PREFLIGHT,
    )
    .expect_err("elsewhere");
    assert!(e.message.contains("5.00 mm and 0.00° from where the TCP is"), "{e}");
    // too fast for the PAROL6
    let mut fast = pieces;
    fast[0].x_mm = format!("{x} + 20*t^16");
    let e = compile(
        &model,
        &program(vec![Step::TimeFunction { sample_rate_hz: 50.0, pieces: fast }]),
        &q0,
        CompileOptions::PREFLIGHT,
    )
    .expect_err("fast");
    assert!(e.message.contains("mm/s at t ="), "{e}");
}

#[test]
fn a_problem_in_a_blended_chain_names_the_step_where_it_is_not_the_chains_first() {
    // trial6: Draw's fifth line (in a chain of blended lines from step 3) given a roll the wrist
    // cannot make was reported as "line 15, step 3", and the step list marked step 3 red
    let (model, q0) = start();
    let far = offset(&model, &q0, [0.0, 0.0, 900.0]);
    let blend = Some(5.0);
    let p = program(vec![
        Step::Dwell { seconds: 0.1 },
        Step::MoveL {
            pose: offset(&model, &q0, [20.0, 0.0, 0.0]),
            speed_mm_s: None,
            blend_mm: blend,
            duration_s: None,
        },
        Step::MoveL {
            pose: offset(&model, &q0, [20.0, 20.0, 0.0]),
            speed_mm_s: None,
            blend_mm: blend,
            duration_s: None,
        },
        Step::MoveL { pose: far, speed_mm_s: None, blend_mm: None, duration_s: None },
    ]);
    let e = compile(&model, &p, &q0, CompileOptions::PREFLIGHT).expect_err("out of reach");
    assert_eq!((e.index, e.line, e.kind), (3, 13, "move_l"), "{e}");
    assert!(e.tcp_mm.is_some(), "{e:?}");
    assert!(e.message.contains("steps 2–4 are one blended path; t counts from step 2"), "{e}");
}

#[test]
fn the_built_in_draw_with_a_roll_edited_in_its_last_blended_line_names_that_line() {
    let model = RobotModel::parol6();
    let q0 = crate::parol6::standby_rad().to_vec();
    let mut draw =
        crate::program::builtin::programs(&model).into_iter().find(|p| p.name == "Draw").expect("built-in Draw");
    // the line after the chain 3–5 (index 5, step 6): the roll typed as -0.5 rad in the step editor
    let Step::MoveL { pose, .. } = &mut draw.steps[5].step else { panic!("step 6 of Draw is a line") };
    pose.position_mm = [25.4, 250.5, 292.1];
    pose.rpy_deg[0] = (-0.5f64).to_degrees();
    let e = compile(&model, &draw, &q0, CompileOptions::PREFLIGHT).expect_err("the wrist cannot make that roll");
    assert_eq!(e.index, 5, "{e}");
    assert_eq!(e.line, draw.steps[5].line, "{e}");
}

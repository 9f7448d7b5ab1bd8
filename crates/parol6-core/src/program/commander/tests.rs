use super::*;
use crate::program::PoseMm;
use nalgebra::Isometry3;

const EXAMPLE: &str = "Begin()\nDelay(1)\nMoveJoint(90,-80,170,0,60,180,t=2)\n\nMoveJoint(90, -85, 175, 0, 55, 180, v=50, a=30, poly)\n\
MovePose(30,263.6,292.1,90,-50,0)\nMoveCart(30,263.6,272.1,90,-50,0,t=1.5,trap,speed)\nMoveCartRelTRF(0,0,-10,0,0,15)\n\
Output(1,HIGH)\nGripper(120,60,400)\nDummy()\r\nMoveJoint(90,-80,170,0,60,180,v=70)\nLoop()\n";

#[test]
fn every_command_maps_to_its_step_with_the_file_line() {
    let p = parse_commander(EXAMPLE).expect("valid");
    assert!(p.looping);
    assert_eq!(p.speed.joint_fraction, COMMANDER_JOINT_FRACTION);
    let lines: Vec<usize> = p.steps.iter().map(|s| s.line).collect();
    assert_eq!(lines, vec![2, 3, 5, 6, 7, 8, 9, 10, 11, 12]);
    let steps: Vec<&Step> = p.steps.iter().map(|s| &s.step).collect();
    assert_eq!(*steps[0], Step::Dwell { seconds: 1.0 });
    assert_eq!(
        *steps[1],
        Step::MoveJoints {
            joints_deg: vec![90.0, -80.0, 170.0, 0.0, 60.0, 180.0],
            speed_fraction: None,
            duration_s: Some(2.0)
        }
    );
    assert!(
        matches!(steps[2], Step::MoveJoints { speed_fraction: Some(f), duration_s: None, .. } if (*f - 0.5).abs() < 1e-12)
    );
    match steps[3] {
        Step::MovePose { pose, config: None, speed_fraction: None, duration_s: None } => {
            // the commander's frame at (30, 263.6, 292.1), official (90, -50, 0) = Rx(0)·Ry(-50)·Rz(90):
            // our flange (bare-flange import) is that pose times inv(inv(L6)·DH6)
            let want = crate::angles::rotation_from_abc_deg([90.0, -50.0, 0.0]);
            let commander = crate::frames::commander_from_flange(&pose.isometry());
            assert!((commander.rotation.to_rotation_matrix().matrix() - want.matrix()).norm() < 1e-12);
            let p = commander.translation.vector * 1000.0;
            assert!((p - nalgebra::Vector3::new(30.0, 263.6, 292.1)).norm() < 1e-9, "{p}");
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(steps[4], Step::MoveL { duration_s: Some(d), speed_mm_s: None, blend_mm: None, .. } if *d == 1.5));
    match steps[5] {
        Step::MoveRelTool { offset_mm, rotation_deg, speed_mm_s: None, duration_s: Some(d) } => {
            // 10 mm along the commander frame's -z is 10 mm along our +z (Rx(π) between them); its
            // 15° about the commander frame's z is -15° about ours, about a point 52 mm away
            assert_eq!(*d, COMMANDER_CART_DURATION_S);
            assert_eq!(*rotation_deg, [0.0, 0.0, -15.0]);
            let (s, c) = 15f64.to_radians().sin_cos();
            // offset = (0, 0, 10) + o − Rz(−15°)·o, o = (−45.25, 0, −25.8) the commander frame's origin
            let want = [-45.25 + 45.25 * c, -45.25 * s, 10.0];
            for (g, w) in offset_mm.iter().zip(want) {
                assert!((g - w).abs() < 1e-9, "{offset_mm:?} vs {want:?}");
            }
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(*steps[6], Step::SetOutput { output: 1, on: true });
    assert_eq!(
        *steps[7],
        Step::Gripper { action: GripperAction::Position, position: Some(120), speed: Some(60), current_ma: Some(400) }
    );
    assert_eq!(*steps[8], Step::Dwell { seconds: 0.0 });
    // a lone v= is the commander's default, as it runs it
    assert!(matches!(steps[9], Step::MoveJoints { speed_fraction: None, duration_s: None, .. }));
}

#[test]
fn errors_name_the_line_and_command() {
    let wrap = |body: &str| format!("Begin()\n{body}\nEnd()\n");
    let cases = [
        (wrap("MoveJoint(1,2,3)"), "line 2, MoveJoint: needs 6 numbers, got 3"),
        (wrap("MoveJoint(1,2,3,4,5,x)"), "line 2, MoveJoint: \"x\" is not a number (written like -12.5)"),
        (wrap("MoveJoint(1,2,3,4,5,6,v=150,a=10)"), "line 2, MoveJoint: v= is a percentage 0–100, got 150"),
        (wrap("MoveCart(1,2,3,4,5,6,t=0)"), "line 2, MoveCart: t= is a time above 0 s, got 0"),
        (
            wrap("MoveCart(1,2,3,4,5,6,trap,poly)"),
            "line 2, MoveCart: option \"poly\" repeats or conflicts with an earlier one",
        ),
        (
            wrap("MovePose(1,2,3,4,5,6,fast)"),
            "line 2, MovePose: \"fast\" is not a move option (v=%, a=%, t=s, trap or poly, speed) or comes before a number",
        ),
        (wrap("Delay(0.01)"), "line 2, Delay: the delay must be longer than 0.01 s, got 0.01"),
        (wrap("Output(3,HIGH)"), "line 2, Output: the output is 1 or 2, got \"3\""),
        (wrap("Output(1,ON)"), "line 2, Output: the level is HIGH or LOW, got \"ON\""),
        (wrap("Gripper(300,10,500)"), "line 2, Gripper: the position is a whole number 0–255, got 300"),
        (
            wrap("Gripper_cal()"),
            "line 2, Gripper_cal: gripper calibration has no program step here; calibrate from the gripper panel",
        ),
        (wrap("Home()"), "line 2, Home: the commander lists this command but does not implement it"),
        (wrap("Jump(1)"), "line 2, Jump: is not a PAROL commander command"),
        (wrap("Delay 1"), "line 2, Delay: a command is written Name(arguments)"),
        (
            wrap("# pick the part"),
            "line 2, \"# pick the part\": a comment: the commander's program format has no comments; delete the line",
        ),
        (wrap("// x"), "line 2, \"// x\": a comment: the commander's program format has no comments; delete the line"),
        (wrap("Dummy(1)"), "line 2, Dummy: Dummy() takes no arguments"),
        ("Delay(1)\nEnd()\n".into(), "line 1, Delay: the program must start with Begin()"),
        ("Begin()\nDelay(1)\n".into(), "line 2, Delay: the program must end with End() or Loop()"),
        ("Begin()\n".into(), "line 1, Begin: the program must end with End() or Loop()"),
        ("Begin()\nEnd()\nDelay(1)\nEnd()".into(), "line 2, End: End() must be the last command"),
        ("\n \n".into(), "the program is empty: it needs Begin() … End()"),
    ];
    for (text, want) in cases {
        assert_eq!(parse_commander(&text).expect_err(&text).to_string(), want, "{text}");
    }
}

#[test]
fn export_writes_what_has_an_equivalent_and_reads_back_the_same() {
    let p = parse_commander(EXAMPLE).expect("valid");
    let text = program_to_commander(&p).expect("writes");
    assert!(
        text.starts_with(
            "Begin()\nDelay(1)\nMoveJoint(90,-80,170,0,60,180,t=2)\nMoveJoint(90,-85,175,0,55,180,v=50,a=50)\n"
        ),
        "{text}"
    );
    assert!(text.ends_with("Dummy()\nMoveJoint(90,-80,170,0,60,180)\nLoop()\n"), "{text}");
    let back = parse_commander(&text).expect("reads its own output");
    assert_eq!(back.steps.len(), p.steps.len());
    for (a, b) in p.steps.iter().zip(&back.steps) {
        match (&a.step, &b.step) {
            (Step::MovePose { pose: x, .. }, Step::MovePose { pose: y, .. })
            | (Step::MoveL { pose: x, .. }, Step::MoveL { pose: y, .. }) => {
                assert!(x.isometry().rotation.angle_to(&y.isometry().rotation) < 1e-9);
                let d = x.position_mm.iter().zip(y.position_mm).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                assert!(d < 1e-9, "{x:?} vs {y:?}");
            }
            (
                Step::MoveRelTool { offset_mm: oa, rotation_deg: ra, .. },
                Step::MoveRelTool { offset_mm: ob, rotation_deg: rb, .. },
            ) => {
                assert_eq!(ra, rb);
                assert!(oa.iter().zip(ob).all(|(a, b)| (a - b).abs() < 1e-9), "{oa:?} vs {ob:?}");
            }
            (x, y) => assert_eq!(x, y),
        }
    }
    let mut p2 = p.clone();
    p2.steps[4].step = Step::MoveL {
        pose: PoseMm { position_mm: [0.0; 3], rpy_deg: [0.0; 3] },
        speed_mm_s: Some(50.0),
        blend_mm: None,
        duration_s: None,
    };
    assert_eq!(
        program_to_commander(&p2).expect_err("no t").to_string(),
        "step 5 (line 7, move_l): the commander times Cartesian moves only by t= (3.6 s without it); give the step a duration_s"
    );
    p2.steps[4].step = Step::Home { speed_fraction: None };
    assert_eq!(
        program_to_commander(&p2).expect_err("home").to_string(),
        "step 5 (line 7, home): has no PAROL commander equivalent"
    );
}

proptest::proptest! {
    #[test]
    fn parsing_never_panics(text in "[A-Za-z_(),.=0-9 \\n-]{0,200}") {
        let _ = parse_commander(&text);
    }

    #[test]
    fn parsing_any_text_never_panics(body in "\\PC{0,100}") {
        let _ = parse_commander(&format!("Begin()\n{body}\nEnd()"));
    }

    /// Joint moves written out read back to the same steps.
    #[test]
    fn joint_moves_round_trip(
        moves in proptest::collection::vec((proptest::collection::vec(-180_000i32..180_000, 6), 0.01f64..1.0, proptest::option::of(100i32..10_000)), 1..6)
    ) {
        // numbers as the commander writes them (3 decimals) come back exactly
        let milli = |v: i32| f64::from(v) / 1000.0;
        let steps = moves.into_iter().map(|(j, f, d)| Step::MoveJoints {
            joints_deg: j.into_iter().map(milli).collect(),
            speed_fraction: Some(f),
            duration_s: d.map(milli),
        });
        let p = Program::from_steps("p", steps.collect());
        let back = parse_commander(&program_to_commander(&p).expect("writes")).expect("reads");
        for (a, b) in p.steps.iter().zip(&back.steps) {
            match (&a.step, &b.step) {
                (Step::MoveJoints { joints_deg: ja, speed_fraction: fa, duration_s: Some(da) }, Step::MoveJoints { joints_deg: jb, duration_s: Some(db), speed_fraction: fb }) => {
                    proptest::prop_assert_eq!(ja, jb);
                    proptest::prop_assert_eq!(da, db);
                    proptest::prop_assert!(fa.is_some() && fb.is_none());
                }
                (x, y) => {
                    if let (Step::MoveJoints { speed_fraction: Some(fa), .. }, Step::MoveJoints { speed_fraction: Some(fb), .. }) = (x, y) {
                        // v= is written with 3 decimals of a percent
                        proptest::prop_assert!((fa - fb).abs() <= 5e-6 + 1e-12);
                    } else {
                        proptest::prop_assert!(false, "{x:?} vs {y:?}");
                    }
                }
            }
        }
    }
}

/// The tool of [`crate::Tool::ALL`]'s `i`-th entry as [`CommanderOptions`].
fn options_for(i: usize) -> CommanderOptions {
    let tool = crate::Tool::ALL[i % crate::Tool::ALL.len()];
    let [x, y, z] = tool.tcp_offset_m();
    CommanderOptions { tool: Isometry3::translation(x, y, z) }
}

fn milli(v: i32) -> String {
    frame::number_text(f64::from(v) / 1000.0).expect("finite")
}

proptest::proptest! {
    /// Commander text whose numbers have at most 3 decimals (as the commander writes them)
    /// read and written again is the same text, for every tool: poses (angles as the
    /// commander's readout gives them: rx, rz in (−180, 180], ry in [−89.99, 89.99]), tool-frame
    /// moves, joints and times.
    #[test]
    fn commander_numbers_survive_import_then_export(
        lines in proptest::collection::vec(
            (
                0usize..4,
                proptest::array::uniform3(-500_000i32..500_000),
                (-179_999i32..=180_000, -89_990i32..=89_990, -179_999i32..=180_000),
                1i32..10_000,
            ),
            1..8,
        ),
        tool in 0usize..6,
    ) {
        let mut text = String::from("Begin()\n");
        for (kind, p, (a, b, c), t) in lines {
            let six = [p[0], p[1], p[2], a, b, c].map(milli).join(",");
            let name = ["MoveCart", "MovePose", "MoveCartRelTRF", "MoveJoint"][kind];
            text.push_str(&format!("{name}({six},t={})\n", milli(t)));
        }
        text.push_str("End()\n");
        let options = options_for(tool);
        let program = parse_commander_with(&text, &options).expect("reads");
        let back = program_to_commander_with(&program, &options).expect("writes");
        proptest::prop_assert_eq!(back, text);
    }

    /// A program's poses written as commander text and read again are the same poses to the
    /// 3 decimals written (≤ 0.003°, ≤ 0.005 mm: the rounding of three coordinates plus that
    /// of three angles at the lever between the commander's frame and the TCP, up to 0.16 m
    /// with a tool), and writing them again gives the same text.
    #[test]
    fn program_poses_survive_export_then_import(
        poses in proptest::collection::vec(
            (proptest::array::uniform3(-400.0f64..400.0), proptest::array::uniform3(-180.0f64..180.0), 0.05f64..20.0),
            1..6,
        ),
        tool in 0usize..6,
    ) {
        let steps = poses.iter().enumerate().map(|(i, (p, r, t))| {
            let pose = PoseMm { position_mm: *p, rpy_deg: *r };
            match i % 3 {
                0 => Step::MoveL { pose, speed_mm_s: None, blend_mm: None, duration_s: Some(*t) },
                1 => Step::MovePose { pose, config: None, speed_fraction: None, duration_s: Some(*t) },
                _ => Step::MoveRelTool { offset_mm: *p, rotation_deg: *r, speed_mm_s: None, duration_s: Some(*t) },
            }
        });
        let program = Program::from_steps("p", steps.collect());
        let options = options_for(tool);
        let text = program_to_commander_with(&program, &options).expect("writes");
        proptest::prop_assert!(!text.contains("-0,") && !text.contains("-0)"), "{}", text);
        let back = parse_commander_with(&text, &options).expect("reads");
        for (a, b) in program.steps.iter().zip(&back.steps) {
            let (x, y) = match (&a.step, &b.step) {
                (Step::MoveL { pose: x, .. }, Step::MoveL { pose: y, .. })
                | (Step::MovePose { pose: x, .. }, Step::MovePose { pose: y, .. }) => (x.isometry(), y.isometry()),
                (
                    Step::MoveRelTool { offset_mm: ox, rotation_deg: rx, .. },
                    Step::MoveRelTool { offset_mm: oy, rotation_deg: ry, .. },
                ) => (frame::tool_move(*ox, *rx), frame::tool_move(*oy, *ry)),
                (x, y) => return Err(proptest::test_runner::TestCaseError::fail(format!("{x:?} vs {y:?}"))),
            };
            let dp_mm = (x.translation.vector - y.translation.vector).norm() * 1000.0;
            let dr_deg = (x.rotation.to_rotation_matrix().matrix() - y.rotation.to_rotation_matrix().matrix()).norm().to_degrees();
            proptest::prop_assert!(dp_mm <= 0.005 && dr_deg <= 0.003, "{:?} vs {:?}: {} mm {}°", a.step, b.step, dp_mm, dr_deg);
        }
        proptest::prop_assert_eq!(program_to_commander_with(&back, &options).expect("writes again"), text);
    }
}

/// At ry = ±90° only rx − rz (or rx + rz) is defined: export picks one split, and writing what
/// it reads again gives the same text.
#[test]
fn a_pose_at_gimbal_lock_writes_the_same_text_twice() {
    for b in ["90", "-90", "89.9996"] {
        for tool in 0..6 {
            let options = options_for(tool);
            let text = format!(
                "Begin()\nMoveCart(120.5,-80,250,10,{b},20,t=1)\nMovePose(0,262.57,288.75,-35,{b},135)\nEnd()\n"
            );
            let p = parse_commander_with(&text, &options).expect("reads");
            let once = program_to_commander_with(&p, &options).expect("writes");
            let again = parse_commander_with(&once, &options).expect("reads its own text");
            for (x, y) in p.steps.iter().zip(&again.steps) {
                let (Step::MoveL { pose: x, .. } | Step::MovePose { pose: x, .. }) = &x.step else { panic!() };
                let (Step::MoveL { pose: y, .. } | Step::MovePose { pose: y, .. }) = &y.step else { panic!() };
                let turn = (x.isometry().rotation.to_rotation_matrix().matrix()
                    - y.isometry().rotation.to_rotation_matrix().matrix())
                .norm();
                assert!(turn < 1e-4, "{b} {tool}: {once}");
            }
            assert_eq!(program_to_commander_with(&again, &options).expect("writes"), once, "{b} {tool}");
        }
    }
}

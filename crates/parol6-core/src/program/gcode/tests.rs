//! Tests of the G-code import and export: the dialect word by word, exact errors, round trips.

use proptest::prelude::*;

use super::*;
use crate::angles::{rotation_from_abc_deg, rpy_to_abc_deg};
use crate::program::{GripperAction, Program, Step};

const START: PoseMm = PoseMm { position_mm: [200.0, 0.0, 300.0], rpy_deg: [180.0, 0.0, 0.0] };
const HOME: PoseMm = PoseMm { position_mm: [0.0, 250.0, 350.0], rpy_deg: [180.0, 0.0, 90.0] };

fn opts() -> GcodeImportOptions {
    GcodeImportOptions::new(START, HOME)
}

fn steps(text: &str) -> Vec<Step> {
    match parse_gcode(text, &opts()) {
        Ok(p) => p.steps.into_iter().map(|s| s.step).collect(),
        Err(e) => panic!("{e}\n{text}"),
    }
}

fn err(text: &str) -> String {
    parse_gcode(text, &opts()).expect_err("invalid").to_string()
}

fn pose_of(step: &Step) -> PoseMm {
    match step {
        Step::MoveL { pose, .. } | Step::MovePose { pose, .. } | Step::MoveC { pose, .. } => *pose,
        other => panic!("no pose: {other:?}"),
    }
}

fn near(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

/// The angle between two orientations given as our roll/pitch/yaw, deg.
fn turn_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let q = |r: [f64; 3]| {
        let [x, y, z] = r.map(f64::to_radians);
        nalgebra::UnitQuaternion::from_euler_angles(x, y, z)
    };
    q(a).angle_to(&q(b)).to_degrees()
}

#[test]
fn official_angles_a90_b0_cm20_are_our_roll0_pitch20_yaw90() {
    let s = steps("G0 X250 Y0 Z300 A90 B0 C-20");
    let p = pose_of(&s[0]);
    assert!(near(p.rpy_deg, [0.0, 20.0, 90.0], 1e-9), "{p:?}");
    let program = Program::from_steps(
        "t",
        vec![Step::MovePose { pose: p, config: None, speed_fraction: None, duration_s: None }],
    );
    let model = RobotModel::parol6();
    let text = program_to_gcode(&program, &model, &GcodeExportOptions::new(&program, vec![0.0; 6])).expect("export");
    assert!(text.contains("G0 X250 Y0 Z300 A90 B0 C-20\n"), "{text}");
}

#[test]
fn g0_g1_feed_and_axes_left_out() {
    let s = steps("N1 G21 G90 G0 X100 ; rapid\nG1 Y50 F600\nZ250 A10\n");
    assert_eq!(s.len(), 3);
    match &s[0] {
        Step::MovePose { pose, speed_fraction, .. } => {
            assert_eq!(*speed_fraction, None);
            assert!(near(pose.position_mm, [100.0, 0.0, 300.0], 1e-12));
            // A B C not given yet: 0, not the start's orientation
            assert!(turn_deg(pose.rpy_deg, [0.0; 3]) < 1e-9);
        }
        other => panic!("{other:?}"),
    }
    match &s[2] {
        Step::MoveL { pose, speed_mm_s, blend_mm, .. } => {
            assert_eq!((*speed_mm_s, *blend_mm), (Some(10.0), None));
            assert!(near(pose.position_mm, [100.0, 50.0, 250.0], 1e-12));
            let abc = rpy_to_abc_deg(pose.rpy_deg);
            assert!(near(abc, [10.0, 0.0, 0.0], 1e-9), "{abc:?}");
        }
        other => panic!("{other:?}"),
    }
    // before any F: the program's speed
    assert!(matches!(steps("G1 X1")[0], Step::MoveL { speed_mm_s: None, .. }));
}

#[test]
fn step_lines_are_the_gcode_lines() {
    let p = parse_gcode("%\n(header)\nG0 X1\n\nG1 X2 F600\nG4 P250\n%\n", &opts()).expect("valid");
    let lines: Vec<usize> = p.steps.iter().map(|s| s.line).collect();
    assert_eq!(lines, [3, 5, 6]);
    assert_eq!(p.steps[2].step, Step::Dwell { seconds: 0.25 });
}

#[test]
fn incremental_inch_and_work_offsets() {
    let s = steps("G91 G1 X10 Y-5 F600\nX10\nG90 G20 X1 C45\nG21 G10 L2 P2 X100 Y100 Z-50\nG55 G1 X0 Y0 Z0\nG54 X0");
    let at = |k: usize| pose_of(&s[k]).position_mm;
    assert!(near(at(0), [210.0, -5.0, 300.0], 1e-12));
    assert!(near(at(1), [220.0, -5.0, 300.0], 1e-12));
    assert!(near(at(2), [25.4, -5.0, 300.0], 1e-12));
    assert!((rpy_to_abc_deg(pose_of(&s[2]).rpy_deg)[2] - 45.0).abs() < 1e-9);
    assert!(near(at(3), [100.0, 100.0, -50.0], 1e-12));
    // back in G54 (zero offset): only X moves
    assert!(near(at(4), [0.0, 100.0, -50.0], 1e-12));
    // offsets from the options
    let mut o = opts();
    o.work_offsets[3] = [10.0, 20.0, 30.0, 0.0, 0.0, 0.0];
    let p = parse_gcode("G57 G0 X1 Y2 Z3", &o).expect("valid");
    assert!(near(pose_of(&p.steps[0].step).position_mm, [11.0, 22.0, 33.0], 1e-12));
}

#[test]
fn home_dwell_pauses_gripper_and_end() {
    let s = steps("G28\nG1 X1 F600\nG4 S1.5\nM0\nM1\nM3\nM4 P2\nM5\nM30\n(after the end)\n");
    assert_eq!(s[0], Step::Home { speed_fraction: None });
    // after G28 the axes left out are the home pose's
    assert!(near(pose_of(&s[1]).position_mm, [1.0, 250.0, 350.0], 1e-12));
    assert!(turn_deg(pose_of(&s[1]).rpy_deg, HOME.rpy_deg) < 1e-9);
    assert_eq!(
        s[2..],
        [
            Step::Dwell { seconds: 1.5 },
            Step::Pause { optional: false },
            Step::Pause { optional: true },
            Step::SetOutput { output: 1, on: false },
            Step::SetOutput { output: 2, on: false },
            Step::SetOutput { output: 1, on: true },
        ]
    );
    let mut o = opts();
    o.gripper = GcodeGripper::Electric;
    let p = parse_gcode("M3\nM5", &o).expect("valid");
    let actions: Vec<_> = p
        .steps
        .iter()
        .map(|s| match s.step {
            Step::Gripper { action, .. } => action,
            _ => panic!("{s:?}"),
        })
        .collect();
    assert_eq!(actions, [GripperAction::Close, GripperAction::Open]);
    assert_eq!(
        parse_gcode("M3 P1", &o).expect_err("port").to_string(),
        "line 1: word \"P1\": M3: a port P is for the pneumatic gripper; this import drives the electric one"
    );
}

#[test]
fn blending_with_g64_and_g61() {
    let s = steps("G64 P2.5\nG1 X210 F600\nX220\nG61 X230");
    let blends: Vec<_> =
        s.iter().map(|s| if let Step::MoveL { blend_mm, .. } = s { *blend_mm } else { None }).collect();
    assert_eq!(blends, [Some(2.5), Some(2.5), None]);
}

#[test]
fn arcs_by_ijk_and_r_in_every_plane() {
    // centre (200, 10), from (200, 0) to (190, 10): counter-clockwise is 270° (via at 45°)
    let h = 10.0 * std::f64::consts::FRAC_1_SQRT_2;
    let via_of = |text: &str| match &steps(text)[0] {
        Step::MoveC { via_mm, .. } => *via_mm,
        other => panic!("{other:?}"),
    };
    match &steps("G3 X190 Y10 I0 J10 F600")[0] {
        Step::MoveC { via_mm, pose, speed_mm_s } => {
            assert!(near(*via_mm, [200.0 + h, 10.0 + h, 300.0], 1e-9), "{via_mm:?}");
            assert!(near(pose.position_mm, [190.0, 10.0, 300.0], 1e-12));
            assert_eq!(*speed_mm_s, Some(10.0));
        }
        other => panic!("{other:?}"),
    }
    // clockwise: the quarter, via at 225°
    assert!(near(via_of("G2 X190 Y10 I0 J10"), [200.0 - h, 10.0 - h, 300.0], 1e-9));
    // R: the short arc (centre (190, 0)), and the long one with R negative (centre (200, 10))
    assert!(near(via_of("G3 X190 Y10 R10"), via_of("G3 X190 Y10 I-10 J0"), 1e-9));
    assert!(near(via_of("G3 X190 Y10 R10"), [190.0 + h, h, 300.0], 1e-9));
    assert!(near(via_of("G3 X190 Y10 R-10"), via_of("G3 X190 Y10 I0 J10"), 1e-9));
    assert!(near(via_of("G2 X190 Y10 R10"), via_of("G2 X190 Y10 I0 J10"), 1e-9));
    // full circle: the end is the start
    assert_eq!(
        steps("G2 I-20 F1200")[0],
        Step::MoveCircle {
            center_mm: [180.0, 0.0, 300.0],
            normal: [0.0, 0.0, 1.0],
            angle_deg: -360.0,
            speed_mm_s: Some(20.0)
        }
    );
    // ZX plane: G3 from +X towards +Z... about +Y: (200,0,300) about (190,0,300) → (190,0,290)
    assert!(near(via_of("G18 G3 X190 Z290 I-10 K0"), [190.0 + h, 0.0, 300.0 - h], 1e-9));
    // YZ plane: G3 about +X: from Y towards Z
    assert!(near(via_of("G19 G3 Y-10 Z310 J-10 K0"), [200.0, -10.0 + h, 300.0 + h], 1e-9));
}

#[test]
fn broken_lines_give_exact_errors() {
    let cases = [
        ("G5 X1", "line 1: word \"G5\": unsupported G code"),
        ("G1 X1\nM8", "line 2: word \"M8\": unsupported M code"),
        ("X10", "line 1: word \"X10\": no motion code yet: start the move with G0, G1, G2 or G3"),
        ("G0 G1 X1", "line 1: word \"G1\": conflicts with \"G0\" on the same line (one code of a group per line)"),
        ("G1 X1 X2", "line 1: word \"X2\": X appears twice on the line (\"X1\" first)"),
        ("T1", "line 1: word \"T1\": tool changes (T) are not supported: the tool is chosen in PAROL6 Studio"),
        ("G1 X1 E5", "line 1: word \"E5\": unsupported word"),
        ("M3 S1000", "line 1: word \"S1000\": S is only used by G4 (dwell seconds); there is no spindle"),
        ("G1 X1 I5", "line 1: word \"I5\": I, J, K and R are only used by G2 and G3"),
        ("G1 X1 F60", "line 1: word \"F60\": feed 60 mm/min is below the PAROL6's slowest 120 mm/min (2 mm/s)"),
        ("G2 X210", "line 1: word \"G2\": an arc needs I/J/K (its centre) or R (its radius)"),
        (
            "G2 X210 Z310 I5",
            "line 1: word \"Z310\": helical arcs are not supported: Z changes on an arc in the XY plane (G17)",
        ),
        ("G2 X210 K5", "line 1: word \"K5\": K is not a centre offset in the XY plane (G17): use I and J"),
        (
            "G2 X220 I5",
            "line 1: word \"G2\": the end point is 15 mm from the centre, the start 5 mm: not one circle (tolerance 0.01 mm)",
        ),
        ("G2 X220 R5", "line 1: word \"R5\": radius 5 mm is less than half the distance to the end point (10 mm)"),
        ("G2 R5", "line 1: word \"R5\": an R arc cannot end where it starts: give a full circle's centre with I/J/K"),
        ("G3 X210 I5 R5", "line 1: word \"R5\": an arc takes I/J/K or R, not both"),
        ("G2 I10 C30", "line 1: word \"G2\": a full circle cannot change the orientation (A, B, C)"),
        ("G4", "line 1: word \"G4\": G4 needs P (ms) or S (s)"),
        ("G4 P10 S1", "line 1: word \"S1\": G4 takes P (ms) or S (s), not both"),
        ("G4 S5000", "line 1: word \"S5000\": a dwell must lie in 0–3600 s"),
        ("G28 X0", "line 1: word \"X0\": G28 with axis words (an intermediate point) is not supported"),
        ("G10 L20 P1 X0", "line 1: word \"L20\": only G10 L2 (set a work offset) is supported"),
        ("G10 L2 P7 X0", "line 1: word \"P7\": the work offset is P1 (G54) … P6 (G59)"),
        ("G64", "line 1: word \"G64\": G64 needs P: the corner radius"),
        ("M3 P3", "line 1: word \"P3\": the gripper port is P1 or P2"),
        ("M3 M5", "line 1: word \"M5\": one M code per line (\"M3\" is already on it)"),
        ("M30\nG0 X1", "line 2: word \"G0\": after the program end (M30 on line 1)"),
        ("G0 X20000", "line 1: word \"X20000\": X would be 20000 mm, beyond ±10000 mm"),
        ("G20 G0 X500", "line 1: word \"X500\": X would be 12700 mm, beyond ±10000 mm"),
        ("G1 X1 P5", "line 1: word \"P5\": P is only used by G4, G10, G64 and M3/M4/M5"),
        ("G38.2 Z0", "line 1: word \"G38.2\": unsupported G code"),
        ("G2 I9000", "line 1: word \"G2\": the arc's circle reaches beyond ±10000 mm"),
    ];
    for (text, expected) in cases {
        assert_eq!(err(text), expected, "{text}");
    }
    let big = "G1 X1\n".repeat(MAX_GCODE_BYTES / 6 + 1);
    assert_eq!(err(&big), "the file is 16777218 bytes; G-code files are limited to 16 MiB");
}

#[test]
fn export_writes_every_step_type_it_can() {
    let model = RobotModel::parol6();
    let start = crate::motion::home_position(&model);
    let p0 = PoseMm::from_isometry(&model.tcp_isometry(&start));
    let at = |dx: f64, dz: f64| {
        let mut p = p0;
        p.position_mm[0] += dx;
        p.position_mm[2] += dz;
        p
    };
    let program = Program::from_steps(
        "all",
        vec![
            Step::Home { speed_fraction: None },
            Step::MoveJoints {
                joints_deg: start.iter().map(|v| v.to_degrees()).collect(),
                speed_fraction: None,
                duration_s: None,
            },
            Step::MoveL { pose: at(10.0, 0.0), speed_mm_s: Some(50.0), blend_mm: Some(2.0), duration_s: None },
            Step::MoveL { pose: at(10.0, -10.0), speed_mm_s: Some(50.0), blend_mm: None, duration_s: None },
            Step::Dwell { seconds: 0.5 },
            Step::SetOutput { output: 2, on: true },
            Step::Pause { optional: true },
        ],
    );
    let text = program_to_gcode(&program, &model, &GcodeExportOptions::new(&program, start.clone())).expect("export");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "; parol6: abc=commander");
    assert_eq!(lines[2], "; all");
    assert!(lines.contains(&"G28") && lines.contains(&"G64 P2") && lines.contains(&"G61"), "{text}");
    assert!(lines.contains(&"G4 P500") && lines.contains(&"M5 P2") && lines.contains(&"M1"), "{text}");
    assert!(lines.iter().any(|l| l.starts_with("G0 ") && l.contains("; joints [")), "{text}");
    assert_eq!(lines.last(), Some(&"M30"));
    // and it reads back to the same steps (the joint move as a pose move)
    let back = parse_gcode(&text, &GcodeImportOptions::for_model(&model, &start)).expect("reads back");
    assert_eq!(back.steps.len(), program.steps.len());
    assert_eq!(back.steps[4].step, Step::Dwell { seconds: 0.5 });
    assert!(near(pose_of(&back.steps[3].step).position_mm, at(10.0, -10.0).position_mm, 1e-6));

    let refuse = |step: Step, gripper: GcodeGripper| {
        let p = Program::from_steps("x", vec![Step::Dwell { seconds: 0.1 }, step]);
        let o = GcodeExportOptions { gripper, ..GcodeExportOptions::new(&p, start.clone()) };
        program_to_gcode(&p, &model, &o).expect_err("no equivalent").to_string()
    };
    assert_eq!(
        refuse(Step::WaitInput { input: 1, on: true, timeout_s: None }, GcodeGripper::Pneumatic),
        "step 2 (wait_input): waiting for an input has no G-code equivalent in this dialect"
    );
    let grip = |action| Step::Gripper { action, position: Some(100), speed: None, current_ma: None };
    assert_eq!(
        refuse(grip(GripperAction::Position), GcodeGripper::Electric),
        "step 2 (gripper): a gripper position (100) has no G-code equivalent (only open M5 and close M3)"
    );
    assert!(refuse(grip(GripperAction::Open), GcodeGripper::Pneumatic).contains("pneumatic"));
    assert!(refuse(Step::SetOutput { output: 1, on: true }, GcodeGripper::Electric).contains("electric gripper"));
}

#[test]
fn splines_and_tilted_arcs_become_lines_within_the_tolerance() {
    let model = RobotModel::parol6();
    let start = crate::motion::home_position(&model);
    let p0 = PoseMm::from_isometry(&model.tcp_isometry(&start));
    let off = |d: [f64; 3]| {
        let mut p = p0;
        (0..3).for_each(|k| p.position_mm[k] += d[k]);
        p
    };
    let tilted_via = [p0.position_mm[0] + 20.0, p0.position_mm[1] + 20.0, p0.position_mm[2] + 20.0];
    let program = Program::from_steps(
        "curves",
        vec![
            Step::Spline { waypoints: vec![off([20.0, 10.0, 0.0]), off([40.0, -10.0, 5.0])], speed_mm_s: Some(40.0) },
            Step::MoveC { via_mm: tilted_via, pose: off([0.0, 40.0, 0.0]), speed_mm_s: None },
        ],
    );
    let o = GcodeExportOptions::new(&program, start.clone());
    let text = program_to_gcode(&program, &model, &o).expect("export");
    assert!(text.contains("; a spline:") && text.contains("; an arc outside"), "{text}");
    let back = parse_gcode(&text, &GcodeImportOptions::for_model(&model, &start)).expect("reads back");
    assert!(back.steps.iter().all(|s| matches!(s.step, Step::MoveL { .. })));
    // every line end lies on the spline or the arc within the tolerance: check the last one of each
    let ends: Vec<[f64; 3]> = back.steps.iter().map(|s| pose_of(&s.step).position_mm).collect();
    assert!(ends.iter().any(|e| near(*e, off([40.0, -10.0, 5.0]).position_mm, 1e-6)));
    assert!(near(*ends.last().expect("lines"), off([0.0, 40.0, 0.0]).position_mm, 1e-6));
    assert!(ends.len() > 6, "{} lines", ends.len());
}

#[test]
fn a_sampled_circle_simplifies_within_the_tolerance_with_its_timing() {
    // a circle of radius 20 mm at 10 mm/s, sampled at 100 Hz, a 0.5 s stop, then a line
    let mut samples = Vec::new();
    let r = 20.0;
    let period_s = std::f64::consts::TAU * r / 10.0;
    let n = (period_s * 100.0) as usize;
    for k in 0..=n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let pose = PoseMm { position_mm: [200.0 + r * a.cos(), r * a.sin(), 300.0], rpy_deg: [180.0, 0.0, 0.0] };
        samples.push((period_s * k as f64 / n as f64, pose));
    }
    let t_end = samples.last().expect("samples").0;
    for k in 1..=50 {
        samples.push((t_end + 0.01 * k as f64, samples[n].1));
    }
    let mut last = samples[n].1;
    last.position_mm[2] -= 50.0;
    samples.push((t_end + 0.5 + 1.0, last));
    let tol = PathTolerance { position_mm: 0.05, orientation_deg: 0.5 };
    let text = tcp_path_to_gcode(&samples, &tol, AbcConvention::Commander).expect("path");
    let p = parse_gcode(&text, &opts()).expect("reads back");
    let lines: Vec<&Step> = p.steps.iter().map(|s| &s.step).collect();
    // sagitta ≤ 0.05 mm on r = 20 mm: at least 2π / (2·acos(1 − 0.05/20)) ≈ 45 chords;
    // Ramer–Douglas–Peucker keeps at most about twice the fewest
    let g1 = lines.iter().filter(|s| matches!(s, Step::MoveL { .. })).count();
    assert!((45..=90).contains(&g1), "{g1} lines\n{text}");
    // every sample of the circle lies within the tolerance of the polyline
    let pts: Vec<[f64; 3]> = lines
        .iter()
        .filter_map(|s| match s {
            Step::MoveL { pose, .. } | Step::MovePose { pose, .. } => Some(pose.position_mm),
            _ => None,
        })
        .collect();
    for (_, s) in &samples[..=n] {
        let d = pts.windows(2).map(|w| seg_dist(s.position_mm, w[0], w[1])).fold(f64::INFINITY, f64::min);
        assert!(d <= 0.05 + 1e-9, "{d}");
    }
    // the circle's lines run at 10 mm/s (600 mm/min, chords slightly short), the stop is a dwell
    assert!(text.contains(" F59") || text.contains(" F600"), "{text}");
    assert!(lines.iter().any(|s| matches!(s, Step::Dwell { seconds } if (seconds - 0.5).abs() < 0.02)), "{text}");
    // the last line: 50 mm in 1 s
    assert!(text.trim_end().lines().rev().nth(1).is_some_and(|l| l.ends_with("F3000")), "{text}");
    // bad input
    assert_eq!(
        tcp_path_to_gcode(&[], &tol, AbcConvention::Commander).expect_err("empty").to_string(),
        "the path has no samples"
    );
    let back_in_time = [(1.0, START), (0.5, START)];
    assert_eq!(
        tcp_path_to_gcode(&back_in_time, &tol, AbcConvention::Commander).expect_err("time").to_string(),
        "sample 1: its time 0.5 s does not increase"
    );
}

fn seg_dist(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let v = |x: [f64; 3]| nalgebra::Vector3::from(x);
    let (p, a, b) = (v(p), v(a), v(b));
    let ab = b - a;
    let f = if ab.norm_squared() > 0.0 { ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (p - (a + ab * f)).norm()
}

#[test]
fn a_recording_exports_its_tcp_path() {
    use crate::telemetry::sample::{DriveKind, JointTelemetry, TelemetrySample};
    use crate::telemetry::writer::{McapSink, RecordingInfo};
    let model = RobotModel::parol6();
    let info = RecordingInfo {
        app_version: "t".into(),
        tool: "none".into(),
        program: "p".into(),
        urdf_text: String::new(),
        tracking: String::new(),
    };
    let mut sink = McapSink::new(std::io::Cursor::new(Vec::new()), &model, &info).expect("sink");
    // a straight 40 mm line in 2 s at 1 kHz
    for k in 0..=2000u64 {
        let x = 0.2 + 0.04 * k as f64 / 2000.0;
        let joints = (0..6)
            .map(|_| JointTelemetry {
                cmd_q_rad: 0.0,
                cmd_qd_rad_s: 0.0,
                cmd_qdd_rad_s2: 0.0,
                q_rad: 0.0,
                qd_rad_s: 0.0,
                qdd_rad_s2: 0.0,
                drive: 0.0,
                zone: crate::limits::LimitZone::Safe,
            })
            .collect();
        let sample = TelemetrySample {
            seq: k + 1,
            time_s: k as f64 * 1e-3,
            joints,
            drive: DriveKind::TorqueNm,
            tcp: crate::kinematics::TcpPose::from_xyz_rpy([x, 0.0, 0.3], [std::f64::consts::PI, 0.0, 0.0]),
            worst_zone: None,
            program_step: None,
            link: None,
        };
        sink.write_sample(&sample).expect("sample");
    }
    let (_, cursor) = sink.finish_into_inner().expect("finish");
    let text =
        recording_to_gcode(&cursor.into_inner(), &PathTolerance::default(), AbcConvention::Commander).expect("export");
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with(';')).collect();
    assert_eq!(lines[1], "G0 X200 Y0 Z300 A0 B0 C180", "{text}");
    assert!(lines[2].starts_with("G1 X240 Y0 Z300 ") && lines[2].ends_with("F1200"), "{text}");
    assert_eq!(lines.len(), 4, "{text}");
    assert!(recording_to_gcode(b"not mcap", &PathTolerance::default(), AbcConvention::Commander).is_err());
}

/// Strategy: a random Cartesian program built move by move from where the last one ended.
#[derive(Debug, Clone)]
enum Move {
    Line { d: [f64; 3], abc: [f64; 3], speed: f64, blend: Option<f64> },
    Rapid { d: [f64; 3], abc: [f64; 3] },
    Arc { plane: usize, r: f64, phase: f64, sweep: f64, abc: [f64; 3], speed: f64 },
    Circle { plane: usize, r: f64, phase: f64, ccw: bool, flip: bool, speed: f64 },
}

fn a_move() -> impl Strategy<Value = Move> {
    let d = prop::array::uniform3(-80.0f64..80.0);
    let abc = (-179.0f64..179.0, -85.0f64..85.0, -179.0f64..179.0).prop_map(|(a, b, c)| [a, b, c]);
    prop_oneof![
        (d.clone(), abc.clone(), 2.0f64..200.0, prop::option::of(0.5f64..10.0))
            .prop_map(|(d, abc, speed, blend)| Move::Line { d, abc, speed, blend }),
        (d, abc.clone()).prop_map(|(d, abc)| Move::Rapid { d, abc }),
        (0usize..3, 5.0f64..80.0, 0.0f64..360.0, 5.0f64..355.0, any::<bool>(), abc, 2.0f64..200.0).prop_map(
            |(plane, r, phase, sweep, ccw, abc, speed)| Move::Arc {
                plane,
                r,
                phase,
                sweep: if ccw { sweep } else { -sweep },
                abc,
                speed
            }
        ),
        (0usize..3, 5.0f64..80.0, 0.0f64..360.0, any::<bool>(), any::<bool>(), 2.0f64..200.0)
            .prop_map(|(plane, r, phase, ccw, flip, speed)| Move::Circle { plane, r, phase, ccw, flip, speed }),
    ]
}

fn build(moves: &[Move], start: PoseMm) -> Program {
    let mut at = start;
    let mut out = Vec::new();
    let pose = |p: [f64; 3], abc: [f64; 3]| PoseMm { position_mm: p, rpy_deg: crate::angles::abc_to_rpy_deg(abc) };
    for m in moves {
        let step = match m {
            Move::Line { d, abc, speed, blend } => {
                let p = [at.position_mm[0] + d[0], at.position_mm[1] + d[1], at.position_mm[2] + d[2]];
                Step::MoveL { pose: pose(p, *abc), speed_mm_s: Some(*speed), blend_mm: *blend, duration_s: None }
            }
            Move::Rapid { d, abc } => {
                let p = [at.position_mm[0] + d[0], at.position_mm[1] + d[1], at.position_mm[2] + d[2]];
                Step::MovePose { pose: pose(p, *abc), config: None, speed_fraction: None, duration_s: None }
            }
            Move::Arc { plane, r, phase, sweep, abc, speed } => {
                let plane = arc::Plane::ALL[*plane];
                let (a, b, _) = plane.axes();
                let s = arc::in_plane(&at.position_mm, plane);
                let c = [s[0] - r * phase.to_radians().cos(), s[1] - r * phase.to_radians().sin()];
                let (mid, end) = (arc::rotate(s, c, 0.5 * sweep.to_radians()), arc::rotate(s, c, sweep.to_radians()));
                let (mut via, mut p) = (at.position_mm, at.position_mm);
                (via[a], via[b], p[a], p[b]) = (mid[0], mid[1], end[0], end[1]);
                Step::MoveC { via_mm: via, pose: pose(p, *abc), speed_mm_s: Some(*speed) }
            }
            Move::Circle { plane, r, phase, ccw, flip, speed } => {
                let plane = arc::Plane::ALL[*plane];
                let (a, b, _) = plane.axes();
                let mut centre = at.position_mm;
                centre[a] -= r * phase.to_radians().cos();
                centre[b] -= r * phase.to_radians().sin();
                let sign = if *flip { -1.0 } else { 1.0 };
                let normal = plane.normal().map(|v| v * sign);
                let angle_deg = if *ccw { 360.0 } else { -360.0 } * sign;
                Step::MoveCircle { center_mm: centre, normal, angle_deg, speed_mm_s: Some(*speed) }
            }
        };
        if let Step::MoveL { pose, .. } | Step::MovePose { pose, .. } | Step::MoveC { pose, .. } = &step {
            at = *pose;
        }
        out.push(step);
    }
    Program::from_steps("random", out)
}

/// Two programs follow the same path: the same steps with the same poses, centres and
/// speeds within `tol` (mm, deg, mm/s); a full circle may name its turn by the other normal.
fn assert_same_path(a: &Program, b: &Program, tol: f64) {
    assert_eq!(a.steps.len(), b.steps.len());
    for (x, y) in a.steps.iter().zip(&b.steps) {
        let same_pose = |p: PoseMm, q: PoseMm| {
            near(p.position_mm, q.position_mm, tol) && {
                let quat = |r: [f64; 3]| {
                    nalgebra::UnitQuaternion::from_rotation_matrix(&rotation_from_abc_deg(rpy_to_abc_deg(r)))
                };
                quat(p.rpy_deg).angle_to(&quat(q.rpy_deg)).to_degrees() <= tol
            }
        };
        let same_speed = |s: Option<f64>, t: Option<f64>| match (s, t) {
            (Some(s), Some(t)) => (s - t).abs() <= tol,
            (s, t) => s == t,
        };
        let ok = match (x.step.clone(), y.step.clone()) {
            (
                Step::MoveL { pose: p, speed_mm_s: s, blend_mm: bl, .. },
                Step::MoveL { pose: q, speed_mm_s: t, blend_mm: bm, .. },
            ) => same_pose(p, q) && same_speed(s, t) && same_speed(bl, bm),
            (Step::MovePose { pose: p, .. }, Step::MovePose { pose: q, .. }) => same_pose(p, q),
            (Step::MoveC { via_mm: v, pose: p, speed_mm_s: s }, Step::MoveC { via_mm: w, pose: q, speed_mm_s: t }) => {
                // the via point is not in the G-code: it is rebuilt from the rounded centre and end,
                // so it may move by a few nm more than the written numbers
                near(v, w, 10.0 * tol) && same_pose(p, q) && same_speed(s, t)
            }
            (
                Step::MoveCircle { center_mm: c, normal: n, angle_deg: g, speed_mm_s: s },
                Step::MoveCircle { center_mm: d, normal: m, angle_deg: h, speed_mm_s: t },
            ) => {
                let turn = |n: [f64; 3], g: f64| {
                    let v = nalgebra::Vector3::from(n).normalize() * g;
                    [v[0], v[1], v[2]]
                };
                near(c, d, tol) && near(turn(n, g), turn(m, h), tol) && same_speed(s, t)
            }
            (s, t) => s == t,
        };
        assert!(ok, "{:?}\n  vs {:?}", x.step, y.step);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn cartesian_programs_survive_export_and_import(moves in prop::collection::vec(a_move(), 1..12)) {
        let model = RobotModel::parol6();
        let start_q = crate::motion::home_position(&model);
        let start = PoseMm::from_isometry(&model.tcp_isometry(&start_q));
        let program = build(&moves, start);
        let text = program_to_gcode(&program, &model, &GcodeExportOptions::new(&program, start_q.clone()))
            .expect("export");
        let back = parse_gcode(&text, &GcodeImportOptions::for_model(&model, &start_q)).expect("import");
        assert_same_path(&program, &back, 1e-6);
        // G-code → JSON → G-code keeps the path
        let json = crate::program::json::to_string(&back);
        let again = crate::program::json::parse(&json).expect("json");
        let text2 = program_to_gcode(&again, &model, &GcodeExportOptions::new(&again, start_q.clone())).expect("export");
        let back2 = parse_gcode(&text2, &GcodeImportOptions::for_model(&model, &start_q)).expect("import");
        assert_same_path(&back, &back2, 1e-6);
    }

    #[test]
    fn parsing_never_panics(text in "[GMXYZABCIJKRFPSLN0-9 .+\\-();%\\n]{0,200}") {
        let _ = parse_gcode(&text, &opts());
    }

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        let _ = parse_gcode(&text, &opts());
    }
}

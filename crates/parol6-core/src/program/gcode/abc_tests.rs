//! Tests of the two `A B C` conventions, the `; parol6:` header, orientation words not yet given
//! and feeds above the PAROL6's fastest.

use nalgebra::{Rotation3, UnitQuaternion};
use proptest::prelude::*;

use super::*;
use crate::program::{Program, Step};

const START: PoseMm = PoseMm { position_mm: [200.0, 0.0, 300.0], rpy_deg: [180.0, 0.0, 0.0] };
const HOME: PoseMm = PoseMm { position_mm: [0.0, 250.0, 350.0], rpy_deg: [180.0, 0.0, 90.0] };

fn read(text: &str, abc: AbcChoice) -> Result<Program, String> {
    parse_gcode(text, &GcodeImportOptions::new(START, HOME).with_abc(abc)).map_err(|e| e.to_string())
}

fn first_pose(p: &Program) -> PoseMm {
    match &p.steps[0].step {
        Step::MoveL { pose, .. } | Step::MovePose { pose, .. } => *pose,
        other => panic!("no pose: {other:?}"),
    }
}

fn rotation(p: &PoseMm) -> Rotation3<f64> {
    let [r, y, w] = p.rpy_deg.map(f64::to_radians);
    UnitQuaternion::from_euler_angles(r, y, w).to_rotation_matrix()
}

fn turn_deg(a: &Rotation3<f64>, b: &Rotation3<f64>) -> f64 {
    // via quaternions: acos of a rotation matrix's trace can leave [-1, 1] by rounding
    UnitQuaternion::from_rotation_matrix(a).angle_to(&UnitQuaternion::from_rotation_matrix(b)).to_degrees()
}

const A10_B5_CM8: &str = "G0 X200 Y0 Z300 A10 B5 C-8\n";

#[test]
fn the_two_conventions_read_a10_b5_cm8_24_deg_apart() {
    let commander = first_pose(&read(A10_B5_CM8, AbcChoice::default()).expect("valid"));
    let xyz = first_pose(&read(A10_B5_CM8, AbcChoice::default_to(AbcConvention::Xyz)).expect("valid"));
    // each is its own product of axis rotations (built here, not by the code under test)
    let r =
        |axis: nalgebra::Unit<nalgebra::Vector3<f64>>, deg: f64| Rotation3::from_axis_angle(&axis, deg.to_radians());
    let (x, y, z) = (nalgebra::Vector3::x_axis(), nalgebra::Vector3::y_axis(), nalgebra::Vector3::z_axis());
    let want_commander = r(x, -8.0) * r(y, 5.0) * r(z, 10.0);
    let want_xyz = r(x, 10.0) * r(y, 5.0) * r(z, -8.0);
    assert!(turn_deg(&rotation(&commander), &want_commander) < 1e-9);
    assert!(turn_deg(&rotation(&xyz), &want_xyz) < 1e-9);
    let apart = turn_deg(&rotation(&commander), &rotation(&xyz));
    assert!((apart - 24.267).abs() < 1e-3, "{apart}");
}

#[test]
fn a_header_names_the_convention_and_wins_over_the_default() {
    let text = format!("; parol6: abc=xyz\n(a comment)\n{A10_B5_CM8}");
    let by_header = first_pose(&read(&text, AbcChoice::default()).expect("valid"));
    let xyz = first_pose(&read(A10_B5_CM8, AbcChoice::default_to(AbcConvention::Xyz)).expect("valid"));
    assert!(turn_deg(&rotation(&by_header), &rotation(&xyz)) < 1e-9);
    // asked for explicitly and agreeing: fine; contradicting: an error naming the header's line
    assert!(read(&text, AbcChoice::explicit(AbcConvention::Xyz)).is_ok());
    assert_eq!(
        read(&text, AbcChoice::explicit(AbcConvention::Commander)).expect_err("contradiction"),
        "line 1: the file's header says abc=xyz but abc=commander was asked for (--abc commander): remove the \
         header line or ask for xyz"
    );
    // case and spacing are free; a comment that is not key=value is just a comment
    assert!(read(&format!(";PAROL6:  ABC=Xyz\n{A10_B5_CM8}"), AbcChoice::explicit(AbcConvention::Xyz)).is_ok());
    assert!(read(&format!("; parol6: a note\n{A10_B5_CM8}"), AbcChoice::explicit(AbcConvention::Xyz)).is_ok());
}

#[test]
fn broken_headers_name_their_line() {
    let cases = [
        ("G21\n; parol6: abc=xyz\nG0 X1", "line 2: a \"; parol6:\" header line must come before the first G-code word"),
        ("; parol6: abc=zyx\nG0 X1", "line 1: unknown A/B/C convention \"zyx\" (use commander or xyz)"),
        ("; parol6: units=mm", "line 1: unknown parol6 header setting \"units\" (known: abc)"),
        ("; parol6: abc=xyz fast", "line 1: the parol6 header item \"fast\" is not key=value (e.g. abc=xyz)"),
        (
            "; parol6: abc=xyz\n; parol6: abc=commander",
            "line 2: the header says abc=commander here but abc=xyz on line 1",
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(read(text, AbcChoice::default()).expect_err(text), expected, "{text}");
    }
}

#[test]
fn orientation_words_not_yet_given_are_zero_positions_the_start() {
    for abc in AbcConvention::ALL {
        let p = read("G91 G1 X5 A10 F600\n", AbcChoice::default_to(abc)).expect("valid");
        let pose = first_pose(&p);
        assert_eq!(pose.position_mm, [205.0, 0.0, 300.0]);
        assert!((abc.from_rpy_deg(pose.rpy_deg)[0] - 10.0).abs() < 1e-9);
        let p = read("G0 Z250\n", AbcChoice::default_to(abc)).expect("valid");
        assert!(turn_deg(&rotation(&first_pose(&p)), &Rotation3::identity()) < 1e-9);
    }
}

#[test]
fn any_feed_from_the_slowest_up_is_passed_on() {
    // 30 000 mm/min is 500 mm/s, above the PAROL6's 200: compiling slows it down
    let p = read("G1 X210 F30000\nG20 G1 X9 F600\n", AbcChoice::default()).expect("valid");
    let speeds: Vec<Option<f64>> = p
        .steps
        .iter()
        .map(|s| match s.step {
            Step::MoveL { speed_mm_s, .. } => speed_mm_s,
            _ => None,
        })
        .collect();
    assert_eq!(speeds, [Some(500.0), Some(254.0)]);
    assert_eq!(
        read("G1 X1 F119", AbcChoice::default()).expect_err("slow"),
        "line 1: word \"F119\": feed 119 mm/min is below the PAROL6's slowest 120 mm/min (2 mm/s)"
    );
}

#[test]
fn export_writes_the_header_and_a_name_that_looks_like_one_is_quoted() {
    let model = RobotModel::parol6();
    let q = vec![0.0, -0.5, 3.0, 0.0, 0.3, 0.0];
    let pose = PoseMm::from_isometry(&model.tcp_isometry(&q));
    let mut program = Program::from_steps(
        "parol6: abc=xyz",
        vec![Step::MoveL { pose, speed_mm_s: Some(20.0), blend_mm: None, duration_s: None }],
    );
    program.description = "two\nlines".into();
    let options = GcodeExportOptions::new(&program, q.clone()).with_abc(AbcConvention::Xyz);
    let text = program_to_gcode(&program, &model, &options).expect("export");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[..4], ["; parol6: abc=xyz", lines[1], "; \"parol6: abc=xyz\"", "; two lines"], "{text}");
    assert!(lines[1].contains("R = Rx(A)·Ry(B)·Rz(C)"), "{text}");
    // read back with the other default: the header wins, the pose is the same
    let back = first_pose(&read(&text, AbcChoice::default()).expect("reads back"));
    assert!(turn_deg(&rotation(&back), &rotation(&pose)) < 1e-7);
}

proptest! {
    #[test]
    fn either_convention_exports_and_reads_back_the_same_poses(
        xyz in prop::bool::ANY,
        rpy in prop::array::uniform3(-179.0f64..179.0),
        pos in prop::array::uniform3(-300.0f64..300.0),
    ) {
        let abc = if xyz { AbcConvention::Xyz } else { AbcConvention::Commander };
        let pose = PoseMm { position_mm: pos, rpy_deg: rpy };
        let model = RobotModel::parol6();
        let start = crate::motion::home_position(&model);
        let program = Program::from_steps("p", vec![
            Step::MoveL { pose, speed_mm_s: Some(50.0), blend_mm: None, duration_s: None },
            Step::MovePose { pose, config: None, speed_fraction: None, duration_s: None },
        ]);
        let options = GcodeExportOptions::new(&program, start.clone()).with_abc(abc);
        let text = program_to_gcode(&program, &model, &options).expect("export");
        // the default of the reader is the other convention: the header decides
        let other = if xyz { AbcConvention::Commander } else { AbcConvention::Xyz };
        let back = parse_gcode(&text, &GcodeImportOptions::for_model(&model, &start).with_abc(AbcChoice::default_to(other)))
            .expect("reads back");
        for s in &back.steps {
            let p = match s.step {
                Step::MoveL { pose, .. } | Step::MovePose { pose, .. } => pose,
                _ => unreachable!(),
            };
            prop_assert!(p.position_mm.iter().zip(pos).all(|(a, b)| (a - b).abs() < 1e-6));
            prop_assert!(turn_deg(&rotation(&p), &rotation(&pose)) < 1e-5);
        }
    }
}

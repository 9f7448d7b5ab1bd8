use super::*;
use proptest::prelude::*;

const JOINTS: &str = "# a joint table\nj1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,speed_fraction\n\
90,-80,170,0,60,180,0.6\n\n 90 , -90 , 180 , 0 , 0 , 180 ,\n";

#[test]
fn a_joint_table_reads_as_joint_moves_with_the_rows_lines() {
    let p = parse_csv_table(JOINTS).expect("valid");
    assert_eq!(p.steps.len(), 2);
    assert_eq!(p.steps.iter().map(|s| s.line).collect::<Vec<_>>(), vec![3, 5]);
    assert_eq!(
        p.steps[0].step,
        Step::MoveJoints {
            joints_deg: vec![90.0, -80.0, 170.0, 0.0, 60.0, 180.0],
            speed_fraction: Some(0.6),
            duration_s: None
        }
    );
    assert!(matches!(p.steps[1].step, Step::MoveJoints { speed_fraction: None, .. }));
    let rad = "j6_rad,j5_rad,j4_rad,j3_rad,j2_rad,j1_rad,time_s\n3.141592653589793,0,0,3.141592653589793,-1.5707963267948966,1.5707963267948966,2\n";
    let p = parse_csv_table(rad).expect("radians, columns in any order");
    match &p.steps[0].step {
        Step::MoveJoints { joints_deg, duration_s, .. } => {
            assert!(joints_deg.iter().zip([90.0, -90.0, 180.0, 0.0, 0.0, 180.0]).all(|(a, b)| (a - b).abs() < 1e-9));
            assert_eq!(*duration_s, Some(2.0));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_cartesian_table_reads_as_lines_in_either_angle_convention() {
    let rpy = "x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,speed_mm_s,time_s\n30,263.6,292.1,0,20,90,80,\n";
    let p = parse_csv_table(rpy).expect("valid");
    assert_eq!(
        p.steps[0].step,
        Step::MoveL {
            pose: PoseMm { position_mm: [30.0, 263.6, 292.1], rpy_deg: [0.0, 20.0, 90.0] },
            speed_mm_s: Some(80.0),
            blend_mm: None,
            duration_s: None
        }
    );
    // the official example: our (0, 20, 90) is the official (90, 0, -20)
    let abc = "x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg\n30,263.6,292.1,90,0,-20\n";
    match &parse_csv_table(abc).expect("valid").steps[0].step {
        Step::MoveL { pose, .. } => {
            assert!(pose.rpy_deg.iter().zip([0.0, 20.0, 90.0]).all(|(a, b)| (a - b).abs() < 1e-9), "{pose:?}")
        }
        other => panic!("{other:?}"),
    }
    let back = program_to_csv_with(&parse_csv_table(abc).expect("valid"), AngleConvention::OfficialAbc).expect("ok");
    assert!(back.starts_with("x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg\n"), "{back}");
}

#[test]
fn errors_name_the_row_and_column() {
    let cases = [
        (
            "x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n1,2,3,4,5,6\n\n\n1,abc,3,4,5,6\n",
            "row 5, column \"y_mm\": \"abc\" is not a number",
        ),
        ("x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n1,2,3,4,5\n", "row 2: has 5 cells; the header has 6"),
        (
            "x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n1,2,,4,5,6\n",
            "row 2, column \"z_mm\": is empty; a number is needed",
        ),
        (
            "x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n1,2,inf,4,5,6\n",
            "row 2, column \"z_mm\": \"inf\" is not a finite number",
        ),
        ("x_mm,y_mm,z_mm,roll_deg,pitch_deg\n1,2,3,4,5\n", "header (line 1): column \"yaw_deg\" is missing"),
        (
            "x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,speed_fraction\n",
            "header (line 1): column \"speed_fraction\" does not belong in a Cartesian table (its columns: x_mm, y_mm, z_mm, roll_deg, pitch_deg, yaw_deg, speed_mm_s, time_s)",
        ),
        ("j1_deg,j1_deg\n", "header (line 1): column \"j1_deg\" appears twice"),
        (
            "a,b\n1,2\n",
            "header (line 1): a point table's header names j1_deg … j6_deg (or j1_rad … j6_rad) or x_mm, y_mm, z_mm with roll_deg, pitch_deg, yaw_deg (or rx_deg, ry_deg, rz_deg)",
        ),
        ("", "the table is empty: it needs a header line and rows"),
        ("j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg\n", "the table has a header but no rows"),
    ];
    for (text, want) in cases {
        assert_eq!(parse_csv_table(text).expect_err(text).to_string(), want);
    }
}

#[test]
fn writing_refuses_steps_a_table_cannot_hold() {
    let mut p = parse_csv_table(JOINTS).expect("valid");
    p.steps.push(SourcedStep { step: Step::Dwell { seconds: 1.0 }, line: 9 });
    assert_eq!(
        program_to_csv(&p).expect_err("dwell").to_string(),
        "step 3 (line 9, dwell): a point table holds one kind of step, here move_joints (as the first step); this one has no row form"
    );
    let line = Step::MoveL {
        pose: PoseMm { position_mm: [0.0; 3], rpy_deg: [0.0; 3] },
        speed_mm_s: None,
        blend_mm: Some(5.0),
        duration_s: None,
    };
    let e = program_to_csv(&Program::from_steps("x", vec![line])).expect_err("blend");
    assert!(e.to_string().contains("no blend column"), "{e}");
    assert!(program_to_csv(&Program::default()).is_err());
}

fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![-1000.0f64..1000.0, (-1000i32..1000).prop_map(f64::from), Just(0.0)]
}

fn optional() -> impl Strategy<Value = Option<f64>> {
    prop_oneof![Just(None), (0.01f64..1.0).prop_map(Some)]
}

fn joint_step() -> impl Strategy<Value = Step> {
    (proptest::collection::vec(finite(), 6), optional(), optional()).prop_map(
        |(joints_deg, speed_fraction, duration_s)| Step::MoveJoints { joints_deg, speed_fraction, duration_s },
    )
}

fn line_step() -> impl Strategy<Value = Step> {
    (proptest::array::uniform3(finite()), proptest::array::uniform3(finite()), optional(), optional()).prop_map(
        |(position_mm, rpy_deg, speed_mm_s, duration_s)| Step::MoveL {
            pose: PoseMm { position_mm, rpy_deg },
            speed_mm_s,
            blend_mm: None,
            duration_s,
        },
    )
}

proptest! {
    /// program → table → program gives the same steps; table → program → table the same text.
    #[test]
    fn tables_round_trip(steps in prop_oneof![
        proptest::collection::vec(joint_step(), 1..8),
        proptest::collection::vec(line_step(), 1..8),
    ]) {
        let p = Program::from_steps("t", steps);
        let text = program_to_csv(&p).expect("writes");
        let back = parse_csv_table(&text).expect("reads its own output");
        let a: Vec<&Step> = p.steps.iter().map(|s| &s.step).collect();
        let b: Vec<&Step> = back.steps.iter().map(|s| &s.step).collect();
        prop_assert_eq!(a, b);
        prop_assert_eq!(program_to_csv(&back).expect("writes"), text);
        // one row per line after the header
        prop_assert!(back.steps.iter().enumerate().all(|(i, s)| s.line == i + 2));
    }

    #[test]
    fn parsing_never_panics(text in "[-a-z_0-9,.\\n# \"]{0,200}") {
        let _ = parse_csv_table(&text);
    }

    #[test]
    fn parsing_any_text_never_panics(text in "\\PC{0,200}") {
        let _ = parse_csv_table(&text);
    }
}

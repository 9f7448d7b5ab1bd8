use super::*;
use proptest::prelude::*;

const HEADER: &str =
    "cycle,pose,cmd_x_mm,cmd_y_mm,cmd_z_mm,cmd_a_deg,cmd_b_deg,cmd_c_deg,x_mm,y_mm,z_mm,a_deg,b_deg,c_deg";

#[test]
fn a_written_file_reads_back_the_same() {
    let s = PoseSample {
        cycle: 3,
        pose: 4,
        commanded: PoseMm { position_mm: [200.0, -40.0, 260.0], rpy_deg: [180.0, 0.0, 0.0] },
        attained: PoseMm { position_mm: [200.012, -40.5, 260.25], rpy_deg: [-179.99, 0.01, -0.02] },
    };
    let text = write(&[s]);
    assert!(text.starts_with(HEADER), "{text}");
    assert!(text.contains("\n3,P5,200.000000,"), "{text}");
    assert_eq!(parse(&text).unwrap(), vec![s]);
}

#[test]
fn columns_may_come_in_any_order_with_extras_and_numeric_pose_names() {
    let text = "pose,c_deg,b_deg,a_deg,z_mm,y_mm,x_mm,cmd_c_deg,cmd_b_deg,cmd_a_deg,cmd_z_mm,cmd_y_mm,cmd_x_mm,cycle,note\n\
                2, 3,2,1, 30,20,10, 6,5,4, 300,200,100, 7, tracker\n";
    let s = parse(text).unwrap();
    assert_eq!(s[0].pose, 1);
    assert_eq!(s[0].cycle, 7);
    assert_eq!(s[0].commanded.position_mm, [100.0, 200.0, 300.0]);
    assert_eq!(s[0].attained.rpy_deg, [1.0, 2.0, 3.0]);
}

#[test]
fn malformed_files_name_the_row_and_column() {
    let row = "1,P1,0,0,0,0,0,0,0,0,0,0,0,0";
    let cases = [
        (String::new(), "the file is empty"),
        (format!("{HEADER}\n"), "the file is empty (a header and no rows)"),
        (HEADER.replace(",y_mm", ""), "row 1 (header): column `y_mm` is missing"),
        (
            format!("{HEADER}\n{row}\n1,P2,0,0,0,0,0,0,0,abc,0,0,0,0\n"),
            "row 3, column `y_mm`: \"abc\" is not a finite number",
        ),
        (format!("{HEADER}\n1,P2,0,0,,0,0,0,0,0,0,0,0,0\n"), "row 2, column `cmd_z_mm`: empty"),
        (
            format!("{HEADER}\n0,P2,0,0,0,0,0,0,0,0,0,0,0,0\n"),
            "row 2, column `cycle`: \"0\" is not a positive whole number",
        ),
        (
            format!("{HEADER}\n1,P9,0,0,0,0,0,0,0,0,0,0,0,0\n"),
            "row 2, column `pose`: \"P9\" is not a test pose (P1…P5)",
        ),
        (format!("{HEADER}\n{row}\n1,P2,0,0\n"), "row 3: 4 fields where the header has 14"),
        (format!("{HEADER}\n1,P2,0,0,0,0,0,0,0,0,inf,0,0,0\n"), "row 2, column `z_mm`: \"inf\" is not a finite number"),
    ];
    for (text, want) in cases {
        assert_eq!(parse(&text).unwrap_err().to_string(), want, "{text}");
    }
}

proptest! {
    /// Any text: an error or samples, never a panic.
    #[test]
    fn any_text_parses_or_errs(text in "\\PC{0,300}") {
        let _ = parse(&text);
        let with_header = format!("{HEADER}\n{text}");
        let _ = parse(&with_header);
    }

    /// Written samples read back within the 6 written decimals.
    #[test]
    fn samples_round_trip(v in proptest::array::uniform12(-1000.0f64..1000.0), cycle in 1u32..1000, pose in 0usize..5) {
        let s = PoseSample {
            cycle,
            pose,
            commanded: PoseMm { position_mm: [v[0], v[1], v[2]], rpy_deg: [v[3], v[4], v[5]] },
            attained: PoseMm { position_mm: [v[6], v[7], v[8]], rpy_deg: [v[9], v[10], v[11]] },
        };
        let back = parse(&write(&[s])).unwrap();
        prop_assert_eq!(back.len(), 1);
        prop_assert_eq!((back[0].cycle, back[0].pose), (cycle, pose));
        prop_assert!((back[0].attained.position_mm[1] - v[7]).abs() < 1e-6);
    }
}

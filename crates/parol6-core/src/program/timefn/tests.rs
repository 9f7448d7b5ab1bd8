use super::*;

fn value(text: &str, t: f64) -> f64 {
    compile_expression(text).unwrap_or_else(|e| panic!("{text}: {e:?}")).eval(t).expect("finite")
}

fn syntax_error(text: &str) -> (usize, String) {
    match compile_expression(text) {
        Ok(_) => panic!("{text} parsed"),
        Err(e) => e,
    }
}

#[test]
fn expressions_evaluate_like_the_math() {
    let cases: [(&str, f64, f64); 16] = [
        ("2", 0.0, 2.0),
        ("20 + 25*t", 2.0, 70.0),
        ("-t", 3.0, -3.0),
        ("2*-t", 3.0, -6.0),
        ("--t", 3.0, 3.0),
        ("1/2*4", 0.0, 2.0),
        ("8/2/2", 0.0, 2.0),
        ("10-3-2", 0.0, 5.0),
        ("2^3^1", 0.0, 8.0),
        ("sin(pi/2)", 0.0, 1.0),
        ("cos(2*pi*t)", 0.5, -1.0),
        ("sqrt(t)^2", 9.0, 9.0),
        ("atan2(1, 1)", 0.0, std::f64::consts::FRAC_PI_4),
        ("max(t, 2) + min(t, 2)", 5.0, 7.0),
        ("exp(0) + ln(e) + log10(100) + abs(-1)", 0.0, 5.0),
        ("tau / PI + .5 + 3.", 0.0, 5.5),
    ];
    for (text, t, want) in cases {
        let got = value(text, t);
        assert!((got - want).abs() < 1e-12, "{text} at t = {t}: {got} vs {want}");
    }
}

#[test]
fn syntax_errors_name_the_column() {
    let cases = [
        ("3*t +", 6, "the expression ends where"),
        ("", 1, "empty"),
        ("   ", 1, "empty"),
        ("2 t", 3, "operator (+ - * / ^) is missing before \"t\""),
        ("2(t)", 2, "missing before '('"),
        ("x + 1", 1, "unknown name \"x\""),
        ("sin t", 1, "needs its argument in parentheses"),
        ("(t + 1", 1, "'(' is never closed"),
        ("t + 1)", 6, "')' without a matching '('"),
        ("1..2", 1, "\"1..2\" is not a number"),
        ("3 * * t", 5, "expected before '*'"),
        ("atan2(t)", 8, "atan2 takes 2 arguments"),
        ("sin(t, 1)", 6, "',' outside the arguments"),
        ("t # 2", 3, "unexpected character '#'"),
        ("2 × t", 3, "unexpected character '×'"),
        ("()", 2, "expected before ')'"),
    ];
    for (text, column, needle) in cases {
        let (c, m) = syntax_error(text);
        assert_eq!(c, column, "{text}: {m}");
        assert!(m.contains(needle), "{text}: {m}");
    }
    let deep = format!("{}t{}", "(".repeat(40), ")".repeat(40));
    assert_eq!(syntax_error(&deep).0, MAX_NESTING + 1);
    let long = "1+".repeat(300) + "1";
    assert!(syntax_error(&long).1.contains("characters long"));
}

#[test]
fn the_error_names_piece_axis_expression_and_column() {
    let pieces = vec![TimePiece::position(1.0, "0", "0", "0"), TimePiece::position(1.0, "0", "3*t +", "0")];
    let e = TimeFunction::new(&pieces, 100.0).err().expect("refused");
    assert_eq!(
        e.to_string(),
        "piece 2, y(t) = \"3*t +\": column 6: the expression ends where a number, t, a function or '(' is expected"
    );
}

#[test]
fn a_value_that_is_not_finite_names_the_time() {
    let pieces = vec![TimePiece::position(2.0, "250", "1/(1-t)", "300")];
    let f = TimeFunction::new(&pieces, 100.0).expect("parses");
    let start = PoseMm { position_mm: [250.0, 1.0, 300.0], rpy_deg: [180.0, 0.0, 0.0] }.isometry();
    let e = f.sample(&start).expect_err("inf at t = 1");
    assert_eq!(e.to_string(), "piece 1, y(t) = \"1/(1-t)\": the value is inf, not a finite number at t = 1 s");
    let nan = vec![TimePiece::position(1.0, "sqrt(-1 - t)", "0", "0")];
    let e = TimeFunction::new(&nan, 10.0).expect("parses").sample(&start).expect_err("NaN");
    assert!(e.to_string().contains("NaN, not a finite number at t = 0 s"), "{e}");
}

#[test]
fn pieces_are_sampled_in_local_time_and_must_join() {
    let pieces =
        vec![TimePiece::position(1.0, "100 + 10*t", "0", "300"), TimePiece::position(0.5, "110", "20*t", "300")];
    let f = TimeFunction::new(&pieces, 10.0).expect("parses");
    let start = PoseMm { position_mm: [100.0, 0.0, 300.0], rpy_deg: [180.0, 0.0, 0.0] }.isometry();
    let pts = f.sample(&start).expect("samples");
    // 11 points in the first second, then 5 more (the join is not repeated)
    assert_eq!(pts.len(), 16);
    assert!((pts[10].0 - 1.0).abs() < 1e-12 && (pts[15].0 - 1.5).abs() < 1e-12);
    assert!((pts[15].1.translation.vector - nalgebra::Vector3::new(0.11, 0.01, 0.3)).norm() < 1e-12);
    // orientation held from the start
    assert!(pts.iter().all(|(_, p)| p.rotation.angle_to(&start.rotation) < 1e-12));
    assert!(pts.windows(2).all(|w| w[1].0 > w[0].0));

    let gap = vec![TimePiece::position(1.0, "10*t", "0", "300"), TimePiece::position(1.0, "11", "0", "300")];
    let e = TimeFunction::new(&gap, 10.0).expect("parses").sample(&start).expect_err("gap");
    assert_eq!(e.to_string(), "piece 2: starts 1.00 mm and 0.00° from where piece 1 ends (at most 0.1 mm and 0.1°)");
}

/// Regression (found by a `time_function` fuzz seed): 0.15 s at 20 Hz is 3.0000000000000004
/// sample periods; the rounding gave a fifth point at the same time as the fourth.
#[test]
fn a_whole_number_of_samples_gave_a_repeated_point() {
    let f = TimeFunction::new(&[TimePiece::position(0.15, "t", "0", "0")], 20.0).expect("parses");
    let start = PoseMm { position_mm: [0.0; 3], rpy_deg: [0.0; 3] }.isometry();
    let pts = f.sample(&start).expect("samples");
    let times: Vec<f64> = pts.iter().map(|p| p.0).collect();
    assert_eq!(times.len(), 4, "{times:?}");
    assert!(times.windows(2).all(|w| w[1] > w[0]) && (times[3] - 0.15).abs() < 1e-12, "{times:?}");
}

#[test]
fn angles_come_in_threes_and_bounds_hold() {
    let mut p = TimePiece::position(1.0, "0", "0", "0");
    p.roll_deg = Some("180".into());
    let e = TimeFunction::new(&[p], 10.0).err().expect("one angle");
    assert_eq!(e.to_string(), "piece 1: give roll_deg, pitch_deg and yaw_deg together, or none of them");
    let ok = TimePiece::position(1.0, "0", "0", "0");
    for (rate, needle) in [(0.5, "sample_rate_hz"), (f64::NAN, "sample_rate_hz"), (5000.0, "sample_rate_hz")] {
        assert!(TimeFunction::new(std::slice::from_ref(&ok), rate).err().expect("rate").to_string().contains(needle));
    }
    assert!(TimeFunction::new(&[], 10.0).is_err());
    let long = TimePiece::position(4000.0, "0", "0", "0");
    assert!(TimeFunction::new(&[long], 10.0).err().expect("long").to_string().contains("at most 3600 s"));
    let zero = TimePiece::position(0.0, "0", "0", "0");
    assert_eq!(
        TimeFunction::new(&[zero], 10.0).err().expect("zero").to_string(),
        "piece 1: duration_s must be a number above 0, got 0"
    );
}

proptest::proptest! {
    /// Whatever the text, checking and parsing never panic, and what passes the check
    /// evaluates (to a number or an error) without a panic.
    #[test]
    fn the_parser_never_panics(text in "[-+*/^(),. 0-9a-z]{0,40}", t in -10.0f64..10.0) {
        if let Ok(c) = compile_expression(&text) {
            let _ = c.eval(t);
        }
    }

    #[test]
    fn any_text_never_panics(text in "\\PC{0,60}") {
        let _ = compile_expression(&text);
    }
}

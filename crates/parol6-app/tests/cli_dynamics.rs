//! `parol6 program torques` through the built binary: the torques of a demo program against
//! the PAROL6's joint limits, text and JSON, and bad input refused with exit 2.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use cli_support::run;

#[test]
fn program_torques_of_a_demo_as_json_and_text() {
    let out = run(&["program", "torques", "assets/programs/draw.json", "--json", "--series"]).json("torques");
    let limits: Vec<f64> = out["limits_nm"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    // motor holding torque × reduction: J2 0.45 N·m × 20, J6 0.16 N·m × 10
    assert_eq!(limits.len(), 6);
    assert!((limits[1] - 9.0).abs() < 1e-9 && (limits[5] - 1.6).abs() < 1e-9, "{limits:?}");
    let peaks: Vec<f64> = out["peak_abs_nm"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    // J2 lifts the arm: a gravity torque of the order of a newton-metre, within its limit
    assert!(peaks[1] > 0.5 && peaks[1] < limits[1], "{peaks:?}");
    assert_eq!(out["within_limits"], true);
    let time = out["time_s"].as_array().unwrap();
    assert_eq!(time.len() as u64, out["samples"].as_u64().unwrap());
    let torques = out["torques_nm"].as_array().unwrap();
    assert_eq!(torques.len(), 6);
    assert!(torques.iter().all(|j| j.as_array().unwrap().len() == time.len()));

    let text = run(&["program", "torques", "assets/programs/draw.json"]);
    assert_eq!(text.code(), Some(0), "{text:?}");
    assert!(text.stdout.contains("J2: peak") && text.stdout.contains("of 9.00 N·m"), "{}", text.stdout);
    assert!(text.stdout.trim_end().lines().last().unwrap().starts_with("ok: "), "{}", text.stdout);
}

#[test]
fn program_torques_refuses_bad_input() {
    let r = run(&["program", "torques", "no/such/program.json"]);
    r.assert_no_panic("missing file");
    assert_eq!(r.code(), Some(1), "an unreadable file is a runtime error: {r:?}");
    assert!(r.stderr.contains("no/such/program.json"), "{r:?}");
    let r = run(&["program", "torques", "assets/programs/draw.json", "--start-deg", "1,2"]);
    r.assert_refused("short start pose", "--start-deg");
    let r = run(&["program", "torques", "assets/programs/draw.json", "--series"]);
    assert_eq!(r.code(), Some(2), "--series needs --json: {r:?}");
}

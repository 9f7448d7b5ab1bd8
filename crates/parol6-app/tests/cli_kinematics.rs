//! The `parol6 fk` / `ik` / `bench fk|ik` command line, end to end through the built binary.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::process::{Command, Output};

fn parol6(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_parol6")).args(args).output().expect("the parol6 binary runs")
}

fn json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "exit {:?}, stderr: {}", out.status, String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("stdout is JSON")
}

fn assert_usage_error(out: &Output, needle: &str) {
    assert_eq!(out.status.code(), Some(2), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "one line on stderr: {err}");
    assert!(err.contains(needle), "{err:?} should mention {needle:?}");
    assert!(!err.contains("panicked"), "{err}");
}

fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).collect()
}

#[test]
fn fk_standby_in_degrees() {
    let v = json(&parol6(&["fk", "--joints", "90,-90,180,0,0,180", "--deg"]));
    let p = floats(&v["tcp"]["position_m"]);
    assert!((p[0]).abs() < 1e-9 && (p[1] - 0.236770721).abs() < 1e-9 && (p[2] - 0.334).abs() < 1e-9, "{p:?}");
    assert_eq!(v["tcp"]["matrix"].as_array().map(Vec::len), Some(4));
    assert_eq!(floats(&v["tcp"]["rpy_rad"]).len(), 3);
    assert_eq!(v["within_limits"], true);
}

/// Issue 32: the README says positions are in metres unless `--mm`, but `fk --mm` was refused.
#[test]
fn fk_mm_was_refused() {
    let v = json(&parol6(&["fk", "--joints", "90,-90,180,0,0,180", "--deg", "--mm"]));
    let (m, mm) = (floats(&v["tcp"]["position_m"]), floats(&v["tcp"]["position_mm"]));
    assert!((mm[1] - 236.770721).abs() < 1e-6 && (mm[2] - 334.0).abs() < 1e-6, "{mm:?}");
    assert!(m.iter().zip(&mm).all(|(a, b)| (a * 1e3 - b).abs() < 1e-9));
}

#[test]
fn fk_with_tool_moves_the_tcp() {
    let bare = json(&parol6(&["fk", "--joints", "90,-90,180,0,0,180", "--deg"]));
    let tool = json(&parol6(&["fk", "--joints", "90,-90,180,0,0,180", "--deg", "--tool", "ssg48"]));
    let (a, b) = (floats(&bare["tcp"]["position_m"]), floats(&tool["tcp"]["position_m"]));
    let d: f64 = a.iter().zip(&b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt();
    assert!((d - 0.105).abs() < 1e-9, "SSG-48 TCP is 105 mm along the flange axis, got {d}");
}

#[test]
fn fk_bad_input_is_one_line_exit_2() {
    assert_usage_error(&parol6(&["fk", "--joints", "1,2,abc,4,5,6"]), "value 3");
    assert_usage_error(&parol6(&["fk", "--joints", "1,2,3"]), "expected 6");
    assert_usage_error(&parol6(&["fk", "--joints", "1,2,3,4,5,6", "--tool", "hammer"]), "unknown tool");
    // a file that cannot be read is an I/O failure (exit 1), as for every command (issue 29 item 14)
    let missing = parol6(&["fk", "--joints", "1", "--urdf", "/nonexistent/robot.urdf"]);
    assert_eq!(missing.status.code(), Some(1), "{missing:?}");
    assert!(String::from_utf8_lossy(&missing.stderr).contains("cannot read URDF"), "{missing:?}");
    assert_usage_error(&parol6(&["fk", "--joints", "1,2,3,4,5,6", "--tip", "L9"]), "L9");
}

#[test]
fn ik_round_trips_fk_and_lists_branches() {
    let fk = json(&parol6(&["fk", "--joints", "-30,-75.5,150,90,-60,270", "--deg"]));
    let p = floats(&fk["tcp"]["position_m"]);
    let r = floats(&fk["tcp"]["rpy_rad"]);
    let pose = format!("{},{},{},{},{},{}", p[0], p[1], p[2], r[0], r[1], r[2]);
    let seed = "-0.5,-1.3,2.6,1.5,-1.0,4.7";
    let best = json(&parol6(&["ik", "--pose", &pose, "--seed", seed]));
    let sols = best["solutions"].as_array().expect("solutions");
    assert_eq!(sols.len(), 1);
    let q = floats(&sols[0]["joints_rad"]);
    let want = [-30.0f64, -75.5, 150.0, 90.0, -60.0, 270.0].map(f64::to_radians);
    for (a, b) in q.iter().zip(want) {
        assert!((a - b).abs() < 1e-6, "{q:?}");
    }
    let all = json(&parol6(&["ik", "--pose", &pose, "--seed", seed, "--all"]));
    let sols = all["solutions"].as_array().expect("solutions");
    assert!(sols.len() > 1, "J4 = 90° leaves room for the wrist-flip branch: {sols:?}");
    assert!(sols.iter().all(|s| s["branch"].is_string()), "branches are labelled");
    let d: Vec<f64> = sols.iter().map(|s| s["distance_to_seed"].as_f64().expect("distance")).collect();
    assert!(d.windows(2).all(|w| w[0] <= w[1]), "best first: {d:?}");
}

#[test]
fn ik_mm_and_deg_units() {
    let v = json(&parol6(&["ik", "--pose", "0,236.770721,334,90,-90,0", "--mm", "--deg"]));
    assert_eq!(v["solver"], "closed-form");
    assert!(!v["solutions"].as_array().expect("solutions").is_empty());
}

#[test]
fn ik_unsolvable_is_one_line_exit_2() {
    assert_usage_error(&parol6(&["ik", "--pose", "2,0,0.3,0,0,0"]), "unreachable");
    assert_usage_error(&parol6(&["ik", "--pose", "0.2,0,x,0,0,0"]), "--pose");
    assert_usage_error(&parol6(&["ik", "--pose", "0.2,0.1,0.2,0,0,0", "--seed", "1,2"]), "--seed");
}

#[test]
fn ik_uses_numeric_solver_for_other_chains() {
    let Some(dir) = shared() else { return };
    let urdf = dir.join("urdf/PAROL6.urdf");
    let urdf = urdf.to_str().expect("utf-8 path");
    // original URDF: its joint convention differs, so the numeric solver applies
    let fk = json(&parol6(&["fk", "--joints", "0.2,0.3,-0.5,0.1,0.4,0.2", "--urdf", urdf]));
    let p = floats(&fk["tcp"]["position_m"]);
    let r = floats(&fk["tcp"]["rpy_rad"]);
    let pose = format!("{},{},{},{},{},{}", p[0], p[1], p[2], r[0], r[1], r[2]);
    let v = json(&parol6(&["ik", "--pose", &pose, "--urdf", urdf, "--seed", "0.1,0.2,-0.4,0,0.3,0.1"]));
    assert_eq!(v["solver"], "numeric");
    let q = floats(&v["solutions"][0]["joints_rad"]);
    let back =
        json(&parol6(&["fk", "--joints", &q.iter().map(f64::to_string).collect::<Vec<_>>().join(","), "--urdf", urdf]));
    let p2 = floats(&back["tcp"]["position_m"]);
    for (a, b) in p.iter().zip(&p2) {
        assert!((a - b).abs() < 1e-6);
    }
    // the official python-API URDF is the PAROL6 chain: closed form
    let api = dir.join("urdf/python-api/PAROL6.urdf");
    let v = json(&parol6(&[
        "ik",
        "--pose",
        "0,0.236770721,0.334,1.5707963268,-1.5707963268,0",
        "--urdf",
        api.to_str().expect("utf-8"),
    ]));
    assert_eq!(v["solver"], "closed-form");
}

#[test]
fn bench_fk_and_ik_print_json() {
    let v = json(&parol6(&["bench", "fk", "--n", "2000"]));
    assert!(v["median_ns"].as_f64().is_some_and(|x| x > 0.0));
    assert_eq!(v["n"], 2000);
    let v = json(&parol6(&["bench", "ik", "--n", "300"]));
    for solver in ["analytic", "numeric"] {
        assert!(v[solver]["median_ns"].as_f64().is_some_and(|x| x > 0.0), "{v}");
        assert!(v[solver]["success_rate"].as_f64().is_some_and(|x| x > 0.9), "{v}");
    }
}

fn shared() -> Option<std::path::PathBuf> {
    parol6_tests::shared_dir()
}

//! Issue 29, items 13 and 14 through the built binary: absurd or non-finite numbers are refused
//! as bad input (exit 2) naming the field, whether typed or read from a URDF; a file that cannot
//! be read is an I/O failure (exit 1) for every command; tool names are normalised as documented.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::path::PathBuf;

use cli_support::run;

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("parol6-cli-numbers-{}-{name}", std::process::id()))
}

const HUGE: &str = "1e308,0,0,0,0,0";

#[test]
fn fk_with_1e308_joints_is_refused_naming_the_value() {
    let r = run(&["fk", "--joints", HUGE]);
    r.assert_refused("fk 1e308", "--joints: value 1 (1.000e308 rad) is not a plausible joint position");
    assert!(!r.stderr.contains("00000000000"), "no 300-digit number: {r:?}");
    run(&["fk", "--deg", "--joints", "0,-3601,0,0,0,0"]).assert_refused("fk --deg", "value 2 (-3601°)");
    // within the bound but outside the limits: computed, with the limit warning
    let r = run(&["fk", "--joints", "50,0,0,0,0,0"]);
    assert_eq!(r.json("fk 50 rad")["within_limits"], false);
}

#[test]
fn dynamics_with_1e308_is_refused_instead_of_printing_null_torques() {
    let z = "0,0,0,0,0,0";
    run(&["dynamics", "--joints", HUGE]).assert_refused("dynamics q", "--joints: value 1");
    run(&["dynamics", "--joints", z, "--velocities", "0,-1e308,0,0,0,0"])
        .assert_refused("dynamics qd", "--velocities: value 2 (-1.000e308 rad/s) is not a plausible joint velocity");
    run(&["dynamics", "--joints", z, "--accelerations", "0,0,1e308,0,0,0"])
        .assert_refused("dynamics qdd", "--accelerations: value 3");
    let r = run(&["dynamics", "--joints", "1.57,-1.4,3.1,0,0,3.14", "--velocities", "100,100,100,100,100,100"]);
    let torques = r.json("dynamics fast")["torques_nm"].clone();
    assert!(torques.as_array().unwrap().iter().all(|t| t.as_f64().is_some_and(f64::is_finite)), "{torques}");
}

#[test]
fn screenshot_with_1e308_joints_is_refused() {
    let out = temp("shot.png");
    run(&["screenshot", out.to_str().unwrap(), "--joints", HUGE])
        .assert_refused("screenshot 1e308", "--joints: value 1");
    assert!(!out.exists());
}

#[test]
fn ik_with_an_absurd_pose_is_refused_naming_the_value() {
    run(&["ik", "--pose", "1e308,0,0,0,0,0"]).assert_refused("ik position", "--pose: value 1");
    run(&["ik", "--deg", "--pose", "0.2,0,0.3,0,0,1e9"]).assert_refused("ik angle", "--pose: value 6");
}

fn urdf_with_origin(xyz: &str) -> String {
    format!(
        "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<joint name=\"j\" type=\"revolute\">\
         <parent link=\"a\"/><child link=\"b\"/><origin xyz=\"{xyz}\"/><axis xyz=\"0 0 1\"/>\
         <limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n</robot>\n"
    )
}

#[test]
fn urdf_with_nan_or_1e400_in_an_origin_is_refused_by_fk() {
    for (name, xyz) in [("nan", "0 0 NaN"), ("big", "0 0 1e400")] {
        let path = temp(&format!("{name}.urdf"));
        std::fs::write(&path, urdf_with_origin(xyz)).unwrap();
        let r = run(&["fk", "--urdf", path.to_str().unwrap(), "--joints", "0"]);
        r.assert_refused(name, "joint \"j\" origin xyz is");
        assert!(!r.stdout.contains("null"), "{r:?}");
        std::fs::remove_file(&path).unwrap();
    }
}

#[test]
fn urdf_syntax_error_names_line_and_column() {
    let path = temp("syntax.urdf");
    std::fs::write(&path, "<robot name=\"r\">\n<link name=\"a\">\n<visual></link>\n</robot>\n").unwrap();
    run(&["fk", "--urdf", path.to_str().unwrap(), "--joints", "0"]).assert_refused("syntax", "line 3, column");
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn replay_of_a_missing_file_exits_1_like_mcap_info() {
    let missing = temp("missing.mcap");
    for args in [vec!["replay", missing.to_str().unwrap()], vec!["mcap", "info", missing.to_str().unwrap()]] {
        let r = run(&args);
        r.assert_no_panic("missing");
        assert_eq!(r.code(), Some(1), "{args:?}: {r:?}");
        assert!(r.stderr.contains("cannot read"), "{r:?}");
    }
    let r = run(&["fk", "--urdf", temp("missing.urdf").to_str().unwrap(), "--joints", "0"]);
    assert_eq!(r.code(), Some(1), "missing URDF: {r:?}");
    // content that is not a recording stays the user's input
    let not = temp("not.mcap");
    std::fs::write(&not, b"not a recording").unwrap();
    for args in [vec!["replay", not.to_str().unwrap()], vec!["mcap", "info", not.to_str().unwrap()]] {
        assert_eq!(run(&args).code(), Some(2), "{args:?}");
    }
    std::fs::remove_file(&not).unwrap();
}

#[test]
fn tool_names_are_normalised_as_documented() {
    for name in ["NONE", "none ", "ssg-48", "SSG48", "flange", "Pneumatic"] {
        let r = run(&["fk", "--joints", "1.57,-1.4,3.1,0,0,3.14", "--tool", name]);
        r.json(name);
    }
    run(&["fk", "--joints", "0,0,0,0,0,0", "--tool", "ssg 48"]).assert_refused("ssg 48", "unknown tool \"ssg 48\"");
    let help = run(&["fk", "--help"]);
    assert!(help.stdout.contains("Names are normalised"), "{help:?}");
}

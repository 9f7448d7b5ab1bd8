//! `parol6 program check` warns of joint torque over the motor limits: a PAROL6 whose links
//! are four times as heavy (our own fixture, written from the embedded URDF) needs more J2
//! torque than its motor gives, and pre-flight names the step and line; the same program on the
//! bare PAROL6 has no torque warning.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use cli_support::run;

/// The embedded PAROL6 URDF with every link mass × `factor` (inertias too), written to a
/// temporary folder.
fn heavy_urdf(factor: f64) -> std::path::PathBuf {
    let text = include_str!("../../../assets/parol6/parol6.urdf");
    let mut out = String::new();
    for line in text.lines() {
        let scaled = ["mass value=\"", "ixx=\"", "iyy=\"", "izz=\"", "ixy=\"", "ixz=\"", "iyz=\""].iter().fold(
            line.to_string(),
            |l, key| match l.find(key) {
                Some(i) => {
                    let start = i + key.len();
                    let end = start + l[start..].find('"').expect("closing quote");
                    let v: f64 = l[start..end].parse().expect("a number");
                    format!("{}{}{}", &l[..start], v * factor, &l[end..])
                }
                None => l,
            },
        );
        out.push_str(&scaled);
        out.push('\n');
    }
    let dir = std::env::temp_dir().join(format!("parol6-preflight-torque-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("heavy.urdf");
    std::fs::write(&path, out).expect("write");
    path
}

#[test]
fn program_check_warns_of_joint_torque_over_the_motor_limits() {
    let urdf = heavy_urdf(4.0);
    let urdf_arg = urdf.display().to_string();
    let r = run(&["program", "check", "assets/programs/draw.json", "--urdf", &urdf_arg]);
    // warnings only: the program may still run (exit 0), but it says so, naming step and line
    assert_eq!(r.code(), Some(0), "{r:?}");
    let warning = r
        .stdout
        .lines()
        .find(|l| l.contains("torque") && l.contains("exceeds its motor limit"))
        .unwrap_or_else(|| panic!("no torque warning:\n{}", r.stdout));
    assert!(warning.contains("draw.json:") && warning.contains(": warning: step "), "{warning}");
    assert!(warning.contains("J2 torque") && warning.contains("9.00 N·m"), "{warning}");
    let json = run(&["program", "check", "assets/programs/draw.json", "--urdf", &urdf_arg, "--json"]).json("check");
    assert!(json["torque_warnings"].as_u64().unwrap() > 0, "{json}");
    let issue = json["issues"]
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["message"].as_str().unwrap().contains("exceeds its motor limit"))
        .expect("a torque issue");
    assert_eq!(issue["severity"], "warning");
    assert!(issue["line"].as_u64().unwrap() > 0, "{issue}");
    // the bare PAROL6: no torque warning
    let bare = run(&["program", "check", "assets/programs/draw.json", "--json"]).json("check");
    assert!(bare.get("torque_warnings").is_none(), "{bare}");
    let _ = std::fs::remove_dir_all(urdf.parent().unwrap());
}

//! Our recordings read by the official Python `mcap` reader (`make_reader(…, validate_crcs=True)`,
//! through `tests/peers/mcap_read.py`, which knows nothing of our writer): every chunk's CRC
//! holds, the topics carry the schemas and encodings Foxglove and Lichtblick expect, log times
//! never go back, and the joint states decode to the arm we recorded. `.ci/run` installs the
//! reader; elsewhere the test says SKIPPED when it is missing.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::process::Command;

use cli_support::run;

/// True when python3 can import the official reader (in CI it must).
fn reader_installed() -> bool {
    let ok = Command::new("python3").args(["-c", "import mcap.reader"]).output().is_ok_and(|o| o.status.success());
    if !ok {
        assert!(std::env::var_os("CI").is_none(), "CI must have the Python mcap reader (.ci/run installs it)");
        parol6_tests::skip_notice("SKIPPED mcap_official_reader: python3 -m pip install mcap==1.6.0");
    }
    ok
}

fn read_with_the_official_reader(path: &std::path::Path) -> serde_json::Value {
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/peers/mcap_read.py");
    let out = Command::new("python3").arg(script).arg(path).output().expect("python3 runs");
    assert!(
        out.status.success(),
        "the official reader refused {}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON summary")
}

#[test]
fn the_official_python_reader_reads_our_recordings_with_their_crcs() {
    if !reader_installed() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("parol6-mcap-official-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (connect, backend) in [(None, "simulation"), (Some("--fake-robot"), "robot")] {
        let path = dir.join(format!("{backend}.mcap"));
        let mut args = vec!["record", "--seconds", "2", "-o", path.to_str().unwrap()];
        match connect {
            Some(c) => args.push(c),
            None => args.push("--demo"),
        }
        run(&args).json("record");
        let r = read_with_the_official_reader(&path);
        let topics = r["topics"].as_object().unwrap();
        let expect = [
            ("/robot_description", "std_msgs/String"),
            ("/joint_states", "parol6.JointState"),
            ("/joint_commands", "parol6.JointState"),
            ("/tf", "foxglove.FrameTransforms"),
            ("/tcp_pose", "foxglove.PoseInFrame"),
        ];
        for (topic, schema) in expect {
            let t = &topics[topic];
            assert_eq!(t["schema"], schema, "{backend} {topic}: {t}");
            assert_eq!((&t["message_encoding"], &t["schema_encoding"]), (&"json".into(), &"jsonschema".into()));
            assert_eq!(t["log_time_monotonic"], true, "{backend} {topic}: log times went back");
        }
        assert_eq!(topics["/robot_description"]["count"], 1);
        let states = topics["/joint_states"]["count"].as_u64().unwrap();
        assert_eq!(Some(states), topics["/joint_commands"]["count"].as_u64(), "{backend}: a command per state");
        // the robot reports at 100 Hz, the simulation at 1 kHz while moving: 2 s of either
        assert!(states >= 150, "{backend}: {states} joint states in 2 s");
        assert!(r["chunks"].as_u64().unwrap() >= 1);
        if backend == "robot" {
            assert_eq!(topics["/link"]["schema"], "parol6.LinkHealth", "{r}");
        }
        assert_eq!(r["metadata"]["parol6_studio"]["robot"], "parol6", "{}", r["metadata"]);
        let first = &r["first_joint_state"];
        let names: Vec<&str> = first["name"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
        let model = parol6_core::RobotModel::parol6();
        let joints: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
        assert_eq!(names, joints, "{backend}: URDF joint names");
        let standby = parol6_core::parol6::standby_rad();
        for (q, s) in first["position"].as_array().unwrap().iter().zip(standby) {
            assert!((q.as_f64().unwrap() - s).abs() < 1e-3, "{backend}: the recording starts at standby: {first}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

//! `parol6 serve --ros2`'s `control_msgs/action/FollowJointTrajectory` action (what MoveIt's
//! simple controller manager sends to) against an independent rmw_zenoh action client: the
//! Python script `tests/ros2/action_peer.py` (the official `eclipse-zenoh` package, its own CDR,
//! type hashes copied from the rosidl-generated headers), on loopback only. It sees the
//! action's tokens, sends hostile goals (rejected with control_msgs' error codes, no motion), a
//! valid one (SUCCEEDED, the joint states end at its last point), cancels a slow one, and
//! without `--allow-remote-control` has a valid goal rejected.
//!
//! Without python3 or its `zenoh` module the tests say SKIPPED, except in CI (`CI=true`), where
//! `.ci/run` installs it and they fail.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod cli_support;

use std::net::TcpListener;
use std::process::Command;

fn peer_available() -> bool {
    let ok = Command::new("python3").args(["-c", "import zenoh, zenoh.ext"]).output().is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI: python3 with the eclipse-zenoh package is required (.ci/run installs it)"
        );
        eprintln!("SKIPPED: python3 with the `zenoh` module (pip install eclipse-zenoh==1.10.2) is not installed");
    }
    ok
}

/// Runs the action peer; its JSON report.
fn action_peer(remote: bool) -> serde_json::Value {
    let script = cli_support::workspace_root().join("crates/parol6-app/tests/ros2/action_peer.py");
    let port = TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port().to_string();
    let mut args = vec![script.to_str().unwrap(), "--exe", cli_support::exe(), "--port", &port];
    if remote {
        args.push("--remote");
    }
    let out = Command::new("python3").args(&args).output().expect("python3 runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let report: serde_json::Value = serde_json::from_str(stdout.trim().lines().last().unwrap_or("null"))
        .unwrap_or_else(|e| panic!("the peer's report is not JSON ({e}): {stdout}\n{stderr}"));
    assert!(out.status.success() && report["ok"] == true, "peer failed: {report:#}\n{stderr}");
    report
}

#[test]
fn ros2_follow_joint_trajectory_goal_runs_hostile_goals_are_rejected_with_codes_and_a_cancel_stops() {
    if !peer_available() {
        return;
    }
    let r = action_peer(true);
    assert_eq!(r["action_tokens"], 5, "{r:#}");
    assert_eq!(r["refusals"].as_object().unwrap().len(), 8, "{r:#}");
    assert!(r["end_error_rad"].as_f64().unwrap().abs() < 0.005, "{r:#}");
}

#[test]
fn ros2_follow_joint_trajectory_goal_without_allow_remote_control_is_rejected() {
    if !peer_available() {
        return;
    }
    let r = action_peer(false);
    assert!(r["refusal"].as_str().unwrap().contains("--allow-remote-control"), "{r:#}");
}

#[test]
fn ros2_action_name_that_is_not_a_ros_name_is_refused_with_exit_2() {
    let limit = std::time::Duration::from_secs(60);
    let root = cli_support::workspace_root();
    let run = cli_support::run_in(root, &["serve", "--ros2", "--seconds", "1", "--ros2-action", "a//b"], limit);
    run.assert_no_panic("--ros2-action a//b");
    assert_eq!(run.code(), Some(2), "{run:?}");
    assert!(run.stderr.contains("--ros2-action") && run.stderr.contains("not a ROS name"), "{run:?}");
}

//! `parol6 serve --ros2` against an independent ROS 2 / rmw_zenoh peer: the Python script
//! `tests/ros2/peer.py` (the official `eclipse-zenoh` package, its own CDR and REP-2011 code),
//! on loopback only (a free port, multicast scouting off). It receives /joint_states and /tf
//! (checked against `parol6 fk`), /robot_description as a late joiner, the liveliness tokens,
//! and sends trajectories: hostile ones refused with no motion, a valid one run by the
//! simulation, and without `--allow-remote-control` a valid one refused.
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

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// Runs the peer script; its JSON report.
fn peer(remote: bool) -> serde_json::Value {
    let script = cli_support::workspace_root().join("crates/parol6-app/tests/ros2/peer.py");
    let port = free_port().to_string();
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
fn ros2_peer_sees_the_node_and_hostile_trajectories_are_refused_before_a_valid_one_runs() {
    if !peer_available() {
        return;
    }
    let r = peer(true);
    assert_eq!(r["tokens"], 11, "{r:#}");
    assert!(r["tf_vs_fk_error_m"].as_f64().unwrap() < 1e-6);
    assert_eq!(r["refusals"].as_object().unwrap().len(), 6, "{r:#}");
    assert!(r["executed_peak_rad"].as_f64().unwrap() > 0.19, "{r:#}");
}

#[test]
fn ros2_trajectory_without_allow_remote_control_is_refused() {
    if !peer_available() {
        return;
    }
    let r = peer(false);
    assert!(r["refusal"].as_str().unwrap().contains("--allow-remote-control"), "{r:#}");
}

#[test]
fn ros2_endpoints_other_than_tcp_are_refused_with_exit_2() {
    let root = cli_support::workspace_root();
    let limit = std::time::Duration::from_secs(60);
    for (flag, endpoint) in [("--ros2-connect", "udp/127.0.0.1:7447"), ("--ros2-listen", "tcp/127.0.0.1")] {
        let run = cli_support::run_in(root, &["serve", "--ros2", "--seconds", "1", flag, endpoint], limit);
        run.assert_no_panic(endpoint);
        assert_eq!(run.code(), Some(2), "{flag} {endpoint}: {run:?}");
        assert!(run.stderr.contains(flag) && run.stderr.contains("tcp/ADDRESS:PORT"), "{run:?}");
    }
}

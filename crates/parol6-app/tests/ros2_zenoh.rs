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

#[test]
fn ros2_peer_sees_the_node_and_hostile_trajectories_are_refused_before_a_valid_one_runs() {
    if !cli_support::zenoh_peer_available() {
        return;
    }
    let r = cli_support::run_zenoh_peer("peer.py", true);
    assert_eq!(r["tokens"], 11, "{r:#}");
    assert!(r["tf_vs_fk_error_m"].as_f64().unwrap() < 1e-6);
    assert_eq!(r["refusals"].as_object().unwrap().len(), 6, "{r:#}");
    assert!(r["executed_peak_rad"].as_f64().unwrap() > 0.19, "{r:#}");
}

#[test]
fn ros2_trajectory_without_allow_remote_control_is_refused() {
    if !cli_support::zenoh_peer_available() {
        return;
    }
    let r = cli_support::run_zenoh_peer("peer.py", false);
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

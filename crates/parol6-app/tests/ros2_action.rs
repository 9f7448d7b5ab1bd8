//! `parol6 serve --ros2`'s `control_msgs/action/FollowJointTrajectory` action (what MoveIt's
//! simple controller manager sends to) against an independent rmw_zenoh action client: the
//! Python script `tests/ros2/action_peer.py` (the official `eclipse-zenoh` package, its own CDR,
//! type hashes copied from the rosidl-generated headers), on loopback only. It sees the
//! action's tokens, sends hostile goals (rejected with control_msgs' error codes, no motion), a
//! valid one (SUCCEEDED, the joint states end at its last point, its feedback at 20 Hz matches
//! the joint states of the same stamp), cancels a slow one, and without
//! `--allow-remote-control` has a valid goal rejected. With `--tolerance`: a goal whose
//! `path_tolerance` the simulation's tracking lag exceeds (stopped early, ABORTED with
//! PATH_TOLERANCE_VIOLATED naming the joint), and one whose `goal_tolerance` is not reached
//! within its `goal_time_tolerance` (GOAL_TOLERANCE_VIOLATED after that time), and one whose
//! velocity `path_tolerance` the tracking exceeds (stopped early, PATH_TOLERANCE_VIOLATED naming
//! the joint's velocity). The path violation is read back from `/events` by the Foxglove
//! client of `tests/peers/foxglove_client.py` (serve then also has `--foxglove`).
//!
//! Without python3 or its `zenoh` module the tests say SKIPPED, except in CI (`CI=true`), where
//! `.ci/run` installs it and they fail.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod cli_support;

#[test]
fn ros2_follow_joint_trajectory_goal_runs_hostile_goals_are_rejected_with_codes_and_a_cancel_stops() {
    if !cli_support::zenoh_peer_available() {
        return;
    }
    let r = cli_support::run_zenoh_peer("action_peer.py", true);
    assert_eq!(r["action_tokens"], 5, "{r:#}");
    assert_eq!(r["refusals"].as_object().unwrap().len(), 8, "{r:#}");
    assert!(r["end_error_rad"].as_f64().unwrap().abs() < 0.005, "{r:#}");
    assert!(r["feedback_messages"].as_u64().unwrap() >= 10, "{r:#}");
}

#[test]
fn ros2_action_feedback_is_the_joint_states_path_tolerance_violation_aborts_with_minus_4_goal_tolerance_with_minus_5() {
    if !cli_support::zenoh_peer_available() {
        return;
    }
    let r = cli_support::run_zenoh_peer_with("action_peer.py", true, &["--tolerance", "--events"]);
    // the simulation's tracking lag of J1 moving 0.2 rad in 1 s (about 0.3 mrad) is well within
    // the valid goal's path tolerance (0.05 rad) and above the tight one (0.1 mrad)
    let lag = r["tracking_lag_rad"].as_f64().unwrap();
    assert!(lag > 1e-4 && lag < 0.05, "{r:#}");
    let path = r["path_abort"]["error_string"].as_str().unwrap();
    assert!(path.starts_with("path_tolerance violated: J1 is "), "{r:#}");
    assert!(r["path_abort"]["moved_rad"].as_f64().unwrap().abs() < 0.1, "{r:#}");
    // the violation is in /events, read back by the independent Foxglove client
    // (`tests/peers/foxglove_client.py events`) from `serve --ros2 --foxglove`
    let event = r["path_abort"]["events"].as_str().unwrap();
    assert!(event.contains("network command from ros2 ") && event.contains(path), "{r:#}");
    // and a goal tolerance missed after goal_time_tolerance (one run of the peer for both)
    let goal = r["goal_abort"]["error_string"].as_str().unwrap();
    assert!(goal.contains("goal_time_tolerance 0.300 s") && goal.contains("J1 is "), "{r:#}");
    assert!(r["goal_abort"]["result_after_s"].as_f64().unwrap() >= 0.75, "{r:#}");
    // a velocity path tolerance is enforced too (it was validated and ignored before)
    let velocity = r["velocity_abort"]["error_string"].as_str().unwrap();
    assert!(
        velocity.starts_with("path_tolerance violated: J1 is ") && velocity.contains("rad/s from its desired velocity"),
        "{r:#}"
    );
    assert!(r["velocity_abort"]["moved_rad"].as_f64().unwrap().abs() < 0.1, "{r:#}");
}

#[test]
fn ros2_follow_joint_trajectory_goal_without_allow_remote_control_is_rejected() {
    if !cli_support::zenoh_peer_available() {
        return;
    }
    let r = cli_support::run_zenoh_peer("action_peer.py", false);
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

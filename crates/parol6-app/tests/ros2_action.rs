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

#[test]
fn ros2_follow_joint_trajectory_goal_runs_hostile_goals_are_rejected_with_codes_and_a_cancel_stops() {
    if !cli_support::zenoh_peer_available() {
        return;
    }
    let r = cli_support::run_zenoh_peer("action_peer.py", true);
    assert_eq!(r["action_tokens"], 5, "{r:#}");
    assert_eq!(r["refusals"].as_object().unwrap().len(), 8, "{r:#}");
    assert!(r["end_error_rad"].as_f64().unwrap().abs() < 0.005, "{r:#}");
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

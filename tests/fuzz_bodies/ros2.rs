//! Fuzz body `ros2_cdr` (issue 30): arbitrary bytes as a ROS 2 payload, decoded as every
//! message type we read or send (`JointTrajectory`, `JointState`, `TFMessage`, `String`, and the
//! `FollowJointTrajectory` action's `SendGoal` / `GetResult` / `CancelGoal` requests and responses,
//! its `FeedbackMessage` and `GoalStatusArray`; a decoded goal goes through its own checks and the
//! trajectory's).
//! Nothing panics; the decoders allocate nothing ahead of the input (libFuzzer's malloc limit
//! catches a huge allocation from a hostile count); whatever decodes re-encodes to bytes that
//! decode to the same message (compared as encodings, so NaN compares equal to itself); every
//! sequence within its cap; and a decoded trajectory is either refused or converted into a
//! program of one timed joint move per point after the start, every position within the limits
//! (the pre-flight that follows is fuzzed on programs by `program_file_check`; here it would
//! cost milliseconds an input).

use std::sync::OnceLock;

use parol6_core::model::RobotModel;
use parol6_core::program::Step;
use parol6_core::ros2::action::{
    CancelGoalRequest, CancelGoalResponse, GetResultRequest, GetResultResponse, GoalStatusArray, INVALID_GOAL,
    INVALID_JOINTS, OLD_HEADER_TIMESTAMP, SendGoalRequest, SendGoalResponse,
};
use parol6_core::ros2::cdr::{self, MAX_JOINTS, MAX_POINTS, MAX_TRANSFORMS, Message};
use parol6_core::ros2::feedback::FeedbackMessage;
use parol6_core::ros2::goal::goal_checks;
use parol6_core::ros2::msgs::{JointState, JointTrajectory, StringMsg, TfMessage};
use parol6_core::ros2::trajectory::to_program;

fn model() -> &'static RobotModel {
    static MODEL: OnceLock<RobotModel> = OnceLock::new();
    MODEL.get_or_init(RobotModel::parol6)
}

/// Decodes `data` as `T`; what decodes must re-encode to the same message.
fn round_trip<T: Message>(data: &[u8]) -> Option<T> {
    let msg = cdr::decode::<T>(data).ok()?;
    let again = cdr::encode(&msg).unwrap_or_else(|e| panic!("a decoded message encodes: {e}"));
    let back = cdr::decode::<T>(&again).unwrap_or_else(|e| panic!("our own encoding decodes: {e}"));
    let third = cdr::encode(&back).unwrap_or_else(|e| panic!("encodes: {e}"));
    assert_eq!(third, again, "decode ∘ encode is the identity");
    Some(msg)
}

/// The action's messages: decoded, re-encoded; a goal's own checks refuse with one of
/// control_msgs' codes or pass, and its trajectory takes the trajectory path.
fn action(data: &[u8]) {
    if let Some(req) = round_trip::<SendGoalRequest>(data) {
        let g = &req.goal;
        assert!(g.path_tolerance.len() <= MAX_JOINTS && g.multi_dof_trajectory.points.len() <= MAX_POINTS);
        match goal_checks(model(), g, 1_700_000_000_000_000_000) {
            Ok(tol) => {
                let n = model().joints.len();
                for list in [&tol.goal, &tol.path] {
                    assert_eq!((list.position_rad.len(), list.velocity_rad_s.len()), (n, n));
                    let all = list.position_rad.iter().chain(&list.velocity_rad_s).flatten();
                    assert!(all.clone().all(|t| t.is_finite() && *t > 0.0));
                }
                assert!(tol.goal_time_s.is_finite() && tol.goal_time_s > 0.0);
                trajectory(&g.trajectory);
            }
            Err(e) => assert!([INVALID_GOAL, INVALID_JOINTS, OLD_HEADER_TIMESTAMP].contains(&e.error_code), "{e}"),
        }
    }
    if let Some(f) = round_trip::<FeedbackMessage>(data) {
        let f = &f.feedback;
        assert!(f.joint_names.len() <= MAX_JOINTS && f.desired.positions.len() <= MAX_JOINTS);
        assert!(f.multi_dof_actual.transforms.len() <= MAX_JOINTS);
    }
    round_trip::<SendGoalResponse>(data);
    round_trip::<GetResultRequest>(data);
    round_trip::<GetResultResponse>(data);
    round_trip::<CancelGoalRequest>(data);
    if let Some(c) = round_trip::<CancelGoalResponse>(data) {
        assert!(c.goals_canceling.len() <= MAX_JOINTS);
    }
    if let Some(s) = round_trip::<GoalStatusArray>(data) {
        assert!(s.status_list.len() <= MAX_POINTS);
    }
}

/// The body of `ros2_cdr`.
pub fn ros2_cdr(data: &[u8]) {
    action(data);
    if let Some(t) = round_trip::<JointTrajectory>(data) {
        trajectory(&t);
    }
    if let Some(js) = round_trip::<JointState>(data) {
        assert!(js.name.len() <= MAX_JOINTS && js.position.len() <= MAX_JOINTS);
    }
    if let Some(tf) = round_trip::<TfMessage>(data) {
        assert!(tf.transforms.len() <= MAX_TRANSFORMS);
    }
    round_trip::<StringMsg>(data);
}

/// A decoded trajectory: refused, or timed joint moves within the limits.
fn trajectory(t: &JointTrajectory) {
    assert!(t.joint_names.len() <= MAX_JOINTS && t.points.len() <= MAX_POINTS);
    assert!(t.points.iter().all(|p| p.positions.len() <= MAX_JOINTS && p.velocities.len() <= MAX_JOINTS));
    let model = model();
    let start = parol6_core::parol6::standby_rad();
    if let Ok((program, duration_s)) = to_program(model, t, &start) {
        assert!(duration_s.is_finite() && duration_s >= 0.0);
        assert!(program.steps.len() <= t.points.len());
        for s in &program.steps {
            let Step::MoveJoints { joints_deg, duration_s: Some(d), .. } = &s.step else {
                panic!("a trajectory becomes timed joint moves")
            };
            assert!(*d > 0.0);
            let q: Vec<f64> = joints_deg.iter().map(|v| v.to_radians()).collect();
            assert!(model.limits.contains(&q), "{q:?} within the limits");
        }
    }
}

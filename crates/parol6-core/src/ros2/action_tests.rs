use proptest::prelude::*;

use super::action::{
    ActionNames, CancelGoalRequest, CancelGoalResponse, FollowJointTrajectoryGoal, GetResultRequest, GetResultResponse,
    GoalInfo, GoalStatus, GoalStatusArray, INVALID_GOAL, INVALID_JOINTS, JointComponentTolerance, JointTolerance,
    OLD_HEADER_TIMESTAMP, SendGoalRequest, SendGoalResponse, Uuid, valid_action_name,
};
use super::cdr::{self, CdrError};
use super::goal::check_goal;
use super::graph::{EntityKind, NodeIdentity, Qos, topic_key};
use super::msgs::{Duration, Header, JointTrajectory, JointTrajectoryPoint, Time};
use crate::model::RobotModel;

fn names() -> Vec<String> {
    ["J1", "J2", "J3", "J4", "J5", "J6"].iter().map(|s| s.to_string()).collect()
}

fn standby() -> Vec<f64> {
    crate::parol6::standby_rad().to_vec()
}

fn point(q: &[f64], t_s: f64) -> JointTrajectoryPoint {
    JointTrajectoryPoint { positions: q.to_vec(), time_from_start: Duration::from_secs_f64(t_s), ..Default::default() }
}

/// J1 +0.2 rad in 1 s.
fn small_goal() -> FollowJointTrajectoryGoal {
    let q0 = standby();
    let mut q1 = q0.clone();
    q1[0] += 0.2;
    FollowJointTrajectoryGoal {
        trajectory: JointTrajectory {
            header: Header::default(),
            joint_names: names(),
            points: vec![point(&q0, 0.0), point(&q1, 1.0)],
        },
        ..Default::default()
    }
}

const NOW_NS: u64 = 1_700_000_000_000_000_000;

#[test]
fn a_send_goal_request_round_trips_and_its_goal_id_is_sixteen_bytes_without_a_count() {
    let req = SendGoalRequest { goal_id: Uuid { uuid: [7; 16] }, goal: small_goal() };
    let b = cdr::encode(&req).unwrap();
    assert_eq!(&b[4..20], &[7; 16]);
    // then the trajectory's header: stamp sec 0
    assert_eq!(&b[20..24], &[0, 0, 0, 0]);
    assert_eq!(cdr::decode::<SendGoalRequest>(&b).unwrap(), req);
}

#[test]
fn the_responses_encode_as_ros_sends_them() {
    let r = SendGoalResponse { accepted: true, stamp: Time { sec: 2, nanosec: 3 } };
    assert_eq!(cdr::encode(&r).unwrap(), [0, 1, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0]);
    let r = GetResultResponse { status: 4, result: Default::default() };
    // status int8, padding to 4, error_code int32 0, error_string "" (count 1, NUL)
    assert_eq!(cdr::encode(&r).unwrap(), [0, 1, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0]);
    let status = GoalStatusArray {
        status_list: vec![GoalStatus {
            goal_info: GoalInfo { goal_id: Uuid { uuid: [1; 16] }, stamp: Time::default() },
            status: 2,
        }],
    };
    let b = cdr::encode(&status).unwrap();
    assert_eq!(b.len(), 4 + 4 + 16 + 8 + 1);
    assert_eq!(cdr::decode::<GoalStatusArray>(&b).unwrap(), status);
    let c = CancelGoalResponse { return_code: 0, goals_canceling: vec![GoalInfo::default()] };
    assert_eq!(cdr::decode::<CancelGoalResponse>(&cdr::encode(&c).unwrap()).unwrap(), c);
    let g = GetResultRequest { goal_id: Uuid { uuid: [9; 16] } };
    assert_eq!(cdr::decode::<GetResultRequest>(&cdr::encode(&g).unwrap()).unwrap(), g);
    let c = CancelGoalRequest {
        goal_info: GoalInfo { goal_id: Uuid { uuid: [3; 16] }, stamp: Time { sec: 1, nanosec: 0 } },
    };
    assert_eq!(cdr::decode::<CancelGoalRequest>(&cdr::encode(&c).unwrap()).unwrap(), c);
}

#[test]
fn a_cut_send_goal_names_the_field_it_stopped_in() {
    let b = cdr::encode(&SendGoalRequest { goal_id: Uuid::default(), goal: small_goal() }).unwrap();
    let err = cdr::decode::<SendGoalRequest>(&b[..b.len() - 6]).unwrap_err();
    let CdrError::Field { field, .. } = err else { panic!("{err:?}") };
    assert!(field.starts_with("goal."), "{field}");
}

#[test]
fn action_names_and_keys_follow_rmw_zenoh() {
    let n = ActionNames::of("parol6_arm_controller/follow_joint_trajectory");
    assert_eq!(n.send_goal, "/parol6_arm_controller/follow_joint_trajectory/_action/send_goal");
    assert_eq!(n.status, "/parol6_arm_controller/follow_joint_trajectory/_action/status");
    assert_eq!(
        topic_key(0, &n.send_goal, &super::action::SEND_GOAL),
        "0/parol6_arm_controller/follow_joint_trajectory/_action/send_goal/\
         control_msgs::action::dds_::FollowJointTrajectory_SendGoal_/\
         RIHS01_4915b9909747df962256f0fe9a7dc832ba6e7ec2c5e827c5ba239b7b451d52aa"
    );
    let id = NodeIdentity { domain_id: 0, zid: "ab".into(), node_id: 0, name: "parol6".into() };
    let token =
        id.topic_token(3, EntityKind::ServiceServer, &n.cancel_goal, &super::action::CANCEL_GOAL, &Qos::reliable(10));
    assert!(token.starts_with("@ros2_lv/0/ab/0/3/SS/%/%/parol6/%parol6_arm_controller%follow_joint_trajectory%_action%cancel_goal/action_msgs::srv::dds_::CancelGoal_/RIHS01_6a5f"), "{token}");
    assert!(valid_action_name("/a/b_c") && valid_action_name("x"));
    assert!(
        !valid_action_name("") && !valid_action_name("/") && !valid_action_name("a//b") && !valid_action_name("1a")
    );
}

#[test]
fn a_valid_goal_is_planned_to_its_last_point() {
    let model = RobotModel::parol6();
    let g = check_goal(&model, &small_goal(), &standby(), NOW_NS).unwrap();
    assert!((g.final_q[0] - (standby()[0] + 0.2)).abs() < 1e-9);
    assert_eq!(g.plan.points, 2);
    assert!(g.tolerances.goal.is_empty() && g.tolerances.path.is_empty());
    assert_eq!(g.tolerances.goal_time_s, crate::ros2::tolerance::DEFAULT_GOAL_TIME_TOLERANCE_S);
}

#[test]
fn goal_refusals_carry_control_msgs_error_codes() {
    let model = RobotModel::parol6();
    let q = standby();
    let code = |g: &FollowJointTrajectoryGoal| check_goal(&model, g, &q, NOW_NS).unwrap_err().error_code;
    let mut g = small_goal();
    g.trajectory.joint_names[0] = "shoulder".into();
    assert_eq!(code(&g), INVALID_JOINTS);
    let mut g = small_goal();
    g.multi_dof_trajectory.joint_names = vec!["base".into()];
    assert_eq!(code(&g), INVALID_GOAL);
    let mut g = small_goal();
    g.component_goal_tolerance = vec![JointComponentTolerance { joint_name: "J1".into(), ..Default::default() }];
    assert_eq!(code(&g), INVALID_JOINTS);
    let mut g = small_goal();
    g.path_tolerance = vec![JointTolerance { name: "J9".into(), ..Default::default() }];
    assert_eq!(code(&g), INVALID_JOINTS);
    let mut g = small_goal();
    g.goal_tolerance = vec![JointTolerance { name: "J2".into(), position: f64::NAN, ..Default::default() }];
    assert_eq!(code(&g), INVALID_GOAL);
    let mut g = small_goal();
    g.trajectory.points[1].positions[2] = f64::NAN;
    assert_eq!(code(&g), INVALID_GOAL);
    let mut g = small_goal();
    g.trajectory.points[1].positions[0] = 10.0;
    assert_eq!(code(&g), INVALID_GOAL);
    let mut g = small_goal();
    g.trajectory.points[1].time_from_start = Duration::default();
    assert_eq!(code(&g), INVALID_GOAL);
    let mut g = small_goal();
    g.trajectory.header.stamp = Time::from_unix_ns(NOW_NS - 5_000_000_000);
    assert_eq!(code(&g), OLD_HEADER_TIMESTAMP);
    let mut g = small_goal();
    g.trajectory.header.stamp = Time::from_unix_ns(NOW_NS + 5_000_000_000);
    assert_eq!(code(&g), INVALID_GOAL);
    let mut g = small_goal();
    g.goal_time_tolerance = Duration { sec: -1, nanosec: 0 };
    assert_eq!(code(&g), INVALID_GOAL);
    // a stamp just now and a goal tolerance on J1 are fine
    let mut g = small_goal();
    g.trajectory.header.stamp = Time::from_unix_ns(NOW_NS);
    g.goal_tolerance = vec![JointTolerance { name: "J1".into(), position: 0.01, velocity: -1.0, acceleration: 0.0 }];
    let plan = check_goal(&model, &g, &q, NOW_NS).unwrap();
    assert_eq!(plan.tolerances.goal.position_rad[0], Some(0.01));
}

#[test]
fn path_tolerance_and_goal_time_tolerance_of_a_goal_are_kept() {
    let mut g = small_goal();
    g.path_tolerance = vec![
        JointTolerance { name: "J3".into(), position: 0.02, velocity: 0.0, acceleration: 0.0 },
        JointTolerance { name: "J1".into(), position: -1.0, velocity: 0.0, acceleration: 0.0 },
        JointTolerance { name: "J2".into(), position: 0.0, velocity: 0.0, acceleration: 0.0 },
        JointTolerance { name: "J5".into(), position: 0.0, velocity: 0.3, acceleration: 2.0 },
    ];
    g.goal_time_tolerance = Duration { sec: 1, nanosec: 500_000_000 };
    let plan = check_goal(&RobotModel::parol6(), &g, &standby(), NOW_NS).unwrap();
    assert_eq!(plan.tolerances.path.position_rad, vec![None, None, Some(0.02), None, None, None]);
    assert_eq!(plan.tolerances.path.velocity_rad_s, vec![None, None, None, None, Some(0.3), None]);
    assert_eq!(plan.tolerances.goal_time_s, 1.5);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Any bytes: every action decoder returns, and what decodes re-encodes to itself.
    #[test]
    fn action_decoders_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let mut b = vec![0, 1, 0, 0];
        b.extend_from_slice(&bytes);
        if let Ok(m) = cdr::decode::<SendGoalRequest>(&b) {
            let again = cdr::encode(&m).unwrap();
            prop_assert_eq!(cdr::encode(&cdr::decode::<SendGoalRequest>(&again).unwrap()).unwrap(), again);
        }
        let errors = [
            cdr::decode::<GetResultRequest>(&b).err(),
            cdr::decode::<CancelGoalRequest>(&b).err(),
            cdr::decode::<GoalStatusArray>(&b).err(),
            cdr::decode::<CancelGoalResponse>(&b).err(),
        ];
        for e in errors.into_iter().flatten() {
            prop_assert!(!e.to_string().is_empty());
        }
    }

    /// A goal with a J1 target anywhere: accepted within the limits and speed, else refused with
    /// a code, never planned outside the limits.
    #[test]
    fn any_single_point_goal_is_planned_inside_the_limits_or_refused(dq in -4.0f64..4.0, t in 0.05f64..5.0) {
        let model = RobotModel::parol6();
        let q0 = standby();
        let mut q1 = q0.clone();
        q1[0] += dq;
        let mut g = small_goal();
        g.trajectory.points = vec![point(&q1, t)];
        match check_goal(&model, &g, &q0, NOW_NS) {
            Ok(p) => prop_assert!(model.limits.contains(&p.final_q)),
            Err(e) => prop_assert!(e.error_code == INVALID_GOAL, "{e}"),
        }
    }
}

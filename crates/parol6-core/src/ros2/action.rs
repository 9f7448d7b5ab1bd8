//! The `control_msgs/action/FollowJointTrajectory` action (what MoveIt's simple controller
//! manager sends to) as `rmw_zenoh` carries it: three services (`<name>/_action/send_goal`,
//! `get_result`, `cancel_goal`) and two topics (`<name>/_action/feedback`, `_action/status`),
//! their request / response / message types field for field as the `.action`, `.srv` and
//! `.msg` files define them (control_msgs with the component tolerances, as in ROS 2 Jazzy),
//! their type names and RIHS01 hashes, and the check of a goal before its trajectory takes the
//! same path as one on `/parol6/joint_trajectory` ([`plan_trajectory`](super::plan_trajectory)).
//!
//! A goal is refused with control_msgs' error codes: [`INVALID_JOINTS`] for joint names that
//! are not the robot's (trajectory, tolerances), [`OLD_HEADER_TIMESTAMP`] for a trajectory that
//! ended before it arrived, [`INVALID_GOAL`] for the rest (a multi-DOF trajectory, a tolerance
//! that is not a finite non-negative number, a start in the future, every refusal of the
//! trajectory check and the pre-flight).

use serde::{Deserialize, Serialize};

use super::TypeInfo;
use super::cdr::{Message, Shape, up_to_joints, up_to_points};
use super::msgs::{Duration, POINT};
use super::msgs::{HEADER, Header, JointTrajectory, TIME, Time, Transform, VALUES, Vector3, XYZ, XYZW};

/// `control_msgs/action/FollowJointTrajectory` `Result.SUCCESSFUL`.
pub const SUCCESSFUL: i32 = 0;
/// `Result.INVALID_GOAL`.
pub const INVALID_GOAL: i32 = -1;
/// `Result.INVALID_JOINTS`.
pub const INVALID_JOINTS: i32 = -2;
/// `Result.OLD_HEADER_TIMESTAMP`.
pub const OLD_HEADER_TIMESTAMP: i32 = -3;
/// `Result.PATH_TOLERANCE_VIOLATED`.
pub const PATH_TOLERANCE_VIOLATED: i32 = -4;
/// `Result.GOAL_TOLERANCE_VIOLATED`.
pub const GOAL_TOLERANCE_VIOLATED: i32 = -5;

/// `action_msgs/msg/GoalStatus` values.
pub mod status {
    /// Not known (a goal never accepted).
    pub const UNKNOWN: i8 = 0;
    /// Accepted, not started.
    pub const ACCEPTED: i8 = 1;
    /// Running.
    pub const EXECUTING: i8 = 2;
    /// A cancel was asked for, the motion is being stopped.
    pub const CANCELING: i8 = 3;
    /// Ran to its end within the goal tolerance.
    pub const SUCCEEDED: i8 = 4;
    /// Cancelled.
    pub const CANCELED: i8 = 5;
    /// Ended early or refused.
    pub const ABORTED: i8 = 6;
}

/// `action_msgs/srv/CancelGoal` return codes.
pub mod cancel {
    /// Cancelling.
    pub const ERROR_NONE: i8 = 0;
    /// Refused.
    pub const ERROR_REJECTED: i8 = 1;
    /// No such goal.
    pub const ERROR_UNKNOWN_GOAL_ID: i8 = 2;
    /// The goal has already ended.
    pub const ERROR_GOAL_TERMINATED: i8 = 3;
}

/// The default action name: `<controller>/<action_ns>` of a `moveit_simple_controller_manager`
/// controller named `parol6_arm_controller` with `action_ns: follow_joint_trajectory` (what a
/// ros2_control `joint_trajectory_controller` of that name serves).
pub const DEFAULT_ACTION_NAME: &str = "/parol6_arm_controller/follow_joint_trajectory";

/// `control_msgs/action/FollowJointTrajectory_SendGoal` (a service).
pub const SEND_GOAL: TypeInfo = TypeInfo {
    ros_name: "control_msgs/action/FollowJointTrajectory_SendGoal",
    dds_name: "control_msgs::action::dds_::FollowJointTrajectory_SendGoal_",
    hash: "RIHS01_4915b9909747df962256f0fe9a7dc832ba6e7ec2c5e827c5ba239b7b451d52aa",
};

/// `control_msgs/action/FollowJointTrajectory_GetResult` (a service).
pub const GET_RESULT: TypeInfo = TypeInfo {
    ros_name: "control_msgs/action/FollowJointTrajectory_GetResult",
    dds_name: "control_msgs::action::dds_::FollowJointTrajectory_GetResult_",
    hash: "RIHS01_a42b878fc686578b092e626c27ba796dab419d9d5f3275920e4eca7769062539",
};

/// `control_msgs/action/FollowJointTrajectory_FeedbackMessage` ([`super::feedback::FeedbackMessage`]).
pub const FEEDBACK_MESSAGE: TypeInfo = TypeInfo {
    ros_name: "control_msgs/action/FollowJointTrajectory_FeedbackMessage",
    dds_name: "control_msgs::action::dds_::FollowJointTrajectory_FeedbackMessage_",
    hash: "RIHS01_88e16acd364ad5bc90b661a4f77fec9ab40874e8eeaaf4673e9cd78e41038b99",
};

/// `action_msgs/srv/CancelGoal` (a service).
pub const CANCEL_GOAL: TypeInfo = TypeInfo {
    ros_name: "action_msgs/srv/CancelGoal",
    dds_name: "action_msgs::srv::dds_::CancelGoal_",
    hash: "RIHS01_6a5f062d4e445bb8f6dfeb28d8ba83845efc58238741896b43c9dc8e1cffb775",
};

/// `action_msgs/msg/GoalStatusArray`.
pub const GOAL_STATUS_ARRAY: TypeInfo = TypeInfo {
    ros_name: "action_msgs/msg/GoalStatusArray",
    dds_name: "action_msgs::msg::dds_::GoalStatusArray_",
    hash: "RIHS01_ffe5f95b22109dd7ef2199ccf443f5b6be19c157618c8fc12f4d9a2b5fc6c4dc",
};

/// The service and topic names of action `name` (e.g. `/parol6_arm_controller/follow_joint_trajectory`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ActionNames {
    /// `<name>/_action/send_goal`.
    pub send_goal: String,
    /// `<name>/_action/get_result`.
    pub get_result: String,
    /// `<name>/_action/cancel_goal`.
    pub cancel_goal: String,
    /// `<name>/_action/feedback`.
    pub feedback: String,
    /// `<name>/_action/status`.
    pub status: String,
}

impl ActionNames {
    /// The names under `name` (a leading `/` added when missing, a trailing one dropped).
    pub fn of(name: &str) -> Self {
        let base = format!("/{}", name.trim_matches('/'));
        let sub = |s: &str| format!("{base}/_action/{s}");
        Self {
            send_goal: sub("send_goal"),
            get_result: sub("get_result"),
            cancel_goal: sub("cancel_goal"),
            feedback: sub("feedback"),
            status: sub("status"),
        }
    }
}

/// Is `name` a usable action name: non-empty ROS name tokens (letters, digits, `_`, not
/// starting with a digit) separated by `/`.
pub fn valid_action_name(name: &str) -> bool {
    let inner = name.strip_prefix('/').unwrap_or(name);
    !inner.is_empty()
        && inner.split('/').all(|t| {
            t.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        })
}

/// `unique_identifier_msgs/msg/UUID`: 16 bytes, no count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub struct Uuid {
    /// The bytes.
    pub uuid: [u8; 16],
}

impl Uuid {
    /// As hex, for logs.
    pub fn hex(&self) -> String {
        self.uuid.iter().map(|b| format!("{b:02x}")).collect()
    }
}

/// `geometry_msgs/msg/Twist`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Twist {
    /// m/s.
    pub linear: Vector3,
    /// rad/s.
    pub angular: Vector3,
}

/// `trajectory_msgs/msg/MultiDOFJointTrajectoryPoint`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct MultiDofPoint {
    /// One per joint.
    #[serde(deserialize_with = "up_to_joints")]
    pub transforms: Vec<Transform>,
    /// Empty or one per joint.
    #[serde(deserialize_with = "up_to_joints")]
    pub velocities: Vec<Twist>,
    /// Empty or one per joint.
    #[serde(deserialize_with = "up_to_joints")]
    pub accelerations: Vec<Twist>,
    /// From the trajectory's start.
    pub time_from_start: Duration,
}

/// `trajectory_msgs/msg/MultiDOFJointTrajectory` (we have no multi-DOF joints: it must be empty).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct MultiDofTrajectory {
    /// Stamp and frame.
    pub header: Header,
    /// Joint names.
    #[serde(deserialize_with = "up_to_joints")]
    pub joint_names: Vec<String>,
    /// Points.
    #[serde(deserialize_with = "up_to_points")]
    pub points: Vec<MultiDofPoint>,
}

/// `control_msgs/msg/JointTolerance` (0: the server's default, -1: none).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct JointTolerance {
    /// Joint.
    pub name: String,
    /// rad.
    pub position: f64,
    /// rad/s.
    pub velocity: f64,
    /// rad/s².
    pub acceleration: f64,
}

/// `control_msgs/msg/JointComponentTolerance` (for multi-DOF joints).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct JointComponentTolerance {
    /// Joint.
    pub joint_name: String,
    /// `X_AXIS` 1 … `ROTATION` 5.
    pub component: u16,
    /// Position tolerance.
    pub position: f64,
    /// Velocity tolerance.
    pub velocity: f64,
    /// Acceleration tolerance.
    pub acceleration: f64,
}

/// `control_msgs/action/FollowJointTrajectory_Goal`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FollowJointTrajectoryGoal {
    /// The joint trajectory.
    pub trajectory: JointTrajectory,
    /// Multi-DOF joints' trajectory (must be empty).
    pub multi_dof_trajectory: MultiDofTrajectory,
    /// Tolerances while moving.
    #[serde(deserialize_with = "up_to_joints")]
    pub path_tolerance: Vec<JointTolerance>,
    /// Multi-DOF tolerances while moving (must be empty).
    #[serde(deserialize_with = "up_to_joints")]
    pub component_path_tolerance: Vec<JointComponentTolerance>,
    /// Tolerances at the end.
    #[serde(deserialize_with = "up_to_joints")]
    pub goal_tolerance: Vec<JointTolerance>,
    /// Multi-DOF tolerances at the end (must be empty).
    #[serde(deserialize_with = "up_to_joints")]
    pub component_goal_tolerance: Vec<JointComponentTolerance>,
    /// Leeway after the trajectory's end.
    pub goal_time_tolerance: Duration,
}

/// `FollowJointTrajectory_SendGoal_Request`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct SendGoalRequest {
    /// The client's id of the goal.
    pub goal_id: Uuid,
    /// The goal.
    pub goal: FollowJointTrajectoryGoal,
}

/// `FollowJointTrajectory_SendGoal_Response`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct SendGoalResponse {
    /// Accepted.
    pub accepted: bool,
    /// When it was accepted.
    pub stamp: Time,
}

/// `FollowJointTrajectory_GetResult_Request` (also the body of a cancel's id).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct GetResultRequest {
    /// The goal.
    pub goal_id: Uuid,
}

/// `control_msgs/action/FollowJointTrajectory_Result`.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct FollowJointTrajectoryResult {
    /// [`SUCCESSFUL`] or an error code.
    pub error_code: i32,
    /// Why.
    pub error_string: String,
}

/// `FollowJointTrajectory_GetResult_Response`.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct GetResultResponse {
    /// A [`status`] value.
    pub status: i8,
    /// The result.
    pub result: FollowJointTrajectoryResult,
}

/// `action_msgs/msg/GoalInfo`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct GoalInfo {
    /// The goal (all zero in a cancel: every goal).
    pub goal_id: Uuid,
    /// When it was accepted (in a cancel: goals accepted at or before it, zero: none by time).
    pub stamp: Time,
}

/// `action_msgs/srv/CancelGoal_Request`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct CancelGoalRequest {
    /// Which goals.
    pub goal_info: GoalInfo,
}

/// `action_msgs/srv/CancelGoal_Response`.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct CancelGoalResponse {
    /// A [`cancel`] code.
    pub return_code: i8,
    /// The goals now cancelling.
    #[serde(deserialize_with = "up_to_joints")]
    pub goals_canceling: Vec<GoalInfo>,
}

/// `action_msgs/msg/GoalStatus`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct GoalStatus {
    /// The goal.
    pub goal_info: GoalInfo,
    /// A [`status`] value.
    pub status: i8,
}

/// `action_msgs/msg/GoalStatusArray`.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct GoalStatusArray {
    /// The goals the server knows.
    #[serde(deserialize_with = "up_to_points")]
    pub status_list: Vec<GoalStatus>,
}

pub(crate) const UUID: Shape = Shape::Struct(&[("uuid", Shape::Leaf)]);
const TRAJECTORY: Shape = Shape::Struct(&[("header", HEADER), ("joint_names", VALUES), ("points", Shape::Seq(&POINT))]);
const TWIST: Shape = Shape::Struct(&[("linear", XYZ), ("angular", XYZ)]);
pub(crate) const MULTI_DOF_POINT: Shape = Shape::Struct(&[
    ("transforms", Shape::Seq(&Shape::Struct(&[("translation", XYZ), ("rotation", XYZW)]))),
    ("velocities", Shape::Seq(&TWIST)),
    ("accelerations", Shape::Seq(&TWIST)),
    ("time_from_start", TIME),
]);
const TOLERANCE: Shape = Shape::Seq(&Shape::Struct(&[
    ("name", Shape::Leaf),
    ("position", Shape::Leaf),
    ("velocity", Shape::Leaf),
    ("acceleration", Shape::Leaf),
]));
const COMPONENT_TOLERANCE: Shape = Shape::Seq(&Shape::Struct(&[
    ("joint_name", Shape::Leaf),
    ("component", Shape::Leaf),
    ("position", Shape::Leaf),
    ("velocity", Shape::Leaf),
    ("acceleration", Shape::Leaf),
]));
const GOAL_INFO: Shape = Shape::Struct(&[("goal_id", UUID), ("stamp", TIME)]);

impl Message for SendGoalRequest {
    const SHAPE: &'static Shape = &Shape::Struct(&[
        ("goal_id", UUID),
        (
            "goal",
            Shape::Struct(&[
                ("trajectory", TRAJECTORY),
                (
                    "multi_dof_trajectory",
                    Shape::Struct(&[
                        ("header", HEADER),
                        ("joint_names", VALUES),
                        ("points", Shape::Seq(&MULTI_DOF_POINT)),
                    ]),
                ),
                ("path_tolerance", TOLERANCE),
                ("component_path_tolerance", COMPONENT_TOLERANCE),
                ("goal_tolerance", TOLERANCE),
                ("component_goal_tolerance", COMPONENT_TOLERANCE),
                ("goal_time_tolerance", TIME),
            ]),
        ),
    ]);
}

impl Message for SendGoalResponse {
    const SHAPE: &'static Shape = &Shape::Struct(&[("accepted", Shape::Leaf), ("stamp", TIME)]);
}

impl Message for GetResultRequest {
    const SHAPE: &'static Shape = &Shape::Struct(&[("goal_id", UUID)]);
}

impl Message for GetResultResponse {
    const SHAPE: &'static Shape = &Shape::Struct(&[
        ("status", Shape::Leaf),
        ("result", Shape::Struct(&[("error_code", Shape::Leaf), ("error_string", Shape::Leaf)])),
    ]);
}

impl Message for CancelGoalRequest {
    const SHAPE: &'static Shape = &Shape::Struct(&[("goal_info", GOAL_INFO)]);
}

impl Message for CancelGoalResponse {
    const SHAPE: &'static Shape =
        &Shape::Struct(&[("return_code", Shape::Leaf), ("goals_canceling", Shape::Seq(&GOAL_INFO))]);
}

impl Message for GoalStatusArray {
    const SHAPE: &'static Shape = &Shape::Struct(&[(
        "status_list",
        Shape::Seq(&Shape::Struct(&[("goal_info", GOAL_INFO), ("status", Shape::Leaf)])),
    )]);
}

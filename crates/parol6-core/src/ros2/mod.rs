//! ROS 2 messages as `rmw_zenoh` carries them, without any network code: the CDR payloads
//! (XCDR1, a 4-byte encapsulation header, then the plain CDR body), the type names and RIHS01
//! type hashes that the key expressions carry, the key expressions, liveliness tokens, QoS
//! strings and sample attachments of `rmw_zenoh` (its Jazzy conventions), and the check that
//! turns an incoming `trajectory_msgs/msg/JointTrajectory` into a program that the same
//! pre-flight as every program checks.
//!
//! - [`cdr`]: encode any message; decode the ones we accept, bounded (a size cap before anything
//!   is read, a count cap on every sequence), never panicking, errors naming the field and the
//!   byte;
//! - [`msgs`]: the message types (`sensor_msgs/msg/JointState`, `tf2_msgs/msg/TFMessage`,
//!   `std_msgs/msg/String`, `trajectory_msgs/msg/JointTrajectory`) and builders from our state;
//! - [`graph`]: key expressions, liveliness tokens, QoS strings, GIDs and attachments;
//! - [`action`]: the `control_msgs/action/FollowJointTrajectory` action's services and topics
//!   (types, names, hashes), [`goal`]: a goal's own checks before its trajectory takes the
//!   [`trajectory`] path, [`feedback`]: the feedback message a running goal gets,
//!   [`tolerance`]: its path and goal tolerances (and `goal_time_tolerance`) while it runs;
//! - [`trajectory`]: validation of an incoming trajectory and its conversion to a [`Program`]
//!   (`move_joints` steps with `duration_s`), pre-flight included.
//!
//! The type hashes are those of ROS 2 Jazzy's interfaces, computed per REP-2011 from the type
//! descriptions (sorted referenced types, default values left out, JSON with `", "` and `": "`
//! separators, SHA-256); the Python peer of `crates/parol6-app/tests/ros2_zenoh.rs` recomputes
//! them independently. Those of `sensor_msgs/msg/JointState` and
//! `trajectory_msgs/msg/JointTrajectory` are what a real `ros2 topic info --verbose` prints; those
//! of `std_msgs/msg/String` and `tf2_msgs/msg/TFMessage` what other rmw_zenoh-compatible projects
//! use.
//!
//! [`Program`]: crate::program::Program

pub mod action;
pub mod cdr;
pub mod feedback;
pub mod goal;
pub mod graph;
pub mod msgs;
pub mod tolerance;
pub mod trajectory;

#[cfg(test)]
mod action_tests;
#[cfg(test)]
mod tests;

pub use cdr::CdrError;
pub use trajectory::{TrajectoryError, TrajectoryPlan, plan_trajectory};

/// A ROS 2 message type: its ROS name, the DDS name `rmw_zenoh` puts in key expressions, and
/// its RIHS01 type hash.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TypeInfo {
    /// ROS name, e.g. `sensor_msgs/msg/JointState`.
    pub ros_name: &'static str,
    /// DDS name, e.g. `sensor_msgs::msg::dds_::JointState_`.
    pub dds_name: &'static str,
    /// `RIHS01_` and the SHA-256 of the type description, hex.
    pub hash: &'static str,
}

/// `sensor_msgs/msg/JointState`.
pub const JOINT_STATE: TypeInfo = TypeInfo {
    ros_name: "sensor_msgs/msg/JointState",
    dds_name: "sensor_msgs::msg::dds_::JointState_",
    hash: "RIHS01_a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e",
};

/// `tf2_msgs/msg/TFMessage`.
pub const TF_MESSAGE: TypeInfo = TypeInfo {
    ros_name: "tf2_msgs/msg/TFMessage",
    dds_name: "tf2_msgs::msg::dds_::TFMessage_",
    hash: "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087",
};

/// `std_msgs/msg/String`.
pub const STRING: TypeInfo = TypeInfo {
    ros_name: "std_msgs/msg/String",
    dds_name: "std_msgs::msg::dds_::String_",
    hash: "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
};

/// `trajectory_msgs/msg/JointTrajectory`.
pub const JOINT_TRAJECTORY: TypeInfo = TypeInfo {
    ros_name: "trajectory_msgs/msg/JointTrajectory",
    dds_name: "trajectory_msgs::msg::dds_::JointTrajectory_",
    hash: "RIHS01_179b33eba59d676f6d967ac71fe35e7ca2f64b2f3928f4a018cec115e213796e",
};

/// Topic of the joint states.
pub const TOPIC_JOINT_STATES: &str = "/joint_states";
/// Topic of the link transforms.
pub const TOPIC_TF: &str = "/tf";
/// Topic of the URDF (transient local).
pub const TOPIC_ROBOT_DESCRIPTION: &str = "/robot_description";
/// Topic the trajectories arrive on.
pub const TOPIC_JOINT_TRAJECTORY: &str = "/parol6/joint_trajectory";
/// Topic the trajectories' results (accepted, refused with the reason, done, failed) go out
/// on, as `std_msgs/msg/String` holding one JSON object.
pub const TOPIC_TRAJECTORY_RESULT: &str = "/parol6/trajectory_result";
/// The node's name.
pub const NODE_NAME: &str = "parol6";

//! The ROS 2 messages we send and receive, field for field as their `.msg` files define them
//! (the CDR body is the fields in order), and builders from our own state.

use serde::{Deserialize, Serialize};

use super::cdr::{MAX_JOINTS, Message, Shape, up_to_joints, up_to_points, up_to_transforms};
use crate::telemetry::schema::FrameTransform;

/// `builtin_interfaces/msg/Time`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Time {
    /// Seconds since the Unix epoch.
    pub sec: i32,
    /// Nanoseconds, 0–999 999 999.
    pub nanosec: u32,
}

impl Time {
    /// From nanoseconds since the Unix epoch (saturating at `i32::MAX` seconds).
    pub fn from_unix_ns(ns: u64) -> Self {
        let sec = i32::try_from(ns / 1_000_000_000).unwrap_or(i32::MAX);
        Self { sec, nanosec: (ns % 1_000_000_000) as u32 }
    }
}

/// `builtin_interfaces/msg/Duration`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Duration {
    /// Seconds (may be negative).
    pub sec: i32,
    /// Nanoseconds, 0–999 999 999.
    pub nanosec: u32,
}

impl Duration {
    /// In seconds; `None` when `nanosec` is not below 10⁹.
    pub fn as_secs_f64(&self) -> Option<f64> {
        (self.nanosec < 1_000_000_000).then(|| f64::from(self.sec) + f64::from(self.nanosec) * 1e-9)
    }

    /// The duration of `s` seconds, to the nanosecond (saturating).
    pub fn from_secs_f64(s: f64) -> Self {
        let ns = (s * 1e9).round();
        let ns = if ns.is_finite() { ns.clamp(i32::MIN as f64 * 1e9, i32::MAX as f64 * 1e9) } else { 0.0 } as i64;
        Self { sec: ns.div_euclid(1_000_000_000) as i32, nanosec: ns.rem_euclid(1_000_000_000) as u32 }
    }
}

/// `std_msgs/msg/Header`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Header {
    /// Time of the data.
    pub stamp: Time,
    /// Frame the data is in.
    pub frame_id: String,
}

/// `sensor_msgs/msg/JointState`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct JointState {
    /// Time of the measurement.
    pub header: Header,
    /// URDF joint names.
    #[serde(deserialize_with = "up_to_joints")]
    pub name: Vec<String>,
    /// Positions, rad.
    #[serde(deserialize_with = "up_to_joints")]
    pub position: Vec<f64>,
    /// Velocities, rad/s.
    #[serde(deserialize_with = "up_to_joints")]
    pub velocity: Vec<f64>,
    /// Efforts, N·m (empty when unknown).
    #[serde(deserialize_with = "up_to_joints")]
    pub effort: Vec<f64>,
}

/// `geometry_msgs/msg/Vector3`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Vector3 {
    /// x, m.
    pub x: f64,
    /// y, m.
    pub y: f64,
    /// z, m.
    pub z: f64,
}

/// `geometry_msgs/msg/Quaternion`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

/// `geometry_msgs/msg/Transform`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Transform {
    /// Translation, m.
    pub translation: Vector3,
    /// Rotation.
    pub rotation: Quaternion,
}

/// `geometry_msgs/msg/TransformStamped`: the child frame's pose in the header's frame.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TransformStamped {
    /// Time and parent frame.
    pub header: Header,
    /// Child frame.
    pub child_frame_id: String,
    /// Parent → child.
    pub transform: Transform,
}

/// `tf2_msgs/msg/TFMessage`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TfMessage {
    /// One per URDF joint.
    #[serde(deserialize_with = "up_to_transforms")]
    pub transforms: Vec<TransformStamped>,
}

/// `std_msgs/msg/String`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct StringMsg {
    /// The text.
    pub data: String,
}

/// `trajectory_msgs/msg/JointTrajectoryPoint`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct JointTrajectoryPoint {
    /// Positions, rad, in the order of the trajectory's `joint_names`.
    #[serde(deserialize_with = "up_to_joints")]
    pub positions: Vec<f64>,
    /// Velocities, rad/s (empty or one per joint).
    #[serde(deserialize_with = "up_to_joints")]
    pub velocities: Vec<f64>,
    /// Accelerations, rad/s² (empty or one per joint).
    #[serde(deserialize_with = "up_to_joints")]
    pub accelerations: Vec<f64>,
    /// Efforts (empty or one per joint).
    #[serde(deserialize_with = "up_to_joints")]
    pub effort: Vec<f64>,
    /// When the point is to be reached, from the trajectory's start.
    pub time_from_start: Duration,
}

/// `trajectory_msgs/msg/JointTrajectory`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct JointTrajectory {
    /// Stamp (a start time; ours starts on arrival) and frame.
    pub header: Header,
    /// URDF joint names, in any order.
    #[serde(deserialize_with = "up_to_joints")]
    pub joint_names: Vec<String>,
    /// The points.
    #[serde(deserialize_with = "up_to_points")]
    pub points: Vec<JointTrajectoryPoint>,
}

pub(crate) const TIME: Shape = Shape::Struct(&[("sec", Shape::Leaf), ("nanosec", Shape::Leaf)]);
pub(crate) const HEADER: Shape = Shape::Struct(&[("stamp", TIME), ("frame_id", Shape::Leaf)]);
pub(crate) const VALUES: Shape = Shape::Seq(&Shape::Leaf);
pub(crate) const XYZ: Shape = Shape::Struct(&[("x", Shape::Leaf), ("y", Shape::Leaf), ("z", Shape::Leaf)]);
pub(crate) const XYZW: Shape =
    Shape::Struct(&[("x", Shape::Leaf), ("y", Shape::Leaf), ("z", Shape::Leaf), ("w", Shape::Leaf)]);
const STAMPED: Shape = Shape::Struct(&[
    ("header", HEADER),
    ("child_frame_id", Shape::Leaf),
    ("transform", Shape::Struct(&[("translation", XYZ), ("rotation", XYZW)])),
]);
pub(crate) const POINT: Shape = Shape::Struct(&[
    ("positions", VALUES),
    ("velocities", VALUES),
    ("accelerations", VALUES),
    ("effort", VALUES),
    ("time_from_start", TIME),
]);

impl Message for JointState {
    const SHAPE: &'static Shape = &Shape::Struct(&[
        ("header", HEADER),
        ("name", VALUES),
        ("position", VALUES),
        ("velocity", VALUES),
        ("effort", VALUES),
    ]);
}

impl Message for TfMessage {
    const SHAPE: &'static Shape = &Shape::Struct(&[("transforms", Shape::Seq(&STAMPED))]);
}

impl Message for StringMsg {
    const SHAPE: &'static Shape = &Shape::Struct(&[("data", Shape::Leaf)]);
}

impl Message for JointTrajectory {
    const SHAPE: &'static Shape =
        &Shape::Struct(&[("header", HEADER), ("joint_names", VALUES), ("points", Shape::Seq(&POINT))]);
}

impl JointState {
    /// The state of the joints `names` at `stamp` (frame id empty, as ROS drivers send it);
    /// `effort` may be empty.
    pub fn new(stamp: Time, names: &[String], position: &[f64], velocity: &[f64], effort: &[f64]) -> Self {
        let n = names.len().min(MAX_JOINTS);
        let take = |v: &[f64]| v.iter().take(n).copied().collect::<Vec<f64>>();
        Self {
            header: Header { stamp, frame_id: String::new() },
            name: names.iter().take(n).cloned().collect(),
            position: take(position),
            velocity: take(velocity),
            effort: take(effort),
        }
    }
}

impl TfMessage {
    /// The transforms of our `/tf` (one per URDF joint, parent link → child link), stamped
    /// `stamp`.
    pub fn from_frames(frames: &[FrameTransform], stamp: Time) -> Self {
        let transforms = frames
            .iter()
            .map(|f| TransformStamped {
                header: Header { stamp, frame_id: f.parent_frame_id.clone() },
                child_frame_id: f.child_frame_id.clone(),
                transform: Transform {
                    translation: Vector3 { x: f.translation.x, y: f.translation.y, z: f.translation.z },
                    rotation: Quaternion { x: f.rotation.x, y: f.rotation.y, z: f.rotation.z, w: f.rotation.w },
                },
            })
            .collect();
        Self { transforms }
    }
}

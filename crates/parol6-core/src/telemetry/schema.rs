//! The JSON messages of our MCAP channels and their JSON schemas.
//!
//! `/tf`, `/tcp_pose` and `/events` use Foxglove's well-known schemas (`foxglove.FrameTransforms`,
//! `foxglove.PoseInFrame`, `foxglove.Log`), written here as JSON Schema documents with the
//! field names and types of Foxglove's published ones, so Foxglove and Lichtblick show them
//! (the 3D panel moves the URDF's links from `/tf`). `/joint_states` and `/joint_commands` use
//! the field names of ROS `sensor_msgs/JointState` (`header`, `name`, `position` rad,
//! `velocity` rad/s, `effort` N·m) plus a few of ours; `/robot_description` carries the URDF
//! text in `data` like ROS `std_msgs/String`. Every channel's message encoding is `json`, its
//! schema encoding `jsonschema`.

use serde::{Deserialize, Serialize};

/// Message encoding of every channel.
pub const MESSAGE_ENCODING: &str = "json";
/// Schema encoding of every channel.
pub const SCHEMA_ENCODING: &str = "jsonschema";

/// Schema name of `/tf`.
pub const FRAME_TRANSFORMS: &str = "foxglove.FrameTransforms";
/// Schema name of `/tcp_pose`.
pub const POSE_IN_FRAME: &str = "foxglove.PoseInFrame";
/// Schema name of `/events`.
pub const LOG: &str = "foxglove.Log";
/// Schema name of `/joint_states` and `/joint_commands`.
pub const JOINT_STATE: &str = "parol6.JointState";
/// Schema name of `/robot_description`.
pub const ROBOT_DESCRIPTION: &str = "std_msgs/String";
/// Schema name of `/link`.
pub const LINK_HEALTH: &str = "parol6.LinkHealth";

/// Name of the metadata record every recording carries.
pub const METADATA_NAME: &str = "parol6_studio";

/// A time stamp: seconds and nanoseconds since the Unix epoch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Time {
    /// Whole seconds.
    pub sec: u32,
    /// Nanoseconds, 0–999 999 999.
    pub nsec: u32,
}

impl Time {
    /// From nanoseconds since the epoch (saturating at u32 seconds).
    pub fn from_ns(ns: u64) -> Self {
        let sec = u32::try_from(ns / 1_000_000_000).unwrap_or(u32::MAX);
        Self { sec, nsec: (ns % 1_000_000_000) as u32 }
    }

    /// Nanoseconds since the epoch.
    pub fn as_ns(&self) -> u64 {
        u64::from(self.sec) * 1_000_000_000 + u64::from(self.nsec)
    }
}

/// ROS-style header.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Time of the sample.
    pub stamp: Time,
    /// Frame the data is in (the root link).
    pub frame_id: String,
}

/// The worst limit zone of a sample.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorstZone {
    /// 0-based joint.
    pub joint: usize,
    /// `warning` or `critical`.
    pub zone: String,
}

/// `/joint_states` (measured) and `/joint_commands` (commanded).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointStateMsg {
    /// Stamp and frame.
    pub header: Header,
    /// Joint names, chain order.
    pub name: Vec<String>,
    /// Positions, rad.
    pub position: Vec<f64>,
    /// Velocities, rad/s.
    pub velocity: Vec<f64>,
    /// Torques, N·m (empty when unknown: the robot reports none; commands carry none).
    pub effort: Vec<f64>,
    /// Accelerations, rad/s².
    pub acceleration: Vec<f64>,
    /// Tick counter of the backend.
    pub seq: u64,
    /// Motion clock of the backend, s.
    pub time_s: f64,
    /// Step rates reported by the controller, steps/s (robot only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps_per_s: Option<Vec<f64>>,
    /// Program step being run (absent when none: Foxglove's and Lichtblick's JSON-schema
    /// parsers refuse a nullable `"type": [T, "null"]`, so the schema has one type per field).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program_step: Option<usize>,
    /// Worst limit zone over the joints (absent when all are safe; older files hold `null`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_zone: Option<WorstZone>,
}

/// `foxglove.Vector3`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x, m.
    pub x: f64,
    /// y, m.
    pub y: f64,
    /// z, m.
    pub z: f64,
}

/// `foxglove.Quaternion`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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

/// `foxglove.FrameTransform`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameTransform {
    /// Time of the transform.
    pub timestamp: Time,
    /// Parent link.
    pub parent_frame_id: String,
    /// Child link.
    pub child_frame_id: String,
    /// Child origin in the parent frame, m.
    pub translation: Vector3,
    /// Child orientation in the parent frame.
    pub rotation: Quaternion,
}

/// `foxglove.FrameTransforms`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameTransforms {
    /// One per joint.
    pub transforms: Vec<FrameTransform>,
}

/// `foxglove.Pose`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position, m.
    pub position: Vector3,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `foxglove.PoseInFrame`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PoseInFrame {
    /// Time of the pose.
    pub timestamp: Time,
    /// Frame the pose is in (the root link).
    pub frame_id: String,
    /// The pose.
    pub pose: Pose,
}

/// `foxglove.Log`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LogMsg {
    /// Time of the event.
    pub timestamp: Time,
    /// 0 UNKNOWN, 1 DEBUG, 2 INFO, 3 WARNING, 4 ERROR, 5 FATAL.
    pub level: u8,
    /// Text.
    pub message: String,
    /// Source name.
    pub name: String,
    /// Source file (empty).
    pub file: String,
    /// Source line (0).
    pub line: u32,
}

/// `/robot_description`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobotDescription {
    /// URDF text.
    pub data: String,
}

/// `/link`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinkHealthMsg {
    /// Stamp and frame.
    pub header: Header,
    /// The health.
    #[serde(flatten)]
    pub health: super::sample::LinkHealth,
}

const TIME: &str = r#"{"type":"object","title":"time","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}}}"#;
const VECTOR3: &str = r#"{"title":"foxglove.Vector3","type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}}}"#;
const QUATERNION: &str = r#"{"title":"foxglove.Quaternion","type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},"w":{"type":"number"}}}"#;

fn header_schema() -> String {
    format!(r#"{{"type":"object","properties":{{"stamp":{TIME},"frame_id":{{"type":"string"}}}}}}"#)
}

/// JSON schema of `foxglove.FrameTransform`.
fn frame_transform_schema() -> String {
    format!(
        r#"{{"title":"foxglove.FrameTransform","description":"A transform between two reference frames in 3D space","type":"object","properties":{{"timestamp":{TIME},"parent_frame_id":{{"type":"string","description":"Name of the parent frame"}},"child_frame_id":{{"type":"string","description":"Name of the child frame"}},"translation":{VECTOR3},"rotation":{QUATERNION}}}}}"#
    )
}

/// The JSON schema text of a channel's schema name (`None` for a name we do not write).
pub fn schema_text(name: &str) -> Option<String> {
    let numbers = r#"{"type":"array","items":{"type":"number"}}"#;
    Some(match name {
        FRAME_TRANSFORMS => format!(
            r#"{{"title":"foxglove.FrameTransforms","description":"An array of FrameTransform messages","type":"object","properties":{{"transforms":{{"type":"array","items":{},"description":"Array of transforms"}}}}}}"#,
            frame_transform_schema()
        ),
        POSE_IN_FRAME => format!(
            r#"{{"title":"foxglove.PoseInFrame","description":"A timestamped pose for an object or reference frame in 3D space","type":"object","properties":{{"timestamp":{TIME},"frame_id":{{"type":"string"}},"pose":{{"title":"foxglove.Pose","type":"object","properties":{{"position":{VECTOR3},"orientation":{QUATERNION}}}}}}}}}"#
        ),
        LOG => format!(
            r#"{{"title":"foxglove.Log","description":"A log message","type":"object","properties":{{"timestamp":{TIME},"level":{{"title":"foxglove.LogLevel","description":"Log level","oneOf":[{{"title":"UNKNOWN","const":0}},{{"title":"DEBUG","const":1}},{{"title":"INFO","const":2}},{{"title":"WARNING","const":3}},{{"title":"ERROR","const":4}},{{"title":"FATAL","const":5}}]}},"message":{{"type":"string"}},"name":{{"type":"string"}},"file":{{"type":"string"}},"line":{{"type":"integer","minimum":0}}}}}}"#
        ),
        JOINT_STATE => format!(
            r#"{{"title":"parol6.JointState","description":"Joint positions (rad), velocities (rad/s), efforts (N·m) and accelerations (rad/s²) with sensor_msgs/JointState field names","type":"object","properties":{{"header":{},"name":{{"type":"array","items":{{"type":"string"}}}},"position":{numbers},"velocity":{numbers},"effort":{numbers},"acceleration":{numbers},"seq":{{"type":"integer","minimum":0}},"time_s":{{"type":"number"}},"steps_per_s":{numbers},"program_step":{{"type":"integer","minimum":0,"description":"Program step being run; absent when none"}},"worst_zone":{{"type":"object","description":"Worst limit zone over the joints; absent when all are safe","properties":{{"joint":{{"type":"integer"}},"zone":{{"type":"string"}}}}}}}}}}"#,
            header_schema()
        ),
        ROBOT_DESCRIPTION => {
            r#"{"title":"std_msgs/String","description":"The robot's URDF text","type":"object","properties":{"data":{"type":"string"}}}"#.to_string()
        }
        LINK_HEALTH => format!(
            r#"{{"title":"parol6.LinkHealth","type":"object","properties":{{"header":{},"state":{{"type":"string"}},"loop_rate_hz":{{"type":"number"}},"missing_replies":{{"type":"integer"}},"link_losses":{{"type":"integer"}},"estop_pressed":{{"type":"boolean"}}}}}}"#,
            header_schema()
        ),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_schema_is_json_with_its_title() {
        for name in [FRAME_TRANSFORMS, POSE_IN_FRAME, LOG, JOINT_STATE, ROBOT_DESCRIPTION, LINK_HEALTH] {
            let text = schema_text(name).unwrap_or_default();
            let v: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(v["title"], name, "{name}");
            assert_eq!(v["type"], "object", "{name}");
        }
        assert!(schema_text("foxglove.Unknown").is_none());
    }

    /// Every `"type"` in `v` (at any depth) that is not a single string, as its JSON path.
    fn multi_types(v: &serde_json::Value, path: &str, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Object(map) => {
                for (k, child) in map {
                    if k == "type" && !child.is_string() {
                        out.push(format!("{path}: {child}"));
                    }
                    multi_types(child, &format!("{path}/{k}"), out);
                }
            }
            serde_json::Value::Array(items) => {
                for (i, child) in items.iter().enumerate() {
                    multi_types(child, &format!("{path}/{i}"), out);
                }
            }
            _ => {}
        }
    }

    /// Lichtblick 1.10 (and Foxglove's `parseJsonSchema`) refused `/joint_states` with
    /// `Failed to parse channel schema on /joint_states, error: Error: Unsupported type
    /// ["integer","null"] for program_step`, so its Plot panel had no joint values.
    #[test]
    fn every_schema_has_one_type_per_field_as_foxglove_clients_parse_them() {
        for name in [FRAME_TRANSFORMS, POSE_IN_FRAME, LOG, JOINT_STATE, ROBOT_DESCRIPTION, LINK_HEALTH] {
            let text = schema_text(name).unwrap_or_default();
            let v: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let mut found = Vec::new();
            multi_types(&v, name, &mut found);
            assert!(found.is_empty(), "types that are not one string: {found:?}");
        }
    }

    /// The optional fields are left out when empty (the schema gives them one type, not null),
    /// and older files that hold `null` still read.
    #[test]
    fn joint_state_leaves_out_empty_optionals_and_reads_old_nulls() {
        let js = JointStateMsg {
            header: Header { stamp: Time::from_ns(0), frame_id: "base_link".into() },
            name: vec!["J1".into()],
            position: vec![0.5],
            velocity: vec![0.0],
            effort: vec![],
            acceleration: vec![0.0],
            seq: 1,
            time_s: 0.001,
            steps_per_s: None,
            program_step: None,
            worst_zone: None,
        };
        let text = serde_json::to_string(&js).unwrap_or_default();
        assert!(!text.contains("program_step") && !text.contains("worst_zone"), "{text}");
        let old = format!(r#"{},"program_step":null,"worst_zone":null}}"#, text.trim_end_matches('}'));
        let back: JointStateMsg = serde_json::from_str(&old).unwrap_or_else(|e| panic!("{old}: {e}"));
        assert_eq!(back, js);
    }

    #[test]
    fn time_splits_nanoseconds() {
        let t = Time::from_ns(1_700_000_000_123_456_789);
        assert_eq!((t.sec, t.nsec), (1_700_000_000, 123_456_789));
        assert_eq!(t.as_ns(), 1_700_000_000_123_456_789);
    }
}

//! `control_msgs/action/FollowJointTrajectory_FeedbackMessage` (what `<name>/_action/feedback`
//! carries while a goal runs), field for field as ROS 2 Jazzy's control_msgs (5.x) defines the
//! action's feedback: `header`, `joint_names`, `desired`, `actual` and `error`
//! (`trajectory_msgs/msg/JointTrajectoryPoint`, error = desired − actual), then the multi-DOF
//! fields (`multi_dof_joint_names`, `multi_dof_desired`, `multi_dof_actual`,
//! `multi_dof_error`), empty here. control_msgs 6 (Kilted, Rolling) adds `index` and
//! `multi_dof_index` fields, and with them another type hash: a client of that version does not
//! match our key expression.

use serde::{Deserialize, Serialize};

use super::action::{MULTI_DOF_POINT, MultiDofPoint, UUID, Uuid};
use super::cdr::{MAX_JOINTS, Message, Shape, up_to_joints};
use super::msgs::{Duration, HEADER, Header, JointTrajectoryPoint, POINT, Time, VALUES};

/// `control_msgs/action/FollowJointTrajectory_Feedback`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FollowJointTrajectoryFeedback {
    /// When the state was measured.
    pub header: Header,
    /// The joints of `desired`, `actual` and `error`.
    #[serde(deserialize_with = "up_to_joints")]
    pub joint_names: Vec<String>,
    /// The commanded state (time from the goal's start).
    pub desired: JointTrajectoryPoint,
    /// The measured state.
    pub actual: JointTrajectoryPoint,
    /// `desired − actual`.
    pub error: JointTrajectoryPoint,
    /// Multi-DOF joints (none).
    #[serde(deserialize_with = "up_to_joints")]
    pub multi_dof_joint_names: Vec<String>,
    /// Empty.
    pub multi_dof_desired: MultiDofPoint,
    /// Empty.
    pub multi_dof_actual: MultiDofPoint,
    /// Empty.
    pub multi_dof_error: MultiDofPoint,
}

/// `control_msgs/action/FollowJointTrajectory_FeedbackMessage`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FeedbackMessage {
    /// The goal it is about.
    pub goal_id: Uuid,
    /// Its feedback.
    pub feedback: FollowJointTrajectoryFeedback,
}

/// Positions (rad), velocities (rad/s) and accelerations (rad/s²) of the joints.
#[derive(Debug, Clone, Copy)]
pub struct JointsState<'a> {
    /// Positions, rad.
    pub q: &'a [f64],
    /// Velocities, rad/s.
    pub qd: &'a [f64],
    /// Accelerations, rad/s².
    pub qdd: &'a [f64],
}

impl FeedbackMessage {
    /// Goal `goal_id`'s feedback at `stamp`, `elapsed_s` after its start: the joints `names`
    /// (at most [`MAX_JOINTS`]) commanded at `desired` and measured at `actual`.
    pub fn new(
        goal_id: Uuid,
        stamp: Time,
        names: &[String],
        desired: JointsState<'_>,
        actual: JointsState<'_>,
        elapsed_s: f64,
    ) -> Self {
        let n = names.len().min(MAX_JOINTS);
        let t = Duration::from_secs_f64(elapsed_s);
        let take = |v: &[f64]| v.iter().take(n).copied().collect::<Vec<f64>>();
        let diff = |a: &[f64], b: &[f64]| a.iter().zip(b).take(n).map(|(a, b)| a - b).collect::<Vec<f64>>();
        let point = |s: JointsState<'_>| JointTrajectoryPoint {
            positions: take(s.q),
            velocities: take(s.qd),
            accelerations: take(s.qdd),
            effort: Vec::new(),
            time_from_start: t,
        };
        let error = JointTrajectoryPoint {
            positions: diff(desired.q, actual.q),
            velocities: diff(desired.qd, actual.qd),
            accelerations: diff(desired.qdd, actual.qdd),
            effort: Vec::new(),
            time_from_start: Duration::default(),
        };
        Self {
            goal_id,
            feedback: FollowJointTrajectoryFeedback {
                header: Header { stamp, frame_id: String::new() },
                joint_names: names.iter().take(n).cloned().collect(),
                desired: point(desired),
                actual: point(actual),
                error,
                ..Default::default()
            },
        }
    }
}

impl Message for FeedbackMessage {
    const SHAPE: &'static Shape = &Shape::Struct(&[
        ("goal_id", UUID),
        (
            "feedback",
            Shape::Struct(&[
                ("header", HEADER),
                ("joint_names", VALUES),
                ("desired", POINT),
                ("actual", POINT),
                ("error", POINT),
                ("multi_dof_joint_names", VALUES),
                ("multi_dof_desired", MULTI_DOF_POINT),
                ("multi_dof_actual", MULTI_DOF_POINT),
                ("multi_dof_error", MULTI_DOF_POINT),
            ]),
        ),
    ]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ros2::cdr;

    fn names() -> Vec<String> {
        ["J1", "J2", "J3", "J4", "J5", "J6"].iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn feedback_message_encodes_field_for_field_and_round_trips() {
        let (q_cmd, q) = ([0.1, 0.2, 0.3, 0.4, 0.5, 0.6], [0.1, 0.19, 0.3, 0.4, 0.5, 0.6]);
        let zero = [0.0; 6];
        let msg = FeedbackMessage::new(
            Uuid { uuid: [7; 16] },
            Time { sec: 1_700_000_000, nanosec: 5 },
            &names(),
            JointsState { q: &q_cmd, qd: &zero, qdd: &zero },
            JointsState { q: &q, qd: &zero, qdd: &zero },
            0.25,
        );
        let bytes = cdr::encode(&msg).unwrap();
        // header, uuid, stamp, frame_id "" (count 1 + NUL), joint_names count and "J1"
        assert_eq!(&bytes[..4], &[0, 1, 0, 0]);
        assert_eq!(&bytes[4..20], &[7; 16]);
        assert_eq!(&bytes[20..24], &1_700_000_000i32.to_le_bytes());
        assert_eq!(&bytes[24..28], &5u32.to_le_bytes());
        assert_eq!(&bytes[28..33], &[1, 0, 0, 0, 0]);
        assert_eq!(&bytes[36..40], &6u32.to_le_bytes());
        assert_eq!(&bytes[40..47], &[3, 0, 0, 0, b'J', b'1', 0]);
        // the end: three empty multi-DOF points (3 empty sequences and a zero duration each)
        assert_eq!(&bytes[bytes.len() - 60..], &[0u8; 60]);
        let back: FeedbackMessage = cdr::decode(&bytes).unwrap();
        assert_eq!(back, msg);
        assert!((back.feedback.error.positions[1] - 0.01).abs() < 1e-12);
        assert_eq!(back.feedback.desired.time_from_start, Duration { sec: 0, nanosec: 250_000_000 });
    }
}

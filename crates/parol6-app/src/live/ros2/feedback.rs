//! A running `FollowJointTrajectory` goal as the publishing thread sees it ([`GoalWatch`]):
//! every telemetry sample of the recorder's live outlet (the ones `/joint_states` is thinned
//! from) is checked against the goal's `path_tolerance` (measured against commanded position and
//! velocity),
//! and every [`FEEDBACK_EVERY_JOINT_STATES`]th `/joint_states` sample also goes out as the
//! goal's `FollowJointTrajectory_FeedbackMessage` on `<name>/_action/feedback`, with the same
//! header stamp as that joint state (20 Hz on the simulation and the robot).
//!
//! The publishing thread only records the first violation; the command thread, which owns the
//! run, looks at it every poll ([`super::commands`], 20 ms) and stops the arm through the same
//! path as a cancel (`Commands::stop_motion`: the program runner aborted, STOP to the backend).

use std::sync::{Mutex, MutexGuard, PoisonError};

use parol6_core::ros2::action::Uuid;
use parol6_core::ros2::feedback::{FeedbackMessage, JointsState};
use parol6_core::ros2::msgs::Time;
use parol6_core::ros2::tolerance::{JointMotion, JointTolerances, Violation, worst_violation};
use parol6_core::telemetry::TelemetrySample;

/// One feedback message per this many `/joint_states` messages (100 Hz / 5 = 20 Hz).
pub const FEEDBACK_EVERY_JOINT_STATES: u64 = 5;

/// The goal being watched, shared by the command thread (which starts and ends it) and the
/// publishing thread (which checks and reports it).
#[derive(Debug, Default)]
pub struct GoalWatch {
    inner: Mutex<Option<Watched>>,
}

#[derive(Debug)]
struct Watched {
    goal_id: Uuid,
    path_tolerance: JointTolerances,
    /// Path tolerance checked (until the trajectory's end).
    checking: bool,
    /// Motion clock of the first sample seen, s.
    start_s: Option<f64>,
    joint_states: u64,
    violation: Option<Violation>,
}

impl GoalWatch {
    fn lock(&self) -> MutexGuard<'_, Option<Watched>> {
        // a panic elsewhere leaves plain data behind: keep using it
        self.inner.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Goal `goal_id` starts: feedback from now on, its path tolerance checked.
    pub fn start(&self, goal_id: Uuid, path_tolerance: JointTolerances) {
        *self.lock() =
            Some(Watched { goal_id, path_tolerance, checking: true, start_s: None, joint_states: 0, violation: None });
    }

    /// Its trajectory has ended: the path tolerance is no longer checked (the goal tolerance
    /// is, by the command thread); feedback goes on until [`GoalWatch::end`].
    pub fn trajectory_ended(&self) {
        if let Some(w) = self.lock().as_mut() {
            w.checking = false;
        }
    }

    /// The goal has ended: no more feedback.
    pub fn end(&self) {
        *self.lock() = None;
    }

    /// The first path-tolerance violation seen, if one was.
    pub fn violation(&self) -> Option<Violation> {
        self.lock().as_ref().and_then(|w| w.violation)
    }

    /// One sample of the live outlet (`joint_state`: it is also sent on `/joint_states`, at
    /// `stamp`): checks the path tolerance; the feedback message to send, when one is due.
    pub fn observe(
        &self,
        s: &TelemetrySample,
        names: &[String],
        joint_state: bool,
        stamp: Time,
    ) -> Option<FeedbackMessage> {
        let mut guard = self.lock();
        let w = guard.as_mut()?;
        let start_s = *w.start_s.get_or_insert(s.time_s);
        let col = |f: fn(&parol6_core::telemetry::JointTelemetry) -> f64| s.joints.iter().map(f).collect::<Vec<f64>>();
        let (q_cmd, qd_cmd, q, qd) =
            (col(|j| j.cmd_q_rad), col(|j| j.cmd_qd_rad_s), col(|j| j.q_rad), col(|j| j.qd_rad_s));
        if w.checking && w.violation.is_none() {
            w.violation = worst_violation(
                &w.path_tolerance,
                JointMotion { q_rad: &q_cmd, qd_rad_s: &qd_cmd },
                JointMotion { q_rad: &q, qd_rad_s: &qd },
            );
        }
        if !joint_state {
            return None;
        }
        w.joint_states += 1;
        if (w.joint_states - 1) % FEEDBACK_EVERY_JOINT_STATES != 0 {
            return None;
        }
        let (qdd_cmd, qdd) = (col(|j| j.cmd_qdd_rad_s2), col(|j| j.qdd_rad_s2));
        Some(FeedbackMessage::new(
            w.goal_id,
            stamp,
            names,
            JointsState { q: &q_cmd, qd: &qd_cmd, qdd: &qdd_cmd },
            JointsState { q: &q, qd: &qd, qdd: &qdd },
            s.time_s - start_s,
        ))
    }
}

#[cfg(test)]
mod tests {
    use parol6_core::telemetry::{DriveKind, JointTelemetry, TelemetrySample};

    use super::*;

    fn sample(t_s: f64, lag_rad: f64) -> TelemetrySample {
        let j = JointTelemetry {
            cmd_q_rad: 0.5,
            cmd_qd_rad_s: 0.1,
            cmd_qdd_rad_s2: 0.0,
            q_rad: 0.5 - lag_rad,
            qd_rad_s: 0.1,
            qdd_rad_s2: 0.0,
            drive: 0.0,
            zone: parol6_core::limits::LimitZone::Safe,
        };
        TelemetrySample {
            seq: 0,
            time_s: t_s,
            joints: vec![j; 6],
            drive: DriveKind::TorqueNm,
            tcp: parol6_core::TcpPose {
                position_m: [0.0; 3],
                rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                rpy_rad: [0.0; 3],
                quaternion_wxyz: [1.0, 0.0, 0.0, 0.0],
            },
            worst_zone: None,
            program_step: None,
            link: None,
        }
    }

    fn names() -> Vec<String> {
        (1..=6).map(|i| format!("J{i}")).collect()
    }

    #[test]
    fn feedback_every_fifth_joint_state_and_path_tolerance_until_the_trajectory_ends() {
        let watch = GoalWatch::default();
        assert!(watch.observe(&sample(0.0, 0.0), &names(), true, Time::default()).is_none());
        let mut tol = JointTolerances::none(6);
        tol.position_rad[0] = Some(0.01);
        watch.start(Uuid { uuid: [3; 16] }, tol);
        let sent: Vec<FeedbackMessage> = (0..10)
            .filter_map(|k| watch.observe(&sample(1.0 + k as f64 * 0.01, 0.001), &names(), true, Time::default()))
            .collect();
        assert_eq!(sent.len(), 2);
        assert_eq!(sent[1].feedback.desired.time_from_start.nanosec, 50_000_000);
        assert!((sent[0].feedback.error.positions[0] - 0.001).abs() < 1e-12);
        assert_eq!(watch.violation(), None);
        watch.trajectory_ended();
        watch.observe(&sample(2.0, 0.5), &names(), false, Time::default());
        assert_eq!(watch.violation(), None, "after the trajectory's end the goal tolerance applies");
        watch.start(
            Uuid::default(),
            JointTolerances { position_rad: vec![Some(0.01); 6], velocity_rad_s: vec![None; 6] },
        );
        watch.observe(&sample(3.0, 0.02), &names(), false, Time::default());
        watch.observe(&sample(3.001, 0.5), &names(), false, Time::default());
        let v = watch.violation().unwrap();
        assert!((v.deviation + 0.02).abs() < 1e-12, "the first violation is kept: {v:?}");
        watch.end();
        assert!(watch.observe(&sample(4.0, 0.0), &names(), true, Time::default()).is_none());
    }
}

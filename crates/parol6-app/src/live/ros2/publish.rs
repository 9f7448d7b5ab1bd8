//! The publishing thread: takes the recorder's live outlet (bounded; the recorder never waits
//! on it and counts what it drops) and publishes `/joint_states` and `/tf`, thinned to their
//! rates on the backend's motion clock (the latest sample of each period; the simulation's
//! 1 kHz samples become 100 Hz joint states and 50 Hz transforms). While a
//! `FollowJointTrajectory` goal runs, every sample also goes to its [`GoalWatch`] (path
//! tolerance), and every fifth joint state is also sent as the goal's feedback.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use crossbeam_channel::RecvTimeoutError;
use parol6_core::RobotModel;
use parol6_core::ros2::cdr;
use parol6_core::ros2::msgs::{JointState, TfMessage, Time};
use parol6_core::telemetry::frames::TfFrames;
use parol6_core::telemetry::recorder::{LiveItem, LiveOutlet};
use parol6_core::telemetry::{DriveKind, TelemetrySample};

use super::feedback::GoalWatch;
use super::node::{Publisher, now_unix_ns};

/// `/joint_states` period on the motion clock, s (100 Hz: the robot's control rate).
pub const JOINT_STATES_PERIOD_S: f64 = 0.01;
/// `/tf` period on the motion clock, s (50 Hz).
pub const TF_PERIOD_S: f64 = 0.02;
/// Items the live outlet holds (about 4 s of the simulation's 1 kHz samples).
pub const OUTLET_CAPACITY: usize = 4096;

/// The publishing thread's counters.
#[derive(Debug, Default)]
pub struct PublishCounters {
    /// `/joint_states` messages sent.
    pub joint_states: AtomicU64,
    /// `/tf` messages sent.
    pub tf: AtomicU64,
    /// `FollowJointTrajectory` feedback messages sent.
    pub feedback: AtomicU64,
    /// Samples taken from the outlet (sent or thinned).
    pub samples: AtomicU64,
    /// Publications Zenoh refused (the first is logged).
    pub errors: AtomicU64,
    /// Samples the recorder dropped because the outlet was full (this thread fell behind).
    pub outlet_dropped: AtomicU64,
}

/// What the thread publishes with.
pub struct Telemetry {
    /// The robot (for the transforms).
    pub model: RobotModel,
    /// The URDF's joints as transforms.
    pub frames: TfFrames,
    /// `/joint_states`.
    pub joint_states: Publisher,
    /// `/tf`.
    pub tf: Publisher,
    /// The action's `_action/feedback` and the goal it reports on.
    pub feedback: Option<(Publisher, Arc<GoalWatch>)>,
}

/// Runs until `stop` is set or the recorder goes away.
pub fn run(t: Telemetry, outlet: LiveOutlet, stop: Arc<AtomicBool>, counters: Arc<PublishCounters>) {
    let names: Vec<String> = t.model.joints.iter().map(|j| j.name.clone()).collect();
    let mut next_js = f64::NEG_INFINITY;
    let mut next_tf = f64::NEG_INFINITY;
    let mut warned = false;
    while !stop.load(Ordering::Acquire) {
        counters.outlet_dropped.store(outlet.dropped(), Ordering::Relaxed);
        let first = match outlet.rx.recv_timeout(Duration::from_millis(50)) {
            Ok(item) => item,
            Err(RecvTimeoutError::Timeout) => continue,
            Err(RecvTimeoutError::Disconnected) => break,
        };
        // everything waiting, newest last: only the samples that start a period are sent
        for item in std::iter::once(first).chain(outlet.rx.try_iter()) {
            let LiveItem::Sample(s) = item else { continue };
            counters.samples.fetch_add(1, Ordering::Relaxed);
            let mut sent = |result: Result<(), String>, counter: &AtomicU64| match result {
                Ok(()) => {
                    counter.fetch_add(1, Ordering::Relaxed);
                }
                Err(e) => {
                    counters.errors.fetch_add(1, Ordering::Relaxed);
                    if !warned {
                        tracing::warn!("ROS 2: {e}");
                        warned = true;
                    }
                }
            };
            let stamp = Time::from_unix_ns(now_unix_ns());
            let joint_state = due(&mut next_js, s.time_s, JOINT_STATES_PERIOD_S);
            if joint_state {
                sent(publish_joint_state(&t, &names, &s, stamp), &counters.joint_states);
            }
            if let Some((publisher, watch)) = &t.feedback
                && let Some(msg) = watch.observe(&s, &names, joint_state, stamp)
            {
                sent(cdr::encode(&msg).map_err(|e| e.to_string()).and_then(|p| publisher.put(p)), &counters.feedback);
            }
            if due(&mut next_tf, s.time_s, TF_PERIOD_S) {
                sent(publish_tf(&t, &s, stamp), &counters.tf);
            }
        }
    }
}

/// True when the sample at `t_s` starts a period: `next` then moves on by one period (on a
/// fixed grid, so 1 ms samples give exactly the rate), or past `t_s` after a gap or a clock jump.
fn due(next: &mut f64, t_s: f64, period_s: f64) -> bool {
    if t_s + 1e-6 < *next && t_s + 1.0 > *next {
        return false;
    }
    *next += period_s;
    if *next <= t_s || *next > t_s + 1.0 {
        *next = t_s + period_s;
    }
    true
}

fn publish_joint_state(t: &Telemetry, names: &[String], s: &TelemetrySample, stamp: Time) -> Result<(), String> {
    let q: Vec<f64> = s.joints.iter().map(|j| j.q_rad).collect();
    let qd: Vec<f64> = s.joints.iter().map(|j| j.qd_rad_s).collect();
    // effort only where it is a torque (the simulation); the robot reports step rates
    let effort: Vec<f64> = match s.drive {
        DriveKind::TorqueNm => s.joints.iter().map(|j| j.drive).collect(),
        _ => Vec::new(),
    };
    let msg = JointState::new(stamp, names, &q, &qd, &effort);
    t.joint_states.put(cdr::encode(&msg).map_err(|e| e.to_string())?)
}

fn publish_tf(t: &Telemetry, s: &TelemetrySample, stamp: Time) -> Result<(), String> {
    let q: Vec<f64> = s.joints.iter().map(|j| j.q_rad).collect();
    let frames = t.frames.transforms(&t.model, &q, parol6_core::telemetry::schema::Time::default());
    let msg = TfMessage::from_frames(&frames, stamp);
    t.tf.put(cdr::encode(&msg).map_err(|e| e.to_string())?)
}

#[cfg(test)]
mod tests {
    use super::due;

    #[test]
    fn thinning_1khz_samples_gives_exactly_100hz() {
        let mut next = f64::NEG_INFINITY;
        let sent = (0..10_000).filter(|k| due(&mut next, *k as f64 * 0.001 + 12.345, 0.01)).count();
        assert_eq!(sent, 1000);
    }
}

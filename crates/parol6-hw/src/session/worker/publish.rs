//! Publication, once per tick: the snapshot with its loop statistics, the [`RobotState`]
//! (forward kinematics, zones, commanded setpoint) and the [`MotionSample`] tap.

use std::sync::Arc;
use std::time::Instant;

use parol6_core::limits::ZoneThresholds;
use parol6_core::motion::{IoState, JointDrive, MotionSample, PlannerMode, RobotState, Setpoint, StateSource};

use super::super::snapshot::LinkState;
use super::{TIMING_WINDOW, Worker};

impl Worker {
    pub(super) fn record_tick(&mut self, now: Instant) {
        if let Some(prev) = self.last_tick {
            let dt = now.duration_since(prev).as_secs_f64();
            if self.intervals_s.len() < TIMING_WINDOW {
                self.intervals_s.push(dt);
            } else {
                self.intervals_s[self.interval_pos] = dt;
                self.interval_pos = (self.interval_pos + 1) % TIMING_WINDOW;
            }
        }
        self.last_tick = Some(now);
    }

    pub(super) fn publish(&mut self, now: Instant, t_s: f64) {
        let st = self.parser.stats();
        self.snap.status_frames = st.frames;
        self.snap.invalid_frames = st.invalid_frames;
        self.snap.discarded_bytes = st.discarded_bytes;
        // Replies missing while the link is up; frames sent while it is down are not "dropped".
        let unanswered = self.snap.frames_sent.saturating_sub(st.frames);
        if self.snap.link != LinkState::Connected {
            self.missing_offset = unanswered.saturating_sub(self.snap.missing_replies);
        }
        self.snap.missing_replies = unanswered.saturating_sub(self.missing_offset);
        self.snap.motion = self.streamer.motion_state();
        if !self.intervals_s.is_empty() {
            let nominal = self.cfg.period_s();
            let mean = self.intervals_s.iter().sum::<f64>() / self.intervals_s.len() as f64;
            self.snap.loop_rate_hz = if mean > 0.0 { 1.0 / mean } else { 0.0 };
            self.jitter_scratch.clear();
            self.jitter_scratch.extend(self.intervals_s.iter().map(|d| (d - nominal).abs()));
            self.jitter_scratch.sort_by(f64::total_cmp);
            self.snap.period_jitter_p99_ms =
                parol6_core::stats::percentile(&self.jitter_scratch, 0.99).unwrap_or(0.0) * 1e3;
            self.snap.period_jitter_max_ms = self.jitter_scratch.last().copied().unwrap_or(0.0) * 1e3;
        }
        self.snap.status_age_ms =
            self.snap.last_status_at.map(|t| now.saturating_duration_since(t).as_secs_f64() * 1e3);
        self.snap.published_at = now;
        let state = self.robot_state(t_s);
        // Nothing is sampled before the board's first valid status: until then the joints are
        // the session's zeros, not a measurement (a recording would open on a folded arm).
        if let Some(tap) = self.tap.as_ref().filter(|_| self.snap.status.is_some()) {
            let sample = MotionSample {
                seq: self.streamer.tick(),
                // the status read at this tick describes the arm when the board took the
                // previous frame: the sample is stamped with that frame's instant
                time_s: (t_s - self.cfg.period_s()).max(0.0),
                commanded: state.commanded.clone(),
                measured_q: state.q.clone(),
                measured_qd: state.qd.clone(),
                drive: JointDrive::StepsPerS(self.snap.joint_speed_steps_s.iter().map(|&v| f64::from(v)).collect()),
            };
            if tap.try_send(sample).is_err() {
                self.snap.tap_dropped += 1;
            }
        }
        self.shared.snapshot.store(Arc::new(self.snap.clone()));
        self.shared.state.store(Arc::new(state));
    }

    /// The robot state of this tick: kinematics of the measured joints, zones, the commanded
    /// setpoint, what the planner does and why motion is refused.
    pub(super) fn robot_state(&self, t_s: f64) -> RobotState {
        let q = self.snap.joint_rad.to_vec();
        let qd = self.snap.joint_speed_rad_s.to_vec();
        let planner = self.streamer.planner();
        let streaming = self.streamer.is_streaming();
        // the measured joints are the board's answer to the previous frame: paired with the
        // setpoint of that frame's instant, so commanded − measured is the arm's tracking error
        let commanded = match self.streamer.answered_setpoint() {
            Some(sp) if streaming => sp.clone(),
            _ => Setpoint::at_rest(&q),
        };
        let target_q = if streaming { planner.goal().to_vec() } else { q.clone() };
        let mode = if streaming { planner.mode() } else { PlannerMode::Hold };
        let moving = (streaming && planner.is_moving(t_s)) || qd.iter().any(|v| v.abs() > 1e-3);
        let mut state = RobotState {
            source: StateSource::Robot,
            backend: format!("robot on {}", self.port_name),
            seq: self.streamer.tick(),
            time_s: t_s,
            tcp: self.model.fk(&q),
            zones: Vec::new(),
            q,
            qd,
            commanded,
            target_q,
            mode,
            moving,
            commands_applied: planner.applied(),
            schedule: planner.schedule_state(),
            last_refusal: self.streamer.last_refusal().cloned(),
            blocked: self.snap.motion_allowed().err().map(|e| e.to_string()),
            homed: self.snap.homed.iter().all(|h| *h),
            io: IoState {
                inputs: [self.snap.io[0], self.snap.io[1]],
                outputs: [self.snap.io[2], self.snap.io[3]],
                gripper_position: u8::try_from(self.snap.gripper_position.clamp(0, 255)).unwrap_or(0),
                gripper_current_ma: self.snap.gripper_current_ma,
                gripper_status: self.snap.gripper_status,
                drives_disabled: self.snap.enabled == Some(false) || self.snap.needs_enable,
            },
        };
        state.update_kinematics(&self.model, &ZoneThresholds::default());
        state
    }
}

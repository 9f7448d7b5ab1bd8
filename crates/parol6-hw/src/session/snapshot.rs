//! What the session publishes about the link and the board: [`Snapshot`] with its
//! [`LinkState`], [`MotionState`] and [`HomingState`].

use std::time::{Duration, Instant};

use parol6_core::parol6::JOINT_COUNT;

use super::guard::LimitBreach;
use crate::HwError;
use crate::frame::{CommandCode, StatusFrame};

/// The message of impossible measured positions: the board answers, but no arm can be there.
pub fn impossible_answers(b: &LimitBreach) -> String {
    format!(
        "the controller's answers are impossible: {b} (more than {:.0}° beyond is no arm's position): \
         motion held (IDLE); check the board, its firmware and the cable",
        super::guard::PLAUSIBLE_BEYOND_LIMIT_DEG
    )
}

/// State of the serial link.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum LinkState {
    /// Port open, waiting for the first valid status.
    Connecting,
    /// Valid status frames arriving.
    Connected,
    /// No valid status ever arrived within the no-answer timeout (3 s) since opening: nothing
    /// that speaks the PAROL6 protocol is on this port. The port is re-opened quietly every
    /// reconnect interval.
    NoAnswer,
    /// No valid status for longer than the status timeout, or the port failed; retrying.
    Lost,
    /// The session has ended.
    Closed,
}

/// What the session is streaming.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum MotionState {
    /// IDLE frames: no stepping.
    Idle,
    /// MOVE frames holding the commanded position.
    Holding,
    /// Jogging one joint (0-based) at a speed fraction.
    Jogging {
        /// 0-based joint.
        joint: usize,
        /// Speed fraction −1…1.
        fraction: f64,
    },
    /// Streaming a planned move or a follow (slider) motion.
    Moving {
        /// Time left until the motion ends, s.
        remaining_s: f64,
    },
    /// Homing (HOME, then IDLE frames).
    Homing,
}

/// Progress of the last homing request.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum HomingState {
    /// No homing requested in this session.
    NotRequested,
    /// Sending HOME frames.
    Sending,
    /// Waiting for all homed bits.
    Waiting,
    /// All six joints homed.
    Done,
    /// Homing failed; the reason.
    Failed(String),
}

/// What the session knows, published after every period.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Snapshot {
    /// Port path.
    pub port: String,
    /// Link state.
    pub link: LinkState,
    /// Latest valid, plausible status frame.
    pub status: Option<StatusFrame>,
    /// Joint positions, steps (the last plausible measurement).
    pub joint_steps: [i32; JOINT_COUNT],
    /// Joint positions, rad.
    pub joint_rad: [f64; JOINT_COUNT],
    /// Joint speed set points, steps/s.
    pub joint_speed_steps_s: [i32; JOINT_COUNT],
    /// Joint speed set points, rad/s.
    pub joint_speed_rad_s: [f64; JOINT_COUNT],
    /// Homed flags.
    pub homed: [bool; JOINT_COUNT],
    /// The measured joint furthest outside the step limits while all joints are homed (before
    /// homing the counters mean nothing): a little beyond (an arm pushed there; only a confirmed
    /// jog back inside may move it) or impossibly far (the board's answers are impossible).
    pub limit_breach: Option<LimitBreach>,
    /// E-stop input pressed.
    pub estop_pressed: bool,
    /// INPUT1, INPUT2, OUTPUT1, OUTPUT2 levels as reported.
    pub io: [bool; 4],
    /// Gripper position 0–255 as reported.
    pub gripper_position: i16,
    /// Gripper current, mA, as reported.
    pub gripper_current_ma: i16,
    /// Raw gripper status byte.
    pub gripper_status: u8,
    /// Whether the board is enabled, as far as the board has shown it: `None` until known
    /// (always before any status arrived); `Some(true)` once the board echoed ENABLE, finished
    /// homing or stepped under MOVE; `Some(false)` once it echoed DISABLE.
    pub enabled: Option<bool>,
    /// True after an E-stop until [`crate::Session::enable`] is called.
    pub needs_enable: bool,
    /// What is being streamed.
    pub motion: MotionState,
    /// Homing progress.
    pub homing: HomingState,
    /// Last MOVE target sent, steps.
    pub target_steps: Option<[i32; JOINT_COUNT]>,
    /// Last command code sent.
    pub last_command: Option<CommandCode>,
    /// Configured rate, Hz.
    pub rate_hz: f64,
    /// Achieved loop rate over the last [`super::TIMING_WINDOW`] periods, Hz.
    pub loop_rate_hz: f64,
    /// 99th percentile of |period − nominal| over the last [`super::TIMING_WINDOW`] periods, ms.
    pub period_jitter_p99_ms: f64,
    /// Largest |period − nominal| over the last [`super::TIMING_WINDOW`] periods, ms.
    pub period_jitter_max_ms: f64,
    /// Command frames written.
    pub frames_sent: u64,
    /// Valid status frames received.
    pub status_frames: u64,
    /// Status candidates rejected by the parser (bad end bytes).
    pub invalid_frames: u64,
    /// Well-formed status frames whose positions were physically impossible (a jump larger
    /// than the joint can move in the elapsed time): rejected, never used.
    pub implausible_frames: u64,
    /// Bytes discarded while resynchronising.
    pub discarded_bytes: u64,
    /// Frames sent that got no reply (sent − received).
    pub missing_replies: u64,
    /// Frames the last-line guard had to alter or replace.
    pub guard_trips: u64,
    /// Successful re-opens of the port.
    pub reconnects: u64,
    /// Times the link was lost (the fault text is cleared when it comes back; this count
    /// stays).
    pub link_losses: u64,
    /// Current fault (link loss, E-stop, refused request, homing failure, implausible
    /// status …); cleared when the link recovers or by CLEAR ERROR.
    pub fault: Option<String>,
    /// Age of the latest valid status when this snapshot was published, ms.
    pub status_age_ms: Option<f64>,
    /// Samples the motion-sample tap could not take (its channel was full): dropped and
    /// counted, never waited for (as the simulation's `tap_dropped`).
    pub tap_dropped: u64,
    #[serde(skip)]
    /// When the latest valid status arrived.
    pub last_status_at: Option<Instant>,
    #[serde(skip)]
    /// When this snapshot was published.
    pub published_at: Instant,
}

impl Snapshot {
    pub(crate) fn new(port: &str, rate_hz: f64) -> Self {
        Self {
            port: port.to_string(),
            link: LinkState::Connecting,
            status: None,
            joint_steps: [0; JOINT_COUNT],
            joint_rad: [0.0; JOINT_COUNT],
            joint_speed_steps_s: [0; JOINT_COUNT],
            joint_speed_rad_s: [0.0; JOINT_COUNT],
            homed: [false; JOINT_COUNT],
            limit_breach: None,
            estop_pressed: false,
            io: [false; 4],
            gripper_position: 0,
            gripper_current_ma: 0,
            gripper_status: 0,
            enabled: None,
            needs_enable: false,
            motion: MotionState::Idle,
            homing: HomingState::NotRequested,
            target_steps: None,
            last_command: None,
            rate_hz,
            loop_rate_hz: 0.0,
            period_jitter_p99_ms: 0.0,
            period_jitter_max_ms: 0.0,
            frames_sent: 0,
            status_frames: 0,
            invalid_frames: 0,
            implausible_frames: 0,
            discarded_bytes: 0,
            missing_replies: 0,
            guard_trips: 0,
            reconnects: 0,
            link_losses: 0,
            fault: None,
            status_age_ms: None,
            tap_dropped: 0,
            last_status_at: None,
            published_at: Instant::now(),
        }
    }

    /// Age of the latest valid status now.
    pub fn status_age(&self) -> Option<Duration> {
        self.last_status_at.map(|t| t.elapsed())
    }

    /// True when all six joints are homed.
    pub fn all_homed(&self) -> bool {
        self.homed.iter().all(|&h| h)
    }

    /// Ok when motion commands would be accepted now (link up, no E-stop, enabled, homed, not
    /// homing, every joint within its limits); else why not: [`HwError::Device`] for a link
    /// that is down and for impossible positions, [`HwError::Refused`] otherwise.
    pub fn motion_allowed(&self) -> Result<(), HwError> {
        if self.link != LinkState::Connected {
            let why = match self.link {
                LinkState::NoAnswer => format!("no PAROL6 answers on {}", self.port),
                other => format!("link is {other:?}"),
            };
            return Err(HwError::Device(match &self.fault {
                Some(f) => format!("{why} ({f})"),
                None => why,
            }));
        }
        if self.estop_pressed {
            return Err(HwError::Refused("E-stop is pressed".into()));
        }
        if self.needs_enable {
            return Err(HwError::Refused("E-stop was pressed: enable the controller first".into()));
        }
        if self.enabled == Some(false) {
            return Err(HwError::Refused("controller is disabled: enable it first".into()));
        }
        if matches!(self.homing, HomingState::Sending | HomingState::Waiting) {
            return Err(HwError::Refused("homing is in progress".into()));
        }
        if !self.all_homed() {
            let unhomed: Vec<String> =
                self.homed.iter().enumerate().filter(|(_, h)| !**h).map(|(i, _)| format!("J{}", i + 1)).collect();
            return Err(HwError::Refused(format!(
                "{} not homed: home the arm first (the step counters mean nothing before homing)",
                unhomed.join(" ")
            )));
        }
        match self.limit_breach {
            Some(b) if b.impossible => Err(HwError::Device(impossible_answers(&b))),
            Some(b) => Err(HwError::Refused(format!(
                "{b}: a MOVE target there would lie outside the limits; move it back inside with a \
                 confirmed jog (parol6 hw jog --joint {} --speed {} --beyond-limit)",
                b.joint,
                if b.above() { "-0.2" } else { "0.2" }
            ))),
            None => Ok(()),
        }
    }

    /// The snapshot as JSON (what `parol6 hw status` prints).
    pub fn to_json(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).unwrap_or(serde_json::Value::Null);
        if let Some(obj) = v.as_object_mut() {
            obj.insert(
                "joint_deg".into(),
                serde_json::json!(self.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>()),
            );
            obj.insert("all_homed".into(), serde_json::json!(self.all_homed()));
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refusals_explain_why() {
        let mut s = Snapshot::new("x", 100.0);
        assert!(s.motion_allowed().is_err());
        s.link = LinkState::Connected;
        let msg = s.motion_allowed().unwrap_err().to_string();
        assert!(msg.contains("home"), "{msg}");
        s.homed = [true; JOINT_COUNT];
        assert!(s.motion_allowed().is_ok());
        s.needs_enable = true;
        let msg = s.motion_allowed().unwrap_err().to_string();
        assert!(msg.contains("enable"), "{msg}");
        s.needs_enable = false;
        s.link = LinkState::NoAnswer;
        let msg = s.motion_allowed().unwrap_err().to_string();
        assert!(msg.contains("no PAROL6"), "{msg}");
    }

    #[test]
    fn enabled_is_unknown_before_any_status() {
        let s = Snapshot::new("x", 100.0);
        assert_eq!(s.enabled, None);
        assert!(s.status.is_none());
    }
}

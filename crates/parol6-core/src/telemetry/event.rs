//! [`TelemetryEvent`]s and the [`EventDetector`] that finds them: a joint entering a limit
//! zone (from the samples), a refused command and motion becoming blocked or allowed again
//! (from the [`RobotState`]s), E-stop and link loss (from the link health).

use serde::{Deserialize, Serialize};

use crate::limits::LimitZone;
use crate::motion::RobotState;

use super::sample::{LinkHealth, TelemetrySample};

/// What happened.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum EventKind {
    /// A joint entered a worse limit zone (0-based joint).
    LimitWarning {
        /// 0-based joint.
        joint: usize,
        /// The zone it entered.
        zone: LimitZone,
    },
    /// A command was refused.
    Refusal,
    /// Motion became refused (the reason is the message) or allowed again.
    Blocked {
        /// True when motion is refused from now on.
        blocked: bool,
    },
    /// The E-stop was pressed (`true`) or released.
    EStop {
        /// Pressed.
        pressed: bool,
    },
    /// The link to the controller was lost (`true`) or came back.
    LinkLoss {
        /// Lost.
        lost: bool,
    },
    /// The program step under way changed (0-based; `None`: no program step any more).
    ProgramStep {
        /// The new step.
        step: Option<usize>,
    },
    /// Anything else the caller reports (program start / end …).
    Note,
    /// A command that came over the network (a live server): carried out or refused (the
    /// message says who sent what, and why it was refused).
    NetworkCommand {
        /// True when it was carried out.
        accepted: bool,
    },
}

/// One event, stamped on the backend's motion clock.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TelemetryEvent {
    /// Motion clock, s.
    pub time_s: f64,
    /// What happened.
    pub kind: EventKind,
    /// Human-readable text.
    pub message: String,
}

impl TelemetryEvent {
    /// Foxglove log level: 2 INFO, 3 WARNING, 4 ERROR.
    pub fn log_level(&self) -> u8 {
        match &self.kind {
            EventKind::Note | EventKind::ProgramStep { .. } => 2,
            EventKind::Blocked { blocked: false } | EventKind::EStop { pressed: false } => 2,
            EventKind::LinkLoss { lost: false } | EventKind::NetworkCommand { accepted: true } => 2,
            EventKind::NetworkCommand { accepted: false } => 3,
            EventKind::LimitWarning { .. } | EventKind::Refusal | EventKind::Blocked { .. } => 3,
            EventKind::EStop { .. } | EventKind::LinkLoss { .. } => 4,
        }
    }
}

/// Finds events in successive samples, states and link health.
#[derive(Debug, Clone, Default)]
pub struct EventDetector {
    zones: Vec<LimitZone>,
    last_refusal_id: Option<u64>,
    blocked: Option<String>,
    link: Option<LinkHealth>,
    seen_state: bool,
}

impl EventDetector {
    /// A detector that has seen nothing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// A joint whose zone got worse since the previous sample gives a limit warning (one per
    /// entry, not per sample).
    pub fn observe_sample(&mut self, s: &TelemetrySample, out: &mut Vec<TelemetryEvent>) {
        let n = s.joints.len();
        self.zones.resize(n, LimitZone::Safe);
        for (i, (zone, joint)) in self.zones.iter_mut().zip(&s.joints).enumerate() {
            let now = joint.zone;
            if now > *zone {
                out.push(TelemetryEvent {
                    time_s: s.time_s,
                    kind: EventKind::LimitWarning { joint: i, zone: now },
                    // in degrees, as every message: a window in radians converts what it shows
                    message: format!("J{} {} (q = {:.2}°)", i + 1, now.label(), joint.q_rad.to_degrees()),
                });
            }
            *zone = now;
        }
    }

    /// A new refusal id gives a refusal; a change of the blocked reason gives a blocked event.
    /// The first state only sets the baseline for refusals (an old refusal is not news).
    pub fn observe_state(&mut self, st: &RobotState, out: &mut Vec<TelemetryEvent>) {
        if let Some((id, msg)) = &st.last_refusal
            && self.last_refusal_id != Some(*id)
        {
            if self.seen_state {
                out.push(TelemetryEvent { time_s: st.time_s, kind: EventKind::Refusal, message: msg.clone() });
            }
            self.last_refusal_id = Some(*id);
        }
        if st.blocked != self.blocked && (self.seen_state || st.blocked.is_some()) {
            let (blocked, message) = match &st.blocked {
                Some(why) => (true, format!("motion refused: {why}")),
                None => (false, "motion allowed again".to_string()),
            };
            out.push(TelemetryEvent { time_s: st.time_s, kind: EventKind::Blocked { blocked }, message });
        }
        self.blocked = st.blocked.clone();
        self.seen_state = true;
    }

    /// E-stop and link-loss transitions.
    pub fn observe_link(&mut self, time_s: f64, h: &LinkHealth, out: &mut Vec<TelemetryEvent>) {
        let (was_estop, was_lost, losses) = match &self.link {
            Some(p) => (p.estop_pressed, p.state == "Lost", p.link_losses),
            None => (false, false, 0),
        };
        if h.estop_pressed != was_estop {
            let message = if h.estop_pressed { "E-stop pressed" } else { "E-stop released" };
            out.push(TelemetryEvent {
                time_s,
                kind: EventKind::EStop { pressed: h.estop_pressed },
                message: message.into(),
            });
        }
        let lost = h.state == "Lost" || h.link_losses > losses;
        if lost && !was_lost {
            out.push(TelemetryEvent {
                time_s,
                kind: EventKind::LinkLoss { lost: true },
                message: format!("link lost ({} losses so far)", h.link_losses),
            });
        } else if was_lost && h.state == "Connected" {
            out.push(TelemetryEvent { time_s, kind: EventKind::LinkLoss { lost: false }, message: "link back".into() });
        }
        self.link = Some(h.clone());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::RobotModel;
    use crate::motion::StateSource;

    /// Issue 32's minor (seen again by trial 10): a limit event read "J5 at limit (q = 1.2579
    /// rad)" in a window showing degrees. Like every message it is now in degrees, which a
    /// window in radians converts.
    #[test]
    fn a_limit_event_gives_the_joint_position_in_degrees() {
        use crate::limits::LimitZone;
        use crate::telemetry::{DriveKind, JointTelemetry};
        let joint = |q_rad, zone| JointTelemetry {
            cmd_q_rad: q_rad,
            cmd_qd_rad_s: 0.0,
            cmd_qdd_rad_s2: 0.0,
            q_rad,
            qd_rad_s: 0.0,
            qdd_rad_s2: 0.0,
            drive: 0.0,
            zone,
        };
        let sample = |zone| TelemetrySample {
            seq: 1,
            time_s: 2.0,
            joints: vec![joint(0.0, LimitZone::Safe), joint(1.2579, zone)],
            drive: DriveKind::StepsPerS,
            tcp: crate::kinematics::TcpPose::from_xyz_rpy([0.0; 3], [0.0; 3]),
            worst_zone: None,
            program_step: None,
            link: None,
        };
        let mut d = EventDetector::new();
        let mut out = Vec::new();
        d.observe_sample(&sample(LimitZone::Safe), &mut out);
        d.observe_sample(&sample(LimitZone::Critical), &mut out);
        assert_eq!(out.len(), 1, "{out:?}");
        assert_eq!(out[0].message, "J2 at limit (q = 72.07°)");
    }

    #[test]
    fn refusal_and_blocked_are_reported_once() {
        let model = RobotModel::parol6();
        let mut st = RobotState::at_rest(&model, StateSource::Simulation, "simulation", &[0.0; 6]);
        st.last_refusal = Some((1, "old".into()));
        let mut d = EventDetector::new();
        let mut out = Vec::new();
        d.observe_state(&st, &mut out);
        assert!(out.is_empty(), "an old refusal is not news: {out:?}");
        st.last_refusal = Some((2, "J2 beyond its limit".into()));
        d.observe_state(&st, &mut out);
        d.observe_state(&st, &mut out);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].kind, EventKind::Refusal);
        st.blocked = Some("E-stop".into());
        d.observe_state(&st, &mut out);
        st.blocked = None;
        d.observe_state(&st, &mut out);
        assert_eq!(out[1].kind, EventKind::Blocked { blocked: true });
        assert_eq!(out[2].kind, EventKind::Blocked { blocked: false });
        assert_eq!(out.len(), 3);
    }

    #[test]
    fn estop_and_link_loss_transitions() {
        let mut d = EventDetector::new();
        let mut out = Vec::new();
        let mut h = LinkHealth { state: "Connected".into(), ..LinkHealth::default() };
        d.observe_link(0.0, &h, &mut out);
        assert!(out.is_empty());
        h.estop_pressed = true;
        d.observe_link(1.0, &h, &mut out);
        h.state = "Lost".into();
        h.link_losses = 1;
        d.observe_link(2.0, &h, &mut out);
        d.observe_link(2.1, &h, &mut out);
        h.state = "Connected".into();
        d.observe_link(3.0, &h, &mut out);
        let kinds: Vec<_> = out.iter().map(|e| e.kind.clone()).collect();
        assert_eq!(
            kinds,
            vec![
                EventKind::EStop { pressed: true },
                EventKind::LinkLoss { lost: true },
                EventKind::LinkLoss { lost: false }
            ]
        );
        assert_eq!(out[0].log_level(), 4);
    }
}

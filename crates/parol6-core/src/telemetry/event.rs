//! [`TelemetryEvent`]s and the [`EventDetector`] that finds them: a joint entering a limit
//! zone (from the samples), a refused command and motion becoming blocked or allowed again
//! (from the [`RobotState`]s), E-stop and link loss (from the link health).

use serde::{Deserialize, Serialize};

use crate::limits::{JointLimits, LimitZone, ZoneThresholds};
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
    /// The joints' limits and the zone thresholds the samples' zones were found with: a zone
    /// raised by the prediction alone is named as the prediction it is.
    limits: Option<(JointLimits, ZoneThresholds)>,
}

impl EventDetector {
    /// A detector that has seen nothing yet (and cannot tell a predicted zone from a reached
    /// one: see [`Self::with_limits`]).
    pub fn new() -> Self {
        Self::default()
    }

    /// A detector for samples whose zones came from `limits` and `thresholds`: a joint whose zone
    /// got worse only by the prediction (its position is in a better zone) is reported as
    /// "J5 will reach its limit in ≤ 0.5 s", not as "at limit" 18° from it.
    pub fn with_limits(limits: JointLimits, thresholds: ZoneThresholds) -> Self {
        Self { limits: Some((limits, thresholds)), ..Self::default() }
    }

    /// The words for joint `i` (0-based) entering `zone` at `q_rad`.
    fn limit_words(&self, i: usize, zone: LimitZone, q_rad: f64) -> String {
        let predicted = self.limits.as_ref().and_then(|(limits, t)| {
            let l = limits.get(i)?;
            (t.zone(l, q_rad) < zone).then_some(t.predict_horizon_s)
        });
        match predicted {
            Some(horizon_s) => format!("will reach its limit in ≤ {horizon_s} s"),
            None => zone.label().to_string(),
        }
    }

    /// A joint whose zone got worse since the previous sample gives a limit warning (one per
    /// entry, not per sample).
    pub fn observe_sample(&mut self, s: &TelemetrySample, out: &mut Vec<TelemetryEvent>) {
        let n = s.joints.len();
        self.zones.resize(n, LimitZone::Safe);
        for (i, joint) in s.joints.iter().enumerate() {
            let now = joint.zone;
            if now > self.zones[i] {
                let words = self.limit_words(i, now, joint.q_rad);
                out.push(TelemetryEvent {
                    time_s: s.time_s,
                    kind: EventKind::LimitWarning { joint: i, zone: now },
                    // in degrees, as every message: a window in radians converts what it shows
                    message: format!("J{} {words} (q = {:.2}°)", i + 1, joint.q_rad.to_degrees()),
                });
            }
            self.zones[i] = now;
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

    /// A joint at `q_rad` moving at `qd_rad_s` (commanded as measured), in `zone`.
    fn joint_at(q_rad: f64, qd_rad_s: f64, zone: crate::limits::LimitZone) -> crate::telemetry::JointTelemetry {
        crate::telemetry::JointTelemetry {
            cmd_q_rad: q_rad,
            cmd_qd_rad_s: qd_rad_s,
            cmd_qdd_rad_s2: 0.0,
            q_rad,
            qd_rad_s,
            qdd_rad_s2: 0.0,
            drive: 0.0,
            zone,
        }
    }

    /// A sample at `time_s` of `joints`, nothing else in it.
    fn sample_of(time_s: f64, joints: Vec<crate::telemetry::JointTelemetry>) -> TelemetrySample {
        TelemetrySample {
            seq: 1,
            time_s,
            joints,
            drive: crate::telemetry::DriveKind::StepsPerS,
            tcp: crate::kinematics::TcpPose::from_xyz_rpy([0.0; 3], [0.0; 3]),
            worst_zone: None,
            program_step: None,
            link: None,
        }
    }

    /// Issue 32's minor (seen again by trial 10): a limit event read "J5 at limit (q = 1.2579
    /// rad)" in a window showing degrees. Like every message it is now in degrees, which a
    /// window in radians converts.
    #[test]
    fn a_limit_event_gives_the_joint_position_in_degrees() {
        use crate::limits::LimitZone;
        let sample = |zone| sample_of(2.0, vec![joint_at(0.0, 0.0, LimitZone::Safe), joint_at(1.2579, 0.0, zone)]);
        let mut d = EventDetector::new();
        let mut out = Vec::new();
        d.observe_sample(&sample(LimitZone::Safe), &mut out);
        d.observe_sample(&sample(LimitZone::Critical), &mut out);
        assert_eq!(out.len(), 1, "{out:?}");
        assert_eq!(out[0].message, "J2 at limit (q = 72.07°)");
    }

    /// trial10 n7: "J5 at limit (q = 1.2579 rad)" at J5 = 72°, 18° from its limit: the zone was
    /// raised by the 0.5 s prediction. Such an event says that the joint will reach its limit,
    /// and one reached by position still says "near limit" / "at limit".
    #[test]
    fn a_limit_event_raised_by_the_prediction_says_so() {
        use crate::limits::LimitZone;
        let model = RobotModel::parol6();
        let thresholds = ZoneThresholds::default();
        let j5 = model.limits.get(4).expect("J5").clone();
        let sample = |q5: f64, qd5: f64| {
            let joints = (0..6)
                .map(|i| {
                    let l = model.limits.get(i).expect("a joint");
                    let q_rad = if i == 4 { q5 } else { 0.5 * (l.min + l.max) };
                    let qd_rad_s = if i == 4 { qd5 } else { 0.0 };
                    joint_at(q_rad, qd_rad_s, thresholds.predictive_zone(l, q_rad, qd_rad_s).zone)
                })
                .collect();
            sample_of(1.0, joints)
        };
        // a fifth of the range from the upper limit (a safe position), moving toward it: 0.4 s away
        let q5 = j5.max - 0.2 * j5.range();
        let fast = sample(q5, 0.2 * j5.range() / 0.4);
        assert_eq!(fast.joints[4].zone, LimitZone::Warning, "raised by the prediction");
        assert_eq!(thresholds.zone(&j5, q5), LimitZone::Safe, "a safe position");
        let mut d = EventDetector::with_limits(model.limits.clone(), thresholds);
        let mut out = Vec::new();
        d.observe_sample(&sample(q5, 0.0), &mut out);
        d.observe_sample(&fast, &mut out);
        assert_eq!(out.len(), 1, "{out:?}");
        let deg = q5.to_degrees();
        assert_eq!(out[0].message, format!("J5 will reach its limit in ≤ 0.5 s (q = {deg:.2}°)"));
        assert!(!out[0].message.contains("at limit") && !out[0].message.contains("rad"), "{}", out[0].message);
        // at its limit by position: "at limit"
        let at = j5.max - 0.5f64.to_radians();
        d.observe_sample(&sample(at, 0.0), &mut out);
        assert_eq!(out.len(), 2, "{out:?}");
        assert_eq!(out[1].message, format!("J5 at limit (q = {:.2}°)", at.to_degrees()));
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

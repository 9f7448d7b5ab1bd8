//! [`TelemetryEncoder`]: turns [`TelemetrySample`]s and [`TelemetryEvent`]s into the messages of
//! our channels ([`Channel`]: topic, schema name and JSON schema, JSON bytes, log time). It is
//! the one encoder of the MCAP files ([`McapSink`](super::McapSink)) and of the live servers
//! (the app's `live` module), so a live client gets exactly the topics, schemas and rates of a
//! recording:
//!
//! - `/robot_description` once ([`TelemetryEncoder::robot_description`]);
//! - `/joint_states` and `/joint_commands` every sample;
//! - `/tf` and `/tcp_pose` at most at [`TelemetryEncoder::pose_rate_hz`] (100 Hz);
//! - `/link` when the link state, E-stop or loss count changes, else once a second;
//! - `/events` per event.
//!
//! Log times are Unix nanoseconds: `start_unix_ns` (the wall clock when the encoder began) plus
//! the backend's motion time since the first sample.

use crate::model::RobotModel;

use super::event::TelemetryEvent;
use super::frames::TfFrames;
use super::sample::{DriveKind, LinkHealth, TelemetrySample};
use super::schema::{self, Header, JointStateMsg, LogMsg, Pose, PoseInFrame, Quaternion, Time, Vector3, WorstZone};

/// One of our channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Channel {
    /// `/robot_description`: the URDF text.
    RobotDescription,
    /// `/joint_states`: the measured joints.
    JointStates,
    /// `/joint_commands`: the commanded joints.
    JointCommands,
    /// `/tf`: one transform per URDF joint.
    Tf,
    /// `/tcp_pose`: the TCP in the root link's frame.
    TcpPose,
    /// `/events`: limit warnings, refusals, E-stop, link loss, program steps, network commands.
    Events,
    /// `/link`: the serial link's health (robot only).
    Link,
}

impl Channel {
    /// Every channel, in the order a recording declares them.
    pub const ALL: [Channel; 7] = [
        Channel::RobotDescription,
        Channel::JointStates,
        Channel::JointCommands,
        Channel::Tf,
        Channel::TcpPose,
        Channel::Events,
        Channel::Link,
    ];

    /// The topic (`/joint_states` …).
    pub fn topic(self) -> &'static str {
        match self {
            Channel::RobotDescription => "/robot_description",
            Channel::JointStates => "/joint_states",
            Channel::JointCommands => "/joint_commands",
            Channel::Tf => "/tf",
            Channel::TcpPose => "/tcp_pose",
            Channel::Events => "/events",
            Channel::Link => "/link",
        }
    }

    /// The schema name (`foxglove.FrameTransforms` …).
    pub fn schema_name(self) -> &'static str {
        match self {
            Channel::RobotDescription => schema::ROBOT_DESCRIPTION,
            Channel::JointStates | Channel::JointCommands => schema::JOINT_STATE,
            Channel::Tf => schema::FRAME_TRANSFORMS,
            Channel::TcpPose => schema::POSE_IN_FRAME,
            Channel::Events => schema::LOG,
            Channel::Link => schema::LINK_HEALTH,
        }
    }

    /// The JSON schema text (schema encoding [`schema::SCHEMA_ENCODING`]).
    pub fn schema_text(self) -> String {
        schema::schema_text(self.schema_name()).unwrap_or_default()
    }
}

/// A message could not be encoded as JSON.
#[derive(Debug, thiserror::Error)]
#[error("cannot encode a {topic} message as JSON: {reason}")]
pub struct EncodeError {
    /// The channel's topic.
    pub topic: &'static str,
    /// What serde_json said.
    pub reason: String,
}

/// Encodes samples and events into our channels' messages. See the module docs.
#[derive(Debug, Clone)]
pub struct TelemetryEncoder {
    model: RobotModel,
    frames: TfFrames,
    joint_names: Vec<String>,
    frame_id: String,
    start_unix_ns: u64,
    t0_s: Option<f64>,
    last_pose_s: Option<f64>,
    last_link: Option<(f64, LinkHealth)>,
    buf: Vec<u8>,
    /// The channels encoded this time ([`TelemetryEncoder::encode_sample_for`]).
    wanted: Vec<Channel>,
    /// Highest rate of `/tf` and `/tcp_pose`, Hz.
    pub pose_rate_hz: f64,
}

impl TelemetryEncoder {
    /// An encoder for `model` (the `/tf` pairs from `urdf_text` when given), its log times
    /// counted from `start_unix_ns`.
    pub fn new(model: &RobotModel, urdf_text: Option<&str>, start_unix_ns: u64) -> Self {
        Self {
            model: model.clone(),
            frames: TfFrames::new(model, urdf_text.filter(|t| !t.is_empty())),
            joint_names: model.joints.iter().map(|j| j.name.clone()).collect(),
            frame_id: model.root_link.clone(),
            start_unix_ns,
            t0_s: None,
            last_pose_s: None,
            last_link: None,
            buf: Vec::with_capacity(1024),
            wanted: Channel::ALL.to_vec(),
            pose_rate_hz: 100.0,
        }
    }

    /// Starts the log times afresh: `start_unix_ns` at the next sample (a live server: the wall
    /// clock when its first sample arrives); the rates start afresh too.
    pub fn restart(&mut self, start_unix_ns: u64) {
        self.start_unix_ns = start_unix_ns;
        self.t0_s = None;
        self.last_pose_s = None;
        self.last_link = None;
    }

    /// The wall-clock start of the log times, Unix ns.
    pub fn start_unix_ns(&self) -> u64 {
        self.start_unix_ns
    }

    /// The URDF joint names, chain order.
    pub fn joint_names(&self) -> &[String] {
        &self.joint_names
    }

    /// The `/robot_description` message of `urdf_text`, stamped at the start.
    pub fn robot_description(&self, urdf_text: &str) -> Result<Vec<u8>, EncodeError> {
        serde_json::to_vec(&schema::RobotDescription { data: urdf_text.to_string() })
            .map_err(|e| EncodeError { topic: Channel::RobotDescription.topic(), reason: e.to_string() })
    }

    /// Unix time of motion time `t_s`, ns (the first sample is the start).
    pub fn stamp_ns(&mut self, t_s: f64) -> u64 {
        let t0 = *self.t0_s.get_or_insert(t_s);
        let dt_ns = ((t_s - t0).max(0.0) * 1e9).round();
        self.start_unix_ns.saturating_add(if dt_ns.is_finite() { dt_ns as u64 } else { 0 })
    }

    /// Motion time of the first sample, s (`None` before one).
    pub fn first_time_s(&self) -> Option<f64> {
        self.t0_s
    }

    /// Serialises `msg` into the encoder's buffer and hands it to `emit` with its channel and
    /// log time.
    fn put<T: serde::Serialize, E: From<EncodeError>>(
        &mut self,
        channel: Channel,
        log_time_ns: u64,
        msg: &T,
        emit: &mut impl FnMut(Channel, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        if !self.wanted.contains(&channel) {
            return Ok(());
        }
        self.buf.clear();
        serde_json::to_writer(&mut self.buf, msg)
            .map_err(|e| EncodeError { topic: channel.topic(), reason: e.to_string() })?;
        emit(channel, log_time_ns, &self.buf)
    }

    /// Encodes one sample: `/joint_states` and `/joint_commands` always, `/tf` and `/tcp_pose`
    /// at most at [`TelemetryEncoder::pose_rate_hz`], `/link` when due. `emit` gets each
    /// message (channel, log time ns, JSON bytes) as it is made.
    pub fn encode_sample<E: From<EncodeError>>(
        &mut self,
        s: &TelemetrySample,
        emit: impl FnMut(Channel, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        self.encode_sample_for(s, |_| true, emit)
    }

    /// [`TelemetryEncoder::encode_sample`] that serialises only the channels `wants` names (a
    /// live server: those a client subscribed to); the rates are kept as if all were: `/tf`
    /// comes at the same instants whoever listens.
    pub fn encode_sample_for<E: From<EncodeError>>(
        &mut self,
        s: &TelemetrySample,
        wants: impl Fn(Channel) -> bool,
        mut emit: impl FnMut(Channel, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        self.wanted.clear();
        self.wanted.extend(Channel::ALL.into_iter().filter(|c| wants(*c)));
        let ns = self.stamp_ns(s.time_s);
        let header = Header { stamp: Time::from_ns(ns), frame_id: self.frame_id.clone() };
        let worst_zone = s.worst_zone.map(|(joint, z)| WorstZone { joint, zone: super::zone_name(z).to_string() });
        let measured = JointStateMsg {
            header: header.clone(),
            name: self.joint_names.clone(),
            position: s.joints.iter().map(|j| j.q_rad).collect(),
            velocity: s.joints.iter().map(|j| j.qd_rad_s).collect(),
            effort: match s.drive {
                DriveKind::TorqueNm => s.joints.iter().map(|j| j.drive).collect(),
                DriveKind::StepsPerS => Vec::new(),
            },
            acceleration: s.joints.iter().map(|j| j.qdd_rad_s2).collect(),
            seq: s.seq,
            time_s: s.time_s,
            steps_per_s: (s.drive == DriveKind::StepsPerS).then(|| s.joints.iter().map(|j| j.drive).collect()),
            program_step: s.program_step,
            worst_zone: worst_zone.clone(),
        };
        self.put(Channel::JointStates, ns, &measured, &mut emit)?;
        let commanded = JointStateMsg {
            header: header.clone(),
            name: measured.name,
            position: s.joints.iter().map(|j| j.cmd_q_rad).collect(),
            velocity: s.joints.iter().map(|j| j.cmd_qd_rad_s).collect(),
            effort: Vec::new(),
            acceleration: s.joints.iter().map(|j| j.cmd_qdd_rad_s2).collect(),
            seq: s.seq,
            time_s: s.time_s,
            steps_per_s: None,
            program_step: s.program_step,
            worst_zone,
        };
        self.put(Channel::JointCommands, ns, &commanded, &mut emit)?;
        let pose_due = match self.last_pose_s {
            None => true,
            Some(last) => s.time_s < last || s.time_s - last >= 0.999 / self.pose_rate_hz,
        };
        if pose_due {
            self.last_pose_s = Some(s.time_s);
            let q: Vec<f64> = s.joints.iter().map(|j| j.q_rad).collect();
            let transforms = self.frames.transforms(&self.model, &q, header.stamp);
            self.put(Channel::Tf, ns, &schema::FrameTransforms { transforms }, &mut emit)?;
            let [x, y, z] = s.tcp.position_m;
            let [qw, qx, qy, qz] = s.tcp.quaternion_wxyz;
            let pose = PoseInFrame {
                timestamp: header.stamp,
                frame_id: self.frame_id.clone(),
                pose: Pose { position: Vector3 { x, y, z }, orientation: Quaternion { x: qx, y: qy, z: qz, w: qw } },
            };
            self.put(Channel::TcpPose, ns, &pose, &mut emit)?;
        }
        if let Some(health) = &s.link
            && self.link_due(health, s.time_s)
        {
            self.last_link = Some((s.time_s, health.clone()));
            let health = health.clone();
            self.put(Channel::Link, ns, &schema::LinkHealthMsg { header, health }, &mut emit)?;
        }
        Ok(())
    }

    /// `/link` gets the health when its state, E-stop or loss count changes, else once a second.
    fn link_due(&self, h: &LinkHealth, t_s: f64) -> bool {
        match &self.last_link {
            None => true,
            Some((t, last)) => {
                last.state != h.state
                    || last.estop_pressed != h.estop_pressed
                    || last.link_losses != h.link_losses
                    || !(0.0..1.0).contains(&(t_s - t))
            }
        }
    }

    /// Encodes one event (`/events`, `foxglove.Log`).
    pub fn encode_event<E: From<EncodeError>>(
        &mut self,
        e: &TelemetryEvent,
        mut emit: impl FnMut(Channel, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        let ns = self.stamp_ns(e.time_s);
        self.wanted.clear();
        self.wanted.push(Channel::Events);
        let msg = LogMsg {
            timestamp: Time::from_ns(ns),
            level: e.log_level(),
            message: e.message.clone(),
            name: "parol6".into(),
            file: String::new(),
            line: 0,
        };
        self.put(Channel::Events, ns, &msg, &mut emit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::PAROL6_URDF;
    use crate::telemetry::reader::tests::sample;

    /// Every channel has a schema text titled with its schema name.
    #[test]
    fn every_channel_has_its_schema() {
        for c in Channel::ALL {
            let v: serde_json::Value = serde_json::from_str(&c.schema_text()).expect("schema JSON");
            assert_eq!(v["title"], c.schema_name(), "{}", c.topic());
        }
    }

    /// At 1 kHz, joint messages come every sample and poses at 100 Hz.
    #[test]
    fn poses_are_thinned_to_100_hz_and_joints_are_not() {
        let model = RobotModel::parol6();
        let mut enc = TelemetryEncoder::new(&model, Some(PAROL6_URDF), 1_000_000_000);
        let mut counts = std::collections::BTreeMap::new();
        for k in 1..=1000 {
            enc.encode_sample(&sample(k, 1e-3), |c, _, data: &[u8]| {
                assert!(serde_json::from_slice::<serde_json::Value>(data).is_ok());
                *counts.entry(c).or_insert(0) += 1;
                Ok::<_, EncodeError>(())
            })
            .expect("encode");
        }
        assert_eq!(counts[&Channel::JointStates], 1000);
        assert_eq!(counts[&Channel::JointCommands], 1000);
        assert_eq!(counts[&Channel::Tf], 100);
        assert_eq!(counts[&Channel::TcpPose], 100);
        // only /tf wanted: the same instants, nothing else serialised
        let mut enc = TelemetryEncoder::new(&model, Some(PAROL6_URDF), 1_000_000_000);
        let mut tf_times = Vec::new();
        for k in 1..=1000 {
            enc.encode_sample_for(
                &sample(k, 1e-3),
                |c| c == Channel::Tf,
                |c, t, _: &[u8]| {
                    assert_eq!(c, Channel::Tf);
                    tf_times.push(t);
                    Ok::<_, EncodeError>(())
                },
            )
            .expect("encode");
        }
        assert_eq!(tf_times.len(), 100);
        assert_eq!(tf_times[1] - tf_times[0], 10_000_000);
    }
}

//! Reads our own MCAP recordings: [`read_recording`] → [`Recording`].
//!
//! One linear pass over the file (no index needed), through [`super::walk`]: chunk CRCs are
//! checked before any message of a chunk is used; a file cut short (a crash, a full disk)
//! yields the messages of its complete chunks and those its cut chunk holds up to the cut, and
//! a damaged chunk is skipped; each with a warning naming its byte. The first schema or channel
//! record of an id is kept (the summary's, when the file has a whole one): a later one that
//! differs is a damaged record (a chunk header read as a channel) and is ignored with a
//! warning, so that it cannot hide the channel's messages. Empty files, files that are
//! not MCAP, MCAP files that are not ours and recordings of another robot get an error naming
//! the problem; nothing here panics on any input.

use std::collections::{BTreeMap, HashMap};

use mcap::records::{Record, op};

use crate::model::RobotModel;

use super::schema::{self, JointStateMsg, LogMsg, PoseInFrame};
use super::walk::walk_recording;

/// The records the reader parses: schema, channel, message, metadata.
const READ_OPCODES: [u8; 4] = [op::SCHEMA, op::CHANNEL, op::MESSAGE, op::METADATA];

/// Most warnings kept about messages and records that did not parse.
const MAX_WARNINGS: usize = 20;

/// Why a file is not a recording we can read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecordingError {
    /// Zero bytes.
    #[error("the file is empty (0 bytes): not a recording")]
    Empty,
    /// Does not start with the MCAP magic.
    #[error("not an MCAP file (it does not start with the MCAP magic bytes)")]
    NotMcap,
    /// MCAP, but damaged before any message could be read.
    #[error("the MCAP file is damaged at byte {offset}: {reason}")]
    Damaged {
        /// About where the damage starts.
        offset: usize,
        /// What the MCAP reader said.
        reason: String,
    },
    /// MCAP, but not written by PAROL6 Studio (no `/joint_states` channel or metadata).
    #[error("not a PAROL6 Studio recording: {0}")]
    NotOurs(String),
    /// A recording of another robot than the one loaded.
    #[error(
        "this recording is of robot \"{recorded}\" ({recorded_joints} joints), not of \"{expected}\" ({expected_joints} joints)"
    )]
    OtherRobot {
        /// Robot named in the file.
        recorded: String,
        /// Its joint count.
        recorded_joints: usize,
        /// Robot loaded.
        expected: String,
        /// Its joint count.
        expected_joints: usize,
    },
}

/// Per-topic message counts and the time span, from the messages actually read.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TopicStats {
    /// Messages read.
    pub messages: u64,
    /// Schema name.
    pub schema: String,
}

/// What a recording holds.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Recording {
    /// The metadata record's key/values (app_version, robot, tool, program, joints …).
    pub metadata: BTreeMap<String, String>,
    /// Joint names, chain order.
    pub joint_names: Vec<String>,
    /// `/joint_states` messages, in file order.
    pub measured: Vec<JointStateMsg>,
    /// `/joint_commands` messages, in file order.
    pub commanded: Vec<JointStateMsg>,
    /// `/events` messages.
    pub events: Vec<LogMsg>,
    /// `/link` messages (the serial link's health; robot recordings only), in file order.
    pub link: Vec<schema::LinkHealthMsg>,
    /// `/tcp_pose` messages (the TCP path, at most 100 Hz), in file order.
    pub tcp_path: Vec<PoseInFrame>,
    /// The URDF text of `/robot_description` (empty when absent).
    pub urdf_text: String,
    /// Per topic.
    pub topics: BTreeMap<String, TopicStats>,
    /// First and last message log time, Unix ns.
    pub span_ns: Option<(u64, u64)>,
    /// Problems that did not stop reading (a truncated tail, a message that did not parse).
    pub warnings: Vec<String>,
    /// True when the file ended before its footer (cut short).
    pub truncated: bool,
}

impl Recording {
    /// Duration from the first to the last message, s.
    pub fn duration_s(&self) -> f64 {
        self.span_ns.map(|(a, b)| (b.saturating_sub(a)) as f64 * 1e-9).unwrap_or(0.0)
    }

    /// The robot named in the metadata.
    pub fn robot(&self) -> &str {
        self.metadata.get("robot").map(String::as_str).unwrap_or("")
    }

    /// Refuses a recording of another robot than `model` (name or joint names differ).
    pub fn check_robot(&self, model: &RobotModel) -> Result<(), RecordingError> {
        let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
        if self.robot() != model.name || self.joint_names.iter().map(String::as_str).ne(names.iter().copied()) {
            return Err(RecordingError::OtherRobot {
                recorded: self.robot().to_string(),
                recorded_joints: self.joint_names.len(),
                expected: model.name.clone(),
                expected_joints: names.len(),
            });
        }
        Ok(())
    }
}

#[derive(Default)]
struct Channels {
    /// channel id → (topic, schema id)
    channels: HashMap<u16, (String, u16)>,
    schemas: HashMap<u16, String>,
    filter: ScanFilter,
    /// Log-time bucket of the last joint message kept, per channel.
    last_bucket: HashMap<u16, u64>,
}

/// Reads a whole recording from `bytes`, keeping every joint state and command in
/// [`Recording::measured`] and [`Recording::commanded`]. See the module docs.
pub fn read_recording(bytes: &[u8]) -> Result<Recording, RecordingError> {
    let mut measured = Vec::new();
    let mut commanded = Vec::new();
    let mut rec = scan_recording(bytes, &mut |topic, m| {
        if topic == "/joint_states" {
            measured.push(m);
        } else {
            commanded.push(m);
        }
    })?;
    rec.measured = measured;
    rec.commanded = commanded;
    Ok(rec)
}

/// Reads `bytes` in one pass, handing every `/joint_states` and `/joint_commands` message to
/// `visit` (topic, message) in file order instead of keeping them: memory stays small for long
/// recordings. The returned [`Recording`] has empty `measured` and `commanded`.
pub fn scan_recording(bytes: &[u8], visit: &mut dyn FnMut(&str, JointStateMsg)) -> Result<Recording, RecordingError> {
    scan_recording_filtered(bytes, ScanFilter::default(), visit)
}

/// Which joint messages [`scan_recording_filtered`] parses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ScanFilter {
    /// Per topic, of the `/joint_states` or `/joint_commands` messages whose log times fall in
    /// the same span of this many ns (counted from the Unix epoch), only the first is parsed;
    /// the others are skipped unparsed (0: keep all). Measured and commanded messages of a
    /// tick share their log time, so the same ticks are kept on both.
    pub joint_bucket_ns: u64,
}

/// [`scan_recording`], skipping the joint messages `filter` thins out (they are still counted
/// in [`Recording::topics`]).
pub fn scan_recording_filtered(
    bytes: &[u8],
    filter: ScanFilter,
    visit: &mut dyn FnMut(&str, JointStateMsg),
) -> Result<Recording, RecordingError> {
    if bytes.is_empty() {
        return Err(RecordingError::Empty);
    }
    if !bytes.starts_with(mcap::MAGIC) {
        return Err(RecordingError::NotMcap);
    }
    let mut rec = Recording::default();
    let mut ids = Channels { filter, ..Channels::default() };
    let walked = walk_recording(bytes, &mut |opcode, data| {
        // only the records we use are parsed: the mcap crate's attachment parser panics on a
        // short attachment record (found by the fuzzer)
        if READ_OPCODES.contains(&opcode) {
            match mcap::parse_record(opcode, data) {
                Ok(r) => take_record(r, &mut ids, &mut rec, visit),
                Err(e) => {
                    if rec.warnings.len() < MAX_WARNINGS {
                        rec.warnings.push(format!("a record (opcode {opcode:#04x}) did not parse: {e}"));
                    }
                }
            }
        }
    });
    if let Some((offset, reason)) = walked.damaged_at_start {
        return Err(RecordingError::Damaged { offset, reason });
    }
    if !walked.warnings.is_empty() {
        rec.warnings.extend(walked.warnings);
        rec.warnings.push(format!("read {} samples", samples(&rec)));
    }
    rec.truncated = walked.truncated || !walked.saw_footer;
    if !rec.topics.contains_key("/joint_states") && rec.metadata.is_empty() {
        let topics: Vec<&str> = rec.topics.keys().map(String::as_str).collect();
        return Err(RecordingError::NotOurs(if topics.is_empty() {
            "it holds no messages we know and no PAROL6 Studio metadata".into()
        } else {
            format!("no /joint_states channel and no PAROL6 Studio metadata (topics: {})", topics.join(", "))
        }));
    }
    if rec.joint_names.is_empty() {
        rec.joint_names = rec
            .metadata
            .get("joints")
            .map(|j| j.split(',').filter(|s| !s.is_empty()).map(str::to_string).collect())
            .unwrap_or_default();
    }
    Ok(rec)
}

/// Warns of a schema or channel record that redefines `id` (`was` → `now`): it is ignored.
fn redefined(rec: &mut Recording, what: &str, id: u16, was: &str, now: &str) {
    if rec.warnings.len() < MAX_WARNINGS {
        let now = now.chars().take(60).collect::<String>();
        rec.warnings.push(format!(
            "a {what} record redefines {what} {id} ({was:?}) as {now:?}: a damaged record, ignored (the first {what} {id} is kept)"
        ));
    }
}

fn samples(rec: &Recording) -> u64 {
    rec.topics.get("/joint_states").map_or(0, |t| t.messages)
}

fn take_record(r: Record<'_>, ids: &mut Channels, rec: &mut Recording, visit: &mut dyn FnMut(&str, JointStateMsg)) {
    match r {
        // the first record of an id is kept (the summary's, when the file has one): the MCAP
        // spec has every record of an id the same, so one that differs is damaged (a chunk
        // header read as a channel, found by the fuzzer) and must not hide the channel's messages
        Record::Schema { header, .. } => match ids.schemas.get(&header.id) {
            Some(known) if *known != header.name => {
                redefined(rec, "schema", header.id, known, &header.name);
            }
            Some(_) => {}
            None => {
                ids.schemas.insert(header.id, header.name);
            }
        },
        Record::Channel(c) => match ids.channels.get(&c.id) {
            Some((topic, schema_id)) if (topic, *schema_id) != (&c.topic, c.schema_id) => {
                let (was, now) =
                    (format!("{topic} (schema {schema_id})"), format!("{} (schema {})", c.topic, c.schema_id));
                redefined(rec, "channel", c.id, &was, &now);
            }
            Some(_) => {}
            None => {
                ids.channels.insert(c.id, (c.topic, c.schema_id));
            }
        },
        Record::Metadata(m) if m.name == schema::METADATA_NAME => rec.metadata = m.metadata,
        Record::Message { header, data } => {
            let Some((topic, schema_id)) = ids.channels.get(&header.channel_id) else {
                rec.warnings.push(format!("a message on unknown channel {}", header.channel_id));
                return;
            };
            let t = header.log_time;
            rec.span_ns = Some(match rec.span_ns {
                None => (t, t),
                Some((a, b)) => (a.min(t), b.max(t)),
            });
            let stats = rec.topics.entry(topic.clone()).or_default();
            stats.messages += 1;
            if stats.schema.is_empty() {
                stats.schema = ids.schemas.get(schema_id).cloned().unwrap_or_default();
            }
            let warn = |rec: &mut Recording, e: serde_json::Error| {
                if rec.warnings.len() < MAX_WARNINGS {
                    rec.warnings.push(format!("a {topic} message (sequence {}) is not valid: {e}", header.sequence));
                }
            };
            if ids.filter.joint_bucket_ns > 0 && matches!(topic.as_str(), "/joint_states" | "/joint_commands") {
                let bucket = t / ids.filter.joint_bucket_ns;
                if ids.last_bucket.insert(header.channel_id, bucket) == Some(bucket) {
                    return;
                }
            }
            match topic.as_str() {
                "/joint_states" | "/joint_commands" => match serde_json::from_slice::<JointStateMsg>(&data) {
                    Ok(m) => {
                        if rec.joint_names.is_empty() {
                            rec.joint_names = m.name.clone();
                        }
                        visit(topic, m);
                    }
                    Err(e) => warn(rec, e),
                },
                "/events" => match serde_json::from_slice::<LogMsg>(&data) {
                    Ok(m) => rec.events.push(m),
                    Err(e) => warn(rec, e),
                },
                "/link" => match serde_json::from_slice::<schema::LinkHealthMsg>(&data) {
                    Ok(m) => rec.link.push(m),
                    Err(e) => warn(rec, e),
                },
                "/tcp_pose" => match serde_json::from_slice::<PoseInFrame>(&data) {
                    Ok(m) => rec.tcp_path.push(m),
                    Err(e) => warn(rec, e),
                },
                "/robot_description" => match serde_json::from_slice::<schema::RobotDescription>(&data) {
                    Ok(m) => rec.urdf_text = m.data,
                    Err(e) => warn(rec, e),
                },
                _ => {}
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod recovery_tests;
#[cfg(test)]
pub(crate) mod tests;

//! Reads our own MCAP recordings: [`read_recording`] → [`Recording`].
//!
//! One linear pass over the file (no index needed): chunk CRCs are checked before any message
//! of a chunk is used, so a file cut short (a crash, a full disk) yields the messages of its
//! complete chunks and a warning naming where it ends. Empty files, files that are not MCAP,
//! MCAP files that are not ours and recordings of another robot get an error naming the
//! problem; nothing here panics on any input.

use std::collections::{BTreeMap, HashMap};

use mcap::records::{Record, op};
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};

use crate::model::RobotModel;

use super::schema::{self, JointStateMsg, LogMsg, PoseInFrame};

/// Largest record (a decompressed chunk included) read from a file smaller than this: our
/// chunks close at 8 MiB; a damaged length field must not make the reader allocate more.
const MAX_RECORD_BYTES: usize = 64 << 20;

/// The records the reader parses: footer, schema, channel, message, metadata.
const READ_OPCODES: [u8; 5] = [op::FOOTER, op::SCHEMA, op::CHANNEL, op::MESSAGE, op::METADATA];

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
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_skip_end_magic(true)
            .with_prevalidate_chunk_crcs(true)
            .with_validate_data_section_crc(true)
            .with_validate_summary_section_crc(true)
            .with_record_length_limit(bytes.len().max(MAX_RECORD_BYTES)),
    );
    let mut rec = Recording::default();
    // the mcap reader mishandles an uncompressed chunk whose records overrun it (found by the
    // fuzzer: an integer overflow); we only ever write zstd chunks, so stop before any other
    let bytes = match first_foreign_chunk(bytes) {
        Some((at, why)) => {
            rec.warnings.push(format!("{why} at byte {at}; reading stopped there"));
            &bytes[..at]
        }
        None => bytes,
    };
    let mut ids = Channels { filter, ..Channels::default() };
    let mut pos = 0usize;
    let mut any_record = false;
    let mut saw_footer = false;
    while let Some(event) = reader.next_event() {
        let event = match event {
            Ok(e) => e,
            Err(e) => {
                if !any_record {
                    return Err(RecordingError::Damaged { offset: pos, reason: e.to_string() });
                }
                rec.truncated = true;
                rec.warnings.push(format!(
                    "the file is cut short or damaged near byte {pos} of {} ({e}); read the {} samples of its complete chunks",
                    bytes.len(),
                    samples(&rec)
                ));
                break;
            }
        };
        match event {
            LinearReadEvent::ReadRequest(n) => {
                let end = pos.saturating_add(n).min(bytes.len());
                let chunk = &bytes[pos..end];
                reader.insert(chunk.len()).copy_from_slice(chunk);
                reader.notify_read(chunk.len());
                pos = end;
            }
            LinearReadEvent::Record { opcode, data } => {
                any_record = true;
                // only the records we use are parsed: the mcap crate's attachment parser panics
                // on a short attachment record (found by the fuzzer)
                if !READ_OPCODES.contains(&opcode) {
                    continue;
                }
                match mcap::parse_record(opcode, data) {
                    Ok(Record::Footer(_)) => saw_footer = true,
                    Ok(r) => take_record(r, &mut ids, &mut rec, visit),
                    Err(e) => rec.warnings.push(format!("a record (opcode {opcode:#04x}) did not parse: {e}")),
                }
            }
        }
    }
    if !saw_footer && !rec.truncated {
        rec.truncated = true;
        rec.warnings.push(format!(
            "the file has no footer (cut short at a record boundary after {} bytes); read the {} samples of its complete chunks",
            bytes.len(),
            samples(&rec)
        ));
    }
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

/// The offset of the first top-level chunk record that is not a well-formed zstd chunk (its
/// fields must add up to the record's length), with the reason. Walks the record headers only.
fn first_foreign_chunk(bytes: &[u8]) -> Option<(usize, String)> {
    const CHUNK: u8 = 0x06;
    const FOOTER: u8 = 0x02;
    const DATA_END: u8 = 0x0f;
    let u64_at = |at: usize| -> Option<u64> { Some(u64::from_le_bytes(bytes.get(at..at + 8)?.try_into().ok()?)) };
    let u32_at = |at: usize| -> Option<u32> { Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?)) };
    let mut pos = mcap::MAGIC.len();
    while let (Some(&op), Some(len)) = (bytes.get(pos), u64_at(pos + 1)) {
        if op == FOOTER || op == DATA_END {
            return None;
        }
        let body = pos + 9;
        let end = usize::try_from(len).ok().and_then(|l| body.checked_add(l))?;
        if end > bytes.len() {
            // cut short; a chunk cut short is never read (the mcap reader would start on it)
            return (op == CHUNK).then(|| (pos, "the file is cut short inside a chunk".to_string()));
        }
        if op == CHUNK {
            // start and end time, uncompressed size and CRC, then the compression name
            let name_len = u32_at(body + 28).and_then(|n| usize::try_from(n).ok())?;
            let name_end = (body + 32).checked_add(name_len).filter(|&e| e <= end)?;
            let name = &bytes[body + 32..name_end];
            let compressed = u64_at(name_end).and_then(|c| usize::try_from(c).ok());
            if name != b"zstd" {
                let shown = String::from_utf8_lossy(name).chars().take(16).collect::<String>();
                return Some((pos, format!("a chunk compressed with \"{shown}\" (PAROL6 Studio writes zstd only)")));
            }
            if compressed.and_then(|c| (name_end + 8).checked_add(c)) != Some(end) {
                return Some((pos, "a chunk whose sizes do not add up".to_string()));
            }
        }
        pos = end;
    }
    None
}

fn samples(rec: &Recording) -> u64 {
    rec.topics.get("/joint_states").map_or(0, |t| t.messages)
}

fn take_record(r: Record<'_>, ids: &mut Channels, rec: &mut Recording, visit: &mut dyn FnMut(&str, JointStateMsg)) {
    match r {
        Record::Schema { header, .. } => {
            ids.schemas.insert(header.id, header.name);
        }
        Record::Channel(c) => {
            ids.channels.insert(c.id, (c.topic, c.schema_id));
        }
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
                if rec.warnings.len() < 20 {
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
pub(crate) mod tests;

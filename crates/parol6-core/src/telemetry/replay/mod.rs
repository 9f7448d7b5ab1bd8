//! Loading a recording for replay: [`read_replay_file`] and [`load_replay`] read an MCAP file
//! of ours into a [`SeriesStore`] (the same series as the live plots, TCP from forward
//! kinematics) and its events on the motion clock.
//!
//! Joint states are kept at most at [`REPLAY_RATE_HZ`] (the rate of the live view): of each
//! [`REPLAY_BUCKET_NS`] of log time, the first sample is kept and the others are skipped
//! before their JSON is parsed. A whole file is decoded chunk by chunk on several threads
//! while it is read ([`super::chunked`]; the rows, forward kinematics included, are made there
//! too, `rows`), so a ten-minute 1 kHz recording opens in under a second on two cores. Any
//! other file goes
//! through the linear reader ([`super::reader`]), which gives the same series: a truncated file
//! gives what its complete chunks hold (with the reader's warning); an empty, foreign or
//! damaged file, or a recording of another robot, gives a [`RecordingError`] that says which.

use std::io::Read;
use std::path::Path;

use crate::model::RobotModel;

use super::chunked::{self, ChunkDecoder, FileSource, MessageRef, NotFast, RecordSource, SliceSource};
use super::reader::{Recording, RecordingError, ScanFilter, scan_recording_filtered};
use super::sample::LinkHealth;
use super::schema::JointStateMsg;
use super::series::SeriesStore;

mod rows;

use rows::{ChunkRows, CommandedJson, MeasuredRow, RowJoiner};

/// Highest sample rate a replay keeps, Hz (the live view's).
pub const REPLAY_RATE_HZ: f64 = 250.0;

/// Of each span of this much log time, one joint sample is kept, ns (1 / [`REPLAY_RATE_HZ`]).
pub const REPLAY_BUCKET_NS: u64 = (1e9 / REPLAY_RATE_HZ) as u64;

/// An event of the recording on the motion clock.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayEvent {
    /// Motion time, s.
    pub time_s: f64,
    /// Foxglove log level: 2 info, 3 warning, 4 error.
    pub level: u8,
    /// What happened.
    pub message: String,
}

/// The serial link's health as recorded, on the motion clock (robot recordings).
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayLink {
    /// Motion time, s.
    pub time_s: f64,
    /// State, loop rate, missing replies, losses, E-stop.
    pub health: LinkHealth,
}

/// How a recording was read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadPath {
    /// Chunk by chunk, on this many threads.
    Parallel {
        /// Decoding threads.
        threads: usize,
        /// Chunks.
        chunks: usize,
    },
    /// In one pass by the linear reader (the file is cut short, damaged or unusual).
    Linear,
}

/// A recording ready to replay.
#[derive(Debug, Clone)]
pub struct ReplayData {
    /// The series (every sample kept, at most [`REPLAY_RATE_HZ`]).
    pub store: SeriesStore,
    /// Events, oldest first.
    pub events: Vec<ReplayEvent>,
    /// The serial link's health, oldest first (empty: a simulation recording, or one made
    /// before the link was recorded).
    pub link: Vec<ReplayLink>,
    /// Robot named in the file.
    pub robot: String,
    /// Program named in the file (empty: none).
    pub program: String,
    /// Joint-state samples in the file.
    pub samples_in_file: u64,
    /// Problems that did not stop reading (a truncated tail …).
    pub warnings: Vec<String>,
    /// The file ended before its footer.
    pub truncated: bool,
    /// How it was read.
    pub read_path: ReadPath,
}

impl ReplayData {
    /// The link's health as last recorded at or before motion time `t_s` (`None`: none yet, or
    /// none in the file).
    pub fn link_at(&self, t_s: f64) -> Option<&LinkHealth> {
        let after = self.link.partition_point(|l| l.time_s <= t_s);
        after.checked_sub(1).and_then(|i| self.link.get(i)).map(|l| &l.health)
    }
}

/// Why a recording could not be replayed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReplayError {
    /// The file could not be read.
    #[error("cannot read {path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// What the system said.
        reason: String,
    },
    /// Read, but not a recording we can replay.
    #[error(transparent)]
    Recording(#[from] RecordingError),
}

/// The parallel path's decoder of one chunk: thins the joint messages to one per
/// [`REPLAY_BUCKET_NS`] per topic, parses the kept ones and pairs them into rows.
struct ReplayDecoder<'m> {
    model: &'m RobotModel,
    rows: ChunkRows,
    /// Bucket of the last kept command and measured sample.
    last_bucket: [Option<u64>; 2],
}

impl ChunkDecoder for ReplayDecoder<'_> {
    type Out = ChunkRows;

    fn message(&mut self, m: MessageRef<'_>) -> Result<(), String> {
        let measured = match m.topic {
            "/joint_states" => true,
            "/joint_commands" => false,
            "/events" => {
                self.rows.event(serde_json::from_slice(m.data).map_err(|e| e.to_string())?);
                return Ok(());
            }
            "/link" => {
                self.rows.link(serde_json::from_slice(m.data).map_err(|e| e.to_string())?);
                return Ok(());
            }
            _ => return Ok(()),
        };
        let bucket = m.log_time_ns / REPLAY_BUCKET_NS;
        if self.last_bucket[usize::from(measured)].replace(bucket) == Some(bucket) {
            return Ok(());
        }
        if measured {
            let json = serde_json::from_slice(m.data).map_err(|e| e.to_string())?;
            self.rows.measured(Some(bucket), MeasuredRow::new(self.model, json));
        } else {
            self.rows.commanded(serde_json::from_slice(m.data).map_err(|e| e.to_string())?);
        }
        Ok(())
    }

    fn finish(self) -> ChunkRows {
        self.rows
    }
}

fn finish(rows: RowJoiner, rec: &Recording, read_path: ReadPath) -> ReplayData {
    let mut store = rows.store;
    store.shrink_to_fit();
    if let Some(kind) = rows.drive {
        store.set_drive(kind);
    }
    // stamps to the motion clock, by the first row's pair (none: no rows, nothing to place)
    let on_clock =
        |stamp_ns: u64| rows.first.map(|(t0_s, stamp0_ns)| t0_s + (stamp_ns as f64 - stamp0_ns as f64) * 1e-9);
    let events = rows
        .events
        .iter()
        .filter_map(|e| {
            Some(ReplayEvent { time_s: on_clock(e.timestamp.as_ns())?, level: e.level, message: e.message.clone() })
        })
        .collect();
    let link = rows
        .link
        .iter()
        .filter_map(|m| Some(ReplayLink { time_s: on_clock(m.header.stamp.as_ns())?, health: m.health.clone() }))
        .collect();
    let mut warnings = rec.warnings.clone();
    if store.is_empty() {
        warnings.push("the recording holds no joint-state samples: nothing to replay".into());
    }
    ReplayData {
        store,
        events,
        link,
        robot: rec.robot().to_string(),
        program: rec.metadata.get("program").cloned().unwrap_or_default(),
        samples_in_file: rec.topics.get("/joint_states").map_or(0, |t| t.messages),
        warnings,
        truncated: rec.truncated,
        read_path,
    }
}

fn decoding_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Reads the recording at `path` for replay with `model`: a whole file is decoded while it is
/// read ([`load_whole_replay`]), anything else is read whole and given to [`load_replay`]'s
/// linear reader.
pub fn read_replay_file(path: &Path, model: &RobotModel) -> Result<ReplayData, ReplayError> {
    let io = |e: std::io::Error| ReplayError::Io { path: path.display().to_string(), reason: e.to_string() };
    let file = crate::fsio::open_regular(path).map_err(|e| ReplayError::Io {
        path: path.display().to_string(),
        reason: e.io_error().map_or_else(|| e.to_string(), ToString::to_string),
    })?;
    let len = file.metadata().map_err(io)?.len();
    let data = match load_whole_replay(std::io::BufReader::with_capacity(1 << 16, file), len, model) {
        Some(data) => data,
        None => load_linear(&std::fs::read(path).map_err(io)?, model),
    };
    crate::process::release_freed_memory();
    Ok(data?)
}

/// The parallel path over `reader`, a file of `len` bytes, read piece by piece: `None` when
/// the file is not whole and well-formed (read it whole and give it to [`load_replay`]).
pub fn load_whole_replay(
    reader: impl Read,
    len: u64,
    model: &RobotModel,
) -> Option<Result<ReplayData, RecordingError>> {
    FileSource::new(reader, len).and_then(|source| load_parallel(source, model, decoding_threads())).ok()
}

/// Reads `bytes` (a whole MCAP file) for replay with `model`. See the module docs.
pub fn load_replay(bytes: &[u8], model: &RobotModel) -> Result<ReplayData, RecordingError> {
    let data = match SliceSource::new(bytes).and_then(|source| load_parallel(source, model, decoding_threads())) {
        Ok(data) => data,
        Err(NotFast(_)) => load_linear(bytes, model),
    };
    crate::process::release_freed_memory();
    data
}

/// The parallel path: `Err` leaves the file to the linear reader.
fn load_parallel<'a>(
    source: impl RecordSource<'a>,
    model: &RobotModel,
    threads: usize,
) -> Result<Result<ReplayData, RecordingError>, NotFast> {
    let decoder = || ReplayDecoder { model, rows: ChunkRows::new(model), last_bucket: [None; 2] };
    let read = chunked::decode_chunks(source, threads, decoder)?;
    let joint_names: Vec<String> = match read.metadata.get("joints") {
        Some(j) => j.split(',').filter(|s| !s.is_empty()).map(str::to_string).collect(),
        None => return Err(NotFast("no joint names in the metadata".into())),
    };
    let rec = Recording {
        metadata: read.metadata,
        joint_names,
        topics: read.topics,
        span_ns: read.span_ns,
        warnings: read.warnings,
        ..Recording::default()
    };
    if let Err(e) = rec.check_robot(model) {
        return Ok(Err(e));
    }
    let mut rows = RowJoiner::new(model);
    for chunk in read.outputs {
        rows.add(chunk);
    }
    Ok(Ok(finish(rows, &rec, ReadPath::Parallel { threads: read.threads, chunks: read.chunks })))
}

/// The linear path: any file, whole or not.
fn load_linear(bytes: &[u8], model: &RobotModel) -> Result<ReplayData, RecordingError> {
    let mut chunk = ChunkRows::new(model);
    let filter = ScanFilter { joint_bucket_ns: REPLAY_BUCKET_NS };
    let mut visit = |topic: &str, m: JointStateMsg| match topic {
        "/joint_states" => chunk.measured(None, MeasuredRow::new(model, m.into())),
        _ => chunk.commanded(CommandedJson { position: m.position, seq: m.seq }),
    };
    let rec = scan_recording_filtered(bytes, filter, &mut visit)?;
    rec.check_robot(model)?;
    for e in &rec.events {
        chunk.event(e.clone());
    }
    for m in &rec.link {
        chunk.link(m.clone());
    }
    let mut rows = RowJoiner::new(model);
    rows.add(chunk);
    Ok(finish(rows, &rec, ReadPath::Linear))
}

#[cfg(test)]
mod tests;

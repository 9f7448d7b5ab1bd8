//! Loading a recording for replay: [`read_replay_file`] and [`load_replay`] read an MCAP file
//! of ours into a [`SeriesStore`] (the same series as the live plots, TCP from forward
//! kinematics) and its events on the motion clock.
//!
//! Joint states are kept at most at [`REPLAY_RATE_HZ`] (the rate of the live view): of each
//! [`REPLAY_BUCKET_NS`] of log time, the first sample is kept and the others are skipped
//! before their JSON is parsed. A whole file is decoded chunk by chunk on several threads
//! while it is read ([`super::chunked`]; the samples' forward kinematics is done there too), so
//! a ten-minute 1 kHz recording opens in under a second on two cores. Any other file goes
//! through the linear reader ([`super::reader`]), which gives the same series: a truncated file
//! gives what its complete chunks hold (with the reader's warning); an empty, foreign or
//! damaged file, or a recording of another robot, gives a [`RecordingError`] that says which.

use std::collections::VecDeque;
use std::io::Read;
use std::path::Path;

use serde::Deserialize;

use crate::model::RobotModel;

use super::chunked::{self, FileSource, MessageRef, NotFast, RecordSource, SliceSource};
use super::reader::{Recording, RecordingError, ScanFilter, scan_recording_filtered};
use super::sample::DriveKind;
use super::schema::{JointStateMsg, LogMsg, Time};
use super::series::SeriesStore;

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

#[derive(Debug, Clone, Copy, Deserialize)]
struct Stamp {
    stamp: Time,
}

/// What the replay takes from a `/joint_states` message (the joint names and the rest are
/// skipped unparsed).
#[derive(Debug, Clone, Deserialize)]
struct MeasuredJson {
    header: Stamp,
    position: Vec<f64>,
    velocity: Vec<f64>,
    effort: Vec<f64>,
    acceleration: Vec<f64>,
    seq: u64,
    time_s: f64,
    #[serde(default)]
    steps_per_s: Option<Vec<f64>>,
}

/// What the replay takes from a `/joint_commands` message.
#[derive(Debug, Clone, Deserialize)]
struct CommandedJson {
    position: Vec<f64>,
    seq: u64,
}

/// A measured sample made into its row (forward kinematics included) where it was decoded;
/// the tracking error is filled in when its command is found.
#[derive(Debug, Clone)]
struct MeasuredRow {
    seq: u64,
    time_s: f64,
    stamp_ns: u64,
    position: Vec<f64>,
    drive: DriveKind,
    row: Vec<f32>,
}

/// One decoded message of interest, in file order.
#[derive(Debug, Clone)]
enum Item {
    /// A measured sample and its log-time bucket (`None`: thinned already).
    Measured(Option<u64>, MeasuredRow),
    Commanded(CommandedJson),
    Event(LogMsg),
}

fn at(v: &[f64], j: usize) -> f64 {
    v.get(j).copied().unwrap_or(f64::NAN)
}

/// The row of a measured sample in [`SeriesStore::ids`] order; the tracking error (the fifth
/// block of `n`) is NaN until its command is found.
fn measured_row(model: &RobotModel, m: MeasuredJson) -> MeasuredRow {
    let n = model.dof();
    let (drive_values, drive) = match &m.steps_per_s {
        Some(steps) => (steps.as_slice(), DriveKind::StepsPerS),
        None => (m.effort.as_slice(), DriveKind::TorqueNm),
    };
    let q: Vec<f64> = (0..n).map(|j| at(&m.position, j)).collect();
    let mut row = Vec::with_capacity(5 * n + 6);
    row.extend(q.iter().map(|&v| v as f32));
    row.extend((0..n).map(|j| at(&m.velocity, j) as f32));
    row.extend((0..n).map(|j| at(&m.acceleration, j) as f32));
    row.extend((0..n).map(|j| at(drive_values, j) as f32));
    row.extend((0..n).map(|_| f32::NAN));
    if q.iter().all(|v| v.is_finite()) {
        let tcp = model.fk(&q);
        row.extend(tcp.position_m.iter().map(|&v| v as f32));
        row.extend(tcp.rpy_rad.iter().map(|&v| v as f32));
    }
    MeasuredRow { seq: m.seq, time_s: m.time_s, stamp_ns: m.header.stamp.as_ns(), position: q, drive, row }
}

impl From<JointStateMsg> for MeasuredJson {
    fn from(m: JointStateMsg) -> Self {
        Self {
            header: Stamp { stamp: m.header.stamp },
            position: m.position,
            velocity: m.velocity,
            effort: m.effort,
            acceleration: m.acceleration,
            seq: m.seq,
            time_s: m.time_s,
            steps_per_s: m.steps_per_s,
        }
    }
}

/// Pairs each kept measured sample with its command and appends the row to the store.
struct RowAssembler<'m> {
    model: &'m RobotModel,
    store: SeriesStore,
    /// Measured samples waiting for their command.
    pending: VecDeque<MeasuredRow>,
    /// Motion time and stamp of the first row, for the events.
    first: Option<(f64, u64)>,
    drive: Option<DriveKind>,
    /// Log-time bucket of the last measured sample taken.
    last_bucket: Option<u64>,
    events: Vec<LogMsg>,
}

impl<'m> RowAssembler<'m> {
    fn new(model: &'m RobotModel) -> Self {
        Self {
            model,
            store: SeriesStore::new(model.dof(), f64::INFINITY),
            pending: VecDeque::new(),
            first: None,
            drive: None,
            last_bucket: None,
            events: Vec::new(),
        }
    }

    /// The next item in file order. A measured sample in the log-time bucket of the last one
    /// taken is skipped (the parallel path keeps the first of each bucket of every chunk).
    fn push(&mut self, item: Item) {
        match item {
            Item::Measured(bucket, m) => {
                if bucket.is_some() && self.last_bucket == bucket {
                    return;
                }
                self.last_bucket = bucket;
                self.pending.push_back(m);
                while self.pending.len() > 16 {
                    self.pending.pop_front();
                }
            }
            Item::Commanded(c) => {
                let Some(i) = self.pending.iter().position(|p| p.seq == c.seq) else { return };
                let Some(mut m) = self.pending.drain(..=i).next_back() else { return };
                let n = self.model.dof();
                for (j, e) in m.row[4 * n..5 * n].iter_mut().enumerate() {
                    *e = (at(&c.position, j) - m.position[j]) as f32;
                }
                self.first.get_or_insert((m.time_s, m.stamp_ns));
                self.drive = Some(m.drive);
                self.store.push_row(m.time_s, &m.row);
            }
            Item::Event(e) => self.events.push(e),
        }
    }

    fn finish(mut self, rec: &Recording, read_path: ReadPath) -> ReplayData {
        if let Some(kind) = self.drive {
            self.store.set_drive(kind);
        }
        let events = match self.first {
            Some((t0_s, stamp0_ns)) => self
                .events
                .iter()
                .map(|e| ReplayEvent {
                    time_s: t0_s + (e.timestamp.as_ns() as f64 - stamp0_ns as f64) * 1e-9,
                    level: e.level,
                    message: e.message.clone(),
                })
                .collect(),
            None => Vec::new(),
        };
        let mut warnings = rec.warnings.clone();
        if self.store.is_empty() {
            warnings.push("the recording holds no joint-state samples: nothing to replay".into());
        }
        ReplayData {
            store: self.store,
            events,
            robot: rec.robot().to_string(),
            program: rec.metadata.get("program").cloned().unwrap_or_default(),
            samples_in_file: rec.topics.get("/joint_states").map_or(0, |t| t.messages),
            warnings,
            truncated: rec.truncated,
            read_path,
        }
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
    let file = std::fs::File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    if let Some(data) = load_whole_replay(std::io::BufReader::with_capacity(1 << 16, file), len, model) {
        return Ok(data?);
    }
    let bytes = std::fs::read(path).map_err(io)?;
    Ok(load_linear(&bytes, model)?)
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
    match SliceSource::new(bytes).and_then(|source| load_parallel(source, model, decoding_threads())) {
        Ok(data) => data,
        Err(NotFast(_)) => load_linear(bytes, model),
    }
}

/// The parallel path: `Err` leaves the file to the linear reader.
fn load_parallel<'a>(
    source: impl RecordSource<'a>,
    model: &RobotModel,
    threads: usize,
) -> Result<Result<ReplayData, RecordingError>, NotFast> {
    let read = chunked::decode_chunks(source, threads, || {
        let mut last_bucket = [None::<u64>; 2];
        move |m: MessageRef<'_>| {
            let measured = match m.topic {
                "/joint_states" => true,
                "/joint_commands" => false,
                "/events" => {
                    return serde_json::from_slice(m.data).map(|e| Some(Item::Event(e))).map_err(|e| e.to_string());
                }
                _ => return Ok(None),
            };
            let bucket = m.log_time_ns / REPLAY_BUCKET_NS;
            let last = &mut last_bucket[usize::from(measured)];
            if *last == Some(bucket) {
                return Ok(None);
            }
            *last = Some(bucket);
            let item = if measured {
                serde_json::from_slice(m.data).map(|j| Item::Measured(Some(bucket), measured_row(model, j)))
            } else {
                serde_json::from_slice(m.data).map(Item::Commanded)
            };
            item.map(Some).map_err(|e| e.to_string())
        }
    })?;
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
    let mut rows = RowAssembler::new(model);
    for item in read.items {
        rows.push(item);
    }
    Ok(Ok(rows.finish(&rec, ReadPath::Parallel { threads: read.threads, chunks: read.chunks })))
}

/// The linear path: any file, whole or not.
fn load_linear(bytes: &[u8], model: &RobotModel) -> Result<ReplayData, RecordingError> {
    let mut rows = RowAssembler::new(model);
    let filter = ScanFilter { joint_bucket_ns: REPLAY_BUCKET_NS };
    let mut visit = |topic: &str, m: JointStateMsg| {
        rows.push(match topic {
            "/joint_states" => Item::Measured(None, measured_row(model, m.into())),
            _ => Item::Commanded(CommandedJson { position: m.position, seq: m.seq }),
        })
    };
    let rec = scan_recording_filtered(bytes, filter, &mut visit)?;
    rec.check_robot(model)?;
    for e in &rec.events {
        rows.push(Item::Event(e.clone()));
    }
    Ok(rows.finish(&rec, ReadPath::Linear))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::telemetry::reader::tests::recording_bytes;
    use crate::telemetry::series::{Quantity, SeriesId};

    #[test]
    fn a_recording_is_thinned_to_the_replay_rate_with_its_events() {
        // 2.5 s at 1 kHz
        let data = load_replay(&recording_bytes(2500), &RobotModel::parol6()).expect("replay");
        assert_eq!(data.samples_in_file, 2500);
        let kept = data.store.len();
        assert!((620..=630).contains(&kept), "about 250 Hz kept: {kept}");
        assert_eq!(data.events.len(), 1);
        let (t0, _) = data.store.time_range_s().expect("samples");
        assert!((data.events[0].time_s - 0.5).abs() < 1e-6 && t0 < 0.01, "event on the motion clock");
        assert_eq!(data.program, "demo");
        let tcp_x = data.store.column(SeriesId { quantity: Quantity::TcpPosition, index: 0 }).expect("column");
        assert!(data.store.window_stats(tcp_x, 0.0, 10.0).is_some_and(|s| s.max.is_finite()), "TCP from FK");
        assert!(data.warnings.is_empty() && !data.truncated, "{:?}", data.warnings);
        assert!(matches!(data.read_path, ReadPath::Parallel { chunks: 3.., .. }), "{:?}", data.read_path);
    }

    fn rows(data: &ReplayData) -> Vec<(u64, Vec<u32>)> {
        data.store
            .raw_window(f64::NEG_INFINITY, f64::INFINITY)
            .map(|(t, r)| (t.to_bits(), r.iter().map(|v| v.to_bits()).collect()))
            .collect()
    }

    #[test]
    fn the_parallel_and_the_linear_path_give_the_same_replay() {
        let model = RobotModel::parol6();
        let bytes = recording_bytes(3500);
        let linear = load_linear(&bytes, &model).expect("linear");
        assert_eq!(linear.read_path, ReadPath::Linear);
        for threads in [1, 2, 3] {
            let parallel = load_parallel(SliceSource::new(&bytes).expect("magic"), &model, threads)
                .expect("a whole file")
                .expect("replay");
            let path = parallel.read_path;
            assert!(matches!(path, ReadPath::Parallel { threads: t, chunks: 4.. } if t == threads), "{path:?}");
            assert_eq!(rows(&parallel), rows(&linear), "{threads} threads");
            assert_eq!(parallel.events, linear.events);
            assert_eq!(parallel.samples_in_file, 3500);
            assert_eq!((parallel.robot.as_str(), parallel.program.as_str()), ("parol6", "demo"));
            assert_eq!(parallel.warnings, linear.warnings);
        }
    }

    #[test]
    fn a_file_is_decoded_while_it_is_read_and_a_cut_file_still_replays() {
        let model = RobotModel::parol6();
        let bytes = recording_bytes(3500);
        let dir = std::env::temp_dir().join(format!("parol6-replay-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let whole = dir.join("whole.mcap");
        std::fs::write(&whole, &bytes).expect("write");
        let read = read_replay_file(&whole, &model).expect("replay");
        assert!(matches!(read.read_path, ReadPath::Parallel { .. }), "{:?}", read.read_path);
        assert_eq!(rows(&read), rows(&load_linear(&bytes, &model).expect("linear")));
        let cut = dir.join("cut.mcap");
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("write");
        let read = read_replay_file(&cut, &model).expect("what the complete chunks hold");
        assert!(read.truncated && read.read_path == ReadPath::Linear && !read.store.is_empty());
        let missing = dir.join("missing.mcap");
        match read_replay_file(&missing, &model) {
            Err(e @ ReplayError::Io { .. }) => assert!(e.to_string().contains("missing.mcap"), "{e}"),
            other => panic!("{other:?}"),
        }
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    #[test]
    fn a_damaged_chunk_is_left_to_the_linear_reader_which_names_it() {
        let model = RobotModel::parol6();
        let mut bytes = recording_bytes(2500);
        // a byte in the middle of the file: inside the second chunk's compressed records
        let at = bytes.len() / 2;
        bytes[at] ^= 0x5a;
        assert!(
            load_parallel(SliceSource::new(&bytes).expect("magic"), &model, 2).is_err(),
            "the parallel path refuses it"
        );
        let data = load_replay(&bytes, &model).expect("what can be read");
        assert_eq!(data.read_path, ReadPath::Linear);
        assert!(data.truncated && data.warnings.iter().any(|w| w.contains("damaged")), "{:?}", data.warnings);
        assert!(!data.store.is_empty() && data.store.len() < 620, "{}", data.store.len());
    }

    #[test]
    fn bad_files_are_named_and_a_cut_file_replays_what_it_holds() {
        let model = RobotModel::parol6();
        assert!(matches!(load_replay(&[], &model), Err(RecordingError::Empty)));
        assert!(matches!(load_replay(b"not a recording", &model), Err(RecordingError::NotMcap)));
        let bytes = recording_bytes(2500);
        let cut = load_replay(&bytes[..bytes.len() * 2 / 3], &model).expect("the complete chunks");
        assert!(cut.truncated && cut.warnings.iter().any(|w| w.contains("cut short")), "{:?}", cut.warnings);
        assert_eq!(cut.read_path, ReadPath::Linear);
        assert!(!cut.store.is_empty() && cut.store.len() < 600, "{}", cut.store.len());
        let other = RobotModel::from_urdf_str(
            r#"<robot name="two"><link name="a"/><link name="b"/>
            <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#,
            &crate::model::LoadOptions::default(),
        )
        .expect("model");
        match load_replay(&bytes, &other) {
            Err(e @ RecordingError::OtherRobot { .. }) => assert!(e.to_string().contains("\"parol6\""), "{e}"),
            other => panic!("{other:?}"),
        }
    }
}

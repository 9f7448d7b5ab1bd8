//! [`McapSink`]: writes [`TelemetrySample`]s and [`TelemetryEvent`]s to an MCAP file.
//!
//! Channels: `/robot_description` (once, at the start), `/joint_states` and `/joint_commands`
//! (every sample), `/tf` and `/tcp_pose` (at most 100 Hz), encoded by [`TelemetryEncoder`] (the
//! live servers use the same encoder),
//! `/events`, `/link` (when the link state, E-stop or loss count changes, else once a
//! second), and a metadata record
//! ([`super::schema::METADATA_NAME`]: app version, robot, tool, program, tracking mode, joints). Chunks are
//! zstd-compressed and closed at least every [`FLUSH_INTERVAL_S`] of motion time or wall
//! time, whichever comes first ([`McapSink::flush_if_due`]), so a crash loses at most that;
//! [`McapSink::finish`] writes the summary and index.
//!
//! [`McapSink::create_file`] records a new file in place (a crash leaves every closed chunk
//! readable there). An existing recording is never truncated: the new one is written beside it
//! as `NAME.recording` and renamed over it only by [`McapSink::finish_file`], so a crash or a
//! full disk keeps the old file whole and the new one readable up to its last chunk. A target
//! that is not a regular file (a FIFO, a device, a directory) is refused.
//!
//! Message log times are Unix nanoseconds: the wall-clock time of the recording's first sample
//! plus the backend's motion time since it.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use mcap::records::{MessageHeader, Metadata};
use mcap::{Compression, WriteOptions, Writer};

use crate::model::RobotModel;

use super::TelemetryError;
use super::encode::{Channel, TelemetryEncoder};
use super::event::TelemetryEvent;
use super::sample::TelemetrySample;
use super::schema;

/// Chunks are closed at least this often (of motion time and of wall time), s: a crash
/// (SIGKILL, a power loss) loses at most the open chunk. The reader also gives back what a
/// chunk cut short holds up to the cut, a zstd block of up to 128 KiB of records at a time.
pub const FLUSH_INTERVAL_S: f64 = 0.25;

/// A chunk is closed once its uncompressed records pass this size (8 MiB: about 6 s of a 1 kHz
/// simulation), so at the rates we record the time-based flush closes them.
const CHUNK_BYTES: u64 = 8 << 20;

/// What the metadata record says about a recording.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RecordingInfo {
    /// Version of the app that wrote it.
    pub app_version: String,
    /// Tool fitted (`none`, `ssg48`, …).
    pub tool: String,
    /// Program being run (empty: none).
    pub program: String,
    /// The robot's URDF text, written to `/robot_description`.
    pub urdf_text: String,
    /// Tracking mode of the motion recorded (`official`, `lead`, `feedforward`; empty: not known).
    pub tracking: String,
}

/// What a finished recording holds.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordingSummary {
    /// Samples written (one `/joint_states` and one `/joint_commands` message each).
    pub samples: u64,
    /// Events written.
    pub events: u64,
    /// Messages written, all channels.
    pub messages: u64,
    /// Chunks closed by the periodic flush.
    pub flushes: u64,
    /// Motion time covered, s.
    pub duration_s: f64,
}

/// A file that reaches the disk on every flush (`sync_data`), so a power loss loses at most
/// the chunk being written.
#[derive(Debug)]
pub struct SyncedFile {
    out: BufWriter<KeptBytes<File>>,
    /// Where the recording goes when it is finished, if it is written beside an existing file.
    replaces: Option<(PathBuf, PathBuf)>,
    /// That existing file, held open and locked until it is replaced, so that no other
    /// recording starts on it meanwhile (a file written in place is locked through `out`).
    _replaced: Option<File>,
}

impl SyncedFile {
    /// Renames a recording written beside an existing file over it (nothing to do otherwise).
    fn commit(self) -> Result<(), TelemetryError> {
        if let Some((tmp, target)) = self.replaces {
            std::fs::rename(&tmp, &target).map_err(|e| TelemetryError::Io {
                path: target.display().to_string(),
                reason: format!("the finished recording {} could not replace it: {e}", tmp.display()),
            })?;
        }
        Ok(())
    }
}

impl Write for SyncedFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.out.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()?;
        let file = self.out.get_ref();
        file.inner.sync_data().map_err(|e| file.explain(e))
    }
}

/// A writer that counts the bytes its file keeps (the furthest byte written) and names them,
/// and a full disk, in its errors: "no space left on device (ENOSPC); the file keeps its first
/// N bytes …".
#[derive(Debug)]
pub struct KeptBytes<W> {
    inner: W,
    pos: u64,
    kept_bytes: u64,
}

impl<W> KeptBytes<W> {
    /// Counts what `inner` (an empty file) keeps.
    pub fn new(inner: W) -> Self {
        Self { inner, pos: 0, kept_bytes: 0 }
    }

    /// Bytes the file holds so far.
    pub fn kept_bytes(&self) -> u64 {
        self.kept_bytes
    }

    fn explain(&self, e: std::io::Error) -> std::io::Error {
        let kept = self.kept_bytes;
        std::io::Error::new(
            e.kind(),
            format!("{}; the file keeps its first {kept} bytes, readable up to its last whole chunk", describe_io(&e)),
        )
    }
}

impl<W: Write> Write for KeptBytes<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf).map_err(|e| self.explain(e))?;
        self.pos += n as u64;
        self.kept_bytes = self.kept_bytes.max(self.pos);
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush().map_err(|e| self.explain(e))
    }
}

impl<W: Seek> Seek for KeptBytes<W> {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.pos = self.inner.seek(pos).map_err(|e| self.explain(e))?;
        Ok(self.pos)
    }
}

/// What an I/O error says, a full disk named as such (ENOSPC).
pub fn describe_io(e: &std::io::Error) -> String {
    if e.kind() == std::io::ErrorKind::StorageFull && e.get_ref().is_none() {
        "no space left on device (ENOSPC)".to_string()
    } else {
        e.to_string()
    }
}

impl Seek for SyncedFile {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.out.seek(pos)
    }
}

/// The MCAP channel id of each of our channels.
type ChannelIds = BTreeMap<Channel, u16>;

/// Writes one MCAP recording. See the module docs.
pub struct McapSink<W: Write + Seek> {
    writer: Writer<W>,
    channels: ChannelIds,
    encoder: TelemetryEncoder,
    sequence: u32,
    last_flush_s: f64,
    last_flush_at: Instant,
    summary: RecordingSummary,
}

impl<W: Write + Seek> std::fmt::Debug for McapSink<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("McapSink").field("summary", &self.summary).finish_non_exhaustive()
    }
}

impl McapSink<SyncedFile> {
    /// Starts a recording at `path`: a new file is written in place; over an existing regular
    /// file the recording goes to `NAME.recording` beside it until [`McapSink::finish_file`]
    /// renames it over the old one. A `path` that is not a regular file is refused.
    pub fn create_file(path: &Path, model: &RobotModel, info: &RecordingInfo) -> Result<Self, TelemetryError> {
        let exists = std::fs::symlink_metadata(path).is_ok();
        let io = |e: std::io::Error| TelemetryError::Io { path: path.display().to_string(), reason: e.to_string() };
        let (file, replaces, replaced) = if exists {
            crate::fsio::check_regular(path)?;
            let target = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
            let replaced = File::open(&target).map_err(io)?;
            lock_for_recording(&replaced, path)?;
            let (tmp, file) = create_beside(&target).map_err(io)?;
            (file, Some((tmp, target)), Some(replaced))
        } else {
            let file = std::fs::OpenOptions::new().write(true).create_new(true).open(path).map_err(io)?;
            lock_for_recording(&file, path)?;
            (file, None, None)
        };
        let out =
            SyncedFile { out: BufWriter::with_capacity(1 << 16, KeptBytes::new(file)), replaces, _replaced: replaced };
        Self::new(out, model, info)
    }

    /// [`McapSink::finish`], then a recording written beside an existing file replaces it.
    pub fn finish_file(self) -> Result<RecordingSummary, TelemetryError> {
        let (summary, file) = self.finish_into_inner()?;
        file.commit()?;
        Ok(summary)
    }
}

/// Locks `file` (at `path`) as a recording's target for as long as it stays open: a window
/// and `parol6 record` recording to one file replaced each other's recording, and the one
/// reported as saved was lost. Refused while another recording holds it; on a file system
/// without locks the recording goes on unlocked.
fn lock_for_recording(file: &File, path: &Path) -> Result<(), TelemetryError> {
    match file.try_lock() {
        Ok(()) => Ok(()),
        Err(std::fs::TryLockError::WouldBlock) => Err(TelemetryError::Io {
            path: path.display().to_string(),
            reason: "it is being recorded to now (by another window or parol6 record): stop that \
                     recording first, or choose another file"
                .into(),
        }),
        // no locks here (e.g. some network file systems): nothing to hold
        Err(std::fs::TryLockError::Error(_)) => Ok(()),
    }
}

/// Creates `TARGET.recording` (or `TARGET.recording-N` if that exists) beside `target`.
fn create_beside(target: &Path) -> std::io::Result<(PathBuf, File)> {
    let mut name = target.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(".recording");
    let first = target.with_file_name(&name);
    let mut last = std::io::Error::from(std::io::ErrorKind::AlreadyExists);
    for n in 0..100 {
        let candidate = if n == 0 {
            first.clone()
        } else {
            let mut numbered = name.clone();
            numbered.push(format!("-{n}"));
            target.with_file_name(numbered)
        };
        match std::fs::OpenOptions::new().write(true).create_new(true).open(&candidate) {
            Ok(f) => return Ok((candidate, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = e,
            Err(e) => return Err(e),
        }
    }
    Err(last)
}

/// Nanoseconds since the Unix epoch now.
pub fn unix_now_ns() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)).unwrap_or(0)
}

impl<W: Write + Seek> McapSink<W> {
    /// Starts a recording on `w`: header, schemas, channels, metadata and the URDF.
    pub fn new(w: W, model: &RobotModel, info: &RecordingInfo) -> Result<Self, TelemetryError> {
        let options = WriteOptions::new()
            .compression(Some(Compression::Zstd))
            .chunk_size(Some(CHUNK_BYTES))
            // compressed on the recorder's own thread: zstd's worker threads (one per core by
            // default) took ~20 MB of buffers each, for a stream of a few hundred kB/s
            .compression_threads(0)
            .profile("")
            .library(format!("parol6-studio {}", info.app_version));
        let mut writer = options.create(w)?;
        let none = BTreeMap::new();
        let mut channels = ChannelIds::new();
        for c in Channel::ALL {
            let schema_id = writer.add_schema(c.schema_name(), schema::SCHEMA_ENCODING, c.schema_text().as_bytes())?;
            channels.insert(c, writer.add_channel(schema_id, c.topic(), schema::MESSAGE_ENCODING, &none)?);
        }
        let joint_names: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
        let start_unix_ns = unix_now_ns();
        let metadata = BTreeMap::from([
            ("app_version".to_string(), info.app_version.clone()),
            ("robot".to_string(), model.name.clone()),
            ("tool".to_string(), info.tool.clone()),
            ("program".to_string(), info.program.clone()),
            ("tracking".to_string(), info.tracking.clone()),
            ("joints".to_string(), joint_names.join(",")),
            ("root_link".to_string(), model.root_link.clone()),
            ("started_unix_ns".to_string(), start_unix_ns.to_string()),
        ]);
        writer.write_metadata(&Metadata { name: schema::METADATA_NAME.into(), metadata })?;
        let text = (!info.urdf_text.is_empty()).then_some(info.urdf_text.as_str());
        let encoder = TelemetryEncoder::new(model, text, start_unix_ns);
        let data = encoder.robot_description(&info.urdf_text)?;
        let header = MessageHeader {
            channel_id: channels.get(&Channel::RobotDescription).copied().unwrap_or_default(),
            sequence: 0,
            log_time: start_unix_ns,
            publish_time: start_unix_ns,
        };
        writer.write_to_known_channel(&header, &data)?;
        Ok(Self {
            writer,
            channels,
            encoder,
            sequence: 1,
            last_flush_s: 0.0,
            last_flush_at: Instant::now(),
            summary: RecordingSummary { samples: 0, events: 0, messages: 1, flushes: 0, duration_s: 0.0 },
        })
    }

    /// Highest rate of `/tf` and `/tcp_pose`, Hz (100).
    pub fn set_pose_rate_hz(&mut self, rate_hz: f64) {
        self.encoder.pose_rate_hz = rate_hz;
    }

    /// Writes one sample: joint states and commands always, `/tf` and `/tcp_pose` at most at
    /// 100 Hz, `/link` when the link health changed ([`TelemetryEncoder::encode_sample`]).
    pub fn write_sample(&mut self, s: &TelemetrySample) -> Result<(), TelemetryError> {
        let Self { writer, channels, encoder, sequence, summary, .. } = self;
        encoder.encode_sample(s, |c, log_time, data| {
            write_message(writer, channels, sequence, summary, c, log_time, data)
        })?;
        self.summary.samples += 1;
        let t0 = self.encoder.first_time_s().unwrap_or(s.time_s);
        self.summary.duration_s = (s.time_s - t0).max(self.summary.duration_s);
        self.flush_if_due(s.time_s)
    }

    /// Writes one event to `/events`.
    pub fn write_event(&mut self, e: &TelemetryEvent) -> Result<(), TelemetryError> {
        let Self { writer, channels, encoder, sequence, summary, .. } = self;
        encoder.encode_event(e, |c, log_time, data| {
            write_message(writer, channels, sequence, summary, c, log_time, data)
        })?;
        self.summary.events += 1;
        Ok(())
    }

    /// Closes the current chunk and flushes the file when [`FLUSH_INTERVAL_S`] of motion time
    /// (`now_s`) or of wall time has passed since the last flush.
    pub fn flush_if_due(&mut self, now_s: f64) -> Result<(), TelemetryError> {
        let motion_due = now_s - self.last_flush_s >= FLUSH_INTERVAL_S;
        if motion_due || self.last_flush_at.elapsed().as_secs_f64() >= FLUSH_INTERVAL_S {
            self.writer.flush()?;
            self.last_flush_s = now_s;
            self.last_flush_at = Instant::now();
            self.summary.flushes += 1;
        }
        Ok(())
    }

    /// What has been written so far.
    pub fn summary(&self) -> &RecordingSummary {
        &self.summary
    }

    /// Writes the summary section and the footer; returns what the file holds.
    pub fn finish(self) -> Result<RecordingSummary, TelemetryError> {
        self.finish_into_inner().map(|(summary, _)| summary)
    }

    /// [`McapSink::finish`], also returning the underlying writer.
    pub fn finish_into_inner(mut self) -> Result<(RecordingSummary, W), TelemetryError> {
        self.writer.finish()?;
        let mut w = self.writer.into_inner();
        w.flush().map_err(|e| TelemetryError::Write(describe_io(&e)))?;
        Ok((self.summary, w))
    }
}

/// Writes one encoded message on its channel.
fn write_message<W: Write + Seek>(
    writer: &mut Writer<W>,
    channels: &ChannelIds,
    sequence: &mut u32,
    summary: &mut RecordingSummary,
    channel: Channel,
    log_time: u64,
    data: &[u8],
) -> Result<(), TelemetryError> {
    let channel_id = channels
        .get(&channel)
        .copied()
        .ok_or_else(|| TelemetryError::Mcap(format!("no channel {}", channel.topic())))?;
    let header = MessageHeader { channel_id, sequence: *sequence, log_time, publish_time: log_time };
    *sequence = sequence.wrapping_add(1);
    writer.write_to_known_channel(&header, data)?;
    summary.messages += 1;
    Ok(())
}

#[cfg(test)]
mod tests;

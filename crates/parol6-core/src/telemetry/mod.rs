//! Telemetry: what the robot did, sample by sample, for the live view and for MCAP files.
//!
//! - [`sample`]: a [`TelemetrySample`] per control tick, built from the backends'
//!   [`MotionSample`](crate::motion::MotionSample) tap (commanded and measured joints, TCP pose,
//!   worst limit zone, program step, link health);
//! - [`event`]: [`TelemetryEvent`]s (limit warnings, refusals, E-stop, link loss) and the
//!   detector that finds them in successive samples and robot states;
//! - [`ring`]: the last minutes of samples, published lock-free as a [`LiveView`];
//! - [`recorder`]: the [`Recorder`], which owns its thread and bounded channels, never blocks a
//!   sender, and writes an MCAP file while recording;
//! - [`schema`]: the JSON messages and JSON schemas of the MCAP channels (Foxglove's
//!   well-known schemas where one exists);
//! - [`frames`]: the `/tf` transforms (one per URDF joint, parent link → child link);
//! - [`handshake`]: the Foxglove WebSocket handshake's two names of one subprotocol;
//! - [`encode`]: the one encoder of samples and events into our channels' JSON messages, used
//!   by the MCAP writer and by the live servers (fed from the recorder's live outlets);
//! - [`writer`]: the MCAP writer (zstd chunks closed at least every 0.25 s, summary + index);
//! - [`reader`]: the reader of our own files, tolerant of truncation and damage ([`walk`]);
//! - [`chunked`]: the parallel decoder of whole files' chunks, the fast path of [`replay`];
//! - [`replay`]: a recording loaded into the plots' series for the timeline.

use crate::limits::LimitZone;

pub mod chunked;
pub mod encode;
pub mod event;
pub mod frames;
pub mod handshake;
pub mod reader;
pub mod recorder;
pub mod replay;
pub mod ring;
pub mod sample;
pub mod schema;
pub mod series;
pub mod walk;
pub mod writer;

pub use encode::{Channel, EncodeError, TelemetryEncoder};
pub use event::{EventDetector, EventKind, TelemetryEvent};
pub use reader::{Recording, RecordingError, read_recording};
pub use recorder::{LiveItem, LiveOutlet, Recorder, RecorderConfig, RecorderEvents, RecorderStats};
pub use replay::{
    ReadPath, ReplayData, ReplayError, ReplayEvent, ReplayLink, load_replay, load_whole_replay, read_replay_file,
};
pub use ring::{LiveRing, LiveView};
pub use sample::{DriveKind, JointTelemetry, LinkHealth, SampleBuilder, TelemetrySample};
pub use series::{Quantity, SeriesId, SeriesStore, WindowStats};
pub use writer::{McapSink, RecordingInfo, RecordingSummary};

/// Why telemetry could not be recorded or read.
#[derive(Debug, thiserror::Error)]
pub enum TelemetryError {
    /// A file could not be created, written or read.
    #[error("{path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The recording's path was refused (not a regular file) or could not be checked.
    #[error(transparent)]
    File(#[from] crate::fsio::FsioError),
    /// The MCAP library refused a record.
    #[error("MCAP: {0}")]
    Mcap(String),
    /// Writing the recording failed (a full disk is named ENOSPC, with the bytes the file keeps).
    #[error("{0}")]
    Write(String),
    /// The recorder is not in a state to do this (already recording, not recording, stopped).
    #[error("{0}")]
    State(String),
    /// The recorder's thread has stopped or did not answer.
    #[error("the recorder thread has stopped")]
    Stopped,
}

impl From<encode::EncodeError> for TelemetryError {
    fn from(e: encode::EncodeError) -> Self {
        TelemetryError::Mcap(e.to_string())
    }
}

impl From<mcap::McapError> for TelemetryError {
    fn from(e: mcap::McapError) -> Self {
        match e {
            mcap::McapError::Io(io) => TelemetryError::Write(writer::describe_io(&io)),
            e => TelemetryError::Mcap(e.to_string()),
        }
    }
}

/// Short lowercase name of a limit zone in files and CSV (`safe`, `warning`, `critical`).
pub fn zone_name(zone: LimitZone) -> &'static str {
    match zone {
        LimitZone::Safe => "safe",
        LimitZone::Warning => "warning",
        LimitZone::Critical => "critical",
    }
}

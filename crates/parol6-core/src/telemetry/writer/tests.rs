//! Writer tests: a full disk (ENOSPC) is named, with the bytes the file keeps.

use std::io::{Seek, SeekFrom, Write};
use std::path::Path;

use super::*;
use crate::model::PAROL6_URDF;
use crate::telemetry::reader::tests::sample;

fn info() -> RecordingInfo {
    RecordingInfo {
        app_version: "test".into(),
        tool: "none".into(),
        program: String::new(),
        urdf_text: PAROL6_URDF.into(),
        tracking: String::new(),
    }
}

/// Writes samples at 1 kHz until the sink fails; its error.
fn write_until_error<W: Write + Seek>(mut sink: McapSink<W>) -> TelemetryError {
    for k in 1..=20_000 {
        if let Err(e) = sink.write_sample(&sample(k, 1e-3)) {
            return e;
        }
    }
    sink.finish().expect_err("the disk is full")
}

/// A disk that takes `room` bytes, then answers ENOSPC.
struct SmallDisk {
    data: Vec<u8>,
    pos: u64,
    room: usize,
}

impl Write for SmallDisk {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let pos = self.pos as usize;
        let end = pos + buf.len();
        if end > self.room {
            return Err(std::io::Error::from_raw_os_error(28));
        }
        if self.data.len() < end {
            self.data.resize(end, 0);
        }
        self.data[pos..end].copy_from_slice(buf);
        self.pos = end as u64;
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Seek for SmallDisk {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.pos = match pos {
            SeekFrom::Start(p) => p,
            SeekFrom::End(d) => (self.data.len() as i64 + d) as u64,
            SeekFrom::Current(d) => (self.pos as i64 + d) as u64,
        };
        Ok(self.pos)
    }
}

/// Issue 29 item 15: the full-disk error names ENOSPC and the bytes the file keeps (it said
/// "MCAP: I/O error from writing, or reading a compression stream").
#[test]
fn a_full_disk_names_enospc_and_the_bytes_kept() {
    let model = RobotModel::parol6();
    // a disk that is full from the start
    let full = SmallDisk { data: Vec::new(), pos: 0, room: 0 };
    let e = match McapSink::new(KeptBytes::new(full), &model, &info()) {
        Ok(sink) => write_until_error(sink),
        Err(e) => e,
    };
    let msg = e.to_string();
    assert!(msg.contains("no space left on device (ENOSPC)") && msg.contains("keeps its first 0 bytes"), "{msg}");
    // a disk that fills after 200 kB
    let disk = SmallDisk { data: Vec::new(), pos: 0, room: 200_000 };
    let msg = write_until_error(McapSink::new(KeptBytes::new(disk), &model, &info()).expect("sink")).to_string();
    assert!(msg.contains("no space left on device (ENOSPC)"), "{msg}");
    let kept: u64 = msg
        .split("keeps its first ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{msg}"));
    assert!(kept > 100_000 && kept <= 200_000, "{msg}");
}

fn scratch_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("parol6-writer-{name}-{}", std::process::id()));
    let _ignored_if_absent = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// Issue 29 item 1: a recording started over an existing one truncated it at once, so a crash
/// or a full disk lost the old recording. Now the old file stays whole until the new one is
/// finished, and the new one is readable beside it up to its last closed chunk.
#[test]
fn a_recording_over_an_existing_one_keeps_it_until_finished() {
    let model = RobotModel::parol6();
    let dir = scratch_dir("replace");
    let path = dir.join("run.mcap");
    std::fs::write(&path, b"the old recording").expect("old file");
    let mut sink = McapSink::create_file(&path, &model, &info()).expect("sink");
    let beside = dir.join("run.mcap.recording");
    assert!(beside.exists());
    for k in 1..=500 {
        sink.write_sample(&sample(k, 1e-3)).expect("sample");
    }
    sink.flush_if_due(1e9).expect("flush");
    // a crash now (the sink is never finished) keeps the old file and a readable new one
    assert_eq!(std::fs::read(&path).expect("old"), b"the old recording");
    let partial = crate::telemetry::read_recording(&std::fs::read(&beside).expect("read")).expect("partial recording");
    assert!(partial.measured.len() > 400, "{}", partial.measured.len());
    sink.finish_file().expect("finish");
    assert!(!beside.exists());
    let whole = crate::telemetry::read_recording(&std::fs::read(&path).expect("read")).expect("new recording");
    assert_eq!(whole.measured.len(), 500);
    // a second recording beside a stale `.recording` left by a crash does not touch it
    std::fs::write(&beside, b"left by a crash").expect("stale");
    let sink = McapSink::create_file(&path, &model, &info()).expect("sink");
    assert!(dir.join("run.mcap.recording-1").exists());
    sink.finish_file().expect("finish");
    assert_eq!(std::fs::read(&beside).expect("stale"), b"left by a crash");
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

/// Trial11 (issue 32): a second window on the same HOME recording to the file a first one was
/// still writing replaced it when it finished; the first window's recording, reported as
/// "recorded 17662 samples (45.4 s) to …/dup.mcap", was lost. A file that a recording is
/// written to, or will replace, is now refused as the target of another until that one is
/// finished.
#[test]
fn a_file_being_recorded_is_refused_as_the_target_of_another_recording() {
    let model = RobotModel::parol6();
    let dir = scratch_dir("busy");
    let path = dir.join("run.mcap");
    // the first recording is written in place
    let first = McapSink::create_file(&path, &model, &info()).expect("first");
    let e = McapSink::create_file(&path, &model, &info()).expect_err("a second recording to the same file");
    assert!(e.to_string().contains("being recorded"), "{e}");
    assert!(!dir.join("run.mcap.recording").exists());
    first.finish_file().expect("finish");
    // the next one is written beside the finished file, which it will replace: as busy
    let second = McapSink::create_file(&path, &model, &info()).expect("over the finished one");
    let e = McapSink::create_file(&path, &model, &info()).expect_err("a third recording to the same file");
    assert!(e.to_string().contains("being recorded"), "{e}");
    second.finish_file().expect("finish");
    McapSink::create_file(&path, &model, &info()).expect("free again").finish_file().expect("finish");
    assert!(crate::telemetry::read_recording(&std::fs::read(&path).expect("read")).is_ok());
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

/// Issue 29 item 1: a FIFO or a device as the recording was opened and written (a FIFO blocked
/// the start until a reader came); now it is refused before anything is opened.
#[test]
fn a_recording_onto_a_device_fifo_or_directory_is_refused() {
    let model = RobotModel::parol6();
    let dir = scratch_dir("refuse");
    let fifo = dir.join("pipe.mcap");
    let c = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).expect("path");
    // SAFETY: mkfifo reads a NUL-terminated path that outlives the call.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    for p in [Path::new("/dev/full"), fifo.as_path(), dir.as_path()] {
        match McapSink::create_file(p, &model, &info()) {
            Err(TelemetryError::File(e)) => assert!(e.is_refusal(), "{p:?}: {e}"),
            other => panic!("{p:?}: {other:?}"),
        }
    }
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

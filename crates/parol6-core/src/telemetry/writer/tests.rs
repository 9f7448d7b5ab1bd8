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
    // /dev/full: every write fails with ENOSPC
    let e = match McapSink::create_file(Path::new("/dev/full"), &model, &info()) {
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

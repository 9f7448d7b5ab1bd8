//! Fuzz body `mcap_cut` (issue 29): a valid recording of ours, built once here, with chunk
//! headers (and compressed bytes) changed as the input says and cut at the byte it says, goes
//! to the one-pass reader (which the replay uses for every file that is not whole; the
//! `mcap_reader` target fuzzes the replay's paths on any bytes). Nothing panics, and every sample of every intact
//! chunk (unchanged, and wholly before the cut) is read, as long as the channels can be known
//! (the first chunk is intact, or the file is not cut: the summary repeats them).

use std::io::Cursor;
use std::sync::OnceLock;

use parol6_core::kinematics::TcpPose;
use parol6_core::limits::LimitZone;
use parol6_core::model::RobotModel;
use parol6_core::telemetry::reader::read_recording;
use parol6_core::telemetry::{
    DriveKind, EventKind, JointTelemetry, McapSink, RecordingInfo, TelemetryEvent, TelemetrySample,
};

/// A chunk of the valid recording: where it is, and the log times of its messages (ns).
#[derive(Debug)]
struct Chunk {
    start: usize,
    end: usize,
    first_ns: u64,
    last_ns: u64,
}

/// The valid recording, its chunks and its samples (sequence, log time in ns).
#[derive(Debug)]
struct Valid {
    bytes: Vec<u8>,
    chunks: Vec<Chunk>,
    samples: Vec<(u64, u64)>,
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    b.get(at..at + 8).and_then(|s| s.try_into().ok()).map_or(0, u64::from_le_bytes)
}

/// 1.2 s at 20 Hz, one event, no URDF text, the TCP pose and transforms once a second: five
/// chunks of samples of 0.25 s after the first (schemas and channels), a few kB.
fn valid() -> &'static Valid {
    static VALID: OnceLock<Valid> = OnceLock::new();
    VALID.get_or_init(|| {
        let model = RobotModel::parol6();
        let info = RecordingInfo { app_version: "fuzz".into(), tool: "none".into(), ..RecordingInfo::default() };
        let mut sink = McapSink::new(Cursor::new(Vec::new()), &model, &info).unwrap_or_else(|e| panic!("sink: {e}"));
        sink.set_pose_rate_hz(1.0);
        for k in 1..=24u64 {
            let joints = (0..6)
                .map(|i| JointTelemetry {
                    cmd_q_rad: 0.01 * (k + i) as f64,
                    cmd_qd_rad_s: 0.1,
                    cmd_qdd_rad_s2: 0.0,
                    q_rad: 0.01 * (k + i) as f64 - 1e-4,
                    qd_rad_s: 0.1,
                    qdd_rad_s2: 0.0,
                    drive: 1.0,
                    zone: LimitZone::Safe,
                })
                .collect();
            let s = TelemetrySample {
                seq: k,
                time_s: k as f64 * 0.05,
                joints,
                drive: DriveKind::TorqueNm,
                tcp: TcpPose::from_xyz_rpy([0.2, 0.0, 0.3], [0.0; 3]),
                worst_zone: None,
                program_step: None,
                link: None,
            };
            sink.write_sample(&s).unwrap_or_else(|e| panic!("sample: {e}"));
            if k == 12 {
                let e = TelemetryEvent { time_s: s.time_s, kind: EventKind::Note, message: "half way".into() };
                sink.write_event(&e).unwrap_or_else(|e| panic!("event: {e}"));
            }
        }
        let (_, cursor) = sink.finish_into_inner().unwrap_or_else(|e| panic!("finish: {e}"));
        let bytes = cursor.into_inner();
        assert!(bytes.len() < 65_536, "a cut offset is two bytes: {} bytes", bytes.len());
        let mut chunks = Vec::new();
        let mut pos = 8;
        while pos + 9 <= bytes.len() && bytes[pos] != 0x0f {
            let end = pos + 9 + u64_at(&bytes, pos + 1) as usize;
            if bytes[pos] == 0x06 {
                chunks.push(Chunk {
                    start: pos,
                    end,
                    first_ns: u64_at(&bytes, pos + 9),
                    last_ns: u64_at(&bytes, pos + 17),
                });
            }
            pos = end;
        }
        let rec = read_recording(&bytes).unwrap_or_else(|e| panic!("the valid recording reads: {e}"));
        let samples = rec.measured.iter().map(|m| (m.seq, m.header.stamp.as_ns())).collect::<Vec<_>>();
        assert_eq!(samples.len(), 24);
        assert!(chunks.len() >= 5, "{chunks:?}");
        Valid { bytes, chunks, samples }
    })
}

/// Chunk header fields by offset from the record's start: opcode, length, start and end time,
/// uncompressed size, CRC, compression name length, name, compressed size; then the data.
const FIELDS: [(usize, usize); 9] = [(0, 1), (1, 8), (9, 8), (17, 8), (25, 8), (33, 4), (37, 4), (41, 4), (45, 8)];

/// Input: two bytes of cut offset (`ff ff`: none), then mutations of ten bytes each (chunk, field, value). A
/// field past the header's changes one byte of the compressed data.
pub fn mcap_cut(data: &[u8]) {
    let v = valid();
    let mut bytes = v.bytes.clone();
    let mut damaged = vec![false; v.chunks.len()];
    let (cut, mutations) = match data {
        [0xff, 0xff, rest @ ..] => (bytes.len(), rest),
        [a, b, rest @ ..] => (usize::from(u16::from_le_bytes([*a, *b])) % (bytes.len() + 1), rest),
        _ => (bytes.len(), data),
    };
    for m in mutations.chunks_exact(10) {
        let i = usize::from(m[0]) % v.chunks.len();
        let c = &v.chunks[i];
        let value = u64::from_le_bytes(m[2..10].try_into().unwrap_or_default());
        let field = usize::from(m[1]) % (FIELDS.len() + 1);
        let before = bytes[c.start..c.end].to_vec();
        match FIELDS.get(field) {
            Some(&(at, len)) => bytes[c.start + at..c.start + at + len].copy_from_slice(&value.to_le_bytes()[..len]),
            None => {
                let data_len = c.end - c.start - 53;
                let at = c.start + 53 + (value as usize) % data_len.max(1);
                bytes[at] ^= ((value >> 32) as u8) | 1;
            }
        }
        damaged[i] |= bytes[c.start..c.end] != before[..];
    }
    let bytes = &bytes[..cut];
    let read = read_recording(bytes);
    let channels_known = cut == v.bytes.len() || (!damaged[0] && v.chunks[0].end <= cut);
    if !channels_known {
        return;
    }
    let intact: Vec<&Chunk> =
        v.chunks.iter().zip(&damaged).filter(|(c, d)| !**d && c.end <= cut).map(|(c, _)| c).collect();
    let expected: Vec<u64> = v
        .samples
        .iter()
        .filter(|(_, t)| intact.iter().any(|c| (c.first_ns..=c.last_ns).contains(t)))
        .map(|(seq, _)| *seq)
        .collect();
    if expected.is_empty() {
        return;
    }
    let rec = read.unwrap_or_else(|e| panic!("cut at {cut}, damaged {damaged:?}: {e}"));
    for seq in &expected {
        assert!(
            rec.measured.iter().any(|m| m.seq == *seq),
            "cut at {cut}, damaged {damaged:?}: sample {seq} of an intact chunk is missing; {:?}",
            rec.warnings
        );
    }
}

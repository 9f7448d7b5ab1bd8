//! Reader tests: our files read back whole; empty, garbage, truncated, foreign and
//! other-robot files give the error or warning that names the problem.

use std::collections::BTreeMap;
use std::io::Cursor;

use super::*;
use crate::kinematics::TcpPose;
use crate::model::PAROL6_URDF;
use crate::telemetry::event::{EventKind, TelemetryEvent};
use crate::telemetry::sample::{DriveKind, JointTelemetry, TelemetrySample};
use crate::telemetry::writer::{McapSink, RecordingInfo};

pub(crate) fn sample(seq: u64, dt_s: f64) -> TelemetrySample {
    let joints = (0..6)
        .map(|i| JointTelemetry {
            cmd_q_rad: 0.1 * i as f64,
            cmd_qd_rad_s: 0.0,
            cmd_qdd_rad_s2: 0.0,
            q_rad: 0.1 * i as f64 + 1e-4,
            qd_rad_s: 0.0,
            qdd_rad_s2: 0.0,
            drive: 1.0,
            zone: crate::limits::LimitZone::Safe,
        })
        .collect();
    TelemetrySample {
        seq,
        time_s: seq as f64 * dt_s,
        joints,
        drive: DriveKind::TorqueNm,
        tcp: TcpPose::from_xyz_rpy([0.2, 0.0, 0.3], [0.0; 3]),
        worst_zone: None,
        program_step: None,
        link: None,
    }
}

/// A recording of `n` samples at 1 kHz in memory.
pub(crate) fn recording_bytes(n: u64) -> Vec<u8> {
    recording_bytes_at(n, 1e-3)
}

/// A recording of `n` samples `dt_s` apart in memory.
pub(crate) fn recording_bytes_at(n: u64, dt_s: f64) -> Vec<u8> {
    let model = RobotModel::parol6();
    let info = RecordingInfo {
        app_version: "test".into(),
        tool: "none".into(),
        program: "demo".into(),
        urdf_text: PAROL6_URDF.into(),
        tracking: String::new(),
    };
    let mut sink = McapSink::new(Cursor::new(Vec::new()), &model, &info).expect("sink");
    for k in 1..=n {
        sink.write_sample(&sample(k, dt_s)).expect("sample");
    }
    sink.write_event(&TelemetryEvent { time_s: 0.5, kind: EventKind::Note, message: "hello".into() }).expect("event");
    let (summary, cursor) = sink.finish_into_inner().expect("finish");
    assert_eq!(summary.samples, n);
    cursor.into_inner()
}

#[test]
fn a_whole_recording_reads_back() {
    let bytes = recording_bytes(2500);
    let rec = read_recording(&bytes).expect("read");
    assert!(!rec.truncated && rec.warnings.is_empty(), "{:?}", rec.warnings);
    assert_eq!(rec.measured.len(), 2500);
    assert_eq!(rec.commanded.len(), 2500);
    assert_eq!(rec.events.len(), 1);
    assert_eq!(rec.joint_names, ["J1", "J2", "J3", "J4", "J5", "J6"]);
    assert_eq!(rec.metadata.get("program").map(String::as_str), Some("demo"));
    assert_eq!(rec.urdf_text, PAROL6_URDF);
    assert_eq!(rec.topics.get("/tcp_pose").map(|t| t.schema.as_str()), Some("foxglove.PoseInFrame"));
    assert_eq!(rec.tcp_path.len() as u64, rec.topics.get("/tcp_pose").map_or(0, |t| t.messages));
    assert!((rec.tcp_path[0].pose.position.x - 0.2).abs() < 1e-12, "{:?}", rec.tcp_path[0]);
    rec.check_robot(&RobotModel::parol6()).expect("same robot");
}

#[test]
fn a_truncated_recording_gives_its_complete_chunks_and_a_warning() {
    let bytes = recording_bytes(2500);
    // cut in the middle of the data: chunks are closed every simulated second
    let cut = &bytes[..bytes.len() * 2 / 3];
    let rec = read_recording(cut).expect("readable in part");
    assert!(rec.truncated);
    assert!(rec.warnings.iter().any(|w| w.contains("cut short")), "{:?}", rec.warnings);
    let n = rec.measured.len();
    assert!(n > 0 && n < 2500, "{n} samples");
    assert!(rec.measured.iter().zip(1..).all(|(m, k)| m.seq == k));
    // cut anywhere: never a panic, and never fewer samples for a longer file
    let mut last = 0;
    for len in (0..bytes.len()).step_by(997) {
        let n = read_recording(&bytes[..len]).map_or(0, |r| r.measured.len());
        assert!(n >= last, "cut at {len}: {n} samples, {last} before");
        last = n;
    }
}

#[test]
fn empty_garbage_and_foreign_files_are_named() {
    assert_eq!(read_recording(&[]), Err(RecordingError::Empty));
    assert_eq!(read_recording(b"hello world, not a recording"), Err(RecordingError::NotMcap));
    let mut damaged = mcap::MAGIC.to_vec();
    damaged.extend_from_slice(&[0xff; 64]);
    assert!(matches!(read_recording(&damaged), Err(RecordingError::Damaged { .. })), "{:?}", read_recording(&damaged));
    // a valid MCAP that is not ours
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).expect("writer");
    let ch = w.add_channel(0, "/camera", "raw", &BTreeMap::new()).expect("channel");
    let header = mcap::records::MessageHeader { channel_id: ch, sequence: 0, log_time: 1, publish_time: 1 };
    w.write_to_known_channel(&header, b"pixels").expect("message");
    w.finish().expect("finish");
    let foreign = w.into_inner().into_inner();
    match read_recording(&foreign) {
        Err(RecordingError::NotOurs(why)) => assert!(why.contains("/camera"), "{why}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn another_robot_is_refused_by_name() {
    let rec = read_recording(&recording_bytes(10)).expect("read");
    let other = RobotModel::from_urdf_str(
        r#"<robot name="two"><link name="a"/><link name="b"/><link name="c"/>
        <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
        <joint name="j2" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#,
        &crate::model::LoadOptions::default(),
    )
    .expect("model");
    let e = rec.check_robot(&other).expect_err("other robot");
    assert!(e.to_string().contains("\"parol6\" (6 joints), not of \"two\" (2 joints)"), "{e}");
}

/// Found by the fuzzer: an uncompressed chunk whose inner record overruns the chunk made the
/// mcap crate's reader subtract with overflow. Such chunks are refused by name now, and since
/// issue 29 skipped: the other chunks are read.
#[test]
fn a_chunk_we_never_write_is_skipped_with_a_warning() {
    let mut bytes = recording_bytes(1500);
    // rename the first chunk's compression "zstd" to "none" (same length: sizes still add up)
    let at = bytes.windows(4).position(|w| w == b"zstd").expect("a zstd chunk");
    bytes[at..at + 4].copy_from_slice(b"none");
    match read_recording(&bytes) {
        Ok(rec) => {
            assert!(rec.warnings.iter().any(|w| w.contains("compressed with \"none\"")), "{:?}", rec.warnings);
            // the first chunk holds the schemas and channels only; the summary repeats them
            assert_eq!(rec.measured.len(), 1500);
        }
        Err(e) => assert!(matches!(e, RecordingError::NotOurs(_) | RecordingError::Damaged { .. }), "{e}"),
    }
}

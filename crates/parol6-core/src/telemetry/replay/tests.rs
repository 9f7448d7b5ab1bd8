//! Replay tests: thinning, the parallel and the linear path agree, bad and cut files.
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
    // the damaged chunk is skipped, the others are read (issue 29 item 6)
    assert!(!data.truncated && data.warnings.iter().any(|w| w.contains("damaged")), "{:?}", data.warnings);
    assert!(data.store.len() >= 550 && data.store.len() < 625, "{}", data.store.len());
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

/// Issue 32 major 7: a robot recording replays its link health too (the connection read-out
/// follows the cursor), on both reading paths.
#[test]
fn a_robot_recording_replays_its_link_health_at_the_cursor() {
    use crate::model::PAROL6_URDF;
    use crate::telemetry::reader::tests::sample;
    use crate::telemetry::sample::LinkHealth;
    use crate::telemetry::writer::{McapSink, RecordingInfo};
    let model = RobotModel::parol6();
    let info = RecordingInfo {
        app_version: "test".into(),
        tool: "none".into(),
        program: String::new(),
        urdf_text: PAROL6_URDF.into(),
        tracking: String::new(),
    };
    let mut sink = McapSink::new(std::io::Cursor::new(Vec::new()), &model, &info).expect("sink");
    for k in 1..=3000u64 {
        let mut s = sample(k, 1e-3);
        // connected, then the link is lost at 2 s with the E-stop pressed
        let lost = k >= 2000;
        s.link = Some(LinkHealth {
            state: if lost { "Lost".into() } else { "Connected".into() },
            loop_rate_hz: 100.0,
            missing_replies: k / 100,
            link_losses: u64::from(lost),
            estop_pressed: lost,
        });
        sink.write_sample(&s).expect("sample");
    }
    let (_, cursor) = sink.finish_into_inner().expect("finish");
    let bytes = cursor.into_inner();
    let parallel = load_replay(&bytes, &model).expect("replay");
    assert!(matches!(parallel.read_path, ReadPath::Parallel { .. }), "{:?}", parallel.read_path);
    let linear = load_linear(&bytes, &model).expect("linear");
    assert_eq!(parallel.link, linear.link, "both paths");
    // at the first sample, once a second, and at the change: 0.001, 1.001, 2.0, 3.0 s
    assert_eq!(parallel.link.len(), 4, "{:?}", parallel.link);
    assert!(parallel.link_at(0.0).is_none(), "nothing recorded before the first sample");
    let at = |t: f64| parallel.link_at(t).expect("recorded").clone();
    assert_eq!((at(0.5).state.as_str(), at(0.5).estop_pressed), ("Connected", false));
    assert_eq!((at(1.5).state.as_str(), at(1.5).missing_replies), ("Connected", 10));
    assert_eq!((at(2.5).state.as_str(), at(2.5).link_losses, at(2.5).estop_pressed), ("Lost", 1, true));
    // a simulation recording has none
    assert!(load_replay(&recording_bytes(500), &model).expect("replay").link.is_empty());
}

//! Recorder tests: samples pushed faster than real time go into the live view and the file
//! without a gap; gaps and states become counters and events.

use std::time::Duration;

use super::*;
use crate::model::PAROL6_URDF;
use crate::motion::{JointDrive, Setpoint, StateSource, home_position};
use crate::telemetry::event::EventKind;
use crate::telemetry::read_recording;

pub(crate) fn temp_path(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("parol6-telemetry-{}-{name}", std::process::id()))
}

fn motion(seq: u64, dt_s: f64, q: &[f64]) -> MotionSample {
    MotionSample {
        seq,
        time_s: seq as f64 * dt_s,
        commanded: Setpoint::at_rest(q),
        measured_q: q.to_vec(),
        measured_qd: vec![0.0; q.len()],
        drive: JointDrive::TorqueNm(vec![0.5; q.len()]),
    }
}

fn info() -> RecordingInfo {
    RecordingInfo {
        app_version: "test".into(),
        tool: "none".into(),
        program: String::new(),
        urdf_text: PAROL6_URDF.into(),
        tracking: String::new(),
    }
}

fn wait_for(rec: &Recorder, samples: u64) {
    for _ in 0..500 {
        if rec.stats().samples >= samples {
            return;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn samples_reach_the_file_and_the_live_view_without_gaps() {
    let model = RobotModel::parol6();
    let home = home_position(&model);
    let rec = Recorder::start(model, RecorderConfig::default()).expect("start");
    let path = temp_path("basic.mcap");
    rec.start_recording(&path, &info()).expect("recording");
    let tap = rec.tap();
    rec.set_program_step(Some(2));
    std::thread::sleep(Duration::from_millis(20));
    // 3 s of a 1 kHz simulation, pushed as fast as the channel takes them
    let n = 3000u64;
    let mut sent = 0;
    for k in 1..=n {
        while tap.try_send(motion(k, 1e-3, &home)).is_err() {
            std::thread::sleep(Duration::from_micros(100));
        }
        sent += 1;
    }
    wait_for(&rec, n);
    // the live view is published every 50 ms
    let mut live = rec.live();
    for _ in 0..500 {
        if live.latest().is_some_and(|s| s.seq + 4 > n) {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
        live = rec.live();
    }
    assert!(live.latest().is_some_and(|s| s.seq + 4 > n), "{:?}", live.latest().map(|s| s.seq));
    assert_eq!(rec.stats().missing_samples, 0);
    // the newest minute of a 1 kHz source is kept whole
    assert_eq!(live.len() as u64, n, "live view holds {}", live.len());
    let summary = rec.finish().expect("finish").expect("was recording");
    assert_eq!(summary.samples, sent);
    let bytes = std::fs::read(&path).expect("read back");
    let _ = std::fs::remove_file(&path);
    let file = read_recording(&bytes).expect("readable");
    assert!(!file.truncated, "{:?}", file.warnings);
    assert_eq!(file.measured.len() as u64, n);
    assert_eq!(file.commanded.len() as u64, n);
    assert!(file.measured.iter().zip(1..).all(|(m, k)| m.seq == k), "sequence numbers are contiguous");
    assert!(file.measured.iter().all(|m| m.program_step == Some(2) || m.seq < 20));
    assert!(
        file.events.iter().any(|e| e.message == "program step 3" && e.level == 2),
        "the step change is an event: {:?}",
        file.events
    );
    assert_eq!(file.topics.get("/tf").map(|t| t.messages), Some(300), "tf at 100 Hz");
    assert!((file.duration_s() - 2.999).abs() < 1e-6, "{}", file.duration_s());
    assert_eq!(file.robot(), "parol6");
}

#[test]
fn gaps_are_counted_and_states_become_events() {
    let model = RobotModel::parol6();
    let home = home_position(&model);
    let rec = Recorder::start(model.clone(), RecorderConfig::default()).expect("start");
    let tap = rec.tap();
    for k in [1u64, 2, 3, 3, 7, 8] {
        tap.try_send(motion(k, 0.01, &home)).expect("room");
    }
    wait_for(&rec, 5);
    let mut st = RobotState::at_rest(&model, StateSource::Robot, "robot", &home);
    rec.observe_state(Arc::new(st.clone()));
    st.last_refusal = Some((4, "J1 beyond its limit".into()));
    rec.observe_state(Arc::new(st));
    rec.set_link_health(LinkHealth { state: "Connected".into(), ..LinkHealth::default() });
    rec.set_link_health(LinkHealth { state: "Connected".into(), estop_pressed: true, ..LinkHealth::default() });
    for _ in 0..500 {
        if rec.live().events.iter().any(|e| matches!(e.kind, EventKind::EStop { .. })) {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let stats = rec.stats();
    assert_eq!(stats.samples, 5, "the repeated tick 3 is not a new sample");
    assert_eq!(stats.missing_samples, 3, "ticks 4–6 are missing");
    let kinds: Vec<EventKind> = rec
        .live()
        .events
        .iter()
        .map(|e| e.kind.clone())
        .filter(|k| !matches!(k, EventKind::LimitWarning { .. }))
        .collect();
    assert_eq!(kinds, vec![EventKind::Refusal, EventKind::EStop { pressed: true }]);
    assert_eq!(rec.finish().expect("finish"), None, "nothing was being recorded");
}

#[test]
fn an_unwritable_path_is_an_error_at_once() {
    let rec = Recorder::start(RobotModel::parol6(), RecorderConfig::default()).expect("start");
    let bad = std::path::Path::new("/nonexistent-dir-parol6/x.mcap");
    let e = rec.start_recording(bad, &info()).expect_err("no such folder");
    assert!(e.to_string().contains("/nonexistent-dir-parol6/x.mcap"), "{e}");
    assert_eq!(rec.stop_recording().expect("stop"), None);
}

/// Issue 30: a live outlet gets every sample (not only the live view's 250 Hz) and every event,
/// in order; a full outlet drops and counts without holding the recorder up; a dropped outlet
/// is closed.
#[test]
fn a_live_outlet_gets_every_sample_and_event_and_never_holds_the_recorder() {
    let model = RobotModel::parol6();
    let home = home_position(&model);
    let rec = Recorder::start(model, RecorderConfig::default()).expect("start");
    let outlet = rec.live_outlet(10_000).expect("outlet");
    let small = rec.live_outlet(5).expect("small outlet");
    let tap = rec.tap();
    // the outlets are taken with the control messages, before these samples
    std::thread::sleep(Duration::from_millis(50));
    let n = 1000u64;
    for k in 1..=n {
        while tap.try_send(motion(k, 1e-3, &home)).is_err() {
            std::thread::sleep(Duration::from_micros(100));
        }
    }
    wait_for(&rec, n);
    // control messages are taken before the samples waiting in the tap: sent once they are in
    rec.events().note("hello from the network");
    let mut seqs = Vec::new();
    let mut notes = Vec::new();
    let t0 = std::time::Instant::now();
    while notes.is_empty() && t0.elapsed() < Duration::from_secs(5) {
        match outlet.rx.recv_timeout(Duration::from_millis(100)) {
            Ok(LiveItem::Sample(s)) => seqs.push(s.seq),
            Ok(LiveItem::Event(e)) if e.kind == EventKind::Note => notes.push(e.message),
            Ok(LiveItem::Event(_)) | Err(_) => {}
        }
    }
    assert_eq!(seqs, (1..=n).collect::<Vec<_>>(), "every sample, in order");
    assert_eq!(notes, vec!["hello from the network".to_string()]);
    assert_eq!(outlet.dropped(), 0);
    // the small outlet, never read, kept 5 and counted the rest
    assert_eq!(small.rx.len(), 5);
    assert!(small.dropped() >= n - 5, "{}", small.dropped());
    assert_eq!(rec.stats().missing_samples, 0, "the recorder was never held up");
    drop(small);
    drop(outlet);
    tap.try_send(motion(n + 1, 1e-3, &home)).expect("room");
    wait_for(&rec, n + 1);
    assert_eq!(rec.finish().expect("finish"), None);
}

/// The live view of a 1 kHz source keeps a peak of one sample: it shows in the plots' min/max
/// once the sample is older than the first minute (the view used to keep one sample per 4 ms
/// and drop the others).
#[test]
fn a_one_sample_spike_older_than_a_minute_still_shows_in_the_plotted_min_max() {
    let model = RobotModel::parol6();
    let home = home_position(&model);
    let rec = Recorder::start(model, RecorderConfig::default()).expect("start");
    let tap = rec.tap();
    let n = 70_000u64;
    let spike_seq = 10_003;
    for k in 1..=n {
        let mut m = motion(k, 1e-3, &home);
        if k == spike_seq {
            m.measured_q[0] += 0.5;
        }
        while tap.try_send(m.clone()).is_err() {
            std::thread::sleep(Duration::from_micros(100));
        }
    }
    wait_for(&rec, n);
    let mut live = rec.live();
    for _ in 0..500 {
        if live.latest().is_some_and(|s| s.seq == n) {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
        live = rec.live();
    }
    let mut store = crate::telemetry::SeriesStore::new(6, 600.0);
    store.ingest_live(&live);
    let mut points = Vec::new();
    store.decimated(0, 0.0, 70.0, 800, &mut points);
    let top = points.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
    let expect = f64::from((home[0] + 0.5) as f32);
    assert_eq!(top, expect, "the spike at {} s is plotted", spike_seq as f64 * 1e-3);
    let stats = store.window_stats(0, 9.0, 11.0).expect("samples there");
    assert_eq!(stats.max, expect);
}

/// The live view of a backend the window does not show keeps nothing (its rows would never be
/// drawn: the plots take a backend's rows from the moment it is shown), while a file still gets
/// every sample; turned on again, it keeps rows from then on.
#[test]
fn an_inactive_backends_live_view_keeps_no_rows_but_its_file_gets_every_sample() {
    let model = RobotModel::parol6();
    let home = home_position(&model);
    let rec = Recorder::start(model, RecorderConfig::default()).expect("start");
    let tap = rec.tap();
    let send = |range: std::ops::RangeInclusive<u64>| {
        for k in range {
            while tap.try_send(motion(k, 1e-2, &home)).is_err() {
                std::thread::sleep(Duration::from_micros(100));
            }
        }
    };
    // the view holds `rows` once the recorder has published it
    let view_with = |rows: usize| {
        let mut live = rec.live();
        for _ in 0..300 {
            if live.len() == rows {
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
            live = rec.live();
        }
        live
    };
    send(1..=100);
    wait_for(&rec, 100);
    assert_eq!(view_with(100).len(), 100, "kept while shown");
    rec.keep_live_rows(false);
    let path = temp_path("inactive.mcap");
    rec.start_recording(&path, &info()).expect("recording");
    send(101..=300);
    wait_for(&rec, 300);
    std::thread::sleep(Duration::from_millis(100));
    let live = view_with(0);
    assert_eq!(live.len(), 0, "an inactive backend keeps no rows");
    rec.keep_live_rows(true);
    send(301..=350);
    wait_for(&rec, 350);
    let live = view_with(50);
    assert_eq!(live.len(), 50, "rows again once shown");
    assert_eq!(live.blocks.first().and_then(|b| b.times_s.first()).copied(), Some(301.0 * 1e-2));
    let summary = rec.finish().expect("finish").expect("was recording");
    let _ = std::fs::remove_file(&path);
    assert_eq!(summary.samples, 250, "the file got every sample from its start");
}

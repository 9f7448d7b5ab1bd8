//! Replay on the full app, headless through egui's kittest harness (issue 32, major 7): while a
//! recording is open every read-out shows the recording at the cursor, not the live simulation
//! (the Joints panel's measured positions, the TCP panel's position), the status bar says
//! REPLAY, and the motion controls send nothing, saying why, until the recording is closed.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ui_support::{app_harness, has_label, until};

use parol6_app::app::Parol6App;
use parol6_app::panels::AngleUnit;
use parol6_app::panels::entry::fmt_fixed;
use parol6_core::RobotModel;
use parol6_core::motion::RobotBackend;

/// True when a label reads exactly `text`.
fn shows(h: &Harness<'_, Parol6App>, text: &str) -> bool {
    h.query_all_by_label(text).next().is_some()
}

/// The Joints panel's measured-position text of each joint at `q` (degrees, as shown).
fn joint_texts(q: &[f64]) -> Vec<String> {
    q.iter().map(|&v| AngleUnit::Deg.fmt(v)).collect()
}

/// The TCP panel's X, Y, Z texts at `q`.
fn tcp_texts(model: &RobotModel, q: &[f64]) -> Vec<String> {
    let tcp = model.fk(q);
    (0..3).map(|k| format!("{:>9} mm", fmt_fixed(tcp.position_m[k] * 1000.0, 2))).collect()
}

#[test]
fn replay_shows_the_recording_in_every_readout_and_refuses_motion() {
    let model = RobotModel::parol6();
    let dir = std::env::temp_dir().join(format!("parol6-replay-ui-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("run.mcap");
    let bytes = parol6_app::cli::bench_replay::synthetic_recording(&model, 0.5, 50.0).expect("recording");
    std::fs::write(&path, bytes).expect("write");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.run_steps(2);
    let live_q = h.state().sim().state().q.clone();
    assert!(shows(&h, "SIM"), "the status bar says SIM before replay");

    // open the recording from the File menu
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: run.mcap"));
    h.key_press(egui::Key::Escape);
    h.run_steps(2);

    // move the cursor: an event 20 s in
    h.get_by_label_contains("20.0 s").click();
    h.run_steps(3);
    let cursor_s = h.state().replay().map(|r| r.cursor_s).expect("open");
    let (rec_q, _) = h.state().replay().and_then(|r| r.joints_at_cursor()).expect("a sample at the cursor");
    assert!(cursor_s > 10.0, "the cursor moved: {cursor_s}");
    assert!(
        rec_q.iter().zip(&live_q).any(|(r, l)| (r - l).abs() > 1f64.to_radians()),
        "the recording at the cursor differs from the live arm: {rec_q:?} vs {live_q:?}"
    );

    // every read-out shows the recording, none the live simulation
    for (j, (rec, live)) in joint_texts(&rec_q).iter().zip(joint_texts(&live_q)).enumerate() {
        assert!(shows(&h, rec), "J{}: the recording's {rec} is shown", j + 1);
        if *rec != live {
            assert!(!shows(&h, &live), "J{}: the live {live} is not shown", j + 1);
        }
    }
    for (rec, live) in tcp_texts(&model, &rec_q).iter().zip(tcp_texts(&model, &live_q)) {
        assert!(shows(&h, rec), "TCP: the recording's {rec:?} is shown");
        if *rec != live {
            assert!(!shows(&h, &live), "TCP: the live {live:?} is not shown");
        }
    }
    assert!(shows(&h, "REPLAY"), "the status bar says REPLAY");
    assert!(!shows(&h, "SIM"), "… not SIM");

    // the motion controls send nothing and say why
    let reason = "REPLAY: the read-outs show the recording; motion refused until the recording is closed";
    assert!(has_label(&h, reason), "the joints panel shows why motion is refused");
    h.get_by_label("HOME").click();
    h.run_steps(2);
    h.key_press(egui::Key::H);
    h.run_steps(2);
    assert_eq!(h.state().moves_sent().count(), 0, "nothing moved: {:?}", h.state().moves_sent().collect::<Vec<_>>());
    let refused = format!("refused: {reason}");
    assert!(h.state().notices().iter().any(|n| n.error && n.text == refused), "the refusal names replay");

    // closed: the live arm again, and motion is accepted
    h.get_by_label("Close recording").click();
    until(&mut h, "replay closed", 5.0, |h| h.state().replay().is_none());
    h.run_steps(2);
    assert!(shows(&h, "SIM"), "the status bar says SIM again");
    for text in joint_texts(&live_q) {
        assert!(shows(&h, &text), "the live {text} is shown again");
    }
    h.get_by_label("HOME").click();
    h.run_steps(2);
    assert_eq!(h.state().moves_sent().count(), 1, "HOME is sent once replay is closed");
    let _ = std::fs::remove_dir_all(&dir);
}

//! Replay on the full app, headless through egui's kittest harness (issue 32, major 7): while a
//! recording is open every read-out shows the recording at the cursor, not the live simulation
//! (the Joints panel's measured positions, the TCP panel's position), the status bar says
//! REPLAY, and the motion controls send nothing, saying why, until the recording is closed.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
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

/// Writes a synthetic 50 s recording to a fresh temporary folder named after `tag`.
fn write_recording(model: &RobotModel, tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("run.mcap");
    let bytes = parol6_app::cli::bench_replay::synthetic_recording(model, 0.5, 50.0).expect("recording");
    std::fs::write(&path, bytes).expect("write");
    path
}

/// Opens the recording from the File menu, closes the menu and moves the cursor to the event
/// 20 s in.
fn open_at_20_s(h: &mut Harness<'_, Parol6App>, path: &std::path::Path) {
    ui_support::open_recording(h, path);
    until(h, "the replay", 10.0, |h| has_label(h, "Replay: run.mcap"));
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    h.get_by_label_contains("20.0 s").click();
    h.run_steps(3);
}

#[test]
fn replay_shows_the_recording_in_every_readout_and_refuses_motion() {
    let model = RobotModel::parol6();
    let path = write_recording(&model, "parol6-replay-ui");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.run_steps(2);
    let live_q = h.state().sim().state().q.clone();
    assert!(shows(&h, "SIM"), "the status bar says SIM before replay");

    open_at_20_s(&mut h, &path);
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
    // H acts with the pointer over the 3D view
    let view = h.get_by_label_contains("3D view unavailable").rect().center();
    h.hover_at(view);
    h.run_steps(1);
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
    std::fs::remove_dir_all(path.parent().expect("the recording's folder")).expect("remove the temporary folder");
}

/// A robot recording of `n` samples 10 ms apart at standby from motion time `start_s` whose link
/// is lost at sample `lost_at` with the E-stop pressed.
fn robot_recording(model: &RobotModel, n: u64, lost_at: u64, start_s: f64) -> Vec<u8> {
    use parol6_core::telemetry::writer::{McapSink, RecordingInfo};
    use parol6_core::telemetry::{DriveKind, JointTelemetry, LinkHealth, TelemetrySample};
    let info = RecordingInfo {
        app_version: "test".into(),
        tool: "none".into(),
        program: String::new(),
        urdf_text: parol6_core::model::PAROL6_URDF.into(),
        tracking: String::new(),
    };
    let q = parol6_core::parol6::standby_rad();
    let mut sink = McapSink::new(std::io::Cursor::new(Vec::new()), model, &info).expect("sink");
    for k in 1..=n {
        let joints = q
            .iter()
            .map(|&v| JointTelemetry {
                cmd_q_rad: v,
                cmd_qd_rad_s: 0.0,
                cmd_qdd_rad_s2: 0.0,
                q_rad: v,
                qd_rad_s: 0.0,
                qdd_rad_s2: 0.0,
                drive: 0.0,
                zone: parol6_core::limits::LimitZone::Safe,
            })
            .collect();
        let lost = k >= lost_at;
        let sample = TelemetrySample {
            seq: k,
            time_s: start_s + k as f64 * 0.01,
            joints,
            drive: DriveKind::StepsPerS,
            tcp: model.fk(&q),
            worst_zone: None,
            program_step: None,
            link: Some(LinkHealth {
                state: if lost { "Lost".into() } else { "Connected".into() },
                loop_rate_hz: 99.0,
                missing_replies: 3,
                link_losses: u64::from(lost),
                estop_pressed: lost,
            }),
        };
        sink.write_sample(&sample).expect("sample");
    }
    let event = parol6_core::telemetry::TelemetryEvent {
        time_s: 4.0,
        kind: parol6_core::telemetry::EventKind::Note,
        message: "after the loss".into(),
    };
    sink.write_event(&event).expect("event");
    let (_, cursor) = sink.finish_into_inner().expect("finish");
    cursor.into_inner()
}

/// Issue 32 major 7: the link health of a robot recording is shown at the replay cursor.
#[test]
fn replay_of_a_robot_recording_shows_its_link_health_at_the_cursor() {
    let model = RobotModel::parol6();
    let dir = std::env::temp_dir().join(format!("parol6-replay-link-ui-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("robot.mcap");
    std::fs::write(&path, robot_recording(&model, 500, 300, 0.0)).expect("write");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.run_steps(2);
    assert!(!shows(&h, "REPLAY link"), "no recorded link while live");
    let heading = |h: &Harness<'_, Parol6App>| h.get_by_label("Robot connection").rect();
    let live_heading = heading(&h);
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: robot.mcap"));
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    // the cursor at the start: connected
    until(&mut h, "the recorded link", 5.0, |h| {
        h.query_all_by_label_contains("Connected  loop 99 Hz  missing 3  losses 0").next().is_some()
    });
    // trial9 m9: the recorded link's row pushed the section's heading down 38 px
    assert_eq!(heading(&h), live_heading, "opening the replay moved the Robot connection heading");
    // the cursor after the loss: lost, with the E-stop
    h.get_by_label_contains("after the loss").click();
    until(&mut h, "the recorded loss", 5.0, |h| {
        h.query_all_by_label_contains("Lost  loop 99 Hz  missing 3  losses 1").next().is_some()
    });
    h.get_by_label("Close recording").click();
    until(&mut h, "replay closed", 5.0, |h| h.state().replay().is_none());
    h.run_steps(2);
    assert!(!shows(&h, "REPLAY link"), "no recorded link once closed");
    std::fs::remove_dir_all(path.parent().expect("the recording's folder")).expect("remove the temporary folder");
}

/// The torques the Dynamics panel must show at the replay cursor: inverse dynamics of the
/// recorded measured joints, velocities and accelerations there (a missing value read as 0).
fn recorded_torques_at_cursor(h: &Harness<'_, Parol6App>, model: &RobotModel) -> Vec<f64> {
    use parol6_core::telemetry::{Quantity, SeriesStore};
    let r = h.state().replay().expect("open");
    let (_, row) = r.data.store.row_at(r.cursor_s).expect("a sample at the cursor");
    let n = model.dof();
    let col = |q: Quantity| -> Vec<f64> {
        let at = SeriesStore::offset_of(q, n);
        (0..n)
            .map(|j| row.get(at + j).map_or(0.0, |&v| f64::from(v)))
            .map(|v| if v.is_finite() { v } else { 0.0 })
            .collect()
    };
    let (q, qd, qdd) = (col(Quantity::Position), col(Quantity::Velocity), col(Quantity::Acceleration));
    let mut id = parol6_core::dynamics::InverseDynamics::new(model);
    let mut tau = vec![0.0; n];
    id.compute_into(model, &q, &qd, &qdd, &mut tau);
    tau
}

/// Issue 32, major 7 (last part): during replay the Dynamics panel analysed the program panel's
/// program from the replayed pose, as if live. It now analyses the recording: the joint torques
/// along the recorded motion (the same inverse dynamics), on a worker, with the torques at the
/// cursor, and says REPLAY.
#[test]
fn the_dynamics_panel_analyses_the_recording_during_replay() {
    let model = RobotModel::parol6();
    let path = write_recording(&model, "parol6-replay-dyn");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.state_mut().settings_mut().show_dynamics = true;
    h.run_steps(2);
    open_at_20_s(&mut h, &path);

    let heading = "REPLAY: joint torques along the recording run.mcap";
    until(&mut h, "the recording's analysis", 60.0, |h| {
        has_label(h, heading) && !h.state().dynamics_panel().computing()
    });
    h.run_steps(2);
    assert!(!has_label(&h, "from the current pose, before it runs"), "not the program's analysis");
    let names = model.joint_names();
    let tau = recorded_torques_at_cursor(&h, &model);
    for (j, t) in tau.iter().enumerate() {
        let text = format!("{} {t:.2} N·m", names[j]);
        assert!(shows(&h, &text), "the torque of {} at the cursor: {text}", names[j]);
    }

    // the cursor moves: the torques shown follow it
    h.get_by_label_contains("10.0 s").click();
    h.run_steps(3);
    let tau = recorded_torques_at_cursor(&h, &model);
    let text = format!("{} {:.2} N·m", names[1], tau[1]);
    assert!(shows(&h, &text), "J2 at the new cursor: {text}");
    std::fs::remove_dir_all(path.parent().expect("the recording's folder")).expect("remove the temporary folder");
}

/// Issue 32's frame-time acceptance (closing a ten-minute recording took a 50 ms frame): closing
/// a recording lets go of every handle on it, the Dynamics panel's analysis included (which
/// kept it, tens of MB, until the panel was shown again and then freed it in a frame), and
/// frees it off the UI thread (`app::replay::free_off_ui_thread`).
#[test]
fn closing_a_recording_frees_it_even_after_the_dynamics_panel_analysed_it() {
    let model = RobotModel::parol6();
    let path = write_recording(&model, "parol6-replay-free");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.state_mut().settings_mut().show_dynamics = true;
    h.run_steps(2);
    open_at_20_s(&mut h, &path);
    until(&mut h, "the recording's analysis", 60.0, |h| {
        has_label(h, "REPLAY: joint torques along the recording run.mcap") && !h.state().dynamics_panel().computing()
    });
    h.state_mut().settings_mut().show_dynamics = false;
    h.run_steps(2);
    let data = std::sync::Arc::downgrade(&h.state().replay().expect("open").data);

    h.state_mut().queue_command(parol6_app::panels::AppCommand::CloseRecording);
    h.run_steps(2);
    assert!(h.state().replay().is_none(), "closed");
    let t0 = std::time::Instant::now();
    while data.upgrade().is_some() && t0.elapsed() < std::time::Duration::from_secs(10) {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(data.upgrade().is_none(), "the closed recording is still held");
    std::fs::remove_dir_all(path.parent().expect("the recording's folder")).expect("remove the temporary folder");
}

/// The measurement panel pre-flighted its cube from the replayed pose at every new cursor
/// position, in the frame (a few ms each, and again when the recording closed). The test runs
/// from the live arm, so during replay the live arm's pre-flight is kept.
#[test]
fn the_measurement_pre_flight_stays_the_live_arms_during_replay() {
    let model = RobotModel::parol6();
    let path = write_recording(&model, "parol6-replay-measure");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.run_steps(2);
    for _ in 0..100 {
        if h.state_mut().measure_panel().preflight_from().is_some() {
            break;
        }
        h.run_steps(1);
    }
    let live_q = h.state().backend().state().commanded.q.clone();
    open_at_20_s(&mut h, &path);
    let (_, rec_cmd) = h.state().replay().and_then(|r| r.joints_at_cursor()).expect("a sample at the cursor");
    assert!(rec_cmd.iter().zip(&live_q).any(|(r, l)| (r - l).abs() > 1f64.to_radians()), "{rec_cmd:?} vs {live_q:?}");
    h.run_steps(5);
    let from = h.state_mut().measure_panel().preflight_from().map(<[f64]>::to_vec);
    assert_eq!(from.as_deref(), Some(live_q.as_slice()), "pre-flighted from the live arm, not the recording");
    std::fs::remove_dir_all(path.parent().expect("the recording's folder")).expect("remove the temporary folder");
}

/// The program panel pre-flighted the program again from the replayed pose at every new cursor
/// position (and once more when the recording closed): a 1 000-step program's check took the CPU
/// from the frames of a playing replay. A run starts from the live arm, so the live arm's check
/// is kept while a recording is open.
#[test]
fn the_programs_pre_flight_stays_the_live_arms_during_replay() {
    let model = RobotModel::parol6();
    let path = write_recording(&model, "parol6-replay-program");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.run_steps(2);
    assert!(h.state_mut().program_panel_mut().wait_for_check(std::time::Duration::from_secs(30)), "first check");
    h.run_steps(2);
    let live_q = h.state().backend().state().commanded.q.clone();
    let before = h.state().program_panel().checked().map(std::sync::Arc::clone).expect("a checked program");
    assert!(before.is_from(&live_q), "checked from the live arm before replay");
    open_at_20_s(&mut h, &path);
    let (_, rec_cmd) = h.state().replay().and_then(|r| r.joints_at_cursor()).expect("a sample at the cursor");
    assert!(rec_cmd.iter().zip(&live_q).any(|(r, l)| (r - l).abs() > 1f64.to_radians()), "{rec_cmd:?} vs {live_q:?}");
    for _ in 0..10 {
        h.run_steps(1);
        assert!(!h.state().program_panel().checking(), "no pre-flight starts while the cursor moves");
    }
    let during = h.state().program_panel().checked().map(std::sync::Arc::clone).expect("a checked program");
    assert!(std::sync::Arc::ptr_eq(&before, &during), "the live arm's check is kept during replay");
    std::fs::remove_dir_all(path.parent().expect("the recording's folder")).expect("remove the temporary folder");
}

/// Issue 32's minor: "Replay reports "6209 samples" in one place and "17497" in another" (seen
/// again by the last trial: the opening notice counted the samples replay keeps, the timeline
/// the samples in the file). Both now give the file's count; the notice names what it keeps.
#[test]
fn the_replays_notice_and_header_give_the_same_sample_count() {
    let model = RobotModel::parol6();
    let path = write_recording(&model, "parol6-replay-count");
    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.run_steps(2);
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: run.mcap"));
    let data = std::sync::Arc::clone(&h.state().replay().expect("open").data);
    let in_file = format!("{} samples in the file", data.samples_in_file);
    let notice = h.state().notices().iter().map(|n| n.text.clone()).find(|t| t.starts_with("replaying"));
    let notice = notice.expect("the opening notice");
    assert!(notice.contains(&in_file), "the notice gives the file's count: {notice}");
    if (data.store.len() as u64) < data.samples_in_file {
        assert!(
            notice.contains(&format!(", {} replayed at", data.store.len())),
            "what replay keeps is named: {notice}"
        );
    }
    assert!(
        h.query_all_by_label_contains(&in_file).next().is_some(),
        "the timeline's header gives the same count as the notice: {in_file}"
    );
    std::fs::remove_dir_all(path.parent().expect("the recording's folder")).expect("remove the temporary folder");
}

/// The last trial: in replay the Dynamics panel said "at the cursor (t = 30.61 s)" while the
/// timeline said 3.55 s: the panel gave the recording's motion time, the timeline the time from
/// its start. Both now count from the recording's start.
#[test]
fn the_dynamics_panel_in_replay_counts_time_from_the_recordings_start_as_the_timeline() {
    let model = RobotModel::parol6();
    let dir = std::env::temp_dir().join(format!("parol6-replay-dyn-origin-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("late.mcap");
    // a recording made 30 s after the simulation started, 5 s long
    std::fs::write(&path, robot_recording(&model, 500, 1000, 30.0)).expect("write");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.state_mut().settings_mut().show_dynamics = true;
    h.run_steps(2);
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: late.mcap"));
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    until(&mut h, "the recording's analysis", 60.0, |h| {
        h.query_all_by_label_contains("at the cursor (t = ").next().is_some() && !h.state().dynamics_panel().computing()
    });
    let (t0, _) = h.state().replay().expect("open").span_s();
    let cursor = h.state().replay().expect("open").cursor_s;
    assert!(t0 > 29.0, "the recording starts late: {t0}");
    let from_start = format!("at the cursor (t = {:.2} s):", cursor - t0);
    assert!(shows(&h, &from_start), "the panel counts from the recording's start: {from_start}");
    assert!(shows(&h, &format!("{:.2} s", cursor - t0)), "as the timeline does");
    std::fs::remove_dir_all(&dir).expect("remove the temporary folder");
}

/// Trial 9: in replay the plots' time axis (and the pointer's read-out) gave the recording's
/// clock, 100–130 s, while the timeline counted from 0. They now count from the recording's
/// start too.
#[test]
fn the_plots_in_replay_count_time_from_the_recordings_start_as_the_timeline() {
    let model = RobotModel::parol6();
    let dir = std::env::temp_dir().join(format!("parol6-replay-plot-origin-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("late.mcap");
    std::fs::write(&path, robot_recording(&model, 500, 1000, 30.0)).expect("write");

    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    h.run_steps(2);
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: late.mcap"));
    h.key_press(egui::Key::Escape);
    until(&mut h, "the plots", 10.0, |h| has_label(h, "Export to"));
    let export = h.get_by_label("Export to").rect();
    // along the plot until the pointer is over the recording's samples (a read-out is given only
    // where a line has samples; the plot's window may reach past the recording's 5 s)
    let mut readout = None;
    for dx in (0..16).map(|k| 40.0 + 40.0 * k as f32) {
        h.hover_at(egui::pos2(export.left() + dx, export.bottom() + 80.0));
        h.run_steps(2);
        readout =
            h.query_all_by_label_contains("\nJ1: ").find_map(|n| n.value().or_else(|| n.accesskit_node().label()));
        if readout.is_some() {
            break;
        }
    }
    let text = readout.expect("a hover read-out over the recording's samples");
    let t: f64 = text
        .strip_prefix("t = ")
        .and_then(|r| r.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("a time in {text:?}"));
    // the recording runs from 30 s of motion time; the plot's window may reach past its end
    assert!((0.0..29.0).contains(&t), "the pointer's time counts from the recording's start: {text}");
    std::fs::remove_dir_all(&dir).expect("remove the temporary folder");
}

/// Trial 21 D1: a recording opened while Pick & place ran: the program went on driving the arm
/// to its end while every read-out showed the recorded arm at rest and the status bar said
/// REPLAY. A recording is not opened while a program runs (or the arm moves); it opens once
/// the program is stopped.
#[test]
fn a_recording_is_not_opened_while_a_program_moves_the_arm() {
    use parol6_core::program::runner::RunState;
    let model = RobotModel::parol6();
    let path = write_recording(&model, "parol6-replay-ui-running");
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    until(&mut h, "the program's check", 60.0, |h| !h.state().program_panel().checking());
    ui_support::pointer_on_view(&mut h);
    h.key_press(egui::Key::F5);
    let state = |h: &Harness<'_, Parol6App>| h.state().program_progress().map(|p| p.state.clone());
    until(&mut h, "the program moving the arm", 30.0, |h| state(h) == Some(RunState::Running));
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the refusal", 10.0, |h| {
        h.state().notices().iter().any(|n| n.error && n.text.contains("not opened: a program is running"))
    });
    ui_support::settle(&mut h, 0.5);
    assert!(h.state().replay().is_none() && !h.state().replay_loading(), "no replay while the program runs");
    assert_eq!(state(&h), Some(RunState::Running), "the program runs on, shown live");
    assert!(!shows(&h, "REPLAY"), "the status bar does not say REPLAY");
    // stopped, the arm at rest: the recording opens
    h.key_press(egui::Key::Escape);
    until(&mut h, "the arm at rest", 20.0, |h| !h.state().program_running() && !h.state().backend().state().moving);
    // (the menu's field still holds the path: the same request as its Enter)
    h.state_mut().queue_command(parol6_app::panels::AppCommand::OpenRecording(path.clone()));
    until(&mut h, "the replay", 10.0, |h| h.state().replay().is_some());
}

/// Trial 21 D2: a double-click on *Close recording* closed the recording with the first click,
/// the plots slid up under the pointer, and the second click chose their *torque*. The place
/// the timeline left stays while the pointer is in the lower panel.
#[test]
fn a_double_click_on_close_recording_lands_on_nothing_else() {
    use parol6_core::telemetry::Quantity;
    let model = RobotModel::parol6();
    let path = write_recording(&model, "parol6-replay-ui-close-twice");
    let mut h = app_harness(egui::vec2(1024.0, 700.0));
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: run.mcap"));
    h.key_press(egui::Key::Escape);
    h.run_steps(3);
    let toolbar_before = h.get_by_label("torque").rect();
    let at = h.get_by_label("Close recording").rect().center();
    for _ in 0..2 {
        ui_support::mouse_click(&mut h, at);
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    h.run_steps(3);
    assert!(h.state().replay().is_none(), "the recording closed");
    // its notices no longer stand: "opening …" went when it replayed, "replaying …" when it closed
    // (trial 21 m3)
    let stale: Vec<&str> = h
        .state()
        .notices()
        .iter()
        .map(|n| n.text.as_str())
        .filter(|t| t.starts_with("opening ") || t.starts_with("replaying "))
        .collect();
    assert_eq!(stale, [] as [&str; 0], "stale notices");
    assert_eq!(h.state().plots_panel().quantities, [Quantity::Position], "the second click chose another quantity");
    assert_eq!(h.get_by_label("torque").rect(), toolbar_before, "the plots' toolbar moved under the pointer");
    // the pointer gone to the 3D view, the plots take the place
    ui_support::pointer_on_view(&mut h);
    h.run_steps(3);
    assert!(h.get_by_label("torque").rect().top() < toolbar_before.top() - 20.0, "the plots moved up");
}

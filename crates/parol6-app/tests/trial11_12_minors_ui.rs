//! Minor defects of trials 11, 12 and 20 (issue 32), driven headless through egui's kittest
//! harness on the full app: the status bar's toggles stay in place, F5 refused by the
//! pre-flight says why, STOP and E-STOP say what they ended, one-shot gripper commands answer,
//! a refusal names its file once, a typed `~` is the home directory, and the status bar's clock is
//! the shown state's, and it names the robot drives' state.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use parol6_app::app::Parol6App;
use parol6_app::panels::AppCommand;
use parol6_core::motion::{IoCommand, MotionCommand};
use ui_support::{app_harness, has_label, settle, until};

/// True when a notice's text contains `part`.
fn noticed(h: &Harness<'_, Parol6App>, part: &str) -> bool {
    h.state().notices().iter().any(|n| n.text.contains(part))
}

/// Every notice's text, for a failure message.
fn notices(h: &Harness<'_, Parol6App>) -> Vec<String> {
    h.state().notices().iter().map(|n| n.text.clone()).collect()
}

/// A temporary folder of this test.
fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("parol6-t1112-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The status bar's two toggles: *Share live* (or its LIVE address) and *ROS 2*.
fn toggles(h: &Harness<'_, Parol6App>) -> (egui::Rect, egui::Rect) {
    let share = h.query_by_label("Share live").or_else(|| h.query_by_label_contains("LIVE ws://")).unwrap().rect();
    (share, h.get_by_label("ROS 2").rect())
}

/// trial12 n-b, trial11 n5: "moving" appeared left of *Share live* and pushed both toggles
/// right by ~70 px (a click aimed at Share live during a run hit nothing), and at 1024 wide
/// "LIVE ws://…" pushed *ROS 2* out of the window. The toggles keep their rectangles while the
/// arm moves and while sharing is on, inside the window, at 1024, 1280 and 1600 wide.
#[test]
fn the_status_bar_toggles_stay_in_place_while_moving_and_sharing() {
    for width in [1024.0, 1280.0, 1600.0] {
        let mut h = app_harness(egui::vec2(width, 700.0));
        h.state_mut().settings_mut().share_live_address = "127.0.0.1:0".into();
        settle(&mut h, 0.2);
        let before = toggles(&h);
        assert!(before.1.max.x <= width, "ROS 2 {:?} inside the {width} pt window", before.1);
        let mut goal = parol6_core::parol6::standby_rad().to_vec();
        goal[0] -= 0.6;
        h.state_mut().queue_command(AppCommand::Motion(MotionCommand::MoveJoints {
            goal_rad: goal,
            speed_fraction: 0.2,
            profile: parol6_core::profile::ProfileKind::Trapezoidal,
        }));
        until(&mut h, "the arm moving", 10.0, |h| h.query_all_by_value("moving").next().is_some());
        h.run_steps(2);
        assert_eq!(toggles(&h), before, "{width} wide: the toggles while moving vs at rest");
        if width == 1024.0 {
            h.get_by_label("Share live").click();
            until(&mut h, "sharing", 10.0, |h| h.state().sharing_live().is_some());
            h.run_steps(3);
            assert!(has_label(&h, "LIVE ws://127.0.0.1:"), "the address is shown");
            assert_eq!(toggles(&h), before, "{width} wide: the toggles while sharing vs before");
            h.get_by_label_contains("LIVE ws://").click();
            until(&mut h, "sharing stopped", 10.0, |h| h.state().sharing_live().is_none());
        }
    }
}

/// trial14 m6: at 1024 and 1280 wide with the robot connected, the last read-out before the
/// *Share live* slot was cut mid-word ("cmd laten"). Read-outs are shown whole or not at all.
#[test]
fn the_status_bar_shows_whole_read_outs_or_none() {
    use parol6_app::app::{ConnectTarget, LaunchOptions};
    for width in [1024.0, 1280.0] {
        let opts = LaunchOptions { connect: Some(ConnectTarget::Emulator), ..ui_support::launch_options() };
        let mut h = ui_support::harness_with(opts, egui::vec2(width, 700.0));
        until(&mut h, "the link rate shown", 15.0, |h| h.query_by_label_contains("link ").is_some());
        h.run_steps(3);
        let share = toggles(&h).0;
        let bar: Vec<(String, egui::Rect)> = h
            .root()
            .query_all_by_role(egui::accesskit::Role::Label)
            .filter(|n| (n.rect().center().y - share.center().y).abs() < 4.0 && n.rect().min.x < share.min.x)
            .map(|n| (n.value().or_else(|| n.accesskit_node().label()).unwrap_or_default(), n.rect()))
            .collect();
        assert!(
            bar.iter().any(|(t, _)| t.contains("FPS") || t.trim() == "idle"),
            "{width} wide: the bar's read-outs {bar:?}"
        );
        for (text, rect) in &bar {
            assert!(
                rect.max.x <= share.min.x,
                "{width} wide: {text:?} ends at {} under the Share live slot at {}",
                rect.max.x,
                share.min.x
            );
        }
    }
}

/// trial12 n-e: F5 on a program with pre-flight errors did nothing and said nothing (Run is
/// greyed, the count red). A notice names the count and the first error with its step and line.
#[test]
fn f5_on_a_program_with_pre_flight_errors_says_why_it_does_not_run() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    let dir = temp_dir("far");
    let far = dir.join("far.json");
    std::fs::write(
        &far,
        "{\"format\": \"parol6-program\", \"version\": 1, \"name\": \"Too far\",\n \"steps\": [\n  {\"type\": \"dwell\", \"seconds\": 0.1},\n  {\"type\": \"move_l\", \"pose\": {\"position_mm\": [0, 900, 300], \"rpy_deg\": [180, 0, 90]}},\n  {\"type\": \"move_l\", \"pose\": {\"position_mm\": [0, 950, 300], \"rpy_deg\": [180, 0, 90]}}\n ]}",
    )
    .unwrap();
    ui_support::open_program_file(&mut h, &far);
    until(&mut h, "the pre-flight", 10.0, |h| has_label(h, "pre-flight: 1 error"));
    ui_support::pointer_on_view(&mut h);
    h.key_press(egui::Key::F5);
    h.run_steps(2);
    let want = "Cannot run Too far: pre-flight found 1 error: step 2 (line 4):";
    assert!(h.state().notices().iter().any(|n| n.error && n.text.contains(want)), "{:?}", notices(&h));
    assert!(!h.state().program_running());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// trial12 n-f: Esc (STOP) during a run stopped it without a notice, and at 1024×700 the
/// program's status line is below the fold. A notice says which run stopped and why.
#[test]
fn esc_during_a_run_says_the_run_stopped() {
    let mut h = app_harness(egui::vec2(1024.0, 700.0));
    assert!(h.state_mut().start_program("Draw", false), "Draw starts");
    until(&mut h, "the arm moving", 20.0, |h| h.state().backend().state().moving);
    ui_support::pointer_on_view(&mut h);
    h.key_press(egui::Key::Escape);
    until(&mut h, "the run ended", 10.0, |h| !h.state().program_running());
    h.run_steps(2);
    assert!(noticed(&h, "Draw stopped: the operator pressed STOP"), "{:?}", notices(&h));
}

/// trial11 n3: E-STOP (and STOP) during an ISO 9283 test ended it without a word. A notice
/// says the test stopped and by what.
#[test]
fn e_stop_and_stop_during_an_iso_test_say_the_test_stopped() {
    for (command, why) in [
        (AppCommand::EStop(true), "ISO 9283 test stopped: the operator pressed E-STOP"),
        (AppCommand::Motion(MotionCommand::Stop), "ISO 9283 test stopped: the operator pressed STOP"),
    ] {
        let mut h = app_harness(egui::vec2(1280.0, 2400.0));
        until(&mut h, "the pre-flight", 10.0, |h| has_label(h, "pre-flight: every pose reachable"));
        h.get_by_label("Run test").click();
        until(&mut h, "the test moving", 20.0, |h| {
            h.state().measurement().running() && h.state().backend().state().moving
        });
        h.state_mut().queue_command(command);
        until(&mut h, "the test ended", 10.0, |h| !h.state().measurement().running());
        h.run_steps(2);
        assert!(noticed(&h, why), "{:?}", notices(&h));
    }
}

/// trial11 n2: Calibrate and Clear error gave no visible answer on the fake robot (the
/// simulation here: the same command path). Each says it was sent.
#[test]
fn gripper_calibrate_and_clear_error_answer_with_a_notice() {
    let mut h = app_harness(egui::vec2(1280.0, 800.0));
    h.state_mut().queue_command(AppCommand::Io(IoCommand::GripperCalibrate));
    h.run_steps(2);
    assert!(noticed(&h, "gripper calibration sent"), "{:?}", notices(&h));
    h.state_mut().queue_command(AppCommand::Io(IoCommand::ClearError));
    h.run_steps(2);
    assert!(noticed(&h, "CLEAR ERROR sent"), "{:?}", notices(&h));
}

/// trial11 n11: "cannot record to P: P: it is being recorded to now". The file is named once.
#[test]
fn a_recording_refusal_names_the_file_once() {
    let dir = temp_dir("rec");
    let path = dir.join("held.mcap");
    let opts = parol6_app::app::LaunchOptions { record: Some(path.clone()), ..ui_support::launch_options() };
    let mut first = ui_support::harness_with(opts, egui::vec2(1280.0, 800.0));
    settle(&mut first, 0.3);
    let mut h = app_harness(egui::vec2(1280.0, 800.0));
    h.state_mut().queue_command(AppCommand::Record(Some(path.clone())));
    h.run_steps(2);
    let shown = path.display().to_string();
    let refusal = h.state().notices().iter().find(|n| n.text.contains("being recorded")).map(|n| n.text.clone());
    let refusal = refusal.unwrap_or_else(|| panic!("a refusal: {:?}", notices(&h)));
    assert_eq!(refusal.matches(&shown).count(), 1, "{refusal}");
    assert!(refusal.starts_with(&format!("cannot record to {shown}: it is being recorded")), "{refusal}");
    first.state_mut().queue_command(AppCommand::Record(None));
    settle(&mut first, 0.3);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// trial11 n1: "cannot read ~/квадрат.gcode": a typed `~/` is the home directory.
#[test]
fn a_typed_tilde_in_the_program_file_field_is_the_home_directory() {
    let Some(home) = std::env::var_os("HOME").filter(|h| !h.is_empty()) else { return };
    let name = format!("parol6-no-such-{}.gcode", std::process::id());
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    h.get_by_label("Program file").click();
    h.run_steps(1);
    h.get_by_label("Program file").type_text(&format!("~/{name}"));
    h.run_steps(1);
    h.get_by_label("Open").click();
    let want = std::path::PathBuf::from(home).join(&name).display().to_string();
    until(&mut h, "the error notice", 5.0, |h| h.state().notices().iter().any(|n| n.error && n.text.contains(&name)));
    assert!(noticed(&h, &want), "the home directory, not ~: {:?}", notices(&h));
}

/// trial11 n7: with no program running (also under the E-STOP latch) *Pause (F6)* and *Stop
/// program* gave no reason why they do nothing. They are greyed, and the pointer on them says
/// that no program is running.
#[test]
fn pause_and_stop_program_say_why_they_are_greyed_with_no_run() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    h.state_mut().queue_command(AppCommand::EStop(true));
    h.run_steps(3);
    for name in ["Pause (F6)", "Stop program"] {
        assert!(h.get_by_label(name).accesskit_node().is_disabled(), "{name} is greyed");
        h.get_by_label(name).hover();
        settle(&mut h, 0.8);
        assert!(has_label(&h, "no program is running"), "{name}: the reason on hover");
        ui_support::pointer_on_view(&mut h);
        h.run_steps(2);
    }
}

/// The `t = … s` read-out of the status bar.
fn status_clock_s(h: &Harness<'_, Parol6App>) -> f64 {
    let label = h
        .root()
        .query_all_by_role(egui::accesskit::Role::Label)
        .filter_map(|n| n.value().or_else(|| n.accesskit_node().label()))
        .find(|t| t.starts_with("t = ") && t.ends_with(" s") && !t.contains('\n'))
        .expect("the status bar's clock");
    label.trim_start_matches("t = ").trim_end_matches(" s").trim().parse().unwrap()
}

/// trial 20: connected to the robot after a spell in simulation, the status bar's `t = …` went
/// on with the simulation's clock, 57 s off the plots' time axis (the robot link's clock). It
/// shows the clock of the state shown.
#[test]
fn the_status_bar_clock_is_the_shown_states_clock() {
    use parol6_app::panels::LinkCommand;
    use parol6_core::motion::StateSource;
    let mut h = app_harness(egui::vec2(1280.0, 800.0));
    settle(&mut h, 2.0);
    let sim_t = h.state().backend().state().time_s;
    assert!(sim_t > 1.5, "the simulation's clock runs: {sim_t}");
    assert!((status_clock_s(&h) - sim_t).abs() < 0.5, "simulation: {} vs {sim_t}", status_clock_s(&h));
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::ConnectEmulator));
    until(&mut h, "the robot shown", 15.0, |h| h.state().backend().state().source == StateSource::Robot);
    // the window shows the robot once its first status is in (a loaded host: a few frames later)
    until(&mut h, "the bar showing the link's clock", 10.0, |h| {
        (status_clock_s(h) - h.state().backend().state().time_s).abs() < 0.5
    });
    let robot_t = h.state().backend().state().time_s;
    assert!(robot_t + 1.0 < sim_t + 0.5, "the test needs the two clocks apart: robot {robot_t}, simulation {sim_t}");
}

/// Trial 24 m4: with the drives disabled or the E-stop latched the status bar said a plain
/// "ROBOT". It says the drives' state after ROBOT (and nothing in simulation).
#[test]
fn the_status_bar_says_whether_the_robots_drives_are_enabled() {
    use parol6_app::panels::LinkCommand;
    use parol6_core::motion::StateSource;
    let mut h = app_harness(egui::vec2(1280.0, 800.0));
    settle(&mut h, 0.5);
    assert!(
        h.query_by_label("ENABLED").is_none() && h.query_by_label("DISABLED").is_none(),
        "no drive word in simulation"
    );
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::ConnectEmulator));
    until(&mut h, "the robot enabled", 15.0, |h| {
        let s = h.state().backend().state();
        s.source == StateSource::Robot && s.blocked.is_none()
    });
    until(&mut h, "ENABLED in the bar", 5.0, |h| h.query_by_label("ENABLED").is_some());
    h.get_by_label("E-STOP").click();
    until(&mut h, "the latch", 10.0, |h| h.state().estop_latched());
    until(&mut h, "E-STOP LATCHED in the bar", 5.0, |h| {
        h.query_by_label("E-STOP LATCHED").is_some() && h.query_by_label("ENABLED").is_none()
    });
    ui_support::release_estop(&mut h);
    until(&mut h, "the release", 10.0, |h| !h.state().estop_latched());
    until(&mut h, "ENABLED again", 10.0, |h| h.query_by_label("ENABLED").is_some());
}

/// Trial 26 m1: a double-click on *Disconnect*: the first click disconnected, the port list took
/// the button's place and the second click opened it. The section's controls are greyed a
/// moment after Connect or Disconnect.
#[test]
fn a_double_click_on_disconnect_lands_on_nothing_else() {
    use parol6_app::panels::LinkCommand;
    let mut h = app_harness(egui::vec2(1280.0, 2400.0));
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::ConnectEmulator));
    until(&mut h, "the robot", 15.0, |h| h.state().robot_connected());
    until(&mut h, "Disconnect", 5.0, |h| h.query_by_label("Disconnect").is_some());
    settle(&mut h, 0.5);
    let at = h.get_by_label("Disconnect").rect().center();
    for _ in 0..2 {
        ui_support::mouse_click(&mut h, at);
        until(&mut h, "disconnected", 10.0, |h| !h.state().robot_connected());
        h.run_steps(2);
    }
    assert!(!egui::Popup::is_any_open(&h.ctx), "the second click opened what took Disconnect's place");
    assert!(h.get_by_label("Connect to the built-in emulator").accesskit_node().is_disabled(), "greyed a moment");
    ui_support::click_when_enabled(&mut h, "Connect to the built-in emulator");
    until(&mut h, "connected again", 15.0, |h| h.state().robot_connected());
}

//! Issue 32's minor defects of the operator window, each driven headless through egui's
//! kittest harness on the full app: Esc closes the topmost dialog but stays STOP where the arm
//! moves or the 3D view has the pointer; the point table refuses far values and adds and removes
//! rows, and its errors show in front of it.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui::{self, Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use ui_support::{app_harness, open_program_file, pointer_on_view, settle, type_into, until};

use parol6_app::app::Parol6App;
use parol6_core::program::{PoseMm, Program, Step, json};

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("parol6-minor-ui-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn press(h: &mut Harness<'_, Parol6App>, key: Key) {
    h.event(egui::Event::Key { key, pressed: true, modifiers: Modifiers::NONE, repeat: false, physical_key: None });
    h.run_steps(1);
    h.event(egui::Event::Key { key, pressed: false, modifiers: Modifiers::NONE, repeat: false, physical_key: None });
    h.run_steps(2);
}

/// The pointer over the program panel's "Program file" label: not over the 3D view, no field
/// focused.
fn pointer_on_panel(h: &mut Harness<'_, Parol6App>) {
    let at = h.get_by_label("Program file").rect().center();
    h.hover_at(at);
    h.run_steps(1);
}

fn menu_open(h: &Harness<'_, Parol6App>) -> bool {
    egui::Popup::is_any_open(&h.ctx)
}

/// Issue 32 minor: "Escape closes nothing (menus, dialogs, help, table); today it only acts as
/// STOP. Keep Esc = STOP where the 3D view or a motion control has focus, and let it close the
/// topmost dialog otherwise."
#[test]
fn escape_closes_the_topmost_dialog_and_stays_stop_where_the_arm_moves_or_the_view_has_the_pointer() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    pointer_on_panel(&mut h);
    // help, then the point table over it: Esc closes the table first, then the help
    press(&mut h, Key::F1);
    assert!(h.state().help_open(), "F1 opens the help");
    h.get_by_label("Table").click();
    h.run_steps(3);
    assert!(h.state().program_panel().table_open);
    pointer_on_panel(&mut h);
    press(&mut h, Key::Escape);
    assert!(!h.state().program_panel().table_open, "Esc closes the point table (the topmost)");
    assert!(h.state().help_open(), "the help under it stays");
    press(&mut h, Key::Escape);
    assert!(!h.state().help_open(), "a second Esc closes the help");

    // a menu
    h.query_all_by_label("File").next().unwrap().click();
    h.run_steps(2);
    assert!(menu_open(&h), "the File menu is open");
    pointer_on_panel(&mut h);
    press(&mut h, Key::Escape);
    assert!(!menu_open(&h), "Esc closes the File menu");

    // (the file dialog closes the same way; egui_file's title glyph has no font in the test
    // harness, which refuses tofu, so it is not opened here)

    // while a program runs, Esc is STOP first: the run ends, the help stays open
    until(&mut h, "the program's check", 60.0, |h| !h.state().program_panel().checking());
    press(&mut h, Key::F1);
    press(&mut h, Key::F5);
    until(&mut h, "the program moving the arm", 60.0, |h| h.state().program_running());
    pointer_on_panel(&mut h);
    press(&mut h, Key::Escape);
    until(&mut h, "the run's end", 10.0, |h| !h.state().program_running());
    assert!(h.state().help_open(), "Esc stopped the program and closed nothing");

    // a paused program (nothing moves) with the pointer over the 3D view: Esc is STOP
    press(&mut h, Key::F5);
    until(&mut h, "the program moving the arm", 60.0, |h| h.state().program_running());
    press(&mut h, Key::F6);
    until(&mut h, "the arm at rest", 20.0, |h| !h.state().backend().state().moving);
    pointer_on_view(&mut h);
    press(&mut h, Key::Escape);
    until(&mut h, "the run's end", 10.0, |h| !h.state().program_running());
    assert!(h.state().help_open(), "Esc over the 3D view is STOP, it closed nothing");
}

fn table_program(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("table.json");
    let program = Program::from_steps(
        "table",
        vec![
            Step::MoveL {
                pose: PoseMm { position_mm: [200.0, 0.0, 300.0], rpy_deg: [180.0, 0.0, 0.0] },
                speed_mm_s: None,
                blend_mm: None,
                duration_s: None,
            },
            Step::Dwell { seconds: 1.0 },
        ],
    );
    std::fs::write(&path, json::to_string(&program)).unwrap();
    path
}

/// The app with [`table_program`] opened from a new folder `tag` and its point table shown.
fn table_opened(tag: &str) -> (Harness<'static, Parol6App>, std::path::PathBuf) {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    let dir = temp_dir(tag);
    let path = table_program(&dir);
    open_program_file(&mut h, &path);
    h.get_by_label("Table").click();
    h.run_steps(3);
    (h, dir)
}

fn steps(h: &Harness<'_, Parol6App>) -> Vec<Step> {
    h.state().program_panel().program().steps.iter().map(|s| s.step.clone()).collect()
}

fn error_with(h: &Harness<'_, Parol6App>, text: &str) -> bool {
    h.state().notices().iter().any(|n| n.error && n.text.contains(text))
}

/// Issue 32 minor: "The point table accepts "1e9" (shown as "100000(") and silently reverts
/// "abc". It has no add/remove-row controls, and its Save-as error hides behind the table
/// window."
#[test]
fn the_point_table_refuses_far_values_adds_and_removes_rows_and_shows_its_errors_in_front() {
    let (mut h, dir) = table_opened("table");
    let before = steps(&h);
    type_into(&mut h, "table 1 X", "1e9");
    assert_eq!(steps(&h), before, "1e9 mm is refused");
    assert!(error_with(&h, "table row 1, X"), "the refusal names the cell: {:?}", h.state().notices());
    type_into(&mut h, "table 1 X", "abc");
    assert_eq!(steps(&h), before);
    assert!(error_with(&h, "\"abc\" is not a number"), "{:?}", h.state().notices());
    type_into(&mut h, "table 2 time", "1e9");
    assert_eq!(steps(&h), before, "a dwell of 1e9 s is refused");

    // add a row (a copy of the selected one, after it) and remove it again
    h.get_by_label("Add row").click();
    h.run_steps(3);
    assert_eq!(steps(&h).len(), 3, "Add row adds a step");
    assert_eq!(steps(&h)[2], before[1], "the new row copies the last one");
    h.get_by_label("Remove row").click();
    h.run_steps(3);
    assert_eq!(steps(&h), before, "Remove row removes the selected step");

    // a save that fails shows its error in front of the table window
    type_into(&mut h, "table 2 time", "2");
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::write(&dir, b"a file where the folder was").unwrap();
    h.get_by_label("Save").click();
    h.run_steps(3);
    let notice = h.state().notices().iter().rev().find(|n| n.error).expect("the save's error").text.clone();
    let at = h.get_by_label(&notice).rect().center();
    // the notices' layer is drawn in front of every window (and lets clicks through to them)
    let notices = egui::LayerId::new(egui::Order::Tooltip, egui::Id::unique("parol6-notices"));
    assert!(notices.order > egui::Order::Middle);
    assert!(h.ctx.memory(|m| m.areas().is_visible(&notices)), "the notices' layer is shown");
    let area = h.ctx.memory(|m| m.area_rect(notices.id)).expect("the notices' rectangle");
    assert!(area.contains(at), "the notice at {at:?} is in the notices' layer {area:?}, in front of every window");
    std::fs::remove_file(&dir).unwrap();
}

/// Trial 19 m1: Esc in a point-table cell being typed into closed the whole table (egui drops
/// the keyboard on Esc before the app looked at who had it). The first Esc leaves the cell,
/// dropping what was typed; the second closes the table.
#[test]
fn escape_in_a_point_table_cell_leaves_the_cell_and_keeps_the_table_open() {
    let (mut h, dir) = table_opened("table-esc");
    let before = steps(&h);
    h.get_by_label("table 1 X").click();
    h.run_steps(1);
    h.get_by_label("table 1 X").type_text("123");
    h.run_steps(1);
    let focused = |h: &Harness<'_, Parol6App>| h.ctx.memory(|m| m.focused()).is_some();
    assert!(focused(&h), "the cell has the keyboard");
    press(&mut h, Key::Escape);
    assert!(h.state().program_panel().table_open, "the first Esc leaves the cell, the table stays open");
    assert!(!focused(&h), "the cell gave up the keyboard");
    assert_eq!(steps(&h), before, "what was typed is dropped");
    assert!(h.state().moves_sent().next().is_none(), "Esc in the table moved nothing");
    pointer_on_panel(&mut h);
    press(&mut h, Key::Escape);
    assert!(!h.state().program_panel().table_open, "the second Esc closes the table");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A pose away from the standby wrist singularity (J5 = 34°), where a jog moves freely.
fn work_pose() -> Vec<f64> {
    let mut q = parol6_core::parol6::standby_rad().to_vec();
    q[1] += 0.2;
    q[2] -= 0.3;
    q[4] = 0.6;
    q
}

fn jog_harness() -> Harness<'static, Parol6App> {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    h.state_mut().teleport(work_pose()).expect("teleport");
    h.run_steps(3);
    settle(&mut h, 0.2);
    h
}

fn pointer_button(h: &mut Harness<'_, Parol6App>, at: egui::Pos2, pressed: bool) {
    h.hover_at(at);
    let button = egui::PointerButton::Primary;
    h.event(egui::Event::PointerButton { pos: at, button, pressed, modifiers: Default::default() });
}

/// Holds the jog button `name` for `s` seconds, calling `during` once half-way.
fn hold_button(h: &mut Harness<'_, Parol6App>, name: &str, s: f64, during: impl FnOnce(&mut Harness<'_, Parol6App>)) {
    let at = h.get_by_label(name).rect().center();
    pointer_button(h, at, true);
    settle(h, s / 2.0);
    during(h);
    settle(h, s / 2.0);
    pointer_button(h, at, false);
    ui_support::until(h, "the arm at rest", 10.0, |h| !h.state().backend().state().moving);
    h.run_steps(2);
}

fn label_with(h: &Harness<'_, Parol6App>, text: &str) -> Option<String> {
    h.root()
        .query_all_by_role(egui::accesskit::Role::Label)
        .filter_map(|n| n.value().or_else(|| n.accesskit_node().label()))
        .find(|t| t.contains(text))
}

/// Issue 32 minor: "Radians are not applied to the jog read-out, the angle increment or the
/// Measurement tool RPY."
#[test]
fn radians_reach_the_jog_readout_the_angle_increment_and_the_measurement_rpy() {
    let mut h = jog_harness();
    h.state_mut().settings_mut().unit = parol6_app::panels::AngleUnit::Rad;
    h.run_steps(3);
    hold_button(&mut h, "+Rz", 0.6, |_| {});
    let all: Vec<String> = h
        .root()
        .query_all_by_role(egui::accesskit::Role::Label)
        .filter_map(|n| n.value().or_else(|| n.accesskit_node().label()))
        .collect();
    let readout = label_with(&h, "released after").unwrap_or_else(|| panic!("the jog's read-out: {all:?}"));
    assert!(readout.ends_with(" rad"), "the read-out is in rad: {readout}");
    let tcp = label_with(&h, " mm · ").expect("the jog panel's TCP line");
    assert!(tcp.ends_with(" rad"), "the jog panel's TCP line is in rad: {tcp}");
    type_into(&mut h, "Step angle", "0.1");
    let (_, step_deg) = h.state().cartesian_jog_panel().step_increments();
    assert!((step_deg - 0.1f64.to_degrees()).abs() < 1e-9, "0.1 typed in rad is {step_deg}°");
    assert!(h.query_by_label("Tool RPY rad").is_some(), "the measurement's tool orientation is in rad");
    assert!(h.query_by_label("Tool RPY °").is_none());
}

/// Issue 32 minors: "The jog readout "released after N mm" keeps changing during later
/// motions." "The jog message grows from 1 to 4 lines and pushes the panels below it."
#[test]
fn the_jog_readout_is_frozen_at_release_and_its_message_keeps_one_height() {
    let mut h = jog_harness();
    let below = |h: &Harness<'_, Parol6App>| h.get_by_label("Cartesian target").rect().top();
    let y0 = below(&h);
    let mut y_held = 0.0;
    hold_button(&mut h, "+X", 0.6, |h| y_held = below(h));
    let released = label_with(&h, "released after").expect("the jog's read-out");
    assert_eq!(y_held, y0, "the held jog's message moved the panel below");
    assert_eq!(below(&h), y0, "the released jog's message moved the panel below");
    // at rest, the read-out stays as it was
    settle(&mut h, 0.3);
    assert_eq!(label_with(&h, "released after").as_deref(), Some(released.as_str()), "read-out changed");
    // a later motion (HOME) does not rewrite what the jog moved: the line empties (trial 21 m1,
    // trial 22 m4: it stayed through programs, HOME and E-STOP)
    pointer_on_view(&mut h);
    press(&mut h, Key::H);
    until(&mut h, "HOME moving", 10.0, |h| h.state().backend().state().moving);
    settle(&mut h, 0.3);
    assert_eq!(label_with(&h, "released after"), None, "the jog's line after HOME");
    assert_eq!(below(&h), y0, "the emptied line moved the panel below");
    press(&mut h, Key::Escape);
}

/// A held jog that Esc (STOP) ended said "released after …", as if the operator had let go. It
/// says "ended by STOP after …"; the next jog, let go, says "released after …" again.
#[test]
fn a_held_jog_ended_by_stop_says_so() {
    let mut h = jog_harness();
    let mut sent_at_stop = 0;
    hold_button(&mut h, "+X", 0.8, |h| {
        press(h, Key::Escape);
        sent_at_stop = h.state().moves_sent().count();
    });
    // the button was held on after STOP: the jog does not start again (let go, press anew)
    let after: Vec<String> = h.state().moves_sent().skip(sent_at_stop).map(str::to_string).collect();
    assert_eq!(after, [] as [String; 0], "the jog button held through STOP jogged again");
    let stopped = label_with(&h, "ended by STOP after");
    assert!(stopped.as_deref().is_some_and(|t| t.starts_with("+X (world)")), "the read-out: {stopped:?}");
    assert!(label_with(&h, "released after").is_none(), "the jog was not let go first");
    hold_button(&mut h, "+Y", 0.4, |_| {});
    assert!(label_with(&h, "+Y (world) released after").is_some(), "the next jog, let go");
    // a STOP after the jog came to rest does not rewrite it
    pointer_on_view(&mut h);
    press(&mut h, Key::Escape);
    h.run_steps(3);
    assert!(label_with(&h, "+Y (world) released after").is_some(), "a later STOP rewrote the jog's line");
}

/// Issue 32 minor: "During a held Cartesian jog the joint sliders show the jog's planned end
/// instead of the arm."
#[test]
fn joint_read_outs_follow_the_arm_during_a_held_cartesian_jog() {
    let mut h = jog_harness();
    let mut seen = (0.0, 0.0, 0.0);
    hold_button(&mut h, "+X", 1.0, |h| {
        let s = h.state().backend().state();
        let shown: f64 = h.get_by_label("J1 target").value().unwrap().parse().unwrap();
        seen = (shown, s.q[0].to_degrees(), s.target_q[0].to_degrees());
    });
    let (shown, arm, planned_end) = seen;
    assert!((planned_end - arm).abs() > 10.0, "the test needs a jog whose end is far: {seen:?}");
    assert!((shown - arm).abs() < 3.0, "J1 shows {shown:.2}°, the arm is at {arm:.2}° (planned end {planned_end:.2}°)");
}

/// Issue 32 minor: "The run status is stale after opening another program."
#[test]
fn opening_another_program_clears_the_last_runs_status() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    let dir = temp_dir("stale");
    let (a, b) = (dir.join("first.json"), dir.join("second.json"));
    for (path, name) in [(&a, "first"), (&b, "second")] {
        let program = Program::from_steps(name, vec![Step::Dwell { seconds: 0.1 }]);
        std::fs::write(path, json::to_string(&program)).unwrap();
    }
    open_program_file(&mut h, &a);
    pointer_on_panel(&mut h);
    press(&mut h, Key::F5);
    until(&mut h, "the run's end", 20.0, |h| {
        h.state().program_progress().is_some_and(|p| p.state.is_finished()) && !h.state().program_running()
    });
    h.run_steps(2);
    let all: Vec<String> = h
        .root()
        .query_all_by_role(egui::accesskit::Role::Label)
        .filter_map(|n| n.value().or_else(|| n.accesskit_node().label()))
        .collect();
    assert!(label_with(&h, "first: done").is_some(), "the run's outcome is shown: {all:?}");
    h.state_mut().open_program_file(&b).unwrap();
    until(&mut h, "the second program's load", 30.0, |h| !h.state().program_panel().checking());
    h.run_steps(2);
    assert_eq!(h.state().program_panel().program().name, "second");
    let all: Vec<String> = h
        .root()
        .query_all_by_role(egui::accesskit::Role::Label)
        .filter_map(|n| n.value().or_else(|| n.accesskit_node().label()))
        .filter(|t| t.contains("first"))
        .collect();
    assert!(label_with(&h, "first: done").is_none(), "the last program's outcome is gone: {all:?}");
    assert!(label_with(&h, "Idle").is_some(), "the progress line is idle");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The window on the built-in emulator with Draw running and the arm moving.
fn draw_running_on_the_fake_robot() -> Harness<'static, Parol6App> {
    use parol6_app::app::{ConnectTarget, LaunchOptions};
    let opts = LaunchOptions { connect: Some(ConnectTarget::Emulator), ..ui_support::launch_options() };
    let mut h = ui_support::harness_with(opts, egui::vec2(1280.0, 2400.0));
    until(&mut h, "the emulator answers", 15.0, |h| {
        let s = h.state().backend().state();
        s.source == parol6_app::panels::StateSource::Robot && s.blocked.is_none()
    });
    assert!(h.state_mut().start_program("Draw", false));
    until(&mut h, "the program moving the arm", 60.0, |h| {
        h.state().program_running() && h.state().backend().state().moving
    });
    settle(&mut h, 0.3);
    h
}

/// Issue 32 minor: "Disconnect mid-program reports "halted: refused: link is Lost": say that
/// the operator disconnected, once, in plain words."
#[test]
fn disconnecting_mid_program_says_once_that_the_operator_disconnected() {
    let mut h = draw_running_on_the_fake_robot();
    h.get_by_label("Disconnect").click();
    settle(&mut h, 1.5);
    let notices: Vec<String> = h.state().notices().iter().map(|n| n.text.clone()).collect();
    assert!(!notices.iter().any(|n| n.contains("link is")), "no link jargon: {notices:?}");
    let said = notices.iter().filter(|n| n.contains("the operator disconnected")).count();
    assert_eq!(said, 1, "said once: {notices:?}");
    let line = label_with(&h, "Draw: the operator").unwrap_or_default();
    assert!(line.contains("the operator disconnected"), "the progress line says so: {line:?}");
}

/// Issue 32 minor: "The MCAP metadata has "program": "" although Draw ran." A recording
/// started with a built-in program loaded names it.
#[test]
fn a_recording_names_the_program_loaded_when_it_started() {
    let dir = temp_dir("mcap");
    let path = dir.join("draw.mcap");
    let opts = parol6_app::app::LaunchOptions { record: Some(path.clone()), ..ui_support::launch_options() };
    let mut h = ui_support::harness_with(opts, egui::vec2(1280.0, 1400.0));
    let loaded = h.state().program_panel().program().name.clone();
    assert!(!loaded.is_empty());
    settle(&mut h, 0.3);
    h.query_all_by_label("File").next().unwrap().click();
    h.run_steps(2);
    h.get_by_label("Stop recording").click();
    h.run_steps(3);
    let rec = parol6_core::telemetry::reader::read_recording(&std::fs::read(&path).unwrap()).unwrap();
    assert_eq!(rec.metadata.get("program"), Some(&loaded), "{:?}", rec.metadata);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 32 minor: "There is no lasting recording indicator: show a red dot, the file name and
/// the elapsed time in the status bar."
#[test]
fn the_status_bar_shows_the_recording_with_its_file_and_elapsed_time() {
    let dir = temp_dir("rec");
    let path = dir.join("shown.mcap");
    let opts = parol6_app::app::LaunchOptions { record: Some(path.clone()), ..ui_support::launch_options() };
    let mut h = ui_support::harness_with(opts, egui::vec2(1280.0, 1400.0));
    settle(&mut h, 1.2);
    let shown = label_with(&h, "REC shown.mcap").expect("the recording in the status bar");
    assert!(shown.starts_with("REC shown.mcap 0:") && !shown.ends_with("0:00"), "the elapsed time counts: {shown}");
    h.query_all_by_label("File").next().unwrap().click();
    h.run_steps(2);
    h.get_by_label("Stop recording").click();
    h.run_steps(3);
    assert!(label_with(&h, "REC shown.mcap").is_none(), "gone once stopped");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 32 minor: "The File menu stays open over an error." A File-menu action that fails
/// closes the menu, so the error notice is seen, not hidden under it.
#[test]
fn a_file_menu_action_that_fails_closes_the_menu_over_its_error() {
    let mut h = app_harness(egui::vec2(1280.0, 800.0));
    let dir = temp_dir("file-menu");
    // a recording that is not there
    ui_support::open_recording(&mut h, &dir.join("no-such-run.mcap"));
    until(&mut h, "the open's error", 20.0, |h| error_with(h, "no-such-run.mcap"));
    h.run_steps(2);
    assert!(!menu_open(&h), "the File menu closed over the error of Open recording");

    // recording to a place that cannot be written (a path under a file)
    h.query_all_by_label("File").next().unwrap().click();
    h.run_steps(2);
    assert!(menu_open(&h));
    let blocker = dir.join("a-file");
    std::fs::write(&blocker, "x").unwrap();
    let target = blocker.join("out.mcap");
    h.get_by_label("Record to").click();
    h.run_steps(1);
    h.get_by_label("Record to").type_text(&target.display().to_string());
    h.run_steps(1);
    h.get_by_label("Start recording").click();
    h.run_steps(3);
    assert!(error_with(&h, "out.mcap"), "the recording's error is shown: {:?}", h.state().notices());
    assert!(!menu_open(&h), "the File menu closed over the error of Start recording");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Trial 9: E-STOP during a run ended it with "Draw stopped: halted: refused: controller is
/// disabled: enable it first", the refusal that followed, not its cause. It now says the
/// operator pressed E-STOP, once.
#[test]
fn an_estop_during_a_run_says_once_that_the_operator_pressed_it() {
    let mut h = draw_running_on_the_fake_robot();
    h.get_by_label("E-STOP").click();
    settle(&mut h, 1.5);
    let notices: Vec<String> = h.state().notices().iter().map(|n| n.text.clone()).collect();
    assert!(
        !notices.iter().any(|n| n.contains("Draw stopped") && n.contains("disabled")),
        "no refusal as the cause: {notices:?}"
    );
    let said = notices.iter().filter(|n| n.contains("Draw stopped: the operator pressed E-STOP")).count();
    assert_eq!(said, 1, "said once: {notices:?}");
    ui_support::release_estop(&mut h);
    settle(&mut h, 0.5);
}

/// Regression (trial17 m2): STOP after minutes of a looping run said "stopped after 0 of 12
/// steps", as if nothing had run. A looping run's stop names its passes.
#[test]
fn a_stopped_looping_run_names_its_passes() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    let dir = temp_dir("loop");
    let path = dir.join("loop.json");
    let program = Program::from_steps("loop", vec![Step::Dwell { seconds: 0.05 }, Step::Dwell { seconds: 0.05 }]);
    std::fs::write(&path, json::to_string(&program)).unwrap();
    open_program_file(&mut h, &path);
    h.state_mut().program_panel_mut().looping = true;
    pointer_on_panel(&mut h);
    press(&mut h, Key::F5);
    until(&mut h, "two passes", 20.0, |h| h.state().program_progress().is_some_and(|p| p.passes >= 2));
    press(&mut h, Key::Escape);
    until(&mut h, "the run stopped", 20.0, |h| !h.state().program_running());
    h.run_steps(2);
    let line = label_with(&h, "loop: stopped after").expect("the run's outcome");
    assert!(line.contains(" passes and "), "the stop names the passes: {line}");
    std::fs::remove_dir_all(&dir).unwrap();
}

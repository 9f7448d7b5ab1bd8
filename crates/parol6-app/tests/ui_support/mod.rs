//! The whole app in egui's kittest harness, shared by the UI tests: the embedded PAROL6 in
//! simulation, no settings file, MSAA 1, accessibility check off, three frames run.

#![allow(dead_code)]

use std::time::{Duration, Instant};

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use parol6_app::app::{LaunchOptions, Parol6App};
use parol6_core::RobotModel;

/// The launch options of the UI tests: the embedded PAROL6 in simulation, no settings file,
/// MSAA 1. A test changes what it needs: `LaunchOptions { connect: …, ..launch_options() }`.
pub fn launch_options() -> LaunchOptions {
    LaunchOptions {
        model: RobotModel::parol6(),
        connect: None,
        settings_path: None,
        test_script: None,
        started: Instant::now(),
        msaa_samples: 1,
        record: None,
        replay: None,
        recording_info: Default::default(),
    }
}

/// The app started with `opts`, in a harness of `size` points, three frames run.
pub fn harness_with(opts: LaunchOptions, size: egui::Vec2) -> Harness<'static, Parol6App> {
    let app = Parol6App::new(opts, None).expect("app");
    let mut h = Harness::builder()
        .with_size(size)
        .with_accessibility_check(false)
        .build_ui_state(|ui, app: &mut Parol6App| app.frame(ui), app);
    h.run_steps(3);
    h
}

/// The app in a harness of `size` points.
pub fn app_harness(size: egui::Vec2) -> Harness<'static, Parol6App> {
    harness_with(launch_options(), size)
}

/// Runs frames until `f` holds (at most `s` seconds of wall time); fails naming `what`.
pub fn until(h: &mut Harness<'_, Parol6App>, what: &str, s: f64, f: impl Fn(&Harness<'_, Parol6App>) -> bool) {
    let deadline = Instant::now() + Duration::from_secs_f64(s);
    loop {
        h.run_steps(1);
        if f(h) {
            return;
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(15));
    }
}

/// Clicks *Release E-STOP* once it takes clicks: it stays greyed for a moment after the latch
/// (`panels::io_gripper::ESTOP_RELEASE_HOLD_OFF`).
pub fn release_estop(h: &mut Harness<'_, Parol6App>) {
    click_when_enabled(h, "Release E-STOP");
}

/// Clicks the button labelled `name` once it takes clicks: some are greyed a moment after the
/// click that put them in place (Release E-STOP after the latch, Connect after Disconnect).
#[allow(dead_code)] // not every test binary that includes this module calls it
pub fn click_when_enabled(h: &mut Harness<'_, Parol6App>, name: &str) {
    use egui_kittest::kittest::NodeT;
    until(h, &format!("{name} taking clicks"), 10.0, |h| {
        h.query_by_label(name).is_some_and(|b| !b.accesskit_node().is_disabled())
    });
    h.get_by_label(name).click();
}

/// Runs frames for `s` seconds of wall time (the simulation and the link run on their own
/// threads).
pub fn settle(h: &mut Harness<'_, Parol6App>, s: f64) {
    let until = Instant::now() + Duration::from_secs_f64(s);
    while Instant::now() < until {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(15));
    }
}

/// True when some widget's label contains `text`.
pub fn has_label(h: &Harness<'_, Parol6App>, text: &str) -> bool {
    h.query_all_by_label_contains(text).next().is_some()
}

/// Types `text` into the entry called `name` and presses Enter.
pub fn type_into(h: &mut Harness<'_, Parol6App>, name: &str, text: &str) {
    h.get_by_label(name).click();
    h.run_steps(1);
    h.get_by_label(name).type_text(text);
    h.run_steps(1);
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
}

/// Opens the View menu and clicks its item `label` (the menu stays open).
pub fn click_in_view_menu(h: &mut Harness<'_, Parol6App>, label: &str) {
    h.get_by_label("View").click();
    h.run_steps(2);
    h.get_by_label(label).click();
    h.run_steps(2);
}

/// Types `path` into the program panel's file field and opens it; returns once the panel's
/// worker has read and checked it (or refused it).
pub fn open_program_file(h: &mut Harness<'_, Parol6App>, path: &std::path::Path) {
    h.get_by_label("Program file").click();
    h.run_steps(1);
    h.get_by_label("Program file").type_text(&path.display().to_string());
    h.run_steps(1);
    h.get_by_label("Open").click();
    h.run_steps(3);
    until(h, "the program's load and check", 30.0, |h| !h.state().program_panel().checking());
    h.run_steps(1);
}

/// Writes the loaded (built-in) program to `path` and opens it from there, so that Ctrl+S
/// saves it without a dialog.
pub fn reopen_program_from(h: &mut Harness<'_, Parol6App>, path: &std::path::Path) {
    std::fs::write(path, parol6_core::program::json::to_string(h.state().program_panel().program()))
        .expect("write the program file");
    open_program_file(h, path);
}

/// Types `path` into the File menu's recording field and presses Enter.
pub fn open_recording(h: &mut Harness<'_, Parol6App>, path: &std::path::Path) {
    // the menu bar's File comes before the program panel's File field
    h.query_all_by_label("File").next().expect("the File menu").click();
    h.run_steps(2);
    h.get_by_label("Recording").click();
    h.run_steps(1);
    h.get_by_label("Recording").type_text(&path.display().to_string());
    h.run_steps(1);
    h.key_press(egui::Key::Enter);
    h.run_steps(1);
}

/// Scrolls the scroll area under `at` to its end (20 wheel turns with the pointer there), then
/// lets egui's smooth scrolling run out.
pub fn scroll_to_the_end(h: &mut Harness<'_, Parol6App>, at: egui::Pos2) {
    for _ in 0..20 {
        h.event(egui::Event::PointerMoved(at));
        h.event(egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(0.0, -2000.0),
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Unknown,
            modifiers: egui::Modifiers::NONE,
        });
        h.run_steps(1);
    }
    h.run_steps(30);
}

/// The pointer over a part of the 3D view that no window covers (the jog letters and H act
/// there).
pub fn pointer_on_view(h: &mut Harness<'_, Parol6App>) {
    let view = h.get_by_label_contains("3D view unavailable").rect();
    let free = (1..10)
        .flat_map(|i| (1..10).map(move |j| (i, j)))
        .map(|(i, j)| {
            egui::pos2(view.left() + view.width() * i as f32 / 10.0, view.top() + view.height() * j as f32 / 10.0)
        })
        .find(|&p| h.ctx.layer_id_at(p).is_some_and(|l| l.order == egui::Order::Background))
        .expect("a part of the 3D view no window covers");
    h.hover_at(free);
    h.run_steps(1);
}

/// A primary mouse click at `at`: the pointer moves there, the button goes down in one frame and
/// up in the next (the keyboard focus moves as it does for a mouse, unlike kittest's `click`).
#[allow(dead_code)] // not every test binary that includes this module calls it
pub fn mouse_click(h: &mut Harness<'_, Parol6App>, at: egui::Pos2) {
    h.hover_at(at);
    for pressed in [true, false] {
        let (button, modifiers) = (egui::PointerButton::Primary, egui::Modifiers::NONE);
        h.event(egui::Event::PointerButton { pos: at, button, pressed, modifiers });
        h.run_steps(1);
    }
}

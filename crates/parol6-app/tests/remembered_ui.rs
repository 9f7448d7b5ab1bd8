//! State that survives a restart (issue 32, minor: "The loaded program, the jog frame / mode /
//! increments, the forward-dynamics profiles and the camera are not remembered"): each is
//! changed in the window, the window is dropped without its exit handler (as a crash would end
//! it), and a new window from the same settings file shows it again. A remembered value that
//! cannot be used (a file gone or invalid, an increment out of range) gives the default, and a
//! notice says so. A settings file of an older version, without the new keys, still loads.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use std::path::{Path, PathBuf};

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ui_support::{harness_with, launch_options, reopen_program_from, type_into, until};

use parol6_app::app::remembered::{CameraSetting, LastProgram};
use parol6_app::app::{LaunchOptions, Parol6App, load_settings};
use parol6_app::panels::Settings;
use parol6_core::motion::JogFrame;

const SIZE: egui::Vec2 = egui::vec2(1280.0, 800.0);

/// A fresh folder for one test and its settings file's path.
fn settings_in(test: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("parol6-remembered-{test}-{}", std::process::id()));
    if dir.exists() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("settings.json");
    (dir, path)
}

fn with_settings(path: &Path) -> LaunchOptions {
    LaunchOptions { settings_path: Some(path.to_path_buf()), ..launch_options() }
}

fn write_settings(path: &Path, settings: &Settings) {
    std::fs::write(path, serde_json::to_string_pretty(settings).unwrap()).unwrap();
}

/// A new window from the settings file at `path`, once a program it reopens is read and checked.
fn restart(path: &Path, size: egui::Vec2) -> Harness<'static, Parol6App> {
    let mut h = harness_with(with_settings(path), size);
    until(&mut h, "the reopened program's load and check", 30.0, |h| !h.state().program_panel().checking());
    h.run_steps(2);
    h
}

/// Regression: the built-in Pick & place came back at every start, whatever file was open.
#[test]
fn the_program_file_last_opened_is_reopened_and_checked_at_the_next_start() {
    let (dir, path) = settings_in("file");
    let file = dir.join("mine.json");
    let mut h = harness_with(with_settings(&path), SIZE);
    h.get_by_label("Draw").click();
    h.run_steps(3);
    reopen_program_from(&mut h, &file);
    assert_eq!(h.state().program_panel().file(), Some(file.as_path()));
    let want = Some(LastProgram::File(file.display().to_string()));
    until(&mut h, "the program in the settings file", 10.0, |_| load_settings(Some(&path)).last_program == want);
    drop(h);

    let h = restart(&path, SIZE);
    let panel = h.state().program_panel();
    assert_eq!(panel.file(), Some(file.as_path()), "the file is open again");
    assert_eq!(panel.program().name, "Draw");
    assert!(panel.checked().is_some_and(|c| c.ok), "and checked (pre-flight), as any open");
    assert!(h.state().notices().iter().all(|n| !n.error), "{:?}", h.state().notices());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A built-in program picked is remembered by its name.
#[test]
fn the_built_in_program_last_picked_comes_back_by_name() {
    let (dir, path) = settings_in("builtin");
    let mut h = harness_with(with_settings(&path), SIZE);
    h.get_by_label("Draw").click();
    h.run_steps(3);
    let want = Some(LastProgram::Builtin("Draw".into()));
    until(&mut h, "the program in the settings file", 10.0, |_| load_settings(Some(&path)).last_program == want);
    drop(h);
    let h = restart(&path, SIZE);
    assert_eq!(h.state().program_panel().program().name, "Draw");
    assert_eq!(h.state().program_panel().file(), None);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A remembered file that is gone, invalid or a remembered built-in that no longer exists:
/// the window starts with the default program, and one notice names the file and why.
#[test]
fn a_last_program_that_cannot_be_reopened_gives_the_default_and_one_notice() {
    let (dir, path) = settings_in("gone");
    let invalid = dir.join("broken.json");
    std::fs::write(&invalid, "{ this is not a program").unwrap();
    let gone = dir.join("gone.json");
    let cases = [
        (LastProgram::File(gone.display().to_string()), gone.display().to_string()),
        (LastProgram::File(invalid.display().to_string()), invalid.display().to_string()),
        (LastProgram::Builtin("No such program".into()), "No such program".to_string()),
    ];
    let default = parol6_core::program::builtin::programs(&parol6_core::RobotModel::parol6())[0].name.clone();
    for (last, named) in cases {
        let settings = Settings { last_program: Some(last.clone()), ..Settings::default() };
        write_settings(&path, &settings);
        let mut h = restart(&path, SIZE);
        h.run_steps(5);
        let said: Vec<_> = h.state().notices().iter().filter(|n| n.error && n.text.contains(&named)).collect();
        assert_eq!(said.len(), 1, "{last:?}: one notice naming it: {:?}", h.state().notices());
        assert!(said[0].text.contains("not"), "{last:?}: says why: {}", said[0].text);
        assert!(said[0].text.contains(&format!("started with {default}")), "{}", said[0].text);
        let panel = h.state().program_panel();
        assert_eq!((panel.program().name.as_str(), panel.file()), (default.as_str(), None), "{last:?}");
        assert!(!panel.is_dirty());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Regression: the Cartesian jog's frame, mode and increments were back to World / Hold / 1 mm
/// / 1° at every start.
#[test]
fn the_cartesian_jog_frame_mode_and_increments_survive_a_restart() {
    let (dir, path) = settings_in("jog");
    let mut h = harness_with(with_settings(&path), SIZE);
    h.get_by_label("Tool").click();
    h.run_steps(2);
    h.get_by_label("Step").click();
    h.run_steps(2);
    type_into(&mut h, "Step mm", "2.5");
    type_into(&mut h, "Step angle", "5");
    let jog = h.state().cartesian_jog_panel();
    assert_eq!((jog.frame(), jog.step_mode(), jog.step_increments()), (JogFrame::Tool, true, (2.5, 5.0)));
    until(&mut h, "the jog in the settings file", 10.0, |_| load_settings(Some(&path)).cartesian_jog.step_deg == 5.0);
    drop(h);
    let h = restart(&path, SIZE);
    let jog = h.state().cartesian_jog_panel();
    assert_eq!((jog.frame(), jog.step_mode(), jog.step_increments()), (JogFrame::Tool, true, (2.5, 5.0)));
    // trial 25 m10: Step mode (and its increments) came back without a word
    let said = |h: &Harness<'_, Parol6App>, part: &str| h.state().notices().iter().any(|n| n.text.contains(part));
    assert!(said(&h, "Cartesian jog: Step mode, 2.50 mm and 5.00° per click, as left last time"));

    // an increment out of its range in the file is the default, never 0 or a negative
    let mut s = load_settings(Some(&path));
    s.cartesian_jog.step_mm = -3.0;
    s.cartesian_jog.step_deg = 0.0;
    write_settings(&path, &s);
    let h = restart(&path, SIZE);
    assert_eq!(h.state().cartesian_jog_panel().step_increments(), (1.0, 1.0));
    assert_eq!(h.state().cartesian_jog_panel().frame(), JogFrame::Tool, "the rest is kept");
    // Hold mode comes back quietly
    let mut s = load_settings(Some(&path));
    s.cartesian_jog.step_mode = false;
    write_settings(&path, &s);
    let h = restart(&path, SIZE);
    assert!(!said(&h, "Cartesian jog: Step mode"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Regression: the forward-dynamics form (torque profiles, hold other joints) was empty again
/// at every start.
#[test]
fn the_forward_dynamics_form_survives_a_restart() {
    let (dir, path) = settings_in("torques");
    // the dynamics panel shown, tall enough for the whole form
    let shown = Settings { show_dynamics: true, lower_panel_height_pt: 1200.0, ..Settings::default() };
    write_settings(&path, &shown);
    let size = egui::vec2(1400.0, 1500.0);
    let mut h = harness_with(with_settings(&path), size);
    type_into(&mut h, "J1 torque", "0.2");
    type_into(&mut h, "Run time", "1.5");
    h.get_by_label("hold other joints").click();
    h.run_steps(2);
    let form = h.state().dynamics_panel().form.clone();
    assert_eq!((form.rows[0].torque_nm, form.duration_s, form.hold_others), (0.2, 1.5, true));
    until(&mut h, "the form in the settings file", 10.0, |_| {
        load_settings(Some(&path)).torque_form.is_some_and(|f| f.hold_others && f.duration_s == 1.5)
    });
    drop(h);
    let h = restart(&path, size);
    let again = &h.state().dynamics_panel().form;
    assert_eq!((&again.rows, again.duration_s, again.hold_others), (&form.rows, 1.5, true));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A settings file written before these keys existed loads, with their defaults.
#[test]
fn an_old_settings_file_without_the_new_keys_loads() {
    let (dir, path) = settings_in("old");
    std::fs::write(
        &path,
        r#"{ "unit": "Rad", "show_left": true, "speed_fraction": 0.3, "recent_programs": ["/tmp/a.json"],
             "lower_panel_height_pt": 300.0, "lower_tab": "Plots" }"#,
    )
    .unwrap();
    let s = load_settings(Some(&path));
    assert_eq!((s.unit, s.speed_fraction), (parol6_app::panels::AngleUnit::Rad, 0.3), "the old keys are read");
    assert_eq!(s.last_program, None);
    assert_eq!(s.cartesian_jog, Default::default());
    assert_eq!((s.torque_form, s.camera), (None, None));
    let h = restart(&path, SIZE);
    assert_eq!(h.state().settings().unit, parol6_app::panels::AngleUnit::Rad);
    assert!(h.state().notices().iter().all(|n| !n.error), "{:?}", h.state().notices());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The window with a 3D view drawn on the software rasterizer (or a GPU); `None` where no
/// adapter exists outside CI (the test is then skipped, saying so).
fn renderer(test: &str) -> Option<parol6_app::viewport::OffscreenRenderer> {
    use parol6_app::viewport::{OffscreenRenderer, ViewportError};
    match OffscreenRenderer::new(&parol6_core::RobotModel::parol6(), 64, 64) {
        Ok(r) => Some(r),
        Err(e @ (ViewportError::NoAdapter(_) | ViewportError::Device(_))) => {
            assert!(std::env::var_os("CI").is_none(), "{test}: no usable graphics adapter in CI: {e}");
            parol6_tests::skip_notice(&format!("SKIPPED {test}: {e}"));
            None
        }
        Err(e) => panic!("{test}: {e}"),
    }
}

fn window_with_view(path: &Path, rs: &eframe::egui_wgpu::RenderState) -> Harness<'static, Parol6App> {
    let app = Parol6App::new(with_settings(path), Some(rs)).expect("app");
    let mut h = Harness::builder()
        .with_size(SIZE)
        .with_accessibility_check(false)
        .build_ui_state(|ui, app: &mut Parol6App| app.frame(ui), app);
    h.run_steps(3);
    h
}

/// Regression: the camera (orbit target, distance, yaw, pitch) was the default view at every
/// start. A NaN or absurd remembered view gives the default one.
#[test]
fn the_camera_survives_a_restart_and_an_absurd_one_gives_the_default_view() {
    let Some(mut r) = renderer("the_camera_survives_a_restart") else { return };
    let rs = r.egui_render_state();
    let (dir, path) = settings_in("camera");
    let mut h = window_with_view(&path, &rs);
    let before = h.state().view_camera().expect("a 3D view");
    // a left drag over the 3D view orbits, the wheel zooms
    let c = h.state().view_rect().expect("the 3D view laid out").center();
    h.hover_at(c);
    h.run_steps(1);
    h.drag_at(c);
    h.run_steps(1);
    for i in 1..=5 {
        h.hover_at(c + egui::vec2(12.0 * i as f32, 6.0 * i as f32));
        h.run_steps(1);
    }
    h.drop_at(c + egui::vec2(60.0, 30.0));
    h.run_steps(2);
    let after = h.state().view_camera().unwrap();
    assert!((after.yaw_rad - before.yaw_rad).abs() > 0.1, "the drag orbits: {before:?} → {after:?}");
    let kept = CameraSetting::of(&after);
    until(&mut h, "the camera in the settings file", 10.0, |_| load_settings(Some(&path)).camera == Some(kept));
    drop(h);
    let h = window_with_view(&path, &rs);
    assert_eq!(h.state().view_camera(), Some(after), "the same view after the restart");
    drop(h);

    let mut s = load_settings(Some(&path));
    s.unit = parol6_app::panels::AngleUnit::Rad;
    for absurd in [f32::NAN, 1e9, -1.0] {
        s.camera = Some(CameraSetting { distance_m: absurd, ..kept });
        // serde_json writes a NaN as null, which does not read as a number: the view is then
        // left out, as an absurd one is, and the other settings are kept
        write_settings(&path, &s);
        let h = window_with_view(&path, &rs);
        assert_eq!(h.state().view_camera(), Some(before), "distance {absurd}: the default view");
        assert_eq!(h.state().settings().unit, parol6_app::panels::AngleUnit::Rad, "distance {absurd}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

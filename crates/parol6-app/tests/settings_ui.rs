//! Settings survive a crash: they are written (atomically, off the UI thread) once they change,
//! not only when the window closes the normal way.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::kittest::Queryable;
use ui_support::{harness_with, launch_options, until};

use parol6_app::app::{LaunchOptions, load_settings};
use parol6_app::panels::AngleUnit;

/// Regression (issue 32): settings were written only on Ctrl+Q, so a crash lost them.
#[test]
fn a_changed_setting_is_on_disk_before_the_window_closes() {
    let dir = std::env::temp_dir().join(format!("parol6-settings-ui-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("settings.json");
    let opts = LaunchOptions { settings_path: Some(path.clone()), ..launch_options() };
    let mut h = harness_with(opts, egui::vec2(1280.0, 800.0));
    assert_eq!(load_settings(Some(&path)).unit, AngleUnit::Deg, "a fresh start: degrees");
    h.get_by_label("Units").click();
    h.run_steps(2);
    h.get_by_label("Radians").click();
    // written about half a second after the last change, while the window stays open
    until(&mut h, "the settings on disk", 10.0, |_| load_settings(Some(&path)).unit == AngleUnit::Rad);
    // the window is dropped without its exit handler (as a crash would end it)
    drop(h);
    assert_eq!(load_settings(Some(&path)).unit, AngleUnit::Rad);
    let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers, [std::ffi::OsString::from("settings.json")], "no temporary file left");
    std::fs::remove_dir_all(&dir).unwrap();
}

//! The smallest window the README names, 1024×700 (hand trial under Xvfb): controls that ran
//! under a neighbouring panel or past the window's edge, out of reach, are now in view.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::kittest::Queryable;

/// The plots' export row ran under the right panel at 1024 px: "CSV of the visible window" was
/// cut and "SVG of the plots" could not be reached. The row wraps now.
#[test]
fn the_plots_export_buttons_are_left_of_the_right_panel_at_1024_px() {
    let mut h = ui_support::app_harness(egui::vec2(1024.0, 700.0));
    h.state_mut().settings_mut().show_plots = true;
    h.run_steps(4);
    let right_panel_x = h.get_by_label("TCP").rect().min.x;
    for label in ["CSV of the visible window", "SVG of the plots"] {
        let r = h.get_by_label(label).rect();
        assert!(r.max.x <= right_panel_x, "{label} at {r:?} runs under the right panel (from x = {right_panel_x})");
    }
}

/// trial6: with a recording open at 1024 px, the timeline's first row (the file, its robot,
/// sample count, length and program) was wider than the panel: "Close recording", the scrub
/// bar's right end and the plots' controls under it ran past the panel's edge, under the right
/// panel. The row's text is cut to fit now, and Close stays at its right end.
#[test]
fn the_replay_timeline_and_the_plots_under_it_stay_left_of_the_right_panel_at_1024_px() {
    let model = parol6_core::RobotModel::parol6();
    let dir = std::env::temp_dir().join(format!("parol6-narrow-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("run.mcap");
    let bytes = parol6_app::cli::bench_replay::synthetic_recording(&model, 0.5, 50.0).expect("recording");
    std::fs::write(&path, bytes).expect("write");

    let mut h = ui_support::app_harness(egui::vec2(1024.0, 700.0));
    h.state_mut().settings_mut().show_plots = true;
    h.run_steps(2);
    ui_support::open_recording(&mut h, &path);
    ui_support::until(&mut h, "the replay", 10.0, |h| ui_support::has_label(h, "Replay: run.mcap"));
    h.key_press(egui::Key::Escape);
    h.run_steps(4);
    let right_panel_x = h.get_by_label("TCP").rect().min.x;
    for label in ["Close recording", "SVG of the plots", "TCP rpy"] {
        let r = h.get_by_label(label).rect();
        assert!(r.max.x <= right_panel_x, "{label} at {r:?} runs under the right panel (from x = {right_panel_x})");
    }
    h.get_by_label("Close recording").click();
    ui_support::until(&mut h, "replay closed", 5.0, |h| h.state().replay().is_none());
    std::fs::remove_dir_all(&dir).expect("remove the temporary folder");
}

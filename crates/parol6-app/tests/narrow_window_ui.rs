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

//! The smallest window the README names, 1024×700 (hand trial under Xvfb): controls that ran
//! under a neighbouring panel or past the window's edge, out of reach, are now in view.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::kittest::{NodeT, Queryable};

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

/// ui6's screenshots: with radians chosen, the right column's content was wider than the column
/// (the TCP read-out, the jog speed "40.8 mm/s, 0.3622 rad/s", …), so the column grew to the
/// left under the 3D view, which painted over its first 20 px ("TCP", "Frame", "Speed"). In
/// either unit, every widget of the right column lies inside its 320 pt (in the test harness the
/// same overflow runs past the window's right edge instead).
#[test]
fn the_right_column_keeps_its_width_in_degrees_and_in_radians() {
    use parol6_app::panels::AngleUnit;
    for size in [egui::vec2(1024.0, 700.0), egui::vec2(1280.0, 800.0), egui::vec2(1600.0, 1000.0)] {
        for unit in [AngleUnit::Deg, AngleUnit::Rad] {
            let mut h = ui_support::app_harness(size);
            h.state_mut().settings_mut().unit = unit;
            // the Cartesian target's configurations come from a worker a few frames later
            ui_support::until(&mut h, "the configurations", 10.0, |h| {
                h.query_by_label_contains("(current joints)").is_some()
            });
            h.run_steps(2);
            let column_x = size.x - parol6_app::app::RIGHT_PANEL_WIDTH;
            let tcp = h.get_by_label("TCP").rect();
            let wide: Vec<String> = h
                .query_all(
                    egui_kittest::kittest::by()
                        .predicate(|n| n.role() != egui::accesskit::Role::Window && n.bounding_box().is_some()),
                )
                // the column's widgets: right of the 3D view's middle, between the menu bar and the status bar
                .filter(|n| n.rect().top() >= tcp.top() - 1.0 && n.rect().bottom() < size.y - 30.0)
                .filter(|n| n.rect().center().x > column_x - 40.0)
                .filter(|n| n.rect().left() < column_x - 0.5 || n.rect().right() > size.x - 1.0)
                .map(|n| format!("{:?} at {:?}", n.accesskit_node().label(), n.rect()))
                .collect();
            assert!(
                tcp.min.x >= column_x && wide.is_empty(),
                "{unit:?} at {size:?}: the column starts at x = {column_x}, its heading at {tcp:?}; over its edges: {wide:?}"
            );
        }
    }
}

//! A 1 000-step program in the window (issue 32's acceptance: nothing a user does blocks the
//! window for more than 50 ms; `parol6 bench ui-actions` measures it): the point table lays
//! out only the rows in view, and F5 does not write the whole program as text.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use ui_support::{app_harness, has_label};

/// The window with a generated 1 000-step G-code raster open.
fn with_long_program(tag: &str) -> (egui_kittest::Harness<'static, parol6_app::app::Parol6App>, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("parol6-long-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("raster.gcode");
    parol6_app::cli::bench_program::write_raster_gcode(&file, 1005, None).expect("write");
    let mut h = app_harness(egui::vec2(1280.0, 900.0));
    ui_support::open_program_file(&mut h, &file);
    assert!(h.state().program_panel().program().steps.len() >= 1000, "the long program is open");
    (h, dir)
}

/// The table of 1 000 steps laid out every row in every frame (170 ms a frame on this host);
/// now only the rows in view are, and scrolling brings the others.
#[test]
fn the_point_table_of_a_long_program_lays_out_only_the_rows_in_view() {
    let (mut h, dir) = with_long_program("table");
    h.state_mut().program_panel_mut().table_open = true;
    h.run_steps(3);
    assert!(has_label(&h, "table 2 X"), "the first rows are shown");
    assert!(!has_label(&h, "table 900 X"), "a row far out of view is not laid out");
    let _ = std::fs::remove_dir_all(&dir);
}

/// F5 kept the run command's `Debug` text (the whole program and its check, megabytes) in
/// `moves_sent`: 50 ms of the frame. Now a run is kept by its name and length.
#[test]
fn running_a_long_program_keeps_a_short_record_of_the_command() {
    let (mut h, dir) = with_long_program("run");
    h.key_press(egui::Key::F5);
    h.run_steps(3);
    let last = h.state().moves_sent().last().expect("the run was sent").to_string();
    assert!(last.starts_with("RunProgram"), "{last}");
    assert!(last.len() < 400, "a short record: {} bytes", last.len());
    let _ = std::fs::remove_dir_all(&dir);
}

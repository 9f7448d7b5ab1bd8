//! Measurement panel, driven headless through egui's kittest harness on the full app: the
//! default cube passes the pre-flight; an unreachable cube is refused by the pre-flight (the
//! pose named) and Run starts nothing; a reachable one runs from a pointer click on Run, shows
//! progress and stops on Abort.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ui_support::{app_harness, until};

use parol6_app::app::Parol6App;

fn count(h: &Harness<'_, Parol6App>, text: &str) -> usize {
    h.query_all_by_label_contains(text).count()
}

#[test]
fn the_pre_flight_passes_the_default_cube_and_names_an_unreachable_pose() {
    let mut h = app_harness(egui::vec2(1280.0, 2400.0));
    until(&mut h, "the pre-flight", 10.0, |h| count(h, "pre-flight: every pose reachable") == 1);
    assert_eq!(count(&h, "Measurement (ISO 9283)"), 1);
    h.state_mut().measure_panel().plan.cube.center_mm = [0.0, 330.0, 250.0];
    h.state_mut().measure_panel().plan.cube.edge_mm = 300.0;
    until(&mut h, "the refusal", 10.0, |h| count(h, "pre-flight refuses P") == 1);
    // Run is disabled: a click starts nothing
    let before = h.state().backend().state().commands_applied;
    h.get_by_label("Run test").click();
    h.run_steps(5);
    assert!(!h.state_mut().measure_panel().running(), "no run started");
    assert_eq!(h.state().backend().state().commands_applied, before, "nothing moved");
}

#[test]
fn a_measurement_runs_from_the_panel_with_progress_and_abort() {
    let mut h = app_harness(egui::vec2(1280.0, 2400.0));
    until(&mut h, "the pre-flight", 10.0, |h| count(h, "pre-flight: every pose reachable") == 1);
    h.state_mut().measure_panel().plan.cycles = 2;
    h.run_steps(2);
    // the right panel keeps its width: nothing of it lies beyond the window
    let right = h.get_by_label("Run test").rect();
    assert!(right.max.x <= 1280.0, "the Run button lies inside the window: {right:?}");
    h.get_by_label("Run test").click();
    h.run_steps(2);
    let errors: Vec<String> = h.state().notices().iter().filter(|n| n.error).map(|n| n.text.clone()).collect();
    assert!(errors.is_empty(), "{errors:?}");
    assert!(h.state_mut().measure_panel().running(), "the run started (a pointer click, as a user would)");
    until(&mut h, "progress", 20.0, |h| count(h, "% ") >= 1 && h.state().backend().state().moving);
    h.get_by_label("Abort").click();
    until(&mut h, "the abort", 10.0, |h| !h.state().backend().state().moving);
    h.run_steps(5);
    assert!(!h.state_mut().measure_panel().running(), "aborted");
}

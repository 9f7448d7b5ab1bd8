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
    assert!(!h.state().measurement().running(), "no run started");
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
    assert!(h.state().measurement().running(), "the run started (a pointer click, as a user would)");
    until(&mut h, "progress", 20.0, |h| count(h, "% ") >= 1 && h.state().backend().state().moving);
    h.get_by_label("Abort").click();
    until(&mut h, "the abort", 10.0, |h| !h.state().backend().state().moving);
    h.run_steps(5);
    assert!(!h.state().measurement().running(), "aborted");
}

/// The rectangles a stale layout would move: the 3D view's (its placeholder here), the
/// Measurement heading and the Cartesian jog's +X in the right column.
fn layout_rects(h: &Harness<'_, Parol6App>) -> Vec<(&'static str, egui::Rect)> {
    ["3D view unavailable", "Measurement (ISO 9283)", "+X"]
        .into_iter()
        .filter_map(|l| h.query_by_label_contains(l).map(|n| (l, n.rect())))
        .collect()
}

/// Issue 32 major 4: after a GUI ISO 9283 test the figures table was wider than the right
/// column; the column then gave the width it took beyond its edge to the 3D view and the plots,
/// which painted over its left side (jog buttons, the Measurement title, the table). After a
/// finished test the window is laid out as a fresh one of the same size draws it.
#[test]
fn after_an_iso_test_the_window_is_laid_out_as_a_fresh_full_paint() {
    let size = egui::vec2(1280.0, 2400.0);
    let mut fresh = app_harness(size);
    fresh.run_steps(3);
    let want = layout_rects(&fresh);
    assert_eq!(want.len(), 3, "{want:?}");
    drop(fresh);

    let mut h = app_harness(size);
    until(&mut h, "the pre-flight", 10.0, |h| count(h, "pre-flight: every pose reachable") == 1);
    h.state_mut().measure_panel().plan.cycles = 2;
    h.run_steps(2);
    until(&mut h, "the pre-flight", 10.0, |h| count(h, "pre-flight: every pose reachable") == 1);
    h.get_by_label("Run test").click();
    h.run_steps(2);
    assert!(h.state().measurement().running(), "the test started");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while h.state().measurement().running() {
        assert!(std::time::Instant::now() < deadline, "timed out waiting for the test to finish");
        h.run_steps(1);
        std::thread::sleep(std::time::Duration::from_millis(15));
    }
    h.run_steps(5);
    assert!(count(&h, "AD_p") >= 1 && count(&h, "AP_p mm") == 1, "the figures are shown");
    let got = layout_rects(&h);
    assert_eq!(got.len(), 3, "{got:?}");
    // the 3D view and +X exactly; the heading across (the panels above it may change height)
    for ((l, a), (_, b)) in want.iter().zip(&got) {
        let same = if *l == "Measurement (ISO 9283)" {
            (a.min.x - b.min.x).abs() < 0.5 && (a.max.x - b.max.x).abs() < 0.5
        } else {
            (a.min - b.min).length() < 0.5 && (a.max - b.max).length() < 0.5
        };
        assert!(same, "{l}: fresh {a:?}, after {b:?}");
    }

    // a failed save (no such folder: a long message) then a saved one move nothing below them
    let below = |h: &Harness<'_, Parol6App>| h.get_by_label_contains("AP_p mm").rect();
    let before = below(&h);
    h.state_mut().measure_panel().report_path = "/no such folder/of reports/anywhere at all/r.html".into();
    h.get_by_label("Save report").click();
    h.run_steps(2);
    assert_eq!(below(&h), before, "a two-line error moved the figures under the pointer");

    // Save report over yesterday's report: the first click says it exists, the second replaces
    let dir = std::env::temp_dir().join(format!("parol6-measure-ui-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let report = dir.join("yesterday.html");
    std::fs::write(&report, "<p>yesterday's figures</p>").unwrap();
    h.state_mut().measure_panel().report_path = report.display().to_string();
    h.get_by_label("Save report").click();
    h.run_steps(2);
    assert_eq!(std::fs::read_to_string(&report).unwrap(), "<p>yesterday's figures</p>", "replaced unasked");
    assert_eq!(count(&h, "yesterday.html exists: Save report again replaces it"), 1);
    h.get_by_label("Save report").click();
    h.run_steps(2);
    assert!(std::fs::read_to_string(&report).unwrap().contains("<svg"), "the second click saves the report");
    assert_eq!(below(&h), before, "a saved report's line moved the figures under the pointer");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// trial6: the set-up's fields were drag values, which clamp what is typed without a word:
/// Cycles `1` became 2. Now a value outside the range is refused with it and the field keeps
/// its value; units and a decimal comma are taken as in every number field.
#[test]
fn the_set_up_refuses_a_typed_value_outside_its_range_and_converts_units() {
    let mut h = app_harness(egui::vec2(1280.0, 2400.0));
    until(&mut h, "the pre-flight", 10.0, |h| count(h, "pre-flight: every pose reachable") == 1);
    let cycles = h.state_mut().measure_panel().plan.cycles;
    ui_support::type_into(&mut h, "cycles", "1");
    assert_eq!(h.state_mut().measure_panel().plan.cycles, cycles, "cycles 1 was not refused");
    assert_eq!(count(&h, "cycles: 1 is outside 2–1000"), 1, "the refusal names the range");
    ui_support::type_into(&mut h, "cycles", "2,5");
    assert_eq!(count(&h, "cycles: 2.5 is not a whole number"), 1);
    ui_support::type_into(&mut h, "cycles", "4");
    assert_eq!(h.state_mut().measure_panel().plan.cycles, 4);
    ui_support::type_into(&mut h, "edge", "0,05m");
    assert!((h.state_mut().measure_panel().plan.cube.edge_mm - 50.0).abs() < 1e-9, "0,05m is 50 mm");
    ui_support::type_into(&mut h, "edge", "900");
    assert!((h.state_mut().measure_panel().plan.cube.edge_mm - 50.0).abs() < 1e-9);
    assert_eq!(count(&h, "edge: 900 mm is outside 1–500 mm"), 1);
    ui_support::type_into(&mut h, "tool roll", "0.5rad");
    let roll = h.state_mut().measure_panel().plan.cube.orientation_rpy_deg[0];
    assert!((roll - 0.5_f64.to_degrees()).abs() < 0.01, "0.5rad in degrees: {roll}");
}

/// trial8: during an ISO 9283 test a Cartesian jog (D held with the 3D view focused) moved the
/// arm 41 mm off the test's pose in a real window, and the test went on measuring. While a test
/// drives the arm, a manual motion is refused with a notice now, and nothing of it is sent.
#[test]
fn a_manual_motion_during_a_measurement_is_refused() {
    let mut h = app_harness(egui::vec2(1280.0, 2400.0));
    until(&mut h, "the pre-flight", 10.0, |h| count(h, "pre-flight: every pose reachable") == 1);
    h.state_mut().measure_panel().plan.cycles = 2;
    h.run_steps(2);
    h.get_by_label("Run test").click();
    until(&mut h, "progress", 20.0, |h| count(h, "% ") >= 1 && h.state().backend().state().moving);
    let before = h.state().moves_sent().count();
    let j4_deg = h.state().backend().state().commanded.q[3].to_degrees() + 20.0;
    ui_support::type_into(&mut h, "J4 target", &format!("{j4_deg:.2}"));
    h.get_by_label("HOME").click();
    h.run_steps(2);
    let sent: Vec<String> = h.state().moves_sent().skip(before).map(str::to_string).collect();
    assert!(sent.is_empty(), "manual motions reached the arm during the test: {sent:?}");
    assert!(
        h.state().notices().iter().any(|n| n.error && n.text.contains("Abort it (or STOP) first")),
        "no refusal: {:?}",
        h.state().notices()
    );
    assert!(h.state().measurement().running(), "the test goes on");
    h.get_by_label("Abort").click();
    until(&mut h, "the abort", 10.0, |h| !h.state().backend().state().moving);
}

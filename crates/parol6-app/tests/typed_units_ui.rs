//! A unit typed after a number is converted or refused, never dropped (issue 32, major 2):
//! typed into the real joint fields of the whole app, driven headless through egui's kittest.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::kittest::Queryable;
use ui_support::{app_harness, type_into};

#[test]
fn a_unit_typed_into_a_joint_field_is_converted_or_refused() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    // degrees shown: 0.5 rad is 28.65°, not 0.50°
    type_into(&mut h, "J1 target", "0.5rad");
    assert_eq!(h.get_by_label("J1 target").value().as_deref(), Some("28.65"));
    let last = h.state().moves_sent().last().unwrap().to_string();
    assert!(last.contains("MoveJoints") && last.contains("goal_rad: [0.5,"), "{last}");
    // a length is not an angle: refused, naming the field and what it takes; nothing sent
    let sent = h.state().moves_sent().count();
    type_into(&mut h, "J2 target", "10mm");
    h.run_steps(2);
    let said: Vec<String> = h.state().notices().iter().map(|n| n.text.clone()).collect();
    assert!(
        said.iter().any(|t| t.starts_with("J2: \"10mm\": mm does not fit this field") && t.contains("°, deg or rad")),
        "refused, naming the field and the units it takes: {said:?}"
    );
    assert_eq!(h.state().moves_sent().count(), sent, "nothing moves");
    // degrees typed with a comma and a unit
    type_into(&mut h, "J4 target", "-12,5 deg");
    assert_eq!(h.get_by_label("J4 target").value().as_deref(), Some("-12.50"));
}

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

/// The value box of a slider, the one on the row of the label `row` (e.g. "Speed ×").
fn slider_box(h: &egui_kittest::Harness<'_, parol6_app::app::Parol6App>, row: &str) -> egui::Rect {
    let label = h.get_by_label(row).rect();
    h.query_all_by_role(egui::accesskit::Role::SpinButton)
        .map(|n| n.rect())
        .find(|r| r.center().y >= label.top() - 4.0 && r.center().y <= label.bottom() + 4.0 && r.left() > label.right())
        .unwrap_or_else(|| panic!("no value box on the row of {row}"))
}

/// Types `text` into the value box of the slider on the row of `row`, then Enter.
fn type_into_slider(h: &mut egui_kittest::Harness<'_, parol6_app::app::Parol6App>, row: &str, text: &str) {
    let at = slider_box(h, row).center();
    h.hover_at(at);
    for pressed in [true, false] {
        let modifiers = egui::Modifiers::NONE;
        h.event(egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed, modifiers });
        h.run_steps(1);
    }
    h.run_steps(1);
    h.event(egui::Event::Text(text.to_string()));
    h.run_steps(1);
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
}

/// The last trial: the program's "Speed ×" box read "0,5" as 0.05 (egui's box read every
/// keystroke and clamped "0" to the minimum), and clamped "1e9" and "abc" without a word. A
/// slider's box now reads what is typed as the fields do, once committed, and refuses a value
/// outside its range or no number, saying so, with the value kept.
#[test]
fn a_value_typed_into_a_sliders_box_is_read_as_a_field_reads_it() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    h.run_steps(2);
    type_into_slider(&mut h, "Speed ×", "0,5");
    assert_eq!(h.state().program_panel().speed_override, 0.5, "a comma is a decimal mark");
    for (typed, said) in [("1e9", "outside 0.05–1"), ("abc", "is not a number")] {
        type_into_slider(&mut h, "Speed ×", typed);
        assert_eq!(h.state().program_panel().speed_override, 0.5, "{typed}: the value stays");
        let notices: Vec<String> = h.state().notices().iter().map(|n| n.text.clone()).collect();
        assert!(
            notices.iter().any(|t| t.starts_with("Speed ×") && t.contains(said) && t.contains("it stays 0.50")),
            "{typed}: refused with a word: {notices:?}"
        );
    }
}

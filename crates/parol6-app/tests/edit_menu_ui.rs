//! The menu bar's Edit menu (issue 32, minor): Undo / Redo with the keys of the shortcut table,
//! teach / duplicate / delete / move a step and the point table, each greyed with a reason when it
//! cannot act; no entry moves the arm.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use ui_support::app_harness;

use parol6_app::app::Parol6App;

fn steps(h: &Harness<'_, Parol6App>) -> usize {
    h.state().program_panel().program().steps.len()
}

/// Opens the Edit menu.
fn open_edit(h: &mut Harness<'_, Parol6App>) {
    h.get_by_label("Edit").click();
    h.run_steps(2);
}

/// The Edit menu's entry `label` (its name holds the keys too; the program panel's toolbar has
/// buttons of the same name: the entry is the one that was not there before the menu opened).
fn entry<'h>(h: &'h Harness<'_, Parol6App>, label: &'h str, outside: &[egui::Rect]) -> egui_kittest::Node<'h> {
    h.query_all_by_label_contains(label)
        .find(|n| !outside.contains(&n.rect()))
        .unwrap_or_else(|| panic!("the Edit menu has no entry {label:?}"))
}

#[test]
fn the_edit_menu_edits_the_program_greys_what_cannot_act_and_moves_nothing() {
    let mut h = app_harness(egui::vec2(1280.0, 800.0));
    // the toolbar's buttons of the same names, before the menu opens
    let toolbar: Vec<egui::Rect> = ["Undo", "Redo", "Teach joints", "Point table"]
        .iter()
        .flat_map(|l| h.query_all_by_label_contains(l).map(|n| n.rect()))
        .collect();
    let n = steps(&h);
    open_edit(&mut h);
    assert!(h.query_by_label("File").is_some() && h.query_by_label("View").is_some());
    for (label, greyed) in
        [("Undo", true), ("Redo", true), ("Delete step", true), ("Move step up", true), ("Teach joints", false)]
    {
        assert_eq!(entry(&h, label, &toolbar).accesskit_node().is_disabled(), greyed, "{label}");
    }
    assert!(
        h.query_all_by_label_contains("Ctrl+Z").next().is_some() || cfg!(target_os = "macos"),
        "Undo shows its key from the shortcut table"
    );
    h.get_by_label("Edit").click();
    h.run_steps(2);

    h.state_mut().program_panel_mut().select_step(Some(1));
    h.run_steps(1);
    open_edit(&mut h);
    entry(&h, "Delete step", &toolbar).click();
    h.run_steps(2);
    assert_eq!(steps(&h), n - 1, "Edit → Delete step");
    assert!(h.query_all_by_label_contains("Move step down").next().is_none(), "the menu closes after an action");
    open_edit(&mut h);
    entry(&h, "Undo", &toolbar).click();
    h.run_steps(2);
    assert_eq!(steps(&h), n, "Edit → Undo");
    open_edit(&mut h);
    entry(&h, "Redo", &toolbar).click();
    h.run_steps(2);
    assert_eq!(steps(&h), n - 1, "Edit → Redo");
    open_edit(&mut h);
    entry(&h, "Teach joints", &toolbar).click();
    h.run_steps(2);
    assert_eq!(steps(&h), n, "Edit → Teach joints adds a step");
    open_edit(&mut h);
    entry(&h, "Point table", &toolbar).click();
    h.run_steps(2);
    assert!(h.state().program_panel().table_open, "Edit → Point table opens it");
    assert_eq!(
        h.state().moves_sent().count(),
        0,
        "no Edit entry moved the arm: {:?}",
        h.state().moves_sent().collect::<Vec<_>>()
    );
}

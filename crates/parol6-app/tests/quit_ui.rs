//! Ctrl+Q or closing the window with unsaved program edits asks first (issue 32, major 3):
//! the question names the program and its file and offers Save, Discard and Cancel.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui::{self, Key, Modifiers, ViewportCommand, ViewportId};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use parol6_app::app::Parol6App;

/// The app with the built-in program opened from `path`, then one step taught (unsaved).
fn edited(path: &std::path::Path) -> Harness<'static, Parol6App> {
    let mut h = ui_support::app_harness(egui::vec2(1280.0, 1400.0));
    ui_support::reopen_program_from(&mut h, path);
    h.get_by_label("Teach pose").click();
    h.run_steps(2);
    assert!(h.state().program_panel().is_dirty());
    h
}

/// True when the last frame told the window to close.
fn closes(h: &Harness<'_, Parol6App>) -> bool {
    h.output().viewport_output.get(&ViewportId::ROOT).is_some_and(|v| v.commands.contains(&ViewportCommand::Close))
}

fn ctrl_q(h: &mut Harness<'_, Parol6App>) {
    let ctrl = Modifiers::CTRL | Modifiers::COMMAND;
    h.event(egui::Event::ModifiersChanged(ctrl));
    h.event(egui::Event::Key { key: Key::Q, pressed: true, modifiers: ctrl, repeat: false, physical_key: None });
    h.event(egui::Event::Key { key: Key::Q, pressed: false, modifiers: ctrl, repeat: false, physical_key: None });
    h.event(egui::Event::ModifiersChanged(Modifiers::NONE));
    h.run_steps(1);
}

#[test]
fn quitting_with_unsaved_edits_asks_save_discard_or_cancel() {
    let dir = std::env::temp_dir().join(format!("parol6-quit-ui-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("edited.json");
    let mut h = edited(&path);
    let name = h.state().program_panel().program().name.clone();

    // Ctrl+Q asks, naming the program and the file; nothing closes
    ctrl_q(&mut h);
    assert!(!closes(&h), "Ctrl+Q closed the window over unsaved edits");
    h.run_steps(1);
    assert!(h.state().quit_prompt_open(), "no question");
    let question = format!("The program \"{name}\" (file {}) has unsaved edits", path.display());
    assert!(h.query_by_label_contains(&question).is_some(), "the question names the program and file");
    for b in ["Save and quit", "Discard and quit", "Cancel"] {
        assert!(h.query_all_by_label(b).next().is_some(), "offers {b}");
    }
    // Cancel: keep working
    h.get_by_label("Cancel").click();
    h.run_steps(1);
    assert!(!closes(&h) && !h.state().quit_prompt_open());
    h.run_steps(1);

    // the window's close button asks too (the close is cancelled)
    h.input_mut().viewports.entry(ViewportId::ROOT).or_default().events.push(egui::ViewportEvent::Close);
    h.run_steps(1);
    let cancelled = h.output().viewport_output[&ViewportId::ROOT].commands.contains(&ViewportCommand::CancelClose);
    assert!(cancelled, "the close went through");
    h.run_steps(1);
    assert!(h.state().quit_prompt_open());

    // Save: written, then the window closes
    let on_disk = std::fs::read_to_string(&path).unwrap();
    h.get_by_label("Save and quit").click();
    h.run_steps(1);
    assert!(closes(&h), "Save then quit");
    assert_ne!(std::fs::read_to_string(&path).unwrap(), on_disk, "the taught step was saved");
    assert!(!h.state().program_panel().is_dirty());
}

#[test]
fn discard_quits_without_saving_and_a_clean_program_is_not_asked_about() {
    let dir = std::env::temp_dir().join(format!("parol6-quit-ui-d-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("edited.json");
    let mut h = edited(&path);
    let on_disk = std::fs::read_to_string(&path).unwrap();
    ctrl_q(&mut h);
    h.run_steps(1);
    h.get_by_label("Discard and quit").click();
    h.run_steps(1);
    assert!(closes(&h), "Discard quits");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), on_disk, "nothing written");

    let mut clean = ui_support::app_harness(egui::vec2(1280.0, 1400.0));
    ctrl_q(&mut clean);
    assert!(!clean.state().quit_prompt_open(), "no edits: nothing to ask");
}

/// Regression (issue 32, minor): the File menu had no Quit. It asks over unsaved edits as
/// Ctrl+Q does.
#[test]
fn quit_in_the_file_menu_asks_as_ctrl_q_does() {
    let dir = std::env::temp_dir().join(format!("parol6-quit-ui-m-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = edited(&dir.join("edited.json"));
    h.query_all_by_label("File").next().expect("the File menu").click();
    h.run_steps(2);
    h.get_by_label("Quit (Ctrl+Q)").click();
    h.run_steps(2);
    assert!(!closes(&h) && h.state().quit_prompt_open(), "asks first");
    h.run_steps(2);
    h.get_by_label("Discard and quit").click();
    h.run_steps(1);
    assert!(closes(&h), "then quits");
}

/// Trial11 (issue 32, safety): while the quit question was open (Ctrl+Q over unsaved edits, a
/// program running) its backdrop took the click on E-STOP: the question closed, the drives stayed
/// on and the arm went on moving. STOP and E-STOP now act on the first click above a question.
#[test]
fn stop_and_estop_act_on_the_first_click_while_the_quit_question_is_open() {
    let dir = std::env::temp_dir().join(format!("parol6-quit-estop-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = edited(&dir.join("edited.json"));
    ctrl_q(&mut h);
    h.run_steps(2);
    assert!(h.state().quit_prompt_open(), "no question");
    // the pointer presses wherever the button is drawn (under the question, or above it)
    h.query_all_by_label("STOP").next().expect("STOP").click();
    h.run_steps(2);
    assert!(h.state().quit_prompt_open(), "the click on STOP only closed the question");
    h.query_all_by_label("E-STOP").next().expect("E-STOP").click();
    ui_support::until(&mut h, "the E-stop latches", 5.0, |h| h.state().estop_latched());
    assert!(h.state().quit_prompt_open(), "the question stays until answered");
    assert!(!closes(&h));
    std::fs::remove_dir_all(&dir).unwrap();
}

//! The keyboard never moves the arm by accident (issue 32, major 1): every shortcut of the one
//! table (`panels::shortcuts::SHORTCUTS`) is pressed with the 3D view focused and with a text
//! field focused, and every key that moves the arm with Ctrl, Alt and Super (Cmd) added; the
//! app's log of commands that set the arm moving must stay empty. Positive controls (a plain
//! jog key, H, F5) show the log does see the keyboard.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui::{self, Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use parol6_app::app::Parol6App;
use parol6_app::panels::shortcuts::{Action, Mods, SHORTCUTS, Trigger};

/// The app with the built-in program opened from a file (so Ctrl+S saves it, no dialog).
fn harness(tag: &str) -> Harness<'static, Parol6App> {
    let mut h = ui_support::app_harness(egui::vec2(1280.0, 1400.0));
    let dir = std::env::temp_dir().join(format!("parol6-keyboard-ui-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    ui_support::reopen_program_from(&mut h, &dir.join("program.json"));
    h
}

fn moves(h: &Harness<'_, Parol6App>) -> Vec<String> {
    h.state().moves_sent().map(str::to_string).collect()
}

/// A key going down (held `frames` frames) and up with `modifiers` held throughout.
fn press(h: &mut Harness<'_, Parol6App>, key: Key, modifiers: Modifiers, frames: usize) {
    h.event(egui::Event::ModifiersChanged(modifiers));
    h.event(egui::Event::Key { key, pressed: true, modifiers, repeat: false, physical_key: None });
    h.run_steps(frames);
    h.event(egui::Event::Key { key, pressed: false, modifiers, repeat: false, physical_key: None });
    h.event(egui::Event::ModifiersChanged(Modifiers::NONE));
    h.run_steps(2);
}

/// Clicks the 3D view (the pointer stays over it; no widget has the keyboard).
fn focus_view(h: &mut Harness<'_, Parol6App>) {
    let at = h.get_by_label_contains("3D view unavailable").rect().center();
    click_at(h, at);
    h.run_steps(1);
}

/// A primary click at `at`, the pointer left there.
fn click_at(h: &mut Harness<'_, Parol6App>, at: egui::Pos2) {
    h.hover_at(at);
    for pressed in [true, false] {
        let modifiers = Modifiers::NONE;
        h.event(egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed, modifiers });
        h.run_steps(1);
    }
}

/// Clicks a plain label on the left column, under the step list (the pointer stays there, off
/// the 3D view; no widget has the keyboard); where it clicked.
fn click_off_the_view(h: &mut Harness<'_, Parol6App>) -> egui::Pos2 {
    let off = h.get_by_label_contains("Click a step to edit").rect().center();
    click_at(h, off);
    h.run_steps(2);
    assert!(h.ctx.memory(|m| m.focused().is_none()), "no widget has the keyboard");
    off
}

/// Clicks the J1 target entry (it keeps the keyboard).
fn focus_field(h: &mut Harness<'_, Parol6App>) {
    h.get_by_label("J1 target").click();
    h.run_steps(2);
    assert!(h.ctx.memory(|m| m.focused().is_some()), "the J1 target field has the keyboard");
}

fn mods_of(m: Mods) -> Modifiers {
    match m {
        Mods::Exactly(m) => m,
        Mods::Any => Modifiers::NONE,
    }
}

/// Holds the arm and forgets what was sent.
fn stop_and_clear(h: &mut Harness<'_, Parol6App>) {
    press(h, Key::Escape, Modifiers::NONE, 1);
    ui_support::until(h, "the arm at rest", 10.0, |h| !h.state().backend().state().moving);
}

#[test]
fn no_shortcut_moves_the_arm_with_a_modifier_or_in_a_text_field() {
    let mut h = harness("all");
    // positive controls: the log sees a plain jog key, H and F5 with the view focused
    for (key, what) in [(Key::D, "CartesianJog"), (Key::H, "Home"), (Key::F5, "RunProgram")] {
        focus_view(&mut h);
        let before = moves(&h).len();
        press(&mut h, key, Modifiers::NONE, 3);
        let sent = moves(&h);
        assert!(sent[before..].iter().any(|m| m.contains(what)), "{key:?} sent {:?}", &sent[before..]);
        stop_and_clear(&mut h);
    }

    let start = moves(&h).len();
    let mut tried = 0;
    for s in SHORTCUTS {
        let own = mods_of(s.mods);
        let frames = if s.trigger == Trigger::Hold { 4 } else { 1 };
        // with the 3D view focused, a shortcut that does not move the arm sends no motion
        if !s.action.moves_arm() && s.action != Action::Quit {
            focus_view(&mut h);
            press(&mut h, s.key, own, frames);
            if s.action == Action::ToggleHelp {
                press(&mut h, s.key, own, frames); // closed again: it covers the view
            }
            tried += 1;
            assert_eq!(moves(&h)[start..], [] as [String; 0], "{:?} ({:?}) with the view focused", s.key, s.action);
        }
        // with a text field focused, no shortcut sends motion
        if s.action != Action::Quit {
            focus_field(&mut h);
            press(&mut h, s.key, own, frames);
            if s.action == Action::ToggleHelp {
                press(&mut h, s.key, own, frames);
            }
            tried += 1;
            assert_eq!(moves(&h)[start..], [] as [String; 0], "{:?} {own:?} typed into a field", s.key);
        }
        // a key that moves the arm, with Ctrl, Alt or Super added, sends no motion
        if s.action.moves_arm() {
            for extra in [Modifiers::CTRL | Modifiers::COMMAND, Modifiers::ALT, Modifiers::MAC_CMD] {
                let m = own | extra;
                let bound = SHORTCUTS.iter().any(|t| {
                    t.key == s.key && t.action.moves_arm() && matches!(t.mods, Mods::Exactly(tm) if m.matches_exact(tm))
                });
                if bound {
                    continue; // Ctrl+H is HOME on purpose
                }
                focus_view(&mut h);
                press(&mut h, s.key, m, frames);
                tried += 1;
                assert_eq!(moves(&h)[start..], [] as [String; 0], "{:?} with {m:?}, view focused", s.key);
            }
        }
    }
    assert!(tried > 80, "pressed {tried} chords");
}

/// Ctrl+S saves; S held on after Ctrl is let go must not jog −Y (the defect: it did).
#[test]
fn a_jog_key_pressed_with_ctrl_does_not_jog_when_ctrl_is_let_go_first() {
    let mut h = harness("ctrl");
    focus_view(&mut h);
    for key in [Key::S, Key::A, Key::D] {
        h.event(egui::Event::ModifiersChanged(Modifiers::CTRL | Modifiers::COMMAND));
        let ctrl = Modifiers::CTRL | Modifiers::COMMAND;
        h.event(egui::Event::Key { key, pressed: true, modifiers: ctrl, repeat: false, physical_key: None });
        h.run_steps(2);
        h.event(egui::Event::ModifiersChanged(Modifiers::NONE));
        h.run_steps(4);
        h.event(egui::Event::Key { key, pressed: true, modifiers: Modifiers::NONE, repeat: true, physical_key: None });
        h.run_steps(4);
        h.event(egui::Event::Key {
            key,
            pressed: false,
            modifiers: Modifiers::NONE,
            repeat: false,
            physical_key: None,
        });
        h.run_steps(2);
        assert_eq!(moves(&h), [] as [String; 0], "Ctrl+{key:?}, Ctrl let go first");
    }
    // an open menu holds the jog keys too
    h.get_by_label("View").click();
    h.run_steps(2);
    press(&mut h, Key::D, Modifiers::NONE, 4);
    assert_eq!(moves(&h), [] as [String; 0], "D with the View menu open");
}

/// F1 help is generated from the table: every chord is listed (Ctrl+S, Ctrl+Z, F5, F6, F10 were
/// missing).
#[test]
fn f1_help_lists_every_shortcut_of_the_table() {
    let mut h = ui_support::app_harness(egui::vec2(1280.0, 1400.0));
    h.key_press(Key::F1);
    h.run_steps(3);
    let rows = parol6_app::panels::shortcuts::help_rows();
    for (keys, what, _) in &rows {
        assert!(h.query_by_label(keys).is_some(), "help does not list {keys} ({what})");
    }
    for s in SHORTCUTS {
        let chord = parol6_app::panels::shortcuts::chord(s);
        assert!(rows.iter().any(|r| r.0.split(", ").any(|c| c == chord)), "{chord} is not in the help");
    }
    for chord in ["Ctrl+S", "Ctrl+Z", "Ctrl+Shift+Z", "F5", "F6", "F10", "Esc", "Page Up, Page Down"] {
        let chord = if cfg!(target_os = "macos") { chord.replace("Ctrl", "Cmd") } else { chord.to_string() };
        assert!(h.query_all_by_label_contains(&chord).next().is_some(), "help does not list {chord}");
    }
}

/// Hand trial at 1024×700: the help's key table did not wrap, so its longest rows ran past the
/// window's right edge ("… no panel control type" cut off). Every row's text now ends inside
/// the window.
#[test]
fn f1_help_keys_fit_a_1024_px_window() {
    let width = 1024.0;
    let mut h = ui_support::app_harness(egui::vec2(width, 700.0));
    h.key_press(Key::F1);
    h.run_steps(3);
    let rows = parol6_app::panels::shortcuts::help_rows();
    for (keys, what, scope) in &rows {
        for text in [keys.as_str(), *what, *scope] {
            for node in h.query_all_by_label(text) {
                let r = node.rect();
                assert!(r.max.x <= width, "{text:?} ends at x = {:.0}, past the {width} px window", r.max.x);
            }
        }
    }
}

/// Issue 32 minor: a Shift+letter orientation jog moved the TCP position by 0.11 mm. Shift let go
/// a moment before the letter turned the held key into the letter's linear jog (D: +X), which
/// ran until the letter came up. A held key keeps the chord it went down with: once Shift is let
/// go, it stops, and the TCP stays where it was.
#[test]
fn shift_let_go_before_the_letter_does_not_turn_an_orientation_jog_into_a_linear_one() {
    let mut h = harness("shift");
    focus_view(&mut h);
    let model = parol6_core::RobotModel::parol6();
    let tcp =
        |h: &Harness<'_, Parol6App>| model.tcp_isometry(&h.state().backend().state().commanded.q).translation.vector;
    let before = tcp(&h);
    let hold = |h: &mut Harness<'_, Parol6App>, modifiers: Modifiers, frames: usize| {
        for _ in 0..frames {
            h.event(egui::Event::Key { key: Key::D, pressed: true, modifiers, repeat: true, physical_key: None });
            h.run_steps(1);
            std::thread::sleep(std::time::Duration::from_millis(15));
        }
    };
    h.event(egui::Event::ModifiersChanged(Modifiers::SHIFT));
    h.event(egui::Event::Key {
        key: Key::D,
        pressed: true,
        modifiers: Modifiers::SHIFT,
        repeat: false,
        physical_key: None,
    });
    hold(&mut h, Modifiers::SHIFT, 20);
    // Shift comes up first, D a few frames later
    h.event(egui::Event::ModifiersChanged(Modifiers::NONE));
    hold(&mut h, Modifiers::NONE, 10);
    h.event(egui::Event::Key {
        key: Key::D,
        pressed: false,
        modifiers: Modifiers::NONE,
        repeat: false,
        physical_key: None,
    });
    h.run_steps(2);
    ui_support::until(&mut h, "the arm at rest", 10.0, |h| !h.state().backend().state().moving);
    let sent = moves(&h);
    let moved_mm = (tcp(&h) - before).norm() * 1e3;
    assert!(sent.iter().any(|m| m.contains("Rx")), "Shift+D jogged about X: {sent:?}");
    let linear: Vec<&String> = sent.iter().filter(|m| m.contains(", X,")).collect();
    assert!(linear.is_empty(), "D held on after Shift jogged along X (the TCP moved {moved_mm:.4} mm): {linear:?}");
    assert!(moved_mm < 0.01, "the orientation jog moved the TCP by {moved_mm:.4} mm");
}

/// trial8: in a real window a click on the left column (no text field) and D held jogged the
/// robot +X 41.6 mm: the Cartesian jog keys acted wherever no field had the keyboard, although
/// the guide says "with the 3D view focused", and A D S W Q E are letters of typed text
/// ("0.5rad" typed beside a field jogged −X, then +X). They act only with the pointer over the
/// 3D view now, and a jog key held while the pointer leaves the view stops for good.
#[test]
fn a_cartesian_jog_key_acts_only_with_the_pointer_over_the_3d_view() {
    let mut h = harness("view-only");
    let off = click_off_the_view(&mut h);
    for key in [Key::A, Key::D, Key::S, Key::W, Key::Q, Key::E] {
        press(&mut h, key, Modifiers::NONE, 4);
        press(&mut h, key, Modifiers::SHIFT, 4);
    }
    assert_eq!(moves(&h), [] as [String; 0], "a jog key acted with the pointer off the 3D view");

    // held on the view, then the pointer leaves it: the jog stops and does not come back
    focus_view(&mut h);
    h.event(egui::Event::Key {
        key: Key::D,
        pressed: true,
        modifiers: Modifiers::NONE,
        repeat: false,
        physical_key: None,
    });
    h.run_steps(3);
    assert!(moves(&h).iter().any(|m| m.contains("CartesianJog")), "D on the view jogs: {:?}", moves(&h));
    h.hover_at(off);
    h.run_steps(1);
    let after_leaving = moves(&h).len();
    h.run_steps(3);
    assert_eq!(moves(&h).len(), after_leaving, "the jog went on with the pointer off the view");
    let view = h.get_by_label_contains("3D view unavailable").rect().center();
    h.hover_at(view);
    h.run_steps(3);
    h.event(egui::Event::Key {
        key: Key::D,
        pressed: false,
        modifiers: Modifiers::NONE,
        repeat: false,
        physical_key: None,
    });
    h.run_steps(2);
    assert_eq!(moves(&h).len(), after_leaving, "the jog came back with D still held: {:?}", moves(&h));
}

/// H (HOME) acted wherever no field had the keyboard (the last trial): a path typed beside its
/// field ("/home/…") after a click on a panel sent the arm home. H and Ctrl+H now act as the
/// jog letters do, only with the pointer over the 3D view.
#[test]
fn home_acts_only_with_the_pointer_over_the_3d_view() {
    let mut h = harness("home-view-only");
    click_off_the_view(&mut h);
    press(&mut h, Key::H, Modifiers::NONE, 2);
    press(&mut h, Key::H, Modifiers::COMMAND, 2);
    assert_eq!(moves(&h), [] as [String; 0], "H acted with the pointer off the 3D view");

    focus_view(&mut h);
    press(&mut h, Key::H, Modifiers::NONE, 2);
    assert!(moves(&h).iter().any(|m| m.contains("Home")), "H on the view homes: {:?}", moves(&h));
}

/// Esc while a jog key is still held (its autorepeat going on) stops the jog for good: no jog is
/// sent after it until the key is let go and pressed again (trial15 D1: Esc with Q held over the
/// 3D view, the TCP went on down 100 mm).
#[test]
fn esc_stops_a_held_jog_key_until_the_key_is_pressed_again() {
    let mut h = harness("esc-held");
    focus_view(&mut h);
    let key = |h: &mut Harness<'_, Parol6App>, key, pressed, repeat| {
        h.event(egui::Event::Key { key, pressed, modifiers: Modifiers::NONE, repeat, physical_key: None });
        h.run_steps(1);
    };
    let jogs = |h: &Harness<'_, Parol6App>, from: usize| {
        moves(h)[from..].iter().filter(|m| m.contains("CartesianJog")).count()
    };
    key(&mut h, Key::D, true, false);
    h.run_steps(2);
    assert!(jogs(&h, 0) > 0, "D held over the 3D view jogs: {:?}", moves(&h));
    let at_esc = moves(&h).len();
    h.event(egui::Event::Key {
        key: Key::Escape,
        pressed: true,
        modifiers: Modifiers::NONE,
        repeat: false,
        physical_key: None,
    });
    key(&mut h, Key::Escape, false, false);
    for _ in 0..8 {
        key(&mut h, Key::D, true, true);
    }
    assert_eq!(jogs(&h, at_esc), 0, "a jog was sent after Esc with D still held: {:?}", &moves(&h)[at_esc..]);
    // let go and pressed again, the key jogs again
    key(&mut h, Key::D, false, false);
    let again = moves(&h).len();
    key(&mut h, Key::D, true, false);
    h.run_steps(2);
    assert!(jogs(&h, again) > 0, "D pressed again jogs: {:?}", &moves(&h)[again..]);
}

/// Regression (trial16 n1): Ctrl+D held for 0.8 s made six copies of the selected step, Delete
/// held removed as many: the keys that add or remove a step act once per press, not on the
/// key's repeats. Undo still repeats, as in editors.
#[test]
fn a_held_duplicate_or_delete_key_acts_once() {
    let mut h = harness("repeat");
    h.state_mut().program_panel_mut().select_step(Some(0));
    focus_view(&mut h);
    let count = |h: &Harness<'_, Parol6App>| h.state().program_panel().program().steps.len();
    let held = |h: &mut Harness<'_, Parol6App>, key: Key, modifiers: Modifiers| {
        h.event(egui::Event::ModifiersChanged(modifiers));
        h.event(egui::Event::Key { key, pressed: true, modifiers, repeat: false, physical_key: None });
        h.run_steps(1);
        for _ in 0..5 {
            h.event(egui::Event::Key { key, pressed: true, modifiers, repeat: true, physical_key: None });
            h.run_steps(1);
        }
        h.event(egui::Event::Key { key, pressed: false, modifiers, repeat: false, physical_key: None });
        h.event(egui::Event::ModifiersChanged(Modifiers::NONE));
        h.run_steps(2);
    };
    let before = count(&h);
    held(&mut h, Key::D, Modifiers::CTRL | Modifiers::COMMAND);
    assert_eq!(count(&h), before + 1, "Ctrl+D held: one copy");
    held(&mut h, Key::Delete, Modifiers::NONE);
    assert_eq!(count(&h), before, "Delete held: one step deleted");
    held(&mut h, Key::D, Modifiers::CTRL | Modifiers::COMMAND);
    held(&mut h, Key::D, Modifiers::CTRL | Modifiers::COMMAND);
    held(&mut h, Key::Z, Modifiers::CTRL | Modifiers::COMMAND);
    assert_eq!(count(&h), before, "Ctrl+Z held undid every edit");
}

/// Regression (trial19 D1): W held over the 3D view during a program run was refused with a
/// notice, but F6 (pause) with W still held set the arm jogging +Y at once (149 mm to the
/// workspace's edge in the window): a jog key held while manual motion is refused must be let
/// go and pressed anew once the refusal ends.
#[test]
fn a_jog_key_held_through_a_program_run_does_not_jog_after_pause() {
    use parol6_core::program::runner::RunState;
    let mut h = harness("held-run");
    focus_view(&mut h);
    let state = |h: &Harness<'_, Parol6App>| h.state().program_progress().map(|p| p.state.clone());
    press(&mut h, Key::F5, Modifiers::NONE, 2);
    ui_support::until(&mut h, "the program runs", 10.0, |h| state(h) == Some(RunState::Running));
    let key = |h: &mut Harness<'_, Parol6App>, key, pressed| {
        h.event(egui::Event::Key { key, pressed, modifiers: Modifiers::NONE, repeat: false, physical_key: None });
        h.run_steps(1);
    };
    key(&mut h, Key::W, true);
    h.run_steps(3);
    key(&mut h, Key::F6, true);
    key(&mut h, Key::F6, false);
    ui_support::until(&mut h, "the program paused", 10.0, |h| state(h) == Some(RunState::Paused));
    let at_pause = moves(&h).len();
    for _ in 0..20 {
        h.run_steps(1);
        std::thread::sleep(std::time::Duration::from_millis(15));
    }
    let jogs: Vec<String> = moves(&h)[at_pause..].iter().filter(|m| m.contains("CartesianJog")).cloned().collect();
    assert_eq!(jogs, [] as [String; 0], "W held through the run jogged after F6 (pause)");
    // let go and pressed again, the key jogs
    key(&mut h, Key::W, false);
    let again = moves(&h).len();
    key(&mut h, Key::W, true);
    h.run_steps(2);
    assert!(moves(&h)[again..].iter().any(|m| m.contains("CartesianJog")), "W pressed again jogs");
    key(&mut h, Key::W, false);
}

/// The jog keys are disarmed while a program runs (trial19 D1), the camera's keys are not: an
/// arrow key held over the 3D view still orbits the camera during the run.
#[test]
fn the_camera_keys_stay_held_while_a_program_runs() {
    use parol6_app::panels::shortcuts::held;
    use parol6_core::program::runner::RunState;
    let mut h = harness("orbit-run");
    focus_view(&mut h);
    press(&mut h, Key::F5, Modifiers::NONE, 2);
    ui_support::until(&mut h, "the program runs", 10.0, |h| {
        h.state().program_progress().is_some_and(|p| p.state == RunState::Running)
    });
    h.event(egui::Event::Key {
        key: Key::ArrowLeft,
        pressed: true,
        modifiers: Modifiers::NONE,
        repeat: false,
        physical_key: None,
    });
    h.run_steps(4);
    assert!(h.state().program_running(), "still running");
    assert!(held(&h.ctx, Action::Orbit(-1, 0)), "← held over the view orbits during a run");
    h.event(egui::Event::Key {
        key: Key::ArrowLeft,
        pressed: false,
        modifiers: Modifiers::NONE,
        repeat: false,
        physical_key: None,
    });
    h.run_steps(2);
    press(&mut h, Key::Escape, Modifiers::NONE, 2);
}

/// Trial 20 m: Ctrl+F6 did not pause a running program. Pausing only stops the arm, so F6
/// pauses with any modifier held too (as Esc is STOP with any); F5 with Ctrl still starts nothing.
#[test]
fn f6_pauses_a_running_program_with_a_modifier_held() {
    use parol6_core::program::runner::RunState;
    let mut h = harness("ctrl-f6");
    focus_view(&mut h);
    let state = |h: &Harness<'_, Parol6App>| h.state().program_progress().map(|p| p.state.clone());
    let ctrl = Modifiers::CTRL | Modifiers::COMMAND;
    ui_support::until(&mut h, "the program's check", 60.0, |h| !h.state().program_panel().checking());
    press(&mut h, Key::F5, ctrl, 2);
    h.run_steps(5);
    assert_eq!(moves(&h), [] as [String; 0], "Ctrl+F5 starts nothing");
    for mods in [ctrl, Modifiers::ALT, Modifiers::SHIFT] {
        press(&mut h, Key::F5, Modifiers::NONE, 2);
        ui_support::until(&mut h, "the program runs", 10.0, |h| state(h) == Some(RunState::Running));
        press(&mut h, Key::F6, mods, 2);
        ui_support::until(&mut h, "the program paused", 10.0, |h| state(h) == Some(RunState::Paused));
    }
    stop_and_clear(&mut h);
}

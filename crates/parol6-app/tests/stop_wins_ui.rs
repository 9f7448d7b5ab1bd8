//! Trial 23 and 24 majors, driven headless through egui's kittest harness on the full app: a click on
//! STOP or HOME that takes the keyboard from a joint field holding a typed value does not send
//! that value (STOP and HOME win over the other motions of their frame), the E-STOP button
//! shows the live latch while a recording replays, and a Step over blended lines names the steps
//! that run together. A click on Go over a typed value says the value was not sent.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use ui_support::{app_harness, harness_with, has_label, launch_options, settle, until};

use parol6_app::app::{ConnectTarget, LaunchOptions, Parol6App};

/// A primary click at the centre of the widget labelled `name`, with pointer events (the focus
/// moves as it does for a mouse).
fn click_on(h: &mut Harness<'_, Parol6App>, name: &str) {
    let at = h.get_by_label(name).rect().center();
    ui_support::mouse_click(h, at);
}

/// Types `text` into the J1 target field without Enter: the field keeps the keyboard.
fn type_j1(h: &mut Harness<'_, Parol6App>, text: &str) {
    h.get_by_label("J1 target").click();
    h.run_steps(1);
    h.get_by_label("J1 target").type_text(text);
    h.run_steps(1);
    assert!(h.ctx.memory(|m| m.focused().is_some()), "the J1 field has the keyboard");
}

fn j1_deg(h: &Harness<'_, Parol6App>) -> f64 {
    h.state().backend().state().q[0].to_degrees()
}

/// Trial 24 D1: J1 typed 20 (no Enter), then a click on STOP: the click took the field's keyboard,
/// which committed the value, and J1 swung from 90° to 20° after STOP. Then HOME: the arm went
/// to the typed 60° instead of standby.
#[test]
fn stop_or_home_clicked_over_a_typed_joint_value_does_not_send_it() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    let start = j1_deg(&h);
    type_j1(&mut h, "20");
    click_on(&mut h, "STOP");
    settle(&mut h, 0.6);
    assert!((j1_deg(&h) - start).abs() < 0.1, "J1 moved from {start:.2}° to {:.2}° after STOP", j1_deg(&h));
    assert!(h.state().moves_sent().next().is_none(), "sent {:?}", h.state().moves_sent().collect::<Vec<_>>());
    assert!(h.state().notices().iter().any(|n| n.text.contains("J1: the value typed and not confirmed")), "it says so");

    // HOME from elsewhere: J1 at 60° first, then a typed 30 and a click on HOME
    let mut q = h.state().backend().state().q.clone();
    q[0] = 60f64.to_radians();
    h.state_mut().teleport(q).unwrap();
    settle(&mut h, 0.3);
    type_j1(&mut h, "30");
    click_on(&mut h, "HOME");
    until(&mut h, "HOME at rest", 30.0, |h| {
        let s = h.state().backend().state();
        !s.moving && (s.q[0].to_degrees() - start).abs() < 0.1
    });
    let sent: Vec<String> = h.state().moves_sent().map(str::to_string).collect();
    assert!(sent.iter().all(|m| !m.contains("MoveJoints")), "the typed 30° was sent: {sent:?}");
}

/// Trials 25 m1 and 26 m2: J1 typed and not confirmed, then a click on the 3D view or on the File
/// menu committed the value: the arm moved (under the open menu that covered STOP). A click
/// elsewhere drops it, with a notice; Enter still moves.
#[test]
fn a_click_elsewhere_never_sends_a_typed_joint_value() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    let start = j1_deg(&h);
    type_j1(&mut h, "20");
    click_on(&mut h, "File");
    settle(&mut h, 0.6);
    h.key_press(egui::Key::Escape);
    type_j1(&mut h, "30");
    let view = h.get_by_label_contains("3D view unavailable").rect().center();
    ui_support::mouse_click(&mut h, view);
    settle(&mut h, 0.6);
    assert!((j1_deg(&h) - start).abs() < 0.1, "J1 moved from {start:.2}° to {:.2}°", j1_deg(&h));
    assert!(h.state().moves_sent().next().is_none(), "sent {:?}", h.state().moves_sent().collect::<Vec<_>>());
    let said = h.state().notices().iter().filter(|n| n.text.contains("J1: the value typed and not confirmed")).count();
    assert!(said >= 1, "it says so");
    // Enter moves
    type_j1(&mut h, "40");
    h.key_press(egui::Key::Enter);
    until(&mut h, "J1 at 40°", 20.0, |h| (j1_deg(h) - 40.0).abs() < 0.1);
}

/// Trial 24 D2: with the E-stop latched, a recording opened turned the button back into a plain
/// "E-STOP" (the recording's state has no latch), though the robot stayed latched.
#[test]
fn the_estop_button_shows_the_live_latch_during_replay() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    h.get_by_label("E-STOP").click();
    until(&mut h, "the latch", 5.0, |h| has_label(h, "Release E-STOP"));
    let dir = std::env::temp_dir().join(format!("parol6-stop-wins-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.mcap");
    let model = parol6_core::RobotModel::parol6();
    std::fs::write(&path, parol6_app::cli::bench_replay::synthetic_recording(&model, 0.5, 10.0).unwrap()).unwrap();
    h.state_mut().queue_command(parol6_app::panels::AppCommand::OpenRecording(path));
    until(&mut h, "the replay", 10.0, |h| h.state().replay().is_some());
    h.run_steps(3);
    assert!(has_label(&h, "Release E-STOP"), "during replay the button shows the live latch");
    assert!(h.query_all_by_label("E-STOP").next().is_none(), "no plain E-STOP over the latched arm");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Trial 23 D1: one Step (F10) ran steps 3–6 of Draw (blended into one path) without a word,
/// where the guide said Step runs one step. The notice names the steps that run together.
#[test]
fn step_over_blended_lines_says_which_steps_run_together() {
    use parol6_core::program::runner::RunState;
    let draw = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/programs/draw.json");
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    ui_support::open_program_file(&mut h, &draw);
    until(&mut h, "the program's check", 60.0, |h| !h.state().program_panel().checking());
    let progress = |h: &Harness<'_, Parol6App>| h.state().program_progress().map(|p| (p.state.clone(), p.step));
    let said = |h: &Harness<'_, Parol6App>| h.state().notices().iter().any(|n| n.text.starts_with("Step runs steps"));
    // steps 1 and 2 one at a time, and nothing said
    for paused_at in [1, 2] {
        h.get_by_label("Step (F10)").click();
        until(&mut h, "the step's end", 60.0, |h| progress(h) == Some((RunState::Paused, paused_at)));
    }
    assert!(!said(&h), "a single step needs no word");
    // steps 3–6 are blended: one Step runs them, and says so
    h.get_by_label("Step (F10)").click();
    h.run_steps(2);
    let texts: Vec<String> = h.state().notices().iter().map(|n| n.text.clone()).collect();
    assert!(texts.iter().any(|t| t.starts_with("Step runs steps 3–6 together")), "{texts:?}");
    until(&mut h, "paused after the blended lines", 60.0, |h| progress(h) == Some((RunState::Paused, 6)));
}

/// Trial 25 m2: J1 typed 20 (no Enter), then a click on *Go* (go to joint pose): Go's move won,
/// and the typed value was dropped without a word. A click never sends a typed joint value (trials
/// 25 m1, 26 m2): Go moves, and a notice says the typed value was not sent.
#[test]
fn go_clicked_over_a_typed_joint_value_says_the_value_was_not_sent() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    let start = j1_deg(&h);
    type_j1(&mut h, "20");
    click_on(&mut h, "Go");
    settle(&mut h, 1.0);
    let sent: Vec<String> = h.state().moves_sent().map(str::to_string).collect();
    assert_eq!(sent.len(), 1, "Go's move only: {sent:?}");
    assert!(!sent[0].contains("TypedMotion"), "{sent:?}");
    assert!((j1_deg(&h) - 20.0).abs() > 5.0, "J1 went to the typed 20°: {:.2}° (from {start:.2}°)", j1_deg(&h));
    assert!(
        h.state().notices().iter().any(|n| n.text.contains("J1: the value typed and not confirmed")),
        "it says so: {:?}",
        h.state().notices().iter().map(|n| n.text.clone()).collect::<Vec<_>>()
    );
}

/// Trial 26 m10 and m6: during replay with the robot connected, the per-joint jog buttons looked
/// clickable (only a notice refused them), and *Release E-STOP* said "motion is accepted again"
/// while motion stayed refused until the recording was closed.
#[test]
fn during_replay_the_joint_jog_buttons_are_greyed_and_the_release_says_what_still_holds() {
    use parol6_app::panels::{AppCommand, LinkCommand};
    let mut h = app_harness(egui::vec2(1280.0, 2400.0));
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::ConnectEmulator));
    until(&mut h, "the robot enabled", 15.0, |h| h.state().backend().state().blocked.is_none());
    until(&mut h, "the jog buttons", 5.0, |h| h.query_all_by_label("+").count() == 6);
    assert!(h.query_all_by_label("+").all(|b| !b.accesskit_node().is_disabled()), "live: they take clicks");
    let dir = std::env::temp_dir().join(format!("parol6-stop-wins-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.mcap");
    let model = parol6_core::RobotModel::parol6();
    std::fs::write(&path, parol6_app::cli::bench_replay::synthetic_recording(&model, 0.5, 10.0).unwrap()).unwrap();
    h.state_mut().queue_command(AppCommand::OpenRecording(path));
    until(&mut h, "the replay", 10.0, |h| h.state().replay().is_some());
    h.run_steps(3);
    assert!(h.query_all_by_label("+").all(|b| b.accesskit_node().is_disabled()), "greyed during replay");
    h.get_by_label("E-STOP").click();
    until(&mut h, "the latch", 10.0, |h| h.state().estop_latched());
    ui_support::release_estop(&mut h);
    until(&mut h, "the release", 10.0, |h| !h.state().estop_latched());
    let said = |h: &Harness<'_, Parol6App>, part: &str| h.state().notices().iter().any(|n| n.text.contains(part));
    assert!(said(&h, "motion is accepted once the recording is closed"));
    assert!(!said(&h, "motion is accepted again"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Types `text` and clicks the centre of the widget labelled `on`, all in ONE frame, as a
/// window at ~10 FPS gets them (the kittest harness runs a frame per queued event otherwise).
/// The app holds the click for the next frame (`app::click_after_typing`).
fn type_and_click_in_one_frame(h: &mut Harness<'_, Parol6App>, text: &str, on: &str) {
    let at = h.get_by_label(on).rect().center();
    h.hover_at(at);
    h.run_steps(1);
    let events = &mut h.input_mut().events;
    for c in text.chars() {
        // as the window gets a key: the key, its text, the key let go
        for pressed in [true, false] {
            let modifiers = egui::Modifiers::NONE;
            if let Some(key) = egui::Key::from_name(&c.to_string()) {
                events.push(egui::Event::Key { key, physical_key: None, pressed, repeat: false, modifiers });
            }
            if pressed {
                events.push(egui::Event::Text(c.to_string()));
            }
        }
    }
    events.push(egui::Event::PointerMoved(at));
    for pressed in [true, false] {
        let (button, modifiers) = (egui::PointerButton::Primary, egui::Modifiers::NONE);
        events.push(egui::Event::PointerButton { pos: at, button, pressed, modifiers });
    }
    // the window's input goes through the app's raw-input hook, as eframe sends it: this frame,
    // and the next (which gets what the hook held back)
    for _ in 0..2 {
        let ctx = h.ctx.clone();
        let mut raw = std::mem::take(h.input_mut());
        eframe::App::raw_input_hook(h.state_mut(), &ctx, &mut raw);
        *h.input_mut() = raw;
        h.run_steps(1);
    }
}

/// Trial 29 D1: under load (~10 FPS) the keys typed and the click on *Go* came in one frame;
/// egui gave the field's keyboard away at the click before the field read the keys, and Go moved
/// J1 to 5° for a typed 55. The Cartesian target's X lost digits the same way before *Solve IK*.
/// The lost digits acted as shortcuts instead: `5` picked J5 for the keyboard jog.
#[test]
fn keys_typed_in_the_frame_of_the_click_are_not_lost() {
    let opts = LaunchOptions { connect: Some(ConnectTarget::Emulator), ..launch_options() };
    let mut h = harness_with(opts, egui::vec2(1280.0, 2400.0));
    until(&mut h, "the emulator answers", 15.0, |h| h.state().backend().state().blocked.is_none());
    let jog_pick = |h: &Harness<'_, Parol6App>| {
        let picked: Vec<String> = h
            .query_all_by_label_contains("J")
            .filter(|n| n.accesskit_node().toggled() == Some(egui::accesskit::Toggled::True))
            .filter_map(|n| n.accesskit_node().label())
            .collect();
        picked
    };
    let picked_before = jog_pick(&h);
    assert_eq!(picked_before, ["J1"], "the keyboard jog starts on J1");
    h.get_by_label("J1 pose").click();
    h.run_steps(1);
    type_and_click_in_one_frame(&mut h, "55", "Go");
    until(&mut h, "J1 at the typed 55°", 20.0, |h| (j1_deg(h) - 55.0).abs() < 0.1);
    assert_eq!(jog_pick(&h), picked_before, "a digit typed into the field picked no jog joint");

    h.get_by_label("target X").click();
    h.run_steps(1);
    type_and_click_in_one_frame(&mut h, "78", "Solve IK");
    h.run_steps(2);
    assert_eq!(h.get_by_label("target X").value().as_deref(), Some("78.00"));

    // any text field (trial 31 m1: `rec1.mcap` typed, then Open at once, opened `rec1.mca`)
    h.get_by_label("Program file").click();
    h.run_steps(1);
    type_and_click_in_one_frame(&mut h, "/tmp/no-such-dir/p.json", "Open");
    until(&mut h, "Open's refusal", 10.0, |h| h.state().notices().iter().any(|n| n.text.contains("no-such-dir")));
    let said: Vec<&str> = h.state().notices().iter().map(|n| n.text.as_str()).collect();
    assert!(said.iter().any(|t| t.contains("/tmp/no-such-dir/p.json")), "the whole typed path was opened: {said:?}");
}

/// Trial 29 m1: J2 `abc` (no Enter) in Go to joint pose, then a click on *Go*: J2 was refused
/// ("not a number") and Go still moved, with J2's old value. Go is not sent then.
#[test]
fn go_is_not_sent_when_a_field_left_by_its_click_holds_no_number() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    h.get_by_label("J2 pose").click();
    h.run_steps(1);
    h.get_by_label("J2 pose").type_text("abc");
    h.run_steps(1);
    click_on(&mut h, "Go");
    settle(&mut h, 0.5);
    assert!(h.state().moves_sent().next().is_none(), "sent {:?}", h.state().moves_sent().collect::<Vec<_>>());
    assert!(h.state().notices().iter().any(|n| n.text.contains("Go not sent: J2 holds no number")));
}

/// Trial 30 D1: target Z `280` + Enter, then `abc` (or a value beyond the range) and a click on
/// *Move to target*: the field was refused and the arm still moved, to Z = 280. It is not sent.
#[test]
fn move_to_target_is_not_sent_when_a_field_left_by_its_click_is_refused() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    ui_support::type_into(&mut h, "target Z", "280");
    for typed in ["abc", "1e9"] {
        h.get_by_label("target Z").click();
        h.run_steps(1);
        h.get_by_label("target Z").type_text(typed);
        h.run_steps(1);
        click_on(&mut h, "Move to target");
        settle(&mut h, 0.5);
        assert!(
            h.state().moves_sent().next().is_none(),
            "{typed}: sent {:?}",
            h.state().moves_sent().collect::<Vec<_>>()
        );
        let said = "Move to target not sent: target Z holds no valid value";
        assert!(h.state().notices().iter().any(|n| n.text == said), "{typed}: {:?}", h.state().notices());
    }
    click_on(&mut h, "Move to target");
    settle(&mut h, 0.5);
    assert!(h.state().moves_sent().next().is_some(), "a valid Move to target still moves");
}

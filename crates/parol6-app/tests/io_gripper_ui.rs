//! The I/O & gripper panel, Clear error, the E-stop button and homing feedback (issue 32,
//! safety item 3 and two minors), in the whole app: against the built-in emulator (what reaches
//! the board) and the simulation (the same buttons through the same backend trait).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use std::time::{Duration, Instant};

use eframe::egui::{self, Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};

use parol6_app::app::{ConnectTarget, LaunchOptions, Parol6App};
use parol6_app::panels::io_gripper::ESTOP_LATCHED;
use parol6_core::motion::{RobotBackend, StateSource};
use parol6_core::program::runner::RunState;
use parol6_hw::CommandCode;

use ui_support::{harness_with, has_label, launch_options, type_into, until};

/// The app connected to the built-in emulator, once the board answers (a tall window: the
/// left column shows every panel without scrolling).
fn robot_harness() -> Harness<'static, Parol6App> {
    let opts = LaunchOptions { connect: Some(ConnectTarget::Emulator), ..launch_options() };
    let mut h = harness_with(opts, egui::vec2(1280.0, 2400.0));
    until(&mut h, "the emulator answers", 15.0, |h| {
        let s = h.state().backend().state();
        s.source == StateSource::Robot && s.blocked.is_none()
    });
    h
}

fn emulator_positions(h: &Harness<'_, Parol6App>) -> [i32; 6] {
    h.state().emulator().expect("emulator").snapshot().position_steps
}

/// Clicks the 3D view, so that no widget has the keyboard.
fn focus_view(h: &mut Harness<'_, Parol6App>) {
    let at = h.get_by_label_contains("3D view unavailable").rect().center();
    h.hover_at(at);
    for pressed in [true, false] {
        let modifiers = Modifiers::NONE;
        h.event(egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed, modifiers });
        h.run_steps(1);
    }
}

/// Holds Page Up (jog the selected joint, J1) for `frames` frames.
fn hold_page_up(h: &mut Harness<'_, Parol6App>, frames: usize) {
    let modifiers = Modifiers::NONE;
    h.event(egui::Event::Key { key: Key::PageUp, pressed: true, modifiers, repeat: false, physical_key: None });
    for _ in 0..frames {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(15));
    }
    h.event(egui::Event::Key { key: Key::PageUp, pressed: false, modifiers, repeat: false, physical_key: None });
    h.run_steps(2);
}

#[test]
fn toggling_an_output_reaches_the_emulator() {
    let mut h = robot_harness();
    assert!(!h.state().emulator().unwrap().snapshot().outputs[0]);
    h.get_by_label("OUTPUT 1: LOW").click();
    until(&mut h, "OUTPUT1 high on the board", 10.0, |h| h.state().emulator().unwrap().snapshot().outputs[0]);
    until(&mut h, "the panel shows the board's echo", 10.0, |h| has_label(h, "OUTPUT 1: HIGH"));
    assert!(!h.state().emulator().unwrap().snapshot().outputs[1], "OUTPUT2 untouched");
    h.get_by_label("OUTPUT 1: HIGH").click();
    until(&mut h, "OUTPUT1 low again", 10.0, |h| !h.state().emulator().unwrap().snapshot().outputs[0]);
}

#[test]
fn clear_error_is_sent_to_the_board() {
    let mut h = robot_harness();
    h.state().emulator().unwrap().take_received();
    h.get_by_label("Clear error").click();
    let mut seen = false;
    let deadline = Instant::now() + Duration::from_secs(10);
    while !seen && Instant::now() < deadline {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(15));
        seen = h
            .state()
            .emulator()
            .unwrap()
            .take_received()
            .iter()
            .any(|f| f.command.code == CommandCode::ClearError.byte());
    }
    assert!(seen, "a CLEAR ERROR frame reached the board");
}

#[test]
fn the_estop_latches_and_refuses_a_jog_until_released() {
    let mut h = robot_harness();
    h.get_by_label("E-STOP").click();
    until(&mut h, "DISABLE latched on the board", 10.0, |h| h.state().emulator().unwrap().snapshot().disabled);
    assert!(h.state().estop_latched());
    until(&mut h, "the reason is shown", 5.0, |h| has_label(h, ESTOP_LATCHED));
    // issue 32 minor: Run (F5) and Step (F10) are greyed while the E-stop is latched
    until(&mut h, "the pre-flight", 10.0, |h| has_label(h, "pre-flight: ok"));
    h.run_steps(2);
    assert!(h.get_by_label("Run (F5)").accesskit_node().is_disabled(), "Run (F5) greyed while the E-stop is latched");
    assert!(
        h.get_by_label("Step (F10)").accesskit_node().is_disabled(),
        "Step (F10) greyed while the E-stop is latched"
    );
    let before = emulator_positions(&h);
    focus_view(&mut h);
    hold_page_up(&mut h, 30);
    // H (HOME) goes to the app and is refused there, with the reason
    h.key_press(Key::H);
    h.run_steps(2);
    assert!(h.state().notices().iter().any(|n| n.text.contains(ESTOP_LATCHED)), "refusal names the E-stop");
    std::thread::sleep(Duration::from_millis(300));
    h.run_steps(2);
    assert_eq!(emulator_positions(&h), before, "nothing moved while latched");
    assert_eq!(h.state().moves_sent().count(), 0, "no motion command left the app");

    ui_support::release_estop(&mut h);
    until(&mut h, "ENABLE reached the board", 10.0, |h| !h.state().emulator().unwrap().snapshot().disabled);
    assert!(!h.state().estop_latched());
    until(&mut h, "the robot accepts motion", 10.0, |h| h.state().backend().state().blocked.is_none());
    focus_view(&mut h);
    hold_page_up(&mut h, 40);
    until(&mut h, "the jog moves J1 after the release", 10.0, |h| emulator_positions(h)[0] != before[0]);
}

#[test]
fn the_estop_disables_the_simulation_the_same_way() {
    let mut h = ui_support::app_harness(egui::vec2(1280.0, 2400.0));
    h.get_by_label("E-STOP").click();
    until(&mut h, "the simulated drives are disabled", 5.0, |h| h.state().sim().state().io.drives_disabled);
    // the Cartesian jog is off while latched: holding +X sends nothing
    let plus_x = h.get_by_label("+X").rect().center();
    h.hover_at(plus_x);
    let modifiers = Modifiers::NONE;
    h.event(egui::Event::PointerButton { pos: plus_x, button: egui::PointerButton::Primary, pressed: true, modifiers });
    h.run_steps(10);
    h.event(egui::Event::PointerButton {
        pos: plus_x,
        button: egui::PointerButton::Primary,
        pressed: false,
        modifiers,
    });
    h.run_steps(2);
    assert_eq!(h.state().moves_sent().count(), 0, "no jog left the app while latched");
    ui_support::release_estop(&mut h);
    until(&mut h, "the simulated drives are enabled", 5.0, |h| !h.state().sim().state().io.drives_disabled);
}

/// Trial 7: View → Joints panel off hid STOP and E-STOP with it (and the choice is remembered,
/// so the next start had neither on screen). With the joints panel hidden, the menu bar shows
/// both, and they act as the panel's do.
#[test]
fn stop_and_the_estop_stay_on_screen_with_the_joints_panel_hidden() {
    let size = egui::vec2(1024.0, 700.0);
    let mut h = ui_support::app_harness(size);
    ui_support::click_in_view_menu(&mut h, "Joints panel");
    h.run_steps(2);
    assert!(!has_label(&h, "HOME"), "the joints panel is gone");
    for label in ["STOP", "E-STOP"] {
        let r = h.get_by_label(label).rect();
        assert!(r.min.x >= 0.0 && r.max.x <= size.x && r.min.y >= 0.0 && r.max.y <= size.y, "{label} on screen: {r:?}");
    }
    h.get_by_label("E-STOP").click();
    until(&mut h, "the simulated drives are disabled", 5.0, |h| h.state().sim().state().io.drives_disabled);
    assert!(h.state().estop_latched());
    // the button reads "Release E-STOP" from the frame after the latch (the drives may be off
    // before that frame is laid out)
    until(&mut h, "the release button", 5.0, |h| has_label(h, "Release E-STOP"));
    ui_support::release_estop(&mut h);
    until(&mut h, "the simulated drives are enabled", 5.0, |h| !h.state().sim().state().io.drives_disabled);
    // shown again, the panel has them, the menu bar not
    ui_support::click_in_view_menu(&mut h, "Joints panel");
    h.run_steps(2);
    assert!(has_label(&h, "HOME"));
    assert_eq!(h.query_all_by_label("E-STOP").count(), 1, "one E-STOP, in the joints panel");
}

#[test]
fn gripper_fields_take_units_refuse_the_range_and_move_the_gripper() {
    let mut h = ui_support::app_harness(egui::vec2(1280.0, 2400.0));
    type_into(&mut h, "Gripper position", "300");
    assert!(h.state().notices().iter().any(|n| n.error && n.text.contains("outside 0–255")), "range refused");
    type_into(&mut h, "Gripper current", "0,5 rad");
    assert!(h.state().notices().iter().any(|n| n.text.contains("does not fit")), "a unit that does not fit");
    // trial10 n2: a current in amperes is converted (it was refused: "A does not fit")
    type_into(&mut h, "Gripper current", "0,7A");
    type_into(&mut h, "Gripper position", "200");
    h.get_by_label("Move gripper").click();
    until(&mut h, "the simulated gripper follows", 5.0, |h| {
        let io = h.state().sim().state().io;
        io.gripper_position == 200 && io.gripper_current_ma == 700
    });
    h.get_by_label("Calibrate").click();
    until(&mut h, "calibrated", 5.0, |h| h.state().sim().state().io.gripper().calibrated);
}

/// Trial 32 D1: `xyz` (or `300`) typed into the gripper position, then a click on *Move gripper*:
/// the field was refused and the gripper still moved, to the last accepted value. It is not sent.
#[test]
fn move_gripper_is_not_sent_when_a_field_left_by_its_click_is_refused() {
    let mut h = ui_support::app_harness(egui::vec2(1280.0, 2400.0));
    type_into(&mut h, "Gripper position", "150");
    for typed in ["xyz", "300"] {
        h.get_by_label("Gripper position").click();
        h.run_steps(1);
        h.get_by_label("Gripper position").type_text(typed);
        h.run_steps(1);
        let at = h.get_by_label("Move gripper").rect().center();
        ui_support::mouse_click(&mut h, at);
        h.run_steps(5);
        let said =
            |h: &Harness<'_, Parol6App>| h.state().notices().iter().any(|n| n.text.contains("Move gripper not sent"));
        assert!(said(&h), "{typed}: says why nothing was sent");
        assert_eq!(h.state().sim().state().io.gripper_position, 0, "{typed}: the gripper did not move");
    }
    h.get_by_label("Move gripper").click();
    until(&mut h, "a valid Move gripper still moves", 5.0, |h| h.state().sim().state().io.gripper_position == 150);
}

/// Issue 32 (minor): Home (homing) on the fake robot shows its progress and its outcome.
#[test]
fn home_on_the_fake_robot_shows_progress_and_outcome() {
    let mut h = robot_harness();
    h.get_by_label("Home (homing)").click();
    until(&mut h, "homing progress shown", 10.0, |h| has_label(h, "homing: "));
    until(&mut h, "homing outcome shown", 20.0, |h| has_label(h, "homing done"));
    assert!(h.state().notices().iter().any(|n| n.text.contains("homing done")), "a notice says it");
}

/// Regression (issue 32, minor): robot versus simulation was shown only by a small word in the
/// status bar. The window title names the robot and its port; the simulation says so.
#[test]
fn the_window_title_says_robot_or_simulation() {
    let sim = ui_support::app_harness(egui::vec2(1280.0, 800.0));
    assert_eq!(sim.state().window_title(), Some(parol6_app::app::TITLE_SIMULATION));
    let mut h = robot_harness();
    h.run_steps(2);
    let title = h.state().window_title().unwrap_or_default().to_string();
    // the fake robot's port is a local socket: named in plain words, not by its path
    assert_eq!(title, "PAROL6 Studio — ROBOT (built-in emulator)");
    assert!(has_label(&h, "built-in emulator"), "the connection section names it too");
}

/// Regression (trial13 D1, major): under the latched E-STOP, the Robot connection's *Enable* sent
/// ENABLE and *Home (homing)* started the controller's homing: the arm moved while the window
/// still said "E-STOP latched: drives disabled, motion refused". Both are refused under the latch
/// (only *Release E-STOP* enables), greyed, and no ENABLE or HOME frame reaches the board.
#[test]
fn enable_and_homing_are_refused_while_the_estop_is_latched() {
    use parol6_app::panels::{AppCommand, LinkCommand};
    let mut h = robot_harness();
    h.get_by_label("E-STOP").click();
    until(&mut h, "DISABLE latched on the board", 10.0, |h| h.state().emulator().unwrap().snapshot().disabled);
    until(&mut h, "the reason is shown", 5.0, |h| has_label(h, ESTOP_LATCHED));
    h.run_steps(2);
    h.state().emulator().unwrap().take_received();
    // what the two buttons send, as any other way of sending them would
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::Enable));
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::Home));
    let deadline = Instant::now() + Duration::from_millis(800);
    let mut sent = Vec::new();
    while Instant::now() < deadline {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(15));
        sent.extend(h.state().emulator().unwrap().take_received().into_iter().map(|f| f.command.code));
    }
    for code in [CommandCode::Enable, CommandCode::Home] {
        assert!(!sent.contains(&code.byte()), "{code:?} reached the board under the latched E-stop");
    }
    let board = h.state().emulator().unwrap().snapshot();
    assert!(board.disabled, "the drives stay disabled");
    assert!(h.state().estop_latched());
    assert!(h.state().notices().iter().any(|n| n.text.contains(ESTOP_LATCHED)), "the refusal names the E-stop");
    h.run_steps(2);
    for button in ["Enable", "Home (homing)"] {
        assert!(h.get_by_label(button).accesskit_node().is_disabled(), "{button} greyed while the E-stop is latched");
    }
}

/// Regression (trial13 D2): with the plots hidden while connected, the robot's rows never reached
/// the plots (they take the live view only while shown), and disconnecting dropped the robot's
/// view: Plots opened afterwards showed the simulation alone, no robot stretch, no switch mark.
/// The outgoing backend's rows are taken at the switch, shown or not.
#[test]
fn the_robots_rows_reach_the_plots_when_disconnecting_with_the_plots_hidden() {
    use parol6_app::panels::{AppCommand, LinkCommand};
    let mut h = robot_harness();
    assert!(!has_label(&h, "cmd - meas"), "the plots are hidden");
    // half a second of the robot's status rows
    let until_s = Instant::now() + Duration::from_millis(500);
    while Instant::now() < until_s {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(15));
    }
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::Disconnect));
    until(&mut h, "the simulation again", 15.0, |h| h.state().backend().state().source == StateSource::Simulation);
    h.state_mut().show_plot(parol6_core::telemetry::Quantity::Position);
    until(&mut h, "the simulation's rows after the robot's", 15.0, |h| {
        let p = h.state().plots_panel();
        p.switches().iter().any(|&(_, robot)| !robot)
    });
    let p = h.state().plots_panel();
    let (first, _) = p.store().time_range_s().expect("rows");
    let (at, _) = p.switches().into_iter().find(|&(_, robot)| !robot).unwrap();
    assert!(at > first, "the robot's rows come before the switch: from {first} s to {at} s");
}

/// Regression (trial14, major): a Robot connection jog button held with the mouse jogged for
/// 0.8 s only. The button sensed clicks alone, and egui stops counting a press held longer than
/// its click time (0.8 s) as the button's: the jog was released under a still-held button, the
/// joint stopped about 11° on, without a word (docs: "press and hold"). Held for 5 s of egui
/// time, the jog is still sent and the joint still moves on the board.
#[test]
fn a_joint_jog_button_held_with_the_mouse_keeps_jogging() {
    let mut h = robot_harness();
    // the jog grid's first "+" is J1's (the Cartesian jog's buttons are "+X" and so on)
    let at = h.get_all_by_label("+").next().expect("J1 +").rect().center();
    h.hover_at(at);
    let modifiers = Modifiers::NONE;
    h.event(egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed: true, modifiers });
    let jogs_sent = |h: &Harness<'_, Parol6App>| h.state().moves_sent().filter(|m| m.starts_with("Jog(Some")).count();
    // each step is a quarter second of egui time: 12 steps are well past the 0.8 s click time
    // (and, on the old code, past the stop that followed it)
    for _ in 0..12 {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(30));
    }
    let (sent_before, at_before) = (jogs_sent(&h), emulator_positions(&h)[0]);
    for _ in 0..8 {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(40));
    }
    let (sent_after, at_after) = (jogs_sent(&h), emulator_positions(&h)[0]);
    h.event(egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed: false, modifiers });
    h.run_steps(2);
    assert!(sent_after > sent_before, "the jog was no longer sent after 3 s of holding ({sent_before} jogs sent)");
    assert_ne!(at_after, at_before, "J1 stopped on the board while the button was still held");
}

/// Regression (trial 15 minor, issue 32's "the joint sliders show the jog's planned end instead
/// of the arm" for the joint jog): while a joint jog is held on the robot, J1's field showed the
/// jog's far end (its limit) instead of where the arm was.
#[test]
fn the_joint_fields_follow_the_arm_during_a_held_joint_jog() {
    let mut h = robot_harness();
    let at = h.get_all_by_label("+").next().expect("J1 +").rect().center();
    h.hover_at(at);
    let modifiers = Modifiers::NONE;
    h.event(egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed: true, modifiers });
    until(&mut h, "J1 moving", 10.0, |h| h.state().backend().state().moving);
    for _ in 0..4 {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(30));
    }
    let s = h.state().backend().state();
    let (arm_deg, end_deg) = (s.q[0].to_degrees(), s.target_q[0].to_degrees());
    let shown: f64 = h.get_by_label("J1 target").value().unwrap().parse().unwrap();
    h.event(egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed: false, modifiers });
    h.run_steps(2);
    assert!((end_deg - arm_deg).abs() > 10.0, "the test needs a jog whose end is far: {arm_deg:.2}° → {end_deg:.2}°");
    assert!(
        (shown - arm_deg).abs() < 5.0,
        "J1 shows {shown:.2}°, the arm is at {arm_deg:.2}° (jog's end {end_deg:.2}°)"
    );
}

/// Regression (trial14 m4): the plots lost the robot's last moments before a disconnect during
/// motion (J1 stepped 45° → 55.9° at the switch mark instead of a ramp): they took the
/// recorder's last published view, up to 50 ms old and more on a busy host. The robot's last
/// plotted row is where the simulation takes over, the robot's pose when the link closed.
#[test]
fn the_plots_keep_the_robots_last_rows_at_a_disconnect_during_a_move() {
    use parol6_app::panels::{AppCommand, LinkCommand};
    use parol6_core::motion::MotionCommand;
    let mut h = robot_harness();
    h.state_mut().show_plot(parol6_core::telemetry::Quantity::Position);
    let mut goal = parol6_core::parol6::standby_rad().to_vec();
    goal[0] -= 0.6;
    h.state_mut().queue_command(AppCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal,
        speed_fraction: 0.3,
        profile: parol6_core::profile::ProfileKind::Trapezoidal,
    }));
    until(&mut h, "J1 moving", 10.0, |h| h.state().backend().state().moving);
    for _ in 0..6 {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(30));
    }
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::Disconnect));
    until(&mut h, "the simulation again", 15.0, |h| h.state().backend().state().source == StateSource::Simulation);
    // the simulation is sent to the robot's last pose: it holds there once that is applied
    ui_support::settle(&mut h, 0.3);
    let taken_over_deg = h.state().backend().state().q[0].to_degrees();
    until(&mut h, "the switch mark", 15.0, |h| h.state().plots_panel().switches().iter().any(|&(_, robot)| !robot));
    let p = h.state().plots_panel();
    let (switch_s, _) = p.switches().into_iter().find(|&(_, robot)| !robot).unwrap();
    let last_robot_deg = p.store().joint_positions_at(switch_s).expect("the robot's last row")[0].to_degrees();
    assert!(taken_over_deg < 88.0, "the test needs the move under way at the disconnect: J1 {taken_over_deg:.2}°");
    assert!(
        (last_robot_deg - taken_over_deg).abs() < 1.0,
        "the robot's last plotted J1 is {last_robot_deg:.2}°, the simulation took over at {taken_over_deg:.2}°"
    );
}

/// Regression (trial14 m5): disconnecting under the latched E-STOP handed the view to the
/// simulation with its drives enabled (a green "drives enabled" LED under the red "E-STOP latched:
/// drives disabled" line). The backend that becomes the active one is disabled too.
#[test]
fn the_backend_taken_over_under_the_latched_estop_has_its_drives_disabled_too() {
    use parol6_app::panels::{AppCommand, LinkCommand};
    let mut h = robot_harness();
    h.get_by_label("E-STOP").click();
    until(&mut h, "DISABLE latched on the board", 10.0, |h| h.state().emulator().unwrap().snapshot().disabled);
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::Disconnect));
    until(&mut h, "the simulation shown", 10.0, |h| h.state().backend().state().source == StateSource::Simulation);
    until(&mut h, "the simulation's drives disabled", 5.0, |h| h.state().backend().state().io.drives_disabled);
    assert!(h.state().estop_latched(), "still latched");
    ui_support::release_estop(&mut h);
    until(&mut h, "the simulation's drives enabled", 5.0, |h| !h.state().backend().state().io.drives_disabled);
}

/// Presses or lets go of Page Up (jog the selected joint, J1).
fn page_up(h: &mut Harness<'_, Parol6App>, pressed: bool) {
    let modifiers = Modifiers::NONE;
    h.event(egui::Event::Key { key: Key::PageUp, pressed, modifiers, repeat: false, physical_key: None });
}

/// Runs frames for `ms` milliseconds and returns the joint jogs the app sent meanwhile.
fn jogs_sent_during(h: &mut Harness<'_, Parol6App>, ms: u64) -> usize {
    let before = h.state().moves_sent().filter(|m| m.starts_with("Jog(Some")).count();
    let deadline = Instant::now() + Duration::from_millis(ms);
    while Instant::now() < deadline {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(15));
    }
    h.state().moves_sent().filter(|m| m.starts_with("Jog(Some")).count() - before
}

/// Regression (trial19 D1): Page Up pressed while motion was refused (the latched E-stop, a
/// running program, the drives disabled, no robot connected) did nothing, but the key still held
/// jogged J1 as soon as the refusal ended (Release E-STOP, F6, Enable, Connect): the arm moved
/// without a new press. A key held
/// through a refusal must be let go and pressed anew, as after STOP.
#[test]
fn a_jog_key_pressed_while_motion_is_refused_does_not_jog_when_the_refusal_ends() {
    let mut h = robot_harness();
    focus_view(&mut h);
    let start = emulator_positions(&h);

    // the latched E-stop, released with the key still held
    h.get_by_label("E-STOP").click();
    until(&mut h, "DISABLE latched on the board", 10.0, |h| h.state().emulator().unwrap().snapshot().disabled);
    page_up(&mut h, true);
    assert_eq!(jogs_sent_during(&mut h, 300), 0, "no jog under the latch");
    ui_support::release_estop(&mut h);
    until(&mut h, "ENABLE reached the board", 10.0, |h| !h.state().emulator().unwrap().snapshot().disabled);
    until(&mut h, "the robot accepts motion", 10.0, |h| h.state().backend().state().blocked.is_none());
    let jogs = jogs_sent_during(&mut h, 600);
    assert_eq!(jogs, 0, "Page Up pressed under the E-stop latch jogged J1 after Release E-STOP ({jogs} jogs)");
    assert_eq!(emulator_positions(&h)[0], start[0], "J1 stayed where it was after the release");
    page_up(&mut h, false);
    h.run_steps(2);

    // the drives disabled, enabled with the key still held
    h.get_by_label("Disable").click();
    until(&mut h, "the drives disabled", 10.0, |h| h.state().emulator().unwrap().snapshot().disabled);
    page_up(&mut h, true);
    h.run_steps(3);
    h.get_by_label("Enable").click();
    until(&mut h, "the drives enabled", 10.0, |h| !h.state().emulator().unwrap().snapshot().disabled);
    let jogs = jogs_sent_during(&mut h, 600);
    assert_eq!(jogs, 0, "Page Up pressed with the drives disabled jogged J1 after Enable ({jogs} jogs)");
    page_up(&mut h, false);
    h.run_steps(2);

    // a running program, paused (F6) with the key still held
    until(&mut h, "the pre-flight", 10.0, |h| has_label(h, "pre-flight: ok"));
    h.key_press(Key::F5);
    let state = |h: &Harness<'_, Parol6App>| h.state().program_progress().map(|p| p.state.clone());
    until(&mut h, "the program runs", 10.0, |h| state(h) == Some(RunState::Running));
    page_up(&mut h, true);
    h.run_steps(3);
    h.key_press(Key::F6);
    until(&mut h, "the program paused", 10.0, |h| state(h) == Some(RunState::Paused));
    let jogs = jogs_sent_during(&mut h, 600);
    assert_eq!(jogs, 0, "Page Up pressed during a program run jogged J1 after F6 ({jogs} jogs)");
    page_up(&mut h, false);
    h.run_steps(2);

    // disconnected, the key pressed, connected again with the key still held (after Disconnect the
    // section's controls wait 0.8 s: held that long while no jog rows were drawn, the key jogged
    // J1 17 times once connected, until the key was disarmed while the rows are not drawn)
    h.get_by_label("Disconnect").click();
    until(&mut h, "disconnected", 10.0, |h| !h.state().robot_connected());
    page_up(&mut h, true);
    h.run_steps(3);
    ui_support::click_when_enabled(&mut h, "Connect to the built-in emulator");
    until(&mut h, "the emulator answers again", 15.0, |h| {
        let s = h.state().backend().state();
        s.source == StateSource::Robot && s.blocked.is_none()
    });
    let jogs = jogs_sent_during(&mut h, 600);
    assert_eq!(jogs, 0, "Page Up held while disconnected jogged J1 once connected ({jogs} jogs)");
    page_up(&mut h, false);
    h.run_steps(2);

    // pressed anew, the key jogs again
    hold_page_up(&mut h, 40);
    assert!(h.state().moves_sent().any(|m| m.starts_with("Jog(Some")), "a new press jogs");
}

/// Trial 21 D3: a hurried double-click on E-STOP latched it and released it at once (the button
/// turns into *Release E-STOP* in the same place), sending ENABLE; H then homed the arm. The
/// release takes clicks only a moment after the latch.
#[test]
fn a_double_click_on_estop_leaves_it_latched() {
    let mut h = ui_support::app_harness(egui::vec2(1280.0, 1400.0));
    let at = h.get_by_label("E-STOP").rect().center();
    let click = |h: &mut Harness<'_, Parol6App>| ui_support::mouse_click(h, at);
    click(&mut h);
    std::thread::sleep(Duration::from_millis(150));
    click(&mut h);
    h.run_steps(3);
    assert!(h.state().estop_latched(), "the second click of a double-click released the E-stop");
    assert!(has_label(&h, "Release E-STOP"));
    until(&mut h, "the simulated drives disabled", 5.0, |h| h.state().sim().state().io.drives_disabled);
    ui_support::settle(&mut h, 0.3);
    assert!(h.state().sim().state().io.drives_disabled, "no ENABLE was sent");
    // a moment later the release takes a click
    ui_support::release_estop(&mut h);
    until(&mut h, "the release", 5.0, |h| !h.state().estop_latched());
}

/// Trial 22 D1: with `--tool ssg48` and the robot connected, the TCP panel showed the flange
/// (Y 236.77 mm at standby) while the Cartesian target and pre-flight used the tool tip
/// (341.77 mm): *From TCP* → *Solve IK* → *Move to target*, meant to keep the arm where it was,
/// moved it some 40°. The robot's TCP is the tool tip's, as the simulation's.
#[test]
fn with_a_tool_the_robots_tcp_is_the_tool_tip() {
    let mut model = parol6_core::RobotModel::parol6();
    model.set_tool(parol6_core::parol6::Tool::Ssg48);
    let opts = LaunchOptions { model: model.clone(), connect: Some(ConnectTarget::Emulator), ..launch_options() };
    let mut h = harness_with(opts, egui::vec2(1280.0, 2400.0));
    until(&mut h, "the emulator answers", 15.0, |h| {
        let s = h.state().backend().state();
        s.source == StateSource::Robot && s.blocked.is_none()
    });
    h.run_steps(3);
    let state = h.state().backend().state();
    let tip = model.fk(&state.q).position_m;
    for k in 0..3 {
        assert!(
            (state.tcp.position_m[k] - tip[k]).abs() < 1e-9,
            "axis {k}: robot TCP {:?}, tool tip {tip:?}",
            state.tcp
        );
    }
    let y_mm = format!("{:.2} mm", tip[1] * 1000.0);
    assert!(h.query_all_by_label_contains(&y_mm).next().is_some(), "the TCP panel shows the tool tip's Y {y_mm}");
    // From TCP, Solve IK, Move to target: the arm stays where it is
    let sent = h.state().moves_sent().count();
    for button in ["From TCP", "Solve IK"] {
        h.get_by_label(button).click();
        h.run_steps(3);
    }
    until(&mut h, "the IK solution", 10.0, |h| h.query_by_label("Move to target").is_some());
    h.get_by_label("Move to target").click();
    ui_support::settle(&mut h, 1.0);
    let after = h.state().backend().state().q.clone();
    let moved = after.iter().zip(&state.q).map(|(a, b)| (a - b).abs().to_degrees()).fold(0.0, f64::max);
    assert!(
        moved < 0.5,
        "Move to target from the TCP moved a joint {moved:.2}° (sent {:?})",
        h.state().moves_sent().skip(sent).collect::<Vec<_>>()
    );
}

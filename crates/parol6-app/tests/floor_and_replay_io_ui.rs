//! Trial 12 n-d and n-c, driven headless through egui's kittest harness on the full
//! app: a typed pose under the floor is refused by pre-flight's floor rule before anything is
//! sent and a held joint jog stops before it, on the simulation and the robot alike; the replay
//! marks the I/O & gripper section as not recorded.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use parol6_app::app::{ConnectTarget, LaunchOptions, Parol6App};
use ui_support::{harness_with, launch_options, type_into, until};

/// Types trial 12's pose (n-d) into Go to joint pose and presses Go: the TCP would be at
/// z = −83.8 mm, L5 and L6 under the floor.
fn go_under_the_floor(h: &mut Harness<'_, Parol6App>) -> Vec<String> {
    for (name, v) in [("J1", "90"), ("J2", "-3.37"), ("J3", "180"), ("J4", "-12.5"), ("J5", "28.65"), ("J6", "180")] {
        type_into(h, &format!("{name} pose"), v);
    }
    let sent = h.state().moves_sent().count();
    h.get_by_label("Go").click();
    h.run_steps(3);
    assert_eq!(h.state().moves_sent().count(), sent, "nothing is sent: {:?}", h.state().moves_sent().last());
    h.state().notices().iter().map(|n| n.text.clone()).collect()
}

/// The refusal names the link, the rule's words (pre-flight's) and how deep it would go.
fn assert_floor_refusal(said: &[String]) {
    assert!(
        said.iter().any(|t| t.starts_with("refused: L")
            && t.contains("goes below the floor (z = 0): its lowest point at z = -")
            && t.contains(" mm at that pose")),
        "{said:?}"
    );
}

/// Regression (trial 12 n-d): Go to (90, −3.37, 180, −12.5, 28.65, 180) put the TCP at
/// z = −83.8 mm without a word (the emulator), while pre-flight refused a program step there.
#[test]
fn go_to_a_pose_under_the_floor_is_refused_in_the_simulation() {
    let mut h = harness_with(launch_options(), egui::vec2(1280.0, 1400.0));
    let said = go_under_the_floor(&mut h);
    assert_floor_refusal(&said);
}

/// The app connected to the built-in emulator, once it has answered.
fn on_the_fake_robot() -> Harness<'static, Parol6App> {
    let opts = LaunchOptions { connect: Some(ConnectTarget::Emulator), ..launch_options() };
    let mut h = harness_with(opts, egui::vec2(1280.0, 1400.0));
    until(&mut h, "the emulator answers", 20.0, |h| {
        h.state().notices().iter().any(|n| n.text.starts_with("PAROL6 answered"))
    });
    h
}

#[test]
fn go_to_a_pose_under_the_floor_is_refused_on_the_robot() {
    let mut h = on_the_fake_robot();
    let said = go_under_the_floor(&mut h);
    assert_floor_refusal(&said);
}

/// A held joint jog on the robot toward the floor stops before it with one notice naming the
/// joint and the link (pre-flight's words), kept up while the key is held: no link goes under.
#[test]
fn a_held_joint_jog_on_the_robot_stops_before_the_floor() {
    use parol6_app::panels::AppCommand;
    let mut h = on_the_fake_robot();
    // above the floor, J2 leaning forward: J2 + takes the wrist down to it
    for (name, v) in [("J2", "-40"), ("J4", "-12.5"), ("J5", "28.65")] {
        type_into(&mut h, &format!("{name} pose"), v);
    }
    h.get_by_label("Go").click();
    let model = parol6_core::RobotModel::parol6();
    let guard = parol6_core::collision::CollisionGuard::new(&model);
    until(&mut h, "the arm at the pose", 20.0, |h| {
        let q = h.state().backend().state().q.clone();
        q.len() == 6 && (q[1] - (-40f64).to_radians()).abs() < 1e-3
    });
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(12);
    while std::time::Instant::now() < deadline {
        h.state_mut().queue_command(AppCommand::Jog(Some((1, 1))));
        h.run_steps(1);
        let q = h.state().backend().state().q.clone();
        assert_eq!(guard.floor_contact(&model, &q), None, "under the floor at {q:?}");
        std::thread::sleep(std::time::Duration::from_millis(15));
    }
    let said: Vec<String> = h.state().notices().iter().map(|n| n.text.clone()).collect();
    let stops: Vec<&String> = said.iter().filter(|t| t.contains("jog stopped before the floor")).collect();
    assert_eq!(stops.len(), 1, "one notice while held: {said:?}");
    assert!(
        stops[0].starts_with("refused: J2 jog stopped before the floor: L")
            && stops[0].contains("goes below the floor (z = 0)")
    );
    let q = h.state().backend().state().q.clone();
    assert!(q[1] > (-35f64).to_radians(), "J2 jogged toward the floor first: {q:?}");
}

/// Regression (trial 12 n-c): in replay the I/O & gripper section kept showing the live
/// backend's values without a mark, as if they were the recording's (which has no I/O channel).
/// It now says they are not recorded, shows placeholders, disables its controls, and keeps its
/// height: nothing in it moves.
#[test]
fn replay_marks_the_io_and_gripper_section_not_recorded_and_keeps_its_place() {
    use egui_kittest::kittest::NodeT;
    let model = parol6_core::RobotModel::parol6();
    let mut h = harness_with(launch_options(), egui::vec2(1280.0, 2400.0));
    h.run_steps(2);
    assert!(h.query_all_by_label("OUTPUT 1: LOW").next().is_some(), "the live outputs before the replay");
    let before = h.get_by_label("Move gripper").rect();
    let dir = std::env::temp_dir().join(format!("p6-io-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("run.mcap");
    let bytes = parol6_app::cli::bench_replay::synthetic_recording(&model, 0.5, 20.0).expect("recording");
    std::fs::write(&path, bytes).expect("write");
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| ui_support::has_label(h, "Replay: run.mcap"));
    h.key_press(egui::Key::Escape);
    h.run_steps(3);
    assert!(ui_support::has_label(&h, "Not recorded: the live I/O and gripper are hidden during replay"));
    assert!(h.query_all_by_label("OUTPUT 1: LOW").next().is_none(), "no live output value in replay");
    assert!(h.query_all_by_label("OUTPUT 1: —").next().is_some());
    assert!(!ui_support::has_label(&h, "not activated"), "no live gripper state in replay");
    let button = h.get_by_label("Move gripper");
    assert!(button.accesskit_node().is_disabled(), "its controls are disabled");
    let after = button.rect();
    assert!((after.min - before.min).length() < 0.5, "Move gripper moved from {before:?} to {after:?}");
    std::fs::remove_dir_all(&dir).ok();
}

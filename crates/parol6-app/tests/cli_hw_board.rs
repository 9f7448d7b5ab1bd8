//! `parol6 hw …` against lying, broken and stopped boards (issue 29 items 9, 10, 11, 12, 15):
//! the firmware emulator in this process, seen through the hostile-board peer of `tests/`
//! (`parol6_tests::fault_peer` with a `BoardMode`, no transport faults), and the built binary
//! talking to it with `--port`. Device and link events exit 1 naming their cause; the user's
//! input exits 2; nothing waits silently.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test
#![cfg(unix)]

mod cli_support;

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use cli_support::{Run, run_in, workspace_root};
use parol6_hw::emulator::{EmulatorConfig, EmulatorHandle};
use parol6_tests::fault_peer::{FaultConfig, FaultPeer};
use parol6_tests::hostile_board::BoardMode;

/// A move long enough to be under way when something happens (J1 by 60° at 5 % speed).
const LONG_MOVE_DEG: &str = "30,-90,180,0,0,180";

/// The emulator (homed at standby) behind a peer that lies as `mode` says.
/// The tests of this file run one at a time: each drives a 100 Hz session against an emulated
/// board, and on a 2-core CI machine a dozen at once starved each other into 80 ms link losses
/// that the tests do not expect (seen in CI: "link lost … no valid status for 80 ms" in place of
/// the E-stop under test).
fn serial() -> std::sync::MutexGuard<'static, ()> {
    static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());
    ONE_AT_A_TIME.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

fn board(mode: BoardMode) -> (EmulatorHandle, FaultPeer) {
    let emu = EmulatorHandle::spawn(EmulatorConfig { log_commands: false, ..EmulatorConfig::homed_at_standby() })
        .expect("emulator");
    let peer = FaultPeer::spawn(emu.path(), FaultConfig::clean(1).with_board(mode)).expect("peer");
    (emu, peer)
}

fn hw(port: &str, args: &[&str]) -> Run {
    let mut all = vec!["--port", port, "hw"];
    all.extend_from_slice(args);
    run_in(workspace_root(), &all, Duration::from_secs(60))
}

/// `hw ARGS` against a fresh board in `mode`. A loaded host can starve the emulator past the
/// session's 80 ms link-loss limit before the board's own fault shows: "link lost" instead of
/// the fault under test (seen in a CI run beside a GUI trial). Such a run is tried once more on
/// a fresh board; a second link loss fails the test.
fn hw_on(mode: BoardMode, args: &[&str]) -> (Run, EmulatorHandle, FaultPeer) {
    let (emu, peer) = board(mode);
    let run = hw(peer.path(), args);
    if !run.stderr.contains("link lost") {
        return (run, emu, peer);
    }
    eprintln!("link lost on a loaded host; once more on a fresh board: {run:?}");
    drop((emu, peer));
    let (emu, peer) = board(mode);
    (hw(peer.path(), args), emu, peer)
}

/// Asserts exit 1 (a device or link event) with every one of `needles` on stderr.
fn assert_device_failure(run: &Run, what: &str, needles: &[&str]) {
    run.assert_no_panic(what);
    assert_eq!(run.code(), Some(1), "{what}: a device event is exit 1: {run:?}");
    for n in needles {
        assert!(run.stderr.contains(n), "{what}: stderr should name {n:?}: {run:?}");
    }
}

#[test]
fn hw_move_against_a_board_far_outside_the_limits_ends_promptly_with_the_fault() {
    let _one_at_a_time = serial();
    let (run, _emu, peer) =
        hw_on(BoardMode::FarOutside, &["move", "--joints", LONG_MOVE_DEG, "--deg", "--speed", "0.05"]);
    assert_device_failure(&run, "move", &["answers are impossible", "J3 reads -200000 steps"]);
    assert!(run.elapsed < Duration::from_secs(10), "prompt, not a silent wait: {:?}", run.elapsed);
    assert!(peer.take_commands().iter().all(|c| c.command.code != 156), "no MOVE frame at all");
}

#[test]
fn hw_jog_on_a_board_far_outside_the_limits_is_a_device_fault() {
    let _one_at_a_time = serial();
    let (run, _emu, _peer) = hw_on(BoardMode::FarOutside, &["jog", "--joint", "2", "--speed", "0.5", "--seconds", "1"]);
    assert_device_failure(&run, "jog", &["answers are impossible"]);
    assert!(run.stdout.is_empty(), "{run:?}");
}

#[test]
fn hw_move_link_loss_exits_1_naming_the_cause() {
    let _one_at_a_time = serial();
    let (_emu, peer) = board(BoardMode::SilentAfter(150));
    let run = hw(peer.path(), &["move", "--joints", LONG_MOVE_DEG, "--deg", "--speed", "0.05"]);
    assert_device_failure(&run, "move", &["link lost during the move"]);
    assert!(!run.stderr.contains("refused"), "{run:?}");
}

#[test]
fn hw_move_estop_during_the_move_exits_1() {
    let _one_at_a_time = serial();
    let emu = EmulatorHandle::spawn(EmulatorConfig { log_commands: false, ..EmulatorConfig::homed_at_standby() })
        .expect("emulator");
    let port = emu.path().to_string();
    let child = std::thread::spawn(move || hw(&port, &["move", "--joints", LONG_MOVE_DEG, "--deg", "--speed", "0.05"]));
    std::thread::sleep(Duration::from_millis(1500));
    emu.set_estop_pressed(true);
    let run = child.join().unwrap();
    assert_device_failure(&run, "move", &["E-stop pressed during the move"]);
    assert!(!run.stderr.contains("refused"), "{run:?}");
}

#[test]
fn hw_jog_on_a_board_that_never_moves_fails() {
    let _one_at_a_time = serial();
    let (run, _emu, _peer) = hw_on(BoardMode::Stale, &["jog", "--joint", "1", "--speed", "0.8", "--seconds", "2"]);
    assert_device_failure(&run, "jog", &["the arm did not move"]);
}

#[test]
fn hw_move_on_a_board_that_never_moves_names_the_cause() {
    let _one_at_a_time = serial();
    let (run, _emu, _peer) = hw_on(BoardMode::Stale, &["move", "--joints", LONG_MOVE_DEG, "--deg", "--speed", "0.5"]);
    assert_device_failure(&run, "move", &["the move stopped before the goal", "commanded position"]);
    assert!(!run.stderr.contains("condition not met"), "{run:?}");
    assert!(run.elapsed < Duration::from_secs(8), "{:?}", run.elapsed);
}

#[test]
fn hw_jog_after_positions_jumped_to_impossible_values_fails() {
    let _one_at_a_time = serial();
    let (run, _emu, _peer) =
        hw_on(BoardMode::JumpAfter(100), &["jog", "--joint", "2", "--speed", "0.3", "--seconds", "3"]);
    assert_device_failure(&run, "jog", &["impossible"]);
    assert!(run.stdout.is_empty(), "no stopped_at_limit success: {run:?}");
}

#[test]
fn hw_move_after_positions_jumped_to_impossible_values_fails_promptly() {
    let _one_at_a_time = serial();
    let (run, _emu, _peer) =
        hw_on(BoardMode::JumpAfter(100), &["move", "--joints", LONG_MOVE_DEG, "--deg", "--speed", "0.05"]);
    assert_device_failure(&run, "move", &["impossible"]);
    assert!(run.elapsed < Duration::from_secs(8), "{:?}", run.elapsed);
}

#[test]
fn hw_jog_after_hw_disable_fails() {
    let _one_at_a_time = serial();
    let emu = EmulatorHandle::spawn(EmulatorConfig { log_commands: false, ..EmulatorConfig::homed_at_standby() })
        .expect("emulator");
    let disabled = hw(emu.path(), &["disable"]);
    assert_eq!(disabled.code(), Some(0), "{disabled:?}");
    let run = hw(emu.path(), &["jog", "--joint", "1", "--speed", "0.5", "--seconds", "1.5"]);
    assert_device_failure(&run, "jog after disable", &["the arm did not move", "disabled"]);
}

#[test]
fn the_controller_stopped_answering_is_not_said_of_a_board_that_answers_impossibly() {
    let _one_at_a_time = serial();
    let (run, _emu, _peer) = hw_on(BoardMode::Erratic, &["status"]);
    assert_device_failure(&run, "status", &["answers are impossible"]);
    assert!(!run.stderr.contains("stopped answering"), "{run:?}");
}

#[test]
fn a_joint_beyond_its_limit_moves_back_only_inward_with_confirmation() {
    let _one_at_a_time = serial();
    let mut at = parol6_hw::units::STANDBY_STEPS;
    at[0] = 14_300; // J1 pushed 300 steps (2.6°) beyond its upper limit 14 000
    let emu = EmulatorHandle::spawn(EmulatorConfig {
        log_commands: true,
        initial_steps: at,
        ..EmulatorConfig::homed_at_standby()
    })
    .expect("emulator");
    let refused = hw(emu.path(), &["jog", "--joint", "1", "--speed", "-0.5", "--seconds", "1"]);
    refused.assert_refused("jog without confirmation", "--beyond-limit");
    let outward = hw(emu.path(), &["jog", "--joint", "1", "--speed", "0.5", "--seconds", "1", "--beyond-limit"]);
    outward.assert_refused("outward with confirmation", "only a jog back inside");
    emu.take_received();
    let ok = hw(emu.path(), &["jog", "--joint", "1", "--speed", "-0.5", "--seconds", "5", "--beyond-limit"]);
    let v = ok.json("jog back inside");
    assert_eq!(v["back_inside"], true, "{v}");
    let end = emu.snapshot().position_steps[0];
    assert!((13_800..=14_000).contains(&end), "J1 back inside, not far: {end}");
    let frames = emu.take_received();
    let lim = parol6_hw::units::limits_steps();
    for f in &frames {
        for (i, p) in f.command.fields.positions_steps.iter().enumerate() {
            assert!((lim[i].0..=lim[i].1).contains(p), "no position field outside the limits: {f:?}");
        }
        assert_ne!(f.command.code, 156, "no MOVE from beyond the limit");
    }
    assert!(frames.iter().any(|f| f.command.code == 123), "JOG frames moved it");
}

#[test]
fn hw_emulate_survives_an_invalid_utf8_line() {
    let _one_at_a_time = serial();
    let mut child = Command::new(env!("CARGO_BIN_EXE_parol6"))
        .args(["hw", "emulate", "--homed"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut path = String::new();
    out.read_line(&mut path).unwrap();
    assert!(path.starts_with("/dev/"), "{path}");
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(b"state\n\xff\xfe not utf-8\nquit\n").unwrap();
    stdin.flush().unwrap();
    let started = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s);
        }
        if started.elapsed() > Duration::from_secs(10) {
            child.kill().unwrap();
            child.wait().unwrap();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut out, &mut rest).unwrap();
    assert_eq!(status.and_then(|s| s.code()), Some(0), "quit after a bad line ends it; stdout {rest}");
    assert!(rest.contains("stdin line 2 is not UTF-8"), "the bad line is named: {rest}");
}

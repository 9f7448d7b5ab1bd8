//! The real `parol6_hw::Session` against the firmware emulator over a pseudo-terminal.
//! Timeouts are generous: these tests must pass on a loaded 2-core CI machine.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::time::{Duration, Instant};

use parol6_core::parol6::standby_rad;
use parol6_core::profile::ProfileKind;
use parol6_hw::emulator::{EmulatorConfig, EmulatorHandle, ReceivedFrame};
use parol6_hw::frame::CommandCode;
use parol6_hw::session::{HomingState, LinkState, MotionState, Session, SessionConfig};
use parol6_hw::units::{STANDBY_STEPS, limits_steps, max_speed_steps_s};

const LONG: Duration = Duration::from_secs(10);

fn start(config: EmulatorConfig) -> (EmulatorHandle, Session) {
    let emu = EmulatorHandle::spawn(config).expect("emulator");
    let session = Session::open(emu.path(), SessionConfig::default()).expect("session");
    session.wait_connected(LONG).expect("connected");
    (emu, session)
}

/// Every frame the host ever sent: targets within limits, zero speeds, never 69 / JOG.
fn assert_safe(frames: &[ReceivedFrame]) {
    let lim = limits_steps();
    let vmax = max_speed_steps_s();
    assert!(!frames.is_empty());
    for f in frames {
        let c = &f.command;
        assert_ne!(c.code, 69);
        assert_ne!(c.code, CommandCode::Jog.byte(), "jogging must stream MOVE targets");
        assert!(c.command().is_some(), "unknown code {}", c.code);
        for i in 0..6 {
            let p = c.fields.positions_steps[i];
            assert!((lim[i].0..=lim[i].1).contains(&p), "J{} target {p} outside {:?}", i + 1, lim[i]);
            assert!(c.fields.speeds_steps_s[i].abs() <= vmax[i]);
            assert_eq!(c.fields.speeds_steps_s[i], 0, "zero feed-forward");
        }
    }
}

fn hold_jog(session: &Session, joint: usize, fraction: f64, for_s: f64) {
    let end = Instant::now() + Duration::from_secs_f64(for_s);
    while Instant::now() < end {
        // At the limit, refreshing the jog further out is refused (and says so).
        if let Err(e) = session.jog(joint, fraction) {
            assert!(e.to_string().contains("limit"), "{e}; {:?}", session.snapshot().fault);
        }
        std::thread::sleep(Duration::from_millis(40));
    }
}

/// Waits until the emulator's counters stop changing.
fn settled(emu: &EmulatorHandle) -> [i32; 6] {
    let mut last = emu.snapshot().position_steps;
    let end = Instant::now() + LONG;
    loop {
        std::thread::sleep(Duration::from_millis(100));
        let now = emu.snapshot().position_steps;
        if now == last || Instant::now() > end {
            return now;
        }
        last = now;
    }
}

#[test]
fn connects_and_reports_boot_status() {
    let (emu, session) = start(EmulatorConfig::default());
    let s = session.wait_until(LONG, |s| s.status_frames >= 5).expect("status");
    assert_eq!(s.joint_steps, [0; 6]);
    assert!(!s.all_homed());
    assert!(!s.estop_pressed);
    assert_eq!(s.link, LinkState::Connected);
    assert!(s.loop_rate_hz > 0.0);
    assert!(s.status_age().is_some());
    // Unhomed at 0 steps: J3 is outside its limits, so motion is refused with a reason.
    let err = session.jog(0, 0.5).expect_err("outside limits");
    assert!(err.to_string().contains("home"), "{err}");
    drop(session);
    assert_safe(&emu.take_received());
}

#[test]
fn homes_then_moves_along_the_profile() {
    let (emu, session) = start(EmulatorConfig::default());
    session.home_blocking().expect("homing");
    let s = session.wait_until(LONG, |s| s.all_homed() && s.joint_steps == STANDBY_STEPS).expect("at standby");
    assert_eq!(s.homing, HomingState::Done);
    let mut goal = standby_rad().to_vec();
    goal[0] += 0.3;
    goal[1] -= 0.2;
    goal[4] += 0.25;
    let s = session.move_to_blocking(&goal, 0.8, ProfileKind::Trapezoidal, LONG).expect("move");
    assert_eq!(s.motion, MotionState::Holding);
    let expected = parol6_hw::units::joints_rad_to_steps(&goal).expect("steps");
    let at = settled(&emu);
    for i in 0..6 {
        assert!((at[i] - expected[i]).abs() <= 3, "J{} {} vs {}", i + 1, at[i], expected[i]);
    }
    let frames = emu.take_received();
    assert!(frames.iter().filter(|f| f.command.code == CommandCode::Home.byte()).count() >= 1);
    assert!(frames.iter().any(|f| f.command.code == CommandCode::Move.byte()));
    assert_safe(&frames);
    // A goal outside the limits is refused before anything is sent.
    let mut bad = standby_rad().to_vec();
    bad[1] = 0.5;
    assert!(session.move_to(&bad, 0.5, ProfileKind::JerkLimited).is_err());
}

#[test]
fn jog_moves_and_stops_on_release_and_deadman() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    hold_jog(&session, 0, 0.5, 0.5);
    assert!(matches!(session.snapshot().motion, MotionState::Jogging { joint: 0, .. }));
    session.jog_release().expect("release");
    let after_release = settled(&emu);
    assert!(after_release[0] > STANDBY_STEPS[0] + 500, "J1 moved: {after_release:?}");
    assert_eq!(after_release[1..], STANDBY_STEPS[1..], "other joints stay put");
    session.wait_until(LONG, |s| s.motion == MotionState::Holding).expect("holding");
    // Dead-man: one jog call and no refresh → stops by itself within ~200 ms.
    session.jog(0, -1.0).expect("jog");
    session.wait_until(LONG, |s| s.motion == MotionState::Holding).expect("dead-man stop");
    let p1 = settled(&emu);
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(emu.snapshot().position_steps, p1, "no motion after the dead-man stop");
    assert!(p1[0] < after_release[0]);
    assert_safe(&emu.take_received());
}

#[test]
fn jog_stops_at_the_joint_limit() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    // J5 jog max 8000 steps/s; the limit is 6400 steps away.
    hold_jog(&session, 4, 1.0, 1.5);
    session.jog_release().expect("release");
    let at = settled(&emu);
    assert!(at[4] <= 6400 && at[4] > 6000, "J5 {}", at[4]);
    assert_safe(&emu.take_received());
}

#[test]
fn estop_stops_motion_disables_and_needs_enable() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    session.jog(1, 0.5).expect("jog");
    emu.set_estop_pressed(true);
    let s = session.wait_until(LONG, |s| s.estop_pressed).expect("estop seen");
    assert!(s.needs_enable);
    session.wait_until(LONG, |s| s.last_command == Some(CommandCode::Disable)).expect("disable sent");
    // sent is not yet read: the board latches DISABLE when its receiver takes the frame (a
    // loaded machine can delay the pty by a few ms)
    let t0 = std::time::Instant::now();
    while !emu.snapshot().disabled {
        assert!(t0.elapsed() < LONG, "emulator latched DISABLE");
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(session.jog(1, 0.5).is_err());
    assert!(session.enable().is_err(), "enable refused while pressed");
    emu.set_estop_pressed(false);
    session.wait_until(LONG, |s| !s.estop_pressed).expect("released");
    let err = session.jog(1, 0.5).expect_err("needs enable");
    assert!(err.to_string().contains("enable"), "{err}");
    session.enable().expect("enable");
    session.wait_until(LONG, |s| !s.needs_enable && s.enabled == Some(true)).expect("enabled");
    session.wait_until(LONG, |_| !emu.snapshot().disabled).expect("board enabled");
    let before = settled(&emu);
    hold_jog(&session, 1, 0.5, 0.4);
    session.jog_release().expect("release");
    let after = settled(&emu);
    assert!(after[1] > before[1], "jog works again after enable");
    assert_safe(&emu.take_received());
}

#[test]
fn silent_board_is_link_loss_and_recovers() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    session.jog(0, 0.5).expect("jog");
    emu.set_mute(true);
    let s = session.wait_until(LONG, |s| s.link == LinkState::Lost).expect("lost");
    assert!(s.fault.as_deref().unwrap_or("").contains("link lost"), "{:?}", s.fault);
    assert!(matches!(s.motion, MotionState::Idle), "motion stopped: {:?}", s.motion);
    assert!(session.jog(0, 0.5).is_err());
    emu.set_mute(false);
    session.wait_until(LONG, |s| s.link == LinkState::Connected).expect("recovered");
    // Motion was cancelled, not resumed.
    assert_eq!(session.snapshot().motion, MotionState::Idle);
    assert_safe(&emu.take_received());
}

#[test]
fn port_closed_mid_jog_is_reported_without_panic() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    session.jog(2, 0.5).expect("jog");
    std::thread::sleep(Duration::from_millis(100));
    emu.stop();
    let s = session.wait_until(LONG, |s| s.link == LinkState::Lost).expect("lost");
    assert!(s.fault.is_some());
    assert_eq!(s.motion, MotionState::Idle);
    assert!(session.jog(2, 0.5).is_err());
    // Still alive and retrying; closing is clean.
    std::thread::sleep(Duration::from_millis(1200));
    assert_ne!(session.snapshot().link, LinkState::Closed);
    session.close();
}

#[test]
fn closing_leaves_the_board_with_a_zero_speed_idle_frame() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    hold_jog(&session, 5, 0.3, 0.3);
    session.close();
    let frames = emu.take_received();
    let last = frames.last().expect("frames");
    assert_eq!(last.command.code, CommandCode::Idle.byte());
    assert_eq!(last.command.fields.speeds_steps_s, [0; 6]);
    assert_safe(&frames);
}

#[test]
fn outputs_and_gripper_reach_the_board() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    session.set_output(1, true).expect("out1");
    session.set_gripper(200, 128, 500).expect("gripper");
    let s = session.wait_until(LONG, |s| s.io[2] && s.gripper_position == 200).expect("echo");
    assert!(!s.io[3]);
    assert_eq!(s.gripper_current_ma, 500);
    assert!(session.set_output(3, true).is_err());
    assert!(session.set_gripper(10, 10, 5000).is_err());
    emu.set_inputs(true, false);
    session.wait_until(LONG, |s| s.io[0] && !s.io[1]).expect("inputs");
}

#[test]
fn homing_fails_clearly_after_its_timeout() {
    let emu =
        EmulatorHandle::spawn(EmulatorConfig { home_duration_s: 60.0, ..EmulatorConfig::default() }).expect("emulator");
    let cfg = SessionConfig { home_timeout: Duration::from_millis(500), ..SessionConfig::default() };
    let session = Session::open(emu.path(), cfg).expect("session");
    session.wait_connected(LONG).expect("connected");
    let err = session.home_blocking().expect_err("timeout");
    assert!(err.to_string().contains("homing failed"), "{err}");
    assert!(matches!(session.snapshot().homing, HomingState::Failed(_)));
}

#[test]
fn rate_is_configurable_and_checked() {
    let emu = EmulatorHandle::spawn(EmulatorConfig::default()).expect("emulator");
    assert!(Session::open(emu.path(), SessionConfig { rate_hz: 20.0, ..SessionConfig::default() }).is_err());
    let session =
        Session::open(emu.path(), SessionConfig { rate_hz: 250.0, ..SessionConfig::default() }).expect("session");
    session.wait_connected(LONG).expect("connected");
    let s = session.wait_until(LONG, |s| s.frames_sent >= 300).expect("frames");
    // Loose bound only: the exact rate is measured by `parol6 bench serial`.
    assert!(s.loop_rate_hz > 100.0, "{}", s.loop_rate_hz);
}

/// Regression: "jogging J1 (either end), J2 (lower) or J3 (upper) into its limit locks out all
/// motion until re-homing". The arm ends exactly on the step limit, which is inside the limits,
/// and motion back inside (and of other joints) is accepted.
#[test]
fn jogging_into_the_limit_locks_out_all_motion_until_rehoming() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    let lim = limits_steps();
    for (joint, dir, seconds) in [(0, 1.0, 0.6), (0, -1.0, 2.2), (1, -1.0, 1.2), (2, 1.0, 1.5)] {
        hold_jog(&session, joint, dir, seconds);
        session.jog_release().expect("release");
        let at = settled(&emu);
        let limit = if dir > 0.0 { lim[joint].1 } else { lim[joint].0 };
        assert_eq!(at[joint], limit, "J{} reached its limit exactly", joint + 1);
        let s = session.wait_until(LONG, |s| s.joint_steps[joint] == limit).expect("measured");
        assert!(s.motion_allowed().is_ok(), "not locked out: {:?}", s.motion_allowed());
        // Further out is refused with a reason; back inside works.
        let err = session.jog(joint, dir).expect_err("further out");
        assert!(err.to_string().contains("limit"), "{err}");
        hold_jog(&session, joint, -dir * 0.5, 0.3);
        session.jog_release().expect("release");
        let back = settled(&emu);
        assert!((back[joint] - limit).abs() > 100, "J{} moved back inside: {}", joint + 1, back[joint]);
        // Other joints move too.
        hold_jog(&session, 5, 0.3, 0.2);
        session.jog_release().expect("release");
    }
    // ROBOT.md's exact maximum in degrees is accepted (`hw move --joints 123.046875,… --deg`).
    let mut goal = standby_rad().to_vec();
    goal[0] = 123.046875f64.to_radians();
    let s = session.move_to_blocking(&goal, 1.0, ProfileKind::Trapezoidal, LONG).expect("move to J1 max");
    assert_eq!(s.target_steps.map(|t| t[0]), Some(14_000), "commanded exactly to the step limit");
    assert!((s.joint_steps[0] - 14_000).abs() <= 3, "{}", s.joint_steps[0]);
    assert_safe(&emu.take_received());
}

/// "Connecting to a port where no PAROL6 answers says connected": it now says that no
/// controller answers, and enabled never reads true without a status.
#[test]
fn a_port_where_no_parol6_answers_is_reported_as_such() {
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    emu.set_mute(true);
    let session = Session::open(emu.path(), SessionConfig::default()).expect("session");
    let s = session.wait_until(LONG, |s| s.link == LinkState::NoAnswer).expect("no answer");
    let fault = s.fault.clone().unwrap_or_default();
    assert!(fault.contains("no PAROL6 answered on") && fault.contains("within 3 s"), "{fault}");
    assert!(s.status.is_none());
    assert_ne!(s.enabled, Some(true));
    assert!(session.jog(0, 0.5).is_err());
    // It answers later: connected, and the stale fault is gone.
    emu.set_mute(false);
    let s = session.wait_until(LONG, |s| s.link == LinkState::Connected).expect("answered");
    assert!(s.fault.is_none(), "{:?}", s.fault);
}

/// Issue 32 (minor): after the E-stop is released and ENABLE succeeds, the "E-stop pressed"
/// fault text goes away (it stayed red under the LEDs until a CLEAR ERROR).
#[test]
fn estop_text_clears_after_release_and_enable() {
    let (emu, session) = start(EmulatorConfig::homed_at_standby());
    emu.set_estop_pressed(true);
    let s = session.wait_until(LONG, |s| s.estop_pressed && s.fault.is_some()).expect("estop seen");
    assert!(s.fault.as_deref().unwrap_or("").contains("E-stop"), "{:?}", s.fault);
    emu.set_estop_pressed(false);
    session.wait_until(LONG, |s| !s.estop_pressed).expect("released");
    session.enable().expect("enable");
    let s = session.wait_until(LONG, |s| !s.needs_enable && s.enabled == Some(true)).expect("enabled");
    // one more period, so a stale text would have been published again
    std::thread::sleep(Duration::from_millis(50));
    let s2 = session.snapshot();
    assert_eq!(s2.fault, None, "fault after enable: {:?} (at enable: {:?})", s2.fault, s.fault);
}

/// Issue 32 (major 8): a recording of the robot starts at the board's first answer: the tap
/// sends nothing before the first valid status (it sent the session's all-zero joints, J3 = 0
/// far outside its limit, so a replay opened on a folded arm with false "at limit" events).
#[test]
fn the_first_tap_sample_is_the_boards_first_status_not_zeros() {
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    let (tx, rx) = crossbeam_channel::bounded(1024);
    let session = Session::open_with_tap(emu.path(), SessionConfig::default(), Some(tx)).expect("session");
    session.wait_connected(LONG).expect("connected");
    std::thread::sleep(Duration::from_millis(200));
    let first = rx.try_recv().expect("samples arrive");
    let standby = standby_rad();
    for (j, want) in standby.iter().enumerate() {
        assert!((first.measured_q[j] - want).abs() < 1e-3, "first sample: measured {:?}", first.measured_q);
        assert!((first.commanded.q[j] - want).abs() < 1e-3, "first sample: commanded {:?}", first.commanded.q);
    }
}

/// Issue 32 (major 8): samples the tap could not take are counted, not silently dropped, and
/// the count is published in the snapshot.
#[test]
fn a_full_tap_counts_the_dropped_samples() {
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    let (tx, rx) = crossbeam_channel::bounded(2);
    let session = Session::open_with_tap(emu.path(), SessionConfig::default(), Some(tx)).expect("session");
    session.wait_connected(LONG).expect("connected");
    let s = session.wait_until(LONG, |s| s.tap_dropped >= 5).expect("drops counted");
    assert!(s.tap_dropped >= 5, "{}", s.tap_dropped);
    assert_eq!(rx.len(), 2, "the tap kept the first samples");
    assert!(session.snapshot().to_json()["tap_dropped"].as_u64().unwrap() >= 5);
}

/// The emulator's log of received frames stops at `log_frames_max` until taken (the window's
/// built-in emulator keeps a minute; the default ~33 minutes of a 100 Hz host stayed resident in
/// a window left running), and logs again once taken.
#[test]
fn the_emulators_log_keeps_at_most_its_cap_until_taken() {
    let (emu, session) = start(EmulatorConfig { log_frames_max: 20, ..EmulatorConfig::homed_at_standby() });
    let at = session.snapshot().status_frames;
    session.wait_until(LONG, |s| s.status_frames >= at + 40).expect("40 more cycles");
    assert_eq!(emu.take_received().len(), 20, "the log stops at its cap");
    let at = session.snapshot().status_frames;
    session.wait_until(LONG, |s| s.status_frames >= at + 5).expect("5 more cycles");
    let again = emu.take_received().len();
    assert!((1..=20).contains(&again), "logged again once taken: {again}");
}

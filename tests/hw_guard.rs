//! The session's last line of defence against a corrupted status stream, end to end: the real
//! `parol6_hw::Session` against the firmware emulator with status replies altered in flight.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use parol6_hw::emulator::{EmulatorConfig, EmulatorHandle, ReceivedFrame};
use parol6_hw::frame::CommandCode;
use parol6_hw::session::guard::max_target_step;
use parol6_hw::session::{Session, SessionConfig};
use parol6_hw::units::{STANDBY_STEPS, limits_steps};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};

const LONG: Duration = Duration::from_secs(10);
const PERIOD_S: f64 = 0.01;

fn start() -> (EmulatorHandle, Session) {
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    let session = Session::open(emu.path(), SessionConfig::default()).expect("session");
    session.wait_connected(LONG).expect("connected");
    (emu, session)
}

/// Jogs `joint` for `seconds`, refreshing every 40 ms; refusals (the link or a fault stopped
/// motion) are fine here.
fn hold_jog(session: &Session, joint: usize, fraction: f64, seconds: f64) {
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    while Instant::now() < end {
        let _ = session.jog(joint, fraction);
        std::thread::sleep(Duration::from_millis(40));
    }
    let _ = session.jog_release();
}

/// Every MOVE target within the step limits and within the speed limit × elapsed periods of
/// the previous MOVE target (frames in between count as periods).
fn assert_targets_bounded(frames: &[ReceivedFrame]) {
    let lim = limits_steps();
    let mut prev: Option<([i32; 6], u32)> = None;
    for f in frames {
        let c = &f.command;
        if c.code != CommandCode::Move.byte() {
            prev = prev.map(|(p, n)| (p, n + 1));
            if c.code == CommandCode::Idle.byte() || c.code == CommandCode::Disable.byte() {
                prev = None; // motion restarts from the measured position
            }
            continue;
        }
        let t = c.fields.positions_steps;
        for i in 0..6 {
            assert!((lim[i].0..=lim[i].1).contains(&t[i]), "J{} target {} outside {:?}", i + 1, t[i], lim[i]);
            if let Some((p, n)) = prev {
                let step = (t[i] - p[i]).abs();
                assert!(step <= max_target_step(i, PERIOD_S, n), "J{} target jumped {step} steps in {n} frames", i + 1);
            }
        }
        prev = Some((t, 1));
    }
}

/// Regression: "a single bit error in one status frame makes a joint that is not being moved
/// twitch at 3× its speed limit". During a jog of J4, bit 11 of J1's position is flipped in
/// one status reply: J1's MOVE target never changes and the frame is counted as implausible.
#[test]
fn a_single_bit_error_in_one_status_frame_makes_a_joint_twitch() {
    let (emu, session) = start();
    let armed = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&armed);
    emu.set_status_corruptor(Some(Box::new(move |_, status| {
        if flag.swap(false, Ordering::Relaxed) {
            status.positions_steps[0] ^= 1 << 11;
        }
        Duration::ZERO
    })));
    let _ = emu.take_received();
    let end = Instant::now() + Duration::from_millis(700);
    let mut flipped = false;
    while Instant::now() < end {
        if let Err(e) = session.jog(3, 0.5) {
            panic!("jog J4: {e}; {:?}", session.snapshot().fault);
        }
        std::thread::sleep(Duration::from_millis(40));
        if !flipped && Instant::now() + Duration::from_millis(400) > end {
            armed.store(true, Ordering::Relaxed);
            flipped = true;
        }
    }
    session.jog_release().expect("release");
    std::thread::sleep(Duration::from_millis(100));
    let s = session.snapshot();
    assert!(!armed.load(Ordering::Relaxed), "the flip was sent");
    assert_eq!(s.implausible_frames, 1, "the flipped frame is counted");
    assert_eq!(s.guard_trips, 0);
    assert!(s.fault.is_none(), "{:?}", s.fault);
    let frames = emu.take_received();
    let moves: Vec<_> = frames.iter().filter(|f| f.command.code == CommandCode::Move.byte()).collect();
    assert!(moves.len() > 30);
    for f in &moves {
        assert_eq!(f.command.fields.positions_steps[0], STANDBY_STEPS[0], "J1 target never changes");
    }
    assert!(moves.last().map(|f| f.command.fields.positions_steps[3]).unwrap_or(0) > 500, "J4 jogged");
    assert_targets_bounded(&frames);
}

/// Persistent garbage stops motion with a clear fault, and motion never starts from a lone
/// garbage frame.
#[test]
fn garbage_status_stops_motion_with_a_fault() {
    let (emu, session) = start();
    emu.set_status_corruptor(Some(Box::new(|i, status| {
        if i % 2 == 0 {
            status.positions_steps[1] = -8_000_000;
        }
        Duration::ZERO
    })));
    hold_jog(&session, 0, 0.5, 0.5);
    let s = session.snapshot();
    assert!(s.implausible_frames >= 5, "{}", s.implausible_frames);
    emu.set_status_corruptor(Some(Box::new(|_, status| {
        status.positions_steps[1] = -8_000_000;
        Duration::ZERO
    })));
    let s = session.wait_until(LONG, |s| s.fault.as_deref().unwrap_or("").contains("impossible")).expect("fault");
    assert_eq!(s.motion, parol6_hw::MotionState::Idle, "motion stopped");
    assert_targets_bounded(&emu.take_received());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4, ..ProptestConfig::default() })]

    /// An adversarial status stream (random garbage positions, random bit flips, random reply
    /// delays) while jogging: no MOVE frame ever steps a joint target faster than its ROBOT.md
    /// §5 limit, and no target leaves the step limits.
    #[test]
    fn adversarial_status_never_moves_targets_faster_than_the_limits(seed in any::<u64>()) {
        let (emu, session) = start();
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        emu.set_status_corruptor(Some(Box::new(move |_, status| {
            let roll: f64 = rng.random();
            if roll < 0.08 {
                for p in &mut status.positions_steps {
                    *p = rng.random_range(-8_388_608..8_388_607);
                }
            } else if roll < 0.16 {
                let j = rng.random_range(0..6);
                status.positions_steps[j] ^= 1 << rng.random_range(0..23);
            }
            if rng.random::<f64>() < 0.1 {
                Duration::from_millis(rng.random_range(0..25))
            } else {
                Duration::ZERO
            }
        })));
        let _ = emu.take_received();
        hold_jog(&session, 0, 0.8, 0.5);
        hold_jog(&session, 3, -1.0, 0.4);
        hold_jog(&session, 2, 0.6, 0.4);
        let frames = emu.take_received();
        assert_targets_bounded(&frames);
        prop_assert!(session.snapshot().implausible_frames > 0);
    }
}

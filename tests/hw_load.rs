//! The session against the firmware emulator at 100 Hz for about 10 s while two busy threads
//! keep both cores of a CI machine saturated: the link must never be reported lost, and the
//! command period must keep its p99 jitter within 2 ms (measured from the recorded frame write
//! times, and cross-checked with the snapshot's own statistic unless steal time stretched one of
//! the periods that statistic covers). On a virtual machine a loss
//! during which the hypervisor took a vCPU away (steal time, `tests/support/steal_watch.rs`)
//! is printed and not counted: the emulated board on that vCPU was frozen.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test
#![cfg(unix)]

use std::hint::black_box;
use std::time::{Duration, Instant};

use parol6_core::motion::{MotionCommand, RobotBackend};
use parol6_hw::emulator::{EmulatorConfig, EmulatorHandle};
use parol6_hw::session::{LinkState, Session, SessionConfig, TIMING_WINDOW};
use parol6_tests::steal_watch::StealWatch;

/// How long the session runs under load.
const RUN: Duration = Duration::from_secs(10);
/// Busy threads (one per core of a 2-core CI machine).
const BURNERS: usize = 2;
/// Allowed p99 of |period − nominal|, ms.
const JITTER_P99_MAX_MS: f64 = 2.0;
/// A gap between two frames this long (over half the status timeout) means the host did not
/// schedule the process at all.
const HOST_FREEZE_MS: f64 = 40.0;
/// Steal time of one vCPU this large around a link loss excuses it (half the status timeout).
const STEAL_EXCUSES: Duration = Duration::from_millis(40);
/// How far before and after a link loss steal time is looked for.
const STEAL_WINDOW: Duration = Duration::from_millis(250);
/// Steal growths seen this long before the end of a stretched period count for it.
const STEAL_BEFORE_PERIOD_END: Duration = Duration::from_millis(30);

/// Spins until `until` (stops by itself), returning a value so the work is not optimised away.
fn burn_until(until: Instant) -> u64 {
    let mut x = 0x9E37_79B9_7F4A_7C15_u64;
    let mut rounds = 0u64;
    while Instant::now() < until {
        for _ in 0..10_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
        }
        rounds += 1;
        black_box(x);
    }
    rounds
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    parol6_core::stats::percentile(sorted, p).unwrap_or(0.0)
}

#[test]
fn session_keeps_its_period_and_link_with_both_cores_busy() {
    // the fake robot's link (a local socket: a pty's bytes wait for a kernel worker that a busy
    // host starves, issue 32)
    let emu =
        EmulatorHandle::spawn_socket(EmulatorConfig { log_commands: false, ..EmulatorConfig::homed_at_standby() })
            .expect("emulator");
    let config = SessionConfig { write_log_capacity: 8192, ..SessionConfig::default() };
    let nominal_s = config.period().as_secs_f64();
    let session = Session::open(emu.path(), config).expect("session");
    session.wait_connected(Duration::from_secs(10)).expect("connected");
    session.wait_until(Duration::from_secs(10), |s| s.status_frames >= 20).expect("status flowing");
    let _ = session.take_write_times();

    let started = Instant::now();
    let end = started + RUN;
    let burners: Vec<_> = (0..BURNERS)
        .map(|i| {
            std::thread::Builder::new()
                .name(format!("cpu-burner-{i}"))
                .spawn(move || burn_until(end + Duration::from_millis(200)))
                .expect("burner thread")
        })
        .collect();

    // Jog J1 back and forth (a realistic stream of changing MOVE targets) and watch the link.
    let mut lost_seen = 0u64;
    let mut link_states = Vec::new();
    let mut losses: Vec<(Instant, String)> = Vec::new();
    let steal = StealWatch::start();
    let mut last_jog = Instant::now() - Duration::from_secs(1);
    let mut write_times = Vec::new();
    while Instant::now() < end {
        let s = session.snapshot();
        if s.link != LinkState::Connected {
            lost_seen += 1;
            if link_states.last() != Some(&s.link) {
                link_states.push(s.link);
                let silent_ms =
                    s.last_status_at.map(|t| s.published_at.saturating_duration_since(t).as_secs_f64() * 1e3);
                losses.push((
                    Instant::now(),
                    format!(
                        "{:?} at {:.3} s: fault {:?}, silent {silent_ms:?} ms, status {} missing {}",
                        s.link,
                        started.elapsed().as_secs_f64(),
                        s.fault,
                        s.status_frames,
                        s.missing_replies
                    ),
                ));
            }
        }
        if last_jog.elapsed() >= Duration::from_millis(50) {
            let second = started.elapsed().as_secs();
            let fraction = if second.is_multiple_of(2) { 0.3 } else { -0.3 };
            let _ = RobotBackend::send(&session, MotionCommand::JogJoint { joint: 0, fraction });
            last_jog = Instant::now();
        }
        write_times.extend(session.take_write_times());
        std::thread::sleep(Duration::from_millis(2));
    }
    let _ = RobotBackend::send(&session, MotionCommand::JogRelease);
    write_times.extend(session.take_write_times());
    let snap = session.snapshot();
    session.close();
    let burner_rounds: u64 = burners.into_iter().map(|b| b.join().expect("burner thread")).sum();
    let steal = steal.finish();
    // A loss while the hypervisor held a vCPU for a freeze this long is the host's: the emulated
    // board (on the frozen vCPU) could not answer. Real boards are not frozen by the host.
    let (excused, false_losses): (Vec<_>, Vec<_>) =
        losses.iter().partition(|(at, _)| steal.stolen_near(*at, STEAL_WINDOW, STEAL_WINDOW) >= STEAL_EXCUSES);
    for (_, what) in &excused {
        println!("link loss while the hypervisor stole ≥ {STEAL_EXCUSES:?} of a vCPU: not counted: {what}");
    }

    let intervals_ms: Vec<f64> = write_times.windows(2).map(|w| (w[1] - w[0]).as_secs_f64() * 1e3).collect();
    // A period stretched while the hypervisor held a vCPU (steal of at least half the excess,
    // seen as the vCPU ran again) is the host's, not the session's: left out of the jitter.
    let stolen_period = |w: &[Instant]| {
        let excess = (w[1] - w[0]).saturating_sub(Duration::from_secs_f64(nominal_s));
        excess > Duration::from_millis(2)
            && steal.stolen_near(w[1], STEAL_BEFORE_PERIOD_END, STEAL_WINDOW) >= excess / 2
    };
    let stolen_periods = write_times.windows(2).filter(|w| stolen_period(w)).count();
    let mut jitter_ms: Vec<f64> = write_times
        .windows(2)
        .filter(|w| !stolen_period(w))
        .map(|w| ((w[1] - w[0]).as_secs_f64() - nominal_s).abs() * 1e3)
        .collect();
    jitter_ms.sort_by(f64::total_cmp);
    let p99 = percentile(&jitter_ms, 0.99);
    let p50 = percentile(&jitter_ms, 0.5);
    let max = jitter_ms.last().copied().unwrap_or(0.0);
    let mean_ms = intervals_ms.iter().sum::<f64>() / intervals_ms.len().max(1) as f64;
    println!(
        "load: {} frames in {:.1} s (mean period {mean_ms:.3} ms), jitter |period − 10 ms| p50 {p50:.3} ms, \
         p99 {p99:.3} ms, max {max:.3} ms; snapshot p99 {:.3} ms max {:.3} ms (last {TIMING_WINDOW} periods), loop {:.1} Hz; \
         status {} missing replies {} invalid {}; link not connected in {lost_seen} polls {link_states:?}; \
         fault {:?}; burner rounds {burner_rounds}; steal {:?} in {} growths, {stolen_periods} periods \
         stretched by it left out of the jitter",
        write_times.len(),
        RUN.as_secs_f64(),
        snap.period_jitter_p99_ms,
        snap.period_jitter_max_ms,
        snap.loop_rate_hz,
        snap.status_frames,
        snap.missing_replies,
        snap.invalid_frames,
        snap.fault,
        steal.total(),
        steal.events.len(),
    );
    assert!(stolen_periods * 10 <= intervals_ms.len(), "over 10 % of the periods were stretched by steal time");
    assert!(write_times.len() >= 900, "only {} frames written in {:.0} s", write_times.len(), RUN.as_secs_f64());
    assert!(burner_rounds > 0);
    // A link loss also counts against the session unless the whole host froze: a gap between two
    // of the session's own frames of more than half the status timeout means this process was
    // not scheduled at all, so the emulator could not answer either.
    let host_froze = max >= HOST_FREEZE_MS;
    if !false_losses.is_empty() && host_froze {
        println!("link loss during a host freeze of {max:.1} ms: not counted against the session");
    }
    assert!(
        false_losses.is_empty() || host_froze,
        "false link loss under load: {false_losses:?}, fault {:?} (largest period gap {max:.1} ms)",
        snap.fault
    );
    assert!(p99 <= JITTER_P99_MAX_MS, "period jitter p99 {p99:.3} ms > {JITTER_P99_MAX_MS} ms (max {max:.3} ms)");
    // The snapshot's statistic covers the last TIMING_WINDOW periods and cannot tell steal time
    // apart: a stretched period there (and the short one that catches up after it) is the host's.
    let window_start = write_times.len().saturating_sub(TIMING_WINDOW + 1);
    let stolen_in_window = write_times[window_start..].windows(2).filter(|w| stolen_period(w)).count();
    if stolen_in_window > 0 {
        println!(
            "snapshot jitter not checked: {stolen_in_window} of its last {TIMING_WINDOW} periods were stretched by steal time"
        );
    } else {
        assert!(
            snap.period_jitter_p99_ms <= JITTER_P99_MAX_MS,
            "snapshot period jitter p99 {:.3} ms > {JITTER_P99_MAX_MS} ms",
            snap.period_jitter_p99_ms
        );
    }
}

//! The threaded simulation: commands through the handle take effect, refusals surface in the
//! snapshot with increasing ids, the snapshot advances on its own, shutdown is clean. Waits are
//! generous (a loaded CI machine); no timing thresholds here (those are in `parol6 bench`).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use parol6_core::motion::MotionCommand;
use std::time::{Duration, Instant};

use parol6_core::RobotModel;
use parol6_core::parol6::standby_rad;
use parol6_core::profile::ProfileKind;
use parol6_core::sim::{SimCommand, SimConfig, SimError, SimHandle, SimMode, SimSnapshot};

fn wait_for(h: &SimHandle, what: &str, ok: impl Fn(&SimSnapshot) -> bool) -> std::sync::Arc<SimSnapshot> {
    let end = Instant::now() + Duration::from_secs(20);
    loop {
        let s = h.snapshot();
        if ok(&s) {
            return s;
        }
        assert!(Instant::now() < end, "timed out waiting for {what}; last snapshot at t = {} s", s.sim_time_s);
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn the_thread_steps_and_applies_commands() {
    let h = SimHandle::spawn(RobotModel::parol6(), SimConfig::default()).expect("spawns");
    assert_eq!(h.model().dof(), 6);
    let first = h.snapshot();
    wait_for(&h, "time to advance", |s| s.seq > first.seq + 10);
    let goal = vec![1.0, -1.2, 2.8, 0.3, -0.4, 2.0];
    h.send(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal.clone(),
        speed_fraction: 1.0,
        profile: ProfileKind::JerkLimited,
    }))
    .expect("queued");
    let s = wait_for(&h, "the move to start", |s| s.moving || max_abs_diff(&s.q, &goal) < 1e-3);
    assert_eq!(s.target_q, goal);
    let s = wait_for(&h, "the goal", |s| !s.moving && max_abs_diff(&s.q, &goal) < 1e-3);
    assert!(s.last_command_latency_ns.is_some());
    assert_eq!(s.link_poses.len(), h.model().links.len());
    assert!(s.last_error.is_none());
    let stats = h.stats();
    assert!(stats.steps > 0 && stats.commands >= 1);
    assert!(!h.drain_latencies_ns().is_empty());
    h.shutdown();
}

#[test]
fn refusals_surface_in_the_snapshot_with_increasing_ids() {
    let h = SimHandle::spawn(RobotModel::parol6(), SimConfig::default()).expect("spawns");
    let mut bad = standby_rad().to_vec();
    bad[1] = 1.0; // J2 far above its limit
    h.send(SimCommand::Motion(MotionCommand::follow(bad.clone()))).expect("queued");
    let s1 = wait_for(&h, "the first refusal", |s| s.last_error.is_some());
    let (id1, msg1) = s1.last_error.clone().expect("error");
    assert!(msg1.contains("J2"), "{msg1}");
    h.send(SimCommand::Motion(MotionCommand::follow(vec![1.0; 2]))).expect("queued");
    let s2 = wait_for(&h, "the second refusal", |s| s.last_error.as_ref().is_some_and(|(id, _)| *id > id1));
    let (_, msg2) = s2.last_error.clone().expect("error");
    assert!(msg2.contains("expected 6"), "{msg2}");
    // the robot did not move
    assert!(max_abs_diff(&s2.q, &standby_rad()) < 1e-3);
    drop(h); // Drop stops the thread too
}

#[test]
fn kinematic_mode_and_teleport_through_the_handle() {
    let config = SimConfig { mode: SimMode::Kinematic, ..SimConfig::default() };
    let h = SimHandle::spawn(RobotModel::parol6(), config).expect("spawns");
    let q = vec![0.4, -1.0, 2.6, 0.2, 0.3, 1.0];
    h.send(SimCommand::Teleport(q.clone())).expect("queued");
    // the PAROL6's joints are its simulated drives' step counters: the teleport lands on the
    // nearest whole motor step of each joint
    let within_half_a_step = |s: &SimSnapshot| {
        s.q.iter().zip(&q).enumerate().all(|(j, (a, b))| {
            (parol6_core::motion::stepper::steps_of_rad(j, *a) - parol6_core::motion::stepper::steps_of_rad(j, *b))
                .abs()
                <= 0.5 + 1e-9
        })
    };
    wait_for(&h, "the teleport", |s| within_half_a_step(s) && s.mode == SimMode::Kinematic);
    h.send(SimCommand::SetMode(SimMode::Dynamic)).expect("queued");
    h.send(SimCommand::Motion(MotionCommand::home())).expect("queued");
    wait_for(&h, "home", |s| s.mode == SimMode::Dynamic && !s.moving && max_abs_diff(&s.q, &standby_rad()) < 1e-3);
    h.shutdown();
}

#[test]
fn every_accepted_command_is_applied_and_a_full_queue_is_reported() {
    let h = SimHandle::spawn(RobotModel::parol6(), SimConfig::default()).expect("spawns");
    let (mut ok, mut full) = (0u64, 0u64);
    for _ in 0..20_000 {
        match h.send(SimCommand::Motion(MotionCommand::Stop)) {
            Ok(()) => ok += 1,
            Err(SimError::ChannelFull) => full += 1,
            Err(e) => panic!("unexpected {e}"),
        }
    }
    assert_eq!(ok + full, 20_000);
    let end = Instant::now() + Duration::from_secs(20);
    while h.stats().commands < ok {
        assert!(Instant::now() < end, "only {} of {ok} accepted commands applied", h.stats().commands);
        std::thread::sleep(Duration::from_millis(5));
    }
    assert_eq!(h.stats().commands, ok);
    assert_eq!(h.drain_latencies_ns().len() as u64, ok);
    h.shutdown();
}

/// Steps per wake-up over `window` (the thread's own counters, no timing threshold).
fn steps_per_wake(h: &SimHandle, window: Duration) -> f64 {
    let a = h.stats();
    std::thread::sleep(window);
    let b = h.stats();
    (b.steps - a.steps) as f64 / (b.wakes - a.wakes).max(1) as f64
}

#[test]
fn a_resting_arm_wakes_the_thread_seldom_and_a_command_still_moves_it() {
    let h = SimHandle::spawn(RobotModel::parol6(), SimConfig::default()).expect("spawns");
    // the arm settles under gravity, rests after 0.5 s still, then the thread wakes every 50 steps
    let end = Instant::now() + Duration::from_secs(20);
    let mut ratio = steps_per_wake(&h, Duration::from_millis(300));
    while ratio < 25.0 {
        assert!(Instant::now() < end, "still waking every {ratio:.1} steps after 20 s at rest");
        ratio = steps_per_wake(&h, Duration::from_millis(300));
    }
    let rest = h.snapshot();
    assert!(!rest.moving);
    // every step is still taken: simulated time keeps up with the wall clock
    let goal = vec![1.0, -1.2, 2.8, 0.3, -0.4, 2.0];
    h.send(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal.clone(),
        speed_fraction: 1.0,
        profile: ProfileKind::JerkLimited,
    }))
    .unwrap();
    let moving = wait_for(&h, "the move to start", |s| s.moving || max_abs_diff(&s.q, &goal) < 1e-3);
    assert!(moving.commands_applied > rest.commands_applied);
    // while moving the thread wakes every few steps again
    assert!(steps_per_wake(&h, Duration::from_millis(200)) < 25.0 || !h.snapshot().moving);
    let done = wait_for(&h, "the goal", |s| !s.moving && max_abs_diff(&s.q, &goal) < 2e-3);
    assert!(max_abs_diff(&done.target_q, &goal) < 1e-9);
    h.shutdown();
}

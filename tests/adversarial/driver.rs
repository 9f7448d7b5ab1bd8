//! The adversarial lanes' driver: realistic motion through `RobotBackend` (jogs with
//! refreshes ended by release, stop or the dead-man; profiled moves of 1–3 joints, sometimes
//! stopped midway; stops; re-enabling after E-stops), logging when each joint was commanded.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use parol6_core::motion::{BackendError, MotionCommand, RobotBackend};
use parol6_core::parol6::JOINT_COUNT;
use parol6_core::profile::{JointMove, ProfileKind};
use parol6_hw::emulator::EmulatorHandle;
use parol6_hw::session::{LinkState, MotionState, Session};
use parol6_hw::units::{joints_steps_to_rad, limits_steps};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// From `from` on, the driver commands motion of the joints in the bit mask `joints`.
#[derive(Debug, Clone, Copy)]
pub struct Phase {
    pub from: Instant,
    pub joints: u8,
}

#[derive(Debug, Default)]
pub struct DriverLog {
    pub phases: Vec<Phase>,
    pub write_times: Vec<Instant>,
    pub last_drain: Option<Instant>,
    pub jogs: u64,
    pub moves: u64,
    pub stops: u64,
    pub deadman_stops: u64,
    pub enables: u64,
    pub refusals: u64,
    pub backend_closed: bool,
}

impl DriverLog {
    pub fn drain(&mut self, session: &Session) {
        self.write_times.extend(session.take_write_times());
        self.last_drain = Some(Instant::now());
    }

    /// Submits through `RobotBackend`; records the phase when accepted.
    pub fn submit(&mut self, session: &Session, cmd: MotionCommand, joints: u8) -> bool {
        let from = Instant::now();
        match RobotBackend::send(session, cmd) {
            Ok(()) => {
                self.phases.push(Phase { from, joints });
                true
            }
            Err(BackendError::Closed) => {
                self.backend_closed = true;
                false
            }
            Err(_) => {
                self.refusals += 1;
                false
            }
        }
    }
}

pub fn sleep_ms(ms: u64) {
    std::thread::sleep(Duration::from_millis(ms));
}

/// Waits until the session has processed everything submitted before `since` and is holding
/// or idle; false after `timeout`.
pub fn wait_settled(session: &Session, since: Instant, timeout: Duration, log: &mut DriverLog) -> bool {
    let end = Instant::now() + timeout;
    while Instant::now() < end {
        let s = session.snapshot();
        if s.published_at > since && matches!(s.motion, MotionState::Holding | MotionState::Idle) {
            return true;
        }
        log.drain(session);
        sleep_ms(5);
    }
    false
}

/// Jogs one joint with refreshes, then ends by release, stop or the dead-man.
pub fn jog(session: &Session, rng: &mut StdRng, stop: &AtomicBool, log: &mut DriverLog) {
    let joint = rng.random_range(0..JOINT_COUNT);
    let fraction = rng.random_range(0.2..=1.0) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let mask = 1u8 << joint;
    let hold = Duration::from_millis(rng.random_range(150..=800));
    let started = Instant::now();
    if !log.submit(session, MotionCommand::JogJoint { joint, fraction }, mask) {
        sleep_ms(10);
        return;
    }
    log.jogs += 1;
    while started.elapsed() < hold && !stop.load(Ordering::Relaxed) {
        sleep_ms(rng.random_range(20..=60));
        log.drain(session);
        if !log.submit(session, MotionCommand::JogJoint { joint, fraction }, mask) {
            break;
        }
    }
    match rng.random_range(0..10) {
        0..=5 => {
            log.submit(session, MotionCommand::JogRelease, 0);
        }
        6..=7 => {
            if log.submit(session, MotionCommand::Stop, 0) {
                log.stops += 1;
            }
        }
        _ => {
            // Dead-man: no refresh, the session stops the jog by itself after 200 ms.
            sleep_ms(300);
            log.phases.push(Phase { from: Instant::now(), joints: 0 });
            log.deadman_stops += 1;
        }
    }
}

/// A profiled move of 1–3 joints from where the session holds, sometimes stopped midway.
pub fn profiled_move(session: &Session, emu: &EmulatorHandle, rng: &mut StdRng, log: &mut DriverLog) {
    if !wait_settled(session, Instant::now(), Duration::from_millis(500), log) {
        return;
    }
    let s = session.snapshot();
    let basis = match (s.motion, s.target_steps) {
        (MotionState::Holding, Some(t)) => t,
        // A lying board: the session starts from what it measured, not from the truth.
        (MotionState::Idle, _) => {
            let truth = emu.snapshot().position_steps;
            let lying = (0..JOINT_COUNT).any(|i| (truth[i] - s.joint_steps[i]).abs() > 1000);
            if lying { s.joint_steps } else { truth }
        }
        _ => return,
    };
    let lim = limits_steps();
    if (0..JOINT_COUNT).any(|i| !(lim[i].0..=lim[i].1).contains(&basis[i])) {
        return;
    }
    let mut goal = basis;
    for _ in 0..rng.random_range(1..=3) {
        let i = rng.random_range(0..JOINT_COUNT);
        let inner = (lim[i].1 - lim[i].0) / 14;
        goal[i] = rng.random_range(lim[i].0 + inner..=lim[i].1 - inner);
    }
    let mask = (0..JOINT_COUNT).filter(|&i| goal[i] != basis[i]).fold(0u8, |m, i| m | (1 << i));
    let (basis_rad, goal_rad) = (joints_steps_to_rad(&basis), joints_steps_to_rad(&goal));
    let speed_fraction = rng.random_range(0.2..=0.9);
    let profile = if rng.random_bool(0.5) { ProfileKind::Trapezoidal } else { ProfileKind::JerkLimited };
    let duration_s =
        JointMove::parol6(&basis_rad, &goal_rad, speed_fraction, profile).map(|m| m.duration_s()).unwrap_or(2.0);
    let submitted = Instant::now();
    // "done" only once the session has applied this move (it may wait for the arm to rest first)
    let applied_before = session.state().commands_applied;
    let cmd = MotionCommand::MoveJoints { goal_rad: goal_rad.to_vec(), speed_fraction, profile };
    if !log.submit(session, cmd, mask) {
        sleep_ms(10);
        return;
    }
    log.moves += 1;
    let stop_at = rng.random_bool(0.25).then(|| duration_s * rng.random_range(0.2..=0.8));
    let limit = Duration::from_secs_f64(duration_s + 2.0);
    loop {
        sleep_ms(10);
        log.drain(session);
        let t = submitted.elapsed();
        if stop_at.is_some_and(|at| t.as_secs_f64() >= at) {
            if log.submit(session, MotionCommand::Stop, 0) {
                log.stops += 1;
            }
            break;
        }
        let s = session.snapshot();
        let applied = session.state().commands_applied > applied_before;
        let done =
            applied && s.published_at > submitted && matches!(s.motion, MotionState::Holding | MotionState::Idle);
        if done || t > limit {
            log.phases.push(Phase { from: Instant::now(), joints: 0 });
            break;
        }
    }
}

/// One lane's driver: realistic motion until `stop`, re-enabling after (false) E-stops.
pub fn drive(session: &Session, emu: &EmulatorHandle, seed: u64, stop: &AtomicBool) -> DriverLog {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut log = DriverLog::default();
    while !stop.load(Ordering::Relaxed) && !log.backend_closed {
        log.drain(session);
        let s = session.snapshot();
        if s.link != LinkState::Connected {
            sleep_ms(5);
            continue;
        }
        if s.needs_enable && !s.estop_pressed {
            log.phases.push(Phase { from: Instant::now(), joints: 0 });
            match session.enable() {
                Ok(()) => log.enables += 1,
                Err(_) => log.refusals += 1,
            }
            sleep_ms(20);
            continue;
        }
        match rng.random_range(0..10) {
            0..=3 => jog(session, &mut rng, stop, &mut log),
            4..=8 => profiled_move(session, emu, &mut rng, &mut log),
            _ => {
                if log.submit(session, MotionCommand::Stop, 0) {
                    log.stops += 1;
                }
                sleep_ms(rng.random_range(20..=200));
            }
        }
    }
    log.drain(session);
    log
}

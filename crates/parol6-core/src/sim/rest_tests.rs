//! The dynamic arm at rest: once settled with nothing commanded its physics is not stepped (the
//! idle app costs next to nothing), and the next command moves it as before.

use super::*;
use crate::motion::MotionCommand;
use crate::parol6::standby_rad;
use crate::profile::ProfileKind;

fn dynamic() -> Simulation {
    let config = SimConfig { mode: SimMode::Dynamic, ..SimConfig::default() };
    Simulation::new(RobotModel::parol6(), config).expect("embedded model builds")
}

/// Starts a trapezoidal move of joint `joint` by `by_rad` from `from` at `speed_fraction`;
/// returns the goal.
fn start_move(s: &mut Simulation, from: &[f64], joint: usize, by_rad: f64, speed_fraction: f64) -> Vec<f64> {
    let mut goal = from.to_vec();
    goal[joint] += by_rad;
    s.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal.clone(),
        speed_fraction,
        profile: ProfileKind::Trapezoidal,
    }))
    .expect("free move");
    goal
}

fn run_steps(s: &mut Simulation, n: usize) {
    for _ in 0..n {
        s.step();
    }
}

#[test]
fn a_settled_arm_rests_exactly_and_a_command_wakes_it() {
    let mut s = dynamic();
    run_steps(&mut s, 2000);
    assert!(s.resting(), "standby held for 2 s must count as rest");
    let held = s.q().to_vec();
    let standby = standby_rad();
    assert!(held.iter().zip(standby).all(|(q, r)| (q - r).abs() < 1e-3), "rested away from standby: {held:?}");
    run_steps(&mut s, 500);
    assert_eq!(s.q(), held.as_slice(), "a resting arm must not drift");

    let goal = start_move(&mut s, &held, 0, 0.3, 0.8);
    assert!(!s.resting(), "a command ends the rest");
    run_steps(&mut s, 3000);
    assert!((s.q()[0] - goal[0]).abs() < 2e-3, "J1 at {} after the move, goal {}", s.q()[0], goal[0]);
    assert!(s.resting(), "settled again after the move");
}

#[test]
fn a_moving_setpoint_never_rests() {
    let mut s = dynamic();
    start_move(&mut s, &standby_rad(), 1, 0.4, 0.05);
    for _ in 0..1500 {
        s.step();
        assert!(!s.resting(), "rested while moving at t = {:.3} s", s.sim_time_s());
    }
}

#[test]
fn the_tap_gets_every_step_while_moving_and_every_tenth_at_rest() {
    let mut s = dynamic();
    let (tx, rx) = crossbeam_channel::bounded(100_000);
    s.set_tap(Some(tx));
    run_steps(&mut s, 2000);
    assert!(s.resting());
    start_move(&mut s, &standby_rad(), 0, 0.2, 0.8);
    run_steps(&mut s, 3000);
    let samples: Vec<MotionSample> = rx.try_iter().collect();
    // numbered without gaps (the recorder counts gaps as lost samples)
    assert!(samples.windows(2).all(|w| w[1].seq == w[0].seq + 1));
    let gaps_ms: Vec<i64> = samples.windows(2).map(|w| ((w[1].time_s - w[0].time_s) * 1e3).round() as i64).collect();
    assert!(gaps_ms.iter().all(|g| *g == 1 || *g == 10), "{gaps_ms:?}");
    // settling (0.5 s still) at 1 kHz, rest at 100 Hz, the move at 1 kHz, rest again
    let at_rest = gaps_ms.iter().filter(|g| **g == 10).count();
    assert!(at_rest > 100, "{at_rest} samples 10 ms apart");
    let first_rest = gaps_ms.iter().position(|g| *g == 10).unwrap_or(0);
    assert!(first_rest >= 450, "rest reported after {first_rest} steps");
    let moving = samples.iter().filter(|m| m.commanded.qd.iter().any(|v| *v != 0.0)).count();
    assert!(moving > 300, "{moving} samples of the move");
    assert!(
        samples
            .windows(2)
            .filter(|w| w[1].commanded.qd.iter().any(|v| *v != 0.0))
            .all(|w| { ((w[1].time_s - w[0].time_s) * 1e3).round() as i64 == 1 }),
        "every step of the move is sampled"
    );
}

/// Issue 32 (safety 3): DISABLE (the E-stop button) stops the simulated arm and refuses motion
/// until ENABLE, as the robot's board does; the state says why.
#[test]
fn disabled_drives_refuse_motion_until_enabled() {
    use crate::motion::IoCommand;
    let mut s = dynamic();
    let jog = MotionCommand::JogJoint { joint: 0, fraction: 0.5 };
    s.apply(SimCommand::Motion(jog.clone())).expect("jog");
    s.apply(SimCommand::Io(IoCommand::Disable)).expect("disable");
    assert!(matches!(s.apply(SimCommand::Motion(jog.clone())), Err(SimError::DrivesDisabled)));
    let state = s.snapshot().robot_state();
    assert!(state.io.drives_disabled);
    assert!(state.blocked.as_deref().unwrap_or("").contains("disabled"), "{:?}", state.blocked);
    s.apply(SimCommand::Io(IoCommand::Enable)).expect("enable");
    assert!(s.snapshot().robot_state().blocked.is_none());
    s.apply(SimCommand::Motion(jog)).expect("jog after enable");
}

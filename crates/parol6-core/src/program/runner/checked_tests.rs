//! A checked program is checked once: the runner reuses the check from the joints it was
//! checked from, and checks again from anywhere else.

use super::tests::{sim, square};
use super::*;
use crate::program::check::{CheckOptions, RECHECK_TOLERANCE_RAD, check_program};

#[test]
fn the_runner_does_not_check_a_checked_program_again_from_the_same_start() {
    let (model, sim) = sim(4.0);
    let (_, steps) = square(&model);
    let program = Program::from_steps("square", steps);
    let start = sim.state().commanded.q.clone();
    let checked = Arc::new(check_program(&model, &program, &start, CheckOptions::default()));
    assert!(checked.ok, "{:?}", checked.issues);
    // the old way (a program without its check) checks once on the runner's thread
    let unchecked = ProgramRunner::start(sim.clone(), model.clone(), program, RunOptions::default()).expect("thread");
    let done = unchecked.join();
    assert_eq!((&done.state, done.preflights_run), (&RunState::Done, 1), "{done:?}");
    // back to where it was checked from
    let back = MotionCommand::MoveJoints {
        goal_rad: start.clone(),
        speed_fraction: 1.0,
        profile: crate::profile::ProfileKind::JerkLimited,
    };
    RobotBackend::send(sim.as_ref(), back).expect("move back");
    let t0 = std::time::Instant::now();
    while sim.state().moving || sim.state().mode != PlannerMode::Hold || !checked.is_from(&sim.state().commanded.q) {
        assert!(t0.elapsed() < Duration::from_secs(20), "the arm did not come back");
        std::thread::sleep(Duration::from_millis(10));
    }
    let runner = ProgramRunner::start_checked(sim.clone(), model, checked, RunOptions::default()).expect("thread");
    let done = runner.join();
    assert_eq!(done.state, RunState::Done, "{done:?}");
    assert_eq!(done.preflights_run, 0, "the check was reused: {done:?}");
}

#[test]
fn the_runner_checks_a_checked_program_again_from_another_start() {
    let (model, sim) = sim(4.0);
    let (_, steps) = square(&model);
    let program = Program::from_steps("square", steps);
    let mut elsewhere = sim.state().commanded.q.clone();
    elsewhere[0] += 10.0 * RECHECK_TOLERANCE_RAD;
    let checked = Arc::new(check_program(&model, &program, &elsewhere, CheckOptions::default()));
    assert!(!checked.is_from(&sim.state().commanded.q));
    let done = ProgramRunner::start_checked(sim.clone(), model.clone(), Arc::clone(&checked), RunOptions::default())
        .expect("thread")
        .join();
    assert_eq!((&done.state, done.preflights_run), (&RunState::Done, 1), "{done:?}");
    // another speed override is another check too
    let slower = RunOptions { speed_override: 0.5, ..RunOptions::default() };
    let start = sim.state().commanded.q.clone();
    let here = Arc::new(check_program(&model, &checked.program, &start, CheckOptions::default()));
    let runner = ProgramRunner::start_checked(sim, model, here, slower).expect("thread");
    runner.abort();
    assert_eq!(runner.join().preflights_run, 1);
}

/// A program refused by its check is refused again without checking (the report says why).
#[test]
fn a_checked_program_with_an_error_is_refused_from_its_check() {
    let (model, sim) = sim(1.0);
    let (q, mut steps) = square(&model);
    let mut far = crate::program::PoseMm::from_isometry(&model.tcp_isometry(&q));
    far.position_mm[2] += 900.0;
    steps.insert(2, crate::program::Step::MoveL { pose: far, speed_mm_s: None, blend_mm: None, duration_s: None });
    let start = sim.state().commanded.q.clone();
    let checked = Arc::new(check_program(&model, &Program::from_steps("bad", steps), &start, CheckOptions::default()));
    let before = sim.state().commands_applied;
    let done = ProgramRunner::start_checked(sim.clone(), model, checked, RunOptions::default()).expect("thread").join();
    match &done.state {
        RunState::Failed(why) => assert!(why.starts_with("pre-flight: step 3"), "{why}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(done.preflights_run, 0);
    assert_eq!(sim.state().commands_applied, before, "nothing was sent");
}

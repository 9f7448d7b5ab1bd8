use super::*;
use crate::motion::{BackendError, IoCommand};
use crate::program::{PoseMm, Step};
use crate::sim::{SimConfig, SimHandle, SimMode};
use std::time::Instant;

pub(super) fn sim(time_scale: f64) -> (RobotModel, Arc<SimHandle>) {
    let model = RobotModel::parol6();
    let config = SimConfig { mode: SimMode::Kinematic, time_scale, ..SimConfig::default() };
    let sim = Arc::new(SimHandle::spawn(model.clone(), config).expect("sim"));
    (model, sim)
}

/// A pose away from the standby wrist singularity, and a program of lines around it.
pub(super) fn square(model: &RobotModel) -> (Vec<f64>, Vec<Step>) {
    let mut q = crate::parol6::standby_rad().to_vec();
    q[1] += 0.2;
    q[2] -= 0.3;
    q[4] = 0.6;
    let p0 = PoseMm::from_isometry(&model.tcp_isometry(&q));
    let at = |dx: f64, dy: f64| {
        let mut p = p0;
        p.position_mm[0] += dx;
        p.position_mm[1] += dy;
        p
    };
    let steps = vec![
        Step::MoveJoints {
            joints_deg: q.iter().map(|v| v.to_degrees()).collect(),
            speed_fraction: Some(1.0),
            duration_s: None,
        },
        Step::MoveL { pose: at(40.0, 0.0), speed_mm_s: Some(100.0), blend_mm: None, duration_s: None },
        Step::SetOutput { output: 1, on: true },
        Step::MoveL { pose: at(40.0, 40.0), speed_mm_s: Some(100.0), blend_mm: None, duration_s: None },
        Step::Dwell { seconds: 0.1 },
        Step::MoveL { pose: at(0.0, 0.0), speed_mm_s: Some(100.0), blend_mm: None, duration_s: None },
    ];
    (q, steps)
}

fn wait_for(runner: &ProgramRunner, what: &str, f: impl Fn(&RunProgress) -> bool) -> RunProgress {
    let t0 = Instant::now();
    loop {
        let p = runner.progress();
        if f(&p) {
            return p;
        }
        assert!(!p.state.is_finished() || f(&p), "{what}: the run ended: {p:?}");
        assert!(t0.elapsed() < Duration::from_secs(30), "{what}: timed out at {p:?}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn a_program_runs_to_its_end_on_the_simulation() {
    let (model, sim) = sim(4.0);
    let (q, steps) = square(&model);
    let program = Program::from_steps("square", steps);
    let runner =
        ProgramRunner::start(sim.clone(), model.clone(), program.clone(), RunOptions::default()).expect("thread");
    let done = runner.join();
    assert_eq!(done.state, RunState::Done, "{done:?}");
    assert_eq!(done.steps_done, 6);
    let s = sim.state();
    // back at the start of the square, output 1 on
    let end = model.tcp_isometry(&s.commanded.q).translation.vector;
    let want = model.tcp_isometry(&q).translation.vector;
    assert!((end - want).norm() < 1e-6, "{end:?} vs {want:?}");
    assert!(s.io.outputs[0]);
    // the run took the planned time (motion clock), plus at most a few polls; the clock is a
    // sum of step durations from a start that differs run to run, so it may fall short of the
    // planned sum by a rounding (regression: "took 3.515 s for 3.515 s")
    let took = done.clock_s.1 - done.clock_s.0;
    assert!(
        took >= done.planned_s - 1e-9 && took < done.planned_s + 0.5,
        "took {took:.12} s for {:.12} s",
        done.planned_s
    );
}

#[test]
fn pause_stops_on_the_path_and_resume_finishes_the_program() {
    let (model, sim) = sim(1.0);
    let (q, steps) = square(&model);
    let program = Program::from_steps("square", steps);
    let runner = ProgramRunner::start(sim.clone(), model.clone(), program, RunOptions::default()).expect("thread");
    // pause during the first line
    wait_for(&runner, "the first line", |p| p.step == 1 && p.state == RunState::Running);
    let start = pause_on_the_first_line(&model, &sim, &runner, &q);
    let paused = wait_for(&runner, "pause", |p| p.state == RunState::Paused);
    std::thread::sleep(Duration::from_millis(200));
    let s = sim.state();
    assert!(!s.moving, "stopped while paused");
    assert_eq!(s.mode, PlannerMode::Paused);
    // stopped on the first line: y and z of the start, x part-way
    let here = model.tcp_isometry(&s.commanded.q).translation.vector;
    assert!((here.y - start.y).abs() < 0.05e-3 && (here.z - start.z).abs() < 0.05e-3, "{here:?}");
    assert!(here.x > start.x + 1e-3 && here.x < start.x + 0.04 - 1e-3, "part-way: {here:?}");
    assert!(paused.steps_done <= 1);
    runner.control(RunnerControl::Resume);
    let done = runner.join();
    assert_eq!(done.state, RunState::Done, "{done:?}");
    let end = model.tcp_isometry(&sim.state().commanded.q).translation.vector;
    assert!((end - start).norm() < 1e-6);
}

/// Trial 7: the operator paused a program mid-line, jogged the arm, pressed Resume: the next
/// trajectory started 29° away from the arm, was refused, and the run failed with "invalid
/// command: the trajectory starts 29.4665° away from the commanded position". The arm now
/// goes back to where the paused step starts, then the program goes on to its end.
#[test]
fn an_arm_moved_while_paused_returns_to_the_path_and_the_program_goes_on() {
    let (model, sim) = sim(4.0);
    let (q, steps) = square(&model);
    let program = Program::from_steps("square", steps);
    let runner = ProgramRunner::start(sim.clone(), model.clone(), program, RunOptions::default()).expect("thread");
    wait_for(&runner, "the first line", |p| p.step == 1 && p.state == RunState::Running);
    let start = pause_on_the_first_line(&model, &sim, &runner, &q);
    wait_for(&runner, "pause", |p| p.state == RunState::Paused);
    // the operator moves J1 by 20° (as a jog or a typed joint does)
    let mut moved = sim.state().commanded.q.clone();
    moved[0] += 20f64.to_radians();
    let cmd = MotionCommand::MoveJoints {
        goal_rad: moved.clone(),
        speed_fraction: 1.0,
        profile: crate::profile::ProfileKind::Trapezoidal,
    };
    RobotBackend::send(&*sim, cmd).expect("the manual move");
    let t0 = Instant::now();
    while (sim.state().commanded.q[0] - moved[0]).abs() > 1e-9 || sim.state().moving {
        assert!(t0.elapsed() < Duration::from_secs(10), "the manual move does not end");
        std::thread::sleep(Duration::from_millis(2));
    }
    runner.control(RunnerControl::Resume);
    wait_for(&runner, "the return to the path", |p| {
        p.waiting_for.as_deref().is_some_and(|w| w.contains("return to where step 2 starts"))
    });
    let done = runner.join();
    assert_eq!(done.state, RunState::Done, "{done:?}");
    assert_eq!(done.steps_done, 6);
    let end = model.tcp_isometry(&sim.state().commanded.q).translation.vector;
    assert!((end - start).norm() < 1e-6, "back at the start of the square: {end:?} vs {start:?}");
    assert!(sim.state().io.outputs[0], "the output step ran");
}

#[test]
fn single_step_runs_one_step_per_press_and_stop_holds() {
    let (model, sim) = sim(4.0);
    let (_, steps) = square(&model);
    let program = Program::from_steps("square", steps);
    let opts = RunOptions { single_step: true, ..RunOptions::default() };
    let runner = ProgramRunner::start(sim.clone(), model, program, opts).expect("thread");
    let p = wait_for(&runner, "first step", |p| p.state == RunState::Paused && p.steps_done == 1);
    assert_eq!(p.step, 1);
    runner.control(RunnerControl::Step);
    wait_for(&runner, "second step", |p| p.state == RunState::Paused && p.steps_done == 2);
    runner.control(RunnerControl::Step);
    wait_for(&runner, "the output step", |p| p.state == RunState::Paused && p.steps_done == 3);
    // the output was sent; the simulation applies it on its next step
    let t0 = Instant::now();
    while !sim.state().io.outputs[0] {
        assert!(t0.elapsed() < Duration::from_secs(1), "output 1 never set");
        std::thread::sleep(Duration::from_millis(1));
    }
    runner.control(RunnerControl::Stop);
    let end = runner.join();
    assert_eq!(end.state, RunState::Stopped);
    assert_eq!(end.steps_done, 3);
    assert!(!sim.state().moving);
}

#[test]
fn a_wait_for_an_input_times_out_or_goes_on_when_it_comes() {
    let (model, sim) = sim(1.0);
    let wait = Program::from_steps("wait", vec![Step::WaitInput { input: 2, on: true, timeout_s: Some(0.3) }]);
    let failed =
        ProgramRunner::start(sim.clone(), model.clone(), wait.clone(), RunOptions::default()).expect("thread").join();
    match failed.state {
        RunState::Failed(why) => assert!(why.contains("input 2 high did not come within 0.3 s"), "{why}"),
        other => panic!("{other:?}"),
    }
    let long = Program::from_steps("wait", vec![Step::WaitInput { input: 2, on: true, timeout_s: Some(20.0) }]);
    let runner = ProgramRunner::start(sim.clone(), model, long, RunOptions::default()).expect("thread");
    let p = wait_for(&runner, "waiting", |p| p.waiting_for.is_some());
    assert_eq!(p.waiting_for.as_deref(), Some("input 2 high"));
    sim.io(IoCommand::SetSimulatedInput { input: 2, on: true }).expect("set");
    assert_eq!(runner.join().state, RunState::Done);
}

#[test]
fn a_program_that_fails_pre_flight_never_moves() {
    let (model, sim) = sim(1.0);
    let (q, mut steps) = square(&model);
    let mut far = PoseMm::from_isometry(&model.tcp_isometry(&q));
    far.position_mm[2] += 900.0;
    steps.insert(2, Step::MoveL { pose: far, speed_mm_s: None, blend_mm: None, duration_s: None });
    let before = sim.state().commands_applied;
    let done = ProgramRunner::start(sim.clone(), model, Program::from_steps("bad", steps), RunOptions::default())
        .expect("thread")
        .join();
    match done.state {
        RunState::Failed(why) => assert!(why.starts_with("pre-flight: step 3"), "{why}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(sim.state().commands_applied, before, "nothing was sent");
}

#[test]
fn a_pause_step_waits_for_resume_and_an_optional_one_only_when_asked() {
    let (model, sim) = sim(4.0);
    let (_, steps) = square(&model);
    let mut with_pause = steps.clone();
    with_pause.insert(2, Step::Pause { optional: false });
    with_pause.insert(4, Step::Pause { optional: true });
    let program = Program::from_steps("pauses", with_pause);
    // optional pauses off: it stops at the M0 only
    let runner =
        ProgramRunner::start(sim.clone(), model.clone(), program.clone(), RunOptions::default()).expect("thread");
    let p = wait_for(&runner, "the pause", |p| p.state == RunState::Paused);
    assert_eq!((p.step, p.steps_done), (2, 2), "{p:?}");
    assert!(p.waiting_for.as_deref().is_some_and(|w| w.contains("operator")), "{p:?}");
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(runner.progress().state, RunState::Paused, "it waits for the operator");
    assert!(!sim.state().moving);
    runner.control(RunnerControl::Resume);
    let done = runner.join();
    assert_eq!((&done.state, done.steps_done), (&RunState::Done, 8), "{done:?}");
    // optional pauses on: both pause
    let opts = RunOptions { optional_pauses: true, ..RunOptions::default() };
    let runner = ProgramRunner::start(sim.clone(), model, program, opts).expect("thread");
    wait_for(&runner, "the first pause", |p| p.state == RunState::Paused && p.steps_done == 2);
    runner.control(RunnerControl::Resume);
    wait_for(&runner, "the optional pause", |p| p.state == RunState::Paused && p.steps_done == 4);
    runner.control(RunnerControl::Resume);
    assert_eq!(runner.join().state, RunState::Done);
}

/// The simulation, except that it refuses STOP (as a robot whose link went down just then).
pub(crate) struct RefusesStop(pub(crate) Arc<SimHandle>);

impl RobotBackend for RefusesStop {
    fn submit(&self, cmd: MotionCommand, at_s: Option<f64>) -> Result<(), BackendError> {
        match cmd {
            MotionCommand::Stop => Err(BackendError::Refused("the link is down".into())),
            other => self.0.submit(other, at_s),
        }
    }

    fn state(&self) -> Arc<RobotState> {
        self.0.state()
    }

    fn io(&self, cmd: IoCommand) -> Result<(), BackendError> {
        self.0.io(cmd)
    }
}

#[test]
fn stop_best_effort_records_a_refused_stop_in_the_progress() {
    let (model, sim) = sim(1.0);
    let (_, steps) = square(&model);
    let backend = Arc::new(RefusesStop(sim.clone()));
    let runner = ProgramRunner::start(backend, model, Program::from_steps("square", steps), RunOptions::default())
        .expect("thread");
    let p = wait_for(&runner, "the first line", |p| p.step == 1 && p.state == RunState::Running);
    assert_eq!(p.stop_failed, None);
    runner.control(RunnerControl::Stop);
    let done = runner.join();
    assert_eq!(done.state, RunState::Stopped, "{done:?}");
    assert_eq!(done.stop_failed.as_deref(), Some("STOP (stopped while running) failed: the link is down"), "{done:?}");
}

/// Waits until the first line of [`square`] (from `q`) has moved the TCP 5 mm, then pauses;
/// where the TCP started, m.
fn pause_on_the_first_line(
    model: &RobotModel,
    sim: &SimHandle,
    runner: &ProgramRunner,
    q: &[f64],
) -> nalgebra::Vector3<f64> {
    let start = model.tcp_isometry(q).translation.vector;
    let t0 = Instant::now();
    while model.tcp_isometry(&sim.state().commanded.q).translation.x < start.x + 0.005 {
        assert!(t0.elapsed() < Duration::from_secs(10), "the line does not move");
        std::thread::sleep(Duration::from_millis(1));
    }
    runner.control(RunnerControl::Pause);
    start
}

/// The simulation, except that at rest it reports as its commanded setpoint a point 2 µrad (a
/// fraction of a motor step) on J1 beside where the planner holds the arm, as a robot does just
/// after a move ends: its `commanded` is the setpoint of the frame the board answered, one frame
/// late.
struct AnswersOneFrameLate(Arc<SimHandle>);

impl RobotBackend for AnswersOneFrameLate {
    fn submit(&self, cmd: MotionCommand, at_s: Option<f64>) -> Result<(), BackendError> {
        self.0.submit(cmd, at_s)
    }

    fn state(&self) -> Arc<RobotState> {
        let s = self.0.state();
        if s.mode != PlannerMode::Hold || s.moving {
            return s;
        }
        let mut late = s.as_ref().clone();
        late.commanded.q[0] -= 2e-6;
        Arc::new(late)
    }

    fn io(&self, cmd: IoCommand) -> Result<(), BackendError> {
        self.0.io(cmd)
    }
}

/// Regression (trial11, issue 32): a looping Pick & place on the fake robot stopped between two
/// passes with "step 1: … refused: the trajectory starts 0.0001° away from the commanded
/// position": the runner planned the pass from the reported setpoint, one frame late, instead of
/// from where the planner holds the arm.
#[test]
fn a_looping_run_plans_each_pass_from_where_the_planner_holds_the_arm() {
    let (model, sim) = sim(4.0);
    let (_, steps) = square(&model);
    let backend = Arc::new(AnswersOneFrameLate(sim.clone()));
    let opts = RunOptions { looping: true, ..RunOptions::default() };
    let runner = ProgramRunner::start(backend, model, Program::from_steps("square", steps), opts).expect("thread");
    wait_for(&runner, "the second pass", |p| p.passes >= 1 && p.steps_done >= 2);
    runner.control(RunnerControl::Stop);
    let done = runner.join();
    assert_eq!(done.state, RunState::Stopped, "{done:?}");
}

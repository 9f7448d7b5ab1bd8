//! Issue acceptance: the same program run on the simulation and on the serial session against
//! the firmware emulator produces identical commanded trajectories and the same end poses.
//!
//! The program runner compiles the program from the commanded pose each backend holds and
//! schedules every step on the backend's motion clock (starting on the 10 ms grid), so the
//! commanded joints must agree at every common time stamp after the start.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

use crossbeam_channel::Receiver;
use parol6_core::RobotModel;
use parol6_core::motion::{MotionSample, RobotBackend};
use parol6_core::parol6::rad_per_step;
use parol6_core::program::runner::{ProgramRunner, RunOptions, RunProgress, RunState};
use parol6_core::program::{PoseMm, Program, Step};
use parol6_core::sim::{SimCommand, SimConfig, SimHandle};
use parol6_hw::session::{Session, SessionConfig};
use parol6_hw::units::{STANDBY_STEPS, joints_steps_to_rad};
use parol6_hw::{EmulatorConfig, EmulatorHandle};

const LONG: Duration = Duration::from_secs(10);

/// Joint move away from the wrist singularity, a line, an output, a quarter circle, a dwell,
/// a line back, and a joint move home: every kind of motion step.
fn program(model: &RobotModel) -> Program {
    let work_deg = [90.0, -80.0, 170.0, 0.0, 60.0, 180.0];
    let work: Vec<f64> = work_deg.iter().map(|d: &f64| d.to_radians()).collect();
    let p0 = PoseMm::from_isometry(&model.tcp_isometry(&work));
    let at = |dx: f64, dy: f64| {
        let mut p = p0;
        p.position_mm[0] += dx;
        p.position_mm[1] += dy;
        p
    };
    let center = at(30.0, 30.0).position_mm;
    let standby: Vec<f64> = joints_steps_to_rad(&STANDBY_STEPS).iter().map(|r| r.to_degrees()).collect();
    Program::from_steps(
        "parity",
        vec![
            Step::MoveJoints { joints_deg: work_deg.to_vec(), speed_fraction: Some(0.8), duration_s: None },
            Step::MoveL { pose: at(30.0, 0.0), speed_mm_s: Some(120.0), blend_mm: None, duration_s: None },
            Step::SetOutput { output: 1, on: true },
            Step::MoveCircle { center_mm: center, normal: [0.0, 0.0, 1.0], angle_deg: 90.0, speed_mm_s: Some(80.0) },
            Step::Dwell { seconds: 0.2 },
            Step::MoveL { pose: at(0.0, 0.0), speed_mm_s: Some(120.0), blend_mm: None, duration_s: None },
            Step::MoveJoints { joints_deg: standby, speed_fraction: Some(0.8), duration_s: None },
        ],
    )
}

/// Samples keyed by whole milliseconds after the first step's start.
fn collect(rx: &Receiver<MotionSample>, start_s: f64, end_s: f64) -> BTreeMap<i64, MotionSample> {
    let t0 = (start_s * 1000.0).round() as i64;
    let t1 = (end_s * 1000.0).round() as i64;
    rx.try_iter()
        .filter_map(|s| {
            let ms = (s.time_s * 1000.0).round() as i64;
            (t0..=t1).contains(&ms).then_some((ms - t0, s))
        })
        .collect()
}

fn run(backend: Arc<dyn RobotBackend>, model: &RobotModel) -> std::thread::JoinHandle<RunProgress> {
    let runner = ProgramRunner::start(backend, model.clone(), program(model), RunOptions::default()).expect("thread");
    std::thread::spawn(move || runner.join())
}

#[test]
fn one_program_gives_the_same_commanded_trajectory_on_both_backends() {
    let model = RobotModel::parol6();
    let q0 = joints_steps_to_rad(&STANDBY_STEPS).to_vec();
    let (sim_tx, sim_rx) = crossbeam_channel::bounded(100_000);
    let sim = Arc::new(SimHandle::spawn_with_tap(model.clone(), SimConfig::default(), Some(sim_tx)).expect("sim"));
    sim.send(SimCommand::Teleport(q0.clone())).expect("teleport");
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    let (hw_tx, hw_rx) = crossbeam_channel::bounded(100_000);
    // trajectories are compared here, not link supervision (see tests/hw_load.rs)
    let cfg = SessionConfig { status_timeout: Duration::from_millis(500), ..SessionConfig::default() };
    let session = Arc::new(Session::open_with_tap(emu.path(), cfg, Some(hw_tx)).expect("session"));
    session.wait_until(LONG, |s| s.status_frames >= 10).expect("status");
    std::thread::sleep(Duration::from_millis(100));

    let on_sim = run(sim.clone(), &model);
    let on_robot = run(session.clone(), &model);
    let (a, b) = (on_sim.join().expect("sim run"), on_robot.join().expect("robot run"));
    assert_eq!(a.state, RunState::Done, "simulation: {a:?}");
    assert_eq!(b.state, RunState::Done, "robot: {b:?}; session fault {:?}", session.snapshot().fault);
    assert!((a.planned_s - b.planned_s).abs() < 1e-12, "planned {} vs {}", a.planned_s, b.planned_s);
    assert!(sim.state().io.outputs[0] && session.state().io.outputs[0], "output 1 set on both");
    std::thread::sleep(Duration::from_millis(300));
    let settled = emu.snapshot().position_steps;

    let sim_samples = collect(&sim_rx, a.clock_s.0, a.clock_s.0 + a.planned_s);
    let hw_samples = collect(&hw_rx, b.clock_s.0, b.clock_s.0 + b.planned_s);
    let mut compared = 0;
    let mut max_diff = 0.0f64;
    for (ms, h) in &hw_samples {
        let Some(s) = sim_samples.get(ms) else { continue };
        compared += 1;
        for j in 0..6 {
            let d = (s.commanded.q[j] - h.commanded.q[j]).abs();
            assert!(d <= 1e-9, "J{} commanded differs by {d:e} rad at start + {ms} ms", j + 1);
            max_diff = max_diff.max(d);
        }
    }
    // in the (dynamic) simulation the measured TCP stays within 1 mm of the commanded one
    let max_tcp_mm = sim_samples
        .values()
        .map(|s| {
            (model.tcp_isometry(&s.measured_q).translation.vector
                - model.tcp_isometry(&s.commanded.q).translation.vector)
                .norm()
                * 1e3
        })
        .fold(0.0, f64::max);
    assert!(max_tcp_mm < 1.0, "measured TCP {max_tcp_mm:.3} mm from the commanded one");
    let expected = (a.planned_s * 100.0) as usize;
    assert!(compared + 5 >= expected, "only {compared} of ~{expected} common time stamps");
    // the same end: the commanded ends agree and the emulated arm settles on them within 1 step
    let (end_sim, end_hw) = (sim.state().commanded.q.clone(), session.state().commanded.q.clone());
    for j in 0..6 {
        assert!((end_sim[j] - end_hw[j]).abs() <= 1e-9, "J{} end", j + 1);
        let end = parol6_hw::units::rad_to_steps(j, end_hw[j]).expect("steps");
        assert!((settled[j] - end).abs() <= 1, "J{} settled at {} steps, commanded {end}", j + 1, settled[j]);
        assert!((end_sim[j] - q0[j]).abs() <= rad_per_step(j), "J{} back at the start", j + 1);
    }
    eprintln!(
        "program parity: {compared} common 10 ms stamps over {:.2} s, max commanded difference {max_diff:e} rad; \
         max tracking error sim {:.4}°, emulated robot {:.3}°; simulated TCP within {max_tcp_mm:.3} mm",
        a.planned_s,
        a.max_tracking_error_rad.to_degrees(),
        b.max_tracking_error_rad.to_degrees()
    );
}

/// On the robot, an E-stop during a program ends it with the reason, and the arm holds; the
/// program does not start again until the robot accepts motion.
#[test]
fn an_e_stop_halts_a_program_on_the_robot_with_the_reason() {
    let model = RobotModel::parol6();
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    let cfg = SessionConfig { status_timeout: Duration::from_millis(500), ..SessionConfig::default() };
    let session = Arc::new(Session::open(emu.path(), cfg).expect("session"));
    session.wait_until(LONG, |s| s.status_frames >= 10).expect("status");
    let runner =
        ProgramRunner::start(session.clone(), model.clone(), program(&model), RunOptions::default()).expect("thread");
    let t0 = std::time::Instant::now();
    while runner.progress().steps_done < 1 {
        assert!(t0.elapsed() < LONG, "the program does not advance: {:?}", runner.progress());
        std::thread::sleep(Duration::from_millis(10));
    }
    emu.set_estop_pressed(true);
    let end = runner.join();
    match &end.state {
        RunState::Failed(why) => assert!(why.contains("halted") && why.to_lowercase().contains("e-stop"), "{why}"),
        other => panic!("expected a halt, got {other:?}"),
    }
    assert!(end.steps_done < end.steps);
    // held: the board stops stepping
    std::thread::sleep(Duration::from_millis(300));
    let a = emu.snapshot().position_steps;
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(a, emu.snapshot().position_steps, "the arm holds after the E-stop");
    // a new run is refused while the E-stop is pressed
    let again = ProgramRunner::start(session.clone(), model.clone(), program(&model), RunOptions::default())
        .expect("thread")
        .join();
    match again.state {
        RunState::Failed(why) => assert!(why.contains("does not accept motion"), "{why}"),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

/// Regression (found by the GUI soak): a looping program on the robot failed at the start of
/// its second pass with "the arm is moving", because the measured joints still lagged the end
/// of the first pass. The runner now waits for the arm to rest between passes.
#[test]
fn a_looping_program_on_the_robot_runs_pass_after_pass() {
    let model = RobotModel::parol6();
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    let cfg = SessionConfig { status_timeout: Duration::from_millis(500), ..SessionConfig::default() };
    let session = Arc::new(Session::open(emu.path(), cfg).expect("session"));
    session.wait_until(LONG, |s| s.status_frames >= 10).expect("status");
    std::thread::sleep(Duration::from_millis(100));
    let standby: Vec<f64> = joints_steps_to_rad(&STANDBY_STEPS).iter().map(|r| r.to_degrees()).collect();
    let mut away = standby.clone();
    away[0] += 20.0;
    let mut program = Program::from_steps(
        "loop",
        vec![
            Step::MoveJoints { joints_deg: away, speed_fraction: Some(1.0), duration_s: None },
            Step::MoveJoints { joints_deg: standby, speed_fraction: Some(1.0), duration_s: None },
        ],
    );
    program.looping = true;
    let runner = ProgramRunner::start(session.clone(), model, program, RunOptions::default()).expect("thread");
    let end = std::time::Instant::now() + Duration::from_secs(30);
    while runner.progress().passes < 3 && !runner.is_finished() && std::time::Instant::now() < end {
        std::thread::sleep(Duration::from_millis(20));
    }
    let p = runner.progress();
    runner.control(parol6_core::program::runner::RunnerControl::Stop);
    let last = runner.join();
    assert!(p.passes >= 3, "only {} passes; state {:?}", p.passes, p.state);
    assert_eq!(last.state, RunState::Stopped, "{last:?}");
}

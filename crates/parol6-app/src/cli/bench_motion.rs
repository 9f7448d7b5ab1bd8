//! `parol6 bench motion`: the motion engine's speed targets, as JSON.
//!
//! - `movel_tick_us`: planning a 100 mm MoveL at the 1 kHz control rate (timing law, IK that
//!   keeps the branch, speed-cap check), per 1 ms sample;
//! - `preflight_1000_moves_ms`: pre-flight of the 1 000-move pick-and-place program of
//!   `parol6_core::motion::preflight::bench_program` (checker built once per run, included);
//! - `program_check_1000_steps_ms`: `parol6 program check` of a 1 000-step program end to end
//!   (compile at 10 ms + pre-flight);
//! - `runner_cpu_percent`: CPU the program runner thread uses while a program runs on the
//!   1 kHz simulation in real time, percent of one core (after the check and the 1 ms
//!   planning, whose time is reported as `planning_1001_steps_s`).

use std::sync::Arc;
use std::time::Instant;

use parol6_core::RobotModel;
use parol6_core::motion::MotionCaps;
use parol6_core::motion::cartesian::{CartesianCaps, plan};
use parol6_core::motion::path::TcpPath;
use parol6_core::motion::preflight::Preflight;
use parol6_core::motion::preflight::bench_program::bench_program;
use parol6_core::program::check::{CheckOptions, check_program};
use parol6_core::program::runner::{ProgramRunner, RunOptions, RunState};
use parol6_core::program::{PoseMm, Program, Step};
use parol6_core::sim::{SimConfig, SimHandle};
use parol6_core::stats::Summary;

use super::{CliError, CliResult, print_json};

/// Runs the motion benchmarks with `repeats` timed runs of each (medians reported).
pub fn bench_motion(repeats: usize, runner_seconds: f64) -> CliResult {
    let model = RobotModel::parol6();
    let caps = MotionCaps::of(&model);
    // MoveL: 100 mm at 100 mm/s from a pose clear of singularities
    let q0 = work_pose();
    let a = model.tcp_isometry(&q0);
    let mut b = a;
    b.translation.vector.x += 0.1;
    let path = TcpPath::line(&a, &b);
    let mut per_tick_us = Vec::with_capacity(repeats);
    let mut samples = 0;
    for _ in 0..repeats {
        let t = Instant::now();
        let mv = plan(&model, &q0, &path, &CartesianCaps::default(), &caps, 1.0, 0.001)
            .map_err(|e| CliError::runtime(format!("MoveL planning failed: {e}")))?;
        samples = mv.trajectory.samples().len();
        per_tick_us.push(t.elapsed().as_secs_f64() * 1e6 / samples as f64);
    }
    // pre-flight of 1 000 planned moves
    let moves = bench_program(&model, 1000).map_err(|e| CliError::runtime(e.to_string()))?;
    let mut preflight_ms = Vec::with_capacity(repeats);
    let mut issues = 0;
    for _ in 0..repeats {
        let t = Instant::now();
        let checker = Preflight::new(&model, &caps, &[]).map_err(|e| CliError::runtime(e.to_string()))?;
        let report = checker.check(&moves);
        preflight_ms.push(t.elapsed().as_secs_f64() * 1e3);
        issues = report.issues.len();
    }
    // a 1 000-step program checked end to end
    let program = thousand_steps(&model);
    let mut check_ms = Vec::with_capacity(repeats);
    let mut check_ok = false;
    for _ in 0..repeats.min(5) {
        let t = Instant::now();
        let r = check_program(&model, &program, &q0, CheckOptions::default());
        check_ms.push(t.elapsed().as_secs_f64() * 1e3);
        check_ok = r.ok;
    }
    let runner = runner_cpu(&model, runner_seconds)?;
    let stat = |v: &mut Vec<f64>| {
        Summary::from_samples(v).map(|s| serde_json::json!({"median": s.p50, "p99": s.p99, "n": s.n}))
    };
    print_json(&serde_json::json!({
        "target": "motion",
        "movel_tick_us": stat(&mut per_tick_us),
        "movel_samples": samples,
        "preflight_1000_moves_ms": stat(&mut preflight_ms),
        "preflight_issues": issues,
        "program_check_1000_steps_ms": stat(&mut check_ms),
        "program_check_ok": check_ok,
        "runner": runner,
    }))
}

fn work_pose() -> Vec<f64> {
    [90.0f64, -80.0, 170.0, 0.0, 60.0, 180.0].iter().map(|d| d.to_radians()).collect()
}

/// 250 pick-and-place cycles: a joint move over a station, a line down 40 mm, a line back up,
/// a joint move back.
fn thousand_steps(model: &RobotModel) -> Program {
    let over = PoseMm::from_isometry(&model.tcp_isometry(&work_pose()));
    let mut down = over;
    down.position_mm[2] -= 40.0;
    let stations = [[90.0, -80.0, 170.0, 0.0, 60.0, 180.0], [70.0, -80.0, 170.0, 0.0, 60.0, 160.0]];
    let mut steps = Vec::with_capacity(1000);
    for _ in 0..250 {
        steps.push(Step::MoveJoints { joints_deg: stations[1].to_vec(), speed_fraction: Some(0.8), duration_s: None });
        steps.push(Step::MoveJoints { joints_deg: stations[0].to_vec(), speed_fraction: Some(0.8), duration_s: None });
        steps.push(Step::MoveL { pose: down, speed_mm_s: Some(100.0), blend_mm: None, duration_s: None });
        steps.push(Step::MoveL { pose: over, speed_mm_s: Some(100.0), blend_mm: None, duration_s: None });
    }
    Program::from_steps("bench", steps)
}

/// The runner thread's CPU share while it drives a program on the real-time 1 kHz simulation.
fn runner_cpu(model: &RobotModel, seconds: f64) -> Result<serde_json::Value, CliError> {
    if seconds <= 0.0 {
        return Ok(serde_json::Value::Null);
    }
    let sim = Arc::new(SimHandle::spawn(model.clone(), SimConfig::default()).map_err(CliError::runtime)?);
    let mut program = thousand_steps(model);
    // from standby to the work pose first
    program.steps.insert(
        0,
        parol6_core::program::SourcedStep {
            step: Step::MoveJoints {
                joints_deg: vec![90.0, -80.0, 170.0, 0.0, 60.0, 180.0],
                speed_fraction: Some(1.0),
                duration_s: None,
            },
            line: 0,
        },
    );
    let runner = ProgramRunner::start(sim, model.clone(), program, RunOptions::default())
        .map_err(|e| CliError::runtime(e.to_string()))?;
    // time from the first scheduled step on (checking and planning excluded, as in the CPU)
    let t = Instant::now();
    while runner.progress().state == RunState::Preparing {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let planning_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    std::thread::sleep(std::time::Duration::from_secs_f64(seconds));
    runner.abort();
    let p = runner.join();
    let wall = t.elapsed().as_secs_f64();
    if let RunState::Failed(why) = &p.state {
        return Err(CliError::runtime(format!("the runner failed: {why}")));
    }
    Ok(serde_json::json!({
        "seconds": wall,
        "planning_1001_steps_s": planning_s,
        "steps_done": p.steps_done,
        "cpu_s": p.runner_cpu_s,
        "cpu_percent": p.runner_cpu_s.map(|c| c / wall * 100.0),
    }))
}

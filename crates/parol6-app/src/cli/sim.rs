//! `parol6 dynamics` (inverse dynamics as JSON) and the simulation benchmarks
//! `parol6 bench physics` and `parol6 bench latency`.

use parol6_core::motion::MotionCommand;
use std::time::{Duration, Instant};

use parol6_core::dynamics::InverseDynamics;
use parol6_core::profile::ProfileKind;
use parol6_core::sim::{SimCommand, SimConfig, SimError, SimHandle, SimMode, Simulation};
use serde_json::json;

use super::common::{NsStats, parse_list};
use super::kin::{check_plausible, parse_joint_positions};
use super::options::RobotArgs;
use super::{CliError, CliResult, print_json, warn};
use parol6_core::limits::plausible;

/// Arguments of `parol6 dynamics`.
#[derive(Debug, clap::Args)]
pub struct DynamicsArgs {
    /// Joint positions J1,…,JN, finite numbers (rad, or degrees with --deg).
    #[arg(long, value_name = "J1,J2,…", allow_hyphen_values = true)]
    pub joints: String,
    /// Joint velocities, finite numbers (rad/s, or °/s with --deg); default all 0.
    #[arg(long, value_name = "V1,V2,…", allow_hyphen_values = true)]
    pub velocities: Option<String>,
    /// Joint accelerations, finite numbers (rad/s², or °/s² with --deg); default all 0.
    #[arg(long, value_name = "A1,A2,…", allow_hyphen_values = true)]
    pub accelerations: Option<String>,
    /// Angles, velocities and accelerations are in degrees.
    #[arg(long)]
    pub deg: bool,
}

/// Runs `parol6 dynamics`: the joint torques (gravity + inertial + Coriolis) the motion needs.
pub fn run_dynamics(a: &DynamicsArgs, robot: &RobotArgs) -> CliResult {
    let model = robot.load()?;
    let n = model.dof();
    let q = parse_joint_positions("--joints", &a.joints, n, a.deg)?;
    let (scale, deg) = if a.deg { (std::f64::consts::PI / 180.0, "°") } else { (1.0, "rad") };
    let rates = |what: &str, text: &Option<String>, bound: f64, unit: &str, quantity: &str| match text {
        Some(s) => {
            let typed = parse_list(what, s, Some(n))?;
            check_plausible(what, &typed, 1, (bound, scale), &format!("{deg}{unit}"), quantity)?;
            Ok::<_, CliError>(typed.into_iter().map(|v| v * scale).collect())
        }
        None => Ok(vec![0.0; n]),
    };
    let qd = rates("--velocities", &a.velocities, plausible::JOINT_VELOCITY_MAX_ABS_RAD_S, "/s", "joint velocity")?;
    let qdd = rates(
        "--accelerations",
        &a.accelerations,
        plausible::JOINT_ACCELERATION_MAX_ABS_RAD_S2,
        "/s²",
        "joint acceleration",
    )?;
    let within = model.limits.check(&q);
    if let Err(e) = &within {
        warn(e);
    }
    let t = InverseDynamics::new(&model).compute(&model, &q, &qd, &qdd).map_err(CliError::usage)?;
    if let Some(j) = t.total_nm.iter().position(|v| !v.is_finite()) {
        return Err(CliError::usage(format!("the torque of joint {} is not a finite number for these values", j + 1)));
    }
    print_json(&json!({
        "joints": model.joint_names(),
        "joints_rad": q,
        "velocities_rad_s": qd,
        "accelerations_rad_s2": qdd,
        "within_limits": within.is_ok(),
        "torques_nm": t.total_nm,
        "gravity_nm": t.gravity_nm,
        "inertial_coriolis_nm": t.inertial_coriolis_nm,
        "gravity_m_s2": parol6_core::sim::multibody::GRAVITY_M_S2,
    }))
}

fn sim_error(e: SimError) -> CliError {
    CliError::runtime(e)
}

/// Two collision-free poses of the PAROL6 the benchmarks move between.
fn bench_poses() -> (Vec<f64>, Vec<f64>) {
    (parol6_core::parol6::standby_rad().to_vec(), vec![1.2, -1.2, 2.8, 0.3, -0.4, 2.0])
}

/// `parol6 bench physics`: wall time of [`Simulation::step`] (dynamic mode, colliders, the arm
/// moving back and forth), then the CPU share of the 1 kHz real-time thread over `cpu_seconds`.
pub fn bench_physics(n: usize, cpu_seconds: f64) -> CliResult {
    if n == 0 || !(cpu_seconds.is_finite() && (0.0..=600.0).contains(&cpu_seconds)) {
        return Err(CliError::usage("--n must be > 0 and --cpu-seconds within 0–600"));
    }
    let model = parol6_core::RobotModel::parol6();
    let config = SimConfig { mode: SimMode::Dynamic, ..SimConfig::default() };
    let mut sim = Simulation::new(model.clone(), config).map_err(sim_error)?;
    let colliders = sim.physics().collider_count();
    let (a, b) = bench_poses();
    let mut go_to_b = true;
    let mut samples = Vec::with_capacity(n);
    for _ in 0..200 {
        sim.step(); // warm-up
    }
    while samples.len() < n {
        if !sim.is_moving() {
            let goal = if go_to_b { b.clone() } else { a.clone() };
            go_to_b = !go_to_b;
            sim.apply(SimCommand::Motion(MotionCommand::MoveJoints {
                goal_rad: goal,
                speed_fraction: 1.0,
                profile: ProfileKind::Trapezoidal,
            }))
            .map_err(sim_error)?;
        }
        let t0 = Instant::now();
        sim.step();
        samples.push(t0.elapsed().as_nanos() as f64);
    }
    let stats = NsStats::from_samples(&mut samples);

    // the real-time thread: same motion, measured CPU time of the sim thread
    let cpu = if cpu_seconds > 0.0 {
        let handle = SimHandle::spawn(model, config).map_err(sim_error)?;
        let end = Instant::now() + Duration::from_secs_f64(cpu_seconds);
        let mut go_to_b = true;
        while Instant::now() < end {
            if !handle.snapshot().moving {
                let goal = if go_to_b { b.clone() } else { a.clone() };
                go_to_b = !go_to_b;
                handle
                    .send(SimCommand::Motion(MotionCommand::MoveJoints {
                        goal_rad: goal,
                        speed_fraction: 1.0,
                        profile: ProfileKind::Trapezoidal,
                    }))
                    .map_err(sim_error)?;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let s = handle.stats();
        let snap = handle.snapshot();
        handle.shutdown();
        json!({
            "seconds": cpu_seconds,
            "thread_cpu_percent": s.cpu_fraction().map(|f| f * 100.0),
            "steps": s.steps,
            "overruns": s.overruns,
            "step_rate_hz": snap.step_rate_hz,
        })
    } else {
        serde_json::Value::Null
    };
    print_json(&json!({
        "bench": "physics",
        "mode": "dynamic",
        "colliders": colliders,
        "collision_guard": config.check_collisions,
        "rate_hz": config.rate_hz,
        "median_ns": stats.median_ns,
        "p99_ns": stats.p99_ns,
        "mean_ns": stats.mean_ns,
        "n": stats.n,
        "realtime_thread": cpu,
    }))
}

/// Largest `--interval-us` of `bench latency` (the command line refuses more).
pub const MAX_INTERVAL_US: u64 = 100_000;

/// `parol6 bench latency`: with the 1 kHz thread running, another thread sends `n` jog targets
/// (one every `interval_us` on average, jittered); command creation → applied on the sim thread.
pub fn bench_latency(n: usize, interval_us: u64) -> CliResult {
    if n == 0 || interval_us > MAX_INTERVAL_US {
        return Err(CliError::usage(format!("--n must be > 0 and --interval-us within 0–{MAX_INTERVAL_US}")));
    }
    let model = parol6_core::RobotModel::parol6();
    let config = SimConfig { mode: SimMode::Dynamic, ..SimConfig::default() };
    let handle = SimHandle::spawn(model, config).map_err(sim_error)?;
    std::thread::sleep(Duration::from_millis(100));
    let _ = handle.drain_latencies_ns();
    let base = parol6_core::parol6::standby_rad();
    let start = Instant::now();
    let mut full = 0usize;
    let mut latencies: Vec<f64> = Vec::with_capacity(n);
    std::thread::scope(|s| -> CliResult {
        let sender = s.spawn(|| -> Result<usize, SimError> {
            let mut rejected_full = 0;
            for i in 0..n {
                let mut q = base.to_vec();
                q[0] += 0.2 * ((i as f64) * 0.01).sin();
                q[4] += 0.2 * ((i as f64) * 0.013).cos();
                loop {
                    match handle.send(SimCommand::Motion(MotionCommand::follow(q.clone()))) {
                        Ok(()) => break,
                        Err(SimError::ChannelFull) => {
                            rejected_full += 1;
                            std::thread::sleep(Duration::from_micros(50));
                        }
                        Err(e) => return Err(e),
                    }
                }
                // jittered spacing: 0.5–1.5 × interval
                let jitter = interval_us / 2 + (i as u64).wrapping_mul(7919) % (interval_us + 1);
                std::thread::sleep(Duration::from_micros(jitter));
            }
            Ok(rejected_full)
        });
        full = sender.join().map_err(|_| CliError::runtime("sender thread panicked"))?.map_err(sim_error)?;
        Ok(())
    })?;
    // let the last commands land
    let deadline = Instant::now() + Duration::from_secs(2);
    while latencies.len() < n && Instant::now() < deadline {
        latencies.extend(handle.drain_latencies_ns().into_iter().map(|v| v as f64));
        std::thread::sleep(Duration::from_millis(5));
    }
    let elapsed = start.elapsed().as_secs_f64();
    let s = handle.stats();
    let snap = handle.snapshot();
    handle.shutdown();
    if latencies.len() < n {
        return Err(CliError::runtime(format!("only {} of {n} commands were applied", latencies.len())));
    }
    let stats = NsStats::from_samples(&mut latencies);
    print_json(&json!({
        "bench": "latency",
        "commands": n,
        "median_ns": stats.median_ns,
        "p99_ns": stats.p99_ns,
        "mean_ns": stats.mean_ns,
        "max_ns": latencies.last().copied().unwrap_or(0.0),
        "n": stats.n,
        "queue_full_retries": full,
        "seconds": elapsed,
        "sim_steps": s.steps,
        "sim_overruns": s.overruns,
        "sim_thread_cpu_percent": s.cpu_fraction().map(|f| f * 100.0),
        "step_rate_hz": snap.step_rate_hz,
    }))
}

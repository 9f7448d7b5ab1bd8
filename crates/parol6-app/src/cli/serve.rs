//! `parol6 serve --foxglove [ADDR] [--ros2] [--allow-remote-control] [--port P | --fake-robot]`:
//! serves the simulation (default) or the controller live, without a window, until SIGINT /
//! SIGTERM (exit 130) or `--seconds S`.
//!
//! The backend's sample tap feeds a [`Recorder`] (as `parol6 record` does, without a file); each
//! server takes the recorder's live outlet ([`crate::live`]). Once every server listens, one
//! JSON line goes to stdout: `{"listening": {"foxglove": "ws://127.0.0.1:8765"}, …}` (with port
//! 0 the port chosen); at the end one more: the summary (clients, messages sent, dropped).
//! `--demo` moves the simulation gently back and forth, `--program FILE` runs a program on the
//! backend once (pre-flight first) while serving: both for demonstrations and tests.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use parol6_core::RobotModel;
use parol6_core::motion::{MotionCommand, RobotBackend};
use parol6_core::program::runner::{ProgramRunner, RunOptions};
use parol6_core::sim::{SimConfig, SimHandle};
use parol6_core::telemetry::{LinkHealth, Recorder, RecorderConfig};
use serde_json::json;

use super::common::{RateArgs, open};
use super::options::{ConnectArgs, RobotArgs, f64_above, f64_within};
use super::record::{link_health, urdf_text};
use super::{CliError, CliResult, interrupt, print_json};
use crate::live::{LiveServer, LiveSource, RemoteControl};

/// Arguments of `parol6 serve`.
#[derive(Debug, clap::Args)]
pub struct ServeArgs {
    /// Serve Foxglove's WebSocket protocol (Foxglove, Lichtblick: "Open connection",
    /// ws://ADDR) at ADDR: IP:PORT, a port (on 127.0.0.1), or nothing for 127.0.0.1:8765. Only
    /// localhost unless an address is given (0.0.0.0:8765: every interface). Port 0 takes a free
    /// port (the JSON line says which).
    #[arg(long, value_name = "ADDR")]
    #[allow(clippy::option_option)]
    pub foxglove: Option<Option<String>>,
    /// Serve ROS 2 over Zenoh (rmw_zenoh conventions): /joint_states, /tf, /robot_description,
    /// and trajectories on /parol6/joint_trajectory (refused unless --allow-remote-control).
    #[arg(long)]
    pub ros2: bool,
    /// Carry out motion commands that come over the network (ROS 2 trajectories), after the same
    /// pre-flight as a program. Off by default: they are refused and logged to /events.
    #[arg(long)]
    pub allow_remote_control: bool,
    /// Stop after this many seconds (default: until Ctrl-C or SIGTERM, exit 130).
    #[arg(long, value_parser = f64_above(0.0, 1e7))]
    pub seconds: Option<f64>,
    /// Simulation only: move gently back and forth (10 % of the way toward each joint's
    /// mid-range and back, again and again) while serving.
    #[arg(long, conflicts_with = "program")]
    pub demo: bool,
    /// Run this program once on the backend while serving (.json, .gcode/.nc, .csv, .txt; from
    /// where the arm is; pre-flight first). Pause steps are run through.
    #[arg(long, value_name = "FILE")]
    pub program: Option<PathBuf>,
    /// Speed override of --program, 0.01–1.
    #[arg(long, default_value_t = 1.0, value_parser = f64_within(0.01, 1.0), requires = "program")]
    pub speed: f64,
    /// Session settings (robot only).
    #[command(flatten)]
    pub rate: RateArgs,
    /// Where the ROS 2 node connects (with --ros2).
    #[command(flatten)]
    pub ros2_options: super::serve_ros2::Ros2Args,
}

/// How often the main loop passes the backend's state and link health to the recorder.
const FEED_INTERVAL: Duration = Duration::from_millis(20);

/// The backend served: the simulation or the controller's session (the emulator behind
/// `--fake-robot` lives as long as it).
struct Backend {
    backend: Arc<dyn RobotBackend>,
    link_health: Box<dyn Fn() -> Option<LinkHealth>>,
    source: String,
    /// The simulation (`None`: the controller).
    sim: Option<Arc<SimHandle>>,
    _emulator: Option<parol6_hw::emulator::EmulatorHandle>,
}

/// Runs `parol6 serve`.
pub fn run(args: &ServeArgs, robot: &RobotArgs, connect: &ConnectArgs) -> CliResult {
    if args.foxglove.is_none() && !args.ros2 {
        return Err(CliError::usage("nothing to serve: give --foxglove [ADDR] and/or --ros2"));
    }
    let on_robot = connect.fake_robot || connect.port.is_some();
    if on_robot && (robot.urdf.is_some() || robot.tip.is_some()) {
        return Err(CliError::usage("--urdf and --tip apply to the simulation only (the controller is a PAROL6)"));
    }
    if on_robot && args.demo {
        return Err(CliError::usage("--demo moves the simulation only; it never moves a robot"));
    }
    let foxglove_addr = match &args.foxglove {
        Some(given) => Some(
            crate::live::bind_address(given.as_deref(), crate::live::FOXGLOVE_DEFAULT_PORT)
                .map_err(|e| CliError::usage(format!("--foxglove: {e}")))?,
        ),
        None => None,
    };
    let model = robot.load()?;
    let text = urdf_text(robot)?;
    // the program is read and checked before anything opens or moves
    let program = match &args.program {
        Some(file) => {
            let start = parol6_core::motion::home_position(&model);
            let mut p = super::program::load(file, &model, &start)?;
            for s in &mut p.steps {
                if s.step == (parol6_core::program::Step::Pause { optional: false }) {
                    s.step = parol6_core::program::Step::Pause { optional: true };
                }
            }
            Some(p)
        }
        None => None,
    };
    let recorder = Recorder::start(model.clone(), RecorderConfig::default()).map_err(CliError::runtime)?;
    let backend = open_backend(args, connect, &model, &recorder)?;
    let remote = RemoteControl::new(args.allow_remote_control, Some(recorder.events()));
    let source = LiveSource {
        model: &model,
        urdf_text: &text,
        recorder: &recorder,
        remote: remote.clone(),
        backend: Arc::clone(&backend.backend),
    };
    let mut servers: Vec<Box<dyn LiveServer>> = Vec::new();
    if let Some(addr) = foxglove_addr {
        servers.push(start_foxglove(&source, addr)?);
    }
    if args.ros2 {
        servers.push(start_ros2(args, &source)?);
    }
    let listening: serde_json::Map<String, serde_json::Value> =
        servers.iter().map(|s| (s.name().to_string(), json!(s.address()))).collect();
    print_json(&json!({
        "listening": listening,
        "source": backend.source,
        "remote_control": remote.allowed(),
    }))?;
    let started = Instant::now();
    let source_name = backend.source.clone();
    drop(source);
    let outcome = serve_until_done(args, &backend, &model, &recorder, program);
    let servers: serde_json::Map<String, serde_json::Value> =
        servers.into_iter().map(|s| (s.name().to_string(), s.stop())).collect();
    if backend.sim.is_some()
        && interrupt::requested()
        && let Err(e) = backend.backend.send(MotionCommand::Stop)
    {
        super::warn(format!("STOP after the signal: {e}"));
    }
    let sim = backend.sim.as_ref().map(|s| sim_json(&s.stats()));
    // the simulation's thread (or the session, then the emulator) stops here
    drop(backend);
    let stats = recorder.stats();
    let (commands, refused) = remote.counts();
    let mut out = json!({
        "command": "serve",
        "source": source_name,
        "wall_s": started.elapsed().as_secs_f64(),
        "servers": servers,
        "samples": stats.samples,
        "missing_samples": stats.missing_samples,
        "recorder_cpu_percent": stats.thread_cpu_ns as f64 * 1e-7 / started.elapsed().as_secs_f64().max(1e-9),
        "process_cpu_s": crate::live::process_cpu_s(),
        "sim": sim,
        "network_commands": commands,
        "network_commands_refused": refused,
        "program": outcome?,
    });
    drop(recorder);
    if interrupt::requested() {
        out["interrupted"] = interrupt::json();
        print_json(&out)?;
        return Err(interrupt::error("the servers stopped"));
    }
    print_json(&out)
}

/// The simulation's step rate and CPU, for the summary: a live server must not slow it.
fn sim_json(s: &parol6_core::sim::SimStats) -> serde_json::Value {
    let wall_s = s.wall_ns as f64 * 1e-9;
    json!({
        "steps": s.steps,
        "overruns": s.overruns,
        "steps_per_s": if wall_s > 0.0 { s.steps as f64 / wall_s } else { 0.0 },
        "cpu_percent": s.cpu_fraction().map(|f| f * 100.0),
    })
}

/// Opens the simulation (default) or the controller, its tap into `recorder`.
fn open_backend(
    args: &ServeArgs,
    connect: &ConnectArgs,
    model: &RobotModel,
    recorder: &Recorder,
) -> Result<Backend, CliError> {
    if connect.fake_robot || connect.port.is_some() {
        let link = open(connect, &args.rate, Some(recorder.tap()), model.tool)?;
        let session = Arc::new(link.session);
        let source = session.snapshot().port.clone();
        let health_of = Arc::clone(&session);
        Ok(Backend {
            backend: session,
            link_health: Box::new(move || Some(link_health(&health_of.snapshot()))),
            source,
            sim: None,
            _emulator: link.emulator,
        })
    } else {
        let config = SimConfig { tracking: args.rate.tracking.unwrap_or_default(), ..SimConfig::default() };
        let sim =
            Arc::new(SimHandle::spawn_with_tap(model.clone(), config, Some(recorder.tap())).map_err(CliError::usage)?);
        Ok(Backend {
            backend: Arc::clone(&sim) as Arc<dyn RobotBackend>,
            link_health: Box::new(|| None),
            source: "simulation".to_string(),
            sim: Some(sim),
            _emulator: None,
        })
    }
}

/// Feeds the recorder every [`FEED_INTERVAL`] until `--seconds` or a signal, running the demo or
/// the program meanwhile; the program's summary, if one ran.
fn serve_until_done(
    args: &ServeArgs,
    backend: &Backend,
    model: &RobotModel,
    recorder: &Recorder,
    program: Option<parol6_core::program::Program>,
) -> Result<serde_json::Value, CliError> {
    let end = args.seconds.and_then(|s| Duration::try_from_secs_f64(s).ok()).map(|d| Instant::now() + d);
    let mut runner = match program {
        Some(p) => {
            let opts = RunOptions { speed_override: args.speed, ..RunOptions::default() };
            Some(
                ProgramRunner::start(Arc::clone(&backend.backend), model.clone(), p, opts)
                    .map_err(|e| CliError::runtime(format!("cannot start the program thread: {e}")))?,
            )
        }
        None => None,
    };
    let mut demo = args.demo.then(|| Demo::new(model));
    let mut step = None;
    while !interrupt::requested() && end.is_none_or(|e| Instant::now() < e) {
        recorder.observe_state(backend.backend.state());
        if let Some(h) = (backend.link_health)() {
            recorder.set_link_health(h);
        }
        if let Some(r) = &runner {
            let p = r.progress();
            let now = (!p.state.is_finished()).then_some(p.step);
            if now != step {
                step = now;
                recorder.set_program_step(step);
            }
        }
        if let Some(d) = demo.as_mut() {
            d.tick(backend.backend.as_ref())?;
        }
        std::thread::sleep(FEED_INTERVAL);
    }
    let Some(r) = runner.take() else { return Ok(serde_json::Value::Null) };
    if !r.progress().state.is_finished() {
        r.abort();
        if let Err(e) = backend.backend.send(MotionCommand::Stop) {
            super::warn(format!("STOP at the end: {e}"));
        }
    }
    let p = r.join();
    Ok(json!({
        "name": p.name,
        "state": format!("{:?}", p.state),
        "steps_done": p.steps_done,
        "steps": p.steps,
    }))
}

/// `--demo`: a gentle move toward each joint's mid-range and back, the next as soon as the arm
/// has stopped (so it moves nearly all the time: the simulation's tap runs at 1 kHz).
struct Demo {
    home: Vec<f64>,
    away: Vec<f64>,
    toward_away: bool,
    /// No new move before this (the state shows a move only once the backend took it).
    next: Instant,
}

impl Demo {
    fn new(model: &RobotModel) -> Self {
        let home = parol6_core::motion::home_position(model);
        let away = home
            .iter()
            .zip(model.limits.iter())
            .map(|(&h, l)| if l.is_bounded() { h + 0.1 * (0.5 * (l.min + l.max) - h) } else { h + 0.1 })
            .collect();
        Self { home, away, toward_away: true, next: Instant::now() }
    }

    fn tick(&mut self, backend: &dyn RobotBackend) -> CliResult {
        if Instant::now() < self.next || backend.state().moving {
            return Ok(());
        }
        let goal = if self.toward_away { self.away.clone() } else { self.home.clone() };
        self.toward_away = !self.toward_away;
        self.next = Instant::now() + Duration::from_millis(200);
        let profile = parol6_core::profile::ProfileKind::JerkLimited;
        backend
            .send(MotionCommand::MoveJoints { goal_rad: goal, speed_fraction: 0.3, profile })
            .map_err(|e| CliError::runtime(format!("the backend refused the demo move: {e}")))
    }
}

/// Starts the Foxglove WebSocket server at `addr`.
#[cfg(feature = "foxglove")]
fn start_foxglove(source: &LiveSource<'_>, addr: std::net::SocketAddr) -> Result<Box<dyn LiveServer>, CliError> {
    crate::live::foxglove::FoxgloveServer::start(source, addr)
        .map(|s| Box::new(s) as Box<dyn LiveServer>)
        .map_err(|e| CliError::runtime(format!("--foxglove {addr}: {e}")))
}

/// Without the `foxglove` feature: refused.
#[cfg(not(feature = "foxglove"))]
fn start_foxglove(_source: &LiveSource<'_>, _addr: std::net::SocketAddr) -> Result<Box<dyn LiveServer>, CliError> {
    Err(CliError::usage("--foxglove: this parol6 was built without the `foxglove` feature"))
}

/// Starts the ROS 2 (Zenoh) server.
fn start_ros2(args: &ServeArgs, source: &LiveSource<'_>) -> Result<Box<dyn LiveServer>, CliError> {
    super::serve_ros2::start(&args.ros2_options, source)
}

//! `parol6 record --seconds N -o OUT.mcap [--port P | --fake-robot] [--demo]`: records the
//! simulation (default) or the controller to an MCAP file without a window; and the
//! [`Telemetry`] helper that `hw jog|move --record` use too.
//!
//! The backend's sample tap feeds a [`Recorder`]; a feeder thread passes the backend's state
//! (refusals, blocked) and, for the robot, the link health (E-stop, link loss) every 20 ms.
//! The file is created once the backend is open ([`Telemetry::prepare`], then
//! [`Telemetry::begin`]). SIGINT / SIGTERM end the recording early: the simulation gets STOP,
//! the file is closed with its summary, exit 130 ([`super::interrupt`]).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use parol6_core::motion::tracking::TrackingMode;
use parol6_core::motion::{MotionCommand, RobotBackend, RobotState, home_position};
use parol6_core::profile::ProfileKind;
use parol6_core::sim::{SimConfig, SimHandle};
use parol6_core::telemetry::{LinkHealth, Recorder, RecorderConfig, RecordingInfo, TelemetryError};
use parol6_core::{RobotModel, Tool};
use serde_json::json;

use super::common::tool_of;
use super::common::{RateArgs, open};
use super::options::{ConnectArgs, RobotArgs, f64_above};
use super::{CliError, CliResult, interrupt, print_json};

/// Arguments of `parol6 record`.
#[derive(Debug, clap::Args)]
pub struct RecordArgs {
    /// Duration, s, > 0 and ≤ 3600.
    #[arg(long, value_parser = f64_above(0.0, 3600.0))]
    pub seconds: f64,
    /// Output MCAP file.
    #[arg(short = 'o', long = "output", value_name = "OUT.mcap", value_parser = super::options::output_file)]
    pub output: PathBuf,
    /// Simulation only: move gently back and forth (10 % of the way toward each joint's
    /// mid-range) instead of holding still.
    #[arg(long)]
    pub demo: bool,
}

pub use crate::app::link_health;

/// A recorder writing one file, for one command.
pub struct Telemetry {
    recorder: Recorder,
    path: PathBuf,
    info: RecordingInfo,
    /// When the file was created ([`Telemetry::begin`]).
    started: OnceLock<Instant>,
}

impl Telemetry {
    /// Starts a recorder for `model` and a file at `path` (the URDF of `urdf_text`).
    pub fn start(model: &RobotModel, tool: Tool, urdf_text: &str, path: &Path) -> Result<Self, CliError> {
        Self::start_for_program(model, tool, urdf_text, path, "")
    }

    /// [`Telemetry::start`] with the program's name in the file's metadata.
    pub fn start_for_program(
        model: &RobotModel,
        tool: Tool,
        urdf_text: &str,
        path: &Path,
        program: &str,
    ) -> Result<Self, CliError> {
        let telemetry = Self::prepare(model, tool, urdf_text, path, program)?;
        telemetry.begin()?;
        Ok(telemetry)
    }

    /// A recorder whose [`Telemetry::tap`] can be given to a backend before the file exists:
    /// `path` is created (and an existing file replaced) only by [`Telemetry::begin`], once the
    /// command has checked its request and opened its controller.
    pub fn prepare(
        model: &RobotModel,
        tool: Tool,
        urdf_text: &str,
        path: &Path,
        program: &str,
    ) -> Result<Self, CliError> {
        let recorder = Recorder::start(model.clone(), RecorderConfig::default()).map_err(CliError::runtime)?;
        let info = RecordingInfo {
            app_version: env!("CARGO_PKG_VERSION").to_string(),
            tool: tool.name().to_string(),
            program: program.to_string(),
            urdf_text: urdf_text.to_string(),
            tracking: String::new(),
        };
        Ok(Self { recorder, path: path.to_path_buf(), info, started: OnceLock::new() })
    }

    /// Names the tracking mode of the motion recorded (in the file's metadata).
    pub fn with_tracking(mut self, mode: TrackingMode) -> Self {
        self.info.tracking = mode.name().to_string();
        self
    }

    /// Creates the file and starts recording into it (once; later calls do nothing).
    pub fn begin(&self) -> Result<(), CliError> {
        if self.started.get().is_some() {
            return Ok(());
        }
        self.recorder.start_recording(&self.path, &self.info).map_err(|e| match e {
            TelemetryError::File(f) => CliError::from(f),
            e => CliError::runtime(e),
        })?;
        self.started.get_or_init(Instant::now);
        Ok(())
    }

    /// The program step under way (written with every sample until changed).
    pub fn set_program_step(&self, step: Option<usize>) {
        self.recorder.set_program_step(step);
    }

    /// The tap to give the backend.
    pub fn tap(&self) -> crossbeam_channel::Sender<parol6_core::motion::MotionSample> {
        self.recorder.tap()
    }

    /// Runs `body` while a thread passes `poll()`'s state and link health to the recorder.
    pub fn feed_while<R>(
        &self,
        poll: &(dyn Fn() -> (Arc<RobotState>, Option<LinkHealth>) + Sync),
        body: impl FnOnce() -> R,
    ) -> R {
        let stop = AtomicBool::new(false);
        std::thread::scope(|scope| {
            scope.spawn(|| {
                while !stop.load(Ordering::Acquire) {
                    let (state, link) = poll();
                    self.recorder.observe_state(state);
                    if let Some(h) = link {
                        self.recorder.set_link_health(h);
                    }
                    std::thread::sleep(Duration::from_millis(20));
                }
            });
            let r = body();
            stop.store(true, Ordering::Release);
            r
        })
    }

    /// Closes the file; returns what it holds as JSON.
    pub fn finish(self) -> Result<serde_json::Value, CliError> {
        let wall_s = self.started.get().map_or(0.0, |t| t.elapsed().as_secs_f64());
        let stats_before = self.recorder.stats();
        let error = self.recorder.last_error();
        let summary = self.recorder.finish().map_err(CliError::runtime)?;
        if let Some(e) = error {
            return Err(CliError::runtime(format!("{}: {e}", self.path.display())));
        }
        let summary =
            summary.ok_or_else(|| CliError::runtime(format!("{}: the recording was not open", self.path.display())))?;
        let bytes = std::fs::metadata(&self.path).map(|m| m.len()).unwrap_or(0);
        Ok(json!({
            "file": self.path.display().to_string(),
            "samples": summary.samples,
            "missing_samples": stats_before.missing_samples,
            "events": summary.events,
            "messages": summary.messages,
            "duration_s": summary.duration_s,
            "bytes": bytes,
            "recorder_cpu_percent": if wall_s > 0.0 { stats_before.thread_cpu_ns as f64 * 1e-9 / wall_s * 100.0 } else { 0.0 },
        }))
    }
}

/// The URDF text of the selected robot (the embedded PAROL6 or the `--urdf` file).
pub fn urdf_text(robot: &RobotArgs) -> Result<String, CliError> {
    match &robot.urdf {
        None => Ok(parol6_core::model::PAROL6_URDF.to_string()),
        Some(p) => parol6_core::fsio::read_regular_bounded_string(p, parol6_core::urdf_input::MAX_URDF_BYTES as u64)
            .map_err(CliError::from),
    }
}

/// Runs `parol6 record`.
pub fn run(args: &RecordArgs, robot: &RobotArgs, connect: &ConnectArgs) -> CliResult {
    let duration = Duration::try_from_secs_f64(args.seconds)
        .ok()
        .filter(|d| !d.is_zero() && d.as_secs_f64() <= 3600.0)
        .ok_or_else(|| CliError::usage(format!("--seconds must be > 0 and ≤ 3600 (got {})", args.seconds)))?;
    let on_robot = connect.fake_robot || connect.port.is_some();
    if on_robot && (robot.urdf.is_some() || robot.tip.is_some()) {
        return Err(CliError::usage("--urdf and --tip apply to the simulation only (the controller is a PAROL6)"));
    }
    if on_robot && args.demo {
        return Err(CliError::usage("--demo moves the simulation only; it never moves a robot"));
    }
    let model = robot.load()?;
    let text = urdf_text(robot)?;
    // the file is created once the controller answers: a port that cannot be opened leaves it alone
    let telemetry =
        Telemetry::prepare(&model, tool_of(robot), &text, &args.output, "")?.with_tracking(TrackingMode::default());
    let source;
    if on_robot {
        let link = open(connect, &RateArgs::defaults(), Some(telemetry.tap()), model.tool)?;
        telemetry.begin()?;
        source = link.session.snapshot().port.clone();
        let poll = || (link.session.robot_state(), Some(link_health(&link.session.snapshot())));
        // it only listens: the session closes with IDLE frames when `link` is dropped
        telemetry.feed_while(&poll, || interrupt::sleep(duration));
    } else {
        let sim = SimHandle::spawn_with_tap(model.clone(), SimConfig::default(), Some(telemetry.tap()))
            .map_err(CliError::usage)?;
        telemetry.begin()?;
        source = "simulation".to_string();
        let poll = || (sim.state(), None);
        let demo = telemetry.feed_while(&poll, || demo_or_hold(&sim, &model, args.demo, duration));
        if interrupt::requested() {
            RobotBackend::send(&sim, MotionCommand::Stop)
                .map_err(|e| CliError::runtime(format!("the simulation refused STOP: {e}")))?;
        }
        sim.shutdown();
        demo?;
    }
    let mut out = telemetry.finish()?;
    out["command"] = json!("record");
    out["source"] = json!(source);
    out["seconds"] = json!(args.seconds);
    if interrupt::requested() {
        out["interrupted"] = interrupt::json();
        let what = format!("recording {} closed with {} samples", args.output.display(), out["samples"]);
        print_json(&out)?;
        return Err(interrupt::error(what));
    }
    print_json(&out)
}

/// Holds still for `duration`, or with `demo` moves 10 % of the way toward each joint's
/// mid-range and back, again and again.
fn demo_or_hold(sim: &SimHandle, model: &RobotModel, demo: bool, duration: Duration) -> CliResult {
    let end = Instant::now() + duration;
    if !demo {
        interrupt::sleep(duration);
        return Ok(());
    }
    let home = home_position(model);
    let away: Vec<f64> = home
        .iter()
        .zip(model.limits.iter())
        .map(|(&h, l)| if l.is_bounded() { h + 0.1 * (0.5 * (l.min + l.max) - h) } else { h + 0.1 })
        .collect();
    let mut toward_away = true;
    while Instant::now() < end && !interrupt::requested() {
        let goal = if toward_away { away.clone() } else { home.clone() };
        toward_away = !toward_away;
        let cmd = MotionCommand::MoveJoints { goal_rad: goal, speed_fraction: 0.3, profile: ProfileKind::JerkLimited };
        RobotBackend::send(sim, cmd)
            .map_err(|e| CliError::runtime(format!("the simulation refused the demo move: {e}")))?;
        let step_end = (Instant::now() + Duration::from_secs(2)).min(end);
        interrupt::sleep(step_end.saturating_duration_since(Instant::now()));
    }
    Ok(())
}

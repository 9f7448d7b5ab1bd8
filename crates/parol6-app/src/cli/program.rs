//! `parol6 program check|run|torques|convert`: pre-flight a program file of any format, run it on the
//! headless simulation, the controller emulator (`--fake-robot`) or the robot (`--port`) with
//! the same runner the window uses, show its joint torques before it runs
//! ([`super::program_torques`]), or convert it between formats (by extension).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use parol6_core::RobotModel;
use parol6_core::motion::{RobotBackend, RobotState};
use parol6_core::program::Program;
use parol6_core::program::check::{CheckOptions, CheckReport, Severity, check_program};
use parol6_core::program::files::{
    FormatContext, ProgramFormat, ProgramIoError, export_notes, read_program, write_program,
};
use parol6_core::program::gcode::{AbcChoice, AbcConvention};
use parol6_core::program::runner::{ProgramRunner, RunOptions, RunState};
use parol6_core::sim::{SimConfig, SimHandle, SimMode};
use parol6_core::telemetry::LinkHealth;

use super::common::tool_of;
use super::common::{RateArgs, open};
use super::options::{ConnectArgs, RobotArgs, f64_within};
use super::record::{Telemetry, link_health, urdf_text};
use super::{CliError, CliResult, interrupt, print_json};

/// Simulated seconds per wall second of a headless run without `--realtime`; the simulation
/// thread runs behind when the machine cannot keep up.
pub const HEADLESS_TIME_SCALE: f64 = 20.0;

/// Arguments of `parol6 program`.
#[derive(Debug, clap::Args)]
pub struct ProgramArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: ProgramCommand,
}

/// `parol6 program` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum ProgramCommand {
    /// Pre-flight a program before anything moves: reachability, limits, joint and motor
    /// speeds, singularities, collisions, duration. Exit 2 when it finds an error.
    Check {
        /// Program file: .json (native), .gcode/.nc, .csv point table, .txt commander program.
        file: PathBuf,
        /// Start pose J1,…,J6 in degrees (default: the standby pose).
        #[arg(long, value_name = "J1,…,J6", allow_hyphen_values = true)]
        start_deg: Option<String>,
        /// Print the report as JSON (`{"ok","moves","duration_s","issues":[…],"plan":[…]}`; the plan
        /// lists each planned step: index, line, kind, config, start_tcp / end_tcp in mm and deg,
        /// duration_s).
        #[arg(long)]
        json: bool,
        /// Also print the plan, a line per planned step: line, kind, the configuration it ends in
        /// (shoulder/elbow/wrist), its duration and the TCP where it ends (mm, roll/pitch/yaw deg).
        #[arg(long, conflicts_with = "json")]
        plan: bool,
        /// G-code A B C: commander (R = Rx(C)·Ry(B)·Rz(A), the default) or xyz
        /// (R = Rx(A)·Ry(B)·Rz(C)). A file's `; parol6: abc=…` header wins over the default; an
        /// --abc that contradicts the header is an error naming its line.
        #[arg(long, value_name = "commander|xyz")]
        abc: Option<AbcConvention>,
    },
    /// Run a program: on the headless simulation (as fast as it can unless --realtime), or
    /// with --fake-robot / --port on the controller. Prints a JSON summary (`schedule_slip_s`:
    /// how much later than planned the steps ran where they were handed over late). A pause
    /// step (G-code M0) waits for an operator, and a headless run has none: it is refused
    /// before anything moves (naming its line) unless --skip-pauses. Ctrl-C or SIGTERM stops
    /// the arm (the robot holds, then IDLE), closes the recording and exits 130.
    Run {
        /// Program file: .json (native), .gcode/.nc, .csv point table, .txt commander program.
        file: PathBuf,
        /// Start pose J1,…,J6 in degrees (default: the standby pose), as for `program check`:
        /// the file is read and checked from there. The simulation starts there; on the robot
        /// (--fake-robot / --port) the arm must already be there (within 0.1° on every joint:
        /// the run is refused otherwise; move it with `parol6 hw move --joints … --deg`).
        /// Without it the robot runs from wherever it is.
        #[arg(long, value_name = "J1,…,J6", allow_hyphen_values = true)]
        start_deg: Option<String>,
        /// Speed override: every step's speed × this, 0.01–1.
        #[arg(long, default_value_t = 1.0, value_parser = f64_within(0.01, 1.0))]
        speed: f64,
        /// Run the simulation in real time.
        #[arg(long)]
        realtime: bool,
        /// Record the run to this MCAP file (Foxglove / Lichtblick; `parol6 mcap info|csv`).
        #[arg(long, value_name = "OUT.mcap", value_parser = super::options::output_file)]
        record: Option<PathBuf>,
        /// G-code A B C: commander (R = Rx(C)·Ry(B)·Rz(A), the default) or xyz
        /// (R = Rx(A)·Ry(B)·Rz(C)). A file's `; parol6: abc=…` header wins over the default; an
        /// --abc that contradicts the header is an error naming its line.
        #[arg(long, value_name = "commander|xyz")]
        abc: Option<AbcConvention>,
        /// Run through pause steps (G-code M0) instead of refusing the program: nobody can
        /// resume a headless run. The JSON lists them as `skipped_pauses` (step, line).
        /// Optional pauses (M1) never pause a headless run.
        #[arg(long)]
        skip_pauses: bool,

        /// Session settings (robot only).
        #[command(flatten)]
        rate: RateArgs,
    },
    /// Inverse dynamics of a program before it runs: the joint torques (gravity + inertial +
    /// Coriolis) along its planned trajectories, each joint's peak against its limit, and a
    /// warning for every stretch over a limit (the PAROL6's limits: motor holding torque ×
    /// gear reduction).
    Torques {
        /// Program file: .json (native), .gcode/.nc, .csv point table, .txt commander program.
        file: PathBuf,
        /// Start pose J1,…,J6 in degrees (default: the standby pose).
        #[arg(long, value_name = "J1,…,J6", allow_hyphen_values = true)]
        start_deg: Option<String>,
        /// Print JSON (`{"joints","limits_nm","peak_abs_nm","duration_s","warnings":[…]}`).
        #[arg(long)]
        json: bool,
        /// With --json, add the time series (`time_s`, `torques_nm[joint][sample]`, 100 Hz).
        #[arg(long, requires = "json")]
        series: bool,
    },
    /// Convert a program between formats, chosen by the extensions: .json (native),
    /// .gcode/.nc, .csv point table, .txt commander program; or a recording (.mcap) into
    /// G-code of its TCP path. A step the target format cannot hold is an error naming it;
    /// nothing is written then.
    Convert {
        /// The program to read.
        input: PathBuf,
        /// The file to write (replaced atomically).
        output: PathBuf,
        /// The pose the program starts from, J1,…,J6 in degrees (default: the standby pose):
        /// where G-code axes that are not yet set take their values.
        #[arg(long, value_name = "J1,…,J6", allow_hyphen_values = true)]
        start_deg: Option<String>,
        /// G-code A B C, read (a .gcode input) and written (a .gcode output): commander
        /// (R = Rx(C)·Ry(B)·Rz(A), the default) or xyz (R = Rx(A)·Ry(B)·Rz(C)). An input's
        /// `; parol6: abc=…` header wins over the default; an --abc that contradicts it is an
        /// error naming its line.
        #[arg(long, value_name = "commander|xyz")]
        abc: Option<AbcConvention>,
    },
}

impl ProgramCommand {
    /// The subcommand's name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Check { .. } => "check",
            Self::Run { .. } => "run",
            Self::Torques { .. } => "torques",
            Self::Convert { .. } => "convert",
        }
    }

    /// True when it talks to a controller when asked to (`--port`, `--fake-robot`).
    pub fn talks_to_controller(&self) -> bool {
        matches!(self, Self::Run { .. })
    }
}

/// Runs `parol6 program …`.
pub fn run(args: &ProgramArgs, robot: &RobotArgs, connect: &ConnectArgs) -> CliResult {
    match &args.command {
        ProgramCommand::Check { file, start_deg, json, plan, abc } => {
            let model = robot.load()?;
            let start = start_pose(start_deg.as_deref(), &model)?;
            let program = load_with_abc(file, &model, &start, *abc)?;
            let report = check_program(&model, &program, &start, CheckOptions::default());
            if *json {
                print_json(&serde_json::to_value(&report).map_err(|e| CliError::runtime(e.to_string()))?)?;
            } else {
                print_report(file, &report, *plan)?;
            }
            if report.ok { Ok(()) } else { Err(CliError { status: super::EXIT_USAGE, message: String::new() }) }
        }
        ProgramCommand::Run { file, start_deg, speed, realtime, rate, record, abc, skip_pauses } => {
            let model = robot.load()?;
            let start = start_pose(start_deg.as_deref(), &model)?;
            if let Err(e) = model.limits.check(&start) {
                return Err(CliError::usage(format!("--start-deg: the start pose is outside the limits: {e}")));
            }
            let mut program = load_with_abc(file, &model, &start, *abc)?;
            let skipped_pauses = headless_pauses(file, &mut program, *skip_pauses)?;
            // --tracking, else the program's own, else the default
            let tracking = rate.tracking.or(program.tracking).unwrap_or_default();
            let rate = &RateArgs { tracking: Some(tracking), ..rate.clone() };
            let opts = RunOptions { speed_override: *speed, ..RunOptions::default() };
            let robot_link = connect.port.is_some() || connect.fake_robot;
            if robot_link && *realtime {
                return Err(CliError::usage(
                    "--realtime applies to the simulation; the robot always runs in real time",
                ));
            }
            // the file is created once the backend is open and at the start pose
            let telemetry = match record {
                Some(path) => Some(
                    Telemetry::prepare(&model, tool_of(robot), &urdf_text(robot)?, path, &program.name)?
                        .with_tracking(tracking),
                ),
                None => None,
            };
            let tap = telemetry.as_ref().map(Telemetry::tap);
            let begin = || telemetry.as_ref().map_or(Ok(()), Telemetry::begin);
            let mut summary = if robot_link {
                // the session is dropped before the emulator behind it
                let link = open(connect, rate, tap, model.tool)?;
                let _emulator = link.emulator;
                let session = Arc::new(link.session);
                if start_deg.is_some() {
                    arm_at(&session.robot_state(), &start)?;
                }
                begin()?;
                let poll = || (session.robot_state(), Some(link_health(&session.snapshot())));
                run_on(Arc::clone(&session) as Arc<dyn RobotBackend>, model, program, opts, telemetry.as_ref(), &poll)
            } else {
                let time_scale = if *realtime { 1.0 } else { HEADLESS_TIME_SCALE };
                let config = SimConfig { mode: SimMode::Dynamic, time_scale, tracking, ..SimConfig::default() };
                let sim = Arc::new(SimHandle::spawn_with_tap(model.clone(), config, tap).map_err(CliError::usage)?);
                if start_deg.is_some() {
                    place_sim(&sim, &start)?;
                }
                begin()?;
                let poll = || (sim.state(), None);
                run_on(Arc::clone(&sim) as Arc<dyn RobotBackend>, model, program, opts, telemetry.as_ref(), &poll)
            };
            summary.json["tracking"] = serde_json::json!(tracking.name());
            if let Some(t) = telemetry {
                summary.json["recording"] = t.finish()?;
            }
            if !summary.json.is_null() {
                summary.json["skipped_pauses"] = serde_json::json!(
                    skipped_pauses
                        .iter()
                        .filter(|p| p.step <= summary.steps_done)
                        .map(|p| serde_json::json!({"step": p.step, "line": p.line}))
                        .collect::<Vec<_>>()
                );
            }
            if interrupt::requested() {
                summary.json["interrupted"] = interrupt::json();
                let what = match summary.json["recording"]["file"].as_str() {
                    Some(f) => format!("the run stopped; recording {f} closed"),
                    None => "the run stopped".to_string(),
                };
                print_json(&summary.json)?;
                return Err(interrupt::error(what));
            }
            print_json(&summary.json)?;
            summary.outcome
        }
        ProgramCommand::Torques { file, start_deg, json, series } => {
            let model = robot.load()?;
            let start = start_pose(start_deg.as_deref(), &model)?;
            let program = load(file, &model, &start)?;
            super::program_torques::run(file, &model, &program, &start, *json, *series)
        }
        ProgramCommand::Convert { input, output, start_deg, abc } => {
            if is_recording(input) {
                return recording_to_gcode_file(input, output, abc.unwrap_or_default());
            }
            let model = robot.load()?;
            let start = start_pose(start_deg.as_deref(), &model)?;
            let program = load_with_abc(input, &model, &start, *abc)?;
            let ctx = FormatContext { abc: abc_choice(*abc), ..FormatContext::new(&model, &start) };
            write_program(&program, output, &ctx).map_err(cli_error)?;
            print_json(&serde_json::json!({
                "input": input.display().to_string(),
                "output": output.display().to_string(),
                "name": program.name,
                "steps": program.steps.len(),
                "notes": ProgramFormat::from_path(output).map(|f| export_notes(&program, f)).unwrap_or_default(),
            }))
        }
    }
}

fn is_recording(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("mcap"))
}

/// `program convert REC.mcap OUT.gcode`: the recorded TCP path (`/tcp_pose`) as G1 lines
/// within 0.1 mm / 0.5° of it.
fn recording_to_gcode_file(input: &Path, output: &Path, abc: AbcConvention) -> CliResult {
    use parol6_core::program::gcode::{PathTolerance, recording_to_gcode};
    let ext = output.extension().and_then(|e| e.to_str()).unwrap_or_default().to_ascii_lowercase();
    if !["gcode", "nc", "ngc"].contains(&ext.as_str()) {
        return Err(CliError::usage(format!(
            "{}: a recording converts to G-code only (.gcode, .nc, .ngc)",
            output.display()
        )));
    }
    let bytes = super::mcap::read_recording_file(input)?;
    let text = recording_to_gcode(&bytes, &PathTolerance::default(), abc)
        .map_err(|e| CliError::usage(format!("{}: {e}", input.display())))?;
    let lines = text.lines().filter(|l| l.starts_with("G1")).count();
    parol6_core::fsio::write_atomic_bytes(output, text.as_bytes())?;
    print_json(&serde_json::json!({
        "input": input.display().to_string(),
        "output": output.display().to_string(),
        "g1_lines": lines,
        "tolerance_mm": PathTolerance::default().position_mm,
    }))
}

/// `--start-deg`, or the standby / home pose.
fn start_pose(text: Option<&str>, model: &RobotModel) -> Result<Vec<f64>, CliError> {
    match text {
        Some(text) => parse_joints_deg(text, model.dof()),
        None => Ok(parol6_core::motion::home_position(model)),
    }
}

/// Largest difference between the arm's commanded joints and `--start-deg` on the robot, rad.
const START_TOLERANCE_RAD: f64 = 0.1 * std::f64::consts::PI / 180.0;

/// Refuses a run on the robot unless its commanded joints are at `start`.
fn arm_at(state: &RobotState, start: &[f64]) -> Result<(), CliError> {
    let q = &state.commanded.q;
    let off = q.iter().zip(start).enumerate().find(|(_, (a, b))| (*a - *b).abs() > START_TOLERANCE_RAD);
    match off {
        None if q.len() == start.len() => Ok(()),
        _ => Err(CliError::usage(format!(
            "--start-deg: the arm is at [{}]° (J{}), not at the start pose; move it there first \
             (parol6 hw move --joints … --deg) or leave --start-deg out to run from where it is",
            q.iter().map(|v| format!("{:.2}", v.to_degrees())).collect::<Vec<_>>().join(", "),
            off.map_or(1, |(i, _)| i + 1)
        ))),
    }
}

/// Places the simulated arm at `start` (at rest) and waits until its state shows it.
fn place_sim(sim: &SimHandle, start: &[f64]) -> Result<(), CliError> {
    sim.send(parol6_core::sim::SimCommand::Teleport(start.to_vec()))
        .map_err(|e| CliError::runtime(format!("--start-deg: {e}")))?;
    let t0 = Instant::now();
    loop {
        let s = sim.state();
        let there = s.commanded.q.iter().zip(start).all(|(a, b)| (a - b).abs() < 1e-9);
        if there && !s.moving {
            return Ok(());
        }
        if t0.elapsed() > Duration::from_secs(5) {
            return Err(CliError::runtime("--start-deg: the simulation did not take the start pose"));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// A file that cannot be read or written is a runtime error (exit 1); bad content, an unknown
/// extension or a step the format cannot hold is a usage error (exit 2).
fn cli_error(e: ProgramIoError) -> CliError {
    match e {
        ProgramIoError::Io { .. } => CliError::runtime(e.to_string()),
        ProgramIoError::File(f) => f.into(),
        _ => CliError::usage(e.to_string()),
    }
}

/// The summary of a run and how the command ends.
struct RunSummary {
    json: serde_json::Value,
    /// Program steps completed.
    steps_done: usize,
    outcome: CliResult,
}

/// A pause step run through with `--skip-pauses`.
struct SkippedPause {
    /// 1-based step.
    step: usize,
    /// 1-based line of the file (0: unknown).
    line: usize,
}

/// Pause steps (G-code `M0`) wait for an operator to resume, and a headless run has none: they
/// are refused, naming the first one's line, unless `skip`, where they are made optional (an
/// optional pause does not pause a run without optional pauses) and returned.
fn headless_pauses(file: &Path, program: &mut Program, skip: bool) -> Result<Vec<SkippedPause>, CliError> {
    use parol6_core::program::Step;
    let pauses: Vec<usize> = program
        .steps
        .iter()
        .enumerate()
        .filter(|(_, s)| s.step == Step::Pause { optional: false })
        .map(|(i, _)| i)
        .collect();
    let Some(&first) = pauses.first() else { return Ok(Vec::new()) };
    if !skip {
        let more = match pauses.len() {
            1 => String::new(),
            n => format!(" (and {} more)", n - 1),
        };
        return Err(CliError::usage(format!(
            "{}:{}: step {}: a pause step (G-code M0) waits for the operator to resume, and a headless run has \
             no operator{more}: run it in the window, or pass --skip-pauses to run through the pauses",
            file.display(),
            program.steps[first].line,
            first + 1
        )));
    }
    Ok(pauses
        .into_iter()
        .map(|i| {
            program.steps[i].step = Step::Pause { optional: true };
            SkippedPause { step: i + 1, line: program.steps[i].line }
        })
        .collect())
}

type StatePoll<'a> = dyn Fn() -> (Arc<RobotState>, Option<LinkHealth>) + Sync + 'a;

fn run_on(
    backend: Arc<dyn RobotBackend>,
    model: RobotModel,
    program: Program,
    opts: RunOptions,
    telemetry: Option<&Telemetry>,
    poll: &StatePoll<'_>,
) -> RunSummary {
    let name = backend.state().backend.clone();
    let wall = Instant::now();
    let runner = match ProgramRunner::start(Arc::clone(&backend), model, program, opts) {
        Ok(r) => r,
        Err(e) => {
            let outcome = Err(CliError::runtime(format!("cannot start the program thread: {e}")));
            return RunSummary { json: serde_json::Value::Null, steps_done: 0, outcome };
        }
    };
    // a progress line on stderr while it runs; the program step goes into the recording
    let wait = || {
        let mut last = Instant::now();
        let mut step = None;
        while !runner.progress().state.is_finished() {
            if interrupt::sleep(Duration::from_millis(20)) {
                stop_on_signal(&runner, backend.as_ref());
                return;
            }
            let p = runner.progress();
            if let Some(t) = telemetry
                && step != Some(p.step)
            {
                step = Some(p.step);
                t.set_program_step(step);
            }
            if last.elapsed() >= Duration::from_secs(1) {
                super::output::progress(format!("step {} of {}, {:.1} s left", p.step + 1, p.steps, p.time_left_s));
                last = Instant::now();
            }
        }
    };
    match telemetry {
        Some(t) => t.feed_while(poll, wait),
        None => wait(),
    }
    let p = runner.join();
    if interrupt::requested() {
        // the robot holds a moment before its session closes with IDLE frames
        wait_at_rest(backend.as_ref());
    }
    let (state, failure) = match &p.state {
        _ if interrupt::requested() => ("interrupted", None),
        RunState::Done => ("done", None),
        RunState::Stopped => ("stopped", None),
        RunState::Failed(why) => ("failed", Some(why.clone())),
        _ => ("ended", None),
    };
    let json = serde_json::json!({
        "program": p.name,
        "backend": name,
        "state": state,
        "reason": failure,
        "steps_done": p.steps_done,
        "steps": p.steps,
        "planned_s": p.planned_s,
        "duration_s": p.clock_s.1 - p.clock_s.0,
        "wall_s": wall.elapsed().as_secs_f64(),
        "max_tracking_error_deg": p.max_tracking_error_rad.to_degrees(),
        "schedule_slip_s": p.schedule_slip_s,
        "stop_failed": p.stop_failed,
    });
    if let Some(failure) = &p.stop_failed {
        super::warn(failure);
    }
    let outcome = match failure {
        None => Ok(()),
        Some(why) => {
            let refused = why.starts_with("pre-flight")
                || why.contains("not homed")
                || why.contains("does not accept motion")
                || why.contains("is moving")
                || why.starts_with("step ");
            Err(if refused { CliError::usage(why) } else { CliError::runtime(why) })
        }
    };
    RunSummary { json, steps_done: p.steps_done, outcome }
}

/// A signal during a run: the runner schedules nothing more and the backend gets STOP (it
/// holds the commanded position of this instant), as the window's STOP button does.
fn stop_on_signal(runner: &ProgramRunner, backend: &dyn RobotBackend) {
    runner.abort();
    if let Err(e) = backend.send(parol6_core::motion::MotionCommand::Stop) {
        super::warn(format!("STOP after the signal: {e}"));
    }
}

/// Waits (at most 0.4 s) until the backend holds still after STOP.
fn wait_at_rest(backend: &dyn RobotBackend) {
    let t0 = Instant::now();
    while backend.state().moving && t0.elapsed() < Duration::from_millis(400) {
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Reads a program file of any format (by extension), starting from `start_q` where the format
/// needs a start pose; errors name the file and where in it.
pub fn load(path: &Path, model: &RobotModel, start_q: &[f64]) -> Result<Program, CliError> {
    load_with_abc(path, model, start_q, None)
}

/// [`load`] with G-code `A B C` as `--abc` says (`None`: the default, or the file's header).
pub fn load_with_abc(
    path: &Path,
    model: &RobotModel,
    start_q: &[f64],
    abc: Option<AbcConvention>,
) -> Result<Program, CliError> {
    let ctx = FormatContext { abc: abc_choice(abc), ..FormatContext::new(model, start_q) };
    read_program(path, &ctx).map_err(cli_error)
}

/// `--abc` given: asked for explicitly (a header that contradicts it is an error); not given:
/// the default, which a file's header overrides.
fn abc_choice(abc: Option<AbcConvention>) -> AbcChoice {
    abc.map_or_else(AbcChoice::default, AbcChoice::explicit)
}

fn parse_joints_deg(text: &str, dof: usize) -> Result<Vec<f64>, CliError> {
    let vals: Vec<f64> = text
        .split(',')
        .enumerate()
        .map(|(i, s)| match s.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v.to_radians()),
            _ => {
                Err(CliError::usage(format!("--start-deg: value {} (\"{}\") is not a finite number", i + 1, s.trim())))
            }
        })
        .collect::<Result<_, _>>()?;
    if vals.len() != dof {
        return Err(CliError::usage(format!("--start-deg: {} values given, the robot has {dof} joints", vals.len())));
    }
    Ok(vals)
}

fn print_report(file: &Path, r: &CheckReport, plan: bool) -> CliResult {
    use std::fmt::Write as _;
    let mut out = String::new();
    if plan {
        for p in &r.plan {
            let [x, y, z] = p.end_tcp.position_mm;
            let [roll, pitch, yaw] = p.end_tcp.rpy_deg;
            let _ = writeln!(
                out,
                "{}:{}: step {}: {:<13} {:<18} {:>8.2} s  to ({x:.2}, {y:.2}, {z:.2}) mm ({roll:.2}, {pitch:.2}, {yaw:.2})°",
                file.display(),
                p.line,
                p.index + 1,
                p.kind,
                p.config.as_deref().unwrap_or("-"),
                p.duration_s
            );
        }
    }
    for i in &r.issues {
        let sev = if i.severity == Severity::Error { "error" } else { "warning" };
        let _ = writeln!(out, "{}:{}: {sev}: step {}: {}", file.display(), i.line, i.move_index + 1, i.message);
    }
    let _ = writeln!(
        out,
        "{}: {} steps, {:.2} s, {} errors, {} warnings",
        if r.ok { "ok" } else { "refused" },
        r.moves,
        r.duration_s,
        r.issues.iter().filter(|i| i.severity == Severity::Error).count(),
        r.issues.iter().filter(|i| i.severity == Severity::Warning).count()
    );
    super::output::print_line(out.trim_end())
}

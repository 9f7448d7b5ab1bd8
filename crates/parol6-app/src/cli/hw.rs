//! `parol6 hw …`: the serial controller from the command line (owned by the hardware work);
//! `parol6 bench serial` is in [`super::hw_bench`].
//!
//! Every subcommand prints JSON on stdout, except `emulate`, whose first stdout line is the
//! pseudo-terminal path (then one JSON line per stdin command). The subcommands that talk to a
//! controller take the global `--port P` or `--fake-robot` (the built-in emulator, powered up
//! homed at standby, started in-process for the one command).
//!
//! `jog` and `move` check their request and open the controller before `--record` creates its
//! file. On SIGINT / SIGTERM ([`super::interrupt`]) they stop the arm the normal way: the
//! session holds (MOVE frames at a fixed target, [`super::hw_stop`]), then closes with IDLE
//! frames as on link loss; the recording is closed and the command exits 130.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crossbeam_channel::Sender;
use parol6_core::model::PAROL6_URDF;
use parol6_core::motion::MotionSample;
use parol6_core::motion::tracking::TrackingMode;
use parol6_core::{RobotModel, Tool};

use parol6_core::profile::ProfileKind;
use parol6_hw::HwError;
use parol6_hw::emulator::{EmulatorConfig, EmulatorHandle};
use parol6_hw::frame::CommandCode;
use parol6_hw::session::{HomingState, Session, Snapshot};
use serde_json::json;

use super::common::{RateArgs, hw_err, open, parse_list};
use super::hw_checks::{JogEnd, jog_back_inside, jog_outcome, new_fault, read_command_line, ready_to_move};
use super::options::{ConnectArgs, f64_above, f64_within};
use super::output::print_line;
use super::record::{Telemetry, link_health};
use super::{CliError, CliResult, interrupt, print_json};

/// The tool of the `hw` commands: they drive the bare PAROL6 (no `--tool`; their recordings say `Tool::None`):
/// the session's TCP is the flange.
fn bare_flange() -> parol6_core::na::Isometry3<f64> {
    parol6_core::na::Isometry3::identity()
}

/// Slowest `hw move --speed` (fraction of the max joint speeds): the longest move of the arm
/// (every joint end to end, jerk-limited) then takes about 90 s.
pub const MIN_MOVE_SPEED: f64 = 0.05;

/// A jogged joint this close to a limit, rad, has reached it (a few steps).
const LIMIT_REACHED_RAD: f64 = 1e-3;

/// Arguments of `parol6 hw`.
#[derive(Debug, clap::Args)]
pub struct HwArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: HwCommand,
}

/// `parol6 hw` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum HwCommand {
    /// List serial ports (PAROL6 boards, USB 0483:5740, first).
    Ports,
    /// Print one status snapshot.
    Status(RateArgs),
    /// Send ENABLE (101).
    Enable(RateArgs),
    /// Send DISABLE (102).
    Disable(RateArgs),
    /// Home all joints and wait (fails after 45 s).
    Home(RateArgs),
    /// Jog one joint for a while (streamed MOVE targets with a dead-man).
    Jog {
        /// Session settings.
        #[command(flatten)]
        rate: RateArgs,
        /// Joint number, 1–6.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=6))]
        joint: u64,
        /// Speed fraction of the jog speed, −1…1 (the sign is the direction).
        #[arg(long, allow_hyphen_values = true, value_parser = f64_within(-1.0, 1.0))]
        speed: f64,
        /// Duration, s, > 0 and ≤ 60.
        #[arg(long, value_parser = f64_above(0.0, 60.0))]
        seconds: f64,
        /// Record the session to this MCAP file.
        #[arg(long, value_name = "OUT.mcap", value_parser = super::options::output_file)]
        record: Option<PathBuf>,
        /// The operator's confirmation for a joint measured a little beyond one of its limits
        /// (after a crash): jog it back inside (JOG speed frames at a quarter of the jog speed,
        /// inward only) until it is within its limits. Without it such a jog is refused.
        #[arg(long)]
        beyond_limit: bool,
    },
    /// Move to a joint pose along the synchronised profile.
    Move {
        /// Session settings.
        #[command(flatten)]
        rate: RateArgs,
        /// Six joint values J1,…,J6, finite numbers within the joint limits (rad, or degrees
        /// with --deg).
        #[arg(long, value_name = "J1,…,J6", allow_hyphen_values = true)]
        joints: String,
        /// Joint values are in degrees.
        #[arg(long)]
        deg: bool,
        /// Speed fraction of the max joint speeds, 0.05–1 (at 0.05 the longest move takes about 90 s).
        #[arg(long, default_value_t = 0.5, value_parser = f64_within(MIN_MOVE_SPEED, 1.0))]
        speed: f64,
        /// Jerk-limited (quintic) instead of trapezoidal profile.
        #[arg(long)]
        smooth: bool,
        /// Record the session to this MCAP file.
        #[arg(long, value_name = "OUT.mcap", value_parser = super::options::output_file)]
        record: Option<PathBuf>,
    },
    /// Run the controller emulator on a pseudo-terminal; prints its path first.
    /// Stdin commands: `estop on|off`, `in1 on|off`, `in2 on|off`, `mute on|off`, `state`, `quit`.
    Emulate {
        /// Power up homed at the standby pose (the firmware boots unhomed at 0 steps).
        #[arg(long)]
        homed: bool,
        /// Duration of the compressed homing sequence, s, > 0 and ≤ 60.
        #[arg(long, default_value_t = 1.0, value_parser = f64_above(0.0, 60.0))]
        home_seconds: f64,
    },
}

impl HwCommand {
    /// The subcommand's name on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Ports => "ports",
            Self::Status(_) => "status",
            Self::Enable(_) => "enable",
            Self::Disable(_) => "disable",
            Self::Home(_) => "home",
            Self::Jog { .. } => "jog",
            Self::Move { .. } => "move",
            Self::Emulate { .. } => "emulate",
        }
    }

    /// True for the subcommands that open a controller (and take `--port` / `--fake-robot`).
    pub fn talks_to_controller(&self) -> bool {
        !matches!(self, Self::Ports | Self::Emulate { .. })
    }
}

/// Waits until `code` has been written at least once after `frames_before` frames.
fn wait_sent(session: &Session, code: CommandCode, frames_before: u64) -> Result<(), CliError> {
    session
        .wait_until(Duration::from_secs(2), |s| s.last_command == Some(code) && s.frames_sent > frames_before)
        .map(|_| ())
        .map_err(hw_err)
}

/// Whether the board is enabled, as far as this session knows, and on what basis: what this
/// session commanded, or a homing that succeeded (the firmware homes only while enabled).
/// Otherwise unknown (`null`): the status frame does not report it; the board powers up enabled.
fn enabled_json(s: &Snapshot) -> (serde_json::Value, &'static str) {
    enabled_known(s.enabled, &s.homing, s.needs_enable || s.estop_pressed)
}

fn enabled_known(
    commanded: Option<bool>,
    homing: &HomingState,
    estop_since: bool,
) -> (serde_json::Value, &'static str) {
    match (commanded, homing) {
        (Some(e), _) => (json!(e), "commanded"),
        (None, HomingState::Done) if !estop_since => (json!(true), "homed"),
        _ => (serde_json::Value::Null, "unknown"),
    }
}

fn summary(s: &Snapshot) -> serde_json::Value {
    let (enabled, basis) = enabled_json(s);
    json!({
        "port": s.port,
        "link": s.link,
        "joint_steps": s.joint_steps,
        "joint_deg": s.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
        "homed": s.homed,
        "estop_pressed": s.estop_pressed,
        "enabled": enabled,
        "enabled_basis": basis,
        "fault": s.fault,
    })
}

/// Runs `parol6 hw`.
pub fn run(args: &HwArgs, connect: &ConnectArgs) -> CliResult {
    match &args.command {
        HwCommand::Ports => {
            let ports = parol6_hw::list_ports().map_err(hw_err)?;
            print_json(&json!({ "ports": ports }))
        }
        HwCommand::Status(rate) => {
            let link = open(connect, rate, None, bare_flange())?;
            let s = link.session.wait_until(Duration::from_secs(2), |s| s.status_frames >= 3).map_err(hw_err)?;
            let mut out = s.to_json();
            let (enabled, basis) = enabled_json(&s);
            out["enabled"] = enabled;
            out["enabled_basis"] = json!(basis);
            print_json(&out)
        }
        HwCommand::Enable(rate) => send_latch(connect, rate, "enable", CommandCode::Enable, Session::enable),
        HwCommand::Disable(rate) => send_latch(connect, rate, "disable", CommandCode::Disable, Session::disable),
        HwCommand::Home(rate) => {
            let link = open(connect, rate, None, bare_flange())?;
            let t0 = Instant::now();
            link.session.home_blocking().map_err(hw_err)?;
            let s = link.session.snapshot();
            print_json(&json!({
                "command": "home", "ok": true, "seconds": t0.elapsed().as_secs_f64(), "state": summary(&s)
            }))
        }
        HwCommand::Jog { rate, joint, speed, seconds, record, beyond_limit } => {
            let request = JogRequest { joint: *joint, speed: *speed, seconds: *seconds, beyond_limit: *beyond_limit };
            recorded(record.as_deref(), rate.tracking.unwrap_or_default(), |tap, t| {
                jog(connect, rate, &request, tap, t)
            })
        }
        HwCommand::Move { rate, joints, deg, speed, smooth, record } => {
            let target = MoveTarget { joints, deg: *deg, speed: *speed, smooth: *smooth };
            recorded(record.as_deref(), rate.tracking.unwrap_or_default(), |tap, t| {
                move_to(connect, rate, &target, tap, t)
            })
        }
        HwCommand::Emulate { homed, home_seconds } => emulate_until_signal(*homed, *home_seconds),
    }
}

/// Runs `body` with a recorder when `record` names a file, and prints its JSON with the
/// recording's summary added. The recorder's file is created by the body ([`Telemetry::begin`])
/// once the request is checked and the controller answers: a refused request or a port that
/// cannot be opened leaves an existing file alone. A body stopped by a signal returns its JSON
/// with `"interrupted"` set; the command then exits 130.
fn recorded(
    record: Option<&Path>,
    tracking: TrackingMode,
    body: impl FnOnce(Option<Sender<MotionSample>>, Option<&Telemetry>) -> Result<serde_json::Value, CliError>,
) -> CliResult {
    let telemetry = match record {
        Some(p) => {
            Some(Telemetry::prepare(&RobotModel::parol6(), Tool::None, PAROL6_URDF, p, "")?.with_tracking(tracking))
        }
        None => None,
    };
    let mut out = body(telemetry.as_ref().map(Telemetry::tap), telemetry.as_ref())?;
    if let Some(t) = telemetry {
        out["recording"] = t.finish()?;
    }
    if out["interrupted"].is_null() {
        return print_json(&out);
    }
    let what = match out["recording"]["file"].as_str() {
        Some(f) => {
            format!("the arm held, then IDLE; recording {f} closed with {} samples", out["recording"]["samples"])
        }
        None => "the arm held, then IDLE".to_string(),
    };
    print_json(&out)?;
    Err(interrupt::error(what))
}

/// Runs `body`, feeding the session's state and link health to the recorder meanwhile.
fn fed<R>(telemetry: Option<&Telemetry>, session: &Session, body: impl FnOnce() -> R) -> R {
    match telemetry {
        Some(t) => {
            let poll = || (session.robot_state(), Some(link_health(&session.snapshot())));
            t.feed_while(&poll, body)
        }
        None => body(),
    }
}

/// The arguments of `hw jog`.
struct JogRequest {
    joint: u64,
    speed: f64,
    seconds: f64,
    beyond_limit: bool,
}

fn jog(
    connect: &ConnectArgs,
    rate: &RateArgs,
    request: &JogRequest,
    tap: Option<Sender<MotionSample>>,
    telemetry: Option<&Telemetry>,
) -> Result<serde_json::Value, CliError> {
    let JogRequest { joint, speed, seconds, beyond_limit } = *request;
    let joint_index = match joint {
        1..=6 => (joint - 1) as usize,
        _ => return Err(CliError::usage(format!("--joint must be 1–6 (got {joint})"))),
    };
    let duration = Duration::try_from_secs_f64(seconds)
        .ok()
        .filter(|d| !d.is_zero() && d.as_secs_f64() <= 60.0)
        .ok_or_else(|| CliError::usage(format!("--seconds must be > 0 and ≤ 60 (got {seconds})")))?;
    if !(speed.is_finite() && (-1.0..=1.0).contains(&speed)) {
        return Err(CliError::usage(format!("--speed must be within −1…1 (got {speed})")));
    }
    let link = open(connect, rate, tap, bare_flange())?;
    if let Some(t) = telemetry {
        t.begin()?;
    }
    let session = &link.session;
    let start = session.snapshot();
    ready_to_move(&start)?;
    if beyond_limit {
        let inside = fed(telemetry, session, || jog_back_inside(session, joint_index, speed, duration))?;
        let s = session.snapshot();
        return Ok(json!({
            "command": "jog", "joint": joint, "speed": speed, "seconds": seconds, "beyond_limit": true,
            "back_inside": inside, "start_steps": start.joint_steps, "end_steps": s.joint_steps, "state": summary(&s),
        }));
    }
    let end = fed(telemetry, session, || jog_for(session, joint_index, speed, duration))?;
    let s = session.snapshot();
    if interrupt::requested() {
        let out = json!({
            "command": "jog", "joint": joint, "speed": speed, "seconds": seconds,
            "start_deg": start.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
            "end_deg": s.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
        });
        return Ok(super::hw_stop::hold_before_closing(link, out));
    }
    let commanded = parol6_core::motion::RobotBackend::state(session).commanded.q.get(joint_index).copied();
    let commanded_steps = commanded.and_then(|q| parol6_hw::units::rad_to_steps(joint_index, q).ok());
    jog_outcome(joint_index, &start, &s, commanded_steps, &end)?;
    let stopped_at_limit = end.stopped_at_limit;
    Ok(json!({
        "command": "jog", "joint": joint, "speed": speed, "seconds": seconds, "stopped_at_limit": stopped_at_limit,
        "start_deg": start.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
        "end_deg": s.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
        "state": summary(&s),
    }))
}

/// Jogs for `duration` (or until the joint reaches its limit, or the session reports a fault:
/// the jog ends there), then releases.
fn jog_for(session: &Session, joint_index: usize, speed: f64, duration: Duration) -> Result<JogEnd, CliError> {
    let end = Instant::now() + duration;
    let mut stopped_at_limit = false;
    let before = session.snapshot();
    session.jog(joint_index, speed).map_err(hw_err)?;
    while Instant::now() < end {
        if interrupt::sleep(Duration::from_millis(50)) {
            // the caller holds, then closes
            return Ok(JogEnd { stopped_at_limit: false, fault: None });
        }
        if let Some(fault) = new_fault(&before, &session.snapshot()) {
            // The session stopped motion (an arm that does not follow, E-stop, impossible
            // positions …): no new jog from here.
            session.jog_release().map_err(hw_err)?;
            return Ok(JogEnd { stopped_at_limit: false, fault: Some(fault) });
        }
        if let Err(e) = session.jog(joint_index, speed) {
            // The session refuses to go on once the joint reaches its limit: the jog ends there.
            let limit = session.config().limits.iter().nth(joint_index).map(|l| (l.min, l.max));
            // the commanded position reaches the limit first; the measured one lags (MOVE law)
            let state = parol6_core::motion::RobotBackend::state(session);
            let at = state.commanded.q.get(joint_index).copied().unwrap_or(f64::NAN);
            match limit {
                Some((min, max)) if at <= min + LIMIT_REACHED_RAD || at >= max - LIMIT_REACHED_RAD => {
                    stopped_at_limit = true;
                    break;
                }
                _ => return Err(hw_err(e)),
            }
        }
    }
    session.jog_release().map_err(hw_err)?;
    std::thread::sleep(Duration::from_millis(300));
    Ok(JogEnd { stopped_at_limit, fault: None })
}

/// The arguments of `hw move`.
struct MoveTarget<'a> {
    joints: &'a str,
    deg: bool,
    speed: f64,
    smooth: bool,
}

fn move_to(
    connect: &ConnectArgs,
    rate: &RateArgs,
    target: &MoveTarget<'_>,
    tap: Option<Sender<MotionSample>>,
    telemetry: Option<&Telemetry>,
) -> Result<serde_json::Value, CliError> {
    let MoveTarget { joints, deg, speed, smooth } = *target;
    let mut goal = parse_list("--joints", joints, Some(6))?;
    if deg {
        goal.iter_mut().for_each(|v| *v = v.to_radians());
    }
    let kind = if smooth { ProfileKind::JerkLimited } else { ProfileKind::Trapezoidal };
    // Validate before touching the port.
    let limits = parol6_core::limits::JointLimits::parol6();
    limits.enforce(&goal, parol6_core::limits::LimitPolicy::Reject).map_err(CliError::usage)?;
    if !(speed.is_finite() && (MIN_MOVE_SPEED..=1.0).contains(&speed)) {
        return Err(CliError::usage(format!("--speed must be within {MIN_MOVE_SPEED}…1 (got {speed})")));
    }
    let link = open(connect, rate, tap, bare_flange())?;
    let session = &link.session;
    let start = session.snapshot();
    // Before planning from the measured position: it may be impossible (issue 29 item 9).
    ready_to_move(&start)?;
    let plan =
        parol6_core::profile::JointMove::parol6(&start.joint_rad, &goal, speed, kind).map_err(CliError::usage)?;
    let timeout = Duration::try_from_secs_f64(plan.duration_s() + 10.0)
        .map_err(|_| CliError::usage(format!("the move would take {} s", plan.duration_s())))?;
    if let Some(t) = telemetry {
        t.begin()?;
    }
    let t0 = Instant::now();
    let s = fed(telemetry, session, || session.move_to_blocking_or(&goal, speed, kind, timeout, &interrupt::requested))
        .map_err(hw_err)?;
    if interrupt::requested() {
        let out = json!({
            "command": "move", "ok": false, "planned_s": plan.duration_s(), "seconds": t0.elapsed().as_secs_f64(),
            "goal_deg": goal.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
        });
        return Ok(super::hw_stop::hold_before_closing(link, out));
    }
    Ok(json!({
        "command": "move", "ok": true, "planned_s": plan.duration_s(), "seconds": t0.elapsed().as_secs_f64(),
        "goal_deg": goal.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
        "state": summary(&s),
    }))
}

/// `hw enable` / `hw disable`: sends the latch command, waits until it is on the wire, prints
/// the resulting state.
fn send_latch(
    connect: &ConnectArgs,
    rate: &RateArgs,
    name: &str,
    code: CommandCode,
    op: fn(&Session) -> Result<(), HwError>,
) -> CliResult {
    let link = open(connect, rate, None, bare_flange())?;
    let before = link.session.snapshot().frames_sent;
    op(&link.session).map_err(hw_err)?;
    wait_sent(&link.session, code, before)?;
    print_json(&json!({"command": name, "ok": true, "state": summary(&link.session.snapshot())}))
}

pub(super) fn emulate(homed: bool, home_seconds: f64) -> CliResult {
    if !(home_seconds.is_finite() && home_seconds > 0.0 && home_seconds <= 60.0) {
        return Err(CliError::usage("--home-seconds must be > 0 and ≤ 60"));
    }
    let base = if homed { EmulatorConfig::homed_at_standby() } else { EmulatorConfig::default() };
    let config = EmulatorConfig { home_duration_s: home_seconds, log_commands: false, ..base };
    let emu = EmulatorHandle::spawn(config).map_err(hw_err)?;
    print_line(emu.path())?;
    let stdin = std::io::stdin();
    let mut input = stdin.lock();
    let mut inputs = (false, false);
    let mut buf = Vec::new();
    let mut line_no = 0u64;
    loop {
        line_no += 1;
        let line = match read_command_line(&mut input, line_no, &mut buf) {
            Ok(None) => break,
            Ok(Some(Ok(line))) => line,
            Ok(Some(Err(msg))) => {
                print_json(&json!({ "error": msg }))?;
                continue;
            }
            Err(e) => return Err(CliError::runtime(format!("cannot read stdin: {e}"))),
        };
        let words: Vec<&str> = line.split_whitespace().collect();
        let on = |w: Option<&&str>| matches!(w.copied(), Some("on" | "1" | "pressed" | "true"));
        let reply = match words.first().copied() {
            None => continue,
            Some("estop") => {
                emu.set_estop_pressed(on(words.get(1)));
                json!({"estop_pressed": on(words.get(1))})
            }
            Some("in1") | Some("in2") => {
                let level = on(words.get(1));
                if words[0] == "in1" {
                    inputs.0 = level;
                } else {
                    inputs.1 = level;
                }
                emu.set_inputs(inputs.0, inputs.1);
                json!({"in1": inputs.0, "in2": inputs.1})
            }
            Some("mute") => {
                emu.set_mute(on(words.get(1)));
                json!({"mute": on(words.get(1))})
            }
            Some("state") => serde_json::to_value(&*emu.snapshot()).unwrap_or_default(),
            Some("quit") | Some("exit") => return Ok(()),
            Some(other) => json!({"error": format!("unknown command {other}")}),
        };
        print_json(&reply)?;
    }
    // Stdin closed (e.g. started in the background): serve until killed.
    loop {
        std::thread::park();
    }
}

/// `hw emulate` until `quit` or a signal: the emulator serves its stdin on a thread of its own
/// (a read of stdin cannot be interrupted); a signal ends the command with 130 (the process
/// exit closes the pseudo-terminal).
fn emulate_until_signal(homed: bool, home_seconds: f64) -> CliResult {
    let (done_tx, done_rx) = crossbeam_channel::bounded(1);
    std::thread::Builder::new()
        .name("parol6-emulate".into())
        .spawn(move || {
            // the receiver is gone only once the command has ended
            if done_tx.send(emulate(homed, home_seconds)).is_err() {
                tracing::debug!("hw emulate ended after its command");
            }
        })
        .map_err(|e| CliError::runtime(format!("cannot start the emulator thread: {e}")))?;
    loop {
        match done_rx.recv_timeout(interrupt::POLL) {
            Ok(result) => return result,
            Err(crossbeam_channel::RecvTimeoutError::Timeout) if interrupt::requested() => {
                return Err(interrupt::error("emulator stopped"));
            }
            Err(crossbeam_channel::RecvTimeoutError::Timeout) => {}
            Err(crossbeam_channel::RecvTimeoutError::Disconnected) => {
                return Err(CliError::runtime("the emulator thread ended without a result"));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The help says the longest move at the minimum speed takes about 90 s.
    #[test]
    fn slowest_longest_move_takes_about_90_s() {
        let limits = parol6_core::limits::JointLimits::parol6();
        let from: Vec<f64> = limits.iter().map(|l| l.min).collect();
        let to: Vec<f64> = limits.iter().map(|l| l.max).collect();
        let plan = parol6_core::profile::JointMove::parol6(&from, &to, MIN_MOVE_SPEED, ProfileKind::JerkLimited)
            .expect("plan");
        eprintln!("longest move at speed {MIN_MOVE_SPEED}: {:.1} s", plan.duration_s());
        assert!((60.0..=120.0).contains(&plan.duration_s()), "{} s", plan.duration_s());
    }

    #[test]
    fn enabled_is_known_after_homing() {
        assert_eq!(enabled_known(None, &HomingState::NotRequested, false), (serde_json::Value::Null, "unknown"));
        assert_eq!(enabled_known(None, &HomingState::Done, false), (json!(true), "homed"));
        assert_eq!(enabled_known(None, &HomingState::Done, true), (serde_json::Value::Null, "unknown"));
        assert_eq!(enabled_known(Some(false), &HomingState::Done, false), (json!(false), "commanded"));
    }
}

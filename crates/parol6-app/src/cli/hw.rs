//! `parol6 hw …`: the serial controller from the command line (owned by the hardware work),
//! and `parol6 bench serial`.
//!
//! Every subcommand prints JSON on stdout, except `emulate`, whose first stdout line is the
//! pseudo-terminal path (then one JSON line per stdin command).

use std::io::{BufRead, Write};
use std::time::{Duration, Instant};

use parol6_core::profile::ProfileKind;
use parol6_hw::emulator::{EmulatorConfig, EmulatorHandle};
use parol6_hw::frame::CommandCode;
use parol6_hw::session::{LinkState, Session, SessionConfig, Snapshot};
use parol6_hw::{HwError, units};
use serde_json::json;

use super::bench::NsStats;
use super::{CliError, CliResult, print_json};

/// How long to wait for the first status frame.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(3);

/// Arguments of `parol6 hw`.
#[derive(Debug, clap::Args)]
pub struct HwArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: HwCommand,
}

/// Port selection shared by the subcommands.
#[derive(Debug, Clone, clap::Args)]
pub struct PortArgs {
    /// Serial port (default: the first USB device with VID:PID 0483:5740).
    #[arg(long, value_name = "P")]
    pub port: Option<String>,
    /// Command rate, Hz (50–500).
    #[arg(long, default_value_t = 100.0)]
    pub rate: f64,
}

/// `parol6 hw` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum HwCommand {
    /// List serial ports (PAROL6 boards, USB 0483:5740, first).
    Ports,
    /// Print one status snapshot.
    Status(PortArgs),
    /// Send ENABLE (101).
    Enable(PortArgs),
    /// Send DISABLE (102).
    Disable(PortArgs),
    /// Home all joints and wait (fails after 45 s).
    Home(PortArgs),
    /// Jog one joint for a while (streamed MOVE targets with a dead-man).
    Jog {
        /// Port selection.
        #[command(flatten)]
        port: PortArgs,
        /// Joint number, 1–6.
        #[arg(long)]
        joint: usize,
        /// Speed fraction −1…1 of the jog speed.
        #[arg(long, allow_hyphen_values = true)]
        speed: f64,
        /// Duration, s (0–60).
        #[arg(long)]
        seconds: f64,
    },
    /// Move to a joint pose along the synchronised profile.
    Move {
        /// Port selection.
        #[command(flatten)]
        port: PortArgs,
        /// Six joint values J1,…,J6 (rad, or degrees with --deg).
        #[arg(long, allow_hyphen_values = true, value_delimiter = ',')]
        joints: Vec<f64>,
        /// Joint values are in degrees.
        #[arg(long)]
        deg: bool,
        /// Speed fraction 0–1 of the max joint speeds.
        #[arg(long, default_value_t = 0.5)]
        speed: f64,
        /// Jerk-limited (quintic) instead of trapezoidal profile.
        #[arg(long)]
        smooth: bool,
    },
    /// Run the controller emulator on a pseudo-terminal; prints its path first.
    /// Stdin commands: `estop on|off`, `in1 on|off`, `in2 on|off`, `mute on|off`, `state`, `quit`.
    Emulate {
        /// Power up homed at the standby pose (the firmware boots unhomed at 0 steps).
        #[arg(long)]
        homed: bool,
        /// Duration of the compressed homing sequence, s.
        #[arg(long, default_value_t = 1.0)]
        home_seconds: f64,
    },
}

fn hw_err(e: HwError) -> CliError {
    match e {
        HwError::Limit(_) | HwError::Profile(_) | HwError::Units(_) | HwError::BadConfig(_) => CliError::usage(e),
        other => CliError::runtime(other),
    }
}

fn open(args: &PortArgs) -> Result<Session, CliError> {
    let config = SessionConfig { rate_hz: args.rate, ..SessionConfig::default() };
    let session = match &args.port {
        Some(p) => Session::open(p, config),
        None => Session::open_auto(config),
    }
    .map_err(hw_err)?;
    session.wait_connected(CONNECT_TIMEOUT).map_err(|_| {
        let s = session.snapshot();
        CliError::runtime(format!(
            "no valid status from the controller on {} within {:.0} s ({})",
            s.port,
            CONNECT_TIMEOUT.as_secs_f64(),
            s.fault.clone().unwrap_or_else(|| "is it a PAROL6?".into())
        ))
    })?;
    Ok(session)
}

/// Waits until `code` has been written at least once after `since`.
fn wait_sent(session: &Session, code: CommandCode, frames_before: u64) -> Result<(), CliError> {
    session
        .wait_until(Duration::from_secs(2), |s| s.last_command == Some(code) && s.frames_sent > frames_before)
        .map(|_| ())
        .map_err(hw_err)
}

fn summary(s: &Snapshot) -> serde_json::Value {
    json!({
        "port": s.port,
        "link": s.link,
        "joint_steps": s.joint_steps,
        "joint_deg": s.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
        "homed": s.homed,
        "estop_pressed": s.estop_pressed,
        "enabled": s.enabled,
        "fault": s.fault,
    })
}

/// Runs `parol6 hw`.
pub fn run(args: &HwArgs) -> CliResult {
    match &args.command {
        HwCommand::Ports => {
            let ports = parol6_hw::list_ports().map_err(hw_err)?;
            print_json(&json!({ "ports": ports }));
            Ok(())
        }
        HwCommand::Status(p) => {
            let session = open(p)?;
            let s = session.wait_until(Duration::from_secs(2), |s| s.status_frames >= 3).map_err(hw_err)?;
            print_json(&s.to_json());
            Ok(())
        }
        HwCommand::Enable(p) => send_latch(p, "enable", CommandCode::Enable, Session::enable),
        HwCommand::Disable(p) => send_latch(p, "disable", CommandCode::Disable, Session::disable),
        HwCommand::Home(p) => {
            let session = open(p)?;
            let t0 = Instant::now();
            session.home_blocking().map_err(hw_err)?;
            let s = session.snapshot();
            print_json(&json!({
                "command": "home", "ok": true, "seconds": t0.elapsed().as_secs_f64(), "state": summary(&s)
            }));
            Ok(())
        }
        HwCommand::Jog { port, joint, speed, seconds } => {
            if !(1..=6).contains(joint) {
                return Err(CliError::usage(format!("--joint must be 1–6 (got {joint})")));
            }
            if !(speed.is_finite() && (-1.0..=1.0).contains(speed)) {
                return Err(CliError::usage(format!("--speed must be within −1…1 (got {speed})")));
            }
            if !(seconds.is_finite() && *seconds > 0.0 && *seconds <= 60.0) {
                return Err(CliError::usage(format!("--seconds must be within 0–60 (got {seconds})")));
            }
            let session = open(port)?;
            let start = session.snapshot();
            let end = Instant::now() + Duration::from_secs_f64(*seconds);
            while Instant::now() < end {
                session.jog(joint - 1, *speed).map_err(hw_err)?;
                std::thread::sleep(Duration::from_millis(50));
            }
            session.jog_release().map_err(hw_err)?;
            std::thread::sleep(Duration::from_millis(300));
            let s = session.snapshot();
            if s.link != LinkState::Connected {
                return Err(CliError::runtime(format!(
                    "link lost during the jog: {}",
                    s.fault.clone().unwrap_or_default()
                )));
            }
            print_json(&json!({
                "command": "jog", "joint": joint, "speed": speed, "seconds": seconds,
                "start_deg": start.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
                "end_deg": s.joint_rad.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
                "state": summary(&s),
            }));
            Ok(())
        }
        HwCommand::Move { port, joints, deg, speed, smooth } => {
            if joints.len() != 6 {
                return Err(CliError::usage(format!("--joints needs 6 values, got {}", joints.len())));
            }
            let goal: Vec<f64> = if *deg { joints.iter().map(|d| d.to_radians()).collect() } else { joints.clone() };
            let kind = if *smooth { ProfileKind::JerkLimited } else { ProfileKind::Trapezoidal };
            // Validate before touching the port.
            let limits = parol6_core::limits::JointLimits::parol6();
            limits.enforce(&goal, parol6_core::limits::LimitPolicy::Reject).map_err(CliError::usage)?;
            if !(speed.is_finite() && *speed > 0.0) {
                return Err(CliError::usage(format!("--speed must be a number > 0 (got {speed})")));
            }
            let session = open(port)?;
            let start = session.snapshot();
            let plan = parol6_core::profile::JointMove::parol6(&start.joint_rad, &goal, *speed, kind)
                .map_err(CliError::usage)?;
            let timeout = Duration::from_secs_f64(plan.duration_s() + 10.0);
            let t0 = Instant::now();
            let s = session.move_to_blocking(&goal, *speed, kind, timeout).map_err(hw_err)?;
            print_json(&json!({
                "command": "move", "ok": true, "planned_s": plan.duration_s(), "seconds": t0.elapsed().as_secs_f64(),
                "goal_deg": goal.iter().map(|r| r.to_degrees()).collect::<Vec<_>>(),
                "state": summary(&s),
            }));
            Ok(())
        }
        HwCommand::Emulate { homed, home_seconds } => emulate(*homed, *home_seconds),
    }
}

/// `hw enable` / `hw disable`: sends the latch command, waits until it is on the wire, prints
/// the resulting state.
fn send_latch(p: &PortArgs, name: &str, code: CommandCode, op: fn(&Session) -> Result<(), HwError>) -> CliResult {
    let session = open(p)?;
    let before = session.snapshot().frames_sent;
    op(&session).map_err(hw_err)?;
    wait_sent(&session, code, before)?;
    print_json(&json!({"command": name, "ok": true, "state": summary(&session.snapshot())}));
    Ok(())
}

fn emulate(homed: bool, home_seconds: f64) -> CliResult {
    if !(home_seconds.is_finite() && home_seconds > 0.0 && home_seconds <= 60.0) {
        return Err(CliError::usage("--home-seconds must be within 0–60"));
    }
    let base = if homed { EmulatorConfig::homed_at_standby() } else { EmulatorConfig::default() };
    let config = EmulatorConfig { home_duration_s: home_seconds, log_commands: false, ..base };
    let emu = EmulatorHandle::spawn(config).map_err(hw_err)?;
    let mut out = std::io::stdout();
    writeln!(out, "{}", emu.path()).map_err(CliError::runtime)?;
    out.flush().map_err(CliError::runtime)?;
    let stdin = std::io::stdin();
    let mut inputs = (false, false);
    for line in stdin.lock().lines() {
        let Ok(line) = line else { break };
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
        print_json(&reply);
    }
    // Stdin closed (e.g. started in the background): serve until killed.
    loop {
        std::thread::park();
    }
}

/// `parol6 bench serial`: runs the real session against the in-process emulator over a pty
/// and measures the period jitter (as the controller receives the frames) and the latency
/// from a jog press to the first changed MOVE target on the wire.
pub fn bench_serial(seconds: f64, rate_hz: f64, presses: usize) -> CliResult {
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= 600.0) {
        return Err(CliError::usage("--seconds must be within 0–600"));
    }
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).map_err(hw_err)?;
    let config = SessionConfig { rate_hz, write_log_capacity: 1 << 16, ..SessionConfig::default() };
    let session = Session::open(emu.path(), config).map_err(hw_err)?;
    session.wait_connected(CONNECT_TIMEOUT).map_err(hw_err)?;
    let period_s = 1.0 / rate_hz;

    // 1. Period jitter while idle: host write times (the session's period) and the
    //    controller's receive times (adds pty transfer and emulator wake-up).
    let _ = emu.take_received();
    let _ = session.take_write_times();
    std::thread::sleep(Duration::from_secs_f64(seconds));
    let frames = emu.take_received();
    let writes = session.take_write_times();
    let mut write_dev_ns: Vec<f64> =
        writes.windows(2).map(|w| (w[1].duration_since(w[0]).as_secs_f64() - period_s).abs() * 1e9).collect();
    let write_jitter = NsStats::from_samples(&mut write_dev_ns);
    let write_jitter_max_ns = write_dev_ns.last().copied().unwrap_or(0.0);
    let mut dev_ns: Vec<f64> =
        frames.windows(2).map(|w| (w[1].at.duration_since(w[0].at).as_secs_f64() - period_s).abs() * 1e9).collect();
    let achieved_hz = if frames.len() >= 2 {
        (frames.len() - 1) as f64 / frames[frames.len() - 1].at.duration_since(frames[0].at).as_secs_f64()
    } else {
        0.0
    };
    let jitter = NsStats::from_samples(&mut dev_ns);
    let session_jitter_p99_ms = session.snapshot().period_jitter_p99_ms;

    // 2. Jog press → first changed target on the wire.
    let mut lat_ns = Vec::with_capacity(presses);
    // J1 target of the last frame seen before each press.
    let mut last_known = frames.last().map(|f| f.command.fields.positions_steps[0]);
    for k in 0..presses {
        // Spread the press over the period.
        std::thread::sleep(Duration::from_secs_f64(period_s * (k % 7) as f64 / 7.0));
        let before = emu.take_received();
        if let Some(f) = before.last() {
            last_known = Some(f.command.fields.positions_steps[0]);
        }
        let last_target = last_known;
        let pressed = Instant::now();
        let dir = if k % 2 == 0 { 1.0 } else { -1.0 };
        session.jog(0, dir).map_err(hw_err)?;
        let deadline = pressed + Duration::from_secs(1);
        let mut found = None;
        let mut seen = Vec::new();
        while found.is_none() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(1));
            seen.extend(emu.take_received());
            let mut prev = last_target;
            for f in &seen {
                let t = f.command.fields.positions_steps[0];
                if f.at >= pressed && f.command.code == CommandCode::Move.byte() && prev.is_some_and(|p| p != t) {
                    found = Some(f.at);
                    break;
                }
                prev = Some(t);
            }
        }
        session.jog_release().map_err(hw_err)?;
        std::thread::sleep(Duration::from_millis(150));
        seen.extend(emu.take_received());
        last_known = seen.last().map(|f| f.command.fields.positions_steps[0]).or(last_known);
        let Some(at) = found else {
            return Err(CliError::runtime("a jog press never reached the wire within 1 s"));
        };
        lat_ns.push(at.duration_since(pressed).as_secs_f64() * 1e9);
    }
    let latency = NsStats::from_samples(&mut lat_ns);
    let lat_max_ns = lat_ns.last().copied().unwrap_or(0.0);
    let jitter_max_ns = dev_ns.last().copied().unwrap_or(0.0);
    let s = session.snapshot();
    print_json(&json!({
        "bench": "serial",
        "rate_hz": rate_hz,
        "period_ms": period_s * 1e3,
        "achieved_rate_hz": achieved_hz,
        "frames": frames.len(),
        "period_jitter": write_jitter.json(),
        "period_jitter_p99_ms": write_jitter.p99_ns / 1e6,
        "period_jitter_max_ms": write_jitter_max_ns / 1e6,
        "received_period_jitter": jitter.json(),
        "received_period_jitter_p99_ms": jitter.p99_ns / 1e6,
        "received_period_jitter_max_ms": jitter_max_ns / 1e6,
        "session_snapshot_jitter_p99_ms": session_jitter_p99_ms,
        "jog_latency": latency.json(),
        "jog_latency_max_ms": lat_max_ns / 1e6,
        "jog_within_one_period": lat_max_ns <= period_s * 1e9,
        "jitter_p99_within_1ms": write_jitter.p99_ns <= 1e6,
        "missing_replies": s.missing_replies,
        "invalid_frames": s.invalid_frames,
        "jog_max_steps_s_j1": units::jog_max_speed_steps_s()[0],
    }));
    Ok(())
}

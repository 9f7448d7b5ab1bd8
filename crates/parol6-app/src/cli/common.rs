//! Helpers shared by several subcommands, so that no subcommand's file imports another's for
//! them: latency statistics ([`NsStats`]), comma-separated number lists ([`parse_list`]), the
//! selected tool ([`tool_of`]), and the controller link of every subcommand that talks to one
//! ([`RateArgs`], `open`, `Link`, `hw_err`, `not_connected`).

use std::time::Duration;

use crossbeam_channel::Sender;
use parol6_core::Tool;
use parol6_core::motion::MotionSample;
use parol6_core::motion::tracking::TrackingMode;
use parol6_hw::HwError;
use parol6_hw::emulator::{EmulatorConfig, EmulatorHandle};
use parol6_hw::session::{Session, SessionConfig, Snapshot, impossible_answers};

use super::CliError;
use super::options::{ConnectArgs, RobotArgs, f64_within};

/// Latency statistics over a set of samples, nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NsStats {
    /// Median.
    pub median_ns: f64,
    /// 99th percentile.
    pub p99_ns: f64,
    /// Mean.
    pub mean_ns: f64,
    /// Samples.
    pub n: usize,
}

impl NsStats {
    /// Statistics of `samples` (sorted in place). All zero when empty.
    pub fn from_samples(samples: &mut [f64]) -> Self {
        if samples.is_empty() {
            return Self { median_ns: 0.0, p99_ns: 0.0, mean_ns: 0.0, n: 0 };
        }
        samples.sort_by(f64::total_cmp);
        match parol6_core::stats::Summary::from_sorted(samples) {
            Some(s) => Self { median_ns: s.p50, p99_ns: s.p99, mean_ns: s.mean, n: s.n },
            None => Self { median_ns: 0.0, p99_ns: 0.0, mean_ns: 0.0, n: 0 },
        }
    }

    /// As a JSON object with `median_ns`, `p99_ns`, `mean_ns`, `n`.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({"median_ns": self.median_ns, "p99_ns": self.p99_ns, "mean_ns": self.mean_ns, "n": self.n})
    }
}

/// Parses a comma-separated list of numbers, naming the offending field on error.
pub fn parse_list(what: &str, text: &str, expected: Option<usize>) -> Result<Vec<f64>, CliError> {
    let values: Vec<f64> = text
        .split(',')
        .enumerate()
        .map(|(i, s)| {
            let s = s.trim();
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(CliError::usage(format!("{what}: value {} (\"{s}\") is not a finite number", i + 1))),
            }
        })
        .collect::<Result<_, _>>()?;
    if let Some(n) = expected
        && values.len() != n
    {
        return Err(CliError::usage(format!("{what}: expected {n} comma-separated values, got {}", values.len())));
    }
    Ok(values)
}

/// The tool selected with `--tool` (none when not given).
pub fn tool_of(robot: &RobotArgs) -> Tool {
    robot.tool.as_deref().and_then(Tool::from_name).unwrap_or(Tool::None)
}

/// How long to wait for the first status frame.
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(3);

/// Session settings shared by the subcommands that talk to a controller.
#[derive(Debug, Clone, clap::Args)]
pub struct RateArgs {
    /// Command rate, Hz, 50–500.
    #[arg(long, default_value_t = 100.0, value_parser = f64_within(50.0, 500.0))]
    pub rate: f64,
    /// Which MOVE targets motion streams: official (the plan now, zero feed-forward, as the
    /// official API: the arm trails by ≈ 25 ms), lead (the plan 25 ms ahead: the arm is where the
    /// plan says when it says it), feedforward (the same tracking as lead, with feed-forward
    /// speeds). The simulation's board uses the same mode. Default: a program file's own
    /// `tracking`, else lead.
    #[arg(long, value_name = "official|lead|feedforward")]
    pub tracking: Option<TrackingMode>,
}

impl RateArgs {
    /// The default rate and tracking mode.
    pub fn defaults() -> Self {
        Self { rate: 100.0, tracking: None }
    }
}

/// Maps a session error to the exit status: refused or invalid requests 2, device failures 1.
pub fn hw_err(e: HwError) -> CliError {
    match e {
        HwError::Limit(_) | HwError::Profile(_) | HwError::Units(_) | HwError::BadConfig(_) | HwError::Refused(_) => {
            CliError::usage(e)
        }
        other => CliError::runtime(other),
    }
}

/// An open controller session, and the emulator behind it with `--fake-robot`.
pub(crate) struct Link {
    /// Dropped first: it leaves the controller with IDLE frames while the emulator still runs.
    pub(crate) session: Session,
    pub(crate) emulator: Option<EmulatorHandle>,
}

/// Opens the controller of `connect` (the emulator with `--fake-robot`), with an optional
/// telemetry tap, and waits for its first status. `tool_in_flange`: the tool's TCP in the
/// flange frame (`RobotModel::tool`): the session's TCP is the tool tip's.
pub(crate) fn open(
    connect: &ConnectArgs,
    rate: &RateArgs,
    tap: Option<Sender<MotionSample>>,
    tool_in_flange: parol6_core::na::Isometry3<f64>,
) -> Result<Link, CliError> {
    let config = SessionConfig {
        rate_hz: rate.rate,
        tracking: rate.tracking.unwrap_or_default(),
        tool_in_flange,
        ..SessionConfig::default()
    };
    let emulator = if connect.fake_robot {
        Some(
            EmulatorHandle::spawn_socket(EmulatorConfig { log_commands: false, ..EmulatorConfig::homed_at_standby() })
                .map_err(hw_err)?,
        )
    } else {
        None
    };
    let session = match (&emulator, &connect.port) {
        (Some(emu), _) => Session::open_with_tap(emu.path(), config, tap),
        (None, Some(p)) => Session::open_with_tap(p, config, tap),
        (None, None) => parol6_hw::find_parol6_port().and_then(|p| Session::open_with_tap(&p, config, tap)),
    }
    .map_err(hw_err)?;
    if session.wait_connected(CONNECT_TIMEOUT).is_err() {
        return Err(CliError::runtime(not_connected(&session.snapshot(), CONNECT_TIMEOUT.as_secs_f64())));
    }
    Ok(Link { session, emulator })
}

/// The message when no link came up in time although status frames arrived: a board that
/// answered with impossible positions (issue 29 item 15) or one that stopped answering.
pub fn not_connected(s: &Snapshot, secs: f64) -> String {
    if s.status_frames == 0 {
        return format!(
            "no PAROL6 answered on {} within {secs:.0} s (is the controller powered and is this its port?)",
            s.port
        );
    }
    if s.implausible_frames > 0 || s.limit_breach.is_some_and(|b| b.impossible) {
        let why = s.limit_breach.filter(|b| b.impossible).map(|b| impossible_answers(&b)).unwrap_or_else(|| {
            format!(
                "the controller's answers are impossible: {} of {} status frames showed positions that jump \
                 further than any joint can move",
                s.implausible_frames, s.status_frames
            )
        });
        return format!(
            "the controller on {} answers, but not with a usable position within {secs:.0} s: {why}",
            s.port
        );
    }
    format!(
        "the controller on {} stopped answering within {secs:.0} s ({})",
        s.port,
        s.fault.clone().unwrap_or_else(|| "link lost".into())
    )
}

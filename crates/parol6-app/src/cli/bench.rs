//! `parol6 bench …`: benchmarks that print JSON (`median_ns`, `p99_ns`, `n`, …).
//! Each target lives next to the code it measures; this file only dispatches and does the
//! shared statistics.

use super::options::{RobotArgs, f64_above, f64_within};
use super::{CliError, CliResult};

/// Arguments of `parol6 bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// What to measure.
    #[command(subcommand)]
    pub target: BenchTarget,
}

/// Benchmark targets.
#[derive(Debug, clap::Subcommand)]
pub enum BenchTarget {
    /// Forward kinematics.
    Fk {
        /// Number of samples, 1–10 000 000.
        #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
        n: u64,
    },
    /// Inverse kinematics, closed-form and numeric, on random reachable in-limit poses.
    Ik {
        /// Number of poses, 1–1 000 000.
        #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
        n: u64,
    },
    /// Full-UI rendering offscreen while the arm sweeps all joints (`fps_median`,
    /// `frame_ms_p50`, `frame_ms_p99`, `ui_cpu_ms_p50`).
    Render(super::gui::BenchRenderArgs),
    /// Serial session against the in-process controller emulator over a pty: period jitter
    /// and jog-press → wire latency (`period_jitter_p99_ms`, `jog_latency_max_ms`).
    Serial {
        /// Seconds of idle streaming to measure the period jitter, > 0 and ≤ 600.
        #[arg(long, default_value_t = 10.0, value_parser = f64_above(0.0, 600.0))]
        seconds: f64,
        /// Command rate, Hz, 50–500.
        #[arg(long, default_value_t = 100.0, value_parser = f64_within(50.0, 500.0))]
        rate: f64,
        /// Number of jog presses for the latency, 1–1000.
        #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u64).range(1..=1000))]
        presses: u64,
    },
    /// Simulation step time (dynamic, with colliders; `median_ns`, `p99_ns`) and the CPU share
    /// of the 1 kHz real-time thread (`realtime_thread.thread_cpu_percent`).
    Physics {
        /// Number of steps timed, 1–1 000 000.
        #[arg(long, default_value_t = 20_000, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
        n: u64,
        /// Seconds of the real-time thread for the CPU measurement, 0–600 (0 = skip).
        #[arg(long, default_value_t = 3.0, value_parser = f64_within(0.0, 600.0))]
        cpu_seconds: f64,
    },
    /// Motion engine: MoveL interpolation + IK per 1 ms tick, pre-flight of 1 000 moves, a
    /// 1 000-step program check, the program runner's CPU share at 1 kHz.
    Motion {
        /// Timed runs of each measurement, 1–1000.
        #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..=1000))]
        repeats: u64,
        /// Seconds of a program run on the real-time simulation for the runner's CPU share,
        /// 0–600 (0 = skip).
        #[arg(long, default_value_t = 5.0, value_parser = f64_within(0.0, 600.0))]
        runner_seconds: f64,
    },
    /// Opening a synthetic recording for replay (`open_ms_median`; ≤ 1000 ms for ten minutes).
    Replay {
        /// Length of the recording, minutes, > 0 and ≤ 60.
        #[arg(long, default_value_t = 10.0, value_parser = f64_above(0.0, 60.0))]
        minutes: f64,
        /// Sample rate of the recording, Hz, 10–2000 (1000: the simulation's).
        #[arg(long, default_value_t = 1000.0, value_parser = f64_within(10.0, 2000.0))]
        rate: f64,
        /// Timed opens, 1–100.
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=100))]
        repeats: u64,
        /// Keep the synthetic recording at this path (to open it in the window, `parol6 replay`).
        #[arg(long, value_name = "OUT.mcap", value_parser = super::options::output_file)]
        keep: Option<std::path::PathBuf>,
    },
    /// Opening a generated G-code file of `--lines` lines in the window (headless): the longest
    /// frame while it is read, checked and planned on a worker (`frame_ms_max`,
    /// `frames_over_50ms`), and the time to its pre-flight result (`checked_in_s`).
    ProgramLoad {
        /// Lines of the file, 10–1 000 000.
        #[arg(long, default_value_t = 200_000, value_parser = clap::value_parser!(u64).range(10..=1_000_000))]
        lines: u64,
        /// Round the corners between lines with this radius, mm (`G64 P…`; default: exact stops,
        /// every line its own move).
        #[arg(long, value_parser = f64_above(0.0, 100.0))]
        blend_mm: Option<f64>,
        /// Window size, WxH px.
        #[arg(long, default_value = "1280x800")]
        size: String,
        /// Keep the generated file at this path.
        #[arg(long, value_name = "OUT.gcode", value_parser = super::options::output_file)]
        keep: Option<std::path::PathBuf>,
    },
    /// `parol6 program check` of the generated G-code raster `program-load` opens, without the
    /// window: reading, planning, pre-flight walk and torque pass, `--repeats` times
    /// (`check_s_median`; ≤ 5 s for 200 000 lines on a quiet 2-core host).
    ProgramCheck {
        /// Lines of the file, 10–1 000 000.
        #[arg(long, default_value_t = 200_000, value_parser = clap::value_parser!(u64).range(10..=1_000_000))]
        lines: u64,
        /// Round the corners between lines with this radius, mm (`G64 P…`; default: exact stops).
        #[arg(long, value_parser = f64_above(0.0, 100.0))]
        blend_mm: Option<f64>,
        /// Timed checks, 1–100.
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=100))]
        repeats: u64,
    },
    /// The window (headless) driven through a user's actions on a `--steps`-step program and a
    /// `--minutes` recording: the longest frame during each action (`actions[].frame_ms_max`)
    /// and the actions over 50 ms (`over_50ms`).
    UiActions {
        /// Steps of the generated program (a G-code raster), 10–200 000.
        #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u64).range(10..=200_000))]
        steps: u64,
        /// Length of the synthetic recording, minutes, > 0 and ≤ 60.
        #[arg(long, default_value_t = 10.0, value_parser = f64_above(0.0, 60.0))]
        minutes: f64,
        /// Sample rate of the recording, Hz, 10–2000 (1000: the simulation's).
        #[arg(long, default_value_t = 1000.0, value_parser = f64_within(10.0, 2000.0))]
        rate: f64,
        /// Window size, WxH px.
        #[arg(long, default_value = "1280x800")]
        size: String,
    },
    /// Command → applied latency with the 1 kHz thread running while another thread sends
    /// commands (`median_ns`, `p99_ns`).
    Latency {
        /// Number of commands, 1–1 000 000.
        #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
        n: u64,
        /// Mean spacing between two commands, µs, 0–100 000.
        #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(0..=100_000))]
        interval_us: u64,
    },
}

impl BenchTarget {
    /// The target's name on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Fk { .. } => "fk",
            Self::Ik { .. } => "ik",
            Self::Render(_) => "render",
            Self::Serial { .. } => "serial",
            Self::Physics { .. } => "physics",
            Self::Latency { .. } => "latency",
            Self::Motion { .. } => "motion",
            Self::Replay { .. } => "replay",
            Self::ProgramLoad { .. } => "program-load",
            Self::ProgramCheck { .. } => "program-check",
            Self::UiActions { .. } => "ui-actions",
        }
    }

    /// True for the benches that open a graphics adapter (the headless window or its renderer).
    pub fn opens_gpu(&self) -> bool {
        match self {
            Self::Render(_) | Self::ProgramLoad { .. } | Self::UiActions { .. } => true,
            Self::Fk { .. }
            | Self::Ik { .. }
            | Self::Serial { .. }
            | Self::Physics { .. }
            | Self::Latency { .. }
            | Self::Motion { .. }
            | Self::Replay { .. }
            | Self::ProgramCheck { .. } => false,
        }
    }
}

/// A count within a range clap already checked, as `usize`.
fn count(n: u64) -> Result<usize, CliError> {
    usize::try_from(n).map_err(|_| CliError::usage(format!("count {n} is too large for this machine")))
}

/// Runs `parol6 bench`.
pub fn run(args: &BenchArgs, robot: &RobotArgs) -> CliResult {
    match &args.target {
        BenchTarget::Fk { n } => super::kin::bench_fk(count(*n)?),
        BenchTarget::Ik { n } => super::kin::bench_ik(count(*n)?),
        BenchTarget::Render(a) => super::gui::bench_render(a, robot),
        BenchTarget::Serial { seconds, rate, presses } => {
            super::hw_bench::bench_serial(*seconds, *rate, count(*presses)?)
        }
        BenchTarget::Physics { n, cpu_seconds } => super::sim::bench_physics(count(*n)?, *cpu_seconds),
        BenchTarget::Latency { n, interval_us } => super::sim::bench_latency(count(*n)?, *interval_us),
        BenchTarget::Replay { minutes, rate, repeats, keep } => {
            super::bench_replay::bench_replay(*minutes, *rate, count(*repeats)?, keep.as_deref())
        }
        BenchTarget::Motion { repeats, runner_seconds } => {
            super::bench_motion::bench_motion(count(*repeats)?, *runner_seconds)
        }
        BenchTarget::UiActions { steps, minutes, rate, size } => {
            super::bench_ui::bench_ui_actions(&super::bench_ui::UiActionsArgs {
                steps: count(*steps)?,
                minutes: *minutes,
                rate_hz: *rate,
                size: super::render::parse_size(size)?,
            })
        }
        BenchTarget::ProgramCheck { lines, blend_mm, repeats } => {
            super::bench_program::bench_program_check(count(*lines)?, *blend_mm, count(*repeats)?)
        }
        BenchTarget::ProgramLoad { lines, blend_mm, size, keep } => super::bench_program::bench_program_load(
            count(*lines)?,
            *blend_mm,
            super::render::parse_size(size)?,
            keep.as_deref(),
        ),
    }
}

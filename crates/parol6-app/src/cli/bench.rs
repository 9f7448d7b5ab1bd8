//! `parol6 bench …`: benchmarks that print JSON (`median_ns`, `p99_ns`, `n`, …).
//! Each target lives next to the code it measures; this file only dispatches and does the
//! shared statistics.

use super::CliResult;

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
        /// Number of samples.
        #[arg(long, default_value_t = 100_000)]
        n: usize,
    },
    /// Inverse kinematics, closed-form and numeric, on random reachable in-limit poses.
    Ik {
        /// Number of poses.
        #[arg(long, default_value_t = 100_000)]
        n: usize,
    },
    /// Full-UI rendering offscreen while the arm sweeps all joints (`fps_median`,
    /// `frame_ms_p50`, `frame_ms_p99`, `ui_cpu_ms_p50`).
    Render(super::gui::BenchRenderArgs),
    /// Serial session against the in-process controller emulator over a pty: period jitter
    /// and jog-press → wire latency (`period_jitter_p99_ms`, `jog_latency_max_ms`).
    Serial {
        /// Seconds of idle streaming to measure the period jitter.
        #[arg(long, default_value_t = 10.0)]
        seconds: f64,
        /// Command rate, Hz (50–500).
        #[arg(long, default_value_t = 100.0)]
        rate: f64,
        /// Number of jog presses for the latency.
        #[arg(long, default_value_t = 50)]
        presses: usize,
    },
    /// Simulation step time (dynamic, with colliders; `median_ns`, `p99_ns`) and the CPU share
    /// of the 1 kHz real-time thread (`realtime_thread.thread_cpu_percent`).
    Physics {
        /// Number of steps timed.
        #[arg(long, default_value_t = 20_000)]
        n: usize,
        /// Seconds of the real-time thread for the CPU measurement (0 = skip).
        #[arg(long, default_value_t = 3.0)]
        cpu_seconds: f64,
    },
    /// Command → applied latency with the 1 kHz thread running while another thread sends
    /// commands (`median_ns`, `p99_ns`).
    Latency {
        /// Number of commands.
        #[arg(long, default_value_t = 10_000)]
        n: usize,
        /// Mean spacing between two commands, µs.
        #[arg(long, default_value_t = 200)]
        interval_us: u64,
    },
}

/// Runs `parol6 bench`.
pub fn run(args: &BenchArgs) -> CliResult {
    match &args.target {
        BenchTarget::Fk { n } => super::kin::bench_fk(*n),
        BenchTarget::Ik { n } => super::kin::bench_ik(*n),
        BenchTarget::Render(a) => super::gui::bench_render(a),
        BenchTarget::Serial { seconds, rate, presses } => super::hw::bench_serial(*seconds, *rate, *presses),
        BenchTarget::Physics { n, cpu_seconds } => super::sim::bench_physics(*n, *cpu_seconds),
        BenchTarget::Latency { n, interval_us } => super::sim::bench_latency(*n, *interval_us),
    }
}

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
        let n = samples.len();
        let pick = |q: f64| samples[((n as f64 - 1.0) * q).round() as usize];
        Self { median_ns: pick(0.5), p99_ns: pick(0.99), mean_ns: samples.iter().sum::<f64>() / n as f64, n }
    }

    /// As a JSON object with `median_ns`, `p99_ns`, `mean_ns`, `n`.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({"median_ns": self.median_ns, "p99_ns": self.p99_ns, "mean_ns": self.mean_ns, "n": self.n})
    }
}

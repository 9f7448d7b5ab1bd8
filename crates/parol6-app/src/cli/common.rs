//! Helpers shared by several subcommands, so that no subcommand's file imports another's for
//! them: latency statistics ([`NsStats`]), comma-separated number lists ([`parse_list`]) and the
//! selected tool ([`tool_of`]).

use parol6_core::Tool;

use super::CliError;
use super::options::RobotArgs;

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

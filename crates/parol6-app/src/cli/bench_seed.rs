//! `parol6 bench render --compare-seed`: runs the old HMI's per-frame work
//! (`shared/bench/seed_frame.py`: PyBullet camera image + Matplotlib redraw + two physics steps)
//! in the same run and reads its JSON, so the ratio is measured under the same machine load.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::CliError;

/// Where the seed script, its URDF and the Python interpreter are.
#[derive(Debug, Clone)]
pub struct SeedSetup {
    /// `seed_frame.py`.
    pub script: PathBuf,
    /// The PAROL6 URDF the script loads.
    pub urdf: PathBuf,
    /// Python interpreter with pybullet, matplotlib and numpy.
    pub python: String,
    /// Timed seed frames.
    pub frames: u32,
}

impl SeedSetup {
    /// The defaults: `$PAROL6_SHARED` (the reference pack, `…/shared/parol6`) or
    /// `../shared/parol6`; its sibling `bench/seed_frame.py`; `$PAROL6_SEED_PYTHON` or `python3`.
    pub fn from_env(script: Option<&Path>, python: Option<&str>, frames: u32) -> Self {
        let pack = std::env::var_os("PAROL6_SHARED")
            .map(PathBuf::from)
            .unwrap_or_else(|| Path::new("..").join("shared").join("parol6"));
        let script =
            script.map(Path::to_path_buf).unwrap_or_else(|| pack.join("..").join("bench").join("seed_frame.py"));
        let python = python
            .map(str::to_string)
            .or_else(|| std::env::var("PAROL6_SEED_PYTHON").ok())
            .unwrap_or_else(|| "python3".to_string());
        Self { script, urdf: pack.join("urdf").join("PAROL6.urdf"), python, frames }
    }
}

/// Runs the seed script and returns its JSON (the last line of its output).
pub fn run_seed_frame(setup: &SeedSetup) -> Result<serde_json::Value, CliError> {
    for (what, path) in [("--seed-script", &setup.script), ("the seed URDF", &setup.urdf)] {
        if !path.is_file() {
            return Err(CliError::usage(format!(
                "{what}: {} not found (set PAROL6_SHARED to the reference pack, …/shared/parol6)",
                path.display()
            )));
        }
    }
    let out = Command::new(&setup.python)
        .arg(&setup.script)
        .arg(&setup.urdf)
        .arg(setup.frames.to_string())
        .output()
        .map_err(|e| CliError::runtime(format!("cannot run {} (--seed-python): {e}", setup.python)))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let last = stderr.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("");
        return Err(CliError::runtime(format!(
            "{} failed ({}): {last} (it needs pybullet, matplotlib and numpy; --seed-python names the interpreter)",
            setup.script.display(),
            out.status
        )));
    }
    parse_seed_output(&stdout)
}

/// The JSON object on the last non-empty line of the seed script's output (PyBullet prints its
/// own lines before it).
pub fn parse_seed_output(stdout: &str) -> Result<serde_json::Value, CliError> {
    let line = stdout.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("");
    let v: serde_json::Value = serde_json::from_str(line)
        .map_err(|e| CliError::runtime(format!("seed script: last line is not JSON ({e}): {line:.120}")))?;
    match v.get("seed_frame_ms_median").and_then(serde_json::Value::as_f64) {
        Some(ms) if ms.is_finite() && ms > 0.0 => Ok(v),
        _ => Err(CliError::runtime(format!("seed script: no positive seed_frame_ms_median in {line:.120}"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_last_json_line_is_read_and_checked() {
        let out = "pybullet build time: now\n\n{\"seed_frame_ms_median\": 160.0, \"seed_fps\": 6.25}\n";
        let v = parse_seed_output(out).ok().and_then(|v| v["seed_fps"].as_f64());
        assert_eq!(v, Some(6.25));
        assert!(parse_seed_output("no json here").is_err());
        assert!(parse_seed_output("{\"seed_frame_ms_median\": 0}").is_err());
        assert!(parse_seed_output("{\"seed_fps\": 3}").is_err());
    }
}

//! `parol6 program torques FILE`: inverse dynamics of a program before it runs (the core's
//! [`program_torques`]), as text or JSON.

use std::path::Path;

use parol6_core::RobotModel;
use parol6_core::program::Program;
use parol6_core::program::compile::{CompileOptions, compile};
use parol6_core::program::torques::{ProgramTorques, program_torques, torque_limits_nm};
use serde_json::json;

use super::{CliError, CliResult, print_json};

/// Compiles `program` from `start_q` (100 Hz samples, as pre-flight) and prints its torques.
pub fn run(
    file: &Path,
    model: &RobotModel,
    program: &Program,
    start_q: &[f64],
    as_json: bool,
    series: bool,
) -> CliResult {
    let steps = compile(model, program, start_q, CompileOptions::PREFLIGHT)
        .map_err(|e| CliError::usage(format!("{}: {e}", file.display())))?;
    let t = program_torques(model, &steps, start_q, torque_limits_nm(model));
    if as_json {
        let mut v = json!({
            "file": file.display().to_string(),
            "joints": model.joint_names(),
            "duration_s": t.time_s.last().copied().unwrap_or(0.0),
            "samples": t.time_s.len(),
            "limits_nm": t.limits_nm,
            "limits_source": limits_source(model),
            "peak_abs_nm": t.peak_abs_nm,
            "within_limits": t.warnings.is_empty(),
            "warnings": t.warnings,
            "warnings_dropped": t.warnings_dropped,
        });
        if series {
            v["time_s"] = json!(t.time_s);
            v["torques_nm"] = json!(t.torques_nm);
        }
        return print_json(&v);
    }
    super::output::print_line(text_report(file, model, &t).trim_end())
}

fn limits_source(model: &RobotModel) -> Option<&'static str> {
    torque_limits_nm(model).map(|_| "motor holding torque (PAROL6 BOM) × gear reduction (ROBOT.md §1)")
}

/// The human-readable report: per joint peak vs limit, then the warnings (`file:line:`).
pub fn text_report(file: &Path, model: &RobotModel, t: &ProgramTorques) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    for w in &t.warnings {
        let _ = writeln!(
            out,
            "{}:{}: warning: J{} torque {:.2} N·m at t = {:.2} s exceeds its limit {:.2} N·m ({:.2}–{:.2} s, {})",
            file.display(),
            w.line,
            w.joint,
            w.peak_nm,
            w.peak_s,
            w.limit_nm,
            w.start_s,
            w.end_s,
            w.step_kind
        );
    }
    if t.warnings_dropped > 0 {
        let _ = writeln!(out, "… and {} more stretches over a limit", t.warnings_dropped);
    }
    for (j, name) in model.joint_names().iter().enumerate() {
        let peak = t.peak_abs_nm.get(j).copied().unwrap_or(0.0);
        match t.limits_nm.as_ref().and_then(|l| l.get(j)) {
            Some(limit) => {
                let _ = writeln!(out, "{name}: peak {peak:.2} N·m of {limit:.2} N·m ({:.0} %)", 100.0 * peak / limit);
            }
            None => {
                let _ = writeln!(out, "{name}: peak {peak:.2} N·m (no documented limit)");
            }
        }
    }
    let _ = writeln!(
        out,
        "{}: {:.2} s, {} samples, {} stretches over a limit",
        if t.warnings.is_empty() { "ok" } else { "over limit" },
        t.time_s.last().copied().unwrap_or(0.0),
        t.time_s.len(),
        t.warnings.len() + t.warnings_dropped
    );
    out
}

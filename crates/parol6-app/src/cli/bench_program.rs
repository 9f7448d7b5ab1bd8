//! `parol6 bench program-load`: opening a large G-code file in the window (headless, the whole
//! UI rendered offscreen) while it is read, checked and planned on the program panel's worker.
//! The file is generated on the fly: a raster of `G1` lines 0.2 mm long (every line its own
//! stop-and-go move, the most work per line; `--blend-mm` rounds the corners instead, as CAM
//! output with `G64` does). Reports the longest frame while loading (`frame_ms_max`, the app's
//! own part `app_ms_max`), the frames over 50 ms, and the time until the pre-flight result is
//! shown (`checked_in_s`).
//!
//! `parol6 bench program-check`: the same file through `parol6 program check` without the
//! window (`check_s_median`).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde_json::json;

use parol6_core::program::check::{CheckOptions, CheckedProgram, check_program};

use super::{CliError, CliResult, print_json};
use crate::ui_screenshot::HeadlessApp;

/// A frame longer than this is a visible stall, ms.
const STALL_MS: f64 = 50.0;
/// Frames are paced at 60 Hz, as a window with vsync draws them.
const FRAME_PERIOD: Duration = Duration::from_millis(16);
/// The load must end within this, s.
const LOAD_LIMIT_S: f64 = 300.0;

/// Writes a G-code raster of `lines` lines to `path`: 0.2 mm `G1` segments at 100 mm/s, 40 mm
/// rows 0.5 mm apart over a 20 mm band in front of the PAROL6, exact stops (`G61`) or corners
/// rounded by `blend_mm` (`G64 P…`).
pub fn write_raster_gcode(path: &Path, lines: usize, blend_mm: Option<f64>) -> Result<(), CliError> {
    let mut text = String::with_capacity(lines * 24);
    text.push_str("; parol6 bench program-load: a generated raster\nG21 G90\nG0 X0 Y220 Z250 A90 B0 C90\n");
    match blend_mm {
        Some(b) => text.push_str(&format!("G64 P{b}\n")),
        None => text.push_str("G61\n"),
    }
    text.push_str("G1 F6000\n");
    let (mut x, mut y, mut dir) = (0.0f64, 220.0f64, 1.0f64);
    // 5 lines above and M30 below
    for _ in 0..lines.saturating_sub(6) {
        x += dir * 0.2;
        if x.abs() >= 20.0 {
            dir = -dir;
            y += 0.5;
            if y > 240.0 {
                y = 220.0;
            }
        }
        text.push_str(&format!("G1 X{x:.3} Y{y:.3}\n"));
    }
    text.push_str("M30\n");
    // `--keep FILE` may name a user's file: replaced whole or left as it was
    Ok(parol6_core::fsio::write_atomic_bytes(path, text.as_bytes())?)
}

/// Runs `parol6 bench program-load`.
pub fn bench_program_load(
    lines: usize,
    blend_mm: Option<f64>,
    (width, height): (u32, u32),
    keep: Option<&Path>,
) -> CliResult {
    let path: PathBuf = match keep {
        Some(p) => p.to_path_buf(),
        None => std::env::temp_dir().join(format!("parol6-bench-program-{}.gcode", std::process::id())),
    };
    write_raster_gcode(&path, lines, blend_mm)?;
    let result = measure(&path, lines, blend_mm, (width, height));
    if keep.is_none()
        && let Err(e) = std::fs::remove_file(&path)
    {
        eprintln!("warning: cannot remove {}: {e}", path.display());
    }
    print_json(&result?)
}

/// The check of a 200 000-line raster must take at most this, s (issue 33).
const CHECK_LIMIT_S: f64 = 5.0;

/// Runs `parol6 bench program-check`: the generated raster read and checked from the home
/// pose as `parol6 program check FILE` does it, `repeats` times.
pub fn bench_program_check(lines: usize, blend_mm: Option<f64>, repeats: usize) -> CliResult {
    let path = std::env::temp_dir().join(format!("parol6-bench-check-{}.gcode", std::process::id()));
    write_raster_gcode(&path, lines, blend_mm)?;
    let result = time_checks(&path, repeats);
    if let Err(e) = std::fs::remove_file(&path) {
        eprintln!("warning: cannot remove {}: {e}", path.display());
    }
    let (times_s, report) = result?;
    let mut sorted = times_s.clone();
    sorted.sort_by(f64::total_cmp);
    let median_s = parol6_core::stats::percentile(&sorted, 0.5);
    print_json(&json!({
        "target": "program-check",
        "lines": lines,
        "blend_mm": blend_mm,
        "steps": report.moves,
        "ok": report.ok,
        "issues": report.issues.len(),
        "program_duration_s": report.duration_s,
        "repeats": repeats,
        "check_s": times_s,
        "check_s_median": median_s,
        "check_s_min": sorted.first(),
        "limit_s": CHECK_LIMIT_S,
        "within_limit": median_s.is_some_and(|m| m <= CHECK_LIMIT_S),
        "load_average": parol6_core::process::host_load_average_1min(),
    }))
}

/// Wall times of `repeats` reads and checks of `path`, s, and the last report.
fn time_checks(path: &Path, repeats: usize) -> Result<(Vec<f64>, CheckedProgram), CliError> {
    let model = parol6_core::RobotModel::parol6();
    let start = parol6_core::motion::home_position(&model);
    let mut times_s = Vec::with_capacity(repeats);
    let mut last = None;
    for _ in 0..repeats {
        let t0 = Instant::now();
        let program = super::program::load(path, &model, &start)?;
        let report = check_program(&model, &program, &start, CheckOptions::default());
        times_s.push(t0.elapsed().as_secs_f64());
        last = Some(report);
    }
    last.map(|r| (times_s, r)).ok_or_else(|| CliError::usage("at least one repeat"))
}

fn measure(path: &Path, lines: usize, blend_mm: Option<f64>, size: (u32, u32)) -> Result<serde_json::Value, CliError> {
    let model = parol6_core::RobotModel::parol6();
    let mut headless = HeadlessApp::new(model, size.0, size.1).map_err(CliError::from)?;
    // warm-up: pipelines, fonts, the built-in program's own check
    for _ in 0..5 {
        headless.frame().map_err(CliError::from)?;
    }
    headless.app.wait_for_program_check(Duration::from_secs(10));
    for _ in 0..5 {
        headless.frame().map_err(CliError::from)?;
    }
    let t0 = Instant::now();
    headless.app.open_program_file(path).map_err(CliError::runtime)?;
    let (mut frame_ms, mut app_ms, mut ui_ms) = (Vec::new(), Vec::new(), Vec::new());
    let mut checking_frames = 0usize;
    loop {
        let start = Instant::now();
        let (_, timing) = headless.frame().map_err(CliError::from)?;
        frame_ms.push(timing.frame_ms);
        app_ms.push(timing.app_ms);
        ui_ms.push(timing.ui_cpu_ms);
        if !headless.app.program_panel().checking() {
            break;
        }
        checking_frames += 1;
        if t0.elapsed().as_secs_f64() > LOAD_LIMIT_S {
            return Err(CliError::runtime(format!("the program was not checked within {LOAD_LIMIT_S} s")));
        }
        std::thread::sleep(FRAME_PERIOD.saturating_sub(start.elapsed()));
    }
    let checked_in_s = t0.elapsed().as_secs_f64();
    let panel = headless.app.program_panel();
    let Some(checked) = panel.checked() else {
        let why = headless.app.notices().last().map(|n| n.text.clone()).unwrap_or_default();
        return Err(CliError::runtime(format!("the program did not load: {why}")));
    };
    let errors = checked.issues.iter().filter(|i| i.severity == parol6_core::program::check::Severity::Error).count();
    let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    let mut sorted = frame_ms.clone();
    sorted.sort_by(f64::total_cmp);
    Ok(json!({
        "target": "program-load",
        "lines": lines,
        "blend_mm": blend_mm,
        "steps": checked.program.steps.len(),
        "ok": checked.ok,
        "errors": errors,
        "warnings": checked.issues.len() - errors,
        "program_duration_s": checked.duration_s,
        "checked_in_s": checked_in_s,
        "frames": frame_ms.len(),
        "checking_frames": checking_frames,
        "frame_ms_max": max(&frame_ms),
        "frame_ms_p50": parol6_core::stats::percentile(&sorted, 0.5),
        "frames_over_50ms": frame_ms.iter().filter(|f| **f > STALL_MS).count(),
        "app_ms_max": max(&app_ms),
        "ui_cpu_ms_max": max(&ui_ms),
        "path_points": panel.overlay().map_or(0, |o| o.len()),
        "adapter": headless.adapter_info(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression: `bench program-load --keep FILE` created FILE in place (truncated first); a
    /// user's file named there is now replaced whole, and a FIFO or folder is refused as it is.
    #[test]
    fn the_kept_gcode_file_is_written_atomically() {
        let dir = std::env::temp_dir().join(format!("parol6-bench-program-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let kept = dir.join("raster.gcode");
        std::fs::write(&kept, "old").expect("old file");
        write_raster_gcode(&kept, 20, None).expect("written");
        let text = std::fs::read_to_string(&kept).expect("read");
        assert!(text.starts_with("; parol6 bench program-load") && text.ends_with("M30\n"), "{text}");
        let names: Vec<_> = std::fs::read_dir(&dir).expect("list").map(|e| e.expect("entry").file_name()).collect();
        assert_eq!(names, [std::ffi::OsString::from("raster.gcode")], "no temporary file left");
        let folder = dir.join("a-folder");
        std::fs::create_dir_all(&folder).expect("folder");
        let err = write_raster_gcode(&folder, 20, None).expect_err("a folder is refused");
        assert_eq!(err.status, 2, "{err:?}");
        assert!(folder.is_dir());
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}

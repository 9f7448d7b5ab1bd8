//! `parol6 screenshot --ui --run PROGRAM [--plot QUANTITY]`: the whole window after a built-in
//! program has run, on the simulation or (with `--fake-robot` / `--port`) on the controller,
//! with the plots panel showing one quantity. Scripted pictures for the manual, and the
//! simulation-vs-robot comparison of a plot (e.g. `--plot cmd-meas`).

use std::path::Path;
use std::time::{Duration, Instant};

use parol6_core::motion::StateSource;
use parol6_core::program::runner::RunState;
use parol6_core::telemetry::Quantity;
use serde_json::json;

use super::options::{ConnectArgs, RobotArgs};
use super::{CliError, CliResult, print_json};
use crate::app::ConnectTarget;
use crate::ui_screenshot::HeadlessApp;
use crate::viewport::write_png;

/// Longest program run waited for, s.
const RUN_LIMIT_S: f64 = 120.0;
/// Longest wait for the controller's first status, s.
const CONNECT_LIMIT_S: f64 = 5.0;

/// What `screenshot --ui` runs before its picture (from `ScreenshotArgs`).
#[derive(Debug, Clone)]
pub struct UiRun {
    /// Picture size, px.
    pub size_px: (u32, u32),
    /// Built-in program to run first.
    pub run: Option<String>,
    /// Quantity plotted alone.
    pub plot: Option<Quantity>,
}

/// Runs the program (if any) with the plots shown (if asked), then writes the PNG.
pub fn run_ui_program_screenshot(args: &UiRun, out: &Path, robot: &RobotArgs, connect: &ConnectArgs) -> CliResult {
    let (w, h) = args.size_px;
    let model = robot.load()?;
    let target = match (&connect.port, connect.fake_robot) {
        (Some(port), _) => Some(ConnectTarget::Port(port.clone())),
        (None, true) => Some(ConnectTarget::Emulator),
        (None, false) => None,
    };
    let on_robot = target.is_some();
    let t0 = Instant::now();
    let mut headless = HeadlessApp::connected(model, w, h, target).map_err(CliError::from)?;
    if on_robot && !headless.app.robot_connected() {
        let why = headless.app.notices().last().map(|n| n.text.clone()).unwrap_or_default();
        return Err(CliError::runtime(format!("the controller did not connect: {why}")));
    }
    if let Some(q) = args.plot {
        headless.app.show_plot(q);
    }
    let mut longest_frame_ms = 0.0f64;
    let mut frames = 0u64;
    let mut frame = |headless: &mut HeadlessApp| -> Result<_, CliError> {
        let (img, timing) = headless.frame().map_err(CliError::from)?;
        longest_frame_ms = longest_frame_ms.max(timing.frame_ms);
        frames += 1;
        Ok(img)
    };
    if on_robot {
        let deadline = Instant::now() + Duration::from_secs_f64(CONNECT_LIMIT_S);
        // the first status, then a link that accepts motion
        loop {
            let s = headless.app.backend().state();
            if s.source == StateSource::Robot && s.blocked.is_none() {
                break;
            }
            if Instant::now() > deadline {
                let why = s.blocked.clone().unwrap_or_else(|| "no status".to_string());
                return Err(CliError::runtime(format!(
                    "the controller was not ready for motion within {CONNECT_LIMIT_S} s: {why}"
                )));
            }
            frame(&mut headless)?;
        }
    }
    let mut program_s = None;
    if let Some(name) = &args.run {
        if !headless.app.start_program(name, false) {
            return Err(CliError::usage(format!("--run: no built-in program called \"{name}\"")));
        }
        // the runner checks the program on its own thread, then runs it; a frame takes its progress
        let started = Instant::now();
        let limit = Duration::from_secs_f64(RUN_LIMIT_S);
        loop {
            frame(&mut headless)?;
            let state = headless.app.program_progress().map(|p| p.state.clone());
            match state {
                Some(RunState::Done) if !headless.app.program_running() => break,
                Some(RunState::Failed(why)) => {
                    return Err(CliError::usage(format!("--run: \"{name}\" failed: {why}")));
                }
                Some(RunState::Stopped) => return Err(CliError::runtime(format!("--run: \"{name}\" was stopped"))),
                None if started.elapsed() > Duration::from_secs(10) => {
                    let why = headless.app.notices().last().map(|n| n.text.clone()).unwrap_or_default();
                    return Err(CliError::usage(format!("--run: \"{name}\" did not start: {why}")));
                }
                _ => {}
            }
            if started.elapsed() > limit {
                return Err(CliError::runtime(format!("--run: \"{name}\" ran longer than {RUN_LIMIT_S} s")));
            }
        }
        program_s = Some(started.elapsed().as_secs_f64());
    }
    // let the last samples reach the plots and egui settle its layout
    let mut img = None;
    for _ in 0..4 {
        img = Some(frame(&mut headless)?);
    }
    let img = img.ok_or_else(|| CliError::runtime("no frame rendered"))?;
    write_png(out, &img).map_err(CliError::runtime)?;
    print_json(&json!({
        "path": out.display().to_string(),
        "width": img.width,
        "height": img.height,
        "ui": true,
        "backend": if on_robot { "robot" } else { "simulation" },
        "program": args.run,
        "program_s": program_s,
        "plot": args.plot.map(|q| q.label()),
        "frames": frames,
        "longest_frame_ms": longest_frame_ms,
        "total_ms": t0.elapsed().as_secs_f64() * 1e3,
    }))
}

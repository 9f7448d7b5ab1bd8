//! `parol6 screenshot`: renders the robot with no window and no display.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use parol6_core::telemetry::Quantity;
use serde_json::json;

use super::kin::{default_seed, parse_joint_positions};
use super::options::{ConnectArgs, RobotArgs};
use super::{CliError, CliResult, print_json, warn};
use crate::ui_screenshot::HeadlessApp;
use crate::viewport::{OffscreenRenderer, SceneFrame, ViewportOptions, write_png};

/// Arguments of `parol6 screenshot`.
#[derive(Debug, Clone, clap::Args)]
pub struct ScreenshotArgs {
    /// Output PNG file (a file name: "-" is refused, stdout carries the JSON report).
    #[arg(value_name = "OUT.png")]
    pub out: PathBuf,
    /// Joint values J1,…,JN, finite numbers (rad, or degrees with --deg; default: the standby pose, or
    /// mid-range for other robots).
    #[arg(long, value_name = "J1,J2,…", allow_hyphen_values = true)]
    pub joints: Option<String>,
    /// Joint values are in degrees.
    #[arg(long)]
    pub deg: bool,
    /// Image size WIDTHxHEIGHT in pixels, each side 1–16384.
    #[arg(long, value_name = "WxH", default_value = "1280x800")]
    pub size: String,
    /// Render the whole window layout (panels and 3D view), not only the 3D view.
    #[arg(long)]
    pub ui: bool,
    /// Render this many frames and report the median time per frame (a benchmark), 1–10 000.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub repeat: u64,
    /// With --ui: run this built-in program (e.g. draw, "pick & place") on the simulation, or on
    /// the controller with --fake-robot / --port, and take the picture when it has finished
    /// (at most 120 s).
    #[arg(long, value_name = "PROGRAM", requires = "ui", conflicts_with = "joints")]
    pub run: Option<String>,
    /// With --ui: show the plots panel with this quantity alone: position, velocity,
    /// acceleration, drive, cmd-meas, tcp-position or tcp-orientation.
    #[arg(long, value_name = "QUANTITY", requires = "ui", value_parser = parse_quantity)]
    pub plot: Option<Quantity>,
}

/// The `--plot` names, in [`Quantity::ALL`] order.
const PLOT_NAMES: [&str; 7] =
    ["position", "velocity", "acceleration", "drive", "cmd-meas", "tcp-position", "tcp-orientation"];

fn parse_quantity(text: &str) -> Result<Quantity, String> {
    let name = text.trim().to_ascii_lowercase();
    PLOT_NAMES
        .iter()
        .position(|n| *n == name)
        .and_then(|i| Quantity::ALL.get(i).copied())
        .ok_or_else(|| format!("\"{text}\" is not a quantity; use one of {}", PLOT_NAMES.join(", ")))
}

impl ScreenshotArgs {
    /// The parsed `--size` (width, height) in pixels.
    pub fn size_px(&self) -> Result<(u32, u32), CliError> {
        parse_size(&self.size)
    }

    /// The output path, refused when it is not a file name.
    pub fn out_path(&self) -> Result<&Path, CliError> {
        if let Some(why) = super::options::output_file_refusal(self.out.as_os_str()) {
            return Err(CliError::usage(format!("OUT.png: {why}")));
        }
        if self.out.is_dir() {
            return Err(CliError::usage(format!("OUT.png: \"{}\" is not a file name", self.out.display())));
        }
        Ok(&self.out)
    }

    /// The robot and the joint values (rad) selected by the arguments.
    pub fn robot_and_joints(&self, robot: &RobotArgs) -> Result<(parol6_core::RobotModel, Vec<f64>), CliError> {
        let model = robot.load()?;
        let q = match &self.joints {
            Some(s) => parse_joint_positions("--joints", s, model.dof(), self.deg)?,
            None => default_seed(&model),
        };
        Ok((model, q))
    }
}

/// Parses "WxH" (also "W×H" and "W,H").
pub fn parse_size(text: &str) -> Result<(u32, u32), CliError> {
    let bad = || CliError::usage(format!("--size: expected WIDTHxHEIGHT in pixels such as 1280x800, got \"{text}\""));
    let t = text.trim().to_ascii_lowercase();
    let (w, h) = t.split_once(['x', '×', ',']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(CliError::usage(format!("--size: each side must be 1…16384 px, got {w}x{h}")));
    }
    Ok((w, h))
}

/// Runs `parol6 screenshot`: the 3D view alone, or with `--ui` the whole window layout.
pub fn run_screenshot(a: &ScreenshotArgs, robot: &RobotArgs, connect: &ConnectArgs) -> CliResult {
    let out = a.out_path()?;
    if a.ui && (a.run.is_some() || a.plot.is_some()) {
        let run = super::render_run::UiRun { size_px: a.size_px()?, run: a.run.clone(), plot: a.plot };
        return super::render_run::run_ui_program_screenshot(&run, out, robot, connect);
    }
    if a.ui {
        return run_ui_screenshot(a, out, robot);
    }
    let (w, h) = a.size_px()?;
    let (model, q) = a.robot_and_joints(robot)?;
    if let Err(e) = model.limits.check(&q) {
        warn(e);
    }
    let t0 = Instant::now();
    let mut r = OffscreenRenderer::new(&model, w, h).map_err(CliError::runtime)?;
    for warning in r.warnings() {
        warn(warning);
    }
    let setup_ms = t0.elapsed().as_secs_f64() * 1e3;
    let scene = SceneFrame::from_joints(&model, &q, None);
    let options = ViewportOptions::default();
    let mut img = None;
    let mut frame_ms = Vec::new();
    for _ in 0..a.repeat.max(1) {
        let t1 = Instant::now();
        img = Some(r.render(&scene, &options).map_err(CliError::runtime)?);
        frame_ms.push(t1.elapsed().as_secs_f64() * 1e3);
    }
    let first_ms = frame_ms.first().copied().unwrap_or(0.0);
    frame_ms.sort_by(f64::total_cmp);
    let ms = parol6_core::stats::percentile(&frame_ms, 0.5).unwrap_or(0.0);
    let img = img.ok_or_else(|| CliError::runtime("nothing was rendered"))?;
    write_png(out, &img).map_err(CliError::runtime)?;
    print_json(&json!({
        "path": out.display().to_string(),
        "width": img.width,
        "height": img.height,
        "adapter": r.adapter_info(),
        "ms": ms,
        "first_frame_ms": first_ms,
        "frames": frame_ms.len(),
        "msaa": r.sample_count(),
        "setup_ms": setup_ms,
        "joints_rad": q,
    }))
}

/// `parol6 screenshot --ui`: the whole window layout at the given joints.
fn run_ui_screenshot(args: &ScreenshotArgs, out: &Path, robot: &RobotArgs) -> CliResult {
    let (w, h) = args.size_px()?;
    let (model, q) = args.robot_and_joints(robot)?;
    if let Err(e) = model.limits.check(&q) {
        return Err(CliError::usage(format!("--joints: {e}")));
    }
    let t0 = Instant::now();
    let mut headless = HeadlessApp::new(model, w, h).map_err(CliError::from)?;
    headless.app.teleport(q.clone()).map_err(CliError::from)?;
    // Let the simulation take the pose, then let egui settle its layout (a few passes).
    let refusals_before = headless.app.sim().snapshot().last_error.as_ref().map(|(id, _)| *id);
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let s = headless.app.sim().snapshot();
        if s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-3) {
            break;
        }
        // the simulation refuses poses that collide (with itself or the ground)
        if let Some((id, msg)) = &s.last_error
            && Some(*id) != refusals_before
        {
            return Err(CliError::usage(format!("--joints: the simulation refused the pose: {msg}")));
        }
        if Instant::now() > deadline {
            return Err(CliError::runtime("the simulation did not take the requested pose within 5 s"));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let mut last = None;
    for k in 0..4 {
        last = Some(headless.frame().map_err(CliError::from)?);
        if k == 0 {
            // the program's pre-flight and planned path (made on a worker) in the picture
            headless.app.wait_for_program_check(Duration::from_secs(10));
        }
    }
    let (img, timing) = last.ok_or_else(|| CliError::runtime("no frame rendered"))?;
    write_png(out, &img).map_err(CliError::runtime)?;
    print_json(&json!({
        "path": out.display().to_string(),
        "width": img.width,
        "height": img.height,
        "ui": true,
        "adapter": headless.adapter_info(),
        "ms": timing.frame_ms,
        "total_ms": t0.elapsed().as_secs_f64() * 1e3,
        "joints_rad": q,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_reject() {
        assert_eq!(parse_size("1280x800").ok().map(|s| (s.0, s.1)), Some((1280, 800)));
        assert_eq!(parse_size(" 64X48 ").ok().map(|s| (s.0, s.1)), Some((64, 48)));
        for bad in ["", "1280", "0x10", "x", "12x-3", "99999x10"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }
}

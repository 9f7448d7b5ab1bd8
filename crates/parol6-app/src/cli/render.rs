//! `parol6 screenshot`: renders the robot with no window and no display.

use std::path::PathBuf;
use std::time::Instant;

use serde_json::json;

use super::kin::{RobotArgs, default_seed, parse_list};
use super::{CliError, CliResult, print_json};
use crate::viewport::{OffscreenRenderer, SceneFrame, ViewportOptions, write_png};

/// Arguments of `parol6 screenshot`.
#[derive(Debug, Clone, clap::Args)]
pub struct ScreenshotArgs {
    /// Output PNG file.
    #[arg(value_name = "OUT.png")]
    pub out: PathBuf,
    /// Joint values J1,…,JN (rad, or degrees with --deg; default: the standby pose, or
    /// mid-range for other robots).
    #[arg(long, value_name = "J1,J2,…", allow_hyphen_values = true)]
    pub joints: Option<String>,
    /// Joint values are in degrees.
    #[arg(long)]
    pub deg: bool,
    /// Image size WIDTHxHEIGHT in pixels.
    #[arg(long, value_name = "WxH", default_value = "1280x800")]
    pub size: String,
    /// Render the whole window layout (panels and 3D view), not only the 3D view.
    #[arg(long)]
    pub ui: bool,
    /// Render this many frames and report the median time per frame (a benchmark).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub repeat: usize,
    #[command(flatten)]
    pub robot: RobotArgs,
}

impl ScreenshotArgs {
    /// The parsed `--size` (width, height) in pixels.
    pub fn size_px(&self) -> Result<(u32, u32), CliError> {
        parse_size(&self.size)
    }

    /// The robot and the joint values (rad) selected by the arguments.
    pub fn robot_and_joints(&self) -> Result<(parol6_core::RobotModel, Vec<f64>), CliError> {
        let model = self.robot.load()?;
        let q = match &self.joints {
            Some(s) => {
                let mut q = parse_list("--joints", s, Some(model.dof()))?;
                if self.deg {
                    q.iter_mut().for_each(|v| *v = v.to_radians());
                }
                q
            }
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

/// Runs `parol6 screenshot` (the 3D-only path; `--ui` goes to [`crate::ui_screenshot`]).
pub fn run_screenshot(a: &ScreenshotArgs) -> CliResult {
    if a.ui {
        return crate::ui_screenshot::run(a);
    }
    let (w, h) = a.size_px()?;
    let (model, q) = a.robot_and_joints()?;
    if let Err(e) = model.limits.check(&q) {
        eprintln!("warning: {e}");
    }
    let t0 = Instant::now();
    let mut r = OffscreenRenderer::new(&model, w, h).map_err(CliError::runtime)?;
    for warning in r.warnings() {
        eprintln!("warning: {warning}");
    }
    let setup_ms = t0.elapsed().as_secs_f64() * 1e3;
    let scene = SceneFrame::from_joints(&model, &q, None);
    let options = ViewportOptions::default();
    let mut img = None;
    let mut frame_ms = Vec::with_capacity(a.repeat.max(1));
    for _ in 0..a.repeat.max(1) {
        let t1 = Instant::now();
        img = Some(r.render(&scene, &options).map_err(CliError::runtime)?);
        frame_ms.push(t1.elapsed().as_secs_f64() * 1e3);
    }
    let first_ms = frame_ms[0];
    frame_ms.sort_by(f64::total_cmp);
    let ms = frame_ms[frame_ms.len() / 2];
    let img = img.ok_or_else(|| CliError::runtime("nothing was rendered"))?;
    write_png(&a.out, &img).map_err(CliError::runtime)?;
    print_json(&json!({
        "path": a.out.display().to_string(),
        "width": img.width,
        "height": img.height,
        "adapter": r.adapter_info(),
        "ms": ms,
        "first_frame_ms": first_ms,
        "frames": frame_ms.len(),
        "msaa": r.sample_count(),
        "setup_ms": setup_ms,
        "joints_rad": q,
    }));
    Ok(())
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

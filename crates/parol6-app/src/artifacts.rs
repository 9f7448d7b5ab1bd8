//! What the test hooks, benchmarks and screenshots write and measure: an image as PNG, this
//! process's resident memory. A leaf: it uses nothing of the app (the window, the panels, the
//! offscreen renderer), only the viewport's PNG encoder, so `app` (its test hooks) and
//! `ui_screenshot` both use it without using each other.

use std::path::Path;

use eframe::egui;

use crate::viewport::{RgbaImage, write_png};

/// Writes RGBA8 pixels (rows top to bottom) as a PNG.
pub fn write_rgba_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> anyhow::Result<()> {
    let img = RgbaImage { width, height, pixels: rgba.to_vec() };
    write_png(path, &img).map_err(|e| anyhow::anyhow!("{e}"))
}

/// Writes an egui screenshot as PNG.
pub fn write_color_image(path: &Path, img: &egui::ColorImage) -> anyhow::Result<()> {
    let [w, h] = img.size;
    let rgba: Vec<u8> = img.pixels.iter().flat_map(|c| c.to_srgba_unmultiplied()).collect();
    write_rgba_png(path, w as u32, h as u32, &rgba)
}

/// Peak resident set size of this process, MB (Linux `VmHWM`), if known.
pub fn peak_rss_mb() -> Option<f64> {
    proc_status_mb("VmHWM:")
}

/// Resident set size of this process now, MB (Linux `VmRSS`), if known.
pub fn rss_mb() -> Option<f64> {
    proc_status_mb("VmRSS:")
}

fn proc_status_mb(field: &str) -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with(field))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

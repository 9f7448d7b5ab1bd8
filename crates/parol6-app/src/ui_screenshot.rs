//! The whole window layout rendered with no window and no display: the app's real UI
//! ([`Parol6App::frame`]) run through `egui::Context::run_ui`, tessellated, and drawn by
//! egui-wgpu (including the 3D view's paint callback) into the [`OffscreenRenderer`]'s
//! targets. Used by `parol6 screenshot --ui` and `parol6 bench render`.

use eframe::egui;
use std::path::Path;
use std::time::{Duration, Instant};

use parol6_core::RobotModel;
use serde_json::json;

use crate::app::{LaunchOptions, Parol6App};
use crate::cli::render::ScreenshotArgs;
use crate::cli::{CliError, CliResult, print_json};
use crate::viewport::{OffscreenRenderer, RgbaImage, write_png};

/// Clear colour behind the panels (egui's dark panel fill).
const CLEAR_SRGB: [u8; 3] = crate::theme::PANEL_BG_SRGB;

/// Writes RGBA8 pixels (rows top to bottom) as a PNG.
pub fn write_rgba_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> anyhow::Result<()> {
    let img = RgbaImage { width, height, pixels: rgba.to_vec() };
    write_png(path, &img).map_err(|e| anyhow::anyhow!("{e}"))
}

/// Timings of one headless frame.
#[derive(Debug, Clone, Copy)]
pub struct FrameTiming {
    /// Whole frame: UI pass, tessellation, GPU rendering and read-back, ms.
    pub frame_ms: f64,
    /// CPU time of the egui pass (the app's UI code and egui layout) plus tessellation, ms.
    pub ui_cpu_ms: f64,
    /// CPU time of the app's own frame function (inside the egui pass), ms.
    pub app_ms: f64,
}

/// The app running headless at a fixed size.
pub struct HeadlessApp {
    renderer: OffscreenRenderer,
    render_state: eframe::egui_wgpu::RenderState,
    ctx: egui::Context,
    /// The app.
    pub app: Parol6App,
    size: (u32, u32),
    t0: Instant,
}

impl HeadlessApp {
    /// Opens a headless device and builds the app on it.
    pub fn new(model: RobotModel, width: u32, height: u32) -> anyhow::Result<Self> {
        let started = Instant::now();
        let renderer = OffscreenRenderer::new(&model, width, height).map_err(|e| anyhow::anyhow!("{e}"))?;
        let render_state = renderer.egui_render_state();
        let opts = LaunchOptions {
            model,
            connect: None,
            settings_path: None,
            test_script: None,
            started,
            msaa_samples: renderer.sample_count(),
        };
        let app = Parol6App::new(opts, Some(&render_state))?;
        let ctx = egui::Context::default();
        ctx.set_visuals(crate::theme::visuals());
        Ok(Self { renderer, render_state, ctx, app, size: (width, height), t0: started })
    }

    /// Adapter description.
    pub fn adapter_info(&self) -> String {
        self.renderer.adapter_info()
    }

    /// Runs and renders one frame; returns the image and the timings.
    pub fn frame(&mut self) -> anyhow::Result<(RgbaImage, FrameTiming)> {
        let start = Instant::now();
        let (w, h) = self.size;
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(w as f32, h as f32))),
            time: Some(self.t0.elapsed().as_secs_f64()),
            focused: true,
            ..Default::default()
        };
        let mut app_ms = 0.0;
        let app = &mut self.app;
        let out = self.ctx.run_ui(input, |ui| {
            app.frame(ui);
            app_ms = app.perf().ui_cpu_ms;
        });
        let ppp = out.pixels_per_point;
        let prims = self.ctx.tessellate(out.shapes, ppp);
        let ui_cpu_ms = start.elapsed().as_secs_f64() * 1000.0;
        let img = self
            .renderer
            .render_egui(&self.render_state, &prims, &out.textures_delta, ppp, CLEAR_SRGB)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let frame_ms = start.elapsed().as_secs_f64() * 1000.0;
        Ok((img, FrameTiming { frame_ms, ui_cpu_ms, app_ms }))
    }
}

/// `parol6 screenshot --ui`: the whole window layout at the given joints.
pub fn run(args: &ScreenshotArgs) -> CliResult {
    let (w, h) = args.size_px()?;
    let (model, q) = args.robot_and_joints()?;
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
    for _ in 0..4 {
        last = Some(headless.frame().map_err(CliError::from)?);
    }
    let (img, timing) = last.ok_or_else(|| CliError::runtime("no frame rendered"))?;
    write_png(&args.out, &img).map_err(CliError::runtime)?;
    print_json(&json!({
        "path": args.out.display().to_string(),
        "width": img.width,
        "height": img.height,
        "ui": true,
        "adapter": headless.adapter_info(),
        "ms": timing.frame_ms,
        "total_ms": t0.elapsed().as_secs_f64() * 1e3,
        "joints_rad": q,
    }));
    Ok(())
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    sorted[((sorted.len() as f64 - 1.0) * q).round() as usize]
}

/// Peak resident set size of this process, MB (Linux `VmHWM`), if known.
pub fn peak_rss_mb() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Performance targets checked by `parol6 bench render --check` (issue 4, point 9).
pub const TARGET_FPS_MEDIAN: f64 = 40.0;
/// UI CPU time per frame, p50, ms.
pub const TARGET_UI_CPU_MS_P50: f64 = 1.0;
/// Peak resident memory, MB.
pub const TARGET_RSS_MB: f64 = 150.0;

/// `parol6 bench render`: frames of the full UI while the arm sweeps all joints; prints JSON.
pub fn bench_render(model: RobotModel, seconds: f64, width: u32, height: u32, check: bool) -> CliResult {
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(CliError::usage(format!("--seconds must be > 0, got {seconds}")));
    }
    let mut headless = HeadlessApp::new(model, width, height).map_err(CliError::from)?;
    if !headless.app.start_demo("Joint sweep", true) {
        return Err(CliError::runtime("no joint sweep demo"));
    }
    // Warm-up: pipelines, fonts, first uploads.
    for _ in 0..5 {
        headless.frame().map_err(CliError::from)?;
    }
    let mut frame_ms = Vec::new();
    let mut ui_ms = Vec::new();
    let mut app_ms = Vec::new();
    let mut moving_frames = 0usize;
    let t0 = Instant::now();
    while t0.elapsed().as_secs_f64() < seconds {
        let (_, t) = headless.frame().map_err(CliError::from)?;
        frame_ms.push(t.frame_ms);
        ui_ms.push(t.ui_cpu_ms);
        app_ms.push(t.app_ms);
        if headless.app.sim().snapshot().moving {
            moving_frames += 1;
        }
    }
    let wall_s = t0.elapsed().as_secs_f64();
    let n = frame_ms.len();
    let mut fps: Vec<f64> = frame_ms.iter().map(|ms| 1000.0 / ms.max(1e-6)).collect();
    for v in [&mut frame_ms, &mut ui_ms, &mut app_ms, &mut fps] {
        v.sort_by(f64::total_cmp);
    }
    let fps_median = percentile(&fps, 0.5);
    let ui_p50 = percentile(&ui_ms, 0.5);
    let rss = peak_rss_mb();
    let pass =
        fps_median >= TARGET_FPS_MEDIAN && ui_p50 <= TARGET_UI_CPU_MS_P50 && rss.is_none_or(|r| r <= TARGET_RSS_MB);
    print_json(&json!({
        "target": "render",
        "width": width,
        "height": height,
        "seconds": wall_s,
        "frames": n,
        "moving_frames": moving_frames,
        "fps_median": fps_median,
        "fps_mean": n as f64 / wall_s,
        "frame_ms_p50": percentile(&frame_ms, 0.5),
        "frame_ms_p99": percentile(&frame_ms, 0.99),
        "ui_cpu_ms_p50": ui_p50,
        "ui_cpu_ms_p99": percentile(&ui_ms, 0.99),
        "app_ui_ms_p50": percentile(&app_ms, 0.5),
        "rss_mb_peak": rss,
        "adapter": headless.adapter_info(),
        "targets": {"fps_median_min": TARGET_FPS_MEDIAN, "ui_cpu_ms_p50_max": TARGET_UI_CPU_MS_P50, "rss_mb_max": TARGET_RSS_MB},
        "pass": pass,
    }));
    if check && !pass {
        return Err(CliError::runtime("render performance below the targets (see the JSON above)"));
    }
    Ok(())
}

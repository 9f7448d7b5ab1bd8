//! The whole window layout rendered with no window and no display: the app's real UI
//! ([`Parol6App::frame`]) run through `egui::Context::run_ui`, tessellated, and drawn by
//! egui-wgpu (including the 3D view's paint callback) into the [`OffscreenRenderer`]'s
//! targets. Used by `parol6 screenshot --ui` and `parol6 bench render` (in [`crate::cli`];
//! this module does not depend on the command line).

use eframe::egui;
use std::time::Instant;

use parol6_core::RobotModel;

use crate::app::{LaunchOptions, Parol6App};
use crate::viewport::offscreen::EguiPassTiming;
use crate::viewport::retained::{RetainedHandle, RetainedStats};
use crate::viewport::{OffscreenRenderer, RgbaImage};

/// Clear colour behind the panels (egui's dark panel fill).
const CLEAR_SRGB: [u8; 3] = crate::theme::PANEL_BG_SRGB;

pub use crate::artifacts::{peak_rss_mb, rss_mb, write_rgba_png};

/// Timings of one headless frame.
#[derive(Debug, Clone, Copy)]
pub struct FrameTiming {
    /// Whole frame: UI pass, tessellation, GPU rendering and read-back, ms.
    pub frame_ms: f64,
    /// CPU time of the egui pass (the app's UI code and egui layout) plus tessellation, ms.
    pub ui_cpu_ms: f64,
    /// CPU time of the app's own frame function (inside the egui pass), ms.
    pub app_ms: f64,
    /// egui's tessellation of the frame's shapes (part of `ui_cpu_ms`), ms.
    pub tessellate_ms: f64,
    /// Uploads, the render pass and the read-back ([`EguiPassTiming`]).
    pub gpu: EguiPassTiming,
    /// Clipped primitives drawn (egui meshes and paint callbacks).
    pub primitives: usize,
    /// Vertices of the egui meshes.
    pub vertices: usize,
    /// Triangles of the egui meshes.
    pub triangles: usize,
    /// Pixels the egui meshes' triangles cover (overlaps counted twice).
    pub egui_area_px: f64,
    /// The frame's numbers when it went through retained painting (only changed rectangles
    /// redrawn; the counts above then describe the one callback that stands for the UI).
    pub retained: Option<RetainedStats>,
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
    /// What is drawn (for the per-layer breakdown of `parol6 bench render --layers`; anything
    /// but all layers draws without retained painting).
    layers: Layers,
    retained: Option<RetainedHandle>,
}

/// Which layers of the frame [`HeadlessApp::frame`] draws; the UI pass always runs in full.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layers {
    /// egui's meshes (panels, text, plots, overlays).
    pub egui: bool,
    /// The 3D view (egui-wgpu paint callbacks).
    pub view_3d: bool,
}

impl Default for Layers {
    fn default() -> Self {
        Self { egui: true, view_3d: true }
    }
}

impl HeadlessApp {
    /// Opens a headless device and builds the app on it.
    pub fn new(model: RobotModel, width: u32, height: u32) -> anyhow::Result<Self> {
        Self::with_layers(model, width, height, Layers::default())
    }

    /// Like [`Self::new`], drawing only `layers`. With all of them, frames are painted as the
    /// window paints them (retained painting on software rasterizers, whose egui pass then has
    /// no depth buffer); otherwise egui draws every frame in full.
    pub fn with_layers(model: RobotModel, width: u32, height: u32, layers: Layers) -> anyhow::Result<Self> {
        Self::build(model, width, height, layers, None)
    }

    /// Like [`Self::new`], connected at start to `connect` (the robot or the built-in emulator).
    pub fn connected(
        model: RobotModel,
        width: u32,
        height: u32,
        connect: Option<crate::app::ConnectTarget>,
    ) -> anyhow::Result<Self> {
        Self::build(model, width, height, Layers::default(), connect)
    }

    fn build(
        model: RobotModel,
        width: u32,
        height: u32,
        layers: Layers,
        connect: Option<crate::app::ConnectTarget>,
    ) -> anyhow::Result<Self> {
        let started = Instant::now();
        let mut renderer = OffscreenRenderer::new(&model, width, height).map_err(|e| anyhow::anyhow!("{e}"))?;
        let retained = layers == Layers::default()
            && crate::viewport::retained::retained_for(renderer.device_type(), renderer.sample_count());
        let render_state = renderer.egui_render_state_with_depth(!retained);
        let opts = LaunchOptions {
            model,
            connect,
            settings_path: None,
            test_script: None,
            started,
            msaa_samples: renderer.sample_count(),
            record: None,
            replay: None,
            recording_info: Default::default(),
        };
        let app = Parol6App::new(opts, Some(&render_state))?;
        let ctx = egui::Context::default();
        ctx.set_visuals(crate::theme::visuals());
        crate::viewport::configure_tessellation(&ctx, &render_state);
        // before retained painting, which must see the whole frame
        crate::app::frame_reuse::install(&ctx);
        let retained = retained
            .then(|| crate::viewport::retained::install(&ctx, &render_state, crate::theme::panel_background(), None));
        Ok(Self { renderer, render_state, ctx, app, size: (width, height), t0: started, layers, retained })
    }

    /// Frames drawn in full and reused so far (none without frame reuse, see
    /// `app::frame_reuse`).
    pub fn reuse_stats(&self) -> Option<crate::app::frame_reuse::ReuseStats> {
        crate::app::frame_reuse::FrameReuse::find(&self.ctx).map(|r| r.stats())
    }

    /// Adapter description.
    pub fn adapter_info(&self) -> String {
        self.renderer.adapter_info()
    }

    /// Runs and renders one frame; returns the image and the timings.
    pub fn frame(&mut self) -> anyhow::Result<(RgbaImage, FrameTiming)> {
        self.frame_with_input(Vec::new())
    }

    /// The window's size now, px.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Resizes the window (the next frame is laid out and drawn at the new size).
    pub fn resize(&mut self, width: u32, height: u32) -> anyhow::Result<()> {
        self.renderer.resize(width, height).map_err(|e| anyhow::anyhow!("{e}"))?;
        self.size = (width, height);
        Ok(())
    }

    /// Like [`Self::frame`], with `events` (key presses, modifier changes) as this frame's
    /// input: what a user's keys do in the window.
    pub fn frame_with_input(&mut self, events: Vec<egui::Event>) -> anyhow::Result<(RgbaImage, FrameTiming)> {
        let start = Instant::now();
        let (w, h) = self.size;
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(w as f32, h as f32))),
            time: Some(self.t0.elapsed().as_secs_f64()),
            focused: true,
            events,
            ..Default::default()
        };
        let mut app_ms = 0.0;
        let app = &mut self.app;
        let out = self.ctx.run_ui(input, |ui| {
            app.frame(ui);
            app_ms = app.perf().ui_cpu_ms;
        });
        let ppp = out.pixels_per_point;
        let t_tess = Instant::now();
        let mut prims = self.ctx.tessellate(out.shapes, ppp);
        let tessellate_ms = t_tess.elapsed().as_secs_f64() * 1000.0;
        let ui_cpu_ms = start.elapsed().as_secs_f64() * 1000.0;
        let layers = self.layers;
        prims.retain(|p| match p.primitive {
            egui::epaint::Primitive::Mesh(_) => layers.egui,
            egui::epaint::Primitive::Callback(_) => layers.view_3d,
        });
        let (mut vertices, mut indices, mut area_px) = (0, 0, 0.0);
        for p in &prims {
            if let egui::epaint::Primitive::Mesh(m) = &p.primitive {
                vertices += m.vertices.len();
                indices += m.indices.len();
                for t in m.indices.chunks_exact(3) {
                    let [a, b, c] =
                        [t[0], t[1], t[2]].map(|i| m.vertices.get(i as usize).map_or(egui::Pos2::ZERO, |v| v.pos));
                    let area = 0.5 * ((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs() * ppp * ppp;
                    area_px += f64::from(area);
                }
            }
        }

        let img = self
            .renderer
            .render_egui(&self.render_state, &prims, &out.textures_delta, ppp, CLEAR_SRGB)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let frame_ms = start.elapsed().as_secs_f64() * 1000.0;
        let gpu = self.renderer.last_egui_timing();
        let primitives = prims.len();
        let timing = FrameTiming {
            frame_ms,
            ui_cpu_ms,
            app_ms,
            tessellate_ms,
            gpu,
            primitives,
            vertices,
            triangles: indices / 3,
            egui_area_px: area_px,
            retained: self.retained.as_ref().map(RetainedHandle::stats),
        };
        Ok((img, timing))
    }
}

/// Performance targets checked by `parol6 bench render --check`: whole frame, p50, ms
/// (1280×800 on a CPU rasterizer, the plots panel open).
pub const TARGET_FRAME_MS_P50: f64 = 10.0;
/// Whole frame, p99, ms.
pub const TARGET_FRAME_MS_P99: f64 = 16.0;
/// UI CPU time per frame, p50, ms.
pub const TARGET_UI_CPU_MS_P50: f64 = 1.0;
/// Resident memory of the running app (`bench render`: at the end of the run), MB.
pub const TARGET_RSS_MB: f64 = 200.0;

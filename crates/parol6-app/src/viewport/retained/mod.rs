//! Retained painting for software rasterizers: the window keeps its last image and each frame
//! redraws only the rectangles whose egui shapes changed.
//!
//! On llvmpipe / lavapipe most of a frame went into shading egui's text, although the panels'
//! text hardly ever changes while the arm moves. [`install`] adds an egui plugin that, after
//! every UI pass, takes the frame's shapes out of egui's output and replaces them with one
//! paint callback. That callback compares the shapes with the last drawn frame
//! ([`damage`]), redraws the changed rectangles (background, every mesh and paint callback
//! reaching into them, in paint order) into a window-sized texture, and copies the texture
//! into egui's render pass. The window and `bench render` / `screenshot --ui` take the same
//! path. On GPUs it is off: there the whole frame costs well under a millisecond.

mod damage;
mod painter;

use std::sync::{Arc, Mutex};

use eframe::egui;
use eframe::egui_wgpu;
use eframe::wgpu;
use egui::epaint::ClippedShape;

use painter::{RetainedFrame, RetainedFrameCallback, RetainedPainter, Shared};

/// Numbers of the last frame drawn through retained painting.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct RetainedStats {
    /// Frames drawn so far.
    pub frames: u64,
    /// Rectangles redrawn in the last frame.
    pub rects: usize,
    /// Pixels inside them.
    pub redrawn_px: f64,
    /// Pixels of the window.
    pub screen_px: f64,
    /// Draw jobs (backgrounds, meshes, paint callbacks) of the last frame.
    pub jobs: usize,
    /// egui triangles submitted in the last frame.
    pub triangles: usize,
    /// Whether the last frame was redrawn in full.
    pub full_redraw: bool,
    /// CPU time of comparing, uploading and recording the last frame, ms.
    pub prepare_ms: f64,
}

/// Reads the numbers of retained painting.
#[derive(Clone)]
pub struct RetainedHandle {
    shared: Arc<Shared>,
}

impl RetainedHandle {
    /// Numbers of the last painted frame.
    pub fn stats(&self) -> RetainedStats {
        self.shared.stats.lock().map(|s| *s).unwrap_or_default()
    }
}

/// Whether retained painting is used on an adapter of `device_type` drawing with `samples`:
/// `PAROL6_RETAINED_UI=0|1` when set, else on software rasterizers without MSAA.
pub fn retained_for(device_type: wgpu::DeviceType, samples: u32) -> bool {
    if samples != 1 {
        return false;
    }
    match std::env::var("PAROL6_RETAINED_UI").ok().as_deref().map(str::trim) {
        Some("0") => false,
        Some("1") => true,
        _ => device_type == wgpu::DeviceType::Cpu,
    }
}

/// Installs retained painting on `ctx` (for good: every root frame goes through it). egui's
/// own pass, into which the kept image is copied, must have one sample and `pass_depth` as its
/// depth attachment. Without one (the window's choice, see [`super::WindowSetup`]) a software
/// rasterizer does not clear, load and store a window-sized depth buffer every frame that
/// nothing uses (1–3 ms less per frame at 1280×800 on llvmpipe); the 3D view, drawn into the
/// kept image, has its own depth buffer there. `background` is the colour egui's panels are
/// drawn on (the clear colour).
pub fn install(
    ctx: &egui::Context,
    render_state: &egui_wgpu::RenderState,
    background: egui::Color32,
    pass_depth: Option<wgpu::TextureFormat>,
) -> RetainedHandle {
    let shared =
        Arc::new(Shared { pending_textures: Mutex::new(Vec::new()), stats: Mutex::new(RetainedStats::default()) });
    let painter = RetainedPainter::new(
        &render_state.device,
        render_state.target_format,
        pass_depth,
        background,
        Arc::clone(&shared),
    );
    render_state.renderer.write().callback_resources.insert(painter);
    let handle = RetainedHandle { shared };
    ctx.add_plugin(RetainedPaint { handle: handle.clone(), drawn_before: false });
    handle
}

/// The egui plugin: swaps each root frame's shapes for one [`RetainedFrameCallback`].
struct RetainedPaint {
    handle: RetainedHandle,
    /// Whether a frame went through retained painting already (the first is drawn in full).
    drawn_before: bool,
}

impl egui::Plugin for RetainedPaint {
    fn debug_name(&self) -> &'static str {
        "parol6 retained painting"
    }

    fn output_hook(&mut self, ctx: &egui::Context, output: &mut egui::FullOutput) {
        if ctx.viewport_id() != egui::ViewportId::ROOT {
            return;
        }
        let force_full = !self.drawn_before;
        self.drawn_before = true;
        let shapes = std::mem::take(&mut output.shapes);
        let primitives = ctx.tessellate(shapes.clone(), output.pixels_per_point);
        // egui's own renderer keeps getting the texture changes too (it owns the textures of
        // other viewports)
        if let Ok(mut pending) = self.handle.shared.pending_textures.lock() {
            pending.push(output.textures_delta.clone());
        }
        let screen = ctx.viewport_rect();
        let callback =
            RetainedFrameCallback { frame: Mutex::new(Some(RetainedFrame { shapes, primitives, force_full })) };
        output.shapes = vec![ClippedShape {
            clip_rect: screen,
            shape: egui::Shape::Callback(egui_wgpu::Callback::new_paint_callback(screen, callback)),
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        }];
    }
}

//! Retained painting for software rasterizers: the window keeps its last image and each frame
//! redraws only the rectangles whose egui shapes changed.
//!
//! On llvmpipe / lavapipe most of a frame went into shading egui's text, although the panels'
//! text hardly ever changes while the arm moves. [`install`] adds an egui plugin that, after
//! every UI pass, takes the frame's shapes out of egui's output and replaces them with one
//! paint callback. That callback compares the shapes with the last drawn frame
//! (`damage`), redraws the changed rectangles (background, every mesh and paint callback
//! reaching into them, in paint order) into a window-sized texture, and copies the texture
//! into egui's render pass. The window and `bench render` / `screenshot --ui` take the same
//! path. On GPUs it is off: there the whole frame costs well under a millisecond. A paint
//! callback's owner may say which part of it changed ([`CallbackDamage`]): the 3D view does
//! while only the arm moves, so the background and grid around it are not redrawn.

mod callback_damage;
mod damage;
mod painter;
mod spread;

pub use callback_damage::CallbackDamage;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use eframe::egui;
use eframe::egui_wgpu;
use eframe::wgpu;
use egui::epaint::ClippedShape;

use painter::{RetainedFrame, RetainedFrameCallback, RetainedPainter, Shared};

/// Margin around a shape's painted area when deciding whether it reaches into a changed
/// rectangle, points (rounding of the tessellator).
const REACH_MARGIN_PT: f32 = 2.0;

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
    /// Frames after the last one that a change spread over several still needs (0–2).
    pub frames_left: usize,
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
/// drawn on (the clear colour). egui's animations are turned off (`animation_time` 0).
pub fn install(
    ctx: &egui::Context,
    render_state: &egui_wgpu::RenderState,
    background: egui::Color32,
    pass_depth: Option<wgpu::TextureFormat>,
) -> RetainedHandle {
    // an animation redraws its whole area every frame while it lasts (a window fading in: five
    // frames of ~35 ms each on llvmpipe, the file dialog's), so on a software rasterizer what
    // appears, opens or scrolls does so at once
    ctx.all_styles_mut(|style| style.animation_time = 0.0);
    let shared = Arc::new(Shared {
        pending_textures: Mutex::new(Vec::new()),
        stats: Mutex::new(RetainedStats::default()),
        need_full: AtomicBool::new(false),
        ctx: ctx.clone(),
    });
    let painter = RetainedPainter::new(
        &render_state.device,
        render_state.target_format,
        pass_depth,
        background,
        Arc::clone(&shared),
    );
    render_state.renderer.write().callback_resources.insert(painter);
    let handle = RetainedHandle { shared };
    CallbackDamage::mark_wanted(ctx);
    ctx.add_plugin(RetainedPaint {
        handle: handle.clone(),
        last_shapes: Vec::new(),
        last_screen: None,
        deferred_next: Vec::new(),
        deferred_after: Vec::new(),
    });
    handle
}

/// Whether egui will discard the pass whose `output` this is and run another (a new grid or
/// window sizing itself): its shapes are never shown (egui paints nothing into such a pass).
/// Output plugins must then leave their state as the last shown frame left it.
pub(crate) fn pass_will_be_discarded(ctx: &egui::Context, output: &egui::FullOutput) -> bool {
    output.platform_output.requested_discard()
        && output.platform_output.num_completed_passes < ctx.options(|o| o.max_passes.get())
}

/// The egui plugin: finds what changed since the last frame, tessellates only the shapes that
/// reach into it, and swaps each root frame's shapes for one [`RetainedFrameCallback`].
struct RetainedPaint {
    handle: RetainedHandle,
    /// The last frame's shapes, for the comparison.
    last_shapes: Vec<ClippedShape>,
    /// The last frame's size in pixels and pixels per point (none before the first frame).
    last_screen: Option<([u32; 2], f32)>,
    /// What a large change left for this frame to redraw (columns or a band, [`spread::plan`]).
    deferred_next: Vec<egui::Rect>,
    /// ... and for the frame after it (columns).
    deferred_after: Vec<egui::Rect>,
}

/// Whether `shape` paints anything inside one of `rects`.
fn reaches(shape: &ClippedShape, rects: &[egui::Rect]) -> bool {
    if shape.transform_after_tessellation != egui::emath::TSTransform::IDENTITY {
        return true;
    }
    let painted = shape.shape.visual_bounding_rect().expand(REACH_MARGIN_PT).intersect(shape.clip_rect);
    painted.is_positive() && rects.iter().any(|r| painted.intersects(*r))
}

impl egui::Plugin for RetainedPaint {
    fn debug_name(&self) -> &'static str {
        "parol6 retained painting"
    }

    fn output_hook(&mut self, ctx: &egui::Context, output: &mut egui::FullOutput) {
        if ctx.viewport_id() != egui::ViewportId::ROOT {
            return;
        }
        let ppp = output.pixels_per_point;
        let screen = ctx.viewport_rect();
        let size_px = [(screen.width() * ppp).round() as u32, (screen.height() * ppp).round() as u32];
        let screen_pt =
            egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(size_px[0] as f32 / ppp, size_px[1] as f32 / ppp));
        // any texture change but new glyphs in the font atlas (drawn text stays valid) may
        // change any pixel
        let textures_changed = output
            .textures_delta
            .set
            .iter()
            .any(|(id, deltas)| *id != egui::TextureId::default() || deltas.iter().any(|d| d.pos.is_none()));
        if pass_will_be_discarded(ctx, output) {
            // egui runs the frame again and shows that pass: compare it with the last frame
            // drawn, not with this one (which paints nothing); keep its texture changes
            if let Ok(mut pending) = self.handle.shared.pending_textures.lock() {
                pending.push(output.textures_delta.clone());
            }
            if textures_changed {
                self.handle.shared.need_full.store(true, Ordering::Relaxed);
            }
            return;
        }
        let shapes = std::mem::take(&mut output.shapes);
        let hints = CallbackDamage::take(ctx);
        // the first frame, the painter asking, a texture that any pixel may show
        let full = self.last_screen.is_none()
            || self.handle.shared.need_full.swap(false, Ordering::Relaxed)
            || textures_changed;
        let rects = if full {
            self.deferred_next.clear();
            self.deferred_after.clear();
            vec![screen_pt]
        } else {
            let on_screen = |v: &mut Vec<egui::Rect>| -> Vec<egui::Rect> {
                v.drain(..).map(|r| r.intersect(screen_pt)).filter(|r| r.is_positive()).collect()
            };
            let (overdue, soon) = (on_screen(&mut self.deferred_next), on_screen(&mut self.deferred_after));
            // a new size or scale changes the whole window (spread as any window-wide change)
            let changed = if self.last_screen != Some((size_px, ppp)) {
                vec![screen_pt]
            } else {
                damage::changed_rects(&self.last_shapes, &shapes, &hints)
            };
            let spread = spread::plan(
                screen_pt,
                || shapes.iter().map(spread::ShapeCost::of).collect(),
                ppp,
                changed,
                &overdue,
                &soon,
            );
            (self.deferred_next, self.deferred_after) = (spread.next, spread.after);
            spread.now
        };
        if !self.deferred_next.is_empty() {
            // the parts left are drawn by the next frames: there must be one, at once (an
            // idle window would otherwise show them stale until its next repaint)
            ctx.request_repaint();
            if let Some(v) = output.viewport_output.get_mut(&egui::ViewportId::ROOT) {
                v.repaint_delay = std::time::Duration::ZERO;
            }
        }
        // only what reaches into the rectangles is tessellated (the painter draws nothing else)
        let reaching: Vec<ClippedShape> = shapes.iter().filter(|s| reaches(s, &rects)).cloned().collect();
        let primitives = if reaching.is_empty() { Vec::new() } else { ctx.tessellate(reaching, ppp) };
        self.last_shapes = shapes;
        self.last_screen = Some((size_px, ppp));
        // egui's own renderer keeps getting the texture changes too (it owns the textures of
        // other viewports)
        if let Ok(mut pending) = self.handle.shared.pending_textures.lock() {
            pending.push(output.textures_delta.clone());
        }
        let full = rects == [screen_pt];
        let frames_left = usize::from(!self.deferred_next.is_empty()) + usize::from(!self.deferred_after.is_empty());
        let frame = RetainedFrame { rects, primitives, full, frames_left };
        let callback = RetainedFrameCallback { frame: Mutex::new(Some(frame)) };
        output.shapes = vec![ClippedShape {
            clip_rect: screen,
            shape: egui::Shape::Callback(egui_wgpu::Callback::new_paint_callback(screen, callback)),
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        }];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{Color32, Pos2, Rect, Shape, Stroke};

    fn clipped(shape: Shape) -> ClippedShape {
        ClippedShape {
            clip_rect: Rect::EVERYTHING,
            shape,
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        }
    }

    #[test]
    fn only_shapes_painting_into_a_changed_rectangle_are_tessellated() {
        let changed = [Rect::from_min_max(Pos2::new(100.0, 100.0), Pos2::new(200.0, 120.0))];
        let inside = clipped(Shape::rect_filled(
            Rect::from_min_size(Pos2::new(150.0, 105.0), egui::vec2(5.0, 5.0)),
            0.0,
            Color32::RED,
        ));
        let far = clipped(Shape::rect_filled(
            Rect::from_min_size(Pos2::new(400.0, 400.0), egui::vec2(5.0, 5.0)),
            0.0,
            Color32::RED,
        ));
        // a line ending just outside still paints into it (its stroke and the margin)
        let edge = clipped(Shape::line_segment(
            [Pos2::new(50.0, 99.0), Pos2::new(99.0, 99.0)],
            Stroke::new(2.0, Color32::RED),
        ));
        assert!(reaches(&inside, &changed));
        assert!(!reaches(&far, &changed));
        assert!(reaches(&edge, &changed));
        // clipped away: paints nothing there
        let mut hidden = inside.clone();
        hidden.clip_rect = Rect::from_min_size(Pos2::new(300.0, 300.0), egui::vec2(10.0, 10.0));
        assert!(!reaches(&hidden, &changed));
        // moved after tessellation: kept, whatever its rectangle
        let mut moved = far.clone();
        moved.transform_after_tessellation = egui::emath::TSTransform::from_translation(egui::vec2(-300.0, -300.0));
        assert!(reaches(&moved, &changed));
    }
}

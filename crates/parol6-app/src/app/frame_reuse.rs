//! Frame reuse: while only the 3D view changes (the arm moves, nobody touches the UI), the
//! panels are laid out at the readout rate ([`READOUT_HZ`]) and the frames between lay out the
//! 3D view alone and show the panels as the last full frame drew them.
//!
//! A reused frame keeps what the user sees and what the pointer hits in step: its shapes are
//! the last full frame's, with the 3D view's own swapped in ([`ReusePlugin`], an egui output
//! hook that runs before retained painting), and the last full frame's widgets are registered
//! again ([`FrameReuse::register_kept_widgets`]) so that a click in the next frame lands on
//! the widget under the pointer. A frame is reused only when that is all that would change:
//! no input for [`QUIET_BEFORE_REUSE`], nothing focused, no popup, menu, window or tooltip,
//! accessibility off, the same screen size and scale, no test script. `PAROL6_REUSE_FRAMES=0`
//! turns it off (every frame full), for comparison.
//!
//! What the panels show that changes during motion (the plots, the timeline, the program's
//! progress) therefore updates at [`READOUT_HZ`], as the numeric read-outs always have; the
//! 3D view updates every frame.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use eframe::egui;
use egui::epaint::ClippedShape;
use egui::{Id, LayerId, Rect};

use super::Parol6App;
#[cfg(doc)]
use crate::panels::READOUT_HZ;

/// Input (a key, the pointer moving, a click, scrolling) makes this many full frames' worth of
/// time: egui's animations after a click or a scroll finish within it.
pub(crate) const QUIET_BEFORE_REUSE: Duration = Duration::from_millis(500);

/// The data key under which [`install`] leaves the handle for the app.
const HANDLE_KEY: &str = "parol6-frame-reuse";
/// The scope id of the 3D view's `Ui`, the same in full and reused frames.
pub(crate) const CENTRAL_SCOPE: &str = "parol6-central";

/// What the app decided about the frame being drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
enum FrameKind {
    /// Everything laid out; the 3D view got `central`.
    Full { central: Rect },
    /// Only the 3D view laid out, into the kept `central`.
    Reused,
}

/// The last full frame, and counts.
#[derive(Default)]
struct Kept {
    this_frame: Option<FrameKind>,
    shapes: Vec<ClippedShape>,
    central: Option<Rect>,
    /// The kept frame's text: laid out again (a cache look-up) in reused frames, or egui's
    /// layout cache, which keeps only what the frame before used, would drop it and the next
    /// full frame would lay out every text anew.
    texts: Arc<Vec<Arc<egui::text::LayoutJob>>>,
    /// Screen rectangle and pixels per point of the kept frame.
    screen: Option<(Rect, f32)>,
    stats: ReuseStats,
}

/// How many frames were drawn in full and how many reused, since start.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReuseStats {
    /// Frames whose panels were laid out.
    pub full_frames: u64,
    /// Frames that showed the panels of the last full frame.
    pub reused_frames: u64,
}

/// The app's handle on frame reuse (found in the egui context, see [`FrameReuse::find`]).
#[derive(Clone)]
pub(crate) struct FrameReuse {
    kept: Arc<Mutex<Kept>>,
}

/// Installs frame reuse on `ctx`. Install it before retained painting (plugins run in the order
/// they were added): that one must see the whole frame. Does nothing when
/// `PAROL6_REUSE_FRAMES=0`.
pub fn install(ctx: &egui::Context) {
    if std::env::var("PAROL6_REUSE_FRAMES").is_ok_and(|v| v.trim() == "0") {
        return;
    }
    install_on(ctx);
}

fn install_on(ctx: &egui::Context) -> FrameReuse {
    let handle = FrameReuse { kept: Arc::new(Mutex::new(Kept::default())) };
    ctx.add_plugin(ReusePlugin { handle: handle.clone() });
    ctx.data_mut(|d| d.insert_temp(Id::unique(HANDLE_KEY), handle.clone()));
    handle
}

impl FrameReuse {
    /// The handle [`install`] left in `ctx`, if any.
    pub(crate) fn find(ctx: &egui::Context) -> Option<Self> {
        ctx.data(|d| d.get_temp::<Self>(Id::unique(HANDLE_KEY)))
    }

    fn with<R>(&self, f: impl FnOnce(&mut Kept) -> R) -> Option<R> {
        self.kept.lock().ok().map(|mut k| f(&mut k))
    }

    /// The 3D view's rectangle of the last full frame, if that frame can be shown again at
    /// this screen size and scale.
    fn kept_central(&self, ctx: &egui::Context) -> Option<Rect> {
        let screen = (ctx.viewport_rect(), ctx.pixels_per_point());
        self.with(|k| if k.screen == Some(screen) { k.central } else { None }).flatten()
    }

    /// Counts so far.
    pub(crate) fn stats(&self) -> ReuseStats {
        self.with(|k| k.stats).unwrap_or_default()
    }

    /// Marks this frame as laid out in full, the 3D view in `central`.
    pub(crate) fn full_frame(&self, central: Rect) {
        self.with(|k| k.this_frame = Some(FrameKind::Full { central }));
    }

    /// Marks this frame as reused, and registers the last full frame's widgets again: egui
    /// finds what the pointer is over from the widgets of the frame before, so without them a
    /// click right after a reused frame would land on nothing. Call after the 3D view was laid
    /// out (its widgets are registered by itself).
    pub(crate) fn register_kept_widgets(&self, ctx: &egui::Context) {
        let texts = self.with(|k| {
            k.this_frame = Some(FrameKind::Reused);
            Arc::clone(&k.texts)
        });
        ctx.fonts_mut(|f| {
            for job in texts.as_deref().into_iter().flatten() {
                let _ = f.layout_job(egui::text::LayoutJob::clone(job));
            }
        });
        // the frame before is the last full frame or a reused one, which registered the same set
        let (kept, present) = ctx.viewport(|v| {
            let kept: Vec<egui::WidgetRect> =
                v.prev_pass.widgets.layers().flat_map(|(_, w)| w.iter().copied()).collect();
            let present: std::collections::HashSet<Id> =
                v.this_pass.widgets.layers().flat_map(|(_, w)| w.iter().map(|w| w.id)).collect();
            (kept, present)
        });
        let screen = ctx.viewport_rect();
        // one Ui per layer and enabled/visible state; they paint nothing
        let mut hosts: Vec<((LayerId, bool, bool), egui::Ui)> = Vec::new();
        for w in kept.into_iter().filter(|w| !present.contains(&w.id)) {
            let key = (w.layer_id, w.enabled, w.visible);
            let i = match hosts.iter().position(|(k, _)| *k == key) {
                Some(i) => i,
                None => {
                    let mut host = egui::Ui::new(
                        ctx.clone(),
                        Id::unique((HANDLE_KEY, key)),
                        egui::UiBuilder::new().layer_id(w.layer_id).max_rect(screen),
                    );
                    if !w.enabled {
                        host.disable();
                    }
                    if !w.visible {
                        host.set_invisible();
                    }
                    hosts.push((key, host));
                    hosts.len() - 1
                }
            };
            let host = &mut hosts[i].1;
            // interact_rect = clip ∩ rect, as it was
            host.set_clip_rect(w.interact_rect);
            host.interact(w.rect, w.id, w.sense);
        }
    }
}

impl Parol6App {
    /// The 3D view's rectangle when this frame can reuse the last full frame's panels, else
    /// `None` (lay out everything). `readout_due`: the read-outs refresh this frame.
    pub(super) fn reusable_central(&mut self, ctx: &egui::Context, now: Instant, readout_due: bool) -> Option<Rect> {
        if !input_quiet(ctx) {
            self.input_at = now;
        }
        let reuse = self.frame_reuse.as_ref()?;
        let quiet = now.duration_since(self.input_at) >= QUIET_BEFORE_REUSE;
        if readout_due || !quiet || self.test.is_some() || self.sweep.is_some() || !self.commands.is_empty() {
            return None;
        }
        if !ui_at_rest(ctx) {
            return None;
        }
        reuse.kept_central(ctx)
    }
}

/// No input this frame: no event, the pointer still and no button or key held, no scrolling.
fn input_quiet(ctx: &egui::Context) -> bool {
    ctx.input(|i| {
        i.events.is_empty()
            && i.pointer.delta() == egui::Vec2::ZERO
            && !i.pointer.any_down()
            && i.keys_down.is_empty()
            && i.smooth_scroll_delta == egui::Vec2::ZERO
    })
}

/// Nothing on screen but the panels: no focused widget (egui drops the focus of a widget it
/// does not see), only background layers (no popup, menu, window or tooltip), and no
/// accessibility tree to build.
fn ui_at_rest(ctx: &egui::Context) -> bool {
    ctx.memory(|m| m.focused().is_none())
        && ctx.memory(|m| m.areas().visible_layer_ids().iter().all(|l| l.order == egui::Order::Background))
        && ctx.viewport(|v| v.this_pass.accesskit_state.is_none())
}

/// The egui plugin: keeps each full frame's shapes and gives reused frames the kept shapes with
/// this frame's 3D view swapped in.
struct ReusePlugin {
    handle: FrameReuse,
}

impl egui::Plugin for ReusePlugin {
    fn debug_name(&self) -> &'static str {
        "parol6 frame reuse"
    }

    fn output_hook(&mut self, ctx: &egui::Context, output: &mut egui::FullOutput) {
        if ctx.viewport_id() != egui::ViewportId::ROOT {
            return;
        }
        let screen = (ctx.viewport_rect(), output.pixels_per_point);
        self.handle.with(|k| match k.this_frame.take() {
            Some(FrameKind::Reused) if k.screen == Some(screen) => {
                if let Some(central) = k.central {
                    let fresh = std::mem::take(&mut output.shapes);
                    output.shapes = splice(&k.shapes, central, fresh);
                }
                k.stats.reused_frames += 1;
            }
            kind => {
                k.shapes = output.shapes.clone();
                let mut texts = Vec::new();
                for s in &k.shapes {
                    collect_texts(&s.shape, &mut texts);
                }
                k.texts = Arc::new(texts);
                k.central = match kind {
                    Some(FrameKind::Full { central }) if central.is_positive() => Some(central),
                    _ => None,
                };
                k.screen = Some(screen);
                k.stats.full_frames += 1;
            }
        });
    }
}

/// The text layouts `shape` paints, into `out`.
fn collect_texts(shape: &egui::Shape, out: &mut Vec<Arc<egui::text::LayoutJob>>) {
    match shape {
        egui::Shape::Text(t) => out.push(Arc::clone(&t.galley.job)),
        egui::Shape::Vec(v) => v.iter().for_each(|s| collect_texts(s, out)),
        _ => {}
    }
}

/// The kept frame's shapes with those inside `central` (the 3D view's, found by their clip
/// rectangle) replaced by `fresh`, in their place in the painting order.
fn splice(kept: &[ClippedShape], central: Rect, fresh: Vec<ClippedShape>) -> Vec<ClippedShape> {
    let region = central.expand(0.5);
    let mut out = Vec::with_capacity(kept.len() + fresh.len());
    let mut fresh = Some(fresh);
    for s in kept {
        if region.contains_rect(s.clip_rect) {
            if let Some(f) = fresh.take() {
                out.extend(f);
            }
        } else {
            out.push(s.clone());
        }
    }
    if let Some(f) = fresh {
        out.extend(f);
    }
    out
}

#[cfg(test)]
#[path = "frame_reuse_tests.rs"]
mod tests;

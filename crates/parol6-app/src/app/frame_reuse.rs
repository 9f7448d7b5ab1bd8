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
//! 3D view updates every frame. A read-out refresh does not lay out every panel at once: the
//! frames after it lay out one step of a wave each ([`super::panel_groups::WAVE`]: the left
//! column, then everything else), with the other groups' kept shapes and widgets, so no single
//! frame carries all of it.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use eframe::egui;
use egui::epaint::ClippedShape;
use egui::{Id, LayerId, Rect};

use super::Parol6App;
use super::panel_groups::{GroupRects, GroupSet, PartialLayout, WAVE};
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
#[derive(Debug, Clone, PartialEq)]
enum FrameKind {
    /// Everything laid out; the 3D view got `central`, the panel groups `groups`.
    Full { central: Rect, groups: GroupRects },
    /// The 3D view and the groups of `lay_out` laid out, into their kept rectangles
    /// (`regions`: the view's first); the other groups kept.
    Partial { regions: Vec<Rect>, lay_out: GroupSet },
}

/// The frame partial frames start from (the last full frame, with each wave step's groups
/// swapped in since), where its groups are, the wave's state, and counts.
#[derive(Default)]
struct Kept {
    this_frame: Option<FrameKind>,
    shapes: Vec<ClippedShape>,
    central: Option<Rect>,
    /// Where the kept frame's panel groups are (as the last full frame put them).
    groups: GroupRects,
    /// The groups whose read-outs were refreshed since they were last laid out.
    stale: GroupSet,
    /// The wave's step to try first.
    next_step: usize,
    /// A group laid out in a partial frame did not come out where the kept frame has it (a
    /// panel appeared, went or changed size without input: a recording opened): the next
    /// frame is full.
    layout_changed: bool,
    /// The kept frame's text: laid out again (a cache look-up) in reused frames, or egui's
    /// layout cache, which keeps only what the frame before used, would drop it and the next
    /// full frame would lay out every text anew.
    texts: Arc<Vec<Arc<egui::text::LayoutJob>>>,
    /// Screen rectangle and pixels per point of the kept frame.
    screen: Option<(Rect, f32)>,
    stats: ReuseStats,
}

/// How many frames were drawn in full, in part and reused, since start.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReuseStats {
    /// Frames whose panels were all laid out.
    pub full_frames: u64,
    /// Frames that laid out one step of a wave (some panel groups) and kept the others.
    pub wave_frames: u64,
    /// Frames that laid out the 3D view alone and kept every panel.
    pub reused_frames: u64,
}

impl Kept {
    /// The wave's next step with a stale group (it is laid out now, so no longer stale), or
    /// no group.
    fn next_wave_step(&mut self) -> GroupSet {
        for i in 0..WAVE.len() {
            let step = (self.next_step + i) % WAVE.len();
            if WAVE[step].intersects(self.stale) {
                self.next_step = (step + 1) % WAVE.len();
                self.stale = self.stale.without(WAVE[step]);
                return WAVE[step];
            }
        }
        GroupSet::EMPTY
    }

    /// Keeps `shapes` as the frame partial frames start from, and the texts they paint.
    fn keep(&mut self, shapes: &[ClippedShape]) {
        self.shapes = shapes.to_vec();
        let mut texts = Vec::new();
        for s in shapes {
            collect_texts(&s.shape, &mut texts);
        }
        self.texts = Arc::new(texts);
    }
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

    /// What this frame lays out when the last full frame can be shown again at this screen
    /// size and scale: the 3D view, and the next step of the wave when groups are stale
    /// (`readout_due`: the read-outs refresh this frame, every group is stale).
    fn partial_layout(&self, ctx: &egui::Context, readout_due: bool) -> Option<PartialLayout> {
        let screen = (ctx.viewport_rect(), ctx.pixels_per_point());
        self.with(|k| {
            let central = k.central.filter(|_| k.screen == Some(screen) && !k.layout_changed)?;
            if readout_due {
                k.stale = GroupSet::ALL;
            }
            Some(PartialLayout { central, lay_out: k.next_wave_step(), rects: k.groups })
        })
        .flatten()
    }

    /// Counts so far.
    pub(crate) fn stats(&self) -> ReuseStats {
        self.with(|k| k.stats).unwrap_or_default()
    }

    /// Marks this frame as laid out in full, the 3D view in `central`, the groups in `groups`.
    pub(crate) fn full_frame(&self, central: Rect, groups: GroupRects) {
        self.with(|k| k.this_frame = Some(FrameKind::Full { central, groups }));
    }

    /// Checks where this partial frame laid out its groups (`laid_out`: as the layout returned
    /// them) against the kept frame: when one moved, appeared or went, the next frame is full.
    pub(crate) fn check_layout(&self, partial: &PartialLayout, laid_out: &GroupRects) {
        let moved = super::panel_groups::PanelGroup::ALL
            .into_iter()
            .any(|g| partial.lay_out.contains(g) && laid_out.get(g) != partial.rects.get(g));
        if moved {
            self.with(|k| k.layout_changed = true);
            tracing::debug!("frame reuse: a panel group moved, the next frame is full");
        }
    }

    /// Marks this frame as laid out in part (`partial`), and registers the kept widgets of
    /// what it did not lay out again: egui finds what the pointer is over from the widgets of
    /// the frame before, so without them a click right after such a frame would land on
    /// nothing. Call after the 3D view was laid out (its widgets and those of the groups laid
    /// out are registered by themselves).
    pub(crate) fn register_kept_widgets(&self, ctx: &egui::Context, partial: &PartialLayout) {
        let regions: Vec<Rect> = std::iter::once(partial.central).chain(partial.rects.of(partial.lay_out)).collect();
        let laid_out: Vec<Rect> = regions.iter().map(|r| r.expand(0.5)).collect();
        let stand_ins: Vec<Rect> =
            partial.rects.of(GroupSet::ALL.without(partial.lay_out)).map(|r| r.expand(0.5)).collect();
        let texts = self.with(|k| {
            k.this_frame = Some(FrameKind::Partial { regions, lay_out: partial.lay_out });
            Arc::clone(&k.texts)
        });
        ctx.fonts_mut(|f| {
            for job in texts.as_deref().into_iter().flatten() {
                let _ = f.layout_job(egui::text::LayoutJob::clone(job));
            }
        });
        // the frame before is the last full frame or a partial one, which registered the same set
        // with the groups it laid out anew
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
        // what this frame laid out registered its widgets; those it no longer has are gone
        let gone = |w: &egui::WidgetRect| laid_out.iter().any(|r| r.contains_rect(w.interact_rect));
        // a stand-in registers its panel's id with its own rectangle: the kept one wins
        let stood_in = |w: &egui::WidgetRect| stand_ins.iter().any(|r| r.contains_rect(w.interact_rect));
        for w in kept.into_iter().filter(|w| !gone(w) && (!present.contains(&w.id) || stood_in(w))) {
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
    /// What this frame lays out when it can reuse the last full frame's panels (the 3D view, and
    /// a step of the wave after a read-out refresh), else `None` (lay out everything): never
    /// while the arm stands still (`moving` false). `readout_due`: the read-outs refresh this
    /// frame.
    pub(super) fn partial_layout(
        &mut self,
        ctx: &egui::Context,
        now: Instant,
        readout_due: bool,
        moving: bool,
    ) -> Option<PartialLayout> {
        if !input_quiet(ctx) {
            self.input_at = now;
        }
        let reuse = self.frame_reuse.as_ref()?;
        let quiet = now.duration_since(self.input_at) >= QUIET_BEFORE_REUSE;
        if !moving
            || !quiet
            || self.hook.as_ref().is_some_and(super::test_hooks::Hook::full_frames)
            || !self.commands.is_empty()
        {
            return None;
        }
        if !ui_at_rest(ctx) {
            return None;
        }
        reuse.partial_layout(ctx, readout_due)
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

/// The egui plugin: keeps each full frame's shapes and gives partial frames the kept shapes with
/// this frame's 3D view and the groups it laid out swapped in (a wave step's result is kept).
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
        if crate::viewport::retained::pass_will_be_discarded(ctx, output) {
            // egui runs the frame again: that pass lays out the same wave step, and keeps
            self.handle.with(|k| {
                if let Some(FrameKind::Partial { lay_out, .. }) = k.this_frame.take()
                    && let Some(step) = WAVE.iter().position(|s| *s == lay_out)
                {
                    k.stale = k.stale.union(lay_out);
                    k.next_step = step;
                }
            });
            return;
        }
        let screen = (ctx.viewport_rect(), output.pixels_per_point);
        self.handle.with(|k| match k.this_frame.take() {
            Some(FrameKind::Partial { regions, lay_out }) if k.screen == Some(screen) => {
                let fresh = std::mem::take(&mut output.shapes);
                output.shapes = splice(&k.shapes, &regions, fresh);
                if lay_out.is_empty() {
                    k.stats.reused_frames += 1;
                } else {
                    k.keep(&output.shapes);
                    k.stats.wave_frames += 1;
                }
            }
            kind => {
                k.keep(&output.shapes);
                (k.central, k.groups) = match kind {
                    Some(FrameKind::Full { central, groups }) if central.is_positive() => (Some(central), groups),
                    _ => (None, GroupRects::default()),
                };
                (k.stale, k.next_step, k.layout_changed) = (GroupSet::EMPTY, 0, false);
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

/// The kept frame's shapes with those inside each of `regions` (the 3D view and the groups laid
/// out this frame, found by their clip rectangles) replaced by the `fresh` ones inside it, in
/// their place in the painting order (after the rest, when the kept frame had none there).
/// Fresh shapes outside every region are dropped: the stand-ins paint nothing, and what the
/// groups laid out paint outside their own rectangle (a side panel's separator line) is the
/// same as the kept frame's.
fn splice(kept: &[ClippedShape], regions: &[Rect], fresh: Vec<ClippedShape>) -> Vec<ClippedShape> {
    let regions: Vec<Rect> = regions.iter().map(|r| r.expand(0.5)).collect();
    let region_of = |clip: Rect| regions.iter().position(|r| r.contains_rect(clip));
    let mut by_region: Vec<Option<Vec<ClippedShape>>> = vec![Some(Vec::new()); regions.len()];
    for s in fresh {
        if let Some(bucket) = region_of(s.clip_rect).and_then(|i| by_region[i].as_mut()) {
            bucket.push(s);
        }
    }
    let mut out = Vec::with_capacity(kept.len() + 16);
    for s in kept {
        match region_of(s.clip_rect) {
            Some(i) => {
                if let Some(f) = by_region[i].take() {
                    out.extend(f);
                }
            }
            None => out.push(s.clone()),
        }
    }
    for f in by_region.into_iter().flatten() {
        out.extend(f);
    }
    out
}

#[cfg(test)]
mod tests;

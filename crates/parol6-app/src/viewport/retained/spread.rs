//! Spreading a costly redraw over two or three frames: what a large change costs a software
//! rasterizer, and which part of it to draw now and which in the next frames.
//!
//! A window-wide change (a recording opened, the window resized) is cut into whole columns at
//! the panels' edges ([`spread_columns`]), in parts of about [`FRAME_PART_US`] of work, at most
//! [`MAX_SPREAD_FRAMES`]; a costly change over part of the window (a window such as the point
//! table appearing over the panels) into two bands, top and bottom ([`spread_bands`]). Either
//! way nothing is more than two frames behind: what the last frame left for this one is drawn
//! first, and what it left for the one after is drawn by then.

use eframe::egui;
use egui::epaint::{ClippedShape, Shape};
use egui::{Rect, pos2};

use super::damage::{FULL_REDRAW_SHARE, merge};

/// A software rasterizer's time per triangle drawn, µs of CPU (set-up and binning; llvmpipe on
/// the 2-core reference machine, from the point table's first frame: 6 500 triangles).
const US_PER_TRIANGLE: f32 = 5.0;
/// Its time per pixel of a filled shape, µs of CPU (the egui shader and blending; from the
/// point table's drop shadow, 260 000 px in 15 ms).
const US_PER_PX: f32 = 0.06;
/// What a paint callback (the 3D view, drawn through its own pipeline) costs, in triangles of
/// egui's: the window-wide redraw of the 3D view alone takes about 3 ms on the reference machine.
const CALLBACK_TRIANGLES: f32 = 600.0;
/// A change estimated to cost more than this is drawn over two frames, µs of CPU: with the
/// rasterizer's two threads, about 15 ms of a frame on two idle cores (a window-wide change of
/// 6 500 triangles, estimated at 33 000, took 37 ms).
pub const SPREAD_ABOVE_US: f32 = 30_000.0;
/// Changes over less of the window than this are never estimated (too small to matter).
const ESTIMATE_ABOVE_SHARE: f32 = 0.08;
/// A window-wide change is cut into at most this many columns.
pub const MAX_SPREAD_COLUMNS: usize = 8;
/// A window-wide change is drawn in parts of about this much work each, µs of CPU (with the
/// rasterizer's two threads and the frame's own work, about 15 ms of a frame on two idle
/// cores: a resize or a recording opening redraws ~55 ms of CPU work in all)...
pub const FRAME_PART_US: f32 = 15_000.0;
/// ... over at least two frames and at most this many.
pub const MAX_SPREAD_FRAMES: usize = 3;

/// What one frame redraws now and what it leaves for the next two.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Spread {
    /// Redrawn in this frame.
    pub now: Vec<Rect>,
    /// Left for the next frame.
    pub next: Vec<Rect>,
    /// Left for the frame after it.
    pub after: Vec<Rect>,
}

impl Spread {
    /// All of it now.
    fn at_once(now: Vec<Rect>) -> Self {
        Self { now, ..Self::default() }
    }
}

/// One shape as the estimate sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeCost {
    /// Its clip rectangle, points.
    pub clip: Rect,
    /// Where it paints (inside the clip), points.
    pub painted: Rect,
    /// Triangles it will have, about.
    pub triangles: f32,
    /// Whether it fills its area (a filled rectangle or circle), so that its pixels count; a
    /// text's pixels are its glyphs' few, a plot line's its thin strips.
    pub fills: bool,
}

impl ShapeCost {
    /// The estimate for `shape`.
    pub fn of(shape: &ClippedShape) -> Self {
        let painted = shape.shape.visual_bounding_rect();
        let painted = if painted.is_finite() && painted.is_positive() {
            painted.intersect(shape.clip_rect)
        } else {
            Rect::NOTHING
        };
        Self { clip: shape.clip_rect, painted, triangles: triangles(&shape.shape), fills: fills(&shape.shape) }
    }

    /// What drawing the part of this shape inside `r` costs, µs (`ppp`: pixels per point).
    fn cost_within(&self, r: Rect, ppp: f32) -> f32 {
        let part = self.painted.intersect(r);
        if !part.is_positive() {
            return 0.0;
        }
        let share = (part.area() / self.painted.area().max(1e-3)).min(1.0);
        let px = if self.fills { part.area() * ppp * ppp * US_PER_PX } else { 0.0 };
        self.triangles * share * US_PER_TRIANGLE + px
    }
}

/// Triangles `shape` is tessellated into, about (a text: two per glyph; a rectangle: its fill
/// and feathered edges, more with round corners).
fn triangles(shape: &Shape) -> f32 {
    match shape {
        Shape::Text(t) => 2.0 * t.galley.rows.iter().map(|r| r.glyphs.len()).sum::<usize>() as f32,
        Shape::Mesh(m) => (m.indices.len() / 3) as f32,
        Shape::Vec(v) => v.iter().map(triangles).sum(),
        Shape::Rect(r) if r.corner_radius == egui::CornerRadius::ZERO => 10.0,
        Shape::Rect(_) | Shape::Circle(_) | Shape::Ellipse(_) => 40.0,
        Shape::Path(p) => 4.0 * p.points.len() as f32,
        Shape::LineSegment { .. } => 6.0,
        Shape::Callback(_) => CALLBACK_TRIANGLES,
        _ => 8.0,
    }
}

/// Whether `shape` covers its area with paint.
fn fills(shape: &Shape) -> bool {
    match shape {
        Shape::Rect(r) => r.fill.a() > 0,
        Shape::Circle(c) => c.fill.a() > 0,
        Shape::Ellipse(e) => e.fill.a() > 0,
        // a mesh is mostly a plot's thin lines, whose bounding box is far larger than what they
        // paint: its triangles say its cost; a paint callback (the 3D view) draws with its own,
        // cheap pipeline: its cost is its scene, whatever its size ([`CALLBACK_TRIANGLES`])
        Shape::Mesh(_) | Shape::Callback(_) => false,
        Shape::Vec(v) => v.iter().any(fills),
        _ => false,
    }
}

/// What redrawing `rects` costs, µs.
pub fn cost(shapes: &[ShapeCost], rects: &[Rect], ppp: f32) -> f32 {
    shapes.iter().map(|s| rects.iter().map(|&r| s.cost_within(r, ppp)).sum::<f32>()).sum()
}

/// The rectangles to redraw now and those left for the next frames, for the frame whose new
/// changes are `changed` (points, not yet merged) after the last frames left `overdue` (for
/// this frame) and `soon` (for the next). The whole window (`screen`) as one rectangle is cut
/// into columns; a change over part of it costing more than [`SPREAD_ABOVE_US`] into two bands;
/// anything else is drawn now. `shapes` gives the frame's shapes' estimates, asked for only
/// when the change is large.
pub fn plan(
    screen: Rect,
    shapes: impl FnOnce() -> Vec<ShapeCost>,
    ppp: f32,
    changed: Vec<Rect>,
    overdue: &[Rect],
    soon: &[Rect],
) -> Spread {
    let new = merge(changed, ppp, screen);
    let all = merge(new.iter().chain(overdue).copied().collect(), ppp, screen);
    // what waits for the next frame, but what this one draws anyway
    let with_soon = |now: &[Rect], mut next: Vec<Rect>| {
        next.extend(soon.iter().filter(|s| !now.iter().any(|n| n.contains_rect(**s))));
        next
    };
    let area: f32 = all.iter().map(Rect::area).sum();
    if area < ESTIMATE_ABOVE_SHARE * screen.area() {
        let next = with_soon(&all, Vec::new());
        return Spread { now: all, next, after: Vec::new() };
    }
    let shapes = shapes();
    if all == [screen] {
        return spread_columns(screen, &shapes, ppp, overdue, soon);
    }
    let total = cost(&shapes, &all, ppp);
    let (now, later) = if total <= SPREAD_ABOVE_US {
        (all, Vec::new())
    } else {
        spread_bands(screen, &shapes, ppp, &new, overdue, total)
    };
    let next = with_soon(&now, later);
    Spread { now, next, after: Vec::new() }
}

/// A costly change over part of the window (`new`, merged) in two horizontal bands: what the
/// last frame left (`overdue`) and the top of `new` now, the cut chosen so that now costs about
/// half of `total`; the rest of `new` next frame.
fn spread_bands(
    screen: Rect,
    shapes: &[ShapeCost],
    ppp: f32,
    new: &[Rect],
    overdue: &[Rect],
    total: f32,
) -> (Vec<Rect>, Vec<Rect>) {
    let budget = 0.5 * total - cost(shapes, overdue, ppp);
    // each shape's cost inside the new change, by the height where it lies
    let mut by_y: Vec<(f32, f32)> = shapes
        .iter()
        .flat_map(|s| new.iter().map(move |&r| (s, r)))
        .filter_map(|(s, r)| {
            let c = s.cost_within(r, ppp);
            (c > 0.0).then(|| (s.painted.intersect(r).center().y, c))
        })
        .collect();
    by_y.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut acc = 0.0;
    let cut = by_y
        .iter()
        .find(|&&(_, c)| {
            acc += c;
            acc >= budget
        })
        .map_or(screen.min.y, |&(y, _)| (y * ppp).round() / ppp);
    let above = |r: &Rect| Rect::from_min_max(r.min, pos2(r.max.x, r.max.y.min(cut)));
    let below = |r: &Rect| Rect::from_min_max(pos2(r.min.x, r.min.y.max(cut)), r.max);
    let later: Vec<Rect> = new.iter().map(below).filter(|r| r.is_positive()).collect();
    let now: Vec<Rect> = overdue.iter().copied().chain(new.iter().map(above)).filter(|r| r.is_positive()).collect();
    if later.is_empty() || now.is_empty() {
        return (merge(new.iter().chain(overdue).copied().collect(), ppp, screen), Vec::new());
    }
    // kept apart: merging them again could give back the whole window
    let now_area: f32 = now.iter().map(Rect::area).sum();
    let now = if now_area > FULL_REDRAW_SHARE * screen.area() { vec![screen] } else { now };
    (now, later)
}

/// Splits the window `screen` into columns at the side edges of its tall clip rectangles (the
/// docked panels and the 3D view: clips at least half the window high), each column at most
/// half the window wide where the edges allow, and shares them out over two or three frames
/// (one part per [`FRAME_PART_US`] of work), the costliest part as light as the columns allow.
/// Every column that reaches into `overdue` (what the last frame left for this one) is drawn
/// now, every one that reaches into `soon` (left for the next) by the next frame. A window with
/// no such edge is not split (all now).
pub fn spread_columns(screen: Rect, shapes: &[ShapeCost], ppp: f32, overdue: &[Rect], soon: &[Rect]) -> Spread {
    let (x0, x1) = (screen.min.x, screen.max.x);
    let mut cuts: Vec<f32> = shapes
        .iter()
        .map(|s| s.clip)
        .filter(|c| c.height() >= 0.5 * screen.height())
        .flat_map(|c| [c.min.x, c.max.x])
        .map(|x| (x * ppp).round() / ppp)
        .filter(|&x| x > x0 + 1.0 && x < x1 - 1.0)
        .collect();
    cuts.sort_by(f32::total_cmp);
    cuts.dedup();
    let mut columns = Vec::new();
    let mut start = x0;
    while start < x1 {
        let reach = start + 0.5 * screen.width();
        let end = cuts
            .iter()
            .copied()
            .rfind(|&c| c > start && c <= reach)
            .or_else(|| cuts.iter().copied().find(|&c| c > start))
            .unwrap_or(x1);
        columns.push(Rect::from_x_y_ranges(start..=end, screen.y_range()));
        start = end;
    }
    if columns.len() < 2 || columns.len() > MAX_SPREAD_COLUMNS {
        return Spread::at_once(vec![screen]);
    }
    let cost: Vec<f32> = columns.iter().map(|&c| self::cost(shapes, &[c], ppp)).collect();
    let total: f32 = cost.iter().sum();
    let parts = ((total / FRAME_PART_US).ceil() as usize).clamp(2, MAX_SPREAD_FRAMES).min(columns.len());
    let reaches = |k: usize, rects: &[Rect]| rects.iter().any(|r| columns[k].intersect(*r).is_positive());
    // the latest part each column may go to: now for what waited, the next frame for what
    // waits for it
    let latest: Vec<usize> = (0..columns.len())
        .map(|k| {
            if reaches(k, overdue) {
                0
            } else if reaches(k, soon) {
                1
            } else {
                parts - 1
            }
        })
        .collect();
    // every share-out of the columns (at most 3^8), the one whose costliest part is lightest
    let mut best: Option<(f32, Vec<usize>)> = None;
    let mut part_of = vec![0usize; columns.len()];
    for code in 0..parts.pow(columns.len() as u32) {
        let mut c = code;
        for p in part_of.iter_mut() {
            *p = c % parts;
            c /= parts;
        }
        if part_of.iter().zip(&latest).any(|(p, l)| p > l) || !part_of.contains(&0) {
            continue;
        }
        let mut load = [0.0f32; MAX_SPREAD_FRAMES];
        for (k, &p) in part_of.iter().enumerate() {
            load[p] += cost[k];
        }
        let heaviest = load.iter().copied().fold(0.0, f32::max);
        if best.as_ref().is_none_or(|(h, _)| heaviest < *h) {
            best = Some((heaviest, part_of.clone()));
        }
    }
    let Some((_, part_of)) = best else {
        return Spread::at_once(vec![screen]);
    };
    let mut spread = Spread::default();
    for (c, p) in columns.into_iter().zip(part_of) {
        match p {
            0 => spread.now.push(c),
            1 => spread.next.push(c),
            _ => spread.after.push(c),
        }
    }
    if spread.next.is_empty() {
        spread.next = std::mem::take(&mut spread.after);
    }
    if spread.next.is_empty() { Spread::at_once(vec![screen]) } else { spread }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::vec2;

    fn screen() -> Rect {
        Rect::from_min_size(egui::Pos2::ZERO, vec2(1280.0, 800.0))
    }

    /// A shape with `triangles` over `painted`, clipped to `clip`, filling its area or not.
    fn shape(clip: Rect, painted: Rect, triangles: f32, fills: bool) -> ShapeCost {
        ShapeCost { clip, painted, triangles, fills }
    }

    /// The left column, the 3D view, the right column (text: triangles, no fill), `scale` times
    /// the triangles; a plot's short clip is no edge; the screen-wide menu bar neither.
    fn window_columns(scale: f32) -> Vec<ShapeCost> {
        let screen = screen();
        let tall = |x0: f32, x1: f32| Rect::from_min_max(pos2(x0, 24.0), pos2(x1, 776.0));
        let plot = Rect::from_min_max(pos2(400.0, 500.0), pos2(700.0, 700.0));
        vec![
            shape(tall(0.0, 350.0), tall(0.0, 350.0), 4000.0 * scale, false),
            shape(tall(350.0, 960.0), tall(350.0, 960.0), 1500.0 * scale, false),
            shape(plot, plot, 500.0 * scale, false),
            shape(tall(960.0, 1280.0), tall(960.0, 1280.0), 4000.0 * scale, false),
            shape(screen, Rect::from_min_max(pos2(0.0, 0.0), pos2(1280.0, 24.0)), 100.0, false),
        ]
    }

    fn xs(v: &[Rect]) -> Vec<(f32, f32)> {
        v.iter().map(|r| (r.min.x, r.max.x)).collect()
    }

    const LEFT: (f32, f32) = (0.0, 350.0);
    const MIDDLE: (f32, f32) = (350.0, 960.0);
    const RIGHT: (f32, f32) = (960.0, 1280.0);

    #[test]
    fn a_window_wide_change_is_spread_over_two_frames_by_whole_columns_of_about_half_the_work() {
        let screen = screen();
        let shapes = window_columns(0.5);
        assert!(cost(&shapes, &[screen], 1.0) <= 2.0 * FRAME_PART_US, "two parts' work");
        let s = plan(screen, || shapes.clone(), 1.0, vec![screen], &[], &[]);
        // the text-heavy columns go to different frames: 40 / 61 of the work, not 80 / 21
        assert_eq!(s.now.len() + s.next.len(), 3);
        assert!(s.after.is_empty(), "{s:?}");
        assert!(xs(&s.now).contains(&LEFT) != xs(&s.now).contains(&RIGHT), "{s:?}");
        let area: f32 = s.now.iter().chain(&s.next).map(Rect::area).sum();
        assert_eq!(area, screen.area(), "the columns cover the window once");
        assert!(s.now.iter().chain(&s.next).all(|r| r.y_range() == screen.y_range()));
        // the next frame changing as much again: what waited is drawn first
        let again = plan(screen, || shapes.clone(), 1.0, vec![screen], &s.next, &[]);
        assert!(xs(&s.next).iter().all(|c| xs(&again.now).contains(c)), "{s:?} then {again:?}");
        // no edge to cut at: the window is drawn at once
        let one = [shape(screen, screen, 1.0, false)];
        assert_eq!(plan(screen, || one.to_vec(), 1.0, vec![screen], &[], &[]), Spread::at_once(vec![screen]));
    }

    #[test]
    fn a_window_wide_change_of_much_work_is_spread_over_three_frames_and_nothing_waits_longer() {
        let screen = screen();
        let shapes = window_columns(1.0);
        assert!(cost(&shapes, &[screen], 1.0) > 2.0 * FRAME_PART_US, "more than two parts' work");
        let s = plan(screen, || shapes.clone(), 1.0, vec![screen], &[], &[]);
        // a column a frame, each once
        assert_eq!((s.now.len(), s.next.len(), s.after.len()), (1, 1, 1), "{s:?}");
        let mut all = xs(&s.now);
        all.extend(xs(&s.next));
        all.extend(xs(&s.after));
        all.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert_eq!(all, vec![LEFT, MIDDLE, RIGHT]);
        // nothing changes: what waited for this frame now, what waits for the next after it
        let second = plan(screen, || shapes.clone(), 1.0, Vec::new(), &s.next, &s.after);
        assert_eq!((second.now.clone(), second.next.clone()), (s.next.clone(), s.after.clone()), "{second:?}");
        let third = plan(screen, || shapes.clone(), 1.0, Vec::new(), &second.next, &second.after);
        assert_eq!(third, Spread::at_once(s.after.clone()));
        // the window resized again meanwhile: the column left for this frame is drawn now and
        // the one left for the next by then, however the rest is shared out
        let resized = plan(screen, || shapes.clone(), 1.0, vec![screen], &s.next, &s.after);
        assert!(xs(&resized.now).contains(&xs(&s.next)[0]), "{resized:?}");
        let by_next: Vec<(f32, f32)> = xs(&resized.now).into_iter().chain(xs(&resized.next)).collect();
        assert!(by_next.contains(&xs(&s.after)[0]), "{resized:?}");
        // the costliest part is no heavier than one text-heavy column and the menu bar
        let heaviest = [&resized.now, &resized.next, &resized.after].map(|p| cost(&shapes, p, 1.0));
        assert!(heaviest.iter().all(|&c| c <= 20_500.0), "{heaviest:?}");
    }

    /// The point table appearing over the panels: a 640 × 360 window of text fields and 6 500
    /// triangles, as measured.
    fn table_window() -> (Rect, Vec<ShapeCost>) {
        let window = Rect::from_min_size(pos2(16.0, 16.0), vec2(640.0, 360.0));
        let mut shapes = vec![shape(window, window, 40.0, true)];
        for row in 0..12 {
            for col in 0..8 {
                let cell = Rect::from_min_size(
                    pos2(window.min.x + 10.0 + 78.0 * col as f32, window.min.y + 40.0 + 26.0 * row as f32),
                    vec2(70.0, 22.0),
                );
                shapes.push(shape(cell, cell, 10.0, true));
                shapes.push(shape(cell, cell.shrink(4.0), 56.0, false));
            }
        }
        (window, shapes)
    }

    #[test]
    fn a_costly_window_appearing_is_drawn_top_band_now_and_bottom_band_next_frame() {
        let (window, shapes) = table_window();
        let total = cost(&shapes, &[window], 1.0);
        assert!(total > SPREAD_ABOVE_US, "the table costs {total} µs");
        let Spread { now, next: later, after } = plan(screen(), || shapes.clone(), 1.0, vec![window], &[], &[]);
        assert!(!later.is_empty(), "spread: {now:?}");
        assert!(after.is_empty());
        // two bands that together are the window, the top one now
        let (top, bottom) = (now[0], later[0]);
        assert_eq!((now.len(), later.len()), (1, 1));
        assert_eq!(top.min, window.min);
        assert_eq!(bottom.max, window.max);
        assert_eq!(top.max.y, bottom.min.y);
        assert_eq!((top.x_range(), bottom.x_range()), (window.x_range(), window.x_range()));
        // each about half of the work
        let (a, b) = (cost(&shapes, &now, 1.0), cost(&shapes, &later, 1.0));
        assert!((a - b).abs() < 0.25 * total, "{a} / {b} of {total} µs");
        // the next frame draws what waited, even when nothing else changed
        let s = plan(screen(), || shapes.clone(), 1.0, Vec::new(), &later, &[]);
        assert_eq!(s, Spread::at_once(later.clone()));
        // ... and with the same change again, what waited first and the rest balanced
        let Spread { now: next, next: after, .. } = plan(screen(), || shapes.clone(), 1.0, vec![window], &later, &[]);
        assert!(next.contains(&bottom), "{next:?}");
        assert!(!after.is_empty() && after.iter().all(|r| window.contains_rect(*r)), "{after:?}");
    }

    #[test]
    fn a_cheap_change_or_a_small_one_is_drawn_at_once() {
        let (window, shapes) = table_window();
        // a few labels over the same window: well under the threshold
        let few: Vec<ShapeCost> = shapes.iter().take(9).copied().collect();
        assert_eq!(plan(screen(), || few.clone(), 1.0, vec![window], &[], &[]), Spread::at_once(vec![window]));
        // one cell of the table changing
        let cell = shapes[1].painted;
        assert_eq!(plan(screen(), || shapes.clone(), 1.0, vec![cell], &[], &[]), Spread::at_once(vec![cell]));
        // ... and what an earlier frame left for the next one keeps waiting for it
        let left = Rect::from_min_size(pos2(900.0, 0.0), vec2(380.0, 800.0));
        let s = plan(screen(), || shapes.clone(), 1.0, vec![cell], &[], &[left]);
        assert_eq!((s.now, s.next, s.after), (vec![cell], vec![left], Vec::new()));
    }

    #[test]
    fn text_costs_its_glyphs_and_a_fill_its_pixels() {
        let r = Rect::from_min_size(egui::Pos2::ZERO, vec2(100.0, 100.0));
        let fill = shape(r, r, 10.0, true);
        let text = shape(r, r, 10.0, false);
        assert_eq!(text.cost_within(r, 1.0), 10.0 * US_PER_TRIANGLE);
        assert_eq!(fill.cost_within(r, 1.0), 10.0 * US_PER_TRIANGLE + 10_000.0 * US_PER_PX);
        // half of it: half the triangles and half the pixels; twice the pixels per point: four
        // times the pixels
        let half = Rect::from_min_size(egui::Pos2::ZERO, vec2(50.0, 100.0));
        assert_eq!(fill.cost_within(half, 1.0), 5.0 * US_PER_TRIANGLE + 5_000.0 * US_PER_PX);
        assert_eq!(fill.cost_within(r, 2.0), 10.0 * US_PER_TRIANGLE + 40_000.0 * US_PER_PX);
        let mut galley_shape = egui::Shape::Noop;
        let ctx = egui::Context::default();
        let _frame = ctx.run_ui(egui::RawInput::default(), |ui| {
            let g =
                ui.painter().layout_no_wrap("twelve glyph".into(), egui::FontId::monospace(12.0), egui::Color32::WHITE);
            galley_shape = egui::Shape::galley(egui::Pos2::ZERO, g, egui::Color32::WHITE);
        });
        let clipped = ClippedShape {
            clip_rect: Rect::EVERYTHING,
            shape: galley_shape,
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        };
        let c = ShapeCost::of(&clipped);
        assert!(!c.fills);
        // glyphs of the 11 visible characters and the space (egui counts it), two triangles each
        assert!((22.0..=24.0).contains(&c.triangles), "{c:?}");
    }
}

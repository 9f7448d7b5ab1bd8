//! Which parts of the window changed between two egui frames: a shape-by-shape comparison of
//! the frames' clipped shapes, turned into a few pixel-aligned rectangles to redraw.

use eframe::egui;
use egui::epaint::{ClippedShape, Shape};
use egui::{Pos2, Rect};

use super::callback_damage::{CallbackDamage, hinted_change};

/// At most this many rectangles are redrawn per frame; more are merged (smallest growth first).
/// Few rectangles would merge far-apart changes (a plot's cursor and the 3D view) into one
/// large area; each rectangle costs only the triangles that reach into it.
pub const MAX_DIRTY_RECTS: usize = 24;

/// More separate rectangles than this redraw the whole window (the merge is quadratic).
const MAX_SEPARATE_RECTS: usize = 96;

/// When the rectangles cover more than this share of the window, the whole window is redrawn
/// as one rectangle (cheaper than drawing the meshes under several overlapping ones).
pub const FULL_REDRAW_SHARE: f32 = 0.6;

/// Margin around each changed shape, points: rounding of the tessellator and text that ends a
/// little outside its galley.
const MARGIN_PT: f32 = 2.0;

/// Whether two shapes paint the same pixels. Texts compare their galleys by pointer first
/// (egui caches laid-out text, so an unchanged label keeps its galley).
fn same_shape(a: &ClippedShape, b: &ClippedShape) -> bool {
    if a.clip_rect != b.clip_rect || a.transform_after_tessellation != b.transform_after_tessellation {
        return false;
    }
    match (&a.shape, &b.shape) {
        (Shape::Text(x), Shape::Text(y)) => {
            x.pos == y.pos
                && x.underline == y.underline
                && x.fallback_color == y.fallback_color
                && x.override_text_color == y.override_text_color
                && x.opacity_factor == y.opacity_factor
                && x.angle == y.angle
                && (std::sync::Arc::ptr_eq(&x.galley, &y.galley) || x.galley == y.galley)
        }
        (x, y) => x == y,
    }
}

/// The screen area a shape paints, points (clipped; empty when nothing shows).
fn painted_rect(s: &ClippedShape) -> Rect {
    let mut r = s.shape.visual_bounding_rect();
    if !r.is_finite() || r.is_negative() {
        return Rect::NOTHING;
    }
    if s.transform_after_tessellation != egui::emath::TSTransform::IDENTITY {
        r = s.transform_after_tessellation * r;
    }
    r.expand(MARGIN_PT).intersect(s.clip_rect)
}

/// How far ahead [`changed_rects`] looks for the next matching pair of shapes after a mismatch.
const RESYNC_LOOKAHEAD: usize = 16;

/// Rectangles (points) covering every pixel that differs between a frame of `old` shapes and
/// one of `new` shapes. Shapes are compared in paint order: after the common head and tail, the
/// two lists are walked side by side, and after a mismatch the walk resynchronises on the
/// nearest pair of equal shapes within [`RESYNC_LOOKAHEAD`] of both (shapes inserted, removed or
/// replaced there count as changed). A label that appears in one panel therefore does not dirty
/// everything painted after it. A paint callback that replaces the last one dirties only what
/// its owner's hint says (`hints`, see [`CallbackDamage`]), wherever the walk meets the pair.
pub fn changed_rects(old: &[ClippedShape], new: &[ClippedShape], hints: &[CallbackDamage]) -> Vec<Rect> {
    let head = old.iter().zip(new).take_while(|(a, b)| same_shape(a, b)).count();
    let (old_rest, new_rest) = (&old[head..], &new[head..]);
    let tail = old_rest.iter().rev().zip(new_rest.iter().rev()).take_while(|(a, b)| same_shape(a, b)).count();
    let old_mid = &old_rest[..old_rest.len() - tail];
    let new_mid = &new_rest[..new_rest.len() - tail];
    // the hinted pairs of callbacks: (index in old_mid, index in new_mid, what changed)
    let mut hinted: Vec<(usize, usize, Rect)> = Vec::new();
    if !hints.is_empty() {
        let callbacks = |v: &[ClippedShape]| -> Vec<usize> {
            (0..v.len()).filter(|&k| matches!(v[k].shape, Shape::Callback(_))).collect()
        };
        let new_callbacks = callbacks(new_mid);
        for oi in callbacks(old_mid) {
            for &nj in &new_callbacks {
                if let Some(r) = hinted_change(&old_mid[oi], &new_mid[nj], hints) {
                    hinted.push((oi, nj, r));
                }
            }
        }
    }
    let mut rects = Vec::new();
    let mut push = |s: &ClippedShape, hint: Option<Rect>| {
        let r = hint.unwrap_or_else(|| painted_rect(s));
        if r.is_positive() {
            rects.push(r);
        }
    };
    let old_hint = |k: usize| hinted.iter().find(|h| h.0 == k).map(|h| h.2);
    let new_hint = |k: usize| hinted.iter().find(|h| h.1 == k).map(|h| h.2);
    let mut push_ranges = |old_range: std::ops::Range<usize>, new_range: std::ops::Range<usize>| {
        for k in old_range {
            push(&old_mid[k], old_hint(k));
        }
        for k in new_range {
            push(&new_mid[k], new_hint(k));
        }
    };
    let (mut i, mut j) = (0, 0);
    while i < old_mid.len() && j < new_mid.len() {
        if same_shape(&old_mid[i], &new_mid[j]) {
            i += 1;
            j += 1;
            continue;
        }
        if hinted.iter().any(|h| (h.0, h.1) == (i, j)) {
            push_ranges(i..i + 1, j..j + 1);
            i += 1;
            j += 1;
            continue;
        }
        let (ni, nj) = resync(old_mid, new_mid, i, j).unwrap_or((i + 1, j + 1));
        push_ranges(i..ni, j..nj);
        (i, j) = (ni, nj);
    }
    push_ranges(i..old_mid.len(), j..new_mid.len());
    rects
}

/// The nearest `(i', j')` past a mismatch at `(i, j)`, by the larger skip first, where the
/// shapes are equal again.
fn resync(old: &[ClippedShape], new: &[ClippedShape], i: usize, j: usize) -> Option<(usize, usize)> {
    for d in 1..=RESYNC_LOOKAHEAD {
        for e in 0..=d {
            for (oi, nj) in [(i + e, j + d), (i + d, j + e)] {
                if let (Some(a), Some(b)) = (old.get(oi), new.get(nj))
                    && same_shape(a, b)
                {
                    return Some((oi, nj));
                }
            }
        }
    }
    None
}

/// Snaps `r` (points) outward to whole pixels and inside `screen` (points).
fn snap(r: Rect, ppp: f32, screen: Rect) -> Rect {
    let px = |v: f32, up: bool| if up { (v * ppp).ceil() / ppp } else { (v * ppp).floor() / ppp };
    Rect::from_min_max(
        Pos2::new(px(r.min.x, false), px(r.min.y, false)),
        Pos2::new(px(r.max.x, true), px(r.max.y, true)),
    )
    .intersect(screen)
}

/// Merges `rects` into at most [`MAX_DIRTY_RECTS`] pixel-aligned rectangles inside `screen`
/// (the whole screen past [`MAX_SEPARATE_RECTS`]):
/// overlapping ones first, then the pair whose union grows least. Covering more than
/// [`FULL_REDRAW_SHARE`] of the screen gives the whole screen.
pub fn merge(rects: Vec<Rect>, ppp: f32, screen: Rect) -> Vec<Rect> {
    let mut out: Vec<Rect> = Vec::new();
    for r in rects.into_iter().map(|r| snap(r, ppp, screen)).filter(|r| r.is_positive()) {
        out.push(r);
        // fold every rectangle the newcomer touches into it, repeatedly
        while let Some(last) = out.pop() {
            match out.iter().position(|o| o.intersects(last)) {
                Some(i) => {
                    let o = out.swap_remove(i);
                    out.push(o.union(last));
                }
                None => {
                    out.push(last);
                    break;
                }
            }
        }
    }
    if out.len() > MAX_SEPARATE_RECTS {
        return vec![screen];
    }
    while out.len() > MAX_DIRTY_RECTS {
        let mut best = (0, 1, f32::INFINITY);
        for i in 0..out.len() {
            for j in i + 1..out.len() {
                let grow = out[i].union(out[j]).area() - out[i].area() - out[j].area();
                if grow < best.2 {
                    best = (i, j, grow);
                }
            }
        }
        let b = out.swap_remove(best.1);
        let a = out.swap_remove(best.0);
        out.push(a.union(b));
    }
    let area: f32 = out.iter().map(Rect::area).sum();
    if area > FULL_REDRAW_SHARE * screen.area() {
        return vec![screen];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::epaint::{CornerRadius, RectShape, Stroke, StrokeKind};
    use egui::{Color32, pos2, vec2};

    fn rect_shape(x: f32, y: f32, color: Color32) -> ClippedShape {
        let r = Rect::from_min_size(pos2(x, y), vec2(10.0, 10.0));
        ClippedShape {
            clip_rect: Rect::from_min_size(Pos2::ZERO, vec2(1000.0, 1000.0)),
            shape: Shape::Rect(RectShape::new(r, CornerRadius::ZERO, color, Stroke::NONE, StrokeKind::Inside)),
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        }
    }

    fn screen() -> Rect {
        Rect::from_min_size(Pos2::ZERO, vec2(1000.0, 1000.0))
    }

    #[test]
    fn identical_frames_have_nothing_to_redraw() {
        let a = vec![rect_shape(0.0, 0.0, Color32::RED), rect_shape(50.0, 50.0, Color32::BLUE)];
        assert!(changed_rects(&a, &a.clone(), &[]).is_empty());
    }

    #[test]
    fn a_recoloured_shape_dirties_only_its_own_area() {
        let a = vec![rect_shape(0.0, 0.0, Color32::RED), rect_shape(500.0, 500.0, Color32::BLUE)];
        let mut b = a.clone();
        b[1] = rect_shape(500.0, 500.0, Color32::GREEN);
        let rects = merge(changed_rects(&a, &b, &[]), 1.0, screen());
        assert_eq!(rects.len(), 1);
        assert!(rects[0].contains_rect(Rect::from_min_size(pos2(500.0, 500.0), vec2(10.0, 10.0))));
        assert!(!rects[0].contains(pos2(5.0, 5.0)), "{rects:?}");
    }

    #[test]
    fn a_moved_shape_dirties_where_it_was_and_where_it_is() {
        let a = vec![rect_shape(100.0, 100.0, Color32::RED)];
        let b = vec![rect_shape(700.0, 100.0, Color32::RED)];
        let rects = merge(changed_rects(&a, &b, &[]), 1.0, screen());
        assert_eq!(rects.len(), 2, "{rects:?}");
        assert!(rects.iter().any(|r| r.contains(pos2(105.0, 105.0))));
        assert!(rects.iter().any(|r| r.contains(pos2(705.0, 105.0))));
    }

    #[test]
    fn an_inserted_shape_dirties_only_the_insertion_when_head_and_tail_match() {
        let a = vec![rect_shape(0.0, 0.0, Color32::RED), rect_shape(900.0, 900.0, Color32::BLUE)];
        let b = vec![a[0].clone(), rect_shape(400.0, 400.0, Color32::GREEN), a[1].clone()];
        let rects = merge(changed_rects(&a, &b, &[]), 1.0, screen());
        assert_eq!(rects.len(), 1);
        assert!(rects[0].contains(pos2(405.0, 405.0)) && !rects[0].contains(pos2(905.0, 905.0)));
    }

    #[test]
    fn shapes_inserted_early_do_not_dirty_the_unchanged_shapes_after_them() {
        let old: Vec<_> = (0..20).map(|i| rect_shape(i as f32 * 45.0, 0.0, Color32::RED)).collect();
        let mut new = old.clone();
        // two new shapes near the start, one shape recoloured near the end
        new.insert(2, rect_shape(100.0, 500.0, Color32::GREEN));
        new.insert(3, rect_shape(150.0, 500.0, Color32::GREEN));
        new[19] = rect_shape(17.0 * 45.0, 0.0, Color32::BLUE);
        let rects = merge(changed_rects(&old, &new, &[]), 1.0, screen());
        assert!(rects.iter().any(|r| r.contains(pos2(105.0, 505.0))));
        assert!(rects.iter().any(|r| r.contains(pos2(17.0 * 45.0 + 5.0, 5.0))));
        for k in [5usize, 10, 15] {
            let p = pos2(k as f32 * 45.0 + 5.0, 5.0);
            assert!(!rects.iter().any(|r| r.contains(p)), "unchanged shape {k} dirtied: {rects:?}");
        }
    }

    #[test]
    fn many_scattered_changes_merge_to_a_few_rectangles_and_large_ones_to_the_screen() {
        let a: Vec<_> = (0..20).map(|i| rect_shape(i as f32 * 45.0, i as f32 * 45.0, Color32::RED)).collect();
        let b: Vec<_> = (0..20).map(|i| rect_shape(i as f32 * 45.0, i as f32 * 45.0, Color32::BLUE)).collect();
        let rects = merge(changed_rects(&a, &b, &[]), 1.0, screen());
        assert!(rects.len() <= MAX_DIRTY_RECTS);
        for s in &b {
            let r = s.shape.visual_bounding_rect();
            assert!(rects.iter().any(|d| d.contains_rect(r)), "{r:?} not covered by {rects:?}");
        }
        let big = merge(vec![Rect::from_min_size(Pos2::ZERO, vec2(900.0, 900.0))], 1.0, screen());
        assert_eq!(big, vec![screen()]);
    }

    #[test]
    fn rectangles_snap_outward_to_whole_pixels() {
        let rects = merge(vec![Rect::from_min_max(pos2(10.3, 10.3), pos2(20.2, 20.2))], 1.5, screen());
        let r = rects[0];
        for v in [r.min.x, r.min.y, r.max.x, r.max.y] {
            assert!(((v * 1.5) - (v * 1.5).round()).abs() < 1e-4, "{r:?}");
        }
        assert!(r.contains_rect(Rect::from_min_max(pos2(10.3, 10.3), pos2(20.2, 20.2))));
    }
}

//! Hints from the owners of paint callbacks: a callback that replaces the last one changed only
//! inside a known rectangle (the 3D view while only the arm moves, see
//! [`crate::viewport::view_damage`]). Without a hint, a new callback dirties all of its
//! rectangle.

use std::sync::Arc;

use eframe::egui;
use egui::epaint::{ClippedShape, Shape};
use egui::{Id, PaintCallback, Rect};

/// The data key of this frame's hints in the egui context.
const HINTS_KEY: &str = "parol6-callback-damage";
/// The data key of the mark that retained painting is installed (it takes the hints).
const WANTED_KEY: &str = "parol6-callback-damage-wanted";
/// Hints kept at most (they pile up when nothing takes them: no retained painting).
const MAX_HINTS: usize = 8;

/// Callback `new` paints the same pixels as callback `old` outside `dirty` (points).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CallbackDamage {
    old: usize,
    new: usize,
    dirty: Rect,
}

/// The identity of a callback: its shared object (a clone is the same callback).
fn identity(c: &PaintCallback) -> usize {
    Arc::as_ptr(&c.callback) as *const () as usize
}

impl CallbackDamage {
    /// `new`, the successor of `old`, changed only inside `dirty`. The owner keeps `old` alive
    /// until then, so its identity cannot be taken by another callback.
    pub fn new(old: &PaintCallback, new: &PaintCallback, dirty: Rect) -> Self {
        Self { old: identity(old), new: identity(new), dirty }
    }

    /// Whether anything takes the hints on `ctx` (retained painting is installed): without it
    /// an owner need not work them out.
    pub fn wanted(ctx: &egui::Context) -> bool {
        ctx.data(|d| d.get_temp::<bool>(Id::unique(WANTED_KEY))).unwrap_or(false)
    }

    /// Marks `ctx` as taking hints.
    pub(super) fn mark_wanted(ctx: &egui::Context) {
        ctx.data_mut(|d| d.insert_temp(Id::unique(WANTED_KEY), true));
    }

    /// Tells retained painting about this frame's `hint`.
    pub fn publish(self, ctx: &egui::Context) {
        ctx.data_mut(|d| {
            let hints = d.get_temp_mut_or_default::<Vec<CallbackDamage>>(Id::unique(HINTS_KEY));
            if hints.len() >= MAX_HINTS {
                hints.remove(0);
            }
            hints.push(self);
        });
    }

    /// The hints published since the last call.
    pub(super) fn take(ctx: &egui::Context) -> Vec<CallbackDamage> {
        ctx.data_mut(|d| d.remove_temp::<Vec<CallbackDamage>>(Id::unique(HINTS_KEY))).unwrap_or_default()
    }
}

/// Where `new` changed from `old` when both are the same-sized paint callback and a hint tells
/// (clipped to what they show), else `None`.
pub(super) fn hinted_change(old: &ClippedShape, new: &ClippedShape, hints: &[CallbackDamage]) -> Option<Rect> {
    let (Shape::Callback(a), Shape::Callback(b)) = (&old.shape, &new.shape) else { return None };
    if a.rect != b.rect || old.clip_rect != new.clip_rect {
        return None;
    }
    let h = hints.iter().rev().find(|h| h.old == identity(a) && h.new == identity(b))?;
    Some(h.dirty.intersect(new.clip_rect).intersect(b.rect))
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Nothing;

    fn callback(rect: Rect) -> ClippedShape {
        ClippedShape {
            clip_rect: rect,
            shape: Shape::Callback(PaintCallback { rect, callback: Arc::new(Nothing) }),
            transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
        }
    }

    fn cb(s: &ClippedShape) -> &PaintCallback {
        match &s.shape {
            Shape::Callback(c) => c,
            _ => unreachable!(),
        }
    }

    #[test]
    fn a_hint_applies_only_to_the_pair_it_names() {
        let view = Rect::from_min_size(egui::pos2(10.0, 10.0), egui::vec2(300.0, 200.0));
        let (a, b, c) = (callback(view), callback(view), callback(view));
        let dirty = Rect::from_min_size(egui::pos2(50.0, 50.0), egui::vec2(40.0, 30.0));
        let hints = [CallbackDamage::new(cb(&a), cb(&b), dirty)];
        assert_eq!(hinted_change(&a, &b, &hints), Some(dirty));
        assert_eq!(hinted_change(&a, &c, &hints), None, "another successor");
        assert_eq!(hinted_change(&c, &b, &hints), None, "another predecessor");
        assert_eq!(hinted_change(&b, &a, &hints), None, "backwards");
        // a clone is the same callback
        assert_eq!(hinted_change(&a.clone(), &b.clone(), &hints), Some(dirty));
        // the view moved: no hint holds
        let mut moved = b.clone();
        moved.clip_rect = moved.clip_rect.translate(egui::vec2(1.0, 0.0));
        assert_eq!(hinted_change(&a, &moved, &hints), None);
        // clipped to the view
        let wide = [CallbackDamage::new(cb(&a), cb(&b), Rect::EVERYTHING)];
        assert_eq!(hinted_change(&a, &b, &wide), Some(view));
    }

    #[test]
    fn hints_are_taken_once_and_bounded() {
        let ctx = egui::Context::default();
        assert!(!CallbackDamage::wanted(&ctx));
        CallbackDamage::mark_wanted(&ctx);
        assert!(CallbackDamage::wanted(&ctx));
        let view = Rect::from_min_size(egui::pos2(0.0, 0.0), egui::vec2(10.0, 10.0));
        let (a, b) = (callback(view), callback(view));
        for _ in 0..20 {
            CallbackDamage::new(cb(&a), cb(&b), view).publish(&ctx);
        }
        assert_eq!(CallbackDamage::take(&ctx).len(), MAX_HINTS);
        assert!(CallbackDamage::take(&ctx).is_empty());
    }
}

//! The parts of the window that frame reuse lays out one at a time ([`PanelGroup`]): after a
//! read-out refresh, the frames of a wave ([`WAVE`]) lay out one step each, so the panels'
//! layout and the redraw of what changed in them are spread over a few frames instead of
//! falling into one. A group not laid out in a frame is held in place by a [`stand_in`]: a
//! panel of the same id and size that paints nothing, so the 3D view keeps its rectangle and
//! the groups laid out find the space they had.

use eframe::egui;
use egui::Rect;

/// One docked part of the window, with its own egui panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PanelGroup {
    /// The menu bar.
    Menu,
    /// The status bar (the panels docked at the bottom edge).
    Status,
    /// The left column (joints, program, connection).
    Left,
    /// The right column (TCP, Cartesian jog, target, measurement).
    Right,
    /// The panel under the 3D view (replay timeline, plots, dynamics).
    Lower,
}

impl PanelGroup {
    /// Every group, in the order the layout allocates them.
    pub const ALL: [PanelGroup; 5] =
        [PanelGroup::Menu, PanelGroup::Status, PanelGroup::Left, PanelGroup::Right, PanelGroup::Lower];

    fn bit(self) -> u8 {
        1 << self as u8
    }
}

/// A set of groups.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct GroupSet(u8);

impl GroupSet {
    /// No group.
    pub const EMPTY: GroupSet = GroupSet(0);
    /// Every group.
    pub const ALL: GroupSet = GroupSet(0b1_1111);

    /// The set of `groups`.
    pub const fn of(groups: &[PanelGroup]) -> GroupSet {
        let mut bits = 0;
        let mut i = 0;
        while i < groups.len() {
            bits |= 1 << groups[i] as u8;
            i += 1;
        }
        GroupSet(bits)
    }

    /// `g` is in the set.
    pub fn contains(self, g: PanelGroup) -> bool {
        self.0 & g.bit() != 0
    }

    /// No group in the set.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Some group is in both sets.
    pub fn intersects(self, other: GroupSet) -> bool {
        self.0 & other.0 != 0
    }

    /// The groups of both sets.
    pub fn union(self, other: GroupSet) -> GroupSet {
        GroupSet(self.0 | other.0)
    }

    /// The set without `other`'s groups.
    pub fn without(self, other: GroupSet) -> GroupSet {
        GroupSet(self.0 & !other.0)
    }
}

/// The steps of a wave, in order: the left column (the most to lay out: ~45 % of the panels'
/// layout time with the plots open), then the rest. Two steps, not one per group: at the
/// read-out rate and ~70 frames a second, more steps would make most frames lay out panels.
pub(crate) const WAVE: [GroupSet; 2] = [
    GroupSet::of(&[PanelGroup::Left]),
    GroupSet::of(&[PanelGroup::Right, PanelGroup::Menu, PanelGroup::Status, PanelGroup::Lower]),
];

/// Where each group's panel was (its outer rectangle, points), `None` where it was not shown.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct GroupRects([Option<Rect>; 5]);

impl GroupRects {
    /// Group `g`'s rectangle.
    pub fn get(&self, g: PanelGroup) -> Option<Rect> {
        self.0[g as usize]
    }

    /// Sets group `g`'s rectangle.
    pub fn set(&mut self, g: PanelGroup, rect: Rect) {
        self.0[g as usize] = Some(rect);
    }

    /// The rectangles of the groups of `set` that were shown.
    pub fn of(&self, set: GroupSet) -> impl Iterator<Item = Rect> + '_ {
        PanelGroup::ALL.into_iter().filter(move |g| set.contains(*g)).filter_map(|g| self.get(g))
    }
}

/// A frame that lays out some groups (maybe none) and shows the others as the kept frame drew
/// them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PartialLayout {
    /// The 3D view's rectangle, kept.
    pub central: Rect,
    /// The groups laid out this frame.
    pub lay_out: GroupSet,
    /// Every group's rectangle in the kept frame.
    pub rects: GroupRects,
}

impl PartialLayout {
    /// Whether `g` is laid out in a frame that follows `partial` (`None`: a full frame).
    pub fn lays_out(partial: Option<&PartialLayout>, g: PanelGroup) -> bool {
        partial.is_none_or(|p| p.lay_out.contains(g))
    }

    /// The rectangle a stand-in must hold for `g` in a frame that follows `partial`: `Some`
    /// when `g` is not laid out and was shown.
    pub fn stand_in_rect(partial: Option<&PartialLayout>, g: PanelGroup) -> Option<Rect> {
        partial.filter(|p| !p.lay_out.contains(g)).and_then(|p| p.rects.get(g))
    }
}

/// Shows `panel` as a stand-in of `size` points (its outer width for a side panel, height for a
/// top or bottom one): no frame, no separator line, not resizable, no content. egui allocates
/// the same rectangle for it as for the panel it stands for, and keeps that panel's state.
pub(crate) fn stand_in(ui: &mut egui::Ui, panel: egui::Panel, size: f32) {
    panel.frame(egui::Frame::NONE).show_separator_line(false).resizable(false).exact_size(size).show(ui, |_| {});
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wave_lays_out_every_group_once() {
        for g in PanelGroup::ALL {
            assert_eq!(WAVE.iter().filter(|s| s.contains(g)).count(), 1, "{g:?}");
        }
        let all = WAVE.iter().fold(GroupSet::ALL, |left, s| left.without(*s));
        assert!(all.is_empty());
        assert!(WAVE.iter().all(|s| !s.is_empty()));
    }

    #[test]
    fn a_stand_in_holds_only_the_groups_not_laid_out() {
        let mut rects = GroupRects::default();
        let left = Rect::from_min_max(egui::pos2(0.0, 20.0), egui::pos2(350.0, 780.0));
        rects.set(PanelGroup::Left, left);
        let p = PartialLayout { central: Rect::ZERO, lay_out: WAVE[1], rects };
        assert_eq!(PartialLayout::stand_in_rect(Some(&p), PanelGroup::Left), Some(left));
        assert_eq!(PartialLayout::stand_in_rect(Some(&p), PanelGroup::Right), None, "not shown");
        assert_eq!(PartialLayout::stand_in_rect(Some(&p), PanelGroup::Lower), None, "laid out");
        assert_eq!(PartialLayout::stand_in_rect(None, PanelGroup::Left), None, "a full frame");
        assert!(PartialLayout::lays_out(None, PanelGroup::Left));
        assert!(PartialLayout::lays_out(Some(&p), PanelGroup::Lower));
        assert!(!PartialLayout::lays_out(Some(&p), PanelGroup::Left));
        assert_eq!(rects.of(GroupSet::ALL).collect::<Vec<_>>(), [left]);
    }
}

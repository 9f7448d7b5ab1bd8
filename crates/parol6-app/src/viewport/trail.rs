//! The TCP trail: a fixed-size ring buffer of points. The GPU copy is a vertex buffer of the
//! same slots plus one bridge slot (a copy of slot 0, so the wrapped strip stays connected);
//! each frame only the newly written slots are uploaded, and the fading is computed in the
//! vertex shader from the slot's age. Every point has its colour (linear RGB, a second vertex
//! buffer of the same slots; [`super::trail_color`]).

/// Default number of trail points.
pub const DEFAULT_TRAIL_CAPACITY: usize = 2000;

/// Smallest TCP move that adds a point, m (a standing arm does not flood the trail).
pub const TRAIL_MIN_STEP_M: f32 = 0.0005;

/// Ring buffer of TCP positions with tracking of what the GPU has not seen yet.
#[derive(Debug, Clone)]
pub struct Trail {
    points_m: Vec<[f32; 3]>,
    /// Linear RGB of each slot.
    colors: Vec<[f32; 3]>,
    /// Slot of the newest point (valid when `len > 0`).
    newest: usize,
    len: usize,
    /// Number of newest points not uploaded yet (≤ capacity).
    pending: usize,
}

impl Trail {
    /// An empty trail of `capacity` points (at least 2).
    pub fn new(capacity: usize) -> Self {
        let capacity = capacity.max(2);
        Self {
            points_m: vec![[0.0; 3]; capacity],
            colors: vec![[1.0; 3]; capacity],
            newest: capacity - 1,
            len: 0,
            pending: 0,
        }
    }

    /// Maximum number of points.
    pub fn capacity(&self) -> usize {
        self.points_m.len()
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there is no point.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Slot of the newest point.
    pub fn newest_slot(&self) -> usize {
        self.newest
    }

    /// Removes every point.
    pub fn clear(&mut self) {
        self.len = 0;
        self.pending = 0;
        self.newest = self.capacity() - 1;
    }

    /// The newest point, if any.
    pub fn last(&self) -> Option<[f32; 3]> {
        (self.len > 0).then(|| self.points_m[self.newest])
    }

    /// Adds `p_m` in colour `rgb` (linear) when it is at least [`TRAIL_MIN_STEP_M`] from the
    /// newest point (or the trail is empty); overwrites the oldest point when full. Returns
    /// whether it was added.
    pub fn push(&mut self, p_m: [f32; 3], rgb: [f32; 3]) -> bool {
        if !p_m.iter().all(|v| v.is_finite()) {
            return false;
        }
        if let Some(last) = self.last() {
            let d2: f32 = (0..3).map(|i| (p_m[i] - last[i]).powi(2)).sum();
            if d2 < TRAIL_MIN_STEP_M * TRAIL_MIN_STEP_M {
                return false;
            }
        }
        let cap = self.capacity();
        self.newest = (self.newest + 1) % cap;
        self.points_m[self.newest] = p_m;
        self.colors[self.newest] = rgb;
        self.len = (self.len + 1).min(cap);
        self.pending = (self.pending + 1).min(cap);
        true
    }

    /// Points in slot order (slot `i` of the ring).
    pub fn slots(&self) -> &[[f32; 3]] {
        &self.points_m
    }

    /// Colours in slot order, linear RGB.
    pub fn colors(&self) -> &[[f32; 3]] {
        &self.colors
    }

    /// Slot ranges written since the last call (at most two, because of the wrap), and clears
    /// the pending count. The caller uploads `slots()[range]` to the same offsets, and slot 0
    /// again to the bridge slot `capacity()` when a range starts at 0.
    pub fn take_pending(&mut self) -> [Option<std::ops::Range<usize>>; 2] {
        let n = std::mem::take(&mut self.pending);
        if n == 0 {
            return [None, None];
        }
        let cap = self.capacity();
        let end = self.newest + 1;
        if n <= end { [Some(end - n..end), None] } else { [Some(cap - (n - end)..cap), Some(0..end)] }
    }

    /// Vertex ranges (in the GPU buffer of `capacity() + 1` slots) to draw as line strips,
    /// oldest first: the part after the newest point up to the bridge slot, then the part up
    /// to the newest point.
    pub fn draw_ranges(&self) -> [Option<std::ops::Range<u32>>; 2] {
        let cap = self.capacity();
        if self.len < 2 {
            return [None, None];
        }
        let end = (self.newest + 1) as u32;
        if self.len < cap {
            // Not wrapped yet: slots 0..len hold the points in order.
            return [Some(0..self.len as u32), None];
        }
        let first = (self.newest + 1 < cap).then(|| end..(cap as u32 + 1));
        [first, Some(0..end)]
    }
}

impl Default for Trail {
    fn default() -> Self {
        Self::new(DEFAULT_TRAIL_CAPACITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RED: [f32; 3] = [1.0, 0.0, 0.0];

    fn p(i: usize) -> [f32; 3] {
        [i as f32 * 0.01, 0.0, 0.0]
    }

    #[test]
    fn fills_wraps_and_clears() {
        let mut t = Trail::new(4);
        assert!(t.is_empty());
        assert_eq!(t.draw_ranges(), [None, None]);
        assert!(t.push(p(0), RED));
        assert!(!t.push(p(0), RED), "a point closer than the minimum step is dropped");
        assert!(t.push(p(1), RED));
        assert_eq!(t.take_pending(), [Some(0..2), None]);
        assert_eq!(t.take_pending(), [None, None]);
        assert_eq!(t.draw_ranges(), [Some(0..2), None]);
        for i in 2..6 {
            assert!(t.push(p(i), [i as f32, 0.0, 0.0]));
        }
        assert_eq!(t.len(), 4);
        // Slots: [4, 5, 2, 3], newest = slot 1; pending 4 points = slots 2,3 then 0,1.
        assert_eq!(t.slots()[1], p(5));
        assert_eq!(t.colors()[1], [5.0, 0.0, 0.0], "each point keeps its colour");
        assert_eq!(t.take_pending(), [Some(2..4), Some(0..2)]);
        // Oldest first: slots 2,3 then the bridge (copy of slot 0), then slots 0,1.
        assert_eq!(t.draw_ranges(), [Some(2..5), Some(0..2)]);
        assert!(t.push(p(6), RED));
        assert!(t.push(p(7), RED));
        // newest = slot 3 = cap-1: one plain strip 0..4.
        assert_eq!(t.draw_ranges(), [None, Some(0..4)]);
        t.clear();
        assert_eq!(t.len(), 0);
        assert_eq!(t.draw_ranges(), [None, None]);
        assert!(!t.push([f32::NAN, 0.0, 0.0], RED));
    }
}

//! Decimated plot lines kept from one frame to the next: while the data and the visible
//! window do not change (a replay with the cursor moving, a paused live view), a line is not
//! decimated again.

use std::collections::HashMap;

use parol6_core::telemetry::series::SeriesStore;

/// What a decimated line depends on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct LineKey {
    /// Which store (its address) and its state: sample count and time range bits.
    store: (usize, usize, u64, u64),
    column: usize,
    t0_bits: u64,
    t1_bits: u64,
    columns_px: usize,
}

/// The lines of the last frame and of this one.
#[derive(Debug, Default)]
pub struct DecimationCache {
    last: HashMap<LineKey, Vec<[f64; 2]>>,
    this: HashMap<LineKey, Vec<[f64; 2]>>,
    /// Lines decimated (not found) since the cache was made.
    pub misses: u64,
}

impl DecimationCache {
    /// Starts a frame: lines not asked for during the last frame are dropped.
    pub fn begin_frame(&mut self) {
        self.last = std::mem::take(&mut self.this);
    }

    /// Column `column` of `store` between `t0_s` and `t1_s`, as [`SeriesStore::decimated`]
    /// gives it for `columns_px` columns.
    pub fn line(&mut self, store: &SeriesStore, column: usize, t0_s: f64, t1_s: f64, columns_px: usize) -> &[[f64; 2]] {
        let (a, b) = store.time_range_s().unwrap_or((0.0, 0.0));
        let key = LineKey {
            store: (std::ptr::from_ref(store) as usize, store.len(), a.to_bits(), b.to_bits()),
            column,
            t0_bits: t0_s.to_bits(),
            t1_bits: t1_s.to_bits(),
            columns_px,
        };
        let misses = &mut self.misses;
        let last = &mut self.last;
        self.this.entry(key).or_insert_with(|| {
            last.remove(&key).unwrap_or_else(|| {
                *misses += 1;
                let mut points = Vec::new();
                store.decimated(column, t0_s, t1_s, columns_px, &mut points);
                points
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn store() -> SeriesStore {
        let mut s = SeriesStore::new(1, 600.0);
        let n = s.ids().len();
        for i in 0..1000 {
            s.push_row(i as f64 * 0.01, &vec![(i as f32 * 0.1).sin(); n]);
        }
        s
    }

    #[test]
    fn an_unchanged_line_is_decimated_once_and_equals_a_fresh_decimation() {
        let s = store();
        let mut c = DecimationCache::default();
        let mut fresh = Vec::new();
        s.decimated(0, 0.0, 10.0, 100, &mut fresh);
        for _ in 0..3 {
            c.begin_frame();
            assert_eq!(c.line(&s, 0, 0.0, 10.0, 100), fresh.as_slice());
        }
        assert_eq!(c.misses, 1);
    }

    #[test]
    fn new_samples_a_moved_window_or_another_width_decimate_again() {
        let mut s = store();
        let mut c = DecimationCache::default();
        c.begin_frame();
        c.line(&s, 0, 0.0, 10.0, 100);
        c.begin_frame();
        c.line(&s, 0, 0.0, 10.5, 100);
        c.begin_frame();
        c.line(&s, 0, 0.0, 10.5, 90);
        let n = s.ids().len();
        s.push_row(10.0, &vec![1.0; n]);
        c.begin_frame();
        let mut fresh = Vec::new();
        s.decimated(0, 0.0, 10.5, 90, &mut fresh);
        assert_eq!(c.line(&s, 0, 0.0, 10.5, 90), fresh.as_slice());
        assert_eq!(c.misses, 4);
    }
}

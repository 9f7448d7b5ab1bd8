//! One tier of a [`super::SeriesStore`]: rows kept at the rate they came, as columns with a
//! min/max pyramid and (tracking-error columns) running sums of squares. See the store's docs.

use std::collections::VecDeque;

/// Level of the first pyramid level kept: blocks of 16 samples (the raw values serve below).
/// The pyramid then takes 1 byte per sample and column (2 with blocks of 8: 5 MB more for a
/// ten-minute replay), and a window's edges read at most 15 raw values each.
const FIRST_LEVEL: u32 = 4;
/// The running sum of squares is kept at every this many samples; a window's sum adds at most
/// this many raw values to it (8 bytes per sample and tracking-error column before).
const SQUARES_BLOCK: u64 = 64;

#[derive(Debug, Clone, Default)]
struct Pyramid {
    /// `levels[i]` is level `FIRST_LEVEL + i`; its front entry is block `first_block[i]`.
    levels: Vec<VecDeque<(f32, f32)>>,
    first_block: Vec<u64>,
}

impl Pyramid {
    fn entry(&self, level: u32, block: u64) -> Option<(f32, f32)> {
        let i = usize::try_from(level.checked_sub(FIRST_LEVEL)?).ok()?;
        let at = usize::try_from(block.checked_sub(*self.first_block.get(i)?)?).ok()?;
        self.levels.get(i)?.get(at).copied()
    }

    fn push(&mut self, level: u32, block: u64, mm: (f32, f32)) {
        let i = (level - FIRST_LEVEL) as usize;
        if self.levels.len() <= i {
            self.levels.resize_with(i + 1, VecDeque::new);
            self.first_block.resize(i + 1, 0);
        }
        if self.levels[i].is_empty() {
            self.first_block[i] = block;
        }
        self.levels[i].push_back(mm);
    }

    /// Drops the blocks that end at or before absolute sample `base`.
    fn expire(&mut self, base: u64) {
        for (i, (level, first)) in self.levels.iter_mut().zip(self.first_block.iter_mut()).enumerate() {
            let k = FIRST_LEVEL + i as u32;
            while !level.is_empty() && (*first + 1) << k <= base {
                level.pop_front();
                *first += 1;
            }
        }
    }

    fn clear(&mut self) {
        self.levels.clear();
        self.first_block.clear();
    }

    fn shrink_to_fit(&mut self) {
        self.levels.iter_mut().for_each(VecDeque::shrink_to_fit);
    }
}

pub(super) fn merge(a: (f32, f32), b: (f32, f32)) -> (f32, f32) {
    (a.0.min(b.0), a.1.max(b.1))
}

pub(super) const EMPTY: (f32, f32) = (f32::INFINITY, f32::NEG_INFINITY);

#[derive(Debug, Clone, Default)]
pub(super) struct Column {
    pub(super) values: VecDeque<f32>,
    pyramid: Pyramid,
    /// Sums of squares (tracking error only).
    squares: Option<SquareSums>,
}

/// Running sums of squares of one column: `marks[j]` is the sum over every sample before
/// absolute index `(first_mark + j) · SQUARES_BLOCK`, `total` over every sample pushed.
#[derive(Debug, Clone, Default)]
struct SquareSums {
    marks: VecDeque<f64>,
    first_mark: u64,
    total: f64,
}

fn square(v: f32) -> f64 {
    if v.is_finite() { f64::from(v) * f64::from(v) } else { 0.0 }
}

/// Rows as columns, the samples older than `span_s` dropped (handed to the caller).
#[derive(Debug, Clone)]
pub(super) struct Tier {
    pub(super) times_s: VecDeque<f64>,
    /// Absolute index of `times_s[0]`.
    pub(super) base: u64,
    pub(super) columns: Vec<Column>,
    pub(super) span_s: f64,
}

/// The part of a window one tier holds: samples, min, max, sum of squares.
#[derive(Debug, Clone, Copy)]
pub(super) struct WindowPart {
    pub(super) samples: usize,
    pub(super) min_max: (f32, f32),
    pub(super) sum_of_squares: Option<f64>,
}

impl Tier {
    /// An empty tier of columns (`squares[c]`: keep sums of squares of column `c`) keeping `span_s`.
    pub(super) fn new(squares: &[bool], span_s: f64) -> Self {
        let columns =
            squares.iter().map(|&sq| Column { squares: sq.then(SquareSums::default), ..Column::default() }).collect();
        Self { times_s: VecDeque::new(), base: 0, columns, span_s }
    }

    pub(super) fn len(&self) -> usize {
        self.times_s.len()
    }

    pub(super) fn first_s(&self) -> Option<f64> {
        self.times_s.front().copied()
    }

    pub(super) fn last_s(&self) -> Option<f64> {
        self.times_s.back().copied()
    }

    pub(super) fn clear(&mut self) {
        self.times_s.clear();
        self.base = 0;
        for c in &mut self.columns {
            c.values.clear();
            c.pyramid.clear();
            if let Some(s) = c.squares.as_mut() {
                *s = SquareSums::default();
            }
        }
    }

    pub(super) fn shrink_to_fit(&mut self) {
        self.times_s.shrink_to_fit();
        for col in &mut self.columns {
            col.values.shrink_to_fit();
            col.pyramid.shrink_to_fit();
            if let Some(sq) = col.squares.as_mut() {
                sq.marks.shrink_to_fit();
            }
        }
    }

    /// Appends a row (the caller keeps time order); the rows then older than the span go to
    /// `expired`, oldest first.
    pub(super) fn push_row(&mut self, time_s: f64, row: &[f32], expired: &mut dyn FnMut(f64, &[f32])) {
        let i = self.base + self.times_s.len() as u64;
        self.times_s.push_back(time_s);
        for (c, col) in self.columns.iter_mut().enumerate() {
            let v = row.get(c).copied().unwrap_or(f32::NAN);
            col.values.push_back(v);
            if let Some(sq) = col.squares.as_mut() {
                sq.total += square(v);
                if (i + 1).is_multiple_of(SQUARES_BLOCK) {
                    if sq.marks.is_empty() {
                        sq.first_mark = (i + 1) / SQUARES_BLOCK;
                    }
                    sq.marks.push_back(sq.total);
                }
            }
            let mut k = FIRST_LEVEL;
            while (i + 1).is_multiple_of(1u64 << k) {
                let block = i >> k;
                let mm = if k == FIRST_LEVEL {
                    let from = (block << k).max(self.base);
                    (from..=i)
                        .filter_map(|a| col.values.get((a - self.base) as usize))
                        .fold(EMPTY, |m, &v| merge(m, (v, v)))
                } else {
                    let lo = col.pyramid.entry(k - 1, 2 * block).unwrap_or(EMPTY);
                    let hi = col.pyramid.entry(k - 1, 2 * block + 1).unwrap_or(EMPTY);
                    merge(lo, hi)
                };
                col.pyramid.push(k, block, mm);
                k += 1;
            }
        }
        self.expire(time_s, expired);
    }

    fn expire(&mut self, now_s: f64, expired: &mut dyn FnMut(f64, &[f32])) {
        let oldest = now_s - self.span_s;
        let mut dropped = 0u64;
        let mut row = Vec::with_capacity(self.columns.len());
        while let Some(&t) = self.times_s.front().filter(|&&t| t < oldest) {
            row.clear();
            row.extend(self.columns.iter().map(|c| c.values.get(dropped as usize).copied().unwrap_or(f32::NAN)));
            expired(t, &row);
            self.times_s.pop_front();
            dropped += 1;
        }
        if dropped == 0 {
            return;
        }
        self.base += dropped;
        for col in &mut self.columns {
            for _ in 0..dropped {
                col.values.pop_front();
            }
            if let Some(sq) = col.squares.as_mut() {
                // a mark is needed while a kept sample lies before it
                let needed = self.base.div_ceil(SQUARES_BLOCK);
                while sq.first_mark < needed && sq.marks.pop_front().is_some() {
                    sq.first_mark += 1;
                }
            }
            col.pyramid.expire(self.base);
        }
    }

    /// Hands every row to `out`, oldest first, and keeps none.
    pub(super) fn take_all(&mut self, out: &mut dyn FnMut(f64, &[f32])) {
        let mut row = Vec::with_capacity(self.columns.len());
        for (i, &t) in self.times_s.iter().enumerate() {
            row.clear();
            row.extend(self.columns.iter().map(|c| c.values.get(i).copied().unwrap_or(f32::NAN)));
            out(t, &row);
        }
        self.clear();
    }

    /// Absolute index of the first sample at or after `t_s`.
    fn index_at(&self, t_s: f64) -> u64 {
        self.base + self.times_s.partition_point(|&t| t < t_s) as u64
    }

    pub(super) fn end(&self) -> u64 {
        self.base + self.times_s.len() as u64
    }

    /// The sum of squares of every sample before absolute index `x` (`base ≤ x ≤ end`): the
    /// next mark (or the total) less the kept samples between `x` and it.
    fn sum_of_squares_before(&self, col: &Column, sq: &SquareSums, x: u64) -> Option<f64> {
        let end = self.end();
        if x < self.base || x > end {
            return None;
        }
        let m = x.div_ceil(SQUARES_BLOCK);
        let (upto, sum) = match m.checked_sub(sq.first_mark).and_then(|j| sq.marks.get(usize::try_from(j).ok()?)) {
            Some(&mark) if m * SQUARES_BLOCK <= end => (m * SQUARES_BLOCK, mark),
            _ => (end, sq.total),
        };
        let raw = (x..upto).map(|k| col.values.get((k - self.base) as usize).copied().map_or(0.0, square));
        Some(sum - raw.sum::<f64>())
    }

    /// Min and max of column `col` over absolute samples `[a, b)`, from the pyramid.
    pub(super) fn range_min_max(&self, col: &Column, a: u64, b: u64) -> (f32, f32) {
        let mut mm = EMPTY;
        let mut p = a.max(self.base);
        let b = b.min(self.end());
        let top = FIRST_LEVEL + col.pyramid.levels.len() as u32;
        while p < b {
            let level = (FIRST_LEVEL..top).rev().find(|&k| p.is_multiple_of(1u64 << k) && p + (1u64 << k) <= b);
            match level.and_then(|k| col.pyramid.entry(k, p >> k).map(|e| (k, e))) {
                Some((k, e)) => {
                    mm = merge(mm, e);
                    p += 1u64 << k;
                }
                None => {
                    if let Some(&v) = col.values.get((p - self.base) as usize) {
                        mm = merge(mm, (v, v));
                    }
                    p += 1;
                }
            }
        }
        mm
    }

    /// The points of column `col` between `t0_s` and `t1_s` for a plot `columns_px` pixels
    /// wide: the raw samples when there are fewer than two per pixel, else per pixel column its
    /// minimum and maximum (in the order they likely occurred). Appends `[t_s, value]` to `out`;
    /// NaN values are left out.
    pub(super) fn decimated(&self, col: usize, t0_s: f64, t1_s: f64, columns_px: usize, out: &mut Vec<[f64; 2]>) {
        let Some(column) = self.columns.get(col) else { return };
        if t1_s.partial_cmp(&t0_s) != Some(std::cmp::Ordering::Greater) || columns_px == 0 {
            return;
        }
        // one sample either side, so the line reaches the edges
        let a = self.index_at(t0_s).saturating_sub(1).max(self.base);
        let b = (self.index_at(t1_s) + 1).min(self.end());
        if b <= a {
            return;
        }
        let raw = |i: u64| -> Option<[f64; 2]> {
            let at = (i - self.base) as usize;
            let v = *column.values.get(at)?;
            v.is_finite().then(|| [self.times_s[at], f64::from(v)])
        };
        if (b - a) as usize <= 2 * columns_px {
            out.extend((a..b).filter_map(raw));
            return;
        }
        out.extend(raw(a));
        let dt = (t1_s - t0_s) / columns_px as f64;
        let mut ca = self.index_at(t0_s);
        for c in 0..columns_px {
            let cb = if c + 1 == columns_px { self.index_at(t1_s) } else { self.index_at(t0_s + (c + 1) as f64 * dt) };
            if cb > ca {
                let (lo, hi) = self.range_min_max(column, ca, cb);
                if lo <= hi {
                    let (ta, tb) =
                        (self.times_s[(ca - self.base) as usize], self.times_s[(cb - 1 - self.base) as usize]);
                    let first = column.values[(ca - self.base) as usize];
                    // the first sample nearer the maximum: the maximum came first
                    let max_first = (f64::from(first) - f64::from(hi)).abs() < (f64::from(first) - f64::from(lo)).abs();
                    let (v0, v1) = if max_first { (hi, lo) } else { (lo, hi) };
                    out.push([ta, f64::from(v0)]);
                    out.push([tb.max(ta), f64::from(v1)]);
                }
                ca = cb;
            }
        }
        if b > self.index_at(t1_s) {
            out.extend(raw(b - 1));
        }
    }

    /// Samples, min / max and (tracking-error columns) the sum of squares of column `col` over
    /// the samples between `t0_s` and `t1_s`; `None` without a sample there.
    pub(super) fn window_part(&self, col: usize, t0_s: f64, t1_s: f64) -> Option<WindowPart> {
        let column = self.columns.get(col)?;
        let a = self.index_at(t0_s);
        let b = self.base + self.times_s.partition_point(|&t| t <= t1_s) as u64;
        if b <= a {
            return None;
        }
        let min_max = self.range_min_max(column, a, b);
        let sum_of_squares = column.squares.as_ref().and_then(|sq| {
            Some(self.sum_of_squares_before(column, sq, b)? - self.sum_of_squares_before(column, sq, a)?)
        });
        Some(WindowPart { samples: (b - a) as usize, min_max, sum_of_squares })
    }

    /// The newest sample at or before `t_s` (the first one before the store starts): its time
    /// and every column's value.
    pub(super) fn row_at(&self, t_s: f64) -> Option<(f64, Vec<f32>)> {
        let after = self.times_s.partition_point(|&t| t <= t_s);
        let at = after.saturating_sub(1);
        let t = *self.times_s.get(at)?;
        Some((t, self.columns.iter().map(|c| c.values.get(at).copied().unwrap_or(f32::NAN)).collect()))
    }

    /// Every kept sample between `t0_s` and `t1_s`: its time and every column's value (CSV
    /// export of the visible window).
    pub(super) fn raw_window(&self, t0_s: f64, t1_s: f64) -> impl Iterator<Item = (f64, Vec<f32>)> + '_ {
        let a = self.times_s.partition_point(|&t| t < t0_s);
        let b = self.times_s.partition_point(|&t| t <= t1_s);
        (a..b.max(a)).filter_map(move |i| {
            let t = *self.times_s.get(i)?;
            Some((t, self.columns.iter().map(|c| c.values.get(i).copied().unwrap_or(f32::NAN)).collect()))
        })
    }
}

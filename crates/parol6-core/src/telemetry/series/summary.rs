//! The summary of a live store's older rows: per [`SUMMARY_BUCKET_S`] of time, the minimum and
//! the maximum of every column in the order they came, at the bucket's first and last sample
//! time (one or two rows are kept as they are). A 1 kHz source becomes 250 Hz of min/max
//! pairs; a source at 250 Hz or slower is kept whole.

/// Length of a summary bucket, s (4 samples of a 1 kHz source).
pub const SUMMARY_BUCKET_S: f64 = 0.004;

/// Turns rows, oldest first, into summary rows. The buckets lie on multiples of
/// [`SUMMARY_BUCKET_S`] from time zero, so the live ring and a store summarise alike.
#[derive(Debug, Clone)]
pub(crate) struct Summarizer {
    width: usize,
    bucket: Option<i64>,
    times_s: Vec<f64>,
    values: Vec<f32>,
    first: Vec<f32>,
    second: Vec<f32>,
}

fn bucket_of(t_s: f64) -> i64 {
    (t_s / SUMMARY_BUCKET_S).floor() as i64
}

impl Summarizer {
    /// A summarizer of rows of `width` columns.
    pub(crate) fn new(width: usize) -> Self {
        Self { width, bucket: None, times_s: Vec::new(), values: Vec::new(), first: Vec::new(), second: Vec::new() }
    }

    /// Adds a row; one of a later bucket first closes the open bucket into `emit`.
    pub(crate) fn push(&mut self, time_s: f64, row: &[f32], emit: &mut dyn FnMut(f64, &[f32])) {
        let b = bucket_of(time_s);
        if self.bucket.is_some_and(|open| open != b) {
            self.flush(emit);
        }
        self.bucket = Some(b);
        self.times_s.push(time_s);
        self.values.extend((0..self.width).map(|c| row.get(c).copied().unwrap_or(f32::NAN)));
    }

    /// The rows of the open bucket, not yet summarised.
    pub(crate) fn pending(&self) -> impl Iterator<Item = (f64, &[f32])> {
        self.times_s.iter().copied().zip(self.values.chunks_exact(self.width.max(1)))
    }

    /// Closes the open bucket into `emit`.
    pub(crate) fn flush(&mut self, emit: &mut dyn FnMut(f64, &[f32])) {
        let n = self.times_s.len();
        if n <= 2 {
            for (t, row) in self.pending() {
                emit(t, row);
            }
        } else {
            self.first.clear();
            self.second.clear();
            for c in 0..self.width {
                // (value, index) of the minimum and the maximum, NaN left out
                let mut lo: Option<(f32, usize)> = None;
                let mut hi: Option<(f32, usize)> = None;
                for (k, &v) in self.values.iter().skip(c).step_by(self.width).enumerate() {
                    if v.is_nan() {
                        continue;
                    }
                    if lo.is_none_or(|(m, _)| v < m) {
                        lo = Some((v, k));
                    }
                    if hi.is_none_or(|(m, _)| v > m) {
                        hi = Some((v, k));
                    }
                }
                let (a, b) = match (lo, hi) {
                    (Some(lo), Some(hi)) if hi.1 < lo.1 => (hi.0, lo.0),
                    (Some(lo), Some(hi)) => (lo.0, hi.0),
                    _ => (f32::NAN, f32::NAN),
                };
                self.first.push(a);
                self.second.push(b);
            }
            emit(self.times_s[0], &self.first);
            emit(self.times_s[n - 1], &self.second);
        }
        self.times_s.clear();
        self.values.clear();
        self.bucket = None;
    }

    /// Forgets the open bucket.
    pub(crate) fn clear(&mut self) {
        self.times_s.clear();
        self.values.clear();
        self.bucket = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(rows: &[(f64, f32)]) -> Vec<(f64, f32)> {
        let mut s = Summarizer::new(1);
        let mut out = Vec::new();
        for &(t, v) in rows {
            s.push(t, &[v], &mut |t, r| out.push((t, r[0])));
        }
        s.flush(&mut |t, r| out.push((t, r[0])));
        out
    }

    #[test]
    fn four_samples_become_their_extremes_in_the_order_they_came() {
        let rows = [(0.0, 1.0), (0.001, 5.0), (0.002, -2.0), (0.003, 0.0), (0.004, 3.0)];
        assert_eq!(run(&rows), vec![(0.0, 5.0), (0.003, -2.0), (0.004, 3.0)]);
    }

    #[test]
    fn a_slow_source_is_kept_whole() {
        let rows: Vec<(f64, f32)> = (0..10).map(|k| (k as f64 * 0.01, k as f32)).collect();
        assert_eq!(run(&rows), rows);
    }
}

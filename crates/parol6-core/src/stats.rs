//! Sample statistics for timings and jitter: one percentile rule for the whole workspace.
//!
//! Rule ("nearest rank on the closed interval"): on a slice sorted ascending with `n` values,
//! the `q`-quantile (`q` in `0.0..=1.0`) is the value at index `round((n − 1) · q)`, rounding
//! halves away from zero. So `q = 0` is the minimum, `q = 1` the maximum, `q = 0.5` the middle
//! value (the upper middle for an even `n`), and the result is always one of the samples (no
//! interpolation). `q` outside `0..=1` is clamped; a NaN `q` counts as 0.

use serde::{Deserialize, Serialize};

/// The `q`-quantile of `sorted` (ascending) by the rule of this module; `None` when empty.
///
/// The caller sorts (`samples.sort_by(f64::total_cmp)`); an unsorted slice gives a value of the
/// slice, but not the quantile.
pub fn percentile(sorted: &[f64], q: f64) -> Option<f64> {
    let last = sorted.len().checked_sub(1)?;
    let q = if q.is_nan() { 0.0 } else { q.clamp(0.0, 1.0) };
    // In 0..=last: q is in [0, 1], so the product is in [0, last] before rounding.
    let index = ((last as f64) * q).round() as usize;
    sorted.get(index.min(last)).copied()
}

/// Count, extremes, median, 99th percentile and mean of a set of samples, in the samples' unit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Number of samples.
    pub n: usize,
    /// Smallest sample.
    pub min: f64,
    /// Median ([`percentile`] 0.5).
    pub p50: f64,
    /// 99th percentile ([`percentile`] 0.99).
    pub p99: f64,
    /// Largest sample.
    pub max: f64,
    /// Arithmetic mean.
    pub mean: f64,
}

impl Summary {
    /// Summary of `samples` in any order (they are copied and sorted with `f64::total_cmp`, so
    /// NaNs sort last); `None` when there are none.
    pub fn from_samples(samples: &[f64]) -> Option<Self> {
        let mut sorted = samples.to_vec();
        sorted.sort_by(f64::total_cmp);
        Self::from_sorted(&sorted)
    }

    /// Summary of samples already sorted ascending; `None` when empty.
    pub fn from_sorted(sorted: &[f64]) -> Option<Self> {
        let (&min, &max) = (sorted.first()?, sorted.last()?);
        Some(Self {
            n: sorted.len(),
            min,
            p50: percentile(sorted, 0.5)?,
            p99: percentile(sorted, 0.99)?,
            max,
            mean: sorted.iter().sum::<f64>() / sorted.len() as f64,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_has_no_percentile_or_summary() {
        assert_eq!(percentile(&[], 0.5), None);
        assert_eq!(Summary::from_samples(&[]), None);
    }

    #[test]
    fn percentile_follows_the_rounded_index_rule() {
        let s: Vec<f64> = (0..=100).map(f64::from).collect(); // 101 values, index = value
        assert_eq!(percentile(&s, 0.0), Some(0.0));
        assert_eq!(percentile(&s, 0.5), Some(50.0));
        assert_eq!(percentile(&s, 0.99), Some(99.0));
        assert_eq!(percentile(&s, 1.0), Some(100.0));
        // n = 4: round(3 · 0.5) = round(1.5) = 2 → the upper middle value
        assert_eq!(percentile(&[1.0, 2.0, 3.0, 4.0], 0.5), Some(3.0));
        // n = 10: round(9 · 0.99) = round(8.91) = 9 → the maximum
        let ten: Vec<f64> = (1..=10).map(f64::from).collect();
        assert_eq!(percentile(&ten, 0.99), Some(10.0));
        assert_eq!(percentile(&[7.0], 0.3), Some(7.0));
    }

    #[test]
    fn out_of_range_quantiles_are_clamped() {
        let s = [1.0, 2.0, 3.0];
        assert_eq!(percentile(&s, -1.0), Some(1.0));
        assert_eq!(percentile(&s, 2.0), Some(3.0));
        assert_eq!(percentile(&s, f64::NAN), Some(1.0));
    }

    #[test]
    fn summary_of_unsorted_samples() {
        let s = Summary::from_samples(&[5.0, 1.0, 4.0, 2.0, 3.0]);
        assert_eq!(s, Some(Summary { n: 5, min: 1.0, p50: 3.0, p99: 5.0, max: 5.0, mean: 3.0 }));
    }

    #[test]
    fn summary_p99_of_a_long_tail() {
        // 1000 samples: index round(999 · 0.99) = 989, so 2 % outliers reach the 99th percentile
        // and 0.5 % do not.
        let mut v = vec![1.0; 980];
        v.extend([100.0; 20]);
        let s = Summary::from_samples(&v).map(|s| (s.p50, s.p99, s.max));
        assert_eq!(s, Some((1.0, 100.0, 100.0)));
        let mut w = vec![1.0; 995];
        w.extend([100.0; 5]);
        let s = Summary::from_samples(&w).map(|s| (s.p50, s.p99, s.max));
        assert_eq!(s, Some((1.0, 1.0, 100.0)));
    }
}

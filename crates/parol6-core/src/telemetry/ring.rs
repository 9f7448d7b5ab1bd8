//! [`LiveRing`]: the last minutes of telemetry and events for the live view, as the plots draw
//! them: `f32` rows ([`SeriesStore::build_row`]), the newest minute at the rate the samples
//! came (up to 1 kHz), older rows as their 4 ms min/max summary (see [`super::series`]). Rows
//! are kept in sealed blocks so that publishing a [`LiveView`] copies only the open blocks,
//! never the history.

use std::collections::VecDeque;
use std::sync::Arc;

use super::event::TelemetryEvent;
use super::sample::{DriveKind, TelemetrySample};
use super::series::{SeriesStore, Summarizer};

/// Rows per sealed block.
const BLOCK_LEN: usize = 256;

/// Rows of the live view, oldest first: times and the rows' values, flat.
#[derive(Debug, Clone, Default)]
pub struct RowBlock {
    /// Time of each row, s.
    pub times_s: Vec<f64>,
    /// The rows, one after the other ([`SeriesStore::ids`] order).
    pub values: Vec<f32>,
    /// Columns per row.
    pub width: usize,
    /// True when the rows are a summary (min/max pairs of 4 ms), false when samples.
    pub summary: bool,
}

impl RowBlock {
    fn new(width: usize, summary: bool) -> Self {
        Self { times_s: Vec::with_capacity(BLOCK_LEN), values: Vec::with_capacity(BLOCK_LEN * width), width, summary }
    }

    fn push(&mut self, t_s: f64, row: &[f32]) {
        self.times_s.push(t_s);
        self.values.extend((0..self.width).map(|c| row.get(c).copied().unwrap_or(f32::NAN)));
    }

    /// Rows in the block.
    pub fn len(&self) -> usize {
        self.times_s.len()
    }

    /// True without rows.
    pub fn is_empty(&self) -> bool {
        self.times_s.is_empty()
    }

    /// Every row: its time and values.
    pub fn rows(&self) -> impl Iterator<Item = (f64, &[f32])> {
        self.times_s.iter().copied().zip(self.values.chunks_exact(self.width.max(1)))
    }

    /// Heap bytes the block holds.
    pub fn heap_bytes(&self) -> usize {
        self.times_s.capacity() * size_of::<f64>() + self.values.capacity() * size_of::<f32>()
    }
}

/// What the live view reads: the kept rows, oldest first, in blocks, and the kept events.
#[derive(Debug, Clone, Default)]
pub struct LiveView {
    /// Summary blocks, then full-rate blocks, oldest first; the open blocks are copies.
    pub blocks: Vec<Arc<RowBlock>>,
    /// What the drive columns hold (of the newest sample).
    pub drive: DriveKind,
    /// The newest sample, whole.
    pub latest: Option<TelemetrySample>,
    /// Events inside the kept time span, oldest first.
    pub events: Vec<TelemetryEvent>,
}

impl LiveView {
    /// Number of kept rows.
    pub fn len(&self) -> usize {
        self.blocks.iter().map(|b| b.len()).sum()
    }

    /// True when nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.blocks.iter().all(|b| b.is_empty())
    }

    /// The newest sample.
    pub fn latest(&self) -> Option<&TelemetrySample> {
        self.latest.as_ref()
    }

    /// Time of the newest row, s.
    pub fn latest_time_s(&self) -> Option<f64> {
        self.blocks.iter().rev().find_map(|b| b.times_s.last().copied())
    }
}

/// The kept history: rows not older than `span_s` before the newest; the newest `full_rate_s`
/// of them at up to `rate_hz` (a faster source is thinned by time), older ones summarised.
#[derive(Debug)]
pub struct LiveRing {
    joints: usize,
    span_s: f64,
    full_rate_s: f64,
    min_dt_s: f64,
    summary: VecDeque<Arc<RowBlock>>,
    summary_open: RowBlock,
    summarizer: Summarizer,
    sealed: VecDeque<Arc<RowBlock>>,
    open: RowBlock,
    events: VecDeque<TelemetryEvent>,
    last_kept_s: Option<f64>,
    latest: Option<TelemetrySample>,
    row: Vec<f32>,
    /// False while the backend is not the one the window shows ([`LiveRing::set_rows_kept`]).
    rows_kept: bool,
}

impl LiveRing {
    /// Keeps `span_s` seconds of samples of `joints` joints, the newest `full_rate_s` at up to
    /// `rate_hz`, older ones as their summary.
    pub fn new(joints: usize, span_s: f64, full_rate_s: f64, rate_hz: f64) -> Self {
        let min_dt_s = if rate_hz.is_finite() && rate_hz > 0.0 { 1.0 / rate_hz } else { 0.0 };
        let width = SeriesStore::row_width(joints);
        let span_s = span_s.max(0.0);
        Self {
            joints,
            span_s,
            full_rate_s: full_rate_s.clamp(0.0, span_s),
            // a little under the period, so that a source at exactly `rate_hz` is never thinned
            min_dt_s: 0.9 * min_dt_s,
            summary: VecDeque::new(),
            summary_open: RowBlock::new(width, true),
            summarizer: Summarizer::new(width),
            sealed: VecDeque::new(),
            open: RowBlock::new(width, false),
            events: VecDeque::new(),
            last_kept_s: None,
            latest: None,
            row: Vec::with_capacity(width),
            rows_kept: true,
        }
    }

    /// Keeps rows and events (`true`, the default), or drops what is kept and keeps nothing
    /// until turned on again: the window's plots only ever take rows of the backend they show
    /// from the moment it is shown, so an inactive backend's ten minutes would never be drawn.
    pub fn set_rows_kept(&mut self, on: bool) {
        self.rows_kept = on;
        if !on {
            let width = self.open.width;
            self.summary.clear();
            self.summary_open = RowBlock::new(width, true);
            self.summarizer = Summarizer::new(width);
            self.sealed.clear();
            self.open = RowBlock::new(width, false);
            self.events.clear();
            self.last_kept_s = None;
        }
    }

    /// Keeps `s` unless it comes too soon after the last kept one; summarises and drops what
    /// is old.
    pub fn push(&mut self, s: &TelemetrySample) {
        if !self.keeps(s.time_s) {
            return;
        }
        self.last_kept_s = Some(s.time_s);
        SeriesStore::sample_row(s, self.joints, &mut self.row);
        self.latest = Some(s.clone());
        self.open.push(s.time_s, &self.row);
        if self.open.len() >= BLOCK_LEN {
            let width = self.open.width;
            let block = std::mem::replace(&mut self.open, RowBlock::new(width, false));
            self.sealed.push_back(Arc::new(block));
        }
        self.age(s.time_s);
    }

    /// Whether [`LiveRing::push`] would keep a sample taken at `time_s` (one per
    /// `1 / rate` seconds is kept).
    pub fn keeps(&self, time_s: f64) -> bool {
        self.rows_kept && !self.last_kept_s.is_some_and(|last| time_s >= last && time_s - last < self.min_dt_s)
    }

    /// Keeps an event.
    pub fn push_event(&mut self, e: &TelemetryEvent) {
        if self.rows_kept {
            self.events.push_back(e.clone());
        }
    }

    fn age(&mut self, now_s: f64) {
        let oldest_kept = now_s - self.span_s;
        let full_from = now_s - self.full_rate_s;
        while let Some(block) = self.sealed.front().filter(|b| b.times_s.last().is_some_and(|&t| t < full_from)) {
            let block = Arc::clone(block);
            self.sealed.pop_front();
            let (summary, open) = (&mut self.summary, &mut self.summary_open);
            for (t, row) in block.rows() {
                self.summarizer.push(t, row, &mut |t, r| {
                    open.push(t, r);
                    if open.len() >= BLOCK_LEN {
                        let width = open.width;
                        let sealed = std::mem::replace(open, RowBlock::new(width, true));
                        summary.push_back(Arc::new(sealed));
                    }
                });
            }
        }
        while self.summary.front().and_then(|b| b.times_s.last()).is_some_and(|&last| last < oldest_kept) {
            self.summary.pop_front();
        }
        while self.events.front().is_some_and(|e| e.time_s < oldest_kept) {
            self.events.pop_front();
        }
    }

    /// A view of what is kept now.
    pub fn view(&self) -> LiveView {
        let mut blocks: Vec<Arc<RowBlock>> = self.summary.iter().cloned().collect();
        if !self.summary_open.is_empty() {
            blocks.push(Arc::new(self.summary_open.clone()));
        }
        let mut pending = RowBlock::new(self.open.width, false);
        for (t, row) in self.summarizer.pending() {
            pending.push(t, row);
        }
        if !pending.is_empty() {
            blocks.push(Arc::new(pending));
        }
        blocks.extend(self.sealed.iter().cloned());
        if !self.open.is_empty() {
            blocks.push(Arc::new(self.open.clone()));
        }
        let drive = self.latest.as_ref().map_or(DriveKind::TorqueNm, |s| s.drive);
        LiveView { blocks, drive, latest: self.latest.clone(), events: self.events.iter().cloned().collect() }
    }

    /// Heap bytes the kept rows hold (blocks and their room for more rows).
    pub fn heap_bytes(&self) -> usize {
        let blocks = self.summary.iter().chain(&self.sealed).map(|b| b.heap_bytes()).sum::<usize>();
        blocks + self.summary_open.heap_bytes() + self.open.heap_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::TcpPose;
    use crate::telemetry::sample::DriveKind;

    fn sample(seq: u64, t: f64) -> TelemetrySample {
        TelemetrySample {
            seq,
            time_s: t,
            joints: Vec::new(),
            drive: DriveKind::TorqueNm,
            tcp: TcpPose::from_xyz_rpy([0.0; 3], [0.0; 3]),
            worst_zone: None,
            program_step: None,
            link: None,
        }
    }

    fn times(v: &LiveView) -> Vec<f64> {
        v.blocks.iter().flat_map(|b| b.times_s.iter().copied()).collect()
    }

    #[test]
    fn keeps_the_span_at_the_rate() {
        let mut ring = LiveRing::new(0, 10.0, 10.0, 250.0);
        // 30 s of a 1 kHz source
        for k in 0..30_000u64 {
            ring.push(&sample(k, k as f64 * 1e-3));
        }
        let v = ring.view();
        let times = times(&v);
        let (first, last) = (times[0], v.latest_time_s().unwrap_or(f64::NAN));
        assert!((29.995..=29.999 + 1e-9).contains(&last), "{last}");
        // whole blocks expire: at most a full-rate and a summary block (256 rows at 250 Hz ≈ 1 s
        // each) older than the span
        assert!(last - first <= 10.0 + 2.1 && last - first >= 10.0 - 1e-9, "span {}", last - first);
        let rate = v.len() as f64 / (last - first);
        assert!((rate - 250.0).abs() < 5.0, "rate {rate}");
        assert!(times.windows(2).all(|w| w[1] > w[0]));
    }

    #[test]
    fn a_source_at_the_rate_is_not_thinned() {
        let mut ring = LiveRing::new(0, 600.0, 60.0, 100.0);
        for k in 0..1000u64 {
            ring.push(&sample(k, k as f64 * 0.01));
        }
        assert_eq!(ring.view().len(), 1000);
    }

    /// A 1 kHz source: the newest minute whole, older rows as 4 ms min/max pairs (half as
    /// many), in time order, the view joined without a gap.
    #[test]
    fn the_live_ring_summarises_rows_older_than_a_minute() {
        let mut ring = LiveRing::new(0, 600.0, 60.0, 1000.0);
        for k in 0..100_000u64 {
            ring.push(&sample(k, k as f64 * 1e-3));
        }
        let v = ring.view();
        let times = times(&v);
        assert!(times.windows(2).all(|w| w[1] > w[0]), "time order");
        let full: usize = v.blocks.iter().filter(|b| !b.summary).map(|b| b.len()).sum();
        let summary: usize = v.blocks.iter().filter(|b| b.summary).map(|b| b.len()).sum();
        assert!((60_000..=60_300).contains(&full), "{full} full-rate rows");
        assert!((19_700..=20_100).contains(&summary), "{summary} summary rows for the older 40 s");
        assert_eq!(times[0], 0.0);
    }
}

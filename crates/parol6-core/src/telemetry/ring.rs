//! [`LiveRing`]: the last minutes of samples and events for the live view, kept in sealed
//! blocks so that publishing a [`LiveView`] copies only the open block, never the history.

use std::collections::VecDeque;
use std::sync::Arc;

use super::event::TelemetryEvent;
use super::sample::TelemetrySample;

/// Samples per sealed block.
const BLOCK_LEN: usize = 256;

/// What the live view reads: the kept samples, oldest first, in blocks, and the kept events.
#[derive(Debug, Clone, Default)]
pub struct LiveView {
    /// Sealed blocks, oldest first, then the open block's copy.
    pub blocks: Vec<Arc<[TelemetrySample]>>,
    /// Events inside the kept time span, oldest first.
    pub events: Vec<TelemetryEvent>,
}

impl LiveView {
    /// Every kept sample, oldest first.
    pub fn samples(&self) -> impl Iterator<Item = &TelemetrySample> {
        self.blocks.iter().flat_map(|b| b.iter())
    }

    /// Number of kept samples.
    pub fn len(&self) -> usize {
        self.blocks.iter().map(|b| b.len()).sum()
    }

    /// True when nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.blocks.iter().all(|b| b.is_empty())
    }

    /// The newest sample.
    pub fn latest(&self) -> Option<&TelemetrySample> {
        self.blocks.iter().rev().find_map(|b| b.last())
    }
}

/// The kept history: samples not older than `span_s` before the newest, at most `rate_hz`
/// (a faster source is decimated by time, so a 1 kHz simulation keeps one sample per
/// `1 / rate_hz`).
#[derive(Debug)]
pub struct LiveRing {
    span_s: f64,
    min_dt_s: f64,
    sealed: VecDeque<Arc<[TelemetrySample]>>,
    open: Vec<TelemetrySample>,
    events: VecDeque<TelemetryEvent>,
    last_kept_s: Option<f64>,
}

impl LiveRing {
    /// Keeps `span_s` seconds at up to `rate_hz`.
    pub fn new(span_s: f64, rate_hz: f64) -> Self {
        let min_dt_s = if rate_hz.is_finite() && rate_hz > 0.0 { 1.0 / rate_hz } else { 0.0 };
        Self {
            span_s: span_s.max(0.0),
            // a little under the period, so that a source at exactly `rate_hz` is never thinned
            min_dt_s: 0.9 * min_dt_s,
            sealed: VecDeque::new(),
            open: Vec::with_capacity(BLOCK_LEN),
            events: VecDeque::new(),
            last_kept_s: None,
        }
    }

    /// Keeps `s` unless it comes too soon after the last kept one; drops what is too old.
    pub fn push(&mut self, s: &TelemetrySample) {
        if !self.keeps(s.time_s) {
            return;
        }
        self.last_kept_s = Some(s.time_s);
        self.open.push(s.clone());
        if self.open.len() >= BLOCK_LEN {
            let block: Arc<[TelemetrySample]> = std::mem::take(&mut self.open).into();
            self.sealed.push_back(block);
            self.open.reserve(BLOCK_LEN);
        }
        self.expire(s.time_s);
    }

    /// Whether [`LiveRing::push`] would keep a sample taken at `time_s` (one per
    /// `1 / rate` seconds is kept).
    pub fn keeps(&self, time_s: f64) -> bool {
        !self.last_kept_s.is_some_and(|last| time_s >= last && time_s - last < self.min_dt_s)
    }

    /// Keeps an event.
    pub fn push_event(&mut self, e: &TelemetryEvent) {
        self.events.push_back(e.clone());
    }

    fn expire(&mut self, now_s: f64) {
        let oldest_kept = now_s - self.span_s;
        while self.sealed.front().and_then(|b| b.last()).is_some_and(|last| last.time_s < oldest_kept) {
            self.sealed.pop_front();
        }
        while self.events.front().is_some_and(|e| e.time_s < oldest_kept) {
            self.events.pop_front();
        }
    }

    /// A view of what is kept now.
    pub fn view(&self) -> LiveView {
        let mut blocks: Vec<Arc<[TelemetrySample]>> = self.sealed.iter().cloned().collect();
        if !self.open.is_empty() {
            blocks.push(self.open.as_slice().into());
        }
        LiveView { blocks, events: self.events.iter().cloned().collect() }
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

    #[test]
    fn keeps_the_span_at_the_rate() {
        let mut ring = LiveRing::new(10.0, 250.0);
        // 30 s of a 1 kHz source
        for k in 0..30_000u64 {
            ring.push(&sample(k, k as f64 * 1e-3));
        }
        let v = ring.view();
        let first = v.samples().next().map(|s| s.time_s).unwrap_or(f64::NAN);
        let last = v.latest().map(|s| s.time_s).unwrap_or(f64::NAN);
        assert!((29.995..=29.999 + 1e-9).contains(&last), "{last}");
        // whole blocks expire: at most one block (256 samples at 250 Hz ≈ 1 s) older than the span
        assert!(last - first <= 10.0 + 1.1 && last - first >= 10.0 - 1e-9, "span {}", last - first);
        let rate = v.len() as f64 / (last - first);
        assert!((rate - 250.0).abs() < 5.0, "rate {rate}");
        let times: Vec<f64> = v.samples().map(|s| s.time_s).collect();
        assert!(times.windows(2).all(|w| w[1] > w[0]));
    }

    #[test]
    fn a_source_at_the_rate_is_not_thinned() {
        let mut ring = LiveRing::new(600.0, 100.0);
        for k in 0..1000u64 {
            ring.push(&sample(k, k as f64 * 0.01));
        }
        assert_eq!(ring.view().len(), 1000);
    }
}

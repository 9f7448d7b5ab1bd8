//! [`SeriesStore`]: telemetry as columns of plot series (joint position, velocity,
//! acceleration, drive, tracking error per joint; TCP position and orientation), for the plots
//! and the replay.
//!
//! Every column keeps a min/max pyramid (level `k` holds the minimum and maximum of aligned
//! blocks of `2^k` samples), so [`SeriesStore::decimated`] returns about two points per pixel
//! column of any time window in `O(columns · log n)`, never walking the raw samples; the
//! tracking-error columns also keep running sums of squares (one every `SQUARES_BLOCK`
//! samples) for the RMS over a window ([`SeriesStore::window_stats`]). Samples older than the store's span are dropped
//! ([`SeriesStore::new`]), so the same store serves the live view (10 minutes, appended to)
//! and a replay (everything, built once).
//!
//! A live store ([`SeriesStore::live`]) keeps its newest minute at the rate the samples came
//! (up to 1 kHz) and older samples as a summary: per 4 ms ([`SUMMARY_BUCKET_S`]) the minimum
//! and the maximum of every column, in the order they came (a bucket of one or two samples is
//! kept as it is), so a peak of one sample is never lost while the store holds half as many
//! rows of a 1 kHz source. Rows are `f32`, built in one place ([`SeriesStore::build_row`]) for
//! the live ring, this store and the replay.

use super::ring::LiveView;
use super::sample::{DriveKind, TelemetrySample};

mod summary;
mod tier;

pub use summary::SUMMARY_BUCKET_S;
pub(crate) use summary::Summarizer;
use tier::{EMPTY, Tier, merge};

/// What a series measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Measured joint position, rad.
    Position,
    /// Measured joint velocity, rad/s.
    Velocity,
    /// Measured joint acceleration, rad/s².
    Acceleration,
    /// Joint torque (N·m, simulation) or step rate (steps/s, robot).
    Drive,
    /// Commanded − measured joint position, rad (the hardware-in-the-loop view).
    TrackingError,
    /// TCP position x, y, z, m.
    TcpPosition,
    /// TCP roll, pitch, yaw (`R = Rz(yaw)·Ry(pitch)·Rx(roll)`), rad.
    TcpOrientation,
}

impl Quantity {
    /// Every quantity, in column order.
    pub const ALL: [Quantity; 7] = [
        Quantity::Position,
        Quantity::Velocity,
        Quantity::Acceleration,
        Quantity::Drive,
        Quantity::TrackingError,
        Quantity::TcpPosition,
        Quantity::TcpOrientation,
    ];

    /// True for the per-joint quantities (the others have three axes).
    pub fn per_joint(self) -> bool {
        !matches!(self, Quantity::TcpPosition | Quantity::TcpOrientation)
    }

    /// Series of this quantity in a row of `joints` joints.
    pub fn width(self, joints: usize) -> usize {
        if self.per_joint() { joints } else { 3 }
    }

    /// Name for headings and CSV columns.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::Position => "position",
            Quantity::Velocity => "velocity",
            Quantity::Acceleration => "acceleration",
            Quantity::Drive => "drive",
            Quantity::TrackingError => "commanded − measured",
            Quantity::TcpPosition => "TCP position",
            Quantity::TcpOrientation => "TCP roll / pitch / yaw",
        }
    }
}

/// One series: a quantity of one joint (0-based) or one axis (0 x / roll, 1 y / pitch, 2 z / yaw).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SeriesId {
    /// The quantity.
    pub quantity: Quantity,
    /// Joint or axis, 0-based.
    pub index: usize,
}

/// Min, max, RMS and peak magnitude of a series over a time window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowStats {
    /// Samples in the window.
    pub samples: usize,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// Largest magnitude.
    pub max_abs: f64,
    /// Root mean square (tracking-error series only).
    pub rms: Option<f64>,
}

/// Telemetry as plot series. See the module docs.
#[derive(Debug, Clone)]
pub struct SeriesStore {
    joints: usize,
    ids: Vec<SeriesId>,
    /// Summary rows (a live store's samples older than its full-rate span).
    older: Tier,
    /// Rows at the rate they came.
    recent: Tier,
    /// A live store's summary of the rows leaving `recent`.
    summarizer: Option<Summarizer>,
    drive: DriveKind,
    row: Vec<f32>,
}

impl SeriesStore {
    /// An empty store for `joints` joints keeping `span_s` seconds (infinite: everything) at
    /// the rate the samples come.
    pub fn new(joints: usize, span_s: f64) -> Self {
        Self::with_tiers(joints, span_s, f64::INFINITY)
    }

    /// An empty live store: `span_s` seconds, the newest `full_rate_s` of them at the rate the
    /// samples come, older ones summarised (see the module docs).
    pub fn live(joints: usize, span_s: f64, full_rate_s: f64) -> Self {
        Self::with_tiers(joints, span_s, full_rate_s)
    }

    fn with_tiers(joints: usize, span_s: f64, full_rate_s: f64) -> Self {
        let mut ids = Vec::new();
        for q in Quantity::ALL {
            ids.extend((0..q.width(joints)).map(|index| SeriesId { quantity: q, index }));
        }
        let squares: Vec<bool> = ids.iter().map(|id| id.quantity == Quantity::TrackingError).collect();
        let span_s = if span_s > 0.0 { span_s } else { f64::INFINITY };
        let summarised = full_rate_s > 0.0 && full_rate_s < span_s;
        let (recent_s, older_s) = if summarised { (full_rate_s, span_s - full_rate_s) } else { (span_s, 0.0) };
        Self {
            joints,
            older: Tier::new(&squares, older_s),
            recent: Tier::new(&squares, recent_s),
            summarizer: summarised.then(|| Summarizer::new(ids.len())),
            ids,
            drive: DriveKind::TorqueNm,
            row: Vec::new(),
        }
    }

    /// Columns of a row for `joints` joints.
    pub fn row_width(joints: usize) -> usize {
        Quantity::ALL.iter().map(|q| q.width(joints)).sum()
    }

    /// First column of quantity `q` in a row for `joints` joints.
    pub fn offset_of(q: Quantity, joints: usize) -> usize {
        Quantity::ALL.iter().take_while(|&&other| other != q).map(|other| other.width(joints)).sum()
    }

    /// The one telemetry row builder: `value(quantity, index)` of every series in column order
    /// ([`SeriesStore::ids`]), as `f32`, into `out` (cleared first). The live ring, the store
    /// and the replay build their rows with it.
    pub fn build_row(joints: usize, out: &mut Vec<f32>, mut value: impl FnMut(Quantity, usize) -> f64) {
        out.clear();
        for q in Quantity::ALL {
            out.extend((0..q.width(joints)).map(|i| value(q, i) as f32));
        }
    }

    /// The row of a live sample (missing joints are NaN).
    pub fn sample_row(s: &TelemetrySample, joints: usize, out: &mut Vec<f32>) {
        Self::build_row(joints, out, |q, i| {
            let joint = s.joints.get(i);
            let of = |f: fn(&super::sample::JointTelemetry) -> f64| joint.map_or(f64::NAN, f);
            match q {
                Quantity::Position => of(|j| j.q_rad),
                Quantity::Velocity => of(|j| j.qd_rad_s),
                Quantity::Acceleration => of(|j| j.qdd_rad_s2),
                Quantity::Drive => of(|j| j.drive),
                Quantity::TrackingError => of(|j| j.cmd_q_rad - j.q_rad),
                Quantity::TcpPosition => s.tcp.position_m.get(i).copied().unwrap_or(f64::NAN),
                Quantity::TcpOrientation => s.tcp.rpy_rad.get(i).copied().unwrap_or(f64::NAN),
            }
        });
    }

    /// Joints per sample.
    pub fn joints(&self) -> usize {
        self.joints
    }

    /// The series, in column order.
    pub fn ids(&self) -> &[SeriesId] {
        &self.ids
    }

    /// The column of a series.
    pub fn column(&self, id: SeriesId) -> Option<usize> {
        self.ids.iter().position(|i| *i == id)
    }

    /// What the drive series hold (of the newest sample).
    pub fn drive(&self) -> DriveKind {
        self.drive
    }

    /// Rows kept (a summarised 4 ms of a 1 kHz source is two).
    pub fn len(&self) -> usize {
        self.older.len() + self.recent.len()
    }

    /// True when nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// First and last sample time, s.
    pub fn time_range_s(&self) -> Option<(f64, f64)> {
        let first = self.older.first_s().or(self.recent.first_s())?;
        let last = self.recent.last_s().or(self.older.last_s())?;
        Some((first, last))
    }

    /// Seconds before which rows are a summary (the oldest full-rate row), if any are.
    pub fn summary_before_s(&self) -> Option<f64> {
        self.older.last_s()?;
        self.recent.first_s().or(self.older.last_s())
    }

    /// Drops everything.
    pub fn clear(&mut self) {
        self.older.clear();
        self.recent.clear();
        if let Some(s) = self.summarizer.as_mut() {
            s.clear();
        }
    }

    /// Gives back the room kept for more samples (a replay's store, filled once, grows no more).
    pub fn shrink_to_fit(&mut self) {
        self.older.shrink_to_fit();
        self.recent.shrink_to_fit();
    }

    /// Appends one sample of every series (`row` in [`SeriesStore::ids`] order; missing values
    /// are NaN). A time before the newest sample starts the store again (a new source).
    pub fn push_row(&mut self, time_s: f64, row: &[f32]) {
        if !time_s.is_finite() {
            return;
        }
        if self.time_range_s().is_some_and(|(_, last)| time_s < last) {
            self.clear();
        }
        let (recent, older, summarizer) = (&mut self.recent, &mut self.older, &mut self.summarizer);
        recent.push_row(time_s, row, &mut |t, r| {
            if let Some(s) = summarizer.as_mut() {
                s.push(t, r, &mut |t, r| older.push_row(t, r, &mut |_, _| {}));
            }
        });
    }

    /// Appends a row that is already a summary (a live view's older rows): every full-rate row
    /// kept is summarised first, all being older.
    fn push_summary_row(&mut self, time_s: f64, row: &[f32]) {
        if self.summarizer.is_none() {
            self.push_row(time_s, row);
            return;
        }
        if !time_s.is_finite() || self.time_range_s().is_some_and(|(_, last)| time_s < last) {
            return;
        }
        let (recent, older, summarizer) = (&mut self.recent, &mut self.older, &mut self.summarizer);
        if let Some(s) = summarizer.as_mut() {
            recent.take_all(&mut |t, r| s.push(t, r, &mut |t, r| older.push_row(t, r, &mut |_, _| {})));
            s.flush(&mut |t, r| older.push_row(t, r, &mut |_, _| {}));
        }
        older.push_row(time_s, row, &mut |_, _| {});
    }

    /// Appends a telemetry sample.
    pub fn push_sample(&mut self, s: &TelemetrySample) {
        let mut row = std::mem::take(&mut self.row);
        Self::sample_row(s, self.joints, &mut row);
        self.drive = s.drive;
        self.push_row(s.time_s, &row);
        self.row = row;
    }

    /// Sets what the drive series hold (a replay sets it from the file).
    pub fn set_drive(&mut self, drive: DriveKind) {
        self.drive = drive;
    }

    /// Appends the rows of `view` newer than the newest kept one; returns how many. When
    /// the view's newest row is older than the store's (another backend), starts again.
    pub fn ingest_live(&mut self, view: &LiveView) -> usize {
        self.ingest_live_shifted(view, 0.0)
    }

    /// [`Self::ingest_live`] with `shift_s` added to the view's times: another backend's view,
    /// whose clock started elsewhere, continues the kept rows (the plots keep their history
    /// over a switch between the simulation and the robot). Rows at or before the newest kept
    /// one, once shifted, are left out.
    pub fn ingest_live_shifted(&mut self, view: &LiveView, shift_s: f64) -> usize {
        let Some(latest) = view.latest_time_s() else { return 0 };
        if self.time_range_s().is_some_and(|(_, last)| latest + shift_s < last) {
            self.clear();
        }
        let last = self.time_range_s().map(|(_, last)| last);
        // the new rows sit in the last blocks: find the first block that has any
        let first_block = match last {
            None => 0,
            Some(last) => {
                view.blocks.iter().rposition(|b| b.times_s.first().is_some_and(|&t| t + shift_s <= last)).unwrap_or(0)
            }
        };
        let mut added = 0;
        for block in &view.blocks[first_block..] {
            for (t, row) in block.rows() {
                let t = t + shift_s;
                if last.is_none_or(|last| t > last) {
                    if block.summary {
                        self.push_summary_row(t, row);
                    } else {
                        self.push_row(t, row);
                    }
                    added += 1;
                }
            }
        }
        self.drive = view.drive;
        added
    }

    /// The points of column `col` between `t0_s` and `t1_s` for a plot `columns_px` pixels
    /// wide: the rows when there are fewer than two per pixel, else per pixel column its
    /// minimum and maximum (in the order they likely occurred). Appends `[t_s, value]` to `out`
    /// (cleared first); NaN values are left out.
    pub fn decimated(&self, col: usize, t0_s: f64, t1_s: f64, columns_px: usize, out: &mut Vec<[f64; 2]>) {
        out.clear();
        self.older.decimated(col, t0_s, t1_s, columns_px, out);
        self.recent.decimated(col, t0_s, t1_s, columns_px, out);
    }

    /// Min, max, peak magnitude and (tracking-error columns) RMS of column `col` over the
    /// samples between `t0_s` and `t1_s`; `None` without a finite sample there.
    pub fn window_stats(&self, col: usize, t0_s: f64, t1_s: f64) -> Option<WindowStats> {
        let parts = [self.older.window_part(col, t0_s, t1_s), self.recent.window_part(col, t0_s, t1_s)];
        let parts: Vec<_> = parts.into_iter().flatten().collect();
        let samples: usize = parts.iter().map(|p| p.samples).sum();
        let (lo, hi) = parts.iter().fold(EMPTY, |m, p| merge(m, p.min_max));
        if samples == 0 || lo > hi {
            return None;
        }
        let sums: Option<Vec<f64>> = parts.iter().map(|p| p.sum_of_squares).collect();
        let rms = sums.map(|s| (s.iter().sum::<f64>().max(0.0) / samples as f64).sqrt());
        let (min, max) = (f64::from(lo), f64::from(hi));
        Some(WindowStats { samples, min, max, max_abs: min.abs().max(max.abs()), rms })
    }

    /// The newest row at or before `t_s` (the first one before the store starts): its time
    /// and every column's value.
    pub fn row_at(&self, t_s: f64) -> Option<(f64, Vec<f32>)> {
        match self.recent.first_s() {
            Some(first) if t_s >= first || self.older.len() == 0 => self.recent.row_at(t_s),
            _ => self.older.row_at(t_s),
        }
    }

    /// The measured joint positions (rad) at or before `t_s`.
    pub fn joint_positions_at(&self, t_s: f64) -> Option<Vec<f64>> {
        let (_, row) = self.row_at(t_s)?;
        Some(row.iter().take(self.joints).map(|&v| f64::from(v)).collect())
    }

    /// Every kept row between `t0_s` and `t1_s`: its time and every column's value (CSV
    /// export of the visible window; before [`SeriesStore::summary_before_s`] the summary's).
    pub fn raw_window(&self, t0_s: f64, t1_s: f64) -> impl Iterator<Item = (f64, Vec<f32>)> + '_ {
        self.older.raw_window(t0_s, t1_s).chain(self.recent.raw_window(t0_s, t1_s))
    }
}

#[cfg(test)]
mod tests;

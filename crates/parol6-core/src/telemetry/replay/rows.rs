//! Joint messages → plot rows. A measured sample becomes its row where it is decoded (forward
//! kinematics included) and is paired with its command by tick in [`ChunkRows`], one per chunk
//! (or one for a whole file read linearly); [`RowJoiner`] joins the chunks in file order into
//! the [`SeriesStore`], pairing what a chunk boundary split and dropping the sample a chunk
//! took again from a log-time bucket the previous chunk had already taken.

use std::collections::VecDeque;

use serde::Deserialize;

use crate::model::RobotModel;
use crate::telemetry::sample::DriveKind;
use crate::telemetry::schema::{JointStateMsg, LinkHealthMsg, LogMsg, Time};
use crate::telemetry::series::{Quantity, SeriesStore};

/// Measured samples waiting for their command, at most.
const MAX_PENDING: usize = 16;

#[derive(Debug, Clone, Copy, Deserialize)]
pub(super) struct Stamp {
    stamp: Time,
}

/// What the replay takes from a `/joint_states` message (the joint names and the rest are
/// skipped unparsed).
#[derive(Debug, Clone, Deserialize)]
pub(super) struct MeasuredJson {
    header: Stamp,
    position: Vec<f64>,
    velocity: Vec<f64>,
    effort: Vec<f64>,
    acceleration: Vec<f64>,
    seq: u64,
    time_s: f64,
    #[serde(default)]
    steps_per_s: Option<Vec<f64>>,
}

impl From<JointStateMsg> for MeasuredJson {
    fn from(m: JointStateMsg) -> Self {
        Self {
            header: Stamp { stamp: m.header.stamp },
            position: m.position,
            velocity: m.velocity,
            effort: m.effort,
            acceleration: m.acceleration,
            seq: m.seq,
            time_s: m.time_s,
            steps_per_s: m.steps_per_s,
        }
    }
}

/// What the replay takes from a `/joint_commands` message.
#[derive(Debug, Clone, Deserialize)]
pub(super) struct CommandedJson {
    pub(super) position: Vec<f64>,
    pub(super) seq: u64,
}

/// A measured sample made into its row; the tracking error is filled in when its command is
/// found.
#[derive(Debug, Clone)]
pub(super) struct MeasuredRow {
    seq: u64,
    time_s: f64,
    stamp_ns: u64,
    position: Vec<f64>,
    drive: DriveKind,
    row: Vec<f32>,
}

fn at(v: &[f64], j: usize) -> f64 {
    v.get(j).copied().unwrap_or(f64::NAN)
}

impl MeasuredRow {
    /// The row ([`SeriesStore::build_row`]); the tracking error is NaN until the command is
    /// found.
    pub(super) fn new(model: &RobotModel, m: MeasuredJson) -> Self {
        let n = model.dof();
        let (drive_values, drive) = match &m.steps_per_s {
            Some(steps) => (steps.as_slice(), DriveKind::StepsPerS),
            None => (m.effort.as_slice(), DriveKind::TorqueNm),
        };
        let q: Vec<f64> = (0..n).map(|j| at(&m.position, j)).collect();
        let tcp = q.iter().all(|v| v.is_finite()).then(|| model.fk(&q));
        let mut row = Vec::with_capacity(SeriesStore::row_width(n));
        SeriesStore::build_row(n, &mut row, |quantity, j| match quantity {
            Quantity::Position => at(&q, j),
            Quantity::Velocity => at(&m.velocity, j),
            Quantity::Acceleration => at(&m.acceleration, j),
            Quantity::Drive => at(drive_values, j),
            // filled in when the command is found
            Quantity::TrackingError => f64::NAN,
            Quantity::TcpPosition => tcp.as_ref().map_or(f64::NAN, |p| at(&p.position_m, j)),
            Quantity::TcpOrientation => tcp.as_ref().map_or(f64::NAN, |p| at(&p.rpy_rad, j)),
        });
        Self { seq: m.seq, time_s: m.time_s, stamp_ns: m.header.stamp.as_ns(), position: q, drive, row }
    }

    /// Fills in the tracking error (commanded − measured) from `c`.
    fn with_command(mut self, c: &CommandedJson) -> Self {
        let n = self.position.len();
        let from = SeriesStore::offset_of(Quantity::TrackingError, n);
        for (j, e) in self.row.iter_mut().skip(from).take(n).enumerate() {
            *e = (at(&c.position, j) - self.position[j]) as f32;
        }
        self
    }
}

/// The rows of one chunk (or of a whole file read linearly), flat.
#[derive(Debug, Clone)]
pub(super) struct ChunkRows {
    width: usize,
    /// Measured samples of this chunk still waiting for their command (the last few).
    pending: VecDeque<MeasuredRow>,
    /// Commands whose sample is not in this chunk (the previous one's last few, if any).
    orphans: Vec<CommandedJson>,
    seqs: Vec<u64>,
    times_s: Vec<f64>,
    values: Vec<f32>,
    /// Motion time and stamp of the first row, for the events.
    first: Option<(f64, u64)>,
    drive: Option<DriveKind>,
    /// Bucket and tick of the chunk's first measured sample, bucket of its last.
    first_measured: Option<(u64, u64)>,
    last_measured_bucket: Option<u64>,
    saw_measured: bool,
    events: Vec<LogMsg>,
    link: Vec<LinkHealthMsg>,
}

impl ChunkRows {
    pub(super) fn new(model: &RobotModel) -> Self {
        Self {
            width: SeriesStore::row_width(model.dof()),
            pending: VecDeque::new(),
            orphans: Vec::new(),
            seqs: Vec::new(),
            times_s: Vec::new(),
            values: Vec::new(),
            first: None,
            drive: None,
            first_measured: None,
            last_measured_bucket: None,
            saw_measured: false,
            events: Vec::new(),
            link: Vec::new(),
        }
    }

    /// A measured sample, in file order, with its log-time bucket (`None`: thinned already).
    pub(super) fn measured(&mut self, bucket: Option<u64>, m: MeasuredRow) {
        if let Some(b) = bucket {
            self.first_measured.get_or_insert((b, m.seq));
        }
        self.last_measured_bucket = bucket;
        self.saw_measured = true;
        self.pending.push_back(m);
        while self.pending.len() > MAX_PENDING {
            self.pending.pop_front();
        }
    }

    /// A command, in file order: its sample's row is complete.
    pub(super) fn commanded(&mut self, c: CommandedJson) {
        match take_pending(&mut self.pending, c.seq) {
            Some(m) => self.push(m.with_command(&c)),
            None if self.orphans.len() < MAX_PENDING => self.orphans.push(c),
            None => {}
        }
    }

    pub(super) fn event(&mut self, e: LogMsg) {
        self.events.push(e);
    }

    /// A `/link` message (the serial link's health), in file order.
    pub(super) fn link(&mut self, m: LinkHealthMsg) {
        self.link.push(m);
    }

    fn push(&mut self, m: MeasuredRow) {
        self.first.get_or_insert((m.time_s, m.stamp_ns));
        self.drive = Some(m.drive);
        self.seqs.push(m.seq);
        self.times_s.push(m.time_s);
        self.values.extend_from_slice(&m.row);
    }
}

/// The measured sample of tick `seq` among `pending`, dropping the older ones.
fn take_pending(pending: &mut VecDeque<MeasuredRow>, seq: u64) -> Option<MeasuredRow> {
    let i = pending.iter().position(|p| p.seq == seq)?;
    pending.drain(..=i).next_back()
}

/// Joins the chunks' rows, in file order, into the store.
pub(super) struct RowJoiner {
    pub(super) store: SeriesStore,
    pending: VecDeque<MeasuredRow>,
    last_measured_bucket: Option<u64>,
    pub(super) first: Option<(f64, u64)>,
    pub(super) drive: Option<DriveKind>,
    pub(super) events: Vec<LogMsg>,
    pub(super) link: Vec<LinkHealthMsg>,
}

impl RowJoiner {
    pub(super) fn new(model: &RobotModel) -> Self {
        Self {
            store: SeriesStore::new(model.dof(), f64::INFINITY),
            pending: VecDeque::new(),
            last_measured_bucket: None,
            first: None,
            drive: None,
            events: Vec::new(),
            link: Vec::new(),
        }
    }

    /// The next chunk's rows.
    pub(super) fn add(&mut self, mut chunk: ChunkRows) {
        // the chunk's first sample is in a bucket the previous chunk had taken: not kept
        let again = match (chunk.first_measured, self.last_measured_bucket) {
            (Some((bucket, seq)), Some(last)) if bucket == last => Some(seq),
            _ => None,
        };
        for c in &chunk.orphans {
            if let Some(m) = take_pending(&mut self.pending, c.seq) {
                let m = m.with_command(c);
                self.first.get_or_insert((m.time_s, m.stamp_ns));
                self.drive = Some(m.drive);
                self.store.push_row(m.time_s, &m.row);
            }
        }
        let width = chunk.width;
        for (k, (&seq, &t)) in chunk.seqs.iter().zip(&chunk.times_s).enumerate() {
            if Some(seq) == again {
                continue;
            }
            if let Some(row) = chunk.values.get(k * width..(k + 1) * width) {
                self.store.push_row(t, row);
            }
        }
        if !chunk.seqs.iter().all(|&s| Some(s) == again) {
            if let Some(first) = chunk.first {
                self.first.get_or_insert(first);
            }
            self.drive = chunk.drive.or(self.drive);
        }
        if chunk.saw_measured {
            chunk.pending.retain(|m| Some(m.seq) != again);
            self.pending = chunk.pending;
            self.last_measured_bucket = chunk.last_measured_bucket;
        }
        self.events.append(&mut chunk.events);
        self.link.append(&mut chunk.link);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn measured(model: &RobotModel, seq: u64) -> MeasuredRow {
        let json = format!(
            r#"{{"header":{{"stamp":{{"sec":1,"nsec":{seq}}}}},"position":[{q},0,0,0,0,0],"velocity":[0,0,0,0,0,0],"effort":[],"acceleration":[0,0,0,0,0,0],"seq":{seq},"time_s":{t}}}"#,
            q = seq as f64 * 0.01,
            t = seq as f64 * 0.004,
        );
        MeasuredRow::new(model, serde_json::from_str(&json).expect("json"))
    }

    fn command(seq: u64) -> CommandedJson {
        CommandedJson { position: vec![seq as f64 * 0.01 + 0.5; 6], seq }
    }

    fn times(j: &RowJoiner) -> Vec<f64> {
        j.store.raw_window(f64::NEG_INFINITY, f64::INFINITY).map(|(t, _)| t).collect()
    }

    /// A pair split by a chunk boundary is joined; a sample a chunk took again from the
    /// previous chunk's last bucket is dropped; the result is the one-chunk result.
    #[test]
    fn chunks_join_into_the_rows_of_one_pass() {
        let model = RobotModel::parol6();
        let mut whole = ChunkRows::new(&model);
        for (bucket, seq) in [(1, 1), (2, 2), (3, 4)] {
            whole.measured(Some(bucket), measured(&model, seq));
            whole.commanded(command(seq));
        }
        let mut one = RowJoiner::new(&model);
        one.add(whole);
        let mut a = ChunkRows::new(&model);
        a.measured(Some(1), measured(&model, 1));
        a.commanded(command(1));
        a.measured(Some(2), measured(&model, 2));
        let mut b = ChunkRows::new(&model);
        b.commanded(command(2));
        b.measured(Some(2), measured(&model, 3));
        b.commanded(command(3));
        b.measured(Some(3), measured(&model, 4));
        b.commanded(command(4));
        let mut split = RowJoiner::new(&model);
        split.add(a);
        split.add(b);
        assert_eq!(times(&split), vec![0.004, 0.008, 0.016]);
        assert_eq!(times(&split), times(&one));
        let rows = |j: &RowJoiner| {
            j.store
                .raw_window(0.0, 1.0)
                .map(|(_, r)| r.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
                .collect::<Vec<_>>()
        };
        assert_eq!(rows(&split), rows(&one));
        let error_j1: Vec<f32> = split.store.raw_window(0.0, 1.0).map(|(_, r)| r[24]).collect();
        assert!(error_j1.iter().all(|e| (e - 0.5).abs() < 1e-6), "tracking error of J1 filled in: {error_j1:?}");
    }
}

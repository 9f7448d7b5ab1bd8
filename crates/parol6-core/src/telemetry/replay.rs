//! Loading a recording for replay: [`load_replay`] reads an MCAP file of ours into a
//! [`SeriesStore`] (the same series as the live plots, TCP from forward kinematics) and its
//! events on the motion clock.
//!
//! Joint states are kept at most at [`REPLAY_RATE_HZ`] (the rate of the live view): a 1 kHz
//! simulation recording is thinned by time before its messages are parsed, so a ten-minute
//! file opens in well under a second. A truncated file gives what its complete chunks hold
//! (with the reader's warning); an empty, foreign or damaged file, or a recording of another
//! robot, gives a [`RecordingError`] that says which.

use std::collections::VecDeque;

use crate::model::RobotModel;

use super::reader::{RecordingError, ScanFilter, scan_recording_filtered};
use super::sample::DriveKind;
use super::schema::JointStateMsg;
use super::series::SeriesStore;

/// Highest sample rate a replay keeps, Hz (the live view's).
pub const REPLAY_RATE_HZ: f64 = 250.0;

/// An event of the recording on the motion clock.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayEvent {
    /// Motion time, s.
    pub time_s: f64,
    /// Foxglove log level: 2 info, 3 warning, 4 error.
    pub level: u8,
    /// What happened.
    pub message: String,
}

/// A recording ready to replay.
#[derive(Debug, Clone)]
pub struct ReplayData {
    /// The series (every sample kept, at most [`REPLAY_RATE_HZ`]).
    pub store: SeriesStore,
    /// Events, oldest first.
    pub events: Vec<ReplayEvent>,
    /// Robot named in the file.
    pub robot: String,
    /// Program named in the file (empty: none).
    pub program: String,
    /// Joint-state samples in the file.
    pub samples_in_file: u64,
    /// Problems that did not stop reading (a truncated tail …).
    pub warnings: Vec<String>,
    /// The file ended before its footer.
    pub truncated: bool,
}

/// Reads `bytes` (a whole MCAP file) for replay with `model`. See the module docs.
pub fn load_replay(bytes: &[u8], model: &RobotModel) -> Result<ReplayData, RecordingError> {
    let n = model.dof();
    let mut store = SeriesStore::new(n, f64::INFINITY);
    let mut pending: VecDeque<JointStateMsg> = VecDeque::new();
    let mut first: Option<(f64, u64)> = None;
    let mut drive = None;
    let mut row: Vec<f32> = Vec::new();
    let mut q = vec![0.0; n];
    let filter = ScanFilter { joint_min_interval_ns: (1e9 / REPLAY_RATE_HZ * 0.9) as u64 };
    let mut visit = |topic: &str, m: JointStateMsg| {
        if topic == "/joint_states" {
            pending.push_back(m);
            while pending.len() > 16 {
                pending.pop_front();
            }
            return;
        }
        let Some(i) = pending.iter().position(|p| p.seq == m.seq) else { return };
        let Some(meas) = pending.drain(..=i).next_back() else { return };
        first.get_or_insert((meas.time_s, meas.header.stamp.as_ns()));
        let at = |v: &[f64], j: usize| v.get(j).copied().unwrap_or(f64::NAN);
        let (drive_values, kind) = match &meas.steps_per_s {
            Some(steps) => (steps.as_slice(), DriveKind::StepsPerS),
            None => (meas.effort.as_slice(), DriveKind::TorqueNm),
        };
        drive = Some(kind);
        for (j, qj) in q.iter_mut().enumerate() {
            *qj = at(&meas.position, j);
        }
        row.clear();
        row.extend(q.iter().map(|&v| v as f32));
        row.extend((0..n).map(|j| at(&meas.velocity, j) as f32));
        row.extend((0..n).map(|j| at(&meas.acceleration, j) as f32));
        row.extend((0..n).map(|j| at(drive_values, j) as f32));
        row.extend((0..n).map(|j| (at(&m.position, j) - at(&meas.position, j)) as f32));
        if q.iter().all(|v| v.is_finite()) {
            let tcp = model.fk(&q);
            row.extend(tcp.position_m.iter().map(|&v| v as f32));
            row.extend(tcp.rpy_rad.iter().map(|&v| v as f32));
        }
        store.push_row(meas.time_s, &row);
    };
    let rec = scan_recording_filtered(bytes, filter, &mut visit)?;
    rec.check_robot(model)?;
    if let Some(kind) = drive {
        store.set_drive(kind);
    }
    let events = match first {
        Some((t0_s, stamp0_ns)) => rec
            .events
            .iter()
            .map(|e| ReplayEvent {
                time_s: t0_s + (e.timestamp.as_ns() as f64 - stamp0_ns as f64) * 1e-9,
                level: e.level,
                message: e.message.clone(),
            })
            .collect(),
        None => Vec::new(),
    };
    let mut warnings = rec.warnings.clone();
    if store.is_empty() {
        warnings.push("the recording holds no joint-state samples: nothing to replay".into());
    }
    Ok(ReplayData {
        store,
        events,
        robot: rec.robot().to_string(),
        program: rec.metadata.get("program").cloned().unwrap_or_default(),
        samples_in_file: rec.topics.get("/joint_states").map_or(0, |t| t.messages),
        warnings,
        truncated: rec.truncated,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::telemetry::reader::tests::recording_bytes;
    use crate::telemetry::series::{Quantity, SeriesId};

    #[test]
    fn a_recording_is_thinned_to_the_replay_rate_with_its_events() {
        // 2.5 s at 1 kHz
        let data = load_replay(&recording_bytes(2500), &RobotModel::parol6()).expect("replay");
        assert_eq!(data.samples_in_file, 2500);
        let kept = data.store.len();
        assert!((620..=630).contains(&kept), "about 250 Hz kept: {kept}");
        assert_eq!(data.events.len(), 1);
        let (t0, _) = data.store.time_range_s().expect("samples");
        assert!((data.events[0].time_s - 0.5).abs() < 1e-6 && t0 < 0.01, "event on the motion clock");
        assert_eq!(data.program, "demo");
        let tcp_x = data.store.column(SeriesId { quantity: Quantity::TcpPosition, index: 0 }).expect("column");
        assert!(data.store.window_stats(tcp_x, 0.0, 10.0).is_some_and(|s| s.max.is_finite()), "TCP from FK");
        assert!(data.warnings.is_empty() && !data.truncated, "{:?}", data.warnings);
    }

    #[test]
    fn bad_files_are_named_and_a_cut_file_replays_what_it_holds() {
        let model = RobotModel::parol6();
        assert!(matches!(load_replay(&[], &model), Err(RecordingError::Empty)));
        assert!(matches!(load_replay(b"not a recording", &model), Err(RecordingError::NotMcap)));
        let bytes = recording_bytes(2500);
        let cut = load_replay(&bytes[..bytes.len() * 2 / 3], &model).expect("the complete chunks");
        assert!(cut.truncated && cut.warnings.iter().any(|w| w.contains("cut short")), "{:?}", cut.warnings);
        assert!(!cut.store.is_empty() && cut.store.len() < 600, "{}", cut.store.len());
        let other = RobotModel::from_urdf_str(
            r#"<robot name="two"><link name="a"/><link name="b"/>
            <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#,
            &crate::model::LoadOptions::default(),
        )
        .expect("model");
        match load_replay(&bytes, &other) {
            Err(e @ RecordingError::OtherRobot { .. }) => assert!(e.to_string().contains("\"parol6\""), "{e}"),
            other => panic!("{other:?}"),
        }
    }
}

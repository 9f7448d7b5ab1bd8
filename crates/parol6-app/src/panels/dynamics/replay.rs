//! The Dynamics panel during replay: the joint torques along the recorded motion, from the
//! recording's measured joint positions, velocities and accelerations at every kept sample,
//! with the same inverse dynamics and limit warnings as the live panel's program analysis
//! ([`motion_torques`]). Computed on a worker when a recording is opened (a ten-minute one is
//! 150 000 samples); the panel shows the torques at the replay cursor and a cursor line on the
//! plot.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crossbeam_channel::{Receiver, TryRecvError, bounded};
use parol6_core::RobotModel;
use parol6_core::program::torques::{ProgramTorques, motion_torques, torque_limits_nm};
use parol6_core::telemetry::{Quantity, ReplayData, SeriesStore};

use super::{MAX_POINTS_PER_LINE, decimate};

/// Samples between two looks at the cancel flag.
const CANCEL_EVERY: usize = 4096;

/// The analysis of one recording.
pub(super) struct RecordingTorques {
    data: Arc<ReplayData>,
    /// The torques, or why there are none.
    pub(super) result: Result<ProgramTorques, String>,
    /// Decimated `[t, τ]` per joint.
    pub(super) lines: Vec<Vec<[f64; 2]>>,
}

impl RecordingTorques {
    /// Each joint's torque at the last sample at or before `t_s` (the first sample before it).
    pub(super) fn at(&self, t_s: f64) -> Option<Vec<f64>> {
        let t = self.result.as_ref().ok()?;
        let k = t.time_s.partition_point(|&x| x <= t_s).saturating_sub(1);
        t.torques_nm.iter().map(|col| col.get(k).copied()).collect()
    }
}

/// What a forgotten analysis held ([`ReplayAnalysis::take`]): freed when dropped.
pub(super) struct HeldAnalysis {
    _done: Option<RecordingTorques>,
    _pending: Option<Arc<ReplayData>>,
}

/// The analysis running on a worker: its recording, its result (once), its cancel flag.
struct Pending {
    data: Arc<ReplayData>,
    result: Receiver<RecordingTorques>,
    cancel: Arc<AtomicBool>,
}

/// The recording's analysis: the one done and the one running.
#[derive(Default)]
pub(super) struct ReplayAnalysis {
    done: Option<RecordingTorques>,
    pending: Option<Pending>,
}

impl ReplayAnalysis {
    /// True while a recording is analysed on the worker.
    pub(super) fn computing(&self) -> bool {
        self.pending.is_some()
    }

    /// The analysis of `data`, once done.
    pub(super) fn of(&self, data: &Arc<ReplayData>) -> Option<&RecordingTorques> {
        self.done.as_ref().filter(|d| Arc::ptr_eq(&d.data, data))
    }

    /// Forgets every analysis (the recording was closed: its memory goes with it).
    pub(super) fn clear(&mut self) {
        drop(self.take());
    }

    /// Forgets every analysis, a running one cancelled, and hands back what it held: the
    /// recording and its torques (tens of MB for a long recording), for the caller to free
    /// where it pleases.
    pub(super) fn take(&mut self) -> HeldAnalysis {
        let pending = self.pending.take().map(|p| {
            p.cancel.store(true, Ordering::Relaxed);
            p.data
        });
        HeldAnalysis { _done: self.done.take(), _pending: pending }
    }

    /// Brings the analysis up to `data`: takes a finished worker's result, or starts a worker
    /// (never computes in the frame).
    pub(super) fn refresh(&mut self, model: &RobotModel, data: &Arc<ReplayData>) {
        if self.of(data).is_some() {
            return;
        }
        if let Some(p) = self.pending.as_ref().filter(|p| Arc::ptr_eq(&p.data, data)) {
            match p.result.try_recv() {
                Ok(done) => {
                    self.done = Some(done);
                    self.pending = None;
                }
                Err(TryRecvError::Empty) => {}
                Err(TryRecvError::Disconnected) => {
                    let result = Err("the analysis stopped without a result".to_string());
                    self.done = Some(RecordingTorques { data: Arc::clone(data), result, lines: Vec::new() });
                    self.pending = None;
                }
            }
            return;
        }
        self.clear();
        let (tx, rx) = bounded(1);
        let cancel = Arc::new(AtomicBool::new(false));
        let (model, worker_data, stop) = (model.clone(), Arc::clone(data), Arc::clone(&cancel));
        let work = move || {
            if let Some(done) = analyse(&model, worker_data, &stop)
                && tx.send(done).is_err()
            {
                tracing::debug!("a recording's dynamics analysis finished after it was superseded");
            }
        };
        match crate::background::spawn("parol6-dynamics-replay", work) {
            Ok(_) => self.pending = Some(Pending { data: Arc::clone(data), result: rx, cancel }),
            Err(e) => {
                let result = Err(format!("cannot start the analysis thread: {e}"));
                self.done = Some(RecordingTorques { data: Arc::clone(data), result, lines: Vec::new() });
            }
        }
    }
}

/// The torques along the recording `data` (on the worker); `None` once `cancel` is set.
fn analyse(model: &RobotModel, data: Arc<ReplayData>, cancel: &AtomicBool) -> Option<RecordingTorques> {
    let store = &data.store;
    let n = model.dof();
    if store.joints() != n {
        let result = Err(format!("the recording has {} joints, the robot {n}", store.joints()));
        return Some(RecordingTorques { data: Arc::clone(&data), result, lines: Vec::new() });
    }
    let (t0, t1) = store.time_range_s().unwrap_or((0.0, 0.0));
    let offset = |q: Quantity| SeriesStore::offset_of(q, n);
    let (pos, vel, acc) = (offset(Quantity::Position), offset(Quantity::Velocity), offset(Quantity::Acceleration));
    let mut rows = store.raw_window(t0, t1);
    let (mut k, mut cancelled) = (0usize, false);
    let torques = motion_torques(model, torque_limits_nm(model), |q, qd, qdd| {
        loop {
            k += 1;
            if k.is_multiple_of(CANCEL_EVERY) && cancel.load(Ordering::Relaxed) {
                cancelled = true;
                return None;
            }
            let (t_s, row) = rows.next()?;
            let value = |c: usize| row.get(c).map_or(f64::NAN, |&v| f64::from(v));
            for j in 0..n {
                q[j] = value(pos + j);
                // a velocity or acceleration not recorded reads as 0
                qd[j] = Some(value(vel + j)).filter(|v| v.is_finite()).unwrap_or(0.0);
                qdd[j] = Some(value(acc + j)).filter(|v| v.is_finite()).unwrap_or(0.0);
            }
            // a sample without its joint positions has no torque
            if q.iter().all(|v| v.is_finite()) {
                return Some(t_s);
            }
        }
    });
    if cancelled {
        return None;
    }
    let lines = torques.torques_nm.iter().map(|col| decimate(&torques.time_s, col, MAX_POINTS_PER_LINE)).collect();
    Some(RecordingTorques { data: Arc::clone(&data), result: Ok(torques), lines })
}

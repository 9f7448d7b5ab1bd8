//! The ISO 9283 pose test the window runs: owned by the app (`AppState::measurement`), started,
//! aborted and collected here, read by the Measurement panel. The test itself runs on the
//! core's driver thread ([`parol6_core::measure::driver`]); this holds its handle and the last
//! finished run on each backend, so a panel redrawn, hidden or replaced loses nothing.

use std::sync::Arc;

use parol6_core::measure::driver::{MeasureError, MeasureProgress, MeasureRun};
use parol6_core::measure::pose_figures::PoseSample;
use parol6_core::motion::StateSource;

/// A finished run: where it ran and what it attained.
#[derive(Debug, Clone)]
pub struct FinishedMeasurement {
    /// Simulation or robot.
    pub source: StateSource,
    /// The backend's name as the status bar shows it.
    pub backend: String,
    /// The poses attained, in visiting order.
    pub samples: Vec<PoseSample>,
}

/// The measurement the app owns: the running test, if any, and the last finished run on each
/// backend.
#[derive(Default)]
pub struct MeasurementState {
    running: Option<(MeasureRun<Vec<PoseSample>>, StateSource, String)>,
    finished: Vec<FinishedMeasurement>,
    /// How the last run ended (text, true when it is an error), until the next one starts.
    outcome: Option<(String, bool)>,
}

impl std::fmt::Debug for MeasurementState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeasurementState")
            .field("running", &self.running.as_ref().map(|(_, source, backend)| (source, backend)))
            .field("finished", &self.finished.len())
            .field("outcome", &self.outcome)
            .finish()
    }
}

impl MeasurementState {
    /// True while a test runs on its thread.
    pub fn running(&self) -> bool {
        self.running.as_ref().is_some_and(|(r, _, _)| !r.is_finished())
    }

    /// The running test's progress (poses attained so far), while one runs or has ended
    /// uncollected.
    pub fn progress(&self) -> Option<Arc<MeasureProgress>> {
        self.running.as_ref().map(|(r, _, _)| r.progress())
    }

    /// The last finished run on each backend, the newest last.
    pub fn finished(&self) -> &[FinishedMeasurement] {
        &self.finished
    }

    /// How the last run ended, until the next one starts.
    pub fn outcome(&self) -> Option<&(String, bool)> {
        self.outcome.as_ref()
    }

    /// Takes over a test started on the backend `backend` (`source`).
    pub fn attach(&mut self, run: MeasureRun<Vec<PoseSample>>, source: StateSource, backend: String) {
        self.outcome = None;
        self.running = Some((run, source, backend));
    }

    /// Aborts the running test (STOP, the E-stop and the panel's Abort do).
    pub fn abort(&self) {
        if let Some((r, _, _)) = &self.running {
            r.abort();
        }
    }

    /// Collects a test whose thread has ended (once per frame): its samples replace the last run
    /// on the same backend, and its outcome is kept to show.
    pub fn collect(&mut self) {
        if self.running() {
            return;
        }
        let Some((run, source, backend)) = self.running.take() else { return };
        let stop_failed = run.progress().stop_failed.clone();
        let mut outcome = match run.join() {
            Ok(samples) => {
                self.finished.retain(|f| f.source != source);
                let text = format!("{} poses measured on the {backend}", samples.len());
                self.finished.push(FinishedMeasurement { source, backend, samples });
                (text, false)
            }
            Err(MeasureError::Aborted) => ("measurement aborted".into(), true),
            Err(e) => (format!("measurement failed: {e}"), true),
        };
        if let Some(failure) = stop_failed {
            outcome = (format!("{}; {failure}", outcome.0), true);
        }
        self.outcome = Some(outcome);
    }
}

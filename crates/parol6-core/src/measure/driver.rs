//! Runs a measurement on any [`RobotBackend`] on its own thread: every move is a program run by
//! the [`ProgramRunner`] (pre-flight included), so a test means the same on the simulation and
//! on the robot. The attained pose is the forward kinematics of the *measured* joints once the
//! arm has settled (not moving, planner holding, then `settle_s` of motion clock). Path tests
//! record the commanded and measured joints while the path runs, from the backend's sample tap
//! when one is given (every control tick) or else by polling its state.
//!
//! Progress (cycle, pose, fraction done, the attained poses so far) is published for the
//! command line's progress bar and the measurement panel; [`MeasureRun::abort`] stops the arm
//! and ends the run.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use arc_swap::ArcSwap;
use crossbeam_channel::Receiver;

use super::cube::{CYCLE_ORDER, POSE_NAMES};
use super::path_figures::{self, PathFigureError, PathFigures};
use super::plan::{PathTestPlan, PlanError, PoseTestPlan};
use super::pose_figures::PoseSample;
use crate::model::RobotModel;
use crate::motion::{MotionSample, PlannerMode, RobotBackend, stop_best_effort};
use crate::program::runner::{ProgramRunner, RunOptions, RunProgress, RunState};
use crate::program::{PoseMm, Program};

/// How often the driver looks at the runner and the backend (wall clock).
const TICK: Duration = Duration::from_millis(5);
/// The longest wait for the arm to settle, wall clock.
const SETTLE_TIMEOUT: Duration = Duration::from_secs(60);
/// Recorded path samples are at least this far apart on the motion clock, s.
const RECORD_PERIOD_S: f64 = 0.004;
/// Rest after a path cycle before the next move, s of motion clock.
const PATH_SETTLE_S: f64 = 0.1;

/// Where a measurement is.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum Phase {
    /// Pre-flight.
    Preparing,
    /// Moving to the start.
    Approaching,
    /// Running cycles.
    Running,
    /// Every cycle done.
    Done,
    /// Aborted by the operator.
    Aborted,
    /// Refused or failed; the reason.
    Failed(String),
}

/// Progress of a measurement.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MeasureProgress {
    /// Phase.
    pub phase: Phase,
    /// Current cycle, 1-based (0 before the first).
    pub cycle: usize,
    /// Number of cycles.
    pub cycles: usize,
    /// The test pose under way (pose test), 0 = P1.
    pub pose: Option<usize>,
    /// Fraction of the test done, 0…1.
    pub fraction: f64,
    /// Attained poses so far (pose test).
    pub attained: Vec<PoseSample>,
    /// A STOP the measurement (or its program run) sent that the backend refused (what it
    /// stopped, and why it failed); `None` when every STOP was taken. The arm may not have stopped.
    pub stop_failed: Option<String>,
}

impl MeasureProgress {
    /// True once the run has ended.
    pub fn is_finished(&self) -> bool {
        matches!(self.phase, Phase::Done | Phase::Aborted | Phase::Failed(_))
    }

    /// A one-line description ("cycle 3 of 30, P4").
    pub fn describe(&self) -> String {
        match &self.phase {
            Phase::Preparing => "pre-flight".into(),
            Phase::Approaching => "moving to the start".into(),
            Phase::Running => match self.pose {
                Some(p) => format!("cycle {} of {}, {}", self.cycle, self.cycles, POSE_NAMES[p]),
                None => format!("cycle {} of {}", self.cycle, self.cycles),
            },
            Phase::Done => "done".into(),
            Phase::Aborted => "aborted".into(),
            Phase::Failed(why) => format!("failed: {why}"),
        }
    }
}

/// Why a measurement ended without results.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeasureError {
    /// Refused before anything moved.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// Aborted by the operator.
    #[error("aborted")]
    Aborted,
    /// A move failed or was refused, or the arm did not settle.
    #[error("{0}")]
    Failed(String),
}

/// One recorded instant of a path test.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TrackSample {
    /// Time since the cycle's path started, s of motion clock.
    pub t_s: f64,
    /// Commanded joints, rad.
    pub commanded_q: Vec<f64>,
    /// Measured joints, rad.
    pub measured_q: Vec<f64>,
}

/// What a path test recorded.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PathRecording {
    /// The test.
    pub plan: PathTestPlan,
    /// The samples of each cycle.
    pub cycles: Vec<Vec<TrackSample>>,
}

impl PathRecording {
    /// The commanded TCP path (of the first cycle) and every cycle's attained TCP path, mm.
    pub fn tcp_paths_mm(&self, model: &RobotModel) -> (Vec<[f64; 3]>, Vec<Vec<[f64; 3]>>) {
        let mm = |q: &[f64]| model.tcp_isometry(q).translation.vector.map(|v| v * 1000.0).into();
        let commanded = self.cycles.first().map_or_else(Vec::new, |c| c.iter().map(|s| mm(&s.commanded_q)).collect());
        let attained = self.cycles.iter().map(|c| c.iter().map(|s| mm(&s.measured_q)).collect()).collect();
        (commanded, attained)
    }

    /// The path figures, with the cornering deviations of a path that has corners.
    pub fn figures(&self, model: &RobotModel) -> Result<PathFigures, PathFigureError> {
        let (commanded, attained) = self.tcp_paths_mm(model);
        let corners = path_figures::corner_deviations(&self.plan.legs_mm(), &attained);
        Ok(path_figures::compute(&commanded, &attained, self.plan.points)?.with_corners(&corners))
    }
}

/// A measurement running on its own thread. Dropping it aborts the run.
pub struct MeasureRun<T> {
    progress: Arc<ArcSwap<MeasureProgress>>,
    abort: Arc<AtomicBool>,
    join: Option<JoinHandle<Result<T, MeasureError>>>,
}

impl<T> std::fmt::Debug for MeasureRun<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeasureRun").field("progress", &self.progress.load()).finish()
    }
}

impl<T: Send + 'static> MeasureRun<T> {
    fn spawn(
        cycles: usize,
        work: impl FnOnce(&Ctx) -> Result<T, MeasureError> + Send + 'static,
        backend: Arc<dyn RobotBackend>,
        model: RobotModel,
    ) -> std::io::Result<Self> {
        let progress = Arc::new(ArcSwap::from_pointee(MeasureProgress {
            phase: Phase::Preparing,
            cycle: 0,
            cycles,
            pose: None,
            fraction: 0.0,
            attained: Vec::new(),
            stop_failed: None,
        }));
        let abort = Arc::new(AtomicBool::new(false));
        let ctx = Ctx { backend, model, abort: Arc::clone(&abort), progress: Arc::clone(&progress) };
        let join = std::thread::Builder::new().name("parol6-measure".into()).spawn(move || {
            let result = work(&ctx);
            let phase = match &result {
                Ok(_) => Phase::Done,
                Err(MeasureError::Aborted) => Phase::Aborted,
                Err(e) => Phase::Failed(e.to_string()),
            };
            ctx.publish(|p| {
                if phase == Phase::Done {
                    p.fraction = 1.0;
                }
                p.phase = phase;
            });
            result
        })?;
        Ok(Self { progress, abort, join: Some(join) })
    }

    /// The latest progress.
    pub fn progress(&self) -> Arc<MeasureProgress> {
        self.progress.load_full()
    }

    /// Stops the arm and ends the run (the thread ends within a few milliseconds).
    pub fn abort(&self) {
        self.abort.store(true, Ordering::SeqCst);
    }

    /// True once the run has ended.
    pub fn is_finished(&self) -> bool {
        self.join.as_ref().is_none_or(JoinHandle::is_finished)
    }

    /// Waits for the end and returns the results.
    pub fn join(mut self) -> Result<T, MeasureError> {
        match self.join.take().map(JoinHandle::join) {
            Some(Ok(result)) => result,
            _ => Err(MeasureError::Failed("the measurement thread ended without a result".into())),
        }
    }
}

impl<T> Drop for MeasureRun<T> {
    fn drop(&mut self) {
        if let Some(j) = self.join.take() {
            self.abort.store(true, Ordering::SeqCst);
            let _ = j.join();
        }
    }
}

/// Starts the pose test of `plan` on `backend` (whose robot, tool included, is `model`).
pub fn start_pose_test(
    backend: Arc<dyn RobotBackend>,
    model: RobotModel,
    plan: PoseTestPlan,
) -> std::io::Result<MeasureRun<Vec<PoseSample>>> {
    MeasureRun::spawn(plan.cycles, move |ctx| ctx.pose_test(&plan), backend, model)
}

/// Starts the path test of `plan`; `tap` is the backend's sample tap, when it has one.
pub fn start_path_test(
    backend: Arc<dyn RobotBackend>,
    model: RobotModel,
    plan: PathTestPlan,
    tap: Option<Receiver<MotionSample>>,
) -> std::io::Result<MeasureRun<PathRecording>> {
    MeasureRun::spawn(plan.cycles, move |ctx| ctx.path_test(&plan, tap.as_ref()), backend, model)
}

struct Ctx {
    backend: Arc<dyn RobotBackend>,
    model: RobotModel,
    abort: Arc<AtomicBool>,
    progress: Arc<ArcSwap<MeasureProgress>>,
}

impl Ctx {
    fn publish(&self, f: impl FnOnce(&mut MeasureProgress)) {
        let mut p = self.progress.load().as_ref().clone();
        f(&mut p);
        self.progress.store(Arc::new(p));
    }

    fn aborted(&self) -> bool {
        self.abort.load(Ordering::SeqCst)
    }

    /// Sends STOP ([`stop_best_effort`]; a refused one is recorded in the progress) and
    /// returns the abort.
    fn stop_arm(&self) -> MeasureError {
        self.record_stop_failure(stop_best_effort(self.backend.as_ref(), "the measurement was aborted"));
        MeasureError::Aborted
    }

    fn record_stop_failure(&self, failure: Option<String>) {
        if let Some(failure) = failure {
            self.publish(|p| p.stop_failed = Some(failure));
        }
    }

    /// Runs `program`, calling `tick` every [`TICK`] while it runs.
    fn run(&self, program: Program, tick: &mut dyn FnMut()) -> Result<RunProgress, MeasureError> {
        let runner =
            ProgramRunner::start(Arc::clone(&self.backend), self.model.clone(), program, RunOptions::default())
                .map_err(|e| MeasureError::Failed(format!("cannot start the program thread: {e}")))?;
        while !runner.is_finished() {
            if self.aborted() {
                runner.abort();
                self.record_stop_failure(runner.join().stop_failed);
                return Err(self.stop_arm());
            }
            std::thread::sleep(TICK);
            tick();
        }
        let done = runner.join();
        self.record_stop_failure(done.stop_failed.clone());
        match &done.state {
            RunState::Done => Ok(done),
            RunState::Failed(why) => Err(MeasureError::Failed(format!("{}: {why}", done.name))),
            other => Err(MeasureError::Failed(format!("{}: ended {other:?}", done.name))),
        }
    }

    /// Waits until the arm rests and the planner holds, then `settle_s` more of motion clock.
    fn settle(&self, settle_s: f64, tick: &mut dyn FnMut()) -> Result<(), MeasureError> {
        let t0 = Instant::now();
        let mut rest_since: Option<f64> = None;
        loop {
            if self.aborted() {
                return Err(self.stop_arm());
            }
            let s = self.backend.state();
            let resting = !s.moving && s.mode == PlannerMode::Hold;
            match (resting, rest_since) {
                (false, _) => rest_since = None,
                (true, None) => rest_since = Some(s.time_s),
                (true, Some(since)) if s.time_s - since >= settle_s => return Ok(()),
                _ => {}
            }
            if let Some(b) = &s.blocked {
                return Err(MeasureError::Failed(format!("the robot stopped accepting motion: {b}")));
            }
            if t0.elapsed() > SETTLE_TIMEOUT {
                return Err(MeasureError::Failed(format!(
                    "the arm did not settle within {} s",
                    SETTLE_TIMEOUT.as_secs()
                )));
            }
            std::thread::sleep(TICK);
            tick();
        }
    }

    /// The attained pose: FK of the measured joints (with this model's tool).
    fn attained(&self) -> PoseMm {
        PoseMm::from_isometry(&self.model.tcp_isometry(&self.backend.state().q))
    }

    fn pose_test(&self, plan: &PoseTestPlan) -> Result<Vec<PoseSample>, MeasureError> {
        plan.preflight(&self.model, &self.backend.state().commanded.q)?;
        self.publish(|p| p.phase = Phase::Approaching);
        // every cycle's P1 is approached from P2: so is the first
        self.run(plan.move_to(1), &mut || {})?;
        self.settle(plan.settle_s, &mut || {})?;
        let commanded = plan.cube.poses().map(|p| PoseMm::from_isometry(&p.isometry()));
        let mut out = Vec::with_capacity(plan.cycles * CYCLE_ORDER.len());
        let total = (plan.cycles * CYCLE_ORDER.len()) as f64;
        for cycle in 1..=plan.cycles {
            for (k, &pose) in CYCLE_ORDER.iter().enumerate() {
                self.publish(|p| {
                    p.phase = Phase::Running;
                    p.cycle = cycle;
                    p.pose = Some(pose);
                });
                self.run(plan.move_to(pose), &mut || {})?;
                self.settle(plan.settle_s, &mut || {})?;
                let sample =
                    PoseSample { cycle: cycle as u32, pose, commanded: commanded[pose], attained: self.attained() };
                out.push(sample);
                let done = ((cycle - 1) * CYCLE_ORDER.len() + k + 1) as f64 / total;
                self.publish(|p| {
                    p.attained.push(sample);
                    p.fraction = done;
                });
            }
        }
        Ok(out)
    }

    fn path_test(
        &self,
        plan: &PathTestPlan,
        tap: Option<&Receiver<MotionSample>>,
    ) -> Result<PathRecording, MeasureError> {
        plan.preflight(&self.model, &self.backend.state().commanded.q)?;
        self.publish(|p| p.phase = Phase::Approaching);
        self.run(plan.approach(), &mut || {})?;
        self.settle(PATH_SETTLE_S, &mut || {})?;
        let mut cycles = Vec::with_capacity(plan.cycles);
        for cycle in 1..=plan.cycles {
            self.publish(|p| {
                p.phase = Phase::Running;
                p.cycle = cycle;
            });
            if let Some(rx) = tap {
                while rx.try_recv().is_ok() {}
            }
            let mut raw: Vec<(f64, Vec<f64>, Vec<f64>)> = Vec::new();
            let mut last_seq = None;
            let mut record = || match tap {
                Some(rx) => {
                    while let Ok(s) = rx.try_recv() {
                        if raw.last().is_none_or(|l| s.time_s - l.0 >= RECORD_PERIOD_S) {
                            raw.push((s.time_s, s.commanded.q, s.measured_q));
                        }
                    }
                }
                None => {
                    let s = self.backend.state();
                    if last_seq != Some(s.seq) {
                        last_seq = Some(s.seq);
                        raw.push((s.time_s, s.commanded.q.clone(), s.q.clone()));
                    }
                }
            };
            let done = self.run(plan.cycle(), &mut record)?;
            self.settle(PATH_SETTLE_S, &mut record)?;
            record();
            let start = done.clock_s.0;
            let samples: Vec<TrackSample> = raw
                .into_iter()
                .filter(|(t, _, _)| *t >= start - 1e-9)
                .map(|(t, c, m)| TrackSample { t_s: t - start, commanded_q: c, measured_q: m })
                .collect();
            cycles.push(samples);
            if let Some(back) = plan.return_from_end() {
                self.run(Program::from_steps("back to the start", vec![back]), &mut || {})?;
                self.settle(PATH_SETTLE_S, &mut || {})?;
            }
            self.publish(|p| p.fraction = cycle as f64 / plan.cycles as f64);
        }
        Ok(PathRecording { plan: *plan, cycles })
    }
}

#[cfg(test)]
mod tests;

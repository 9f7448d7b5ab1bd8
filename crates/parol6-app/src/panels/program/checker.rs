//! The program's loading, pre-flight and planned path, off the UI thread: each request (open a
//! file, check the program from where the arm stands) runs on its own worker thread and
//! answers through a bounded channel of one; the panel polls it once a frame and shows its
//! progress. A newer request supersedes an older one: dropping a [`CheckJob`] cancels its check
//! at the next step, and its answer is never read.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, RecvTimeoutError, TryRecvError, bounded};
use parol6_core::RobotModel;
use parol6_core::program::Program;
use parol6_core::program::check::{CheckOptions, CheckProgress, CheckStage, CheckStatus, CheckedProgram, check_shared};
use parol6_core::program::compile::StepAction;
use parol6_core::program::files::{FormatContext, read_program};
use parol6_core::program::gcode::AbcChoice;

use crate::viewport::{PathOverlay, PathPointStatus};

/// At most this many points of the planned path are drawn (a longer path is thinned evenly in
/// time, one strip, plus its last point): the 3D view projects them every frame.
pub const MAX_OVERLAY_POINTS: usize = 100_000;

/// What a worker answers.
pub(super) struct Checked {
    /// The program read from a file (a load request), owned for the editor.
    pub loaded: Option<Program>,
    /// The check.
    pub checked: Arc<CheckedProgram>,
    /// The planned TCP path for the 3D view.
    pub overlay: Arc<PathOverlay>,
    /// Wall time of the whole request, s.
    pub seconds: f64,
}

/// A request in flight.
pub(super) struct CheckJob {
    /// The file being read (a load request), else `None`.
    pub file: Option<PathBuf>,
    /// The program being checked (`None` while a file is read).
    program: Option<Arc<Program>>,
    start_q: Vec<f64>,
    opts: CheckOptions,
    progress: Arc<CheckProgress>,
    rx: Receiver<Result<Checked, String>>,
    /// When it was asked for.
    pub started: Instant,
}

impl Drop for CheckJob {
    fn drop(&mut self) {
        // superseded or finished: a check still running stops at its next step
        self.progress.cancel();
    }
}

impl CheckJob {
    /// Checks `program` from `start_q` on a worker.
    pub fn check(
        model: &RobotModel,
        program: Arc<Program>,
        start_q: Vec<f64>,
        opts: CheckOptions,
    ) -> std::io::Result<Self> {
        let (model, p, q) = (model.clone(), Arc::clone(&program), start_q.clone());
        Self::spawn(None, Some(program), start_q, opts, move |progress| {
            check_and_plan(&model, &p, &q, opts, progress).map(|(checked, overlay)| (None, checked, overlay))
        })
    }

    /// Reads the program file `path` (G-code A B C by `abc` unless its header says), then
    /// checks it from `start_q`, on a worker.
    pub fn load(
        model: &RobotModel,
        path: &Path,
        abc: AbcChoice,
        start_q: Vec<f64>,
        opts: CheckOptions,
    ) -> std::io::Result<Self> {
        let (model, file, q) = (model.clone(), path.to_path_buf(), start_q.clone());
        Self::spawn(Some(path.to_path_buf()), None, start_q, opts, move |progress| {
            let fctx = FormatContext { abc, ..FormatContext::new(&model, &q) };
            let program = read_program(&file, &fctx).map_err(|e| e.to_string())?;
            let shared = Arc::new(program.clone());
            check_and_plan(&model, &shared, &q, opts, progress)
                .map(|(checked, overlay)| (Some(program), checked, overlay))
        })
    }

    fn spawn(
        file: Option<PathBuf>,
        program: Option<Arc<Program>>,
        start_q: Vec<f64>,
        opts: CheckOptions,
        work: impl FnOnce(&CheckProgress) -> Result<(Option<Program>, CheckedProgram, PathOverlay), String> + Send + 'static,
    ) -> std::io::Result<Self> {
        let (tx, rx) = bounded(1);
        let progress = Arc::new(CheckProgress::default());
        let p = Arc::clone(&progress);
        let started = Instant::now();
        crate::background::spawn("parol6-program-check", move || {
            let answer = work(&p).map(|(loaded, checked, overlay)| Checked {
                loaded,
                checked: Arc::new(checked),
                overlay: Arc::new(overlay),
                seconds: started.elapsed().as_secs_f64(),
            });
            // a superseded request's answer is not wanted: nobody reads it, and the channel
            // (bounded, one) never blocks this send
            if !p.is_cancelled() && tx.try_send(answer).is_err() {
                p.cancel();
            }
        })?;
        Ok(Self { file, program, start_q, opts, progress, rx, started })
    }

    /// True when this job checks `program` from `start_q` with `opts`.
    pub fn is_for(&self, program: &Arc<Program>, start_q: &[f64], opts: CheckOptions) -> bool {
        self.program.as_ref().is_some_and(|p| Arc::ptr_eq(p, program)) && self.start_q == start_q && self.opts == opts
    }

    /// Where the check is.
    pub fn stage(&self) -> CheckStage {
        self.progress.stage()
    }

    /// The answer once it has arrived (`None`: still working).
    pub fn poll(&self) -> Option<Result<Checked, String>> {
        match self.rx.try_recv() {
            Ok(answer) => Some(answer),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err("the program check stopped".into())),
        }
    }

    /// Waits at most `timeout` for the answer (headless rendering, which wants the result in
    /// its first frames).
    pub fn wait(&self, timeout: Duration) -> Option<Result<Checked, String>> {
        match self.rx.recv_timeout(timeout) {
            Ok(answer) => Some(answer),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => Some(Err("the program check stopped".into())),
        }
    }
}

/// The check and the planned path; `Err` when cancelled.
fn check_and_plan(
    model: &RobotModel,
    program: &Arc<Program>,
    start_q: &[f64],
    opts: CheckOptions,
    progress: &CheckProgress,
) -> Result<(CheckedProgram, PathOverlay), String> {
    let checked = check_shared(model, program, start_q, opts, progress).ok_or("superseded")?;
    let overlay = planned_path(model, &checked);
    Ok((checked, overlay))
}

/// The planned TCP path: every pre-flight sample of every motion step, one strip per step (a
/// longer path: every n-th sample, at most [`MAX_OVERLAY_POINTS`], in one strip), coloured by the status
/// of the pre-flight's last checked point at or before it in the same step (an error in a step
/// without checked points, e.g. an unreachable one, colours the whole step).
pub fn planned_path(model: &RobotModel, checked: &CheckedProgram) -> PathOverlay {
    let mut overlay = PathOverlay::default();
    let report = &checked.report;
    let to_path = |s: CheckStatus| match s {
        CheckStatus::Ok => PathPointStatus::Ok,
        CheckStatus::Warning => PathPointStatus::Warning,
        CheckStatus::Error => PathPointStatus::Error,
    };
    // the worst problem of each program step (one pass over the issues)
    let mut worst = vec![None; checked.program.steps.len()];
    for i in &report.issues {
        if let Some(w) = worst.get_mut(i.move_index) {
            *w = (*w).max(Some(i.severity));
        }
    }
    let samples: usize = checked
        .compiled
        .iter()
        .map(|c| match &c.action {
            StepAction::Motion(t) => t.samples().len(),
            _ => 0,
        })
        .sum();
    let stride = samples.div_ceil(MAX_OVERLAY_POINTS).max(1);
    // the checked points are in move order, and in time within a move
    let path = &report.path;
    let sorted = path.is_sorted_by_key(|p| p.move_index);
    let mut counted = 0usize;
    for c in &checked.compiled {
        let StepAction::Motion(traj) = &c.action else { continue };
        let points: Vec<_> = if sorted {
            let lo = path.partition_point(|p| p.move_index < c.steps.start);
            let hi = path.partition_point(|p| p.move_index <= c.steps.start);
            path[lo..hi].iter().collect()
        } else {
            path.iter().filter(|p| p.move_index == c.steps.start).collect()
        };
        let step_worst = worst.get(c.steps.clone()).and_then(|w| w.iter().flatten().max().copied());
        if stride == 1 {
            overlay.break_strip();
        }
        for (k, q) in traj.samples().iter().enumerate() {
            counted += 1;
            if !(counted - 1).is_multiple_of(stride) && counted != samples {
                continue;
            }
            let t = k as f64 * traj.dt_s();
            let status = match points.iter().rev().find(|p| p.t_s <= t + 1e-9) {
                Some(p) => to_path(p.status),
                None => step_worst.map_or(PathPointStatus::Ok, |s| to_path(s.into())),
            };
            let p = model.tcp_isometry(q).translation.vector;
            overlay.push([p.x as f32, p.y as f32, p.z as f32], status);
        }
    }
    overlay
}

/// Why F5 starts nothing (Run is only greyed, and the key gives no other answer): the first
/// pre-flight error with its step and line and how many there are, the check's own failure
/// (`check_error`), or that the pre-flight waits for the arm to stand still.
pub(super) fn run_refusal(name: &str, checked: Option<&CheckedProgram>, check_error: Option<&str>) -> String {
    use parol6_core::program::check::Severity;
    if let Some(e) = check_error {
        return format!("Cannot run {name}: the pre-flight failed: {e}");
    }
    let Some(r) = checked else {
        return format!("Cannot run {name}: the pre-flight runs once the arm stands still");
    };
    let errors = r.issues.iter().filter(|i| i.severity == Severity::Error).count();
    match r.first_error() {
        Some(first) if errors == 1 => format!("Cannot run {name}: pre-flight found 1 error: {first}"),
        Some(first) => format!("Cannot run {name}: pre-flight found {errors} errors, the first: {first}"),
        None => format!("Cannot run {name}: the pre-flight is not clean"),
    }
}

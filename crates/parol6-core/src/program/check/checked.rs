//! A program checked once: [`CheckedProgram`] (the program, the start joints it was checked
//! from, its compiled steps at the pre-flight period and the report), shared by the path
//! overlay, the program panel and the runner, and [`CheckProgress`], which a check publishes
//! while it runs on a worker thread and through which a newer request cancels it.

use std::ops::Deref;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use super::{CheckIssue, CheckOptions, CheckReport, Severity};
use crate::program::Program;
use crate::program::compile::CompiledStep;

/// Start joints within this of the checked ones (every joint, rad) count as the same start: the
/// runner reuses the check instead of checking again. Far below anything a check can tell apart
/// (1e-9 rad moves the PAROL6's TCP by under 1 nm), above the rounding of joint values that pass
/// through a backend's state unchanged.
pub const RECHECK_TOLERANCE_RAD: f64 = 1e-9;

/// A program checked from one start pose.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedProgram {
    /// The program checked.
    pub program: Arc<Program>,
    /// The joints it was checked from, rad.
    pub start_q: Vec<f64>,
    /// How it was checked.
    pub opts: CheckOptions,
    /// Its compiled steps at the pre-flight period (what the path overlay draws); empty when the
    /// program does not compile.
    pub compiled: Vec<CompiledStep>,
    /// The pre-flight report.
    pub report: CheckReport,
}

/// Serialised as its report (`parol6 program check --json`).
impl serde::Serialize for CheckedProgram {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.report.serialize(serializer)
    }
}

impl Deref for CheckedProgram {
    type Target = CheckReport;

    fn deref(&self) -> &CheckReport {
        &self.report
    }
}

impl CheckedProgram {
    /// True when this check holds for a run of `program` from `start_q` with `opts`: the same
    /// program (the same shared value), the same speed override and every start joint within
    /// [`RECHECK_TOLERANCE_RAD`].
    pub fn holds_for(&self, program: &Arc<Program>, start_q: &[f64], opts: CheckOptions) -> bool {
        Arc::ptr_eq(&self.program, program) && self.opts == opts && self.is_from(start_q)
    }

    /// True when `start_q` is within [`RECHECK_TOLERANCE_RAD`] of the checked start.
    pub fn is_from(&self, start_q: &[f64]) -> bool {
        self.start_q.len() == start_q.len()
            && self.start_q.iter().zip(start_q).all(|(a, b)| (a - b).abs() <= RECHECK_TOLERANCE_RAD)
    }

    /// A check that did not finish (the report's one error says so).
    pub(super) fn cancelled(program: Arc<Program>, start_q: &[f64], opts: CheckOptions) -> Self {
        let issue = CheckIssue {
            line: 0,
            move_index: 0,
            severity: Severity::Error,
            message: "the check was cancelled".into(),
            t_s: None,
            tcp_mm: None,
        };
        let report = CheckReport {
            ok: false,
            moves: program.steps.len(),
            duration_s: 0.0,
            issues: vec![issue],
            plan: Vec::new(),
            path: Vec::new(),
            torque_warnings: 0,
        };
        Self { program, start_q: start_q.to_vec(), opts, compiled: Vec::new(), report }
    }
}

/// Where a running check is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CheckStage {
    /// Not started yet.
    Waiting,
    /// Compiling: `done` of `total` program steps planned.
    Planning {
        /// Steps planned.
        done: usize,
        /// Steps in the program.
        total: usize,
    },
    /// Walking the planned moves: the steps before `done` are checked.
    Checking {
        /// Steps checked.
        done: usize,
        /// Steps in the program.
        total: usize,
    },
}

/// The progress of one check, shared between the thread that checks and the one that shows it
/// (lock-free); [`Self::cancel`] stops the check at its next step.
#[derive(Debug, Default)]
pub struct CheckProgress {
    total: AtomicUsize,
    planned: AtomicUsize,
    checked: AtomicUsize,
    /// 0 waiting, 1 planning, 2 checking.
    stage: AtomicUsize,
    cancel: AtomicBool,
}

impl CheckProgress {
    /// Asks the check to stop (it returns `None` at its next step).
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// True once [`Self::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Where the check is.
    pub fn stage(&self) -> CheckStage {
        let total = self.total.load(Ordering::Relaxed);
        match self.stage.load(Ordering::Relaxed) {
            1 => CheckStage::Planning { done: self.planned.load(Ordering::Relaxed), total },
            2 => CheckStage::Checking { done: self.checked.load(Ordering::Relaxed), total },
            _ => CheckStage::Waiting,
        }
    }

    /// A check of `total` program steps starts planning.
    pub(super) fn start(&self, total: usize) {
        self.total.store(total, Ordering::Relaxed);
        self.stage.store(1, Ordering::Relaxed);
    }

    /// `done` steps are planned; false once cancelled.
    pub(super) fn planned(&self, done: usize) -> bool {
        self.planned.store(done, Ordering::Relaxed);
        !self.is_cancelled()
    }

    /// The steps before `done` are checked; false once cancelled.
    pub(super) fn checked(&self, done: usize) -> bool {
        self.stage.store(2, Ordering::Relaxed);
        self.checked.store(done, Ordering::Relaxed);
        !self.is_cancelled()
    }
}

//! Pre-flight of a whole program before anything moves: the program is compiled from the start
//! pose at the pre-flight sample period and every planned move goes through the checks; the
//! report lists every problem with its source line, step and where along the move, and the
//! planned duration.

use serde::Serialize;

use super::Program;
use super::compile::{CompileOptions, StepAction, compile};
use crate::model::RobotModel;

/// How bad a problem is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Runs, but look at it.
    Warning,
    /// Refused: the program does not run.
    Error,
}

/// How to check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckOptions {
    /// Every step's speed × this (0 < f ≤ 1), as the run will use it.
    pub speed_override: f64,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self { speed_override: 1.0 }
    }
}

/// One problem.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckIssue {
    /// 1-based source line (0: unknown).
    pub line: usize,
    /// 0-based step index.
    #[serde(rename = "move")]
    pub move_index: usize,
    /// Error or warning.
    pub severity: Severity,
    /// What and where.
    pub message: String,
    /// Time along the move, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_s: Option<f64>,
    /// TCP position there, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tcp_mm: Option<[f64; 3]>,
}

/// The result of a pre-flight.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckReport {
    /// No errors.
    pub ok: bool,
    /// Number of program steps.
    pub moves: usize,
    /// Planned duration, s (waits for inputs not counted).
    pub duration_s: f64,
    /// Every problem found.
    pub issues: Vec<CheckIssue>,
}

impl CheckReport {
    /// The first error, as a one-line message with its step and line.
    pub fn first_error(&self) -> Option<String> {
        self.issues
            .iter()
            .find(|i| i.severity == Severity::Error)
            .map(|i| format!("step {} (line {}): {}", i.move_index + 1, i.line, i.message))
    }
}

/// Checks `program` from joints `start_q`.
pub fn check_program(model: &RobotModel, program: &Program, start_q: &[f64], opts: CheckOptions) -> CheckReport {
    let mut issues = Vec::new();
    let mut duration_s = 0.0;
    if let Err(e) = model.limits.check(start_q) {
        issues.push(CheckIssue {
            line: 0,
            move_index: 0,
            severity: Severity::Error,
            message: format!("the start pose is outside the limits: {e}"),
            t_s: None,
            tcp_mm: None,
        });
    }
    match compile(model, program, start_q, CompileOptions { speed_override: opts.speed_override, ..CompileOptions::PREFLIGHT }) {
        Ok(compiled) => {
            for c in &compiled {
                duration_s += c.duration_s();
                if let StepAction::Motion(_) = &c.action {
                    // the motion checks come with the pre-flight checker
                }
            }
        }
        Err(e) => issues.push(CheckIssue {
            line: e.line,
            move_index: e.index,
            severity: Severity::Error,
            message: e.message,
            t_s: e.t_s,
            tcp_mm: e.tcp_mm,
        }),
    }
    let ok = !issues.iter().any(|i| i.severity == Severity::Error);
    CheckReport { ok, moves: program.steps.len(), duration_s, issues }
}

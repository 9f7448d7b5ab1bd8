//! Pre-flight of a whole program before anything moves: the program is compiled from the start
//! pose at the pre-flight sample period and every planned move goes through the checks; the
//! report lists every problem with its source line, step and where along the move, and the
//! planned duration.

use std::sync::Arc;

use serde::Serialize;

use super::compile::{CompileOptions, CompileStop, CompiledStep, StepAction, compile_observed};
use super::torques::{TorqueWarning, torque_warning_stream};
use super::{PoseMm, Program};
use crate::ik::ConfigRule;
use crate::model::RobotModel;
use crate::motion::MotionCaps;
use crate::motion::preflight::{MoveKind, PlannedMove, Preflight, PreflightReport};

pub use crate::motion::preflight::{CheckStatus, CheckedPoint, Severity};
pub use checked::{CheckProgress, CheckStage, CheckedProgram, RECHECK_TOLERANCE_RAD};

mod checked;

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

/// One planned step as the pre-flight saw it (every compiled step, motions and the rest).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlannedStep {
    /// 0-based index of its first program step.
    pub index: usize,
    /// How many program steps it covers (a blended chain of lines covers several).
    pub steps: usize,
    /// 1-based source line (0: unknown).
    pub line: usize,
    /// Step type of its first step (`move_pose`, `move_l`, `dwell`, …).
    pub kind: &'static str,
    /// The arm configuration at its end (`front/up/no-flip`; `any` for a part on its border,
    /// e.g. the wrist at J5 = 0); `None` for a robot without named configurations.
    pub config: Option<String>,
    /// TCP pose where it starts: mm, our roll / pitch / yaw in deg (to 0.0001 mm and °).
    pub start_tcp: PoseMm,
    /// TCP pose where it ends.
    pub end_tcp: PoseMm,
    /// Planned duration, s.
    pub duration_s: f64,
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
    /// Every planned step, in order (empty when the program does not compile).
    pub plan: Vec<PlannedStep>,
    /// How many of the warnings are joint torques over the motor limits (inverse dynamics along
    /// the compiled trajectory, [`super::torques::torque_warnings`]): the window asks before it
    /// runs such a program.
    #[serde(skip_serializing_if = "is_zero")]
    pub torque_warnings: usize,
    /// The checked TCP path, coloured by status (for the 3D view; not in the JSON).
    #[serde(skip)]
    pub path: Vec<CheckedPoint>,
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

/// Checks `program` from joints `start_q`: the [`CheckedProgram`] (start joints, the compiled
/// steps, the report) that the path overlay, the program panel and
/// [`ProgramRunner::start_checked`](super::runner::ProgramRunner::start_checked) share.
pub fn check_program(model: &RobotModel, program: &Program, start_q: &[f64], opts: CheckOptions) -> CheckedProgram {
    let program = Arc::new(program.clone());
    match check_shared(model, &program, start_q, opts, &CheckProgress::default()) {
        Some(checked) => checked,
        // never: nothing cancels this progress
        None => CheckedProgram::cancelled(program, start_q, opts),
    }
}

/// [`check_program`] of a shared program, publishing its progress in `progress` (steps
/// planned, then steps checked) and stopping early (`None`) once [`CheckProgress::cancel`] is
/// called: a newer request supersedes this one.
pub fn check_shared(
    model: &RobotModel,
    program: &Arc<Program>,
    start_q: &[f64],
    opts: CheckOptions,
    progress: &CheckProgress,
) -> Option<CheckedProgram> {
    let (compiled, report) = check_report(model, program, start_q, opts, progress)?;
    Some(CheckedProgram { program: Arc::clone(program), start_q: start_q.to_vec(), opts, compiled, report })
}

/// The compiled steps (empty when the program does not compile) and the report; `None` when
/// cancelled.
fn check_report(
    model: &RobotModel,
    program: &Program,
    start_q: &[f64],
    check_opts: CheckOptions,
    progress: &CheckProgress,
) -> Option<(Vec<CompiledStep>, CheckReport)> {
    progress.start(program.steps.len());
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
    let opts = CompileOptions { speed_override: check_opts.speed_override, ..CompileOptions::PREFLIGHT };
    let mut path = Vec::new();
    let mut plan = Vec::new();

    let mut kept = Vec::new();
    let mut torque_warnings = 0;
    let checker = Preflight::new(model, &MotionCaps::of(model), &program.keep_out);
    let Pipeline { compiled, walked, torques } =
        compile_and_walk(model, program, start_q, opts, checker.as_ref().ok(), progress);
    match compiled {
        Err(CompileStop::Cancelled) => return None,
        Ok(compiled) => {
            plan = planned_steps(model, start_q, &compiled);
            for c in &compiled {
                issues.extend(c.warnings.iter().map(|w| CheckIssue {
                    line: c.line,
                    move_index: c.steps.start,
                    severity: Severity::Warning,
                    message: w.clone(),
                    t_s: None,
                    tcp_mm: None,
                }));
            }
            duration_s = compiled.iter().map(|c| c.duration_s()).sum();
            match checker {
                Ok(_) => {
                    let report = walked?;
                    path = report.path;
                    issues.extend(report.issues.into_iter().map(|i| CheckIssue {
                        line: i.line,
                        move_index: i.move_index,
                        severity: i.severity,
                        message: without_place_prefix(&i.message),
                        t_s: Some(i.t_s),
                        tcp_mm: Some(i.tcp_mm),
                    }));
                }
                Err(e) => issues.push(CheckIssue {
                    line: 0,
                    move_index: 0,
                    severity: Severity::Error,
                    message: format!("keep-out shapes: {e}"),
                    t_s: None,
                    tcp_mm: None,
                }),
            }
            let before = issues.len();
            let (warnings, dropped) =
                torques.unwrap_or_else(|| super::torques::torque_warnings(model, &compiled, start_q));
            issues.extend(torque_issues(&warnings, dropped));
            torque_warnings = issues.len() - before;

            kept = compiled;
        }
        Err(CompileStop::Error(e)) => issues.push(CheckIssue {
            line: e.line,
            move_index: e.index,
            severity: Severity::Error,
            message: e.message,
            t_s: e.t_s,
            tcp_mm: e.tcp_mm,
        }),
    }
    let ok = !issues.iter().any(|i| i.severity == Severity::Error);
    Some((kept, CheckReport { ok, moves: program.steps.len(), duration_s, issues, plan, path, torque_warnings }))
}

/// Steps compiled ahead of the pre-flight walk and of the torque pass (the channels between
/// the threads): about a minute of planned raster, a few MB at most (the steps share their
/// trajectories with the compiled program, which is kept anyway). Deep enough that a thread the
/// host takes away for a time slice need not stall the compile (256 held ~4 ms of work; on a
/// host loaded 9-fold neither depth measured faster than the single compile thread before).
const PIPELINE_MOVES: usize = 8192;

/// What [`compile_and_walk`] found.
struct Pipeline {
    /// The compiled steps, or why not.
    compiled: Result<Vec<CompiledStep>, CompileStop>,
    /// The walk's report: `None` when cancelled or without a checker.
    walked: Option<PreflightReport>,
    /// The torque warnings and how many were left out, when the torque pass ran beside the
    /// compile (`None`: not run, the caller runs it after the compile).
    torques: Option<(Vec<TorqueWarning>, usize)>,
}

/// Compiles `program` and, at the same time, walks its moves through `checker` and runs the
/// torque pass over its steps: each on its own thread, taking every step as soon as it is
/// compiled, so a long program's check takes about the longest of the three, not their sum
/// (the torque pass took 29 % of a 200 000-line check after the walk). A panic of either
/// thread is raised here.
fn compile_and_walk(
    model: &RobotModel,
    program: &Program,
    start_q: &[f64],
    opts: CompileOptions,
    checker: Option<&Preflight>,
    progress: &CheckProgress,
) -> Pipeline {
    let plan_only = |observe: &mut dyn FnMut(&CompiledStep) -> bool| {
        compile_observed(model, program, start_q, opts, &mut |c| observe(c) && progress.planned(c.steps.end))
    };
    let Some(checker) = checker else {
        return Pipeline { compiled: plan_only(&mut |_| true), walked: None, torques: None };
    };
    // progress of the walk in program steps: those of the moves checked
    let walk_observer = |mv: &PlannedMove| progress.checked(mv.index + 1);
    let (tx, rx) = crossbeam_channel::bounded::<PlannedMove>(PIPELINE_MOVES);
    let (torque_tx, torque_rx) = crossbeam_channel::bounded::<CompiledStep>(PIPELINE_MOVES);
    std::thread::scope(|scope| {
        let torquer = torque_warning_stream(model, start_q).and_then(|mut stream| {
            let pass = move || {
                for step in torque_rx {
                    stream.step(&step);
                }
                stream.into_warnings()
            };
            std::thread::Builder::new().name("parol6-torques".into()).spawn_scoped(scope, pass).ok()
        });
        // without the torque thread (no limits, or no thread) nobody takes the steps
        let torque_tx = torquer.is_some().then_some(torque_tx);
        let walker = std::thread::Builder::new()
            .name("parol6-preflight".into())
            .spawn_scoped(scope, move || checker.check_stream(rx, &mut |mv| walk_observer(mv)));
        match walker {
            Ok(walker) => {
                // a walk that stopped (cancelled) takes no more moves; the compile then stops too
                let compiled = plan_only(&mut |c| {
                    planned_move(c).is_none_or(|mv| tx.send(mv).is_ok())
                        && torque_tx.as_ref().is_none_or(|t| t.send(c.clone()).is_ok())
                });
                drop(tx);
                drop(torque_tx);
                let walked = joined(walker);
                let torques = torquer.map(joined);
                Pipeline { compiled, walked, torques }
            }
            // no second thread: one after the other
            Err(_) => {
                drop(torque_tx);
                // the torque thread saw no step: its result is not the program's
                if let Some(h) = torquer {
                    joined(h);
                }
                match plan_only(&mut |_| true) {
                    Ok(compiled) => {
                        let moves = compiled.iter().filter_map(planned_move);
                        let walked = checker.check_stream(moves, &mut |mv| walk_observer(mv));
                        Pipeline { compiled: Ok(compiled), walked, torques: None }
                    }
                    Err(stop) => Pipeline { compiled: Err(stop), walked: None, torques: None },
                }
            }
        }
    })
}

/// The result of a scoped thread; its panic is raised here.
fn joined<T>(handle: std::thread::ScopedJoinHandle<'_, T>) -> T {
    handle.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))
}

/// The move the pre-flight walks for a compiled motion step (`None` for the other steps).
fn planned_move(c: &CompiledStep) -> Option<PlannedMove> {
    let StepAction::Motion(t) = &c.action else { return None };
    Some(PlannedMove {
        index: c.steps.start,
        line: c.line,
        label: c.kind.to_string(),
        // a Cartesian move that does not move the joints (a line of no length, as the
        // commander's `MoveCart` to where the arm is) holds still: it is checked as the joint
        // move it is, so a singular pose is a warning there
        kind: if matches!(c.kind, "home" | "move_joints" | "move_pose") || holds_still(t) {
            MoveKind::Joint
        } else {
            MoveKind::Cartesian
        },
        trajectory: Arc::clone(t),
    })
}

/// No joint strays more than this from where a move starts for the move to count as holding
/// still, rad (0.0057°: a commander pose written to 0.001 mm and 0.001° of where the arm is).
const HOLDS_STILL_RAD: f64 = 1e-4;

/// True when no joint moves along the trajectory (beyond [`HOLDS_STILL_RAD`]).
fn holds_still(t: &crate::motion::trajectory::SampledTrajectory) -> bool {
    let samples = t.samples();
    samples
        .first()
        .is_none_or(|q0| samples.iter().all(|q| q.iter().zip(q0).all(|(a, b)| (a - b).abs() < HOLDS_STILL_RAD)))
}

/// A TCP pose for the plan: to 0.1 µm and 0.0001° (no float noise, no −0).
fn tcp_of(model: &RobotModel, q: &[f64]) -> PoseMm {
    let round = |v: f64| {
        let r = (v * 1e4).round() / 1e4;
        if r == 0.0 { 0.0 } else { r }
    };
    let p = PoseMm::from_isometry(&model.tcp_isometry(q));
    PoseMm { position_mm: p.position_mm.map(round), rpy_deg: p.rpy_deg.map(round) }
}

/// The plan's steps with their configuration and TCP poses at both ends.
///
/// A step's configuration is that of its end joints, which are where the next step starts: a
/// Cartesian next step worked it out while planning ([`CompiledStep::start_config`]), and a
/// step that does not move ends where the step before did; only the rest are solved here.
fn planned_steps(model: &RobotModel, start_q: &[f64], compiled: &[CompiledStep]) -> Vec<PlannedStep> {
    let mut from = start_q;
    let mut from_tcp = tcp_of(model, start_q);
    // the configuration of `from`, once known
    let mut from_config: Option<ConfigRule> = compiled.first().and_then(|c| c.start_config);
    compiled
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let still = c.end_q == from;
            let end_tcp = if still { from_tcp } else { PoseMm::from_isometry(&model.tcp_isometry(&c.end_q)) };
            let end_config = model.is_parol6.then(|| {
                let next = compiled.get(i + 1).and_then(|next| next.start_config);
                let known = if still { from_config.or(next) } else { next };
                known.unwrap_or_else(|| ConfigRule::of_start(model, &c.end_q))
            });
            let step = PlannedStep {
                index: c.steps.start,
                steps: c.steps.len(),
                line: c.line,
                kind: c.kind,
                config: end_config.map(|r| r.to_string()),
                start_tcp: from_tcp,
                end_tcp,
                duration_s: c.duration_s(),
            };
            from = &c.end_q;
            from_tcp = end_tcp;
            from_config = end_config;
            step
        })
        .collect()
}

/// The checker's message without its "line L, move M (kind): " prefix (the report carries the
/// line and the step in their own fields).
fn without_place_prefix(message: &str) -> String {
    match (message.starts_with("line "), message.find("): ")) {
        (true, Some(i)) => message[i + 3..].to_string(),
        _ => message.to_string(),
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// One warning per stretch where a joint's torque (inverse dynamics along the compiled
/// trajectory, the tool's mass included) exceeds its motor limit, naming the step and line.
fn torque_issues(warnings: &[TorqueWarning], dropped: usize) -> Vec<CheckIssue> {
    let mut out: Vec<CheckIssue> = warnings
        .iter()
        .map(|w| CheckIssue {
            line: w.line,
            move_index: w.step,
            severity: Severity::Warning,
            message: format!(
                "J{} torque {:.2} N·m exceeds its motor limit {:.2} N·m at t = {:.2} s of the program \
                 (over from {:.2} to {:.2} s): risk of lost steps, slow the step down or lighten the load",
                w.joint,
                w.peak_nm.abs(),
                w.limit_nm,
                w.peak_s,
                w.start_s,
                w.end_s
            ),
            t_s: None,
            tcp_mm: None,
        })
        .collect();
    if dropped > 0
        && let Some(last) = warnings.last()
    {
        out.push(CheckIssue {
            line: last.line,
            move_index: last.step,
            severity: Severity::Warning,
            message: format!("{dropped} more stretches of joint torque over the motor limits are not listed"),
            t_s: None,
            tcp_mm: None,
        });
    }
    out
}

#[cfg(test)]
mod tests;

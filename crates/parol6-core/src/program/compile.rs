//! Program steps → what a runner executes: every motion step becomes a planned joint
//! trajectory ([`SampledTrajectory`]) starting exactly where the previous one ended, at a
//! chosen sample period (1 ms to run on the 1 kHz simulation, 10 ms for pre-flight; the
//! path and its timing law are the same, only the sample density differs).
//!
//! Consecutive `move_l` steps with a `blend_mm` form one path with rounded corners; the
//! compiled step then covers all of them. Errors name the step (0-based), its source line, and
//! where along the move the problem lies.

use std::ops::Range;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};

use super::{GripperAction, Program, SpeedSettings, Step};
use crate::ik::{self, ConfigRule};
use crate::model::RobotModel;
use crate::motion::cartesian::{self, CartesianCaps, CartesianError};
use crate::motion::path::TcpPath;
use crate::motion::trajectory::SampledTrajectory;
use crate::motion::{IoCommand, MotionCaps, home_position};
use crate::profile::ProfileKind;

/// The PAROL6's Cartesian speed limit (ROBOT.md §5), mm/s.
pub const MAX_TCP_SPEED_MM_S: f64 = 200.0;
/// The slowest TCP speed a step may ask for, mm/s (ROBOT.md §5: 1 % of the maximum).
pub const MIN_TCP_SPEED_MM_S: f64 = 2.0;
/// The smallest joint speed fraction a step may ask for.
pub const MIN_JOINT_FRACTION: f64 = 0.01;
/// The most trajectory samples one program may plan to: a bound on memory (about 90 bytes a
/// sample) and planning time; 4 000 s of motion at 1 kHz.
pub const MAX_PLANNED_SAMPLES: usize = 4_000_000;
/// The longest dwell or input wait a step may ask for, s.
pub const MAX_WAIT_S: f64 = 3600.0;
/// Input wait when a step gives none, s.
pub const DEFAULT_INPUT_TIMEOUT_S: f64 = 10.0;

/// What a compiled step does.
#[derive(Debug, Clone, PartialEq)]
pub enum StepAction {
    /// Follow this joint trajectory (it starts where the previous motion ended).
    Motion(Arc<SampledTrajectory>),
    /// Hold still this long, s.
    Dwell(f64),
    /// Set an output or move the gripper.
    Io(IoCommand),
    /// Wait until `input` (1-based) reads `on`, at most `timeout_s`.
    WaitInput {
        /// 1-based input.
        input: u8,
        /// Level to wait for.
        on: bool,
        /// Give up after, s.
        timeout_s: f64,
    },
    /// Pause until the operator resumes (an optional pause only when the run says so).
    Pause {
        /// Only with optional pauses on.
        optional: bool,
    },
}

/// One executable step.
#[derive(Debug, Clone, PartialEq)]
pub struct CompiledStep {
    /// The program steps it covers (more than one for a blended `move_l` chain).
    pub steps: Range<usize>,
    /// 1-based source line of its first step (0: unknown).
    pub line: usize,
    /// Step type of its first step.
    pub kind: &'static str,
    /// What to do.
    pub action: StepAction,
    /// Joint values when it ends, rad.
    pub end_q: Vec<f64>,
    /// What was changed to make the step feasible (a time too short or a speed too high for
    /// the caps, stretched to the fastest the caps allow), in words naming both values.
    pub warnings: Vec<String>,
    /// The configuration rule of the joints it starts from ([`ConfigRule::of_start`]) where its
    /// planning worked it out (a Cartesian move keeps it; `None` for the other steps): the
    /// configuration the step before ends in, without solving it again.
    pub start_config: Option<ConfigRule>,
}

/// What compiling one step noted beside its action.
#[derive(Debug, Default)]
struct StepNotes {
    /// [`CompiledStep::warnings`].
    warnings: Vec<String>,
    /// [`CompiledStep::start_config`].
    start_config: Option<ConfigRule>,
}

impl CompiledStep {
    /// Planned duration, s (a wait for an input counts as 0).
    pub fn duration_s(&self) -> f64 {
        match &self.action {
            StepAction::Motion(t) => t.duration_s(),
            StepAction::Dwell(s) => *s,
            _ => 0.0,
        }
    }
}

/// Why a step cannot be compiled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("step {} (line {line}, {kind}): {message}", index + 1)]
pub struct CompileError {
    /// 0-based step index.
    pub index: usize,
    /// 1-based source line (0: unknown).
    pub line: usize,
    /// Step type.
    pub kind: &'static str,
    /// What is wrong, and where along the move.
    pub message: String,
    /// Time along the move, s, when the problem is at a point of it.
    pub t_s: Option<f64>,
    /// TCP position there, mm.
    pub tcp_mm: Option<[f64; 3]>,
}

/// How to compile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompileOptions {
    /// Sample period of the trajectories, s.
    pub dt_s: f64,
    /// Speed override: every step's speed × this (0 < f ≤ 1).
    pub speed_override: f64,
}

impl CompileOptions {
    /// Trajectories at the simulation's 1 kHz control rate, full speed.
    pub const RUN: Self = Self { dt_s: 0.001, speed_override: 1.0 };
    /// Trajectories at 100 Hz, as pre-flight checks them.
    pub const PREFLIGHT: Self = Self { dt_s: 0.01, speed_override: 1.0 };
}

/// Compiles `program` for `model` starting at joints `start_q`.
pub fn compile(
    model: &RobotModel,
    program: &Program,
    start_q: &[f64],
    opts: CompileOptions,
) -> Result<Vec<CompiledStep>, CompileError> {
    match compile_observed(model, program, start_q, opts, &mut |_: &CompiledStep| true) {
        Ok(steps) => Ok(steps),
        Err(CompileStop::Error(e)) => Err(e),
        // the observer never cancels
        Err(CompileStop::Cancelled) => Ok(Vec::new()),
    }
}

/// Why [`compile_observed`] stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum CompileStop {
    /// A step cannot be compiled.
    Error(CompileError),
    /// The observer asked to stop.
    Cancelled,
}

/// [`compile`], handing `observe` each compiled step as soon as it is compiled (its `steps.end`
/// program steps are then done); it returns false to stop (a newer request supersedes this one).
pub fn compile_observed(
    model: &RobotModel,
    program: &Program,
    start_q: &[f64],
    opts: CompileOptions,
    observe: &mut dyn FnMut(&CompiledStep) -> bool,
) -> Result<Vec<CompiledStep>, CompileStop> {
    let caps = MotionCaps::of(model);
    let mut out = Vec::with_capacity(program.steps.len());
    let mut q = start_q.to_vec();
    let mut planned = 0usize;
    let mut i = 0;
    while i < program.steps.len() {
        let (first, line) = (&program.steps[i].step, program.steps[i].line);
        let blend_end = blended_chain_end(program, i);
        let mut notes = StepNotes::default();
        let (action, covers) = if blend_end > i {
            let traj = compile_blended(model, program, i..blend_end + 1, &q, &caps, opts, &mut notes)
                .map_err(|e| CompileStop::Error(blended_error(model, program, i..blend_end + 1, &q, e)))?;
            (StepAction::Motion(traj), i..blend_end + 1)
        } else {
            let action = compile_one(model, first, &program.speed, &q, &caps, opts, &mut notes)
                .map_err(|e| CompileStop::Error(cartesian_error(i, line, first.kind(), e)))?;
            (action, i..i + 1)
        };
        if let StepAction::Motion(t) = &action {
            q = t.goal().to_vec();
            planned += t.samples().len();
            if planned > MAX_PLANNED_SAMPLES {
                return Err(CompileStop::Error(CompileError {
                    index: i,
                    line,
                    kind: first.kind(),
                    message: format!(
                        "the program plans to more than {MAX_PLANNED_SAMPLES} samples here; split it or make it faster"
                    ),
                    t_s: None,
                    tcp_mm: None,
                }));
            }
        }
        let step = CompiledStep {
            steps: covers.clone(),
            line,
            kind: first.kind(),
            action,
            end_q: q.clone(),
            warnings: notes.warnings,
            start_config: notes.start_config,
        };
        if !observe(&step) {
            return Err(CompileStop::Cancelled);
        }
        out.push(step);
        i = covers.end;
    }
    Ok(out)
}

/// The index of the last `move_l` of a blended chain starting at `i` (`i` when none): the
/// steps `i..=end` run as one path, so a single step (F10) runs them together.
pub fn blended_chain_end(program: &Program, i: usize) -> usize {
    let mut k = i;
    // a line with a fixed duration is never part of a blended chain
    while let Some(Step::MoveL { blend_mm: Some(b), duration_s: None, .. }) = program.steps.get(k).map(|s| &s.step) {
        if *b <= 0.0 || !matches!(program.steps.get(k + 1).map(|s| &s.step), Some(Step::MoveL { duration_s: None, .. }))
        {
            break;
        }
        k += 1;
    }
    k
}

/// A step's problem before it gets its index and line.
enum StepError {
    Message(String),
    Cartesian(CartesianError),
}

impl From<String> for StepError {
    fn from(m: String) -> Self {
        StepError::Message(m)
    }
}

fn compile_one(
    model: &RobotModel,
    step: &Step,
    speed: &SpeedSettings,
    q: &[f64],
    caps: &MotionCaps,
    opts: CompileOptions,
    notes: &mut StepNotes,
) -> Result<StepAction, StepError> {
    let joint_fraction = |f: Option<f64>| -> Result<f64, String> {
        let f = f.unwrap_or(speed.joint_fraction);
        if f.is_finite() && (MIN_JOINT_FRACTION..=1.0).contains(&f) {
            Ok(f * opts.speed_override)
        } else {
            Err(format!("speed_fraction must lie in {MIN_JOINT_FRACTION}–1, got {f}"))
        }
    };
    let from = model.tcp_isometry(q);
    let action = match step {
        Step::Home { speed_fraction } => {
            joint_move(q, &home_position(model), caps, joint_fraction(*speed_fraction)?, opts.dt_s)?
        }
        Step::MoveJoints { joints_deg, speed_fraction, duration_s } => {
            if joints_deg.len() != q.len() {
                return Err(
                    format!("joints_deg has {} values; the robot has {} joints", joints_deg.len(), q.len()).into()
                );
            }
            let goal: Vec<f64> = joints_deg.iter().map(|d| d.to_radians()).collect();
            model.limits.check(&goal).map_err(|e| e.to_string())?;
            match duration_s {
                Some(d) => timed::joint_move_in(q, &goal, caps, *d, opts, &mut notes.warnings)?,
                None => joint_move(q, &goal, caps, joint_fraction(*speed_fraction)?, opts.dt_s)?,
            }
        }
        Step::MovePose { pose, config, speed_fraction, duration_s } => {
            let target = checked_pose(pose)?;
            let rule = config.map_or(ConfigRule::ANY, ConfigRule::exactly);
            let goal = ik::solve_nearest(model, &target, q, rule)
                .map_err(|e| format!("the pose is not reachable: {e}"))?
                .joints_rad;
            model.limits.check(&goal).map_err(|e| e.to_string())?;
            match duration_s {
                Some(d) => timed::joint_move_in(q, &goal, caps, *d, opts, &mut notes.warnings)?,
                None => joint_move(q, &goal, caps, joint_fraction(*speed_fraction)?, opts.dt_s)?,
            }
        }
        Step::MoveL { pose, speed_mm_s, blend_mm, duration_s } => {
            let path = TcpPath::line(&from, &checked_pose(pose)?);
            match duration_s {
                Some(_) if blend_mm.is_some_and(|b| b > 0.0) => {
                    return Err("a line with duration_s cannot blend into the next one (blend_mm)".to_string().into());
                }
                Some(d) => timed::cartesian_move_in(model, q, &path, speed, *d, caps, opts, notes)?,
                None => cartesian_move(model, q, &path, speed, *speed_mm_s, caps, opts, notes)?,
            }
        }
        Step::MoveRelTool { offset_mm, rotation_deg, speed_mm_s, duration_s } => {
            checked_mm(offset_mm, "offset_mm")?;
            if !rotation_deg.iter().all(|a| a.is_finite()) {
                return Err("rotation_deg must be three numbers".to_string().into());
            }
            let path = TcpPath::line(&from, &timed::tool_frame_goal(&from, offset_mm, rotation_deg));
            match duration_s {
                Some(d) => timed::cartesian_move_in(model, q, &path, speed, *d, caps, opts, notes)?,
                None => cartesian_move(model, q, &path, speed, *speed_mm_s, caps, opts, notes)?,
            }
        }
        Step::TimeFunction { sample_rate_hz, pieces } => {
            let function = super::timefn::TimeFunction::new(pieces, *sample_rate_hz).map_err(|e| e.to_string())?;
            let points = function.sample(&from).map_err(|e| e.to_string())?;
            timed::follow(model, q, &points, caps, opts, notes)?
        }
        Step::MoveC { via_mm, pose, speed_mm_s } => {
            let via = Point3::from(checked_mm(via_mm, "via_mm")?);
            let path = TcpPath::arc_through(&from, &via, &checked_pose(pose)?).map_err(|e| e.to_string())?;
            cartesian_move(model, q, &path, speed, *speed_mm_s, caps, opts, notes)?
        }
        Step::MoveCircle { center_mm, normal, angle_deg, speed_mm_s } => {
            let center = Point3::from(checked_mm(center_mm, "center_mm")?);
            let n = Vector3::from(*normal);
            if !angle_deg.is_finite() {
                return Err(format!("angle_deg must be a number, got {angle_deg}").into());
            }
            let path = TcpPath::arc_about(&from, &center, &n, angle_deg.to_radians()).map_err(|e| e.to_string())?;
            cartesian_move(model, q, &path, speed, *speed_mm_s, caps, opts, notes)?
        }
        Step::Spline { waypoints, speed_mm_s } => {
            let mut pts = vec![from];
            for w in waypoints {
                pts.push(checked_pose(w)?);
            }
            let path = TcpPath::spline(&pts).map_err(|e| e.to_string())?;
            cartesian_move(model, q, &path, speed, *speed_mm_s, caps, opts, notes)?
        }
        Step::Dwell { seconds } => StepAction::Dwell(checked_wait(*seconds, "seconds")?),
        Step::Gripper { action, position, speed, current_ma } => {
            let position = match action {
                GripperAction::Open => 0,
                GripperAction::Close => 255,
                GripperAction::Position => {
                    position.ok_or_else(|| "action \"position\" needs a position (0–255)".to_string())?
                }
            };
            let cmd =
                IoCommand::Gripper { position, speed: speed.unwrap_or(128), current_ma: current_ma.unwrap_or(500) };
            cmd.validate()?;
            StepAction::Io(cmd)
        }
        Step::SetOutput { output, on } => {
            let cmd = IoCommand::SetOutput { output: *output, on: *on };
            cmd.validate()?;
            StepAction::Io(cmd)
        }
        Step::WaitInput { input, on, timeout_s } => {
            IoCommand::SetSimulatedInput { input: *input, on: *on }.validate()?;
            let timeout_s = checked_wait(timeout_s.unwrap_or(DEFAULT_INPUT_TIMEOUT_S), "timeout_s")?;
            if timeout_s <= 0.0 {
                return Err("timeout_s must be above 0".to_string().into());
            }
            StepAction::WaitInput { input: *input, on: *on, timeout_s }
        }
        Step::Pause { optional } => StepAction::Pause { optional: *optional },
    };
    Ok(action)
}

fn compile_blended(
    model: &RobotModel,
    program: &Program,
    steps: Range<usize>,
    q: &[f64],
    caps: &MotionCaps,
    opts: CompileOptions,
    notes: &mut StepNotes,
) -> Result<Arc<SampledTrajectory>, StepError> {
    let mut pts = vec![model.tcp_isometry(q)];
    let (mut radius_mm, mut speed_mm_s) = (f64::INFINITY, f64::INFINITY);
    for k in steps {
        if let Step::MoveL { pose, speed_mm_s: s, blend_mm, .. } = &program.steps[k].step {
            pts.push(checked_pose(pose).map_err(StepError::Message)?);
            speed_mm_s = speed_mm_s.min(s.unwrap_or(program.speed.tcp_speed_mm_s));
            if let Some(b) = blend_mm.filter(|b| *b > 0.0) {
                radius_mm = radius_mm.min(b);
            }
        }
    }
    if !radius_mm.is_finite() {
        return Err(StepError::Message("blend_mm must be a finite number".into()));
    }
    let path = TcpPath::blended_polyline(&pts, radius_mm / 1000.0).map_err(|e| StepError::Message(e.to_string()))?;
    match cartesian_move(model, q, &path, &program.speed, Some(speed_mm_s), caps, opts, notes)? {
        StepAction::Motion(t) => Ok(t),
        _ => Err(StepError::Message("a blended path gave no motion".into())),
    }
}

/// A blended chain's problem, named by the step whose line passes nearest the TCP where it
/// is (the chain's first step when the problem has no point): the chain is planned as one
/// path, but the operator edits one step.
fn blended_error(model: &RobotModel, program: &Program, steps: Range<usize>, q: &[f64], e: StepError) -> CompileError {
    let first = steps.start;
    let mut err = cartesian_error(first, program.steps[first].line, program.steps[first].step.kind(), e);
    if let Some(at) = err.tcp_mm.map(Point3::from) {
        let mut from = Point3::from(model.tcp_isometry(q).translation.vector * 1000.0);
        let mut best = (f64::INFINITY, first);
        for k in steps.clone() {
            if let Step::MoveL { pose, .. } = &program.steps[k].step {
                let to = Point3::from(pose.position_mm);
                let d = distance_to_segment(&at, &from, &to);
                if d < best.0 {
                    best = (d, k);
                }
                from = to;
            }
        }
        (err.index, err.line, err.kind) = (best.1, program.steps[best.1].line, program.steps[best.1].step.kind());
    }
    err.message = format!(
        "{} (steps {}–{} are one blended path; t counts from step {})",
        err.message,
        steps.start + 1,
        steps.end,
        steps.start + 1
    );
    err
}

/// Distance from `p` to the segment `a`–`b`, in their unit.
fn distance_to_segment(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let u = if len2 > 0.0 { ((p - a).dot(&ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (p - (a + ab * u)).norm()
}

fn cartesian_error(index: usize, line: usize, kind: &'static str, e: StepError) -> CompileError {
    let (message, t_s, tcp_mm) = match e {
        StepError::Cartesian(CartesianError::Unreachable { t_s, x_mm, y_mm, z_mm, reason }) => (
            format!("TCP ({x_mm:.1}, {y_mm:.1}, {z_mm:.1}) mm at t = {t_s:.3} s is not reachable: {reason}"),
            Some(t_s),
            Some([x_mm, y_mm, z_mm]),
        ),
        StepError::Cartesian(c @ CartesianError::SingularSwing { t_s, x_mm, y_mm, z_mm, .. }) => {
            (c.to_string(), Some(t_s), Some([x_mm, y_mm, z_mm]))
        }
        StepError::Cartesian(c @ CartesianError::Discontinuous { t_s, .. }) => (c.to_string(), Some(t_s), None),
        StepError::Cartesian(c) => (c.to_string(), None, None),
        StepError::Message(m) => (m, None, None),
    };
    CompileError { index, line, kind, message, t_s, tcp_mm }
}

#[expect(clippy::too_many_arguments, reason = "the move, its caps and where its warnings go; one call site each")]
fn cartesian_move(
    model: &RobotModel,
    q: &[f64],
    path: &TcpPath,
    speed: &SpeedSettings,
    speed_mm_s: Option<f64>,
    caps: &MotionCaps,
    opts: CompileOptions,
    notes: &mut StepNotes,
) -> Result<StepAction, StepError> {
    let asked = speed_mm_s.unwrap_or(speed.tcp_speed_mm_s);
    if !(asked.is_finite() && asked >= MIN_TCP_SPEED_MM_S) {
        return Err(
            format!("speed_mm_s must lie in {MIN_TCP_SPEED_MM_S}–{MAX_TCP_SPEED_MM_S} mm/s, got {asked}").into()
        );
    }
    // faster than the arm can go: as fast as it can, and said so (official programs run)
    let v = asked.min(MAX_TCP_SPEED_MM_S);
    if asked > MAX_TCP_SPEED_MM_S {
        notes.warnings.push(format!(
            "speed {asked} mm/s is above the PAROL6's {MAX_TCP_SPEED_MM_S} mm/s: the move runs at \
             {MAX_TCP_SPEED_MM_S} mm/s"
        ));
    }
    for (what, a, min) in
        [("tcp_accel_mm_s2", speed.tcp_accel_mm_s2, 5.5), ("tcp_jerk_mm_s3", speed.tcp_jerk_mm_s3, 55.0)]
    {
        if !(a.is_finite() && a >= min) {
            return Err(format!("speed.{what} must be at least {min}, got {a}").into());
        }
    }
    let tcp = CartesianCaps {
        speed_m_s: v / 1000.0,
        accel_m_s2: speed.tcp_accel_mm_s2 / 1000.0,
        jerk_m_s3: speed.tcp_jerk_mm_s3 / 1000.0,
    };
    let mv =
        cartesian::plan(model, q, path, &tcp, caps, opts.speed_override, opts.dt_s).map_err(StepError::Cartesian)?;
    notes.start_config = Some(mv.start_rule);
    Ok(StepAction::Motion(mv.trajectory))
}

fn joint_move(start: &[f64], goal: &[f64], caps: &MotionCaps, fraction: f64, dt_s: f64) -> Result<StepAction, String> {
    let mv = caps.plan_joint_move(start, goal, fraction, ProfileKind::JerkLimited).map_err(|e| e.to_string())?;
    if mv.sample_count(dt_s) - 1 > cartesian::MAX_MOVE_SAMPLES {
        return Err(format!(
            "the move would take {:.0} s (more than {} samples): raise its speed",
            mv.duration_s(),
            cartesian::MAX_MOVE_SAMPLES
        ));
    }
    Ok(StepAction::Motion(Arc::new(SampledTrajectory::new(dt_s, mv.positions_every(dt_s)))))
}

/// Program positions farther from the base than this are refused, mm.
pub const MAX_POSITION_MM: f64 = 10_000.0;

fn checked_mm(v: &[f64; 3], field: &str) -> Result<Vector3<f64>, String> {
    if v.iter().all(|x| x.is_finite() && x.abs() <= MAX_POSITION_MM) {
        Ok(Vector3::new(v[0], v[1], v[2]) / 1000.0)
    } else {
        Err(format!("{field} must be three numbers within ±{MAX_POSITION_MM} mm, got {v:?}"))
    }
}

fn checked_pose(p: &super::PoseMm) -> Result<Isometry3<f64>, String> {
    checked_mm(&p.position_mm, "position_mm")?;
    if !p.rpy_deg.iter().all(|x| x.is_finite()) {
        return Err("rpy_deg must be three numbers".into());
    }
    Ok(p.isometry())
}

fn checked_wait(s: f64, field: &str) -> Result<f64, String> {
    if s.is_finite() && (0.0..=MAX_WAIT_S).contains(&s) {
        Ok(s)
    } else {
        Err(format!("{field} must lie in 0–{MAX_WAIT_S} s, got {s}"))
    }
}

pub(crate) mod timed;

#[cfg(test)]
mod tests;

//! Inverse dynamics over a compiled program: the joint torques (gravity + inertial +
//! Coriolis, [`InverseDynamics`]) every trajectory sample needs, on one time axis for the whole
//! program, before anything moves; with a warning for every stretch where a joint's torque
//! exceeds its limit ([`crate::parol6::joint_torque_limits_nm`] for the PAROL6).
//!
//! Velocities and accelerations come from central differences of the trajectory samples (the
//! arm is at rest before and after every compiled step). Dwells, I/O and input waits hold the
//! last pose: gravity only.

use serde::Serialize;

use super::compile::{CompiledStep, StepAction};
use crate::dynamics::InverseDynamics;
use crate::model::RobotModel;

/// The most warnings kept (the rest are counted in [`ProgramTorques::warnings_dropped`]).
pub const MAX_TORQUE_WARNINGS: usize = 200;

/// One stretch of time where a joint's torque exceeds its limit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TorqueWarning {
    /// 1-based joint.
    pub joint: usize,
    /// 1-based source line of the step (0: unknown).
    pub line: usize,
    /// 0-based index of the program step.
    pub step: usize,
    /// Step type.
    pub step_kind: &'static str,
    /// Program time where the torque first exceeds the limit, s.
    pub start_s: f64,
    /// Program time where it is back within the limit, s.
    pub end_s: f64,
    /// Program time of the largest |torque| of the stretch, s.
    pub peak_s: f64,
    /// The torque there (signed), N·m.
    pub peak_nm: f64,
    /// The joint's limit, N·m.
    pub limit_nm: f64,
}

/// Joint torques along a whole program.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProgramTorques {
    /// Program time of every sample, s (non-decreasing).
    pub time_s: Vec<f64>,
    /// Per joint, the torque at every sample, N·m (`torques_nm[joint][sample]`).
    pub torques_nm: Vec<Vec<f64>>,
    /// Per joint, the largest |torque|, N·m.
    pub peak_abs_nm: Vec<f64>,
    /// Per joint limits used for the warnings, N·m (`None`: no documented limit, no warnings).
    pub limits_nm: Option<Vec<f64>>,
    /// Stretches over a limit, in time order.
    pub warnings: Vec<TorqueWarning>,
    /// Warnings beyond [`MAX_TORQUE_WARNINGS`], not listed.
    pub warnings_dropped: usize,
}

/// The documented joint torque limits of `model`: the PAROL6's (ROBOT.md §1 reductions ×
/// motor holding torques), none for another robot.
pub fn torque_limits_nm(model: &RobotModel) -> Option<Vec<f64>> {
    (model.is_parol6 && model.dof() == crate::parol6::JOINT_COUNT)
        .then(|| crate::parol6::joint_torque_limits_nm().to_vec())
}

/// Where a sample came from (for the warnings).
#[derive(Clone, Copy)]
struct Origin {
    line: usize,
    step: usize,
    kind: &'static str,
}

struct Builder<'m> {
    model: &'m RobotModel,
    id: InverseDynamics,
    out: ProgramTorques,
    /// Keep every sample's torque (the plot), or only peaks and warnings (pre-flight).
    keep_series: bool,
    /// Per joint, the stretch over the limit now open.
    open: Vec<Option<TorqueWarning>>,
    /// Per joint, the closed stretches (the first [`MAX_TORQUE_WARNINGS`]; the rest counted).
    closed: Vec<Vec<TorqueWarning>>,
    tau: Vec<f64>,
}

impl Builder<'_> {
    fn push(&mut self, t_s: f64, q: &[f64], qd: &[f64], qdd: &[f64], origin: Origin) {
        self.id.compute_into(self.model, q, qd, qdd, &mut self.tau);
        if self.keep_series {
            self.out.time_s.push(t_s);
        }
        for j in 0..self.tau.len() {
            let v = self.tau[j];
            if self.keep_series
                && let Some(col) = self.out.torques_nm.get_mut(j)
            {
                col.push(v);
            }
            if let Some(p) = self.out.peak_abs_nm.get_mut(j) {
                *p = p.max(v.abs());
            }
            let Some(limit) = self.out.limits_nm.as_ref().and_then(|l| l.get(j).copied()) else { continue };
            if v.abs() > limit {
                let w = self.open[j].get_or_insert_with(|| TorqueWarning {
                    joint: j + 1,
                    line: origin.line,
                    step: origin.step,
                    step_kind: origin.kind,
                    start_s: t_s,
                    end_s: t_s,
                    peak_s: t_s,
                    peak_nm: v,
                    limit_nm: limit,
                });
                w.end_s = t_s;
                if v.abs() > w.peak_nm.abs() {
                    w.peak_nm = v;
                    w.peak_s = t_s;
                }
            } else if let Some(w) = self.open[j].take() {
                self.close(j, w);
            }
        }
    }

    fn close(&mut self, j: usize, w: TorqueWarning) {
        match self.closed.get_mut(j) {
            Some(c) if c.len() < MAX_TORQUE_WARNINGS => c.push(w),
            _ => self.out.warnings_dropped += 1,
        }
    }
}

/// Torques of the compiled `steps` of a program starting at joints `start_q`, with warnings
/// against `limits_nm` (one per joint; `None`: no warnings).
pub fn program_torques(
    model: &RobotModel,
    steps: &[CompiledStep],
    start_q: &[f64],
    limits_nm: Option<Vec<f64>>,
) -> ProgramTorques {
    walk(model, steps, start_q, limits_nm, true)
}

/// The stretches over the documented torque limits ([`torque_limits_nm`]) of the compiled
/// `steps` from `start_q`, and how many were left out: what [`program_torques`] warns about,
/// without keeping the series (pre-flight of a long program). Empty for a robot without
/// documented limits.
pub fn torque_warnings(model: &RobotModel, steps: &[CompiledStep], start_q: &[f64]) -> (Vec<TorqueWarning>, usize) {
    let Some(mut stream) = torque_warning_stream(model, start_q) else { return (Vec::new(), 0) };
    for step in steps {
        stream.step(step);
    }
    stream.into_warnings()
}

/// [`torque_warnings`] fed one compiled step at a time ([`TorqueStream::step`], then
/// [`TorqueStream::into_warnings`]); `None` for a robot without documented limits.
pub(crate) fn torque_warning_stream<'m>(model: &'m RobotModel, start_q: &[f64]) -> Option<TorqueStream<'m>> {
    torque_limits_nm(model).map(|limits| TorqueStream::new(model, start_q, Some(limits), false))
}

/// Joint torques along a recorded motion (a replay): the same inverse dynamics and the same
/// warnings as [`program_torques`], at every sample `next` gives. `next` fills the joints'
/// positions (rad), velocities (rad/s) and accelerations (rad/s²) of the next sample and returns
/// its time, s, or `None` at the end. A warning names the sample where its stretch starts as its
/// `step`, line 0 and kind "recording".
pub fn motion_torques(
    model: &RobotModel,
    limits_nm: Option<Vec<f64>>,
    mut next: impl FnMut(&mut [f64], &mut [f64], &mut [f64]) -> Option<f64>,
) -> ProgramTorques {
    let n = model.dof();
    let mut stream = TorqueStream::new(model, &vec![0.0; n], limits_nm, true);
    // no start sample at rest: the recording's first sample is where it starts
    stream.started = true;
    let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut k = 0;
    while let Some(t_s) = next(&mut q, &mut qd, &mut qdd) {
        stream.b.push(t_s, &q, &qd, &qdd, Origin { line: 0, step: k, kind: "recording" });
        k += 1;
    }
    stream.finish()
}

fn walk(
    model: &RobotModel,
    steps: &[CompiledStep],
    start_q: &[f64],
    limits_nm: Option<Vec<f64>>,
    keep_series: bool,
) -> ProgramTorques {
    let mut stream = TorqueStream::new(model, start_q, limits_nm, keep_series);
    for step in steps {
        stream.step(step);
    }
    stream.finish()
}

/// The torque pass one compiled step at a time, in program order (what [`walk`] does over a
/// slice): the pre-flight feeds it each step as soon as it is compiled, on its own thread, so
/// the pass overlaps the planning instead of following it. The same samples in the same order
/// as [`walk`]: the same result, to the bit.
pub(crate) struct TorqueStream<'m> {
    b: Builder<'m>,
    zeros: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    /// Program time where the next step starts, s.
    t0: f64,
    /// Where the last step ended (the start pose before the first).
    q_end: Vec<f64>,
    /// The start sample is pushed (with the first step's line, as [`walk`] does).
    started: bool,
}

impl<'m> TorqueStream<'m> {
    /// A pass from joints `start_q` with warnings against `limits_nm` (one per joint; `None`:
    /// no warnings), keeping every sample's torque when `keep_series`.
    pub(crate) fn new(model: &'m RobotModel, start_q: &[f64], limits_nm: Option<Vec<f64>>, keep_series: bool) -> Self {
        let n = model.dof();
        let b = Builder {
            model,
            id: InverseDynamics::new(model),
            out: ProgramTorques {
                time_s: Vec::new(),
                torques_nm: vec![Vec::new(); n],
                peak_abs_nm: vec![0.0; n],
                limits_nm: limits_nm.filter(|l| l.len() == n),
                warnings: Vec::new(),
                warnings_dropped: 0,
            },
            keep_series,
            open: vec![None; n],
            closed: vec![Vec::new(); n],
            tau: vec![0.0; n],
        };
        Self {
            b,
            zeros: vec![0.0; n],
            qd: vec![0.0; n],
            qdd: vec![0.0; n],
            t0: 0.0,
            q_end: start_q.to_vec(),
            started: false,
        }
    }

    /// The start sample, at rest, once (named after the first step's line, 0 without steps).
    fn start(&mut self, line: usize) {
        if !self.started {
            self.started = true;
            let first = Origin { line, step: 0, kind: "start" };
            self.b.push(0.0, &self.q_end, &self.zeros, &self.zeros, first);
        }
    }

    /// The next compiled step.
    pub(crate) fn step(&mut self, step: &CompiledStep) {
        self.start(step.line);
        let n = self.zeros.len();
        let origin = Origin { line: step.line, step: step.steps.start, kind: step.kind };
        match &step.action {
            StepAction::Motion(traj) => {
                let s = traj.samples();
                let dt = traj.dt_s();
                if s.is_empty() || dt.is_nan() || dt <= 0.0 {
                    // as `walk` did: the step's end is not taken over
                    return;
                }
                for k in 0..s.len() {
                    let (a, c) = (&s[k.saturating_sub(1)], s.get(k + 1).unwrap_or(&s[k]));
                    let b_ = &s[k];
                    for i in 0..n {
                        let at = |v: &Vec<f64>| v.get(i).copied().unwrap_or(0.0);
                        self.qd[i] = (at(c) - at(a)) / (2.0 * dt);
                        self.qdd[i] = (at(c) - 2.0 * at(b_) + at(a)) / (dt * dt);
                    }
                    self.b.push(self.t0 + k as f64 * dt, b_, &self.qd, &self.qdd, origin);
                }
                self.t0 += traj.duration_s();
            }
            StepAction::Dwell(d) => {
                self.b.push(self.t0, &self.q_end, &self.zeros, &self.zeros, origin);
                self.t0 += d.max(0.0);
                self.b.push(self.t0, &self.q_end, &self.zeros, &self.zeros, origin);
            }
            StepAction::Io(_) | StepAction::WaitInput { .. } | StepAction::Pause { .. } => {}
        }
        self.q_end.clone_from(&step.end_q);
    }

    /// The stretches over the limits and how many were left out ([`torque_warnings`]).
    pub(crate) fn into_warnings(self) -> (Vec<TorqueWarning>, usize) {
        let out = self.finish();
        (out.warnings, out.warnings_dropped)
    }

    /// The torques, with every stretch still open closed at its last sample.
    pub(crate) fn finish(mut self) -> ProgramTorques {
        self.start(0);
        let mut b = self.b;
        for j in 0..self.zeros.len() {
            if let Some(w) = b.open[j].take() {
                b.close(j, w);
            }
        }
        let mut all: Vec<TorqueWarning> = b.closed.into_iter().flatten().collect();
        // one warning per stretch over the limit, per joint, sorted by start time
        all.sort_by(|a, b| a.start_s.total_cmp(&b.start_s).then(a.joint.cmp(&b.joint)));
        b.out.warnings_dropped += all.len().saturating_sub(MAX_TORQUE_WARNINGS);
        all.truncate(MAX_TORQUE_WARNINGS);
        b.out.warnings = all;
        b.out
    }
}

#[cfg(test)]
mod tests;

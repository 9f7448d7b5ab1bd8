//! [`MotionPlanner`]: commands in, the commanded joint trajectory out, as a pure function of
//! time on the backend's motion clock.

use std::sync::Arc;

use crate::limits::{JointLimits, LimitPolicy};
use crate::profile::JointMove;

use super::cartesian_jog::{CartesianAxis, CartesianJogPlan, JogFrame, JogKinematics};
use super::trajectory::SampledTrajectory;

use super::validate::{validate, validate_trajectory};
use super::warp::{TimeWarp, ramp_for};
use super::{DEADMAN_S, MotionCaps, MotionCommand, MotionError, Setpoint};

/// What the planner is doing (a summary for states and tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum PlannerMode {
    /// Holding a position.
    Hold,
    /// Slewing toward a target (slider).
    Follow,
    /// A profiled move.
    Move,
    /// A hold-to-run jog.
    Jog,
    /// A planned trajectory (Cartesian move, program segment).
    Trajectory,
    /// A trajectory paused on its path ([`MotionCommand::Pause`]), waiting for
    /// [`MotionCommand::Resume`].
    Paused,
    /// A hold-to-run Cartesian jog.
    CartesianJog,
}

#[derive(Debug, Clone)]
enum Motion {
    Hold,
    Follow { t0: f64, start: Vec<f64>, target: Vec<f64>, speed: Vec<f64>, end_s: f64 },
    Move { t0: f64, mv: JointMove },
    Jog { t0: f64, start: Vec<f64>, joint: usize, vel: f64, stop_at: f64, refreshed: f64 },
    Trajectory { t0: f64, traj: Arc<SampledTrajectory>, warp: TimeWarp },
    CartesianJog { t0: f64, plan: Arc<CartesianJogPlan>, key: (JogFrame, CartesianAxis, f64), refreshed: f64 },
}

/// A trajectory must start within this distance of the commanded position, rad.
pub const TRAJECTORY_START_TOLERANCE_RAD: f64 = 1e-6;

/// A command waiting for its time on the motion clock.
#[derive(Debug, Clone)]
struct Scheduled {
    at_s: f64,
    order: u64,
    cmd: MotionCommand,
}

/// Turns [`MotionCommand`]s into the commanded trajectory. Deterministic: the setpoint at time
/// `t` depends only on the commands and the times they were applied at, never on how often
/// [`MotionPlanner::sample`] is called.
#[derive(Debug, Clone)]
pub struct MotionPlanner {
    limits: JointLimits,
    caps: MotionCaps,
    home: Vec<f64>,
    motion: Motion,
    hold_q: Vec<f64>,
    goal: Vec<f64>,
    pending: Vec<Scheduled>,
    order: u64,
    applied: u64,
    refusal_seq: u64,
    last_refusal: Option<(u64, String)>,
    kinematics: Option<JogKinematics>,
    /// How late the schedule runs, s (see the `schedule` module).
    delay_s: f64,
    /// Scheduled commands received ([`MotionPlanner::note_scheduled`]).
    received: u64,
}

/// Why a jog of `joint` (0-based) in the direction of `fraction`'s sign from `here_rad` is
/// refused: the joint is at or beyond the limit it would move toward (only a jog back inside
/// is allowed). The one place of this rule: the planner applies it, and the serial session
/// asks it before queueing a jog so that its refusal is immediate.
pub fn jog_refusal(limits: &JointLimits, here_rad: &[f64], joint: usize, fraction: f64) -> Option<String> {
    let (lim, q) = (limits.get(joint)?, *here_rad.get(joint)?);
    let upper = fraction > 0.0;
    let stop_at = if upper { lim.max } else { lim.min };
    let blocked = if upper { q >= stop_at } else { fraction < 0.0 && q <= stop_at };
    blocked.then(|| {
        format!(
            "joint {} ({}) is at its {} limit ({:.3}°): jog the other way",
            joint + 1,
            lim.name,
            if upper { "upper" } else { "lower" },
            stop_at.to_degrees()
        )
    })
}

impl MotionPlanner {
    /// A planner holding `q0`. `home` is the target of [`MotionCommand::Home`].
    pub fn new(limits: JointLimits, caps: MotionCaps, home: Vec<f64>, q0: &[f64]) -> Self {
        Self {
            limits,
            caps,
            home,
            motion: Motion::Hold,
            hold_q: q0.to_vec(),
            goal: q0.to_vec(),
            pending: Vec::new(),
            order: 0,
            applied: 0,
            refusal_seq: 0,
            last_refusal: None,
            kinematics: None,
            delay_s: 0.0,
            received: 0,
        }
    }

    /// Gives the planner the kinematic model (and optionally a collision check) that Cartesian
    /// jogs and steps need; without it they are refused.
    pub fn with_kinematics(mut self, kinematics: JogKinematics) -> Self {
        self.kinematics = Some(kinematics);
        self
    }

    /// The kinematics of Cartesian commands, when given.
    pub fn kinematics(&self) -> Option<&JogKinematics> {
        self.kinematics.as_ref()
    }

    /// The current Cartesian jog's plan (where and why it will stop), while one runs.
    pub fn cartesian_jog(&self) -> Option<&CartesianJogPlan> {
        match &self.motion {
            Motion::CartesianJog { plan, .. } => Some(plan),
            _ => None,
        }
    }

    /// The joint limits every command passes.
    pub fn limits(&self) -> &JointLimits {
        &self.limits
    }

    /// The speed / acceleration caps.
    pub fn caps(&self) -> &MotionCaps {
        &self.caps
    }

    /// Holds `q` from now on and forgets scheduled commands (teleport, re-sync to a measured
    /// position, link loss).
    pub fn reset(&mut self, q: &[f64]) {
        self.motion = Motion::Hold;
        self.hold_q = q.to_vec();
        self.goal = q.to_vec();
        self.clear_schedule();
    }

    /// Checks a command against the limits and its own arguments without applying it.
    pub fn validate(&self, cmd: &MotionCommand) -> Result<(), MotionError> {
        validate(&self.limits, cmd)
    }

    /// Applies `cmd` at time `t_s` (an immediate command). An immediate STOP or PAUSE also
    /// drops every scheduled command (and the schedule's delay). A refused command leaves the
    /// planner unchanged.
    pub fn apply(&mut self, cmd: &MotionCommand, t_s: f64) -> Result<(), MotionError> {
        if matches!(cmd, MotionCommand::Stop | MotionCommand::Pause) {
            self.clear_schedule();
        }
        self.apply_at(cmd, t_s)
    }

    /// When the current motion ends if nothing stops it (a jog: when it would reach its
    /// limit), s on the motion clock.
    pub fn path_end_s(&self) -> f64 {
        match &self.motion {
            Motion::Hold => 0.0,
            Motion::Follow { t0, end_s, .. } => t0 + end_s,
            Motion::Move { t0, mv } => t0 + mv.duration_s(),
            Motion::Jog { t0, start, joint, vel, stop_at, .. } => t0 + ((stop_at - start[*joint]) / vel).abs(),
            Motion::Trajectory { t0, traj, warp } => match (warp.end_clock(*t0, traj.duration_s()), warp) {
                (Some(end), _) => end,
                (None, TimeWarp::Pausing { t_s, ramp_s, .. }) => t_s + ramp_s,
                (None, _) => 0.0,
            },
            Motion::CartesianJog { t0, plan, .. } => t0 + plan.duration_s(),
        }
    }

    /// Position along the current motion at `t_s`, ignoring the jog dead-man (what the path
    /// would be if the jog were held to its limit).
    pub fn path_q(&self, t_s: f64) -> Vec<f64> {
        match &self.motion {
            Motion::Jog { t0, start, joint, vel, stop_at, .. } => {
                let mut q = start.clone();
                let free = start[*joint] + vel * (t_s - t0).max(0.0);
                q[*joint] = if *vel > 0.0 { free.min(*stop_at) } else { free.max(*stop_at) };
                q
            }
            Motion::CartesianJog { t0, plan, .. } => {
                let mut sp = Setpoint::at_rest(&[]);
                plan.sample_into(t_s - t0, &mut sp);
                sp.q
            }
            _ => self.setpoint_at(t_s).q,
        }
    }

    /// Commands applied so far (immediate and scheduled, refused ones not counted).
    pub fn applied(&self) -> u64 {
        self.applied
    }

    /// The last refusal of a scheduled command: increasing id and message.
    pub fn last_refusal(&self) -> Option<&(u64, String)> {
        self.last_refusal.as_ref()
    }

    /// Where the current motion is going (the hold position when holding).
    pub fn goal(&self) -> &[f64] {
        &self.goal
    }

    /// The current mode.
    pub fn mode(&self) -> PlannerMode {
        match self.motion {
            Motion::Hold => PlannerMode::Hold,
            Motion::Follow { .. } => PlannerMode::Follow,
            Motion::Move { .. } => PlannerMode::Move,
            Motion::Jog { .. } => PlannerMode::Jog,
            Motion::Trajectory { warp, .. } if warp.is_pausing() => PlannerMode::Paused,
            Motion::Trajectory { .. } => PlannerMode::Trajectory,
            Motion::CartesianJog { .. } => PlannerMode::CartesianJog,
        }
    }

    /// True while the commanded trajectory moves at `t_s`, or scheduled commands wait.
    pub fn is_moving(&self, t_s: f64) -> bool {
        if !self.pending.is_empty() {
            return true;
        }
        match &self.motion {
            Motion::Hold => false,
            Motion::Follow { t0, end_s, .. } => t_s - t0 < *end_s,
            Motion::Move { t0, mv } => !mv.is_finished(t_s - t0),
            Motion::Jog { refreshed, .. } => t_s <= refreshed + DEADMAN_S,
            Motion::Trajectory { t0, traj, warp } => {
                !warp.is_stopped(t_s) && warp.end_clock(*t0, traj.duration_s()).is_none_or(|end| t_s < end)
            }
            Motion::CartesianJog { t0, plan, refreshed, .. } => {
                t_s <= refreshed + DEADMAN_S && t_s - t0 < plan.duration_s()
            }
        }
    }

    /// Applies the scheduled commands due by `t_s`, retires finished motions and returns the
    /// setpoint at `t_s`.
    pub fn sample(&mut self, t_s: f64) -> Setpoint {
        let mut sp = Setpoint::at_rest(&[]);
        self.sample_into(t_s, &mut sp);
        sp
    }

    /// [`MotionPlanner::sample`] into a caller-owned setpoint (no allocation on a steady tick).
    pub fn sample_into(&mut self, t_s: f64, out: &mut Setpoint) {
        self.apply_due(t_s);
        self.retire(t_s);
        self.setpoint_into(t_s, out);
    }

    /// The setpoint sampling at `t_s` would give, ahead of the motion clock and without
    /// changing the planner: scheduled commands due by then are applied on a copy (cloned only
    /// when one is due). The tracking modes' targets ([`super::tracking`]).
    pub fn preview_into(&self, t_s: f64, out: &mut Setpoint) {
        if self.pending.first().is_some_and(|p| p.at_s <= t_s) {
            let mut ahead = self.clone();
            ahead.sample_into(t_s, out);
        } else {
            self.setpoint_into(t_s, out);
        }
    }

    /// The setpoint of the current motion at `t_s` (no side effects).
    pub fn setpoint_at(&self, t_s: f64) -> Setpoint {
        let mut sp = Setpoint::at_rest(&[]);
        self.setpoint_into(t_s, &mut sp);
        sp
    }

    /// [`MotionPlanner::setpoint_at`] into a caller-owned setpoint (no allocation once `out`
    /// has the robot's size: the 1 kHz loops use it).
    pub fn setpoint_into(&self, t_s: f64, out: &mut Setpoint) {
        match &self.motion {
            Motion::Hold => out.set_rest(&self.hold_q),
            Motion::Follow { t0, start, target, speed, .. } => {
                let dt = (t_s - t0).max(0.0);
                out.set_rest(start);
                for i in 0..start.len() {
                    let d = target[i] - start[i];
                    let reach = speed[i] * dt;
                    if d.abs() <= reach {
                        out.q[i] = target[i];
                    } else {
                        out.q[i] = start[i] + d.signum() * reach;
                        out.qd[i] = d.signum() * speed[i];
                    }
                }
            }
            Motion::Move { t0, mv } => {
                out.resize(mv.joint_count());
                mv.sample_into(t_s - t0, &mut out.q, &mut out.qd, &mut out.qdd);
            }
            Motion::Trajectory { t0, traj, warp } => {
                let (tau, rate, rate_d) = warp.at(*t0, t_s);
                traj.sample_into(tau, out);
                for i in 0..out.q.len() {
                    out.qdd[i] = out.qdd[i] * rate * rate + out.qd[i] * rate_d;
                    out.qd[i] *= rate;
                }
            }
            Motion::CartesianJog { t0, plan, refreshed, .. } => {
                let released = t_s >= refreshed + DEADMAN_S;
                plan.sample_into(t_s.min(refreshed + DEADMAN_S) - t0, out);
                if released {
                    out.qd.fill(0.0);
                    out.qdd.fill(0.0);
                }
            }
            Motion::Jog { t0, start, joint, vel, stop_at, refreshed } => {
                let t_end = t_s.min(refreshed + DEADMAN_S);
                let dt = (t_end - t0).max(0.0);
                out.set_rest(start);
                let free = start[*joint] + vel * dt;
                let reached = if *vel > 0.0 { free >= *stop_at } else { free <= *stop_at };
                if reached {
                    out.q[*joint] = *stop_at;
                } else {
                    out.q[*joint] = free;
                    if t_s < refreshed + DEADMAN_S {
                        out.qd[*joint] = *vel;
                    }
                }
            }
        }
    }

    /// Turns a finished motion into a hold at its end.
    fn retire(&mut self, t_s: f64) {
        let done_at = match &self.motion {
            Motion::Hold => None,
            Motion::Follow { t0, end_s, .. } => (t_s - t0 >= *end_s).then_some(t_s),
            Motion::Move { t0, mv } => mv.is_finished(t_s - t0).then_some(t_s),
            Motion::Jog { refreshed, .. } => (t_s > refreshed + DEADMAN_S).then_some(refreshed + DEADMAN_S),
            Motion::Trajectory { t0, traj, warp } => {
                warp.end_clock(*t0, traj.duration_s()).is_some_and(|end| t_s >= end).then_some(t_s)
            }
            Motion::CartesianJog { t0, plan, refreshed, .. } => {
                let end = (t0 + plan.duration_s()).min(refreshed + DEADMAN_S);
                (t_s > end).then_some(end)
            }
        };
        if let Some(t) = done_at {
            self.hold(t);
        }
    }

    fn hold(&mut self, t_s: f64) {
        let q = self.setpoint_at(t_s).q;
        self.goal.clone_from(&q);
        self.hold_q = q;
        self.motion = Motion::Hold;
    }

    fn apply_at(&mut self, cmd: &MotionCommand, t_s: f64) -> Result<(), MotionError> {
        if !t_s.is_finite() {
            return Err(MotionError::Invalid(format!("command time {t_s} is not a finite number")));
        }
        self.validate(cmd)?;
        self.retire(t_s);
        let here = self.setpoint_at(t_s).q;
        match cmd {
            MotionCommand::Follow { target_rad, speed_fraction } => {
                let target = self.limits.enforce(target_rad, LimitPolicy::Reject)?;
                let f = speed_fraction.min(1.0);
                let speed: Vec<f64> = self.caps.speed_rad_s.iter().map(|v| v * f).collect();
                let end_s =
                    here.iter().zip(&target).zip(&speed).map(|((a, b), v)| (b - a).abs() / v).fold(0.0, f64::max);
                self.goal.clone_from(&target);
                self.motion = Motion::Follow { t0: t_s, start: here, target, speed, end_s };
            }
            MotionCommand::MoveJoints { goal_rad, speed_fraction, profile } => {
                let goal = self.limits.enforce(goal_rad, LimitPolicy::Reject)?;
                self.start_move(here, goal, *speed_fraction, *profile, t_s)?;
            }
            MotionCommand::Home { speed_fraction, profile } => {
                let goal = self.limits.enforce(&self.home, LimitPolicy::Clamp)?;
                self.start_move(here, goal, *speed_fraction, *profile, t_s)?;
            }
            MotionCommand::JogJoint { joint, fraction } => {
                let (joint, fraction) = (*joint, fraction.clamp(-1.0, 1.0));
                let vel = fraction * self.caps.speed_rad_s[joint];
                if let Motion::Jog { joint: j, vel: v, refreshed, .. } = &mut self.motion
                    && *j == joint
                    && *v == vel
                {
                    *refreshed = t_s;
                    self.applied += 1;
                    return Ok(());
                }
                if vel == 0.0 {
                    self.hold(t_s);
                    self.applied += 1;
                    return Ok(());
                }
                let lim = self.limits.get(joint).ok_or_else(|| MotionError::Invalid(format!("no joint {joint}")))?;
                let stop_at = if vel > 0.0 { lim.max } else { lim.min };
                if let Some(why) = jog_refusal(&self.limits, &here, joint, fraction) {
                    return Err(MotionError::Invalid(why));
                }
                let mut goal = here.clone();
                goal[joint] = stop_at;
                self.goal = goal;
                self.motion = Motion::Jog { t0: t_s, start: here, joint, vel, stop_at, refreshed: t_s };
            }
            MotionCommand::JogCartesian { frame, axis, fraction } => {
                let fraction = fraction.clamp(-1.0, 1.0);
                let key = (*frame, *axis, fraction);
                if let Motion::CartesianJog { key: k, refreshed, .. } = &mut self.motion
                    && *k == key
                {
                    *refreshed = t_s;
                    self.applied += 1;
                    return Ok(());
                }
                if fraction == 0.0 {
                    self.hold(t_s);
                    self.applied += 1;
                    return Ok(());
                }
                let kin = self.kinematics.as_ref().ok_or_else(no_kinematics)?;
                let plan = CartesianJogPlan::plan(kin, &self.caps, &here, *frame, *axis, fraction)?;
                self.goal = plan.end_q().to_vec();
                self.motion = Motion::CartesianJog { t0: t_s, plan: Arc::new(plan), key, refreshed: t_s };
            }
            MotionCommand::CartesianStep { frame, axis, distance, speed_fraction } => {
                let kin = self.kinematics.as_ref().ok_or_else(no_kinematics)?;
                let traj = super::cartesian_step::plan_step(
                    kin,
                    &self.caps,
                    &here,
                    *frame,
                    *axis,
                    *distance,
                    *speed_fraction,
                )?;
                validate_trajectory(&self.limits, &traj)?;
                self.goal = traj.goal().to_vec();
                self.motion = Motion::Trajectory { t0: t_s, traj, warp: TimeWarp::Normal };
            }
            MotionCommand::JogRelease => {
                if matches!(self.motion, Motion::Jog { .. } | Motion::CartesianJog { .. }) {
                    self.hold(t_s);
                }
            }
            MotionCommand::Stop => self.hold(t_s),
            MotionCommand::Pause => self.pause(t_s),
            MotionCommand::Resume => self.resume(t_s),
            MotionCommand::Trajectory(traj) => {
                let start = traj.samples().first().map(Vec::as_slice).unwrap_or(&[]);
                let gap = start.iter().zip(&here).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                if start.len() != here.len() || gap > TRAJECTORY_START_TOLERANCE_RAD {
                    return Err(MotionError::Invalid(format!(
                        "the trajectory starts {:.4}° away from the commanded position{}",
                        gap.to_degrees(),
                        self.still_running_note(t_s, start)
                    )));
                }
                self.goal = traj.goal().to_vec();
                self.motion = Motion::Trajectory { t0: t_s, traj: Arc::clone(traj), warp: TimeWarp::Normal };
            }
        }
        self.applied += 1;
        Ok(())
    }

    /// Why a trajectory that starts where the running one ends came too early: that one started
    /// late (a scheduled command that arrives after its time starts when it arrives), so the
    /// schedule it was planned on no longer holds. Empty otherwise.
    fn still_running_note(&self, t_s: f64, start: &[f64]) -> String {
        let Motion::Trajectory { t0, traj, warp } = &self.motion else { return String::new() };
        let continues = traj.goal().len() == start.len()
            && traj.goal().iter().zip(start).all(|(a, b)| (a - b).abs() <= TRAJECTORY_START_TOLERANCE_RAD);
        match warp.end_clock(*t0, traj.duration_s()) {
            Some(end) if continues && end > t_s => format!(
                " (it continues the trajectory running now, which ends {:.0} ms later: that one started late, \
                 the schedule was not kept)",
                (end - t_s) * 1e3
            ),
            _ => String::new(),
        }
    }

    /// Slows a trajectory to a stop on its path; any other motion holds at once (STOP).
    fn pause(&mut self, t_s: f64) {
        let Motion::Trajectory { t0, traj, warp } = &self.motion else {
            self.hold(t_s);
            return;
        };
        if warp.is_pausing() {
            return;
        }
        let (tau_s, rate, _) = warp.at(*t0, t_s);
        // the ramp is sized for the path's full speed here; from a lower rate (a pause during
        // a resume ramp) the stop starts part-way down the same ramp, so the rate stays
        // continuous
        let ramp_s = ramp_for(&traj.sample(tau_s).qd, &self.caps.accel_rad_s2);
        let (t_start, ramp) = if rate < 1.0 { (t_s - ramp_s * (1.0 - rate), ramp_s) } else { (t_s, ramp_s) };
        let tau_start = tau_s - (t_s - t_start) + (t_s - t_start).powi(2) / (2.0 * ramp);
        let (t0, traj) = (*t0, Arc::clone(traj));
        self.motion =
            Motion::Trajectory { t0, traj, warp: TimeWarp::Pausing { t_s: t_start, tau_s: tau_start, ramp_s: ramp } };
    }

    /// Picks up a paused trajectory where it stopped (nothing to do otherwise).
    fn resume(&mut self, t_s: f64) {
        let Motion::Trajectory { t0, traj, warp } = &self.motion else { return };
        if !warp.is_stopped(t_s) {
            return;
        }
        let (tau_s, _, _) = warp.at(*t0, t_s);
        let TimeWarp::Pausing { ramp_s, .. } = *warp else { return };
        let (t0, traj) = (*t0, Arc::clone(traj));
        self.motion = Motion::Trajectory { t0, traj, warp: TimeWarp::Resuming { t_s, tau_s, ramp_s } };
    }

    fn start_move(
        &mut self,
        start: Vec<f64>,
        goal: Vec<f64>,
        speed_fraction: f64,
        profile: crate::profile::ProfileKind,
        t_s: f64,
    ) -> Result<(), MotionError> {
        let mv = self.caps.plan_joint_move(&start, &goal, speed_fraction, profile)?;
        self.goal = goal;
        self.motion = Motion::Move { t0: t_s, mv };
        Ok(())
    }
}

fn no_kinematics() -> MotionError {
    MotionError::Invalid("this backend has no kinematic model for Cartesian commands".into())
}

mod schedule;

#[cfg(test)]
mod tests;

//! Simulation: the robot as a rapier multibody stepped at a fixed rate (1 kHz by default).
//!
//! - [`Simulation`] is the deterministic, thread-free core: [`Simulation::apply`] a
//!   [`SimCommand`], [`Simulation::step`] one fixed time step, read a [`SimSnapshot`]. Tests and
//!   headless runs drive it directly, faster than real time. Motion comes from the shared
//!   [`MotionPlanner`] (the serial session uses the same one), sampled at every step.
//! - [`SimHandle`] runs a `Simulation` on its own thread, locked to wall-clock time. Commands go
//!   in through a bounded channel and never block the caller; the latest state comes out as a
//!   lock-free snapshot.
//!
//! Every target passes the planner's limit check before it reaches the multibody, and, when
//! [`SimConfig::check_collisions`] is on, the self-collision guard ([`crate::collision`]) before a
//! target or a profiled move is accepted. Joint torques come from recursive Newton–Euler
//! inverse dynamics ([`crate::dynamics`]).

use std::time::Instant;

use crossbeam_channel::Sender;

use crate::collision::{CollisionGuard, CollisionReport};
use crate::dynamics::InverseDynamics;
use crate::limits::LimitPolicy;
use crate::model::RobotModel;
use crate::motion::{
    JogKinematics, JointDrive, MotionCaps, MotionCommand, MotionPlanner, MotionSample, Setpoint,
    cartesian_jog::JogObstacleCheck, home_position,
};

pub mod multibody;
mod servo;
mod step;
mod thread;
pub mod torque_profile;
mod types;

pub use multibody::{MotorGains, Physics};
pub use thread::{SimHandle, SimStats};
pub use torque_profile::{TorqueProfile, TorqueRun};
pub use types::{ServoModel, SimCommand, SimConfig, SimError, SimMode, SimSnapshot};

/// Time constant of the low-pass filter on the measured joint acceleration, s.
const QDD_FILTER_S: f64 = 0.005;
/// Measured joint speed below which a still setpoint counts toward rest, rad/s.
const REST_QD_RAD_S: f64 = 1e-4;
/// With the firmware servo the measured joints are the drives' step counters (still means
/// exactly still); the links carried to them count as settled below this speed, rad/s (they
/// keep a residual ~1e-4 rad/s of solver jitter, 0.006°/s).
const REST_LINK_QD_RAD_S: f64 = 1e-3;
/// Steps of a still setpoint and a still arm after which the physics is no longer stepped
/// (0.5 s at 1 kHz): the arm holds exactly where it settled until the next command.
const REST_AFTER_STEPS: u32 = 500;
/// While resting, the tap gets a sample every this many steps (100 Hz at 1 kHz, the robot's
/// own rate): a thousand equal samples a second cost the simulation and the recorder ~0.5 % of
/// a core between them in an idle window.
const RESTING_TAP_EVERY_STEPS: u64 = 10;

/// The deterministic simulation core (no thread). See the module docs.
pub struct Simulation {
    model: RobotModel,
    config: SimConfig,
    dt_s: f64,
    mode: SimMode,
    physics: Physics,
    guard: CollisionGuard,
    id: InverseDynamics,
    planner: MotionPlanner,
    /// Dynamic mode under user torques (motors off) instead of the planner.
    torque_control: bool,
    /// The forward-dynamics run under way, with its start time, s.
    torque_run: Option<(TorqueRun, f64)>,
    /// Commanded setpoint of the last step (position, velocity, acceleration).
    sp: Setpoint,
    user_torques: Vec<f64>,
    io: crate::motion::IoState,
    tap: Option<Sender<MotionSample>>,
    tap_dropped: u64,
    /// Samples offered to the tap (their `seq`).
    tap_seq: u64,
    /// The simulated PAROL6 board's drives ([`ServoModel::Firmware`]); `None`: ideal motors.
    servo: Option<servo::SimServo>,
    /// Measured state (the drives' step counters with the firmware servo, else the links).
    q: Vec<f64>,
    qd: Vec<f64>,
    /// The rapier links' joint state (dynamic mode).
    link_q: Vec<f64>,
    link_qd: Vec<f64>,
    torques: Vec<f64>,
    ff: Vec<f64>,
    qd_prev: Vec<f64>,
    /// Actuator speed saturation per joint, rad/s ([`speed_caps`]).
    speed_cap: Vec<f64>,
    /// Measured joint acceleration, low-passed.
    qdd_filt: Vec<f64>,
    /// Consecutive steps with a still setpoint and a still arm.
    rest_steps: u32,
    steps: u64,
    collision: Option<CollisionReport>,
    last_step_ns: u64,
    step_rate_hz: f64,
    last_command_latency_ns: Option<u64>,
    last_error: Option<(u64, String)>,
    error_seq: u64,
    /// Check the current configuration for collisions every this many steps.
    collision_every: u64,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("robot", &self.model.name)
            .field("steps", &self.steps)
            .finish_non_exhaustive()
    }
}

/// Per-joint speed (rad/s) and acceleration (rad/s²) caps of profiled motion.
pub fn motion_caps(model: &RobotModel) -> (Vec<f64>, Vec<f64>) {
    let c = MotionCaps::of(model);
    (c.speed_rad_s, c.accel_rad_s2)
}

/// Speed at which each joint's actuator saturates in dynamic mode, rad/s: for the PAROL6 the
/// firmware's 50 000 steps/s cap (ROBOT.md §1) through each joint's gearing; otherwise twice
/// the URDF velocity limit (10 rad/s when absent).
pub fn speed_caps(model: &RobotModel) -> Vec<f64> {
    if model.is_parol6 && model.dof() == crate::parol6::JOINT_COUNT {
        return (0..crate::parol6::JOINT_COUNT).map(|j| FW_MAX_STEPS_S * crate::parol6::rad_per_step(j)).collect();
    }
    model
        .limits
        .iter()
        .map(|l| if l.max_velocity.is_finite() && l.max_velocity > 0.0 { 2.0 * l.max_velocity } else { 10.0 })
        .collect()
}

/// The PAROL6 firmware's step-rate cap for every joint, steps/s (ROBOT.md §1).
const FW_MAX_STEPS_S: f64 = 50_000.0;

impl Simulation {
    /// Builds the simulation at the home position, at rest.
    pub fn new(model: RobotModel, config: SimConfig) -> Result<Self, SimError> {
        if !(config.rate_hz.is_finite() && config.rate_hz >= 10.0 && config.rate_hz <= 100_000.0) {
            return Err(SimError::Config(format!("rate_hz must lie in 10..=100000 (got {})", config.rate_hz)));
        }
        let n = model.dof();
        let dt_s = 1.0 / config.rate_hz;
        let home = model.limits.enforce(&home_position(&model), LimitPolicy::Clamp)?;
        let mut physics = Physics::build(&model, dt_s)?;
        physics.teleport(&home);
        let guard = CollisionGuard::new(&model);
        let id = InverseDynamics::new(&model);
        let collision_every = (config.rate_hz / 100.0).round().max(1.0) as u64;
        // Cartesian jogs stop before a collision when the guard is on
        let obstacles: Option<std::sync::Arc<dyn JogObstacleCheck>> =
            config.check_collisions.then(|| std::sync::Arc::new(guard.clone()) as _);
        let kinematics = JogKinematics { model: std::sync::Arc::new(model.clone()), obstacles };
        let planner = MotionPlanner::new(model.limits.clone(), MotionCaps::of(&model), home.clone(), &home)
            .with_kinematics(kinematics);
        let mut sim = Self {
            dt_s,
            mode: config.mode,
            physics,
            guard,
            id,
            planner,
            torque_control: false,
            torque_run: None,
            sp: Setpoint::at_rest(&home),
            servo: (config.servo == ServoModel::Firmware && model.is_parol6 && n == crate::parol6::JOINT_COUNT)
                .then(|| servo::SimServo::new(&home, config.tracking, dt_s)),
            link_q: home.clone(),
            link_qd: vec![0.0; n],
            user_torques: vec![0.0; n],
            io: crate::motion::IoState::default(),
            tap: None,
            tap_dropped: 0,
            tap_seq: 0,
            q: home,
            qd: vec![0.0; n],
            torques: vec![0.0; n],
            ff: vec![0.0; n],
            qd_prev: vec![0.0; n],
            speed_cap: speed_caps(&model),
            qdd_filt: vec![0.0; n],
            rest_steps: 0,
            steps: 0,
            collision: None,
            last_step_ns: 0,
            step_rate_hz: config.rate_hz,
            last_command_latency_ns: None,
            last_error: None,
            error_seq: 0,
            collision_every,
            model,
            config,
        };
        let q0 = sim.q.clone();
        sim.hold_drives_at(&q0);
        sim.collision = sim.guard.check(&sim.model, &sim.q);
        sim.update_torques();
        Ok(sim)
    }

    /// The robot model.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// The settings.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// Fixed time step, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// Simulated time, s.
    pub fn sim_time_s(&self) -> f64 {
        self.steps as f64 * self.dt_s
    }

    /// Joint positions, rad.
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// Joint velocities, rad/s.
    pub fn qd(&self) -> &[f64] {
        &self.qd
    }

    /// Current mode.
    pub fn mode(&self) -> SimMode {
        self.mode
    }

    /// True while a move or jog is under way.
    pub fn is_moving(&self) -> bool {
        self.torque_run.is_some() || (!self.torque_control && self.planner.is_moving(self.sim_time_s()))
    }

    /// The motion planner (read access).
    pub fn planner(&self) -> &MotionPlanner {
        &self.planner
    }

    /// Sends a [`MotionSample`] of every step to `tap`, of every tenth while the arm rests
    /// ([`Simulation::resting`]); `seq` counts the samples sent (bounded; samples are dropped
    /// and counted, never waited for, when it is full).
    pub fn set_tap(&mut self, tap: Option<Sender<MotionSample>>) {
        self.tap = tap;
    }

    /// Samples the tap could not take.
    pub fn tap_dropped(&self) -> u64 {
        self.tap_dropped
    }

    /// The self-collision guard.
    pub fn guard(&self) -> &CollisionGuard {
        &self.guard
    }

    /// The rapier world (read access, e.g. for tests and diagnostics).
    pub fn physics(&self) -> &Physics {
        &self.physics
    }

    /// Records a refused command in the snapshot's `last_error` (threaded runs).
    pub(crate) fn record_error(&mut self, e: &SimError) {
        self.error_seq += 1;
        self.last_error = Some((self.error_seq, e.to_string()));
    }

    /// Records a command's creation → applied latency.
    pub(crate) fn record_latency(&mut self, created: Instant, applied: Instant) {
        let ns = applied.saturating_duration_since(created).as_nanos();
        self.last_command_latency_ns = Some(u64::try_from(ns).unwrap_or(u64::MAX));
    }

    pub(crate) fn set_step_rate_hz(&mut self, hz: f64) {
        self.step_rate_hz = hz;
    }

    fn check_target(&self, q: &[f64]) -> Result<Vec<f64>, SimError> {
        let t = self.model.limits.enforce(q, self.config.policy)?;
        if self.config.check_collisions
            && let Some(c) = self.guard.check(&self.model, &t)
        {
            return Err(SimError::Collision { link_a: c.link_a, link_b: c.link_b, at_s: 0.0 });
        }
        Ok(t)
    }

    /// The simulation's limit policy applied to a motion command's target (clamp or keep).
    fn with_policy(&self, cmd: MotionCommand) -> Result<MotionCommand, SimError> {
        if self.config.policy != LimitPolicy::Clamp {
            return Ok(cmd);
        }
        Ok(match cmd {
            MotionCommand::Follow { target_rad, speed_fraction } => MotionCommand::Follow {
                target_rad: self.model.limits.enforce(&target_rad, LimitPolicy::Clamp)?,
                speed_fraction,
            },
            MotionCommand::MoveJoints { goal_rad, speed_fraction, profile } => MotionCommand::MoveJoints {
                goal_rad: self.model.limits.enforce(&goal_rad, LimitPolicy::Clamp)?,
                speed_fraction,
                profile,
            },
            other => other,
        })
    }

    /// Applies a motion command at `t_s`: planned on a copy first, whose swept path is checked
    /// for collisions; a refused command leaves the simulation unchanged.
    fn apply_motion(&mut self, cmd: MotionCommand, t_s: f64, immediate: bool) -> Result<(), SimError> {
        if self.io.drives_disabled && cmd.starts_motion() {
            return Err(SimError::DrivesDisabled);
        }
        let cmd = self.with_policy(cmd)?;
        if self.torque_control {
            self.leave_torque_control();
        }
        let mut next = self.planner.clone();
        if immediate {
            next.apply(&cmd, t_s)?;
        } else {
            next.apply_scheduled(&cmd, t_s)?;
        }
        // a Cartesian jog was planned to stop before the first contact (not refused)
        if self.config.check_collisions
            && cmd.starts_motion()
            && !matches!(cmd, MotionCommand::JogCartesian { .. })
            && let Some((c, at_s)) = self.guard.check_planned(&self.model, &next, t_s)
        {
            return Err(SimError::Collision { link_a: c.link_a, link_b: c.link_b, at_s });
        }
        self.planner = next;
        Ok(())
    }

    /// Applies a command. Refused commands leave the simulation unchanged.
    pub fn apply(&mut self, cmd: SimCommand) -> Result<(), SimError> {
        self.rest_steps = 0;
        let now = self.sim_time_s();
        match cmd {
            SimCommand::Motion(m) => self.apply_motion(m, now, true)?,
            SimCommand::MotionAt { cmd, at_s } => {
                self.planner.note_scheduled();
                if self.io.drives_disabled && cmd.starts_motion() {
                    return Err(SimError::DrivesDisabled);
                }
                let cmd = self.with_policy(cmd)?;
                self.planner.schedule_arriving(cmd, at_s, now)?;
            }
            SimCommand::Teleport(q) => {
                let t = self.check_target(&q)?;
                self.physics.teleport(&t);
                self.q.copy_from_slice(&t);
                self.qd.fill(0.0);
                self.hold_drives_at(&t);
                self.qdd_filt.fill(0.0);
                self.sp = Setpoint::at_rest(&t);
                self.user_torques.fill(0.0);
                self.physics.set_motors_enabled(true);
                self.torque_control = false;
                self.torque_run = None;
                self.planner.reset(&t);
                self.collision = self.guard.check(&self.model, &self.q);
                self.update_torques();
            }
            SimCommand::SetMode(mode) => {
                if mode != self.mode {
                    let here = self.model.limits.enforce(&self.q, LimitPolicy::Clamp)?;
                    self.leave_torque_control();
                    self.physics.teleport(&here);
                    self.q.copy_from_slice(&here);
                    self.qd.fill(0.0);
                    self.hold_drives_at(&here);
                    self.qdd_filt.fill(0.0);
                    self.sp = Setpoint::at_rest(&here);
                    self.planner.reset(&here);
                    self.mode = mode;
                }
            }
            SimCommand::SetTracking(mode) => {
                if let Some(servo) = self.servo.as_mut() {
                    servo.set_mode(mode);
                }
                self.config.tracking = mode;
            }
            SimCommand::Io(io) => {
                io.validate().map_err(SimError::InvalidCommand)?;
                if io == crate::motion::IoCommand::Disable {
                    // as the board: the drives stop where they are, the schedule is dropped
                    self.apply_motion(MotionCommand::Stop, now, true)?;
                }
                self.io.apply(&io);
            }
            SimCommand::ApplyJointTorques(tau) => {
                if self.mode != SimMode::Dynamic {
                    return Err(SimError::InvalidCommand("joint torques need dynamic mode".into()));
                }
                if tau.len() != self.model.dof() {
                    return Err(SimError::InvalidCommand(format!(
                        "expected {} joint torques, got {}",
                        self.model.dof(),
                        tau.len()
                    )));
                }
                if let Some(i) = tau.iter().position(|t| !t.is_finite()) {
                    return Err(SimError::InvalidCommand(format!("torque of joint {} is not finite", i + 1)));
                }
                self.user_torques.copy_from_slice(&tau);
                self.physics.set_motors_enabled(false);
                self.torque_control = true;
                self.torque_run = None;
            }
            SimCommand::RunJointTorques(run) => {
                if self.mode != SimMode::Dynamic {
                    return Err(SimError::InvalidCommand("a torque run needs dynamic mode".into()));
                }
                run.validate(self.model.dof()).map_err(SimError::InvalidCommand)?;
                self.physics.set_motors_enabled(false);
                self.physics.hold_joints(&run.held_joints());
                self.torque_control = true;
                self.torque_run = Some((run, now));
                self.update_run_torques();
            }
        }
        Ok(())
    }

    /// Back from user torques to the planner, holding where the joints are.
    fn leave_torque_control(&mut self) {
        if self.torque_control {
            self.torque_control = false;
            self.torque_run = None;
            self.user_torques.fill(0.0);
            self.physics.set_motors_enabled(true);
            let here: Vec<f64> = self.model.limits.iter().zip(&self.q).map(|(l, &v)| l.clamp(v)).collect();
            self.sp = Setpoint::at_rest(&here);
            self.planner.reset(&here);
            self.hold_drives_at(&here);
        }
    }

    /// The firmware servo's drives at rest at `q` (whole steps), the measured joints with them.
    fn hold_drives_at(&mut self, q: &[f64]) {
        self.link_q.copy_from_slice(q);
        self.link_qd.fill(0.0);
        if let Some(servo) = self.servo.as_mut() {
            servo.teleport(q);
            servo.read(&mut self.q, &mut self.qd);
        }
    }

    /// The tracking mode of the simulated board.
    pub fn tracking(&self) -> crate::motion::tracking::TrackingMode {
        self.servo.as_ref().map_or(self.config.tracking, servo::SimServo::mode)
    }

    /// Advances the setpoint by one step: scheduled commands due by then are applied at their
    /// exact time (collision-checked like immediate ones), then the planner is sampled.
    fn advance_setpoint(&mut self) {
        let t_next = self.sim_time_s() + self.dt_s;
        if self.torque_control {
            self.sp.qd.fill(0.0);
            self.sp.qdd.fill(0.0);
            return;
        }
        while let Some((at_s, cmd)) = self.planner.pop_due(t_next) {
            if let Err(e) = self.apply_motion(cmd.clone(), at_s, false) {
                self.record_error(&SimError::InvalidCommand(format!("{} at t = {at_s:.3} s refused: {e}", cmd.name())));
            }
        }
        self.planner.sample_into(t_next, &mut self.sp);
    }

    /// Advances the simulation by one fixed time step.
    pub fn step(&mut self) {
        let t0 = Instant::now();
        self.update_run_torques();
        // the board's drives: this frame's target (planner sampled at this step's start), 1 step
        let driven = !self.torque_control && self.servo.is_some();
        if let Some(servo) = self.servo.as_mut().filter(|_| driven) {
            servo.step(self.steps, self.steps as f64 * self.dt_s, self.dt_s, &self.planner, &self.sp);
        }
        self.advance_setpoint();
        match self.mode {
            SimMode::Kinematic => match self.servo.as_ref() {
                Some(servo) => servo.read(&mut self.q, &mut self.qd),
                None => {
                    self.q.copy_from_slice(&self.sp.q);
                    self.qd.copy_from_slice(&self.sp.qd);
                }
            },
            SimMode::Dynamic => {
                let (drives_still, link_qd_max) = match self.servo.as_ref() {
                    Some(s) => (!s.moving(), REST_LINK_QD_RAD_S),
                    None => (true, REST_QD_RAD_S),
                };
                let still = !self.torque_control
                    && self.torque_run.is_none()
                    && drives_still
                    && self.sp.qd.iter().chain(&self.sp.qdd).all(|v| *v == 0.0)
                    && self.link_qd.iter().all(|v| v.abs() < link_qd_max);
                // a rest starts counting on the tap's 10-step grid, so that its samples stay on it
                let counting = self.rest_steps > 0 || self.steps.is_multiple_of(RESTING_TAP_EVERY_STEPS);
                self.rest_steps = if still && counting { self.rest_steps.saturating_add(1) } else { 0 };
                if !self.resting() {
                    self.step_physics();
                }
            }
        }
        self.steps += 1;
        if self.tap.is_some() && !self.resting() {
            // the torques of this step (inverse dynamics of the measured motion), only when tapped
            self.update_torques();
        }
        // at rest nothing changes: the state is reported at the robot's rate, not every step
        if let Some(tap) = &self.tap
            && (!self.resting() || self.steps.is_multiple_of(RESTING_TAP_EVERY_STEPS))
        {
            self.tap_seq += 1;
            let sample = MotionSample {
                seq: self.tap_seq,
                time_s: self.sim_time_s(),
                commanded: self.sp.clone(),
                measured_q: self.q.clone(),
                measured_qd: self.qd.clone(),
                drive: JointDrive::TorqueNm(self.torques.clone()),
            };
            if tap.try_send(sample).is_err() {
                self.tap_dropped += 1;
            }
        }
        if self.steps.is_multiple_of(self.collision_every) && !self.resting() {
            self.collision = self.guard.check(&self.model, &self.q);
        }
        self.last_step_ns = u64::try_from(t0.elapsed().as_nanos()).unwrap_or(u64::MAX);
    }

    /// Whether the arm has settled with nothing commanded, so that its physics is not stepped.
    pub fn resting(&self) -> bool {
        self.rest_steps > REST_AFTER_STEPS
    }

    /// Resting with nothing scheduled: until the next command nothing will change, so the
    /// real-time thread may wake seldom (see [`SimHandle`]).
    pub fn dormant(&self) -> bool {
        self.resting() && self.planner.pending() == 0
    }

    /// The current state. The joint torques are computed here (inverse dynamics of the current
    /// motion), not on every step: the real-time thread publishes every few steps.
    pub fn snapshot(&mut self) -> SimSnapshot {
        self.update_torques();
        let link_poses = self.model.link_poses(&self.q);
        let tcp = self.model.fk(&self.q);
        SimSnapshot {
            seq: self.steps,
            sim_time_s: self.sim_time_s(),
            q: self.q.clone(),
            qd: self.qd.clone(),
            torques_nm: self.torques.clone(),
            target_q: self.planner.goal().to_vec(),
            commanded: self.sp.clone(),
            planner_mode: self.planner.mode(),
            commands_applied: self.planner.applied(),
            schedule: self.planner.schedule_state(),
            link_poses,
            tcp,
            zones: self.model.limits.zone_reports(&self.q, &self.qd, &self.config.thresholds),
            collision: self.collision.clone(),
            moving: self.is_moving(),
            torque_run: self.torque_run.is_some(),
            mode: self.mode,
            last_step_ns: self.last_step_ns,
            step_rate_hz: self.step_rate_hz,
            last_command_latency_ns: self.last_command_latency_ns,
            last_error: self.last_error.clone(),
            io: self.io,
        }
    }
}

#[cfg(test)]
mod dynamics_tests;
#[cfg(test)]
mod rest_tests;
#[cfg(test)]
pub(crate) mod tests;

//! Simulation: the robot as a rapier multibody stepped at a fixed rate (1 kHz by default).
//!
//! - [`Simulation`] is the deterministic, thread-free core: [`Simulation::apply`] a
//!   [`SimCommand`], [`Simulation::step`] one fixed time step, read a [`SimSnapshot`]. Tests and
//!   headless runs drive it directly, faster than real time.
//! - [`SimHandle`] runs a `Simulation` on its own thread, locked to wall-clock time. Commands go
//!   in through a bounded channel and never block the caller; the latest state comes out as a
//!   lock-free snapshot.
//!
//! Every target passes the model's [`LimitPolicy`] before it reaches the multibody, and, when
//! [`SimConfig::check_collisions`] is on, the self-collision guard ([`collision`]) before a
//! target or a profiled move is accepted. Joint torques come from recursive Newton–Euler
//! inverse dynamics ([`dynamics`]).

use std::time::Instant;

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use crate::kinematics::TcpPose;
use crate::limits::{LimitPolicy, LimitViolation, ZoneReport, ZoneThresholds};
use crate::model::RobotModel;
use crate::profile::{JointMove, ProfileError, ProfileKind};

pub mod collision;
pub mod dynamics;
pub mod multibody;
mod thread;

pub use collision::{CollisionGuard, CollisionReport};
pub use dynamics::{InverseDynamics, JointTorques};
pub use multibody::{MotorGains, Physics};
pub use thread::{SimHandle, SimStats, thread_cpu_time_ns};

/// How the joints move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum SimMode {
    /// Joints follow the commanded setpoint exactly (no physics; torques from inverse dynamics).
    Kinematic,
    /// The rapier multibody is stepped under gravity; position motors track the setpoint.
    #[default]
    Dynamic,
}

/// Settings of a [`Simulation`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimConfig {
    /// What to do with a target outside the joint limits.
    pub policy: LimitPolicy,
    /// Limit-zone thresholds for [`SimSnapshot::zones`].
    pub thresholds: ZoneThresholds,
    /// Step rate, Hz (1000). The time step is `1 / rate_hz` of simulated time.
    pub rate_hz: f64,
    /// Mode at start.
    pub mode: SimMode,
    /// Refuse targets and moves that collide (self-collision and ground).
    pub check_collisions: bool,
    /// Speed fraction used by [`SimCommand::Home`] (0.5).
    pub speed_fraction: f64,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            policy: LimitPolicy::Reject,
            thresholds: ZoneThresholds::default(),
            rate_hz: 1000.0,
            mode: SimMode::Dynamic,
            check_collisions: true,
            speed_fraction: 0.5,
        }
    }
}

/// A command to the simulation. Joint vectors are in chain order, rad.
#[derive(Debug, Clone, PartialEq)]
pub enum SimCommand {
    /// Move toward these joint values, each joint at its speed limit (jogging); the path is
    /// checked for collisions like a move's.
    SetJointTargets(Vec<f64>),
    /// A synchronised profiled move to `goal`.
    MoveTo {
        /// Goal joint values, rad.
        goal: Vec<f64>,
        /// Fraction of the joint speed / acceleration caps (0 < f ≤ 1).
        speed_fraction: f64,
        /// Profile shape.
        kind: ProfileKind,
    },
    /// Stop where the joints are now (holds position; ends torque control).
    Stop,
    /// Profiled move to the model's home (PAROL6 standby) at [`SimConfig::speed_fraction`].
    Home,
    /// Put the joints at these values instantly, at rest.
    Teleport(Vec<f64>),
    /// Switch between kinematic and dynamic stepping.
    SetMode(SimMode),
    /// Dynamic mode: drive the joints with these torques (N·m), motors off, until a position
    /// command. Kinematic mode refuses it.
    ApplyJointTorques(Vec<f64>),
}

/// Why a command was refused or the simulation could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// The target breaks a joint limit (policy [`LimitPolicy::Reject`]) or is malformed.
    #[error("limit: {0}")]
    Limit(#[from] LimitViolation),
    /// The target, or the swept path of a move, collides.
    #[error("collision: {link_a} hits {link_b} at t = {at_s:.3} s along the move")]
    Collision {
        /// First link.
        link_a: String,
        /// Second link (or `ground`).
        link_b: String,
        /// Time along the move at which the first contact occurs, s (0 for a plain target).
        at_s: f64,
    },
    /// The move cannot be planned.
    #[error("profile: {0}")]
    Profile(#[from] ProfileError),
    /// A command that is not valid now, e.g. torques of the wrong length or in kinematic mode.
    #[error("invalid command: {0}")]
    InvalidCommand(String),
    /// The command channel is full (the simulation is not keeping up).
    #[error("simulation command queue is full")]
    ChannelFull,
    /// The simulation thread has stopped.
    #[error("simulation thread has stopped")]
    ChannelClosed,
    /// The multibody could not be built from the model.
    #[error("cannot build the multibody: {0}")]
    Build(String),
    /// The settings are invalid (e.g. a rate that is not a positive number).
    #[error("invalid simulation config: {0}")]
    Config(String),
}

/// The state of the simulation after a step.
#[derive(Debug, Clone, PartialEq)]
pub struct SimSnapshot {
    /// Number of steps taken.
    pub seq: u64,
    /// Simulated time, s.
    pub sim_time_s: f64,
    /// Joint positions, rad.
    pub q: Vec<f64>,
    /// Joint velocities, rad/s.
    pub qd: Vec<f64>,
    /// Joint torques, N·m: the inverse dynamics (gravity + inertial + Coriolis) of the motion
    /// taking place — measured state with its low-passed acceleration in dynamic mode, the
    /// commanded motion in kinematic mode; under torque control, the applied torques.
    pub torques_nm: Vec<f64>,
    /// Where the joints are going: the goal of the move or the jog target, rad.
    pub target_q: Vec<f64>,
    /// World pose of every link (order of [`RobotModel::links`]).
    pub link_poses: Vec<Isometry3<f64>>,
    /// TCP pose.
    pub tcp: TcpPose,
    /// Limit zone of every joint.
    pub zones: Vec<ZoneReport>,
    /// A collision in the current configuration, if any.
    pub collision: Option<CollisionReport>,
    /// True while a move or jog is under way.
    pub moving: bool,
    /// Current mode.
    pub mode: SimMode,
    /// Wall time of the last step, ns.
    pub last_step_ns: u64,
    /// Steps per second of wall time (threaded), or `rate_hz` when stepped by hand.
    pub step_rate_hz: f64,
    /// Creation → applied time of the last command, ns (threaded runs).
    pub last_command_latency_ns: Option<u64>,
    /// The last refused command: increasing id and message.
    pub last_error: Option<(u64, String)>,
}

/// Time constant of the low-pass filter on the measured joint acceleration, s.
const QDD_FILTER_S: f64 = 0.005;

/// What the joints are doing.
#[derive(Debug, Clone)]
enum Control {
    /// Hold the setpoint.
    Hold,
    /// Slew toward a target at each joint's speed limit.
    Jog,
    /// Follow a profiled move started at `t0_s` of simulated time.
    Profile { mv: JointMove, t0_s: f64 },
    /// Dynamic mode: user torques, motors off.
    Torque,
}

/// The deterministic simulation core (no thread). See the module docs.
pub struct Simulation {
    model: RobotModel,
    config: SimConfig,
    dt_s: f64,
    mode: SimMode,
    physics: Physics,
    guard: CollisionGuard,
    id: InverseDynamics,
    control: Control,
    /// Commanded setpoint (position, velocity, acceleration).
    sp_q: Vec<f64>,
    sp_qd: Vec<f64>,
    sp_qdd: Vec<f64>,
    target_q: Vec<f64>,
    user_torques: Vec<f64>,
    /// Measured state.
    q: Vec<f64>,
    qd: Vec<f64>,
    torques: Vec<f64>,
    ff: Vec<f64>,
    qd_prev: Vec<f64>,
    /// Actuator speed saturation per joint, rad/s ([`speed_caps`]).
    speed_cap: Vec<f64>,
    /// Speed at which jog targets are approached, rad/s (each joint's speed limit).
    jog_speed: Vec<f64>,
    /// Measured joint acceleration, low-passed.
    qdd_filt: Vec<f64>,
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

/// Home position of a model: the PAROL6 standby for the PAROL6, else each joint's mid-range
/// (0 for unbounded joints).
pub fn home_position(model: &RobotModel) -> Vec<f64> {
    if model.is_parol6 && model.dof() == crate::parol6::JOINT_COUNT {
        return crate::parol6::standby_rad().to_vec();
    }
    model.limits.iter().map(|l| if l.is_bounded() { 0.5 * (l.min + l.max) } else { 0.0 }).collect()
}

/// Per-joint speed (rad/s) and acceleration (rad/s²) caps for profiles: the PAROL6 API caps,
/// or for other robots the URDF velocity (2 rad/s when absent) and 3 × that per second.
pub fn motion_caps(model: &RobotModel) -> (Vec<f64>, Vec<f64>) {
    if model.is_parol6 && model.dof() == crate::parol6::JOINT_COUNT {
        return (crate::parol6::max_speed_rad_s().to_vec(), crate::parol6::max_accel_rad_s2().to_vec());
    }
    let v: Vec<f64> = model
        .limits
        .iter()
        .map(|l| if l.max_velocity.is_finite() && l.max_velocity > 0.0 { l.max_velocity } else { 2.0 })
        .collect();
    let a = v.iter().map(|v| 3.0 * v).collect();
    (v, a)
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
        if !(config.speed_fraction.is_finite() && config.speed_fraction > 0.0) {
            return Err(SimError::Config(format!("speed_fraction must be > 0 (got {})", config.speed_fraction)));
        }
        let n = model.dof();
        let dt_s = 1.0 / config.rate_hz;
        let home = model.limits.enforce(&home_position(&model), LimitPolicy::Clamp)?;
        let mut physics = Physics::build(&model, dt_s)?;
        physics.teleport(&home);
        let guard = CollisionGuard::new(&model);
        let id = InverseDynamics::new(&model);
        let collision_every = (config.rate_hz / 100.0).round().max(1.0) as u64;
        let mut sim = Self {
            dt_s,
            mode: config.mode,
            physics,
            guard,
            id,
            control: Control::Hold,
            sp_q: home.clone(),
            sp_qd: vec![0.0; n],
            sp_qdd: vec![0.0; n],
            target_q: home.clone(),
            user_torques: vec![0.0; n],
            q: home,
            qd: vec![0.0; n],
            torques: vec![0.0; n],
            ff: vec![0.0; n],
            qd_prev: vec![0.0; n],
            speed_cap: speed_caps(&model),
            jog_speed: motion_caps(&model).0,
            qdd_filt: vec![0.0; n],
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
        match &self.control {
            Control::Hold | Control::Torque => false,
            Control::Jog => self.sp_q.iter().zip(&self.target_q).any(|(a, b)| (a - b).abs() > 1e-12),
            Control::Profile { .. } => true,
        }
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

    /// Where a new move or jog starts: the setpoint, or under torque control the joints.
    fn start_q(&self) -> Vec<f64> {
        if matches!(self.control, Control::Torque) {
            self.model.limits.iter().zip(&self.q).map(|(l, &v)| l.clamp(v)).collect()
        } else {
            self.sp_q.clone()
        }
    }

    /// Plans and checks a profiled move from the current setpoint to `goal`.
    fn plan_move(&self, goal: &[f64], speed_fraction: f64, kind: ProfileKind) -> Result<JointMove, SimError> {
        let goal = self.model.limits.enforce(goal, self.config.policy)?;
        let (v, a) = motion_caps(&self.model);
        let start = self.model.limits.enforce(&self.start_q(), LimitPolicy::Clamp)?;
        let mv = JointMove::plan(&start, &goal, &v, &a, speed_fraction, kind)?;
        if self.config.check_collisions
            && let Some((c, at_s)) = self.guard.check_move(&self.model, &mv)
        {
            return Err(SimError::Collision { link_a: c.link_a, link_b: c.link_b, at_s });
        }
        Ok(mv)
    }

    /// Applies a command. Refused commands leave the simulation unchanged.
    pub fn apply(&mut self, cmd: SimCommand) -> Result<(), SimError> {
        match cmd {
            SimCommand::SetJointTargets(q) => {
                let t = self.model.limits.enforce(&q, self.config.policy)?;
                if self.config.check_collisions
                    && let Some((c, at_s)) = self.guard.check_jog(&self.model, &self.start_q(), &t, &self.jog_speed)
                {
                    return Err(SimError::Collision { link_a: c.link_a, link_b: c.link_b, at_s });
                }
                self.leave_torque_control();
                self.target_q = t;
                self.control = Control::Jog;
            }
            SimCommand::MoveTo { goal, speed_fraction, kind } => {
                let mv = self.plan_move(&goal, speed_fraction, kind)?;
                self.leave_torque_control();
                self.target_q = mv.goal().to_vec();
                self.control = Control::Profile { mv, t0_s: self.sim_time_s() };
            }
            SimCommand::Home => {
                let home = home_position(&self.model);
                let mv = self.plan_move(&home, self.config.speed_fraction, ProfileKind::Trapezoidal)?;
                self.leave_torque_control();
                self.target_q = mv.goal().to_vec();
                self.control = Control::Profile { mv, t0_s: self.sim_time_s() };
            }
            SimCommand::Stop => {
                self.leave_torque_control();
                let here = self.model.limits.enforce(&self.q, LimitPolicy::Clamp)?;
                self.sp_q.copy_from_slice(&here);
                self.sp_qd.fill(0.0);
                self.sp_qdd.fill(0.0);
                self.target_q = here;
                self.control = Control::Hold;
            }
            SimCommand::Teleport(q) => {
                let t = self.check_target(&q)?;
                self.physics.teleport(&t);
                self.q.copy_from_slice(&t);
                self.qd.fill(0.0);
                self.qdd_filt.fill(0.0);
                self.sp_q.copy_from_slice(&t);
                self.sp_qd.fill(0.0);
                self.sp_qdd.fill(0.0);
                self.user_torques.fill(0.0);
                self.physics.set_motors_enabled(true);
                self.target_q = t;
                self.control = Control::Hold;
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
                    self.qdd_filt.fill(0.0);
                    self.sp_q.copy_from_slice(&here);
                    self.sp_qd.fill(0.0);
                    self.sp_qdd.fill(0.0);
                    self.target_q = here;
                    self.control = Control::Hold;
                    self.mode = mode;
                }
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
                self.control = Control::Torque;
            }
        }
        Ok(())
    }

    fn leave_torque_control(&mut self) {
        if matches!(self.control, Control::Torque) {
            self.user_torques.fill(0.0);
            self.physics.set_motors_enabled(true);
            let here: Vec<f64> = self.model.limits.iter().zip(&self.q).map(|(l, &v)| l.clamp(v)).collect();
            self.sp_q.copy_from_slice(&here);
            self.sp_qd.fill(0.0);
            self.sp_qdd.fill(0.0);
        }
    }

    /// Advances the setpoint by one step.
    fn advance_setpoint(&mut self) {
        let t_next = self.sim_time_s() + self.dt_s;
        match &self.control {
            Control::Hold | Control::Torque => {
                self.sp_qd.fill(0.0);
                self.sp_qdd.fill(0.0);
            }
            Control::Jog => {
                let dt = self.dt_s;
                for (i, l) in self.model.limits.iter().enumerate() {
                    let vmax = self.jog_speed[i];
                    let step = (self.target_q[i] - self.sp_q[i]).clamp(-vmax * dt, vmax * dt);
                    let new_qd = step / dt;
                    self.sp_qdd[i] = (new_qd - self.sp_qd[i]) / dt;
                    self.sp_qd[i] = new_qd;
                    self.sp_q[i] = l.clamp(self.sp_q[i] + step);
                }
                if self.sp_q.iter().zip(&self.target_q).all(|(a, b)| (a - b).abs() <= 1e-12) {
                    self.sp_qd.fill(0.0);
                    self.sp_qdd.fill(0.0);
                }
            }
            Control::Profile { mv, t0_s } => {
                let s = mv.sample(t_next - t0_s);
                let done = mv.is_finished(t_next - t0_s);
                for (i, l) in self.model.limits.iter().enumerate() {
                    self.sp_q[i] = l.clamp(s.q[i]);
                    self.sp_qd[i] = s.qd[i];
                    self.sp_qdd[i] = s.qdd[i];
                }
                if done {
                    self.control = Control::Hold;
                }
            }
        }
    }

    /// Advances the simulation by one fixed time step.
    pub fn step(&mut self) {
        let t0 = Instant::now();
        self.advance_setpoint();
        match self.mode {
            SimMode::Kinematic => {
                self.q.copy_from_slice(&self.sp_q);
                self.qd.copy_from_slice(&self.sp_qd);
            }
            SimMode::Dynamic => {
                if matches!(self.control, Control::Torque) {
                    self.physics.set_joint_torques(&self.user_torques);
                } else {
                    // computed-torque feedforward on the setpoint, motors correct the rest
                    self.id.compute_into(&self.model, &self.sp_q, &self.sp_qd, &self.sp_qdd, &mut self.ff);
                    self.physics.set_joint_torques(&self.ff);
                    self.physics.set_motor_targets(&self.sp_q, &self.sp_qd);
                }
                self.physics.stop_at_limits(&self.speed_cap, self.dt_s);
                self.physics.step();
                self.physics.clamp_joint_velocities(&self.speed_cap);
                self.qd_prev.copy_from_slice(&self.qd);
                self.physics.read_state(&mut self.q, &mut self.qd);
                // measured acceleration, low-passed (time constant QDD_FILTER_S)
                let alpha = self.dt_s / (QDD_FILTER_S + self.dt_s);
                for i in 0..self.qd.len() {
                    let raw = (self.qd[i] - self.qd_prev[i]) / self.dt_s;
                    self.qdd_filt[i] += alpha * (raw - self.qdd_filt[i]);
                }
            }
        }
        self.steps += 1;
        if self.steps.is_multiple_of(self.collision_every) {
            self.collision = self.guard.check(&self.model, &self.q);
        }
        self.last_step_ns = u64::try_from(t0.elapsed().as_nanos()).unwrap_or(u64::MAX);
    }

    fn update_torques(&mut self) {
        match (self.mode, &self.control) {
            (SimMode::Dynamic, Control::Torque) => self.torques.copy_from_slice(&self.user_torques),
            (SimMode::Dynamic, _) => {
                self.id.compute_into(&self.model, &self.q, &self.qd, &self.qdd_filt, &mut self.torques);
            }
            (SimMode::Kinematic, _) => {
                self.id.compute_into(&self.model, &self.q, &self.qd, &self.sp_qdd, &mut self.torques);
            }
        }
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
            target_q: self.target_q.clone(),
            link_poses,
            tcp,
            zones: self.model.limits.zone_reports(&self.q, &self.qd, &self.config.thresholds),
            collision: self.collision.clone(),
            moving: self.is_moving(),
            mode: self.mode,
            last_step_ns: self.last_step_ns,
            step_rate_hz: self.step_rate_hz,
            last_command_latency_ns: self.last_command_latency_ns,
            last_error: self.last_error.clone(),
        }
    }
}

#[cfg(test)]
mod tests;

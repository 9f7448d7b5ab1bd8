//! The simulation's settings, commands, errors and published snapshot.

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use crate::kinematics::TcpPose;
use crate::limits::{LimitPolicy, LimitViolation, ZoneReport, ZoneThresholds};
use crate::motion::tracking::TrackingMode;
use crate::motion::{MotionCommand, MotionError, PlannerMode, Setpoint};
use crate::profile::ProfileError;

use crate::collision::CollisionReport;

/// How the joints move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum SimMode {
    /// Joints follow the commanded setpoint exactly (no physics; torques from inverse dynamics).
    Kinematic,
    /// The rapier multibody is stepped under gravity; position motors track the setpoint.
    #[default]
    Dynamic,
}

/// What drives the simulated joints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ServoModel {
    /// The PAROL6 board's drives: every 10 ms the streamed MOVE target (in the
    /// [`SimConfig::tracking`] mode) is held for the period and the joints step by the
    /// firmware's law ([`crate::motion::stepper`]): its lag, its ±50 000 steps/s clamp, whole
    /// steps. The measured joints are the step counters, as the board reports them; the rapier
    /// links (dynamic mode) are carried stiffly to them. Only for the PAROL6 model; other
    /// models use [`ServoModel::Ideal`].
    #[default]
    Firmware,
    /// Ideal motors that follow the planned setpoint itself (no firmware, no steps): for robot
    /// models other than the PAROL6, which have no such board.
    Ideal,
}

/// Settings of a [`Simulation`](super::Simulation).
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
    /// Simulated seconds per wall-clock second of the threaded simulation (1: real time; a
    /// headless program run uses more, and the thread simply runs behind when the machine
    /// cannot keep up).
    pub time_scale: f64,
    /// What drives the joints (the PAROL6 firmware's stepper law by default).
    pub servo: ServoModel,
    /// Which targets the simulated board is streamed (as the serial session streams the robot).
    pub tracking: TrackingMode,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            policy: LimitPolicy::Reject,
            thresholds: ZoneThresholds::default(),
            rate_hz: 1000.0,
            mode: SimMode::Dynamic,
            check_collisions: true,
            time_scale: 1.0,
            servo: ServoModel::Firmware,
            tracking: TrackingMode::default(),
        }
    }
}

/// A command to the simulation. Motion is a [`MotionCommand`], the same type the serial
/// session takes; the rest are simulation-only. Joint vectors are in chain order, rad.
#[derive(Debug, Clone, PartialEq)]
pub enum SimCommand {
    /// A motion command, applied when the simulation thread sees it.
    Motion(MotionCommand),
    /// A motion command applied at exactly `at_s` of simulated time.
    MotionAt {
        /// The command.
        cmd: MotionCommand,
        /// Simulated time at which it applies, s.
        at_s: f64,
    },
    /// Put the joints at these values instantly, at rest.
    Teleport(Vec<f64>),
    /// Digital I/O or the gripper (the simulation's outputs and gripper follow at once).
    Io(crate::motion::IoCommand),
    /// Switch between kinematic and dynamic stepping.
    SetMode(SimMode),
    /// Changes the tracking mode of the simulated board (from its next 10 ms frame).
    SetTracking(TrackingMode),
    /// Dynamic mode: drive the joints with these torques (N·m), motors off, until a motion
    /// command. Kinematic mode refuses it.
    ApplyJointTorques(Vec<f64>),
    /// Dynamic mode: forward dynamics, a torque profile per joint for a bounded time, motors
    /// off; then the motors hold where the arm is. A motion command (STOP) ends it early; the
    /// joint limits stay enforced. Kinematic mode refuses it.
    RunJointTorques(super::TorqueRun),
}

impl From<MotionError> for SimError {
    fn from(e: MotionError) -> Self {
        match e {
            MotionError::Limit(v) => SimError::Limit(v),
            MotionError::Profile(p) => SimError::Profile(p),
            MotionError::Invalid(m) => SimError::InvalidCommand(m),
        }
    }
}

impl From<MotionCommand> for SimCommand {
    fn from(cmd: MotionCommand) -> Self {
        SimCommand::Motion(cmd)
    }
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
    /// Motion while the drives are disabled (DISABLE, the E-stop button), as the robot refuses it.
    #[error("the drives are disabled (DISABLE): enable them first")]
    DrivesDisabled,
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
    /// The commanded setpoint of this step.
    pub commanded: Setpoint,
    /// What the motion planner does.
    pub planner_mode: PlannerMode,
    /// Motion commands applied so far.
    pub commands_applied: u64,
    /// The scheduled commands: how many arrived and how late the schedule runs.
    pub schedule: crate::motion::ScheduleState,
    /// World pose of every link (order of [`RobotModel::links`](crate::RobotModel::links)).
    pub link_poses: Vec<Isometry3<f64>>,
    /// TCP pose.
    pub tcp: TcpPose,
    /// Limit zone of every joint.
    pub zones: Vec<ZoneReport>,
    /// A collision in the current configuration, if any.
    pub collision: Option<CollisionReport>,
    /// True while a move or jog is under way.
    pub moving: bool,
    /// True while a forward-dynamics torque run ([`SimCommand::RunJointTorques`]) drives the joints.
    pub torque_run: bool,
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
    /// Digital I/O and gripper.
    pub io: crate::motion::IoState,
}

impl SimSnapshot {
    /// The backend-neutral state of this snapshot.
    pub fn robot_state(&self) -> crate::motion::RobotState {
        crate::motion::RobotState {
            source: crate::motion::StateSource::Simulation,
            backend: "simulation".to_string(),
            seq: self.seq,
            time_s: self.sim_time_s,
            q: self.q.clone(),
            qd: self.qd.clone(),
            commanded: self.commanded.clone(),
            target_q: self.target_q.clone(),
            mode: self.planner_mode,
            zones: self.zones.clone(),
            tcp: self.tcp,
            moving: self.moving,
            commands_applied: self.commands_applied,
            last_refusal: self.last_error.clone(),
            blocked: self.io.drives_disabled.then(|| SimError::DrivesDisabled.to_string()),
            homed: true,
            io: self.io,
            schedule: self.schedule,
        }
    }
}

impl From<crate::dynamics::DynamicsError> for SimError {
    fn from(e: crate::dynamics::DynamicsError) -> Self {
        match e {
            crate::dynamics::DynamicsError::InvalidInput(why) => SimError::InvalidCommand(why),
        }
    }
}

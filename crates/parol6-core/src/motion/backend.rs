//! [`RobotBackend`]: the one interface to a robot, simulated or real, and the [`RobotState`]
//! it publishes.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::kinematics::TcpPose;
use crate::limits::{LimitZone, ZoneReport, ZoneThresholds};
use crate::model::RobotModel;

use super::{IoCommand, IoState, MotionCommand, MotionError, PlannerMode, Setpoint};

/// Where a [`RobotState`] comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum StateSource {
    /// The in-process simulation.
    Simulation,
    /// Measured by the controller over the serial link.
    Robot,
}

/// The state of a robot, computed once per published sample on the backend's own thread
/// (forward kinematics, limit zones and time-to-limit included): readers never compute it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobotState {
    /// Source of the values.
    pub source: StateSource,
    /// Backend description ("simulation", "robot on /dev/ttyACM0", …).
    pub backend: String,
    /// Increases with every published state.
    pub seq: u64,
    /// The backend's motion clock, s: the time base of [`RobotBackend::submit`].
    pub time_s: f64,
    /// Measured (or simulated) joint positions, rad.
    pub q: Vec<f64>,
    /// Measured joint velocities, rad/s.
    pub qd: Vec<f64>,
    /// The commanded setpoint of this instant.
    pub commanded: Setpoint,
    /// Where the current motion is going, rad (the hold position when holding).
    pub target_q: Vec<f64>,
    /// What the planner does.
    pub mode: PlannerMode,
    /// Limit zone of every joint, with its prediction.
    pub zones: Vec<ZoneReport>,
    /// TCP pose of the measured joints.
    pub tcp: TcpPose,
    /// True while the commanded trajectory moves or the arm has not settled.
    pub moving: bool,
    /// Motion commands applied so far.
    pub commands_applied: u64,
    /// The last refused command: increasing id and message.
    pub last_refusal: Option<(u64, String)>,
    /// Why motion commands are refused right now (link down, E-stop, disabled, homing …);
    /// `None` when they are accepted.
    pub blocked: Option<String>,
    /// True once the joint positions are known to be true (the simulation always; the robot
    /// after the controller's homing).
    #[serde(default)]
    pub homed: bool,
    /// Digital I/O and gripper.
    #[serde(default)]
    pub io: IoState,
    /// The scheduled commands ([`RobotBackend::submit`] with a time): how many arrived and how
    /// late the schedule runs.
    #[serde(default)]
    pub schedule: ScheduleState,
}

/// Where the backend's schedule stands (see [`MotionPlanner::schedule_arriving`]).
///
/// [`MotionPlanner::schedule_arriving`]: super::MotionPlanner::schedule_arriving
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ScheduleState {
    /// Scheduled commands received so far, refused ones included: a state whose count covers
    /// what a client submitted has seen those commands.
    pub received: u64,
    /// How late the schedule runs, s: a command scheduled for `t` is applied at `t + delay_s`.
    /// 0 while every step is handed over in time; it grows when one arrives late (or starts
    /// late), and returns to 0 when STOP or PAUSE drops the schedule.
    pub delay_s: f64,
}

impl RobotState {
    /// A state at rest at `q`, with kinematics and zones computed from `model`.
    pub fn at_rest(model: &RobotModel, source: StateSource, backend: &str, q: &[f64]) -> Self {
        let zeros = vec![0.0; q.len()];
        Self {
            source,
            backend: backend.to_string(),
            seq: 0,
            time_s: 0.0,
            q: q.to_vec(),
            qd: zeros,
            commanded: Setpoint::at_rest(q),
            target_q: q.to_vec(),
            mode: PlannerMode::Hold,
            zones: model.limits.zone_reports(q, &vec![0.0; q.len()], &ZoneThresholds::default()),
            tcp: model.fk(q),
            moving: false,
            commands_applied: 0,
            last_refusal: None,
            blocked: None,
            homed: source == StateSource::Simulation,
            io: IoState::default(),
            schedule: ScheduleState::default(),
        }
    }

    /// Recomputes the TCP pose and limit zones from `q` and `qd`.
    pub fn update_kinematics(&mut self, model: &RobotModel, thresholds: &ZoneThresholds) {
        self.tcp = model.fk(&self.q);
        self.zones = model.limits.zone_reports(&self.q, &self.qd, thresholds);
    }

    /// Worst zone over all joints, with the joint index (`None` when all are safe).
    pub fn worst_zone(&self) -> Option<(usize, ZoneReport)> {
        self.zones.iter().copied().enumerate().filter(|(_, z)| z.zone != LimitZone::Safe).max_by(|a, b| {
            a.1.zone.cmp(&b.1.zone).then_with(|| {
                let ta = a.1.time_to_limit_s.unwrap_or(f64::INFINITY);
                let tb = b.1.time_to_limit_s.unwrap_or(f64::INFINITY);
                tb.total_cmp(&ta)
            })
        })
    }
}

/// One commanded / measured sample, published by a backend on every control tick when a tap
/// is attached (the simulation: every step; the serial session: every frame).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MotionSample {
    /// Sample counter of the backend, without gaps unless a sample was dropped (the serial
    /// session: its frame ticks; the simulation: the samples it sent, one per step, one per ten
    /// steps while the arm rests).
    pub seq: u64,
    /// Motion clock, s.
    pub time_s: f64,
    /// Commanded setpoint.
    pub commanded: Setpoint,
    /// Measured joint positions at this tick, rad.
    pub measured_q: Vec<f64>,
    /// Measured joint velocities at this tick, rad/s.
    pub measured_qd: Vec<f64>,
    /// What drives each joint at this tick.
    pub drive: JointDrive,
}

/// What drives the joints, per joint: what a backend knows about its actuators.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum JointDrive {
    /// Joint torques of the simulation (inverse dynamics of the measured motion), N·m.
    TorqueNm(Vec<f64>),
    /// Step rates the controller reports, steps/s.
    StepsPerS(Vec<f64>),
}

impl JointDrive {
    /// The per-joint values (N·m or steps/s).
    pub fn values(&self) -> &[f64] {
        match self {
            JointDrive::TorqueNm(v) | JointDrive::StepsPerS(v) => v,
        }
    }
}

/// Why a backend refused a command.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BackendError {
    /// The command breaks a limit or has bad arguments.
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// The backend does not accept motion now (link down, E-stop, disabled, homing …).
    #[error("{0}")]
    Refused(String),
    /// The backend's command queue is full.
    #[error("the command queue is full")]
    QueueFull,
    /// The backend has stopped.
    #[error("the backend has stopped")]
    Closed,
}

/// A robot that takes [`MotionCommand`]s: the simulation or the real robot. Implementations
/// run their own threads; every call returns at once.
pub trait RobotBackend: Send + Sync {
    /// Queues `cmd`. `at_s = None` applies it as soon as the backend's thread sees it;
    /// `Some(t)` applies it at exactly `t` on the motion clock ([`RobotState::time_s`]), so a
    /// scripted sequence gives the same commanded trajectory on every backend. Arguments and
    /// limits are checked before queueing.
    fn submit(&self, cmd: MotionCommand, at_s: Option<f64>) -> Result<(), BackendError>;

    /// The latest published state (lock-free).
    fn state(&self) -> Arc<RobotState>;

    /// Sets a digital output or moves the gripper now (checked first).
    fn io(&self, cmd: IoCommand) -> Result<(), BackendError>;

    /// [`RobotBackend::submit`] now.
    fn send(&self, cmd: MotionCommand) -> Result<(), BackendError> {
        self.submit(cmd, None)
    }
}

/// Sends [`MotionCommand::Stop`] now, for a caller that goes on whatever happens (a program
/// run or a measurement that is ending). A STOP the backend refuses is not dropped: the line
/// to record and show comes back ("STOP (`during`) failed: …"); `None` when the backend took it.
pub fn stop_best_effort(backend: &dyn RobotBackend, during: &str) -> Option<String> {
    backend.send(MotionCommand::Stop).err().map(|e| format!("STOP ({during}) failed: {e}"))
}

//! [`RobotBackend`] for the serial [`Session`]: the app, the sequence runner and the tests drive
//! the real robot through the same trait as the simulation.

use std::sync::Arc;

use parol6_core::RobotModel;
use parol6_core::limits::ZoneThresholds;
use parol6_core::motion::{BackendError, MotionCommand, PlannerMode, RobotBackend, RobotState, Setpoint, StateSource};
use parol6_core::parol6::standby_rad;

use crate::HwError;
use crate::session::{MotionState, Session, Snapshot};
use crate::units::joints_steps_to_rad;

fn backend_error(e: HwError) -> BackendError {
    match e {
        HwError::Closed => BackendError::Closed,
        other => BackendError::Refused(other.to_string()),
    }
}

/// Why the session refuses motion now, if it does.
fn blocked(s: &Snapshot) -> Option<String> {
    s.motion_allowed().err().map(|e| e.to_string())
}

/// The robot state of a session snapshot (kinematics of the measured joints).
pub fn robot_state(s: &Snapshot, model: &RobotModel) -> RobotState {
    let q = s.joint_rad.to_vec();
    let qd = s.joint_speed_rad_s.to_vec();
    let target = s.target_steps.map(|t| joints_steps_to_rad(&t).to_vec()).unwrap_or_else(|| q.clone());
    let mode = match s.motion {
        MotionState::Idle | MotionState::Holding | MotionState::Homing => PlannerMode::Hold,
        MotionState::Jogging { .. } => PlannerMode::Jog,
        MotionState::Moving { .. } => PlannerMode::Move,
    };
    let moving = !matches!(s.motion, MotionState::Idle | MotionState::Holding) || qd.iter().any(|v| v.abs() > 1e-3);
    let mut state = RobotState {
        source: StateSource::Robot,
        backend: format!("robot on {}", s.port),
        seq: s.frames_sent,
        time_s: s.frames_sent as f64 / s.rate_hz,
        commanded: Setpoint::at_rest(&target),
        target_q: target,
        mode,
        zones: Vec::new(),
        tcp: model.fk(&q),
        q,
        qd,
        moving,
        commands_applied: s.frames_sent,
        last_refusal: None,
        blocked: blocked(s),
    };
    state.update_kinematics(model, &ZoneThresholds::default());
    state
}

impl RobotBackend for Session {
    fn submit(&self, cmd: MotionCommand, at_s: Option<f64>) -> Result<(), BackendError> {
        if at_s.is_some() {
            return Err(BackendError::Refused("scheduled commands are not supported by this session yet".into()));
        }
        cmd.validate(&self.config().limits)?;
        let r = match cmd {
            MotionCommand::Follow { target_rad, speed_fraction } => {
                self.move_to(&target_rad, speed_fraction, parol6_core::profile::ProfileKind::Trapezoidal)
            }
            MotionCommand::MoveJoints { goal_rad, speed_fraction, profile } => {
                self.move_to(&goal_rad, speed_fraction, profile)
            }
            MotionCommand::Home { speed_fraction, profile } => self.move_to(&standby_rad(), speed_fraction, profile),
            MotionCommand::JogJoint { joint, fraction } => self.jog(joint, fraction),
            MotionCommand::JogRelease => self.jog_release(),
            MotionCommand::Stop => self.stop(),
            MotionCommand::Trajectory(_) => {
                return Err(BackendError::Refused("planned trajectories are not supported by this session yet".into()));
            }
        };
        r.map_err(backend_error)
    }

    fn state(&self) -> Arc<RobotState> {
        static MODEL: std::sync::OnceLock<RobotModel> = std::sync::OnceLock::new();
        let model = MODEL.get_or_init(RobotModel::parol6);
        Arc::new(robot_state(&self.snapshot(), model))
    }
}

//! [`RobotBackend`] for the serial [`Session`]: the app, the program runner and the tests drive
//! the real robot through the same trait as the simulation. Commands are checked here
//! (arguments, limits, whether the link allows motion) and queued to the session thread, which
//! applies them to its [`MotionPlanner`](parol6_core::motion::MotionPlanner) at once or at
//! their scheduled time on the motion clock; the state is computed on that thread every frame.

use std::sync::Arc;

use parol6_core::motion::{BackendError, IoCommand, MotionCommand, RobotBackend, RobotState};

use crate::HwError;

use crate::session::Session;

impl RobotBackend for Session {
    fn submit(&self, cmd: MotionCommand, at_s: Option<f64>) -> Result<(), BackendError> {
        self.submit_motion(cmd, at_s)
    }

    fn state(&self) -> Arc<RobotState> {
        self.robot_state()
    }

    fn io(&self, cmd: IoCommand) -> Result<(), BackendError> {
        cmd.validate().map_err(BackendError::Refused)?;
        let sent = match cmd {
            IoCommand::SetOutput { output, on } => self.set_output(output, on),
            IoCommand::Gripper { position, speed, current_ma } => self.set_gripper(position, speed, current_ma),
            IoCommand::GripperCalibrate => self.gripper_calibrate(),
            IoCommand::ClearError => self.clear_error().and_then(|()| self.gripper_clear_error()),
            IoCommand::Disable => self.disable(),
            IoCommand::Enable => self.enable(),
            IoCommand::SetSimulatedInput { input, .. } => {
                return Err(BackendError::Refused(format!(
                    "input {input} of the robot is read from the controller board; it cannot be set"
                )));
            }
        };
        sent.map_err(|e| match e {
            HwError::Refused(m) => BackendError::Refused(m),
            other => BackendError::Refused(other.to_string()),
        })
    }
}

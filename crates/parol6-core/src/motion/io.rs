//! Digital I/O and the gripper: [`IoCommand`] to a backend, [`IoState`] in every
//! [`RobotState`](super::RobotState). The robot passes them to the controller board; the
//! simulation keeps them itself (its inputs are set by hand, e.g. from the GUI), so a program
//! step means the same on both.

use serde::{Deserialize, Serialize};

/// Number of digital outputs (and inputs) of the PAROL6 board.
pub const DIGITAL_PORTS: usize = 2;

/// An I/O command.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum IoCommand {
    /// Set digital output `output` (1 or 2).
    SetOutput {
        /// 1-based output.
        output: u8,
        /// Level.
        on: bool,
    },
    /// Move the electric gripper to `position` (0 open … 255 closed).
    Gripper {
        /// Target position, 0–255.
        position: u8,
        /// Speed, 0–255.
        speed: u8,
        /// Current limit, mA (100–2800).
        current_ma: u16,
    },
    /// Simulation only: set digital input `input` (1 or 2) as if wired. The robot refuses it
    /// (its inputs are read from the board).
    SetSimulatedInput {
        /// 1-based input.
        input: u8,
        /// Level.
        on: bool,
    },
}

impl IoCommand {
    /// Checks the port numbers and ranges.
    pub fn validate(&self) -> Result<(), String> {
        let port_ok = |p: u8| (1..=DIGITAL_PORTS as u8).contains(&p);
        match *self {
            IoCommand::SetOutput { output, .. } if !port_ok(output) => {
                Err(format!("output {output} does not exist (1 or 2)"))
            }
            IoCommand::SetSimulatedInput { input, .. } if !port_ok(input) => {
                Err(format!("input {input} does not exist (1 or 2)"))
            }
            IoCommand::Gripper { current_ma, .. } if !(100..=2800).contains(&current_ma) => {
                Err(format!("gripper current {current_ma} mA is outside 100–2800 mA"))
            }
            _ => Ok(()),
        }
    }
}

/// Digital I/O and gripper state as last seen.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct IoState {
    /// Digital inputs 1 and 2.
    pub inputs: [bool; DIGITAL_PORTS],
    /// Digital outputs 1 and 2.
    pub outputs: [bool; DIGITAL_PORTS],
    /// Gripper position 0–255 as reported (commanded, in the simulation).
    pub gripper_position: u8,
}

impl IoState {
    /// Applies `cmd` (the simulation's I/O model: outputs and the gripper follow at once).
    pub fn apply(&mut self, cmd: &IoCommand) {
        match *cmd {
            IoCommand::SetOutput { output, on } => {
                if let Some(o) = self.outputs.get_mut(usize::from(output).wrapping_sub(1)) {
                    *o = on;
                }
            }
            IoCommand::Gripper { position, .. } => self.gripper_position = position,
            IoCommand::SetSimulatedInput { input, on } => {
                if let Some(i) = self.inputs.get_mut(usize::from(input).wrapping_sub(1)) {
                    *i = on;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ports_and_currents_are_checked_and_applied() {
        assert!(IoCommand::SetOutput { output: 3, on: true }.validate().is_err());
        assert!(IoCommand::SetSimulatedInput { input: 0, on: true }.validate().is_err());
        assert!(IoCommand::Gripper { position: 9, speed: 9, current_ma: 50 }.validate().is_err());
        let mut io = IoState::default();
        io.apply(&IoCommand::SetOutput { output: 2, on: true });
        io.apply(&IoCommand::SetSimulatedInput { input: 1, on: true });
        io.apply(&IoCommand::Gripper { position: 200, speed: 50, current_ma: 500 });
        assert_eq!(io, IoState { inputs: [true, false], outputs: [false, true], gripper_position: 200 });
    }
}

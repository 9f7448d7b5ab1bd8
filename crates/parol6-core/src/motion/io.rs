//! Digital I/O, the gripper and the drives: [`IoCommand`] to a backend, [`IoState`] in every
//! [`RobotState`](super::RobotState). The robot passes them to the controller board; the
//! simulation keeps them itself (its inputs are set by hand, e.g. from the GUI; its gripper
//! answers as the emulated board's does), so a program step or a panel button means the same
//! on both.

use serde::{Deserialize, Serialize};

/// Number of digital outputs (and inputs) of the PAROL6 board.
pub const DIGITAL_PORTS: usize = 2;

/// Gripper current limits, mA (PROTOCOL.md §3: the MSG gripper's 100–2800 mA).
pub const GRIPPER_CURRENT_MA: (u16, u16) = (100, 2800);

/// Gripper status bits (PROTOCOL.md §7, MSB first).
const GRIPPER_ACTIVATED: u8 = 0x80;
const GRIPPER_OBJECT_MASK: u8 = 0x30;
const GRIPPER_ERRORS: u8 = 0x08 | 0x04 | 0x02;
const GRIPPER_ERROR: u8 = 0x02;
const GRIPPER_CALIBRATED: u8 = 0x01;

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
    /// One-shot gripper calibration (gripper mode 1 for one frame).
    GripperCalibrate,
    /// CLEAR ERROR to the controller (resets a failed homing, clears the fault text) and the
    /// gripper's clear-error (gripper mode 2 for one frame).
    ClearError,
    /// DISABLE the drives (the E-stop button): motion stops and is refused until
    /// [`IoCommand::Enable`].
    Disable,
    /// ENABLE the drives again.
    Enable,
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
            IoCommand::Gripper { current_ma, .. }
                if !(GRIPPER_CURRENT_MA.0..=GRIPPER_CURRENT_MA.1).contains(&current_ma) =>
            {
                Err(format!(
                    "gripper current {current_ma} mA is outside {}–{} mA",
                    GRIPPER_CURRENT_MA.0, GRIPPER_CURRENT_MA.1
                ))
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
    /// Gripper current as reported, mA (the commanded limit, in the simulation).
    #[serde(default)]
    pub gripper_current_ma: i16,
    /// Raw gripper status byte (PROTOCOL.md §7; see [`IoState::gripper`]).
    #[serde(default)]
    pub gripper_status: u8,
    /// The drives are disabled (DISABLE or the E-stop, until ENABLE).
    #[serde(default)]
    pub drives_disabled: bool,
}

/// The gripper status byte read out (PROTOCOL.md §7).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GripperStatus {
    /// Activated.
    pub activated: bool,
    /// Calibrated.
    pub calibrated: bool,
    /// Temperature, timeout or error bit set.
    pub error: bool,
    /// Object code: 0 moving, 1 object found while closing, 2 object found while opening, 3 at
    /// the target position.
    pub object: u8,
}

impl GripperStatus {
    /// The object code in words.
    pub fn object_text(&self) -> &'static str {
        match self.object {
            0 => "moving",
            1 => "object found (closing)",
            2 => "object found (opening)",
            _ => "at position",
        }
    }
}

impl IoState {
    /// The gripper status byte read out.
    pub fn gripper(&self) -> GripperStatus {
        let s = self.gripper_status;
        GripperStatus {
            activated: s & GRIPPER_ACTIVATED != 0,
            calibrated: s & GRIPPER_CALIBRATED != 0,
            error: s & GRIPPER_ERRORS != 0,
            object: (s & GRIPPER_OBJECT_MASK) >> 4,
        }
    }

    /// Applies `cmd` (the simulation's I/O model: outputs and the gripper follow at once, the
    /// gripper's status byte as the emulated board's: activated, at position, calibrated once
    /// asked).
    pub fn apply(&mut self, cmd: &IoCommand) {
        match *cmd {
            IoCommand::SetOutput { output, on } => {
                if let Some(o) = self.outputs.get_mut(usize::from(output).wrapping_sub(1)) {
                    *o = on;
                }
            }
            IoCommand::Gripper { position, current_ma, .. } => {
                self.gripper_position = position;
                self.gripper_current_ma = i16::try_from(current_ma).unwrap_or(i16::MAX);
                self.gripper_status =
                    GRIPPER_ACTIVATED | GRIPPER_OBJECT_MASK | (self.gripper_status & GRIPPER_CALIBRATED);
            }
            IoCommand::GripperCalibrate => self.gripper_status |= GRIPPER_CALIBRATED,
            IoCommand::ClearError => self.gripper_status &= !GRIPPER_ERROR,
            IoCommand::Disable => self.drives_disabled = true,
            IoCommand::Enable => self.drives_disabled = false,
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
        assert_eq!((io.inputs, io.outputs, io.gripper_position), ([true, false], [false, true], 200));
        assert_eq!(io.gripper_current_ma, 500);
        assert!(io.gripper().activated && !io.gripper().calibrated && !io.gripper().error);
        assert_eq!(io.gripper().object_text(), "at position");
        io.apply(&IoCommand::GripperCalibrate);
        assert!(io.gripper().calibrated);
        io.apply(&IoCommand::Disable);
        assert!(io.drives_disabled);
        io.apply(&IoCommand::Enable);
        assert!(!io.drives_disabled);
    }
}

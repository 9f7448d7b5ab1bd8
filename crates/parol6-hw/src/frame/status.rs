//! The 60-byte controller → host status frame (PROTOCOL.md §4).

use super::codec::{get_i16, get_i24, joint_flags, put_i16, put_i24};
use super::{
    CommandCode, END_BYTES, FrameError, IO_ALWAYS_SET, IO_ESTOP_RELEASED, IO_IN1, IO_IN2, IO_OUT1, IO_OUT2,
    JOINT_BITS_ALWAYS_SET, JOINT_COUNT, START_BYTES, STATUS_CRC_BYTE, STATUS_FRAME_SIZE, STATUS_LEN_BYTE,
    TIMING_TICKS_PER_S,
};

/// A controller → host frame (60 bytes). Bit bytes are kept raw so decode → encode is exact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct StatusFrame {
    /// Stepper position counters, motor steps.
    pub positions_steps: [i32; JOINT_COUNT],
    /// Speed set points in use, steps/s.
    pub speeds_steps_s: [i32; JOINT_COUNT],
    /// Homed bits (`0x80` J1 … `0x04` J6; low two always 1).
    pub homed_bits: u8,
    /// I/O bits (IN1, IN2, OUT1, OUT2, E-stop released; low three always 1).
    pub io_bits: u8,
    /// Temperature-error joint bits.
    pub temperature_error_bits: u8,
    /// Position-error joint bits.
    pub position_error_bits: u8,
    /// Timer ticks between the last two accepted command frames (1/703 125 s, wraps).
    pub timing_ticks: u16,
    /// Timeout-error byte (public FW: constant 100).
    pub timeout_error: u8,
    /// Command code of the frame being answered.
    pub echoed_command: u8,
    /// Gripper CAN ID.
    pub gripper_id: u8,
    /// Gripper position 0–255.
    pub gripper_position: i16,
    /// Gripper speed (public FW: always 1).
    pub gripper_speed: i16,
    /// Gripper current, mA.
    pub gripper_current_ma: i16,
    /// Raw gripper status byte (PROTOCOL.md §7).
    pub gripper_status: u8,
    /// Object-detection byte (public FW: always 1).
    pub gripper_object_byte: u8,
}

impl Default for StatusFrame {
    /// What an idle, unhomed board with no gripper sends (E-stop released).
    fn default() -> Self {
        Self {
            positions_steps: [0; JOINT_COUNT],
            speeds_steps_s: [0; JOINT_COUNT],
            homed_bits: JOINT_BITS_ALWAYS_SET,
            io_bits: IO_ALWAYS_SET | IO_ESTOP_RELEASED,
            temperature_error_bits: JOINT_BITS_ALWAYS_SET,
            position_error_bits: JOINT_BITS_ALWAYS_SET,
            timing_ticks: 0,
            timeout_error: 100,
            echoed_command: CommandCode::Idle.byte(),
            gripper_id: 0,
            gripper_position: 0,
            gripper_speed: 1,
            gripper_current_ma: 2,
            gripper_status: 1,
            gripper_object_byte: 1,
        }
    }
}

impl StatusFrame {
    /// Encodes the frame (as the controller does, with the `0xD4` placeholder). Values are
    /// truncated to 24 bits (`v & 0xFFFFFF`) like the firmware does.
    pub fn encode(&self) -> [u8; STATUS_FRAME_SIZE] {
        let mut b = [0u8; STATUS_FRAME_SIZE];
        b[0..3].copy_from_slice(&START_BYTES);
        b[3] = STATUS_LEN_BYTE;
        for i in 0..JOINT_COUNT {
            put_i24(&mut b[4 + 3 * i..], self.positions_steps[i]);
            put_i24(&mut b[22 + 3 * i..], self.speeds_steps_s[i]);
        }
        b[40] = self.homed_bits;
        b[41] = self.io_bits;
        b[42] = self.temperature_error_bits;
        b[43] = self.position_error_bits;
        b[44..46].copy_from_slice(&self.timing_ticks.to_be_bytes());
        b[46] = self.timeout_error;
        b[47] = self.echoed_command;
        b[48] = self.gripper_id;
        put_i16(&mut b[49..], self.gripper_position);
        put_i16(&mut b[51..], self.gripper_speed);
        put_i16(&mut b[53..], self.gripper_current_ma);
        b[55] = self.gripper_status;
        b[56] = self.gripper_object_byte;
        b[57] = STATUS_CRC_BYTE;
        b[58..60].copy_from_slice(&END_BYTES);
        b
    }

    /// Decodes a whole 60-byte status frame (start, length 56, end checked; CRC ignored).
    pub fn decode(bytes: &[u8]) -> Result<Self, FrameError> {
        if bytes.len() != STATUS_FRAME_SIZE {
            return Err(FrameError::WrongSize { got: bytes.len(), expected: STATUS_FRAME_SIZE });
        }
        if bytes[0..3] != START_BYTES {
            return Err(FrameError::BadStart);
        }
        if bytes[3] != STATUS_LEN_BYTE {
            return Err(FrameError::BadLength { got: bytes[3], expected: STATUS_LEN_BYTE });
        }
        if bytes[58..60] != END_BYTES {
            return Err(FrameError::BadEnd);
        }
        let b = bytes;
        Ok(Self {
            positions_steps: std::array::from_fn(|i| get_i24(&b[4 + 3 * i..])),
            speeds_steps_s: std::array::from_fn(|i| get_i24(&b[22 + 3 * i..])),
            homed_bits: b[40],
            io_bits: b[41],
            temperature_error_bits: b[42],
            position_error_bits: b[43],
            timing_ticks: u16::from_be_bytes([b[44], b[45]]),
            timeout_error: b[46],
            echoed_command: b[47],
            gripper_id: b[48],
            gripper_position: get_i16(&b[49..]),
            gripper_speed: get_i16(&b[51..]),
            gripper_current_ma: get_i16(&b[53..]),
            gripper_status: b[55],
            gripper_object_byte: b[56],
        })
    }

    /// Homed flag per joint.
    pub fn homed_joints(&self) -> [bool; JOINT_COUNT] {
        joint_flags(self.homed_bits)
    }

    /// True when all six joints report homed.
    pub fn all_homed(&self) -> bool {
        self.homed_joints().iter().all(|&h| h)
    }

    /// Temperature-error flag per joint.
    pub fn temperature_error_joints(&self) -> [bool; JOINT_COUNT] {
        joint_flags(self.temperature_error_bits)
    }

    /// Position-error flag per joint.
    pub fn position_error_joints(&self) -> [bool; JOINT_COUNT] {
        joint_flags(self.position_error_bits)
    }

    /// True when the E-stop input reads pressed (bit `0x08` = 0).
    pub fn estop_pressed(&self) -> bool {
        self.io_bits & IO_ESTOP_RELEASED == 0
    }

    /// INPUT1 level.
    pub fn in1(&self) -> bool {
        self.io_bits & IO_IN1 != 0
    }

    /// INPUT2 level.
    pub fn in2(&self) -> bool {
        self.io_bits & IO_IN2 != 0
    }

    /// OUTPUT1 level (echo).
    pub fn out1(&self) -> bool {
        self.io_bits & IO_OUT1 != 0
    }

    /// OUTPUT2 level (echo).
    pub fn out2(&self) -> bool {
        self.io_bits & IO_OUT2 != 0
    }

    /// The `timing` field in seconds.
    pub fn timing_s(&self) -> f64 {
        f64::from(self.timing_ticks) / TIMING_TICKS_PER_S
    }

    /// Gripper object code from status bits `0x20`/`0x10` (PROTOCOL.md §7): 0 moving,
    /// 1 object found closing, 2 object found opening, 3 at target.
    pub fn gripper_object_code(&self) -> u8 {
        (self.gripper_status >> 4) & 0x03
    }
}

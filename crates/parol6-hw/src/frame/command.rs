//! The 56-byte host → controller frame (PROTOCOL.md §3): command codes, the frame the host
//! encodes ([`CommandFrame`]) and the frame a controller decodes ([`ReceivedCommand`]).

use super::codec::{get_i16, get_i24, put_i16, put_i24};
use super::{
    COMMAND_CRC_BYTE, COMMAND_FRAME_SIZE, COMMAND_LEN_BYTE, END_BYTES, FrameError, I24_MAX, I24_MIN, IO_OUT1, IO_OUT2,
    JOINT_COUNT, START_BYTES,
};

/// Command codes the host may send (PROTOCOL.md §5). There is deliberately no variant for
/// 69 (test routine) or 200 (API-simulator teleport).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum CommandCode {
    /// 255: no stepping; speed fields are loaded without stepping; homing continues.
    Idle,
    /// 100: start (or keep running) the homing sequence.
    Home,
    /// 101: clear the disabled latch and the homing state.
    Enable,
    /// 102: set the disabled latch (motors stop, drivers stay powered).
    Disable,
    /// 103: reset the homing state.
    ClearError,
    /// 123: speed mode, each joint steps at its speed field. Keeps running until the next frame.
    Jog,
    /// 156: position streaming, `v = trunc((v_ff + trunc((target − pos)/0.01)) / 2)`.
    Move,
}

impl CommandCode {
    /// Every sendable code.
    pub const ALL: [CommandCode; 7] = [
        CommandCode::Idle,
        CommandCode::Home,
        CommandCode::Enable,
        CommandCode::Disable,
        CommandCode::ClearError,
        CommandCode::Jog,
        CommandCode::Move,
    ];

    /// The byte on the wire.
    pub const fn byte(self) -> u8 {
        match self {
            CommandCode::Idle => 255,
            CommandCode::Home => 100,
            CommandCode::Enable => 101,
            CommandCode::Disable => 102,
            CommandCode::ClearError => 103,
            CommandCode::Jog => 123,
            CommandCode::Move => 156,
        }
    }

    /// The code for a wire byte; `None` for 69, 200 and anything else unknown.
    pub const fn from_byte(byte: u8) -> Option<CommandCode> {
        match byte {
            255 => Some(CommandCode::Idle),
            100 => Some(CommandCode::Home),
            101 => Some(CommandCode::Enable),
            102 => Some(CommandCode::Disable),
            103 => Some(CommandCode::ClearError),
            123 => Some(CommandCode::Jog),
            156 => Some(CommandCode::Move),
            _ => None,
        }
    }

    /// Short lowercase name.
    pub const fn name(self) -> &'static str {
        match self {
            CommandCode::Idle => "idle",
            CommandCode::Home => "home",
            CommandCode::Enable => "enable",
            CommandCode::Disable => "disable",
            CommandCode::ClearError => "clear_error",
            CommandCode::Jog => "jog",
            CommandCode::Move => "move",
        }
    }
}

/// Gripper fields of a command frame (PROTOCOL.md §3 and §7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct GripperCommand {
    /// Target position 0–255.
    pub position: i16,
    /// Target speed 0–255.
    pub speed: i16,
    /// Target current, mA.
    pub current_ma: i16,
    /// Command bits (`0x80` activate, `0x40` move, `0x20` E-stop, `0x10` forwarded).
    pub command_bits: u8,
    /// 0 operate, 1 calibrate, 2 clear gripper error (send 1/2 for one frame only).
    pub mode: u8,
    /// CAN node ID 0–15.
    pub id: u8,
}

/// The fields of a command frame other than the command code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct CommandFields {
    /// Target position per joint, motor steps (i24).
    pub positions_steps: [i32; JOINT_COUNT],
    /// Speed per joint, steps/s (i24; JOG speed or MOVE feed-forward).
    pub speeds_steps_s: [i32; JOINT_COUNT],
    /// Affected-joint bits (stored, never used by FW).
    pub affected_joints: u8,
    /// In/out bits: [`IO_OUT1`], [`IO_OUT2`]; the others are ignored by FW.
    pub io_bits: u8,
    /// Timeout byte (stored, unused by FW).
    pub timeout: u8,
    /// Gripper pass-through.
    pub gripper: GripperCommand,
}

/// A host → controller frame (56 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct CommandFrame {
    /// What the board should do.
    pub command: CommandCode,
    /// Everything else.
    pub fields: CommandFields,
}

impl CommandFrame {
    /// A frame with `command` and all other fields zero.
    pub fn new(command: CommandCode) -> Self {
        Self { command, fields: CommandFields::default() }
    }

    /// Encodes the frame. Fails only when a joint value does not fit 24 bits.
    pub fn encode(&self) -> Result<[u8; COMMAND_FRAME_SIZE], FrameError> {
        for &v in self.fields.positions_steps.iter() {
            if !(I24_MIN..=I24_MAX).contains(&v) {
                return Err(FrameError::OutOfRange { field: "position", value: i64::from(v) });
            }
        }
        for &v in self.fields.speeds_steps_s.iter() {
            if !(I24_MIN..=I24_MAX).contains(&v) {
                return Err(FrameError::OutOfRange { field: "speed", value: i64::from(v) });
            }
        }
        let f = &self.fields;
        let mut b = [0u8; COMMAND_FRAME_SIZE];
        b[0..3].copy_from_slice(&START_BYTES);
        b[3] = COMMAND_LEN_BYTE;
        for i in 0..JOINT_COUNT {
            put_i24(&mut b[4 + 3 * i..], f.positions_steps[i]);
            put_i24(&mut b[22 + 3 * i..], f.speeds_steps_s[i]);
        }
        b[40] = self.command.byte();
        b[41] = f.affected_joints;
        b[42] = f.io_bits;
        b[43] = f.timeout;
        put_i16(&mut b[44..], f.gripper.position);
        put_i16(&mut b[46..], f.gripper.speed);
        put_i16(&mut b[48..], f.gripper.current_ma);
        b[50] = f.gripper.command_bits;
        b[51] = f.gripper.mode;
        b[52] = f.gripper.id;
        b[53] = COMMAND_CRC_BYTE;
        b[54..56].copy_from_slice(&END_BYTES);
        Ok(b)
    }
}

/// A command frame as received by a controller: the raw code byte (which may be one the host
/// API cannot send, such as 69) and the fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ReceivedCommand {
    /// Command code byte as received.
    pub code: u8,
    /// All other fields.
    pub fields: CommandFields,
    /// The "CRC" byte as received (ignored by everyone).
    pub crc_byte: u8,
}

impl ReceivedCommand {
    /// Decodes a whole 56-byte command frame (start, length 52 and end bytes checked; the CRC
    /// byte is not).
    pub fn decode(bytes: &[u8]) -> Result<Self, FrameError> {
        if bytes.len() != COMMAND_FRAME_SIZE {
            return Err(FrameError::WrongSize { got: bytes.len(), expected: COMMAND_FRAME_SIZE });
        }
        if bytes[0..3] != START_BYTES {
            return Err(FrameError::BadStart);
        }
        if bytes[3] != COMMAND_LEN_BYTE {
            return Err(FrameError::BadLength { got: bytes[3], expected: COMMAND_LEN_BYTE });
        }
        if bytes[54..56] != END_BYTES {
            return Err(FrameError::BadEnd);
        }
        Ok(Self::decode_payload(&bytes[4..]))
    }

    /// Decodes the 50 payload bytes at FW's fixed offsets (payload = frame offset − 4). Short
    /// payloads read as zero-padded.
    pub fn decode_payload(payload: &[u8]) -> Self {
        let mut p = [0u8; 50];
        let n = payload.len().min(50);
        p[..n].copy_from_slice(&payload[..n]);
        let fields = CommandFields {
            positions_steps: std::array::from_fn(|i| get_i24(&p[3 * i..])),
            speeds_steps_s: std::array::from_fn(|i| get_i24(&p[18 + 3 * i..])),
            affected_joints: p[37],
            io_bits: p[38],
            timeout: p[39],
            gripper: GripperCommand {
                position: get_i16(&p[40..]),
                speed: get_i16(&p[42..]),
                current_ma: get_i16(&p[44..]),
                command_bits: p[46],
                mode: p[47],
                id: p[48],
            },
        };
        Self { code: p[36], fields, crc_byte: p[49] }
    }

    /// The command, if it is one the host API can send.
    pub fn command(&self) -> Option<CommandCode> {
        CommandCode::from_byte(self.code)
    }

    /// OUTPUT1 level requested.
    pub fn out1(&self) -> bool {
        self.fields.io_bits & IO_OUT1 != 0
    }

    /// OUTPUT2 level requested.
    pub fn out2(&self) -> bool {
        self.fields.io_bits & IO_OUT2 != 0
    }
}

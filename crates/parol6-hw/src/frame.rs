//! Wire frames of PROTOCOL.md §3–4: the 56-byte host → controller [`CommandFrame`] and the
//! 60-byte controller → host [`StatusFrame`]. Integers are big-endian two's complement (i24 for
//! joints, i16 for gripper fields); bit fields are MSB first (bit index 0 = `0x80`).
//!
//! The encoder only takes a [`CommandCode`], which has no variant for code 69 (the firmware's
//! endless test routine), so no API of this crate can put 69 on the wire.

use parol6_core::parol6::JOINT_COUNT;

/// Start bytes of every frame.
pub const START_BYTES: [u8; 3] = [0xFF, 0xFF, 0xFF];
/// End bytes of every frame.
pub const END_BYTES: [u8; 2] = [0x01, 0x02];
/// Length byte of a command frame (bytes after it).
pub const COMMAND_LEN_BYTE: u8 = 52;
/// Total size of a command frame.
pub const COMMAND_FRAME_SIZE: usize = 56;
/// Length byte of a status frame (bytes after it).
pub const STATUS_LEN_BYTE: u8 = 56;
/// Total size of a status frame.
pub const STATUS_FRAME_SIZE: usize = 60;
/// Placeholder "CRC" the hosts send (nobody checks it).
pub const COMMAND_CRC_BYTE: u8 = 0xE4;
/// Placeholder "CRC" the controller sends.
pub const STATUS_CRC_BYTE: u8 = 0xD4;
/// Smallest value an i24 field can carry.
pub const I24_MIN: i32 = -8_388_608;
/// Largest value an i24 field can carry.
pub const I24_MAX: i32 = 8_388_607;
/// Firmware timer ticks per second in the status `timing` field (90 MHz / 128).
pub const TIMING_TICKS_PER_S: f64 = 703_125.0;

/// In/out bit: OUTPUT1 level (bit index 2).
pub const IO_OUT1: u8 = 0x20;
/// In/out bit: OUTPUT2 level (bit index 3).
pub const IO_OUT2: u8 = 0x10;
/// Status I/O bit: INPUT1.
pub const IO_IN1: u8 = 0x80;
/// Status I/O bit: INPUT2.
pub const IO_IN2: u8 = 0x40;
/// Status I/O bit: E-stop input (1 = released, 0 = pressed).
pub const IO_ESTOP_RELEASED: u8 = 0x08;
/// Status I/O bits the firmware always sets.
pub const IO_ALWAYS_SET: u8 = 0x07;
/// Joint-bit bytes (homed, errors): low two bits always set by the firmware.
pub const JOINT_BITS_ALWAYS_SET: u8 = 0x03;

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

/// Why bytes are not a valid frame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    /// Wrong total size.
    #[error("frame is {got} bytes, expected {expected}")]
    WrongSize {
        /// Bytes given.
        got: usize,
        /// Bytes expected.
        expected: usize,
    },
    /// The first three bytes are not `FF FF FF`.
    #[error("frame does not start with FF FF FF")]
    BadStart,
    /// The length byte is not the expected one.
    #[error("length byte {got:#04x}, expected {expected:#04x}")]
    BadLength {
        /// Length byte found.
        got: u8,
        /// Length byte expected.
        expected: u8,
    },
    /// The frame does not end with `01 02`.
    #[error("frame does not end with 01 02")]
    BadEnd,
    /// A value does not fit its field.
    #[error("{field} value {value} does not fit an i24 field")]
    OutOfRange {
        /// Field name.
        field: &'static str,
        /// The value.
        value: i64,
    },
}

/// Writes `v` as a 24-bit big-endian two's complement value (`v & 0xFFFFFF`).
fn put_i24(buf: &mut [u8], v: i32) {
    let u = (v as u32) & 0x00FF_FFFF;
    buf[0] = (u >> 16) as u8;
    buf[1] = (u >> 8) as u8;
    buf[2] = u as u8;
}

/// Reads a 24-bit big-endian two's complement value (sign-extends bit 23).
fn get_i24(buf: &[u8]) -> i32 {
    let u = (u32::from(buf[0]) << 16) | (u32::from(buf[1]) << 8) | u32::from(buf[2]);
    ((u << 8) as i32) >> 8
}

fn put_i16(buf: &mut [u8], v: i16) {
    buf[..2].copy_from_slice(&v.to_be_bytes());
}

fn get_i16(buf: &[u8]) -> i16 {
    i16::from_be_bytes([buf[0], buf[1]])
}

/// Joint bit of joint `i` (0-based) in a homed / error byte: J1 = `0x80` … J6 = `0x04`.
pub const fn joint_bit(joint: usize) -> u8 {
    0x80 >> joint
}

/// Per-joint flags of a joint-bit byte (homed, temperature error, position error).
pub fn joint_flags(byte: u8) -> [bool; JOINT_COUNT] {
    std::array::from_fn(|i| byte & joint_bit(i) != 0)
}

/// A joint-bit byte from per-joint flags, with the two always-set low bits.
pub fn joint_flags_byte(flags: &[bool; JOINT_COUNT]) -> u8 {
    flags.iter().enumerate().fold(JOINT_BITS_ALWAYS_SET, |b, (i, &f)| if f { b | joint_bit(i) } else { b })
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn i24_round_trip_edges() {
        let mut b = [0u8; 3];
        for v in [I24_MIN, -65536, -1, 0, 1, 65535, I24_MAX] {
            put_i24(&mut b, v);
            assert_eq!(get_i24(&b), v);
        }
        put_i24(&mut b, -1);
        assert_eq!(b, [0xFF, 0xFF, 0xFF]);
    }

    #[test]
    fn no_code_69_or_200() {
        for c in CommandCode::ALL {
            assert_ne!(c.byte(), 69);
            assert_ne!(c.byte(), 200);
            assert_eq!(CommandCode::from_byte(c.byte()), Some(c));
        }
        assert_eq!(CommandCode::from_byte(69), None);
        assert_eq!(CommandCode::from_byte(200), None);
    }

    #[test]
    fn home_frame_matches_protocol_md_8_1() {
        let b = CommandFrame::new(CommandCode::Home).encode().unwrap();
        let mut expected = vec![0xFF, 0xFF, 0xFF, 0x34];
        expected.extend([0u8; 36]);
        expected.push(0x64);
        expected.extend([0u8; 12]);
        expected.extend([0xE4, 0x01, 0x02]);
        assert_eq!(b.to_vec(), expected);
    }

    #[test]
    fn encode_rejects_out_of_range() {
        let mut f = CommandFrame::new(CommandCode::Move);
        f.fields.positions_steps[2] = I24_MAX + 1;
        assert!(matches!(f.encode(), Err(FrameError::OutOfRange { .. })));
    }

    #[test]
    fn decode_rejects_bad_frames() {
        let good = StatusFrame::default().encode();
        assert!(StatusFrame::decode(&good).is_ok());
        assert!(matches!(StatusFrame::decode(&good[..59]), Err(FrameError::WrongSize { .. })));
        let mut b = good;
        b[3] = 0x34;
        assert!(matches!(StatusFrame::decode(&b), Err(FrameError::BadLength { .. })));
        let mut b = good;
        b[59] = 3;
        assert_eq!(StatusFrame::decode(&b), Err(FrameError::BadEnd));
        let mut b = good;
        b[1] = 0;
        assert_eq!(StatusFrame::decode(&b), Err(FrameError::BadStart));
        let mut b = good;
        b[57] = 0x00;
        assert!(StatusFrame::decode(&b).is_ok(), "CRC byte is ignored");
    }

    #[test]
    fn default_status_is_unhomed_idle() {
        let s = StatusFrame::default();
        let b = s.encode();
        assert_eq!(&b[40..44], &[0x03, 0x0F, 0x03, 0x03]);
        assert!(!s.estop_pressed());
        assert!(!s.all_homed());
    }

    fn arb_status() -> impl Strategy<Value = StatusFrame> {
        (
            proptest::array::uniform6(I24_MIN..=I24_MAX),
            proptest::array::uniform6(I24_MIN..=I24_MAX),
            any::<[u8; 4]>(),
            any::<u16>(),
            any::<[u8; 3]>(),
            any::<[i16; 3]>(),
            any::<[u8; 2]>(),
        )
            .prop_map(|(p, s, bits, t, bytes, g, gs)| StatusFrame {
                positions_steps: p,
                speeds_steps_s: s,
                homed_bits: bits[0],
                io_bits: bits[1],
                temperature_error_bits: bits[2],
                position_error_bits: bits[3],
                timing_ticks: t,
                timeout_error: bytes[0],
                echoed_command: bytes[1],
                gripper_id: bytes[2],
                gripper_position: g[0],
                gripper_speed: g[1],
                gripper_current_ma: g[2],
                gripper_status: gs[0],
                gripper_object_byte: gs[1],
            })
    }

    proptest! {
        #[test]
        fn status_round_trip(s in arb_status()) {
            let b = s.encode();
            prop_assert_eq!(StatusFrame::decode(&b), Ok(s));
        }

        #[test]
        fn command_round_trip(
            code in proptest::sample::select(CommandCode::ALL.to_vec()),
            p in proptest::array::uniform6(I24_MIN..=I24_MAX),
            s in proptest::array::uniform6(I24_MIN..=I24_MAX),
            bytes in any::<[u8; 6]>(),
            g in any::<[i16; 3]>(),
        ) {
            let frame = CommandFrame { command: code, fields: CommandFields {
                positions_steps: p, speeds_steps_s: s, affected_joints: bytes[0], io_bits: bytes[1],
                timeout: bytes[2],
                gripper: GripperCommand { position: g[0], speed: g[1], current_ma: g[2],
                    command_bits: bytes[3], mode: bytes[4], id: bytes[5] },
            }};
            let b = frame.encode().unwrap();
            let r = ReceivedCommand::decode(&b).unwrap();
            prop_assert_eq!(r.command(), Some(code));
            prop_assert_eq!(r.fields, frame.fields);
            prop_assert_eq!(r.crc_byte, COMMAND_CRC_BYTE);
        }

        #[test]
        fn decoders_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..128)) {
            let _ = StatusFrame::decode(&bytes);
            let _ = ReceivedCommand::decode(&bytes);
            let _ = ReceivedCommand::decode_payload(&bytes);
        }
    }
}

//! Wire frames of PROTOCOL.md §3–4: the 56-byte host → controller [`CommandFrame`] and the
//! 60-byte controller → host [`StatusFrame`]. Integers are big-endian two's complement (i24 for
//! joints, i16 for gripper fields); bit fields are MSB first (bit index 0 = `0x80`).
//!
//! The encoder only takes a [`CommandCode`], which has no variant for code 69 (the firmware's
//! endless test routine), so no API of this crate can put 69 on the wire.

//!
//! Jobs: `command` (host → controller frame and the command codes), `status` (controller →
//! host frame), `codec` (i24 / i16 fields and joint bit bytes), `error` ([`FrameError`]).

use parol6_core::parol6::JOINT_COUNT;

mod codec;
mod command;
mod error;
mod status;

pub use codec::{joint_bit, joint_flags, joint_flags_byte};
pub use command::{CommandCode, CommandFields, CommandFrame, GripperCommand, ReceivedCommand};
pub use error::FrameError;
pub use status::StatusFrame;

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

#[cfg(test)]
mod tests;

//! Field codecs of the wire frames: 24-bit and 16-bit big-endian two's complement integers,
//! and the joint bit bytes (homed, errors; bit index 0 = `0x80` = J1).

use super::{JOINT_BITS_ALWAYS_SET, JOINT_COUNT};

/// Writes `v` as a 24-bit big-endian two's complement value (`v & 0xFFFFFF`).
pub(crate) fn put_i24(buf: &mut [u8], v: i32) {
    let u = (v as u32) & 0x00FF_FFFF;
    buf[0] = (u >> 16) as u8;
    buf[1] = (u >> 8) as u8;
    buf[2] = u as u8;
}

/// Reads a 24-bit big-endian two's complement value (sign-extends bit 23).
pub(crate) fn get_i24(buf: &[u8]) -> i32 {
    let u = (u32::from(buf[0]) << 16) | (u32::from(buf[1]) << 8) | u32::from(buf[2]);
    ((u << 8) as i32) >> 8
}

/// Writes `v` as a 16-bit big-endian two's complement value.
pub(crate) fn put_i16(buf: &mut [u8], v: i16) {
    buf[..2].copy_from_slice(&v.to_be_bytes());
}

/// Reads a 16-bit big-endian two's complement value.
pub(crate) fn get_i16(buf: &[u8]) -> i16 {
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

//! CDR payloads as ROS 2 sends them: a 4-byte encapsulation header (`00 01 00 00`: plain CDR,
//! little-endian; `00 00 00 00`: big-endian) and the XCDR1 body (primitives aligned to their
//! size from the body's start, 8 for `float64`; sequences and strings behind a `uint32` count,
//! strings with their NUL), through the `cdr-encoding` crate.
//!
//! Decoding is bounded: a message over [`MAX_MESSAGE_BYTES`] is refused before a byte of it is
//! read, every sequence has its own count cap (checked element by element, so a count of four
//! billion costs nothing), the crate reads nothing past the input and allocates nothing ahead
//! of it, and no input panics (the `ros2_cdr` fuzz target). An error names the field (its path,
//! e.g. `points[3].time_from_start.nanosec`) and the byte where decoding stopped.

use byteorder::{BigEndian, LittleEndian};
use serde::de::{DeserializeOwned, SeqAccess, Visitor};
use serde::{Deserializer, Serialize};

/// The encapsulation header of plain little-endian CDR, as every message we send starts.
pub const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];
/// The largest message decoded, bytes (a `JointTrajectory` of 10 000 six-joint points with
/// positions and velocities is about 1.1 MiB).
pub const MAX_MESSAGE_BYTES: usize = 2 * 1024 * 1024;
/// Bytes after a message's end that are taken as padding; more is refused (a wrong type).
pub const MAX_TRAILING_BYTES: usize = 8;

/// Why a payload could not be decoded or encoded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CdrError {
    /// Over [`MAX_MESSAGE_BYTES`].
    #[error("the message is {len} bytes; at most {max} are accepted")]
    TooLarge {
        /// Its size, bytes.
        len: usize,
        /// The cap, bytes.
        max: usize,
    },
    /// Shorter than the encapsulation header.
    #[error("the message is {len} bytes, shorter than the 4-byte CDR encapsulation header")]
    NoHeader {
        /// Its size, bytes.
        len: usize,
    },
    /// An encapsulation other than plain CDR.
    #[error("encapsulation 0x{id:04x} at byte 0 is not plain CDR (0x0000 big-endian, 0x0001 little-endian)")]
    Encapsulation {
        /// The representation identifier read.
        id: u16,
    },
    /// A field could not be read.
    #[error("field {field}, byte {offset}: {reason}")]
    Field {
        /// Its path, e.g. `points[3].positions[2]` (`message` when no field was reached).
        field: String,
        /// Byte of the payload (header included) where decoding stopped.
        offset: usize,
        /// What was wrong.
        reason: String,
    },
    /// Bytes left after the message's end.
    #[error("{count} bytes after the message's end at byte {offset} (not a message of this type?)")]
    Trailing {
        /// Byte where the message ended.
        offset: usize,
        /// Bytes left.
        count: usize,
    },
    /// A message could not be encoded (a string or sequence too long for CDR's `uint32` count).
    #[error("cannot encode the message: {0}")]
    Encode(String),
}

/// The layout of a message's fields, to name the field a decoding error is in.
#[derive(Debug)]
pub enum Shape {
    /// A primitive or a string.
    Leaf,
    /// A struct: its fields in order, with their shapes.
    Struct(&'static [(&'static str, Shape)]),
    /// A sequence of elements of this shape.
    Seq(&'static Shape),
}

/// A message type that can be decoded, with its field layout.
pub trait Message: Serialize + DeserializeOwned {
    /// The field layout.
    const SHAPE: &'static Shape;
}

/// `msg` as a payload: the little-endian header and the CDR body.
pub fn encode<T: Serialize>(msg: &T) -> Result<Vec<u8>, CdrError> {
    let mut out = CDR_LE_HEADER.to_vec();
    cdr_encoding::to_writer::<T, LittleEndian, _>(&mut out, msg).map_err(|e| CdrError::Encode(e.to_string()))?;
    Ok(out)
}

/// Decodes a payload of type `T` (either byte order).
pub fn decode<T: Message>(payload: &[u8]) -> Result<T, CdrError> {
    if payload.len() > MAX_MESSAGE_BYTES {
        return Err(CdrError::TooLarge { len: payload.len(), max: MAX_MESSAGE_BYTES });
    }
    let Some((header, body)) = payload.split_first_chunk::<4>() else {
        return Err(CdrError::NoHeader { len: payload.len() });
    };
    match u16::from_be_bytes([header[0], header[1]]) {
        0x0001 => decode_body::<T, LittleEndian>(body),
        0x0000 => decode_body::<T, BigEndian>(body),
        id => Err(CdrError::Encapsulation { id }),
    }
}

fn decode_body<T: Message, BO: byteorder::ByteOrder>(body: &[u8]) -> Result<T, CdrError> {
    let mut de = cdr_encoding::CdrDeserializer::<BO>::new(body);
    match serde_path_to_error::deserialize::<_, T>(&mut de) {
        Ok(msg) => {
            let used = de.bytes_consumed();
            let count = body.len().saturating_sub(used);
            if count > MAX_TRAILING_BYTES {
                return Err(CdrError::Trailing { offset: used + 4, count });
            }
            Ok(msg)
        }
        Err(e) => Err(CdrError::Field {
            field: field_name(T::SHAPE, e.path()),
            offset: de.bytes_consumed() + 4,
            reason: e.inner().to_string(),
        }),
    }
}

/// The path of serde indices (CDR structs are read as sequences) as field names.
fn field_name(shape: &'static Shape, path: &serde_path_to_error::Path) -> String {
    let mut out = String::new();
    let mut node = Some(shape);
    for seg in path.iter() {
        let serde_path_to_error::Segment::Seq { index } = seg else { break };
        match node {
            Some(Shape::Struct(fields)) => match fields.get(*index) {
                Some((name, inner)) => {
                    if !out.is_empty() {
                        out.push('.');
                    }
                    out.push_str(name);
                    node = Some(inner);
                }
                None => break,
            },
            Some(Shape::Seq(inner)) => {
                out.push_str(&format!("[{index}]"));
                node = Some(inner);
            }
            _ => break,
        }
    }
    if out.is_empty() { "message".to_string() } else { out }
}

/// A sequence of at most `max` elements; the count is checked as elements arrive.
struct Bounded<T> {
    max: usize,
    marker: std::marker::PhantomData<T>,
}

impl<'de, T: serde::Deserialize<'de>> Visitor<'de> for Bounded<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "a sequence of at most {} elements", self.max)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        let mut out = Vec::new();
        while let Some(v) = seq.next_element()? {
            if out.len() == self.max {
                return Err(serde::de::Error::custom(format!("more than {} elements", self.max)));
            }
            out.push(v);
        }
        Ok(out)
    }
}

fn bounded<'de, D: Deserializer<'de>, T: serde::Deserialize<'de>>(d: D, max: usize) -> Result<Vec<T>, D::Error> {
    d.deserialize_seq(Bounded { max, marker: std::marker::PhantomData })
}

/// The most joint names, values per point or joint states accepted.
pub const MAX_JOINTS: usize = 64;
/// The most transforms in a `TFMessage`.
pub const MAX_TRANSFORMS: usize = 1024;
/// The most points in a trajectory.
pub const MAX_POINTS: usize = 10_000;

pub(crate) fn up_to_joints<'de, D: Deserializer<'de>, T: serde::Deserialize<'de>>(d: D) -> Result<Vec<T>, D::Error> {
    bounded(d, MAX_JOINTS)
}

pub(crate) fn up_to_transforms<'de, D: Deserializer<'de>, T: serde::Deserialize<'de>>(
    d: D,
) -> Result<Vec<T>, D::Error> {
    bounded(d, MAX_TRANSFORMS)
}

pub(crate) fn up_to_points<'de, D: Deserializer<'de>, T: serde::Deserialize<'de>>(d: D) -> Result<Vec<T>, D::Error> {
    bounded(d, MAX_POINTS)
}

//! [`FrameError`]: why bytes are not a valid wire frame.

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

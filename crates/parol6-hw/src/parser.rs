//! Streaming frame parsers.
//!
//! - [`StatusParser`] (host side): PROTOCOL.md §6's recommended rule: find `FF FF FF 38`, wait
//!   for 60 bytes, require `01 02` at 58–59, otherwise drop one byte and scan again.
//! - [`CommandParser`] (controller side, used by the emulator): the firmware's byte-by-byte
//!   state machine, including its weakness after a stray `0xFF` (the next byte is taken as the
//!   length whatever it is).
//!
//! Both take any bytes without panicking and keep bounded memory.

use crate::frame::{END_BYTES, ReceivedCommand, STATUS_FRAME_SIZE, STATUS_LEN_BYTE, StatusFrame};

/// Header the status parser looks for.
const STATUS_HEADER: [u8; 4] = [0xFF, 0xFF, 0xFF, STATUS_LEN_BYTE];

/// Counters of a [`StatusParser`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct ParserStats {
    /// Frames returned.
    pub frames: u64,
    /// Headers found whose end bytes were wrong (each costs one dropped byte and a rescan).
    pub invalid_frames: u64,
    /// Bytes skipped while looking for a header (junk, corrupted frames).
    pub discarded_bytes: u64,
}

/// Host-side streaming parser for status frames.
#[derive(Debug, Clone, Default)]
pub struct StatusParser {
    buf: Vec<u8>,
    stats: ParserStats,
}

impl StatusParser {
    /// An empty parser.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends received bytes. Call [`StatusParser::next_frame`] until it returns `None`.
    pub fn push(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// Counters so far.
    pub fn stats(&self) -> ParserStats {
        self.stats
    }

    /// Bytes buffered and not yet consumed.
    pub fn buffered(&self) -> usize {
        self.buf.len()
    }

    /// Drops buffered bytes (e.g. after reconnecting). Counters are kept.
    pub fn clear(&mut self) {
        self.buf.clear();
    }

    fn discard(&mut self, n: usize) {
        let n = n.min(self.buf.len());
        self.buf.drain(..n);
        self.stats.discarded_bytes += n as u64;
    }

    /// The next complete, valid frame in the buffer, if any.
    pub fn next_frame(&mut self) -> Option<StatusFrame> {
        loop {
            let Some(start) = self.buf.windows(STATUS_HEADER.len()).position(|w| w == STATUS_HEADER) else {
                // Keep a possible header prefix (up to 3 bytes) for the next push.
                let keep = self.buf.iter().rev().take(3).take_while(|&&b| b == 0xFF).count();
                let drop = self.buf.len() - keep;
                self.discard(drop);
                return None;
            };
            self.discard(start);
            if self.buf.len() < STATUS_FRAME_SIZE {
                return None;
            }
            if self.buf[STATUS_FRAME_SIZE - 2..STATUS_FRAME_SIZE] == END_BYTES {
                let frame = StatusFrame::decode(&self.buf[..STATUS_FRAME_SIZE]).ok();
                if let Some(frame) = frame {
                    self.buf.drain(..STATUS_FRAME_SIZE);
                    self.stats.frames += 1;
                    return Some(frame);
                }
            }
            self.stats.invalid_frames += 1;
            self.discard(1);
        }
    }

    /// Pushes `bytes` and returns every frame now complete.
    pub fn feed(&mut self, bytes: &[u8]) -> Vec<StatusFrame> {
        self.push(bytes);
        std::iter::from_fn(|| self.next_frame()).collect()
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FwState {
    /// Counting consecutive `0xFF` bytes.
    Sync(u8),
    /// Three `0xFF` seen: the next byte is the length.
    Length,
    /// Storing `len` bytes, `stored` so far.
    Data { len: u8, stored: u8 },
}

/// Counters of a [`CommandParser`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct CommandParserStats {
    /// Frames accepted.
    pub accepted: u64,
    /// Frames stored but rejected (end bytes not `01 02`, or shorter than a command).
    pub rejected: u64,
}

/// Controller-side parser reproducing the firmware's receiver (PROTOCOL.md §6). Like the
/// firmware it keeps one 255-byte buffer and decodes fields at fixed offsets.
///
/// Deviations (both are firmware faults, not behaviour a host can rely on): a length byte of 0
/// returns to sync instead of overrunning the buffer, and an accepted frame shorter than a
/// command frame (L < 52) is rejected instead of being decoded from stale buffer bytes.
#[derive(Debug, Clone)]
pub struct CommandParser {
    state: FwState,
    buf: [u8; 255],
    stats: CommandParserStats,
}

impl Default for CommandParser {
    fn default() -> Self {
        Self { state: FwState::Sync(0), buf: [0; 255], stats: CommandParserStats::default() }
    }
}

impl CommandParser {
    /// A parser in the sync state.
    pub fn new() -> Self {
        Self::default()
    }

    /// Counters so far.
    pub fn stats(&self) -> CommandParserStats {
        self.stats
    }

    /// Feeds one byte; returns a command when this byte completes an accepted frame.
    pub fn push_byte(&mut self, byte: u8) -> Option<ReceivedCommand> {
        match self.state {
            FwState::Sync(n) => {
                self.state = if byte == 0xFF {
                    if n + 1 >= 3 { FwState::Length } else { FwState::Sync(n + 1) }
                } else {
                    FwState::Sync(0)
                };
                None
            }
            FwState::Length => {
                self.state = if byte == 0 { FwState::Sync(0) } else { FwState::Data { len: byte, stored: 0 } };
                None
            }
            FwState::Data { len, stored } => {
                self.buf[usize::from(stored)] = byte;
                let stored = stored + 1;
                if stored < len {
                    self.state = FwState::Data { len, stored };
                    return None;
                }
                self.state = FwState::Sync(0);
                let l = usize::from(len);
                let ends_ok = l >= 2 && self.buf[l - 2..l] == END_BYTES;
                if ends_ok && l >= usize::from(crate::frame::COMMAND_LEN_BYTE) {
                    self.stats.accepted += 1;
                    Some(ReceivedCommand::decode_payload(&self.buf[..l]))
                } else {
                    self.stats.rejected += 1;
                    None
                }
            }
        }
    }

    /// Feeds bytes; returns every accepted command in order.
    pub fn feed(&mut self, bytes: &[u8]) -> Vec<ReceivedCommand> {
        bytes.iter().filter_map(|&b| self.push_byte(b)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{CommandCode, CommandFrame};
    use proptest::prelude::*;

    fn status(n: i32) -> StatusFrame {
        StatusFrame { positions_steps: [n, -n, n, 0, -1, 1], ..Default::default() }
    }

    #[test]
    fn parses_back_to_back_frames_split_anywhere() {
        let mut stream = vec![0x00, 0xFF, 0x13];
        for n in 0..5 {
            stream.extend_from_slice(&status(n).encode());
        }
        for split in [1, 7, 59, 60, 61, 200] {
            let mut p = StatusParser::new();
            let mut got = Vec::new();
            for chunk in stream.chunks(split) {
                got.extend(p.feed(chunk));
            }
            assert_eq!(got, (0..5).map(status).collect::<Vec<_>>(), "split {split}");
            assert_eq!(p.stats().discarded_bytes, 3);
        }
    }

    #[test]
    fn resyncs_after_stray_ff_and_corrupt_end() {
        let mut stream = Vec::new();
        let mut bad = status(1).encode();
        bad[59] = 0x03;
        stream.extend_from_slice(&bad);
        stream.push(0xFF);
        stream.extend_from_slice(&status(2).encode());
        let mut p = StatusParser::new();
        assert_eq!(p.feed(&stream), vec![status(2)]);
        assert!(p.stats().invalid_frames >= 1);
    }

    #[test]
    fn firmware_parser_swallows_after_stray_ff() {
        let f = CommandFrame::new(CommandCode::Enable).encode().unwrap();
        let mut stream = vec![0xFF];
        stream.extend_from_slice(&f);
        for _ in 0..5 {
            stream.extend_from_slice(&f);
        }
        let mut p = CommandParser::new();
        // 1 + 6·56 = 337 bytes; the bogus L = 255 frame eats 3 + 255 … the rest resyncs.
        let got = p.feed(&stream);
        assert!(got.len() < 6);
        assert!(got.iter().all(|c| c.command() == Some(CommandCode::Enable)));
        let mut p = CommandParser::new();
        assert_eq!(p.feed(&f).len(), 1);
    }

    proptest! {
        #[test]
        fn status_parser_never_panics_and_finds_embedded_frames(
            junk_before in proptest::collection::vec(any::<u8>(), 0..300),
            n in -1000i32..1000,
        ) {
            let mut p = StatusParser::new();
            let _ = p.feed(&junk_before);
            // After junk, two frames in a row: at least the second one must be found
            // (the first may be swallowed by a header-like junk tail).
            let mut s = status(n).encode().to_vec();
            s.extend_from_slice(&status(n + 1).encode());
            let got = p.feed(&s);
            prop_assert!(got.contains(&status(n + 1)));
            prop_assert!(p.buffered() < STATUS_FRAME_SIZE);
        }

        #[test]
        fn parsers_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2000)) {
            let mut p = StatusParser::new();
            for chunk in bytes.chunks(17) {
                let _ = p.feed(chunk);
            }
            prop_assert!(p.buffered() < STATUS_FRAME_SIZE);
            let mut c = CommandParser::new();
            let _ = c.feed(&bytes);
        }

        #[test]
        fn command_parser_resyncs_after_junk(junk in proptest::collection::vec(any::<u8>(), 0..100)) {
            let f = CommandFrame::new(CommandCode::Idle).encode().unwrap();
            let mut c = CommandParser::new();
            let _ = c.feed(&junk);
            let mut got = Vec::new();
            // Worst case the junk leaves a bogus length of 255 pending: 5 frames clear it.
            for _ in 0..7 {
                got.extend(c.feed(&f));
            }
            prop_assert!(!got.is_empty());
        }
    }
}

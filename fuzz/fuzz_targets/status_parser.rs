//! Feeds arbitrary bytes to the streaming parsers and the frame decoders: none may panic,
//! and every frame the status parser returns must re-encode to a valid frame.
//! Run with `cargo +nightly fuzz run status_parser` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;
use parol6_hw::frame::{ReceivedCommand, STATUS_FRAME_SIZE, StatusFrame};
use parol6_hw::parser::{CommandParser, StatusParser};

fuzz_target!(|data: &[u8]| {
    // Whole buffer, then split at a data-dependent point.
    let mut p = StatusParser::new();
    for frame in p.feed(data) {
        let bytes = frame.encode();
        assert_eq!(StatusFrame::decode(&bytes).ok(), Some(frame));
    }
    assert!(p.buffered() < STATUS_FRAME_SIZE);
    let split = data.first().map_or(0, |&b| usize::from(b)).min(data.len());
    let mut q = StatusParser::new();
    let mut n = q.feed(&data[..split]).len();
    n += q.feed(&data[split..]).len();
    assert_eq!(n, StatusParser::new().feed(data).len());

    let mut c = CommandParser::new();
    let _ = c.feed(data);
    let _ = StatusFrame::decode(data);
    let _ = ReceivedCommand::decode(data);
    let _ = ReceivedCommand::decode_payload(data);
    if data.len() >= STATUS_FRAME_SIZE {
        let _ = StatusFrame::decode(&data[..STATUS_FRAME_SIZE]);
    }
});

//! Feeds arbitrary bytes to the reader of our MCAP recordings
//! (`parol6_core::telemetry::read_recording`): it must never panic, must answer an error for
//! anything that is not MCAP, and what it returns must agree with the streaming scan.
//! Seeds: `fuzz/seeds/mcap_reader/` (small recordings of ours, whole and cut short).
//! Run with `cargo +nightly fuzz run -s none -a mcap_reader` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;
use parol6_core::telemetry::reader::{RecordingError, read_recording, scan_recording};

fuzz_target!(|data: &[u8]| {
    let whole = read_recording(data);
    if data.is_empty() {
        assert_eq!(whole, Err(RecordingError::Empty));
    } else if !data.starts_with(b"\x89MCAP0\r\n") {
        assert_eq!(whole, Err(RecordingError::NotMcap));
    }
    let mut streamed = 0usize;
    let scanned = scan_recording(data, &mut |_, _| streamed += 1);
    match (&whole, &scanned) {
        (Ok(w), Ok(s)) => {
            assert_eq!(w.measured.len() + w.commanded.len(), streamed);
            assert_eq!(w.topics, s.topics);
            assert_eq!(w.truncated, s.truncated);
        }
        (Err(a), Err(b)) => assert_eq!(a, b),
        _ => panic!("read and scan disagree"),
    }
});

//! Feeds arbitrary bytes to the readers of our MCAP recordings: the linear reader
//! (`parol6_core::telemetry::read_recording`, and its streaming scan) and the replay's
//! (`load_replay` on bytes in memory, `load_whole_replay` on a reader). None may panic; the
//! linear reader must answer an error for anything that is not MCAP and agree with its
//! streaming scan; the replay read from memory and from a reader must agree.
//! Seeds: `fuzz/seeds/mcap_reader/` (small recordings of ours, whole and cut short).
//! Run with `cargo +nightly fuzz run -s none -a mcap_reader` from the repository root.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use parol6_core::RobotModel;
use parol6_core::telemetry::reader::{RecordingError, read_recording, scan_recording};
use parol6_core::telemetry::{ReadPath, load_replay, load_whole_replay};

fn model() -> &'static RobotModel {
    static MODEL: OnceLock<RobotModel> = OnceLock::new();
    MODEL.get_or_init(RobotModel::parol6)
}

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
    let in_memory = load_replay(data, model());
    let from_reader = load_whole_replay(data, data.len() as u64, model());
    match (&in_memory, &from_reader) {
        (Ok(a), Some(Ok(b))) => {
            assert!(matches!(a.read_path, ReadPath::Parallel { .. }), "a whole file read from memory in parallel");
            assert_eq!((a.store.len(), a.samples_in_file, &a.events), (b.store.len(), b.samples_in_file, &b.events));
        }
        (Err(a), Some(Err(b))) => assert_eq!(a, b),
        (_, None) => {}
        _ => panic!("the replay from memory and from a reader disagree"),
    }
});

//! Issue 29, items 5 and 6: a file cut anywhere keeps every whole chunk and what its cut chunk
//! holds up to the cut; a crash loses at most the chunk being written (≤ 0.25 s); one damaged
//! chunk header loses that chunk only.

use std::cell::RefCell;
use std::io::{Cursor, Seek, SeekFrom, Write};
use std::rc::Rc;

use super::tests::{recording_bytes_at, sample};
use super::*;
use crate::model::PAROL6_URDF;
use crate::telemetry::writer::{McapSink, RecordingInfo};

/// A chunk of a whole file: where it starts and ends, and its `/joint_states` messages.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ChunkSpan {
    pub start: usize,
    pub end: usize,
    pub samples: usize,
}

/// The chunks of a whole file, from its summary (the mcap crate's reader).
pub(crate) fn chunk_spans(bytes: &[u8]) -> Vec<ChunkSpan> {
    let summary = mcap::read::Summary::read(bytes).expect("summary").expect("a summary");
    let joint_states = summary.channels.values().find(|c| c.topic == "/joint_states").expect("channel").id;
    summary
        .chunk_indexes
        .iter()
        .map(|c| {
            let samples = summary
                .stream_chunk(bytes, c)
                .expect("chunk")
                .filter(|m| m.as_ref().expect("message").channel.id == joint_states)
                .count();
            let start = c.chunk_start_offset as usize;
            ChunkSpan { start, end: start + c.chunk_length as usize, samples }
        })
        .collect()
}

fn samples_read(bytes: &[u8]) -> usize {
    read_recording(bytes).map_or(0, |r| r.measured.len())
}

/// Every offset of a 0.8 s recording at 100 Hz: the samples read never decrease as the cut
/// moves on, and always include every chunk that ends before the cut.
#[test]
fn a_cut_file_keeps_every_whole_chunk_at_every_offset() {
    let bytes = recording_bytes_at(80, 1e-2);
    let chunks = chunk_spans(&bytes);
    assert!(chunks.len() >= 4 && chunks.iter().all(|c| c.samples <= 26), "chunks of at most 0.25 s: {chunks:?}");
    let mut last = 0;
    for cut in 0..=bytes.len() {
        let n = samples_read(&bytes[..cut]);
        let whole: usize = chunks.iter().filter(|c| c.end <= cut).map(|c| c.samples).sum();
        assert!(n >= last, "cut at {cut}: {n} samples, {last} at the cut before");
        assert!(n >= whole, "cut at {cut}: {n} samples, the whole chunks before it hold {whole}");
        last = n;
    }
    assert_eq!(last, 80);
}

/// Issue 29 item 5: a chunk cut short gives back the messages decoded before the cut
/// (streaming zstd: whole blocks of up to 128 KiB of records), and the warning says how much
/// was lost.
#[test]
fn a_cut_chunk_gives_back_what_it_holds_up_to_the_cut() {
    // 1 kHz: a chunk of 0.25 s is about 1 MB of records, several zstd blocks
    let bytes = recording_bytes_at(2000, 1e-3);
    let chunks = chunk_spans(&bytes);
    let big = chunks.iter().filter(|c| c.samples >= 200).collect::<Vec<_>>();
    assert!(!big.is_empty(), "{chunks:?}");
    for c in big {
        let before: usize = chunks.iter().filter(|d| d.end <= c.start).map(|d| d.samples).sum();
        let cut = c.end - 16;
        let rec = read_recording(&bytes[..cut]).expect("readable in part");
        let recovered = rec.measured.len() - before;
        assert!(recovered >= c.samples / 2, "cut 16 bytes before the end of {c:?}: {recovered} recovered");
        assert!(rec.measured.iter().zip(1..).all(|(m, k)| m.seq == k), "in order, none invented");
        assert!(
            rec.warnings.iter().any(|w| w.contains(&format!("byte {}", c.start)) && w.contains("lost")),
            "{:?}",
            rec.warnings
        );
    }
}

/// A `Write + Seek` whose bytes can be read while the sink still writes (what a crash leaves).
#[derive(Clone, Default)]
struct Shared(Rc<RefCell<Cursor<Vec<u8>>>>);

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Seek for Shared {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.0.borrow_mut().seek(pos)
    }
}

/// Issue 29 item 5: chunks close every 0.25 s of log time, so what a crash (SIGKILL, power)
/// leaves on disk reads up to within 0.25 s of the last sample written.
#[test]
fn a_crash_loses_at_most_a_quarter_second() {
    for dt_s in [1e-2, 1e-3] {
        let model = RobotModel::parol6();
        let info = RecordingInfo {
            app_version: "test".into(),
            tool: "none".into(),
            program: String::new(),
            urdf_text: PAROL6_URDF.into(),
            tracking: String::new(),
        };
        let file = Shared::default();
        let mut sink = McapSink::new(file.clone(), &model, &info).expect("sink");
        let n = (2.0 / dt_s) as u64;
        for k in 1..=n {
            sink.write_sample(&sample(k, dt_s)).expect("sample");
            let t_s = k as f64 * dt_s;
            if k % 7 == 0 {
                let bytes = file.0.borrow().get_ref().clone();
                let last_s =
                    read_recording(&bytes).ok().and_then(|r| r.measured.last().map(|m| m.time_s)).unwrap_or(0.0);
                assert!(t_s - last_s <= 0.25 + 1e-9, "{dt_s} s period: at {t_s} s the file reads to {last_s} s");
            }
        }
    }
}

/// Issue 29 item 6: a chunk header whose size fields are set to 4 GiB loses that chunk only:
/// the metadata and every other chunk are read, and a warning names the damaged chunk's byte.
#[test]
fn a_damaged_chunk_header_keeps_the_metadata_and_the_other_chunks() {
    let bytes = recording_bytes_at(2000, 1e-3);
    let chunks = chunk_spans(&bytes);
    let total: usize = chunks.iter().map(|c| c.samples).sum();
    // the record length, then (after opcode, length, start and end time) the uncompressed size
    for (i, c) in chunks.iter().enumerate() {
        for field in [1, 9 + 16] {
            let mut damaged = bytes.clone();
            damaged[c.start + field..c.start + field + 8].copy_from_slice(&(4u64 << 30).to_le_bytes());
            let rec = read_recording(&damaged).unwrap_or_else(|e| panic!("chunk {i} field {field}: {e}"));
            assert_eq!(rec.robot(), "parol6", "chunk {i} field {field}: metadata kept");
            assert!(
                rec.measured.len() >= total - c.samples,
                "chunk {i} field {field}: {} of {total} samples ({} in the damaged chunk)",
                rec.measured.len(),
                c.samples
            );
            if rec.measured.len() < total {
                let at = format!("byte {}", c.start);
                assert!(rec.warnings.iter().any(|w| w.contains(&at)), "chunk {i}: {:?}", rec.warnings);
            }
        }
    }
}

/// Found by the `mcap_cut` libFuzzer run (issue 29): the first chunk's opcode damaged into a
/// channel record's (0x04) made its header read as a channel with the `/joint_states` id (from
/// its start time) and a garbage topic, which replaced the summary's channel: every sample of
/// the intact chunks after it was lost. The first definition of an id is kept (the MCAP spec:
/// records sharing an id are identical), and the redefinition is named in a warning.
#[test]
fn a_damaged_chunk_read_as_a_channel_does_not_replace_the_summarys_channel() {
    let bytes = recording_bytes_at(80, 1e-2);
    let chunks = chunk_spans(&bytes);
    let summary = mcap::read::Summary::read(&bytes).expect("summary").expect("a summary");
    let joint_states = summary.channels.values().find(|c| c.topic == "/joint_states").expect("channel").id;
    let first = chunks.iter().map(|c| c.start).min().expect("chunks");
    let mut damaged = bytes.clone();
    damaged[first] = mcap::records::op::CHANNEL;
    // the chunk's start time: the channel's id, schema id 0 and an empty topic length
    damaged[first + 9..first + 17].copy_from_slice(&u64::from(joint_states).to_le_bytes());
    let len = u64::from_le_bytes(damaged[first + 1..first + 9].try_into().expect("8 bytes")) as usize;
    let parsed = mcap::parse_record(mcap::records::op::CHANNEL, &damaged[first + 9..first + 9 + len]);
    assert!(
        matches!(&parsed, Ok(mcap::records::Record::Channel(c)) if c.id == joint_states && c.topic != "/joint_states"),
        "the damaged chunk reads as a bogus channel: {parsed:?}"
    );
    let rec = read_recording(&damaged).expect("readable");
    let in_first = chunks.iter().find(|c| c.start == first).map_or(0, |c| c.samples);
    assert_eq!(rec.measured.len(), 80 - in_first, "{:?}", rec.warnings);
    assert!(rec.warnings.iter().any(|w| w.contains(&format!("channel {joint_states}"))), "{:?}", rec.warnings);
}

/// The summary's schemas and channels come first and are kept over later records of the same
/// id, so a summary that does not match the footer's CRC is not used: a damaged `/joint_states`
/// channel there loses nothing (the first chunk's is read instead).
#[test]
fn a_damaged_summary_channel_is_not_used() {
    let bytes = recording_bytes_at(80, 1e-2);
    let footer = bytes.len() - 8 - 29;
    let start = u64::from_le_bytes(bytes[footer + 9..footer + 17].try_into().expect("8 bytes")) as usize;
    let at = start + bytes[start..].windows(13).position(|w| w == b"/joint_states").expect("in the summary");
    let mut damaged = bytes.clone();
    damaged[at + 1] = b'J';
    let rec = read_recording(&damaged).expect("readable");
    assert_eq!(rec.measured.len(), 80, "{:?}", rec.warnings);
    assert!(rec.warnings.iter().any(|w| w.contains(&format!("summary (at byte {start})"))), "{:?}", rec.warnings);
}

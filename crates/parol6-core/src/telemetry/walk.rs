//! The records of a recording, walked without trusting the file: the one-pass reader's
//! ([`super::reader`]) way through cut and damaged files.
//!
//! [`walk_recording`] hands every record of the data section to a visitor, the records inside
//! each chunk included, in file order, after the schemas and channels of the summary (when the
//! file has its footer and the summary matches its CRC, so that a damaged first chunk does not
//! lose the channels; the reader keeps the first record of each id, so a damaged record later
//! cannot replace them either). What it does with a file that is not whole:
//!
//! - a chunk whose CRC matches is read whole, even when a size field of its header is wrong
//!   (the CRC covers its records; the warning names the field);
//! - a chunk cut short (a crash, a full disk, a copy cut short) is decompressed as a stream up
//!   to the cut: every whole record before the cut is kept (zstd gives its output a block of up
//!   to 128 KiB of records at a time), and the warning says what was kept and what was lost;
//! - a record whose length runs past the end of the file, or a chunk that cannot be decoded,
//!   is skipped with a warning naming its byte, and the walk goes on at the next record that
//!   makes sense (a chunk whose header adds up, a metadata record, the data-end record or the
//!   footer); without one, the file ends there.
//!
//! Nothing here trusts a length: every slice is bounds-checked and decompressed chunks are
//! bounded by [`MAX_RECORD_BYTES`].

use mcap::records::op;
use zstd::stream::raw::{Decoder, InBuffer, Operation, OutBuffer};

/// Largest decompressed chunk, bytes (ours close at 8 MiB; a damaged size must not make the
/// reader allocate more).
pub const MAX_RECORD_BYTES: usize = 64 << 20;

/// Longest compression name accepted in a chunk header (ours is `zstd`).
const MAX_COMPRESSION_NAME: usize = 16;

/// What [`walk_recording`] found besides the records.
#[derive(Debug, Default)]
pub struct Walked {
    /// The file ended before its footer.
    pub truncated: bool,
    /// The footer was read.
    pub saw_footer: bool,
    /// Records handed to the visitor.
    pub records: usize,
    /// The first damage met, when no record could be read before it: (byte, what).
    pub damaged_at_start: Option<(usize, String)>,
    /// What was skipped, recovered or lost, each naming its byte.
    pub warnings: Vec<String>,
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at.checked_add(8)?)?.try_into().ok()?))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at.checked_add(4)?)?.try_into().ok()?))
}

/// A chunk record's header fields.
struct ChunkHeader<'a> {
    uncompressed_bytes: u64,
    crc: u32,
    compression: &'a [u8],
    compressed_bytes: u64,
    /// Where its compressed records start in the file.
    data_start: usize,
}

/// The header of the chunk record at `pos` (opcode and length included), when it is there.
fn chunk_header(bytes: &[u8], pos: usize) -> Option<ChunkHeader<'_>> {
    let body = pos.checked_add(9)?;
    // message start and end time, uncompressed size, uncompressed CRC, compression, size
    let name_len = usize::try_from(u32_at(bytes, body + 28)?).ok().filter(|&n| n <= MAX_COMPRESSION_NAME)?;
    let name_end = body + 32 + name_len;
    Some(ChunkHeader {
        uncompressed_bytes: u64_at(bytes, body + 16)?,
        crc: u32_at(bytes, body + 24)?,
        compression: bytes.get(body + 32..name_end)?,
        compressed_bytes: u64_at(bytes, name_end)?,
        data_start: name_end + 8,
    })
}

/// The end of the record at `pos`, when its length keeps it inside the file.
fn record_end(bytes: &[u8], pos: usize) -> Option<usize> {
    let len = usize::try_from(u64_at(bytes, pos + 1)?).ok()?;
    pos.checked_add(9)?.checked_add(len).filter(|&e| e <= bytes.len())
}

/// True when a record that a walk can go on from starts at `pos`: a chunk whose header adds up,
/// a metadata record that parses, the data-end record, or the footer before the closing magic.
fn sane_record_at(bytes: &[u8], pos: usize) -> bool {
    let Some(end) = record_end(bytes, pos) else { return false };
    let len = end - pos - 9;
    match bytes[pos] {
        op::CHUNK => chunk_header(bytes, pos).is_some_and(|h| {
            matches!(h.compression, b"zstd" | b"")
                && h.uncompressed_bytes <= MAX_RECORD_BYTES as u64
                && h.data_start.checked_add(h.compressed_bytes as usize) == Some(end)
        }),
        op::METADATA => mcap::parse_record(op::METADATA, &bytes[pos + 9..end]).is_ok(),
        op::DATA_END => len == 4,
        op::FOOTER => len == 20 && end + mcap::MAGIC.len() == bytes.len(),
        _ => false,
    }
}

/// The first chunk with a header that adds up starting in `from..to`.
fn chunk_within(bytes: &[u8], from: usize, to: usize) -> Option<usize> {
    (from..to).find(|&p| bytes[p] == op::CHUNK && sane_record_at(bytes, p))
}

/// The first position after `from` where a walk can go on.
fn resync(bytes: &[u8], from: usize) -> Option<usize> {
    const STARTS: [u8; 4] = [op::CHUNK, op::METADATA, op::DATA_END, op::FOOTER];
    (from..bytes.len().saturating_sub(8)).find(|&p| STARTS.contains(&bytes[p]) && sane_record_at(bytes, p))
}

/// What decompressing a chunk's data gave.
struct Inflated {
    /// The zstd frame ended (else the data ran out first, or zstd refused it).
    complete: bool,
    /// Compressed bytes used.
    consumed: usize,
    /// zstd's complaint, if any.
    error: Option<String>,
}

/// Decompresses the zstd frame at the start of `data` into `out` (at most
/// [`MAX_RECORD_BYTES`]), keeping what it gives before the data runs out or goes wrong.
fn inflate(zstd: &mut Decoder<'static>, data: &[u8], out: &mut Vec<u8>) -> Inflated {
    out.clear();
    let mut input = InBuffer::around(data);
    let result = zstd.reinit().and_then(|()| inflate_into(zstd, &mut input, out));
    out.truncate(MAX_RECORD_BYTES);
    match result {
        Ok(complete) => Inflated { complete, consumed: input.pos(), error: None },
        Err(e) => Inflated { complete: false, consumed: input.pos(), error: Some(e.to_string()) },
    }
}

/// [`inflate`]'s loop: `Ok(true)` when the frame ended.
fn inflate_into(zstd: &mut Decoder<'static>, input: &mut InBuffer<'_>, out: &mut Vec<u8>) -> std::io::Result<bool> {
    const STEP: usize = 1 << 17;
    loop {
        if out.capacity() - out.len() < STEP {
            if out.len() >= MAX_RECORD_BYTES {
                return Ok(false);
            }
            out.reserve(STEP);
        }
        let (before_in, before_out) = (input.pos(), out.len());
        let hint = zstd.run(input, &mut OutBuffer::around_pos(out, before_out))?;
        if hint == 0 {
            return Ok(true);
        }
        if input.pos() == before_in && out.len() == before_out {
            return Ok(false);
        }
    }
}

/// Hands each whole record of `records` (a chunk's content) to `visit`; returns the records
/// and messages handed and the bytes they cover.
fn visit_records(records: &[u8], visit: &mut dyn FnMut(u8, &[u8])) -> (usize, usize, usize) {
    let (mut pos, mut count, mut messages) = (0usize, 0usize, 0usize);
    while let Some(end) = record_end(records, pos) {
        visit(records[pos], &records[pos + 9..end]);
        count += 1;
        messages += usize::from(records[pos] == op::MESSAGE);
        pos = end;
    }
    (count, messages, pos)
}

/// The schema and channel records of the summary, when the file ends with its footer and the
/// summary matches the footer's CRC; returns a warning when it does not (then it is not used).
fn summary_records(bytes: &[u8], visit: &mut dyn FnMut(u8, &[u8])) -> Option<String> {
    let magic = mcap::MAGIC.len();
    let footer = bytes.len().checked_sub(magic + 29)?;
    if footer < magic
        || !bytes.ends_with(mcap::MAGIC)
        || bytes[footer] != op::FOOTER
        || u64_at(bytes, footer + 1) != Some(20)
    {
        return None;
    }
    let start =
        u64_at(bytes, footer + 9).and_then(|s| usize::try_from(s).ok()).filter(|&s| s >= magic && s < footer)?;
    // the CRC covers the summary and the footer up to the CRC itself
    let crc = u32_at(bytes, footer + 25)?;
    if crc != 0 && crc32fast::hash(&bytes[start..footer + 25]) != crc {
        return Some(format!(
            "the summary (at byte {start}) does not match its CRC: its schemas and channels were not used"
        ));
    }
    let summary = &bytes[start..footer];
    let mut pos = 0;
    while let Some(end) = record_end(summary, pos) {
        if matches!(summary[pos], op::SCHEMA | op::CHANNEL) {
            visit(summary[pos], &summary[pos + 9..end]);
        }
        pos = end;
    }
    None
}

/// Walks `bytes` (a file that starts with the MCAP magic). See the module docs.
pub fn walk_recording(bytes: &[u8], visit: &mut dyn FnMut(u8, &[u8])) -> Walked {
    let mut w = Walked::default();
    w.warnings.extend(summary_records(bytes, visit));
    let mut zstd = Decoder::new().ok();
    let mut records = Vec::new();
    let mut pos = mcap::MAGIC.len();
    let mut in_summary = false;
    loop {
        if pos >= bytes.len() {
            w.truncated = true;
            w.warnings.push(format!(
                "the file has no footer (cut short at a record boundary after {} bytes); read every record it holds",
                bytes.len()
            ));
            break;
        }
        let Some(len) = u64_at(bytes, pos + 1) else {
            w.truncated = true;
            w.warnings.push(format!("the file is cut short inside a record header at byte {pos} of {}", bytes.len()));
            break;
        };
        let opcode = bytes[pos];
        let end = record_end(bytes, pos);
        let next = match (opcode, end) {
            (op::CHUNK, _) => chunk(bytes, pos, end, zstd.as_mut(), &mut records, &mut w, visit),
            (_, None) => skip_damaged(
                bytes,
                pos,
                &format!("a record (opcode {opcode:#04x}) of {len} bytes, past the end of the file,"),
                &mut w,
            ),
            (op::FOOTER, Some(end)) if end + mcap::MAGIC.len() == bytes.len() => {
                w.saw_footer = true;
                None
            }
            (_, Some(end)) if let Some(hidden) = chunk_within(bytes, pos + 1, end) => {
                // a damaged length or opcode made this record swallow a chunk
                damage(
                    &mut w,
                    pos,
                    format!(
                        "a record (opcode {opcode:#04x}) at byte {pos} of {len} bytes covers the chunk at byte {hidden}: a damaged header, skipped to that chunk"
                    ),
                );
                Some(hidden)
            }
            (_, Some(end)) => {
                if opcode == op::DATA_END {
                    in_summary = true;
                    let saved = u32_at(bytes, pos + 9).unwrap_or(0);
                    if saved != 0 && crc32fast::hash(&bytes[..pos]) != saved {
                        w.warnings.push(format!(
                            "the data section's CRC (at byte {pos}) does not match: the file was changed after it was written (each chunk is checked by its own CRC)"
                        ));
                    }
                } else if !in_summary || matches!(opcode, op::SCHEMA | op::CHANNEL) {
                    visit(opcode, &bytes[pos + 9..end]);
                    w.records += 1;
                }
                Some(end)
            }
        };
        match next {
            Some(n) => pos = n,
            None => break,
        }
    }
    w
}

/// A record at `pos` that cannot be read (its length runs past the end of the file, or a chunk
/// header does not add up): the walk goes on at the next sane record (it was damaged) or ends
/// (the file is cut short).
fn skip_damaged(bytes: &[u8], pos: usize, what: &str, w: &mut Walked) -> Option<usize> {
    match resync(bytes, pos + 1) {
        Some(next) => {
            damage(
                w,
                pos,
                format!("{what} at byte {pos} cannot be read: skipped to the next whole record, at byte {next}"),
            );
            Some(next)
        }
        None => {
            w.truncated = true;
            damage(w, pos, format!("the file is cut short inside {what} at byte {pos} of {}", bytes.len()));
            None
        }
    }
}

fn damage(w: &mut Walked, pos: usize, why: String) {
    if w.records == 0 && w.damaged_at_start.is_none() {
        w.damaged_at_start = Some((pos, why.clone()));
    }
    w.warnings.push(why);
}

/// The chunk record at `pos` (`end`: where its length says it ends, when inside the file):
/// its records go to `visit`; returns where the walk goes on (`None`: the file ends here).
///
/// A header that adds up is trusted for where the chunk ends. One that does not (damaged, or
/// cut short) is not: its zstd frame is decoded from the rest of the file, and the walk goes on
/// where the frame ends (when it matched its CRC), else at the next sane record.
fn chunk(
    bytes: &[u8],
    pos: usize,
    end: Option<usize>,
    zstd: Option<&mut Decoder<'static>>,
    records: &mut Vec<u8>,
    w: &mut Walked,
    visit: &mut dyn FnMut(u8, &[u8]),
) -> Option<usize> {
    let Some(h) = chunk_header(bytes, pos).filter(|h| h.data_start <= bytes.len()) else {
        return skip_damaged(bytes, pos, "a chunk with a damaged header", w);
    };
    let by_size = usize::try_from(h.compressed_bytes).ok().and_then(|c| h.data_start.checked_add(c));
    let whole = end.filter(|&e| {
        Some(e) == by_size && h.uncompressed_bytes <= MAX_RECORD_BYTES as u64 && matches!(h.compression, b"zstd" | b"")
    });
    let data = &bytes[h.data_start..whole.unwrap_or(bytes.len())];
    let inflated = match (h.compression, zstd) {
        (b"zstd", Some(zstd)) => inflate(zstd, data, records),
        (b"", _) if whole.is_some() => {
            records.clear();
            records.extend_from_slice(data);
            Inflated { complete: true, consumed: data.len(), error: None }
        }
        (name, _) => {
            let shown = String::from_utf8_lossy(name).chars().take(16).collect::<String>();
            let what = if matches!(name, b"zstd" | b"") {
                "a chunk with a damaged header".to_string()
            } else {
                format!("a chunk compressed with \"{shown}\" (PAROL6 Studio writes zstd only)")
            };
            return match end.filter(|&e| Some(e) == by_size) {
                Some(end) => {
                    damage(w, pos, format!("{what} at byte {pos}: skipped"));
                    Some(end)
                }
                None => skip_damaged(bytes, pos, &what, w),
            };
        }
    };
    // a frame that ends before the chunk's data does: the header's length lies (it would hide
    // the chunks after it)
    let whole = whole.filter(|_| !inflated.complete || inflated.consumed == data.len());
    // where the walk goes on when the chunk is done with
    let next = |complete: bool| match whole {
        Some(end) => Some(end),
        None if complete => Some(h.data_start + inflated.consumed),
        None => resync(bytes, pos + 1),
    };
    if inflated.complete {
        if h.crc != 0 && crc32fast::hash(records) != h.crc {
            damage(w, pos, format!("the chunk at byte {pos} is damaged (its CRC does not match): skipped"));
            return next(false);
        }
        let (n, _, _) = visit_records(records, visit);
        w.records += n;
        if whole.is_none() || records.len() as u64 != h.uncompressed_bytes {
            damage(
                w,
                pos,
                format!(
                    "the chunk at byte {pos} has a damaged header (its sizes do not add up); its records matched its CRC and were read"
                ),
            );
        }
        return next(true);
    }
    // cut short or damaged inside its data: keep every whole record decoded before
    let (n, messages, kept) = visit_records(records, visit);
    w.records += n;
    // the data ran out at the end of the file, and no sane record follows (else damaged data
    // made zstd wait for more: the walk goes on there)
    let cut = whole.is_none()
        && inflated.error.is_none()
        && inflated.consumed == data.len()
        && resync(bytes, pos + 1).is_none();
    let lost = match usize::try_from(h.uncompressed_bytes) {
        Ok(size) if size <= MAX_RECORD_BYTES && size >= kept => format!("{} bytes of records", size - kept),
        _ => "the rest of its records (the chunk was still being written)".to_string(),
    };
    let why = format!(
        "{} inside the chunk at byte {pos}: kept the {messages} messages of its first {kept} bytes of records; lost {lost}",
        if cut { "the file is cut short" } else { "the data is damaged" },
    );
    if cut {
        w.truncated = true;
        damage(w, pos, why);
        return None;
    }
    damage(w, pos, format!("{why}{}", inflated.error.map(|e| format!(" (zstd: {e})")).unwrap_or_default()));
    let next = next(false);
    if next.is_none() {
        w.truncated = true;
    }
    next
}

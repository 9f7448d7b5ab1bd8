//! Parallel decoding of a whole recording's chunks: the fast path of [`super::replay`].
//!
//! [`decode_chunks`] takes the file's top-level records from a [`RecordSource`] (a file read
//! piece by piece, [`FileSource`], or bytes in memory, [`SliceSource`]), learns the channels
//! from the first chunk, then decompresses the zstd chunks on up to [`MAX_THREADS`] threads
//! while the source goes on reading, and hands each message to a decoder with its topic; the
//! results come back in file order. The data section's CRC is checked over every byte read
//! (it covers the compressed chunks, so their own CRCs need no second check).
//!
//! It takes only files it can read completely. Anything else (a file cut short or damaged, a
//! chunk that is not zstd, messages outside chunks, a channel first defined after the first
//! chunk) answers [`NotFast`] with the reason, and the caller reads the file with the linear
//! reader ([`super::reader`]), which reads what it can and names the problem.

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::io::Read;

use crossbeam_channel::bounded;
use mcap::records::{Record, op};

use super::reader::TopicStats;
use super::schema;

/// Most threads a file is decoded on.
pub const MAX_THREADS: usize = 4;

/// Largest record accepted, a decompressed chunk included (our chunks close at 8 MiB).
const MAX_RECORD_BYTES: u64 = 64 << 20;

/// Channel ids above this are left to the linear reader (ours count from 1).
const MAX_CHANNELS: usize = 1024;

/// Compressed chunk bytes handed to a decoding thread at a time (one chunk or more).
const BATCH_BYTES: usize = 128 << 10;

/// Most decode warnings kept.
const MAX_WARNINGS: usize = 20;

/// Why a file is left to the linear reader.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NotFast(pub String);

fn not_fast(why: impl Into<String>) -> NotFast {
    NotFast(why.into())
}

/// A top-level record the decoder needs, in file order.
#[derive(Debug)]
pub enum TopRecord<'a> {
    /// A chunk record's body.
    Chunk(Cow<'a, [u8]>),
    /// A metadata record's body.
    Metadata(Cow<'a, [u8]>),
}

/// Where the top-level records come from.
pub trait RecordSource<'a> {
    /// The next chunk or metadata record; `None` once the data section has ended, the data
    /// section's CRC matched and the file is whole (footer and closing magic).
    fn next_record(&mut self) -> Result<Option<TopRecord<'a>>, NotFast>;
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at.checked_add(8)?)?.try_into().ok()?))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at.checked_add(4)?)?.try_into().ok()?))
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(b.get(at..at.checked_add(2)?)?.try_into().ok()?))
}

/// What a top-level record means to the decoder: keep it, skip it, the data section ended.
enum Kind {
    Chunk,
    Metadata,
    Skip,
    DataEnd,
}

fn kind(opcode: u8) -> Result<Kind, NotFast> {
    match opcode {
        op::CHUNK => Ok(Kind::Chunk),
        op::METADATA => Ok(Kind::Metadata),
        op::DATA_END => Ok(Kind::DataEnd),
        op::MESSAGE | op::CHANNEL | op::SCHEMA => Err(not_fast("records outside chunks")),
        op::FOOTER => Err(not_fast("no data-end record")),
        _ => Ok(Kind::Skip),
    }
}

/// The data section's CRC must be there (the chunks' own CRCs are not checked on this path)
/// and match.
fn check_data_crc(saved: u32, computed: impl FnOnce() -> u32) -> Result<(), NotFast> {
    match saved {
        0 => Err(not_fast("no CRC of the data section")),
        saved if computed() != saved => Err(not_fast("the data section's CRC does not match")),
        _ => Ok(()),
    }
}

/// The records of a whole file in memory.
#[derive(Debug)]
pub struct SliceSource<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> SliceSource<'a> {
    /// Walks `bytes` (the whole file).
    pub fn new(bytes: &'a [u8]) -> Result<Self, NotFast> {
        if !bytes.starts_with(mcap::MAGIC) || bytes.len() < 2 * mcap::MAGIC.len() || !bytes.ends_with(mcap::MAGIC) {
            return Err(not_fast("the file does not end with the MCAP magic (cut short?)"));
        }
        Ok(Self { bytes, pos: mcap::MAGIC.len() })
    }
}

impl<'a> RecordSource<'a> for SliceSource<'a> {
    fn next_record(&mut self) -> Result<Option<TopRecord<'a>>, NotFast> {
        let bytes = self.bytes;
        loop {
            let at = self.pos;
            let (Some(&opcode), Some(len)) = (bytes.get(at), u64_at(bytes, at + 1)) else {
                return Err(not_fast("no data-end record"));
            };
            let end = usize::try_from(len)
                .ok()
                .and_then(|l| (at + 9).checked_add(l))
                .filter(|&e| e <= bytes.len())
                .ok_or_else(|| not_fast("a record runs past the end of the file"))?;
            let body = &bytes[at + 9..end];
            self.pos = end;
            match kind(opcode)? {
                Kind::Chunk => return Ok(Some(TopRecord::Chunk(Cow::Borrowed(body)))),
                Kind::Metadata => return Ok(Some(TopRecord::Metadata(Cow::Borrowed(body)))),
                Kind::Skip => {}
                Kind::DataEnd => {
                    // the CRC covers the file from its first byte up to this record
                    check_data_crc(u32_at(body, 0).unwrap_or(0), || crc32fast::hash(&bytes[..at]))?;
                    return Ok(None);
                }
            }
        }
    }
}

/// The records of a file read piece by piece (each record read whole into its own buffer),
/// hashing what it reads for the data section's CRC.
#[derive(Debug)]
pub struct FileSource<R: Read> {
    reader: R,
    crc: crc32fast::Hasher,
    /// Bytes the file holds (for the records' lengths and the closing magic).
    len: u64,
    pos: u64,
}

impl<R: Read> FileSource<R> {
    /// Reads from `reader`, a file of `len` bytes; checks its opening magic.
    pub fn new(mut reader: R, len: u64) -> Result<Self, NotFast> {
        let mut magic = [0u8; 8];
        reader.read_exact(&mut magic).map_err(|e| not_fast(format!("cannot read: {e}")))?;
        if magic != *mcap::MAGIC {
            return Err(not_fast("not MCAP"));
        }
        let mut crc = crc32fast::Hasher::new();
        crc.update(&magic);
        Ok(Self { reader, crc, len, pos: 8 })
    }

    fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), NotFast> {
        self.reader.read_exact(buf).map_err(|e| not_fast(format!("read stopped at byte {}: {e}", self.pos)))?;
        self.pos += buf.len() as u64;
        Ok(())
    }
}

impl<R: Read> RecordSource<'static> for FileSource<R> {
    fn next_record(&mut self) -> Result<Option<TopRecord<'static>>, NotFast> {
        loop {
            let mut head = [0u8; 9];
            self.read_exact(&mut head)?;
            let len = u64_at(&head, 1).unwrap_or(u64::MAX);
            if len > MAX_RECORD_BYTES || self.pos.saturating_add(len) > self.len {
                return Err(not_fast("a record runs past the end of the file"));
            }
            let mut body = vec![0u8; len as usize];
            self.read_exact(&mut body)?;
            let hashed_before = self.crc.clone();
            self.crc.update(&head);
            self.crc.update(&body);
            match kind(head[0])? {
                Kind::Chunk => return Ok(Some(TopRecord::Chunk(Cow::Owned(body)))),
                Kind::Metadata => return Ok(Some(TopRecord::Metadata(Cow::Owned(body)))),
                Kind::Skip => {}
                Kind::DataEnd => {
                    check_data_crc(u32_at(&body, 0).unwrap_or(0), || hashed_before.finalize())?;
                    // the summary and the footer: the file must end with the closing magic
                    let mut rest = Vec::new();
                    self.reader.read_to_end(&mut rest).map_err(|e| not_fast(format!("cannot read: {e}")))?;
                    if !rest.ends_with(mcap::MAGIC) || self.pos + rest.len() as u64 != self.len {
                        return Err(not_fast("the file does not end with the MCAP magic (cut short?)"));
                    }
                    return Ok(None);
                }
            }
        }
    }
}

/// A message handed to the decoder.
#[derive(Debug, Clone, Copy)]
pub struct MessageRef<'a> {
    /// Its channel's topic.
    pub topic: &'a str,
    /// Its log time, Unix ns.
    pub log_time_ns: u64,
    /// Its bytes (JSON for our channels).
    pub data: &'a [u8],
}

/// Decodes the messages of one chunk, in order, into one output.
pub trait ChunkDecoder {
    /// What a chunk gives.
    type Out: Send;
    /// The chunk's next message; an `Err` is a warning (the message is skipped).
    fn message(&mut self, m: MessageRef<'_>) -> Result<(), String>;
    /// After the chunk's last message.
    fn finish(self) -> Self::Out;
}

/// What [`decode_chunks`] read.
#[derive(Debug, Clone)]
pub struct Chunked<T> {
    /// The decoders' outputs, one per chunk, in file order.
    pub outputs: Vec<T>,
    /// The metadata record of ours (app version, robot, tool, program, joints).
    pub metadata: BTreeMap<String, String>,
    /// Per topic, every message counted.
    pub topics: BTreeMap<String, TopicStats>,
    /// First and last message log time, Unix ns.
    pub span_ns: Option<(u64, u64)>,
    /// Messages a decoder refused, with why (at most 20).
    pub warnings: Vec<String>,
    /// Chunks decoded.
    pub chunks: usize,
    /// Threads they were decoded on.
    pub threads: usize,
}

/// A chunk record's body → its decompressed records (checked against the chunk's CRC when
/// `check_crc`: the first chunk, read before the data section's CRC is known).
fn decompress_chunk(
    body: &[u8],
    zstd: &mut zstd::bulk::Decompressor<'_>,
    out: &mut Vec<u8>,
    check_crc: bool,
) -> Result<(), String> {
    // message start and end time, uncompressed size, uncompressed CRC, compression, records
    let short = || "short chunk header".to_string();
    let size = u64_at(body, 16).ok_or_else(short)?;
    let crc = u32_at(body, 24).ok_or_else(short)?;
    let name_len = u32_at(body, 28).and_then(|n| usize::try_from(n).ok()).ok_or_else(short)?;
    let name_end = 32usize.checked_add(name_len).filter(|&e| e <= body.len()).ok_or_else(short)?;
    if &body[32..name_end] != b"zstd" {
        return Err("a chunk that is not zstd-compressed".into());
    }
    let records_len = u64_at(body, name_end).and_then(|n| usize::try_from(n).ok()).ok_or_else(short)?;
    let records = body.get(name_end + 8..).filter(|r| r.len() == records_len).ok_or("chunk sizes do not add up")?;
    if size > MAX_RECORD_BYTES {
        return Err(format!("a chunk of {size} bytes uncompressed"));
    }
    out.clear();
    out.reserve(size as usize);
    let n = zstd.decompress_to_buffer(records, out).map_err(|e| format!("zstd: {e}"))?;
    if n as u64 != size {
        return Err(format!("a chunk decompressed to {n} bytes, not {size}"));
    }
    if check_crc && crc != 0 && crc32fast::hash(out) != crc {
        return Err("a chunk's CRC does not match".into());
    }
    Ok(())
}

/// Walks the records of `records` (opcode, length, body), calling `f(opcode, body)` until it
/// answers `false`; `None` when a record overruns.
fn walk<'a>(records: &'a [u8], mut f: impl FnMut(u8, &'a [u8]) -> bool) -> Option<()> {
    let mut pos = 0usize;
    while pos < records.len() {
        let opcode = *records.get(pos)?;
        let len = usize::try_from(u64_at(records, pos + 1)?).ok()?;
        let end = (pos + 9).checked_add(len).filter(|&e| e <= records.len())?;
        if !f(opcode, &records[pos + 9..end]) {
            return Some(());
        }
        pos = end;
    }
    Some(())
}

/// A decoding thread's chunks: (index in the file, what it gave).
type Decoded<T> = Vec<(usize, ChunkOut<T>)>;

/// What one chunk gave.
struct ChunkOut<T> {
    out: T,
    counts: HashMap<u16, u64>,
    span_ns: Option<(u64, u64)>,
    warnings: Vec<String>,
}

fn decode_one<D: ChunkDecoder>(records: &[u8], topics: &Topics, mut decoder: D) -> Result<ChunkOut<D::Out>, String> {
    let mut counts = HashMap::new();
    let mut span_ns: Option<(u64, u64)> = None;
    let mut warnings = Vec::new();
    let mut problem = None;
    walk(records, |opcode, body| {
        if opcode == op::CHANNEL {
            // a channel defined again must say what the first chunk said
            if let Ok(Record::Channel(c)) = mcap::parse_record(opcode, body)
                && topics.get(c.id) != Some(c.topic.as_str())
            {
                problem = Some(format!("channel {} is first defined after the first chunk", c.id));
            }
            return problem.is_none();
        }
        if opcode != op::MESSAGE {
            return true;
        }
        // channel id, sequence, log time, publish time, data
        let (Some(channel), Some(log_time_ns), Some(data)) = (u16_at(body, 0), u64_at(body, 6), body.get(22..)) else {
            problem = Some("a message record too short for its header".into());
            return false;
        };
        let Some(topic) = topics.get(channel) else {
            problem = Some(format!("a message on unknown channel {channel}"));
            return false;
        };
        *counts.entry(channel).or_insert(0) += 1;
        span_ns = Some(match span_ns {
            None => (log_time_ns, log_time_ns),
            Some((a, b)) => (a.min(log_time_ns), b.max(log_time_ns)),
        });
        if let Err(why) = decoder.message(MessageRef { topic, log_time_ns, data })
            && warnings.len() < MAX_WARNINGS
        {
            warnings.push(format!("a {topic} message is not valid: {why}"));
        }
        true
    })
    .ok_or_else(|| "a record runs past the end of its chunk".to_string())?;
    match problem {
        Some(why) => Err(why),
        None => Ok(ChunkOut { out: decoder.finish(), counts, span_ns, warnings }),
    }
}

/// Channel id → topic (our channel ids are small: a table, not a hash map).
#[derive(Debug, Default)]
struct Topics(Vec<Option<String>>);

impl Topics {
    fn get(&self, channel: u16) -> Option<&str> {
        self.0.get(usize::from(channel)).and_then(Option::as_deref)
    }
}

/// Channel id → topic, from the channel records of the first chunk.
fn channels(first_chunk: &[u8]) -> Result<Topics, NotFast> {
    let mut zstd = zstd::bulk::Decompressor::new().map_err(|e| not_fast(format!("zstd: {e}")))?;
    let mut records = Vec::new();
    decompress_chunk(first_chunk, &mut zstd, &mut records, true).map_err(NotFast)?;
    let mut ids = Topics::default();
    let mut problem = None;
    walk(&records, |opcode, body| {
        if opcode == op::CHANNEL
            && let Ok(Record::Channel(c)) = mcap::parse_record(opcode, body)
        {
            let at = usize::from(c.id);
            if at >= MAX_CHANNELS {
                problem = Some(format!("channel id {at}"));
                return false;
            }
            if ids.0.len() <= at {
                ids.0.resize(at + 1, None);
            }
            ids.0[at] = Some(c.topic);
        }
        true
    })
    .ok_or_else(|| not_fast("a record runs past the end of the first chunk"))?;
    problem.map_or(Ok(ids), |why| Err(not_fast(why)))
}

/// Decodes every message of the whole recording that `source` reads, on up to `threads`
/// threads (at most [`MAX_THREADS`]) besides the one reading: each chunk gets a decoder from
/// `decoder()`, which sees the chunk's messages in order. See the module docs.
pub fn decode_chunks<'a, D: ChunkDecoder>(
    mut source: impl RecordSource<'a>,
    threads: usize,
    decoder: impl Fn() -> D + Sync,
) -> Result<Chunked<D::Out>, NotFast> {
    let mut metadata: Vec<Cow<'a, [u8]>> = Vec::new();
    let first = loop {
        match source.next_record()? {
            Some(TopRecord::Chunk(body)) => break body,
            Some(TopRecord::Metadata(body)) => metadata.push(body),
            None => return Err(not_fast("no chunks")),
        }
    };
    let topics = channels(&first)?;
    let threads = threads.clamp(1, MAX_THREADS);
    let (to_workers, work) = bounded::<Vec<(usize, Cow<'a, [u8]>)>>(4 * threads);
    let (read, results) = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                let work = work.clone();
                let (topics, decoder) = (&topics, &decoder);
                s.spawn(move || -> Result<Decoded<D::Out>, String> {
                    let mut zstd = zstd::bulk::Decompressor::new().map_err(|e| format!("zstd: {e}"))?;
                    let mut records = Vec::new();
                    let mut done = Vec::new();
                    for (i, body) in work.into_iter().flatten() {
                        decompress_chunk(&body, &mut zstd, &mut records, false)?;
                        done.push((i, decode_one(&records, topics, decoder())?));
                    }
                    Ok(done)
                })
            })
            .collect();
        drop(work);
        let mut chunks = 0usize;
        let mut read = Ok(());
        let mut next = Some(first);
        // small chunks (0.25 s at 100 Hz is ~20 kB) go in batches: a hand-over wakes a thread,
        // which costs tens of µs on a virtual machine
        let mut batch = Vec::new();
        let mut batch_bytes = 0usize;
        while let Some(body) = next.take() {
            batch_bytes += body.len();
            batch.push((chunks, body));
            chunks += 1;
            next = loop {
                match source.next_record() {
                    Ok(Some(TopRecord::Chunk(body))) => break Some(body),
                    Ok(Some(TopRecord::Metadata(body))) => metadata.push(body),
                    Ok(None) => break None,
                    Err(e) => {
                        read = Err(e);
                        break None;
                    }
                }
            };
            if (batch_bytes >= BATCH_BYTES || next.is_none()) && to_workers.send(std::mem::take(&mut batch)).is_err() {
                break;
            }
            if batch.is_empty() {
                batch_bytes = 0;
            }
        }
        drop(to_workers);
        let results: Vec<_> =
            workers.into_iter().map(|w| w.join().unwrap_or_else(|_| Err("a decoding thread failed".into()))).collect();
        (read.map(|()| chunks), results)
    });
    let chunks = read?;
    let mut per_chunk: Vec<Option<ChunkOut<D::Out>>> = (0..chunks).map(|_| None).collect();
    for result in results {
        for (i, out) in result.map_err(NotFast)? {
            if let Some(slot) = per_chunk.get_mut(i) {
                *slot = Some(out);
            }
        }
    }
    let mut read = Chunked {
        outputs: Vec::with_capacity(chunks),
        metadata: BTreeMap::new(),
        topics: BTreeMap::new(),
        span_ns: None,
        warnings: Vec::new(),
        chunks,
        threads,
    };
    let mut counts: HashMap<u16, u64> = HashMap::new();
    for out in per_chunk.into_iter().flatten() {
        read.outputs.push(out.out);
        for (channel, n) in out.counts {
            *counts.entry(channel).or_insert(0) += n;
        }
        read.span_ns = match (read.span_ns, out.span_ns) {
            (Some((a, b)), Some((c, d))) => Some((a.min(c), b.max(d))),
            (a, b) => a.or(b),
        };
        read.warnings.extend(out.warnings);
    }
    read.warnings.truncate(MAX_WARNINGS);
    for (channel, n) in counts {
        if let Some(topic) = topics.get(channel) {
            read.topics.entry(topic.to_string()).or_default().messages += n;
        }
    }
    for body in &metadata {
        if let Ok(Record::Metadata(m)) = mcap::parse_record(op::METADATA, body)
            && m.name == schema::METADATA_NAME
        {
            read.metadata = m.metadata;
        }
    }
    Ok(read)
}

//! Files in and out, safely: the one atomic writer and the bounded regular-file reader.
//!
//! Every file the program writes (programs, G-code, CSV, reports, PNG, SVG, settings, bench
//! output) goes through [`write_atomic`] /
//! [`write_atomic_bytes`]: the bytes go to a temporary file beside the target, which is
//! fsynced and then renamed over the target. A failed save (full disk, I/O error, an error
//! of the caller's encoder, a failed rename) removes the temporary file and leaves the old
//! file exactly as it was; a target that exists and is not a regular file (a directory, a
//! FIFO, a device node such as `/dev/full`) is refused, never replaced. A symbolic link to a
//! regular file is followed: the file it points to is replaced and the link stays. MCAP
//! recordings are streamed as they are made, so they cannot be written whole at the end: a new
//! one is written in place, and one over an existing file goes beside it and replaces it when
//! finished (`telemetry::writer::McapSink::create_file`, with the same refusal by file type).
//!
//! Every file the program reads from outside goes through [`open_regular`] /
//! [`read_regular_bounded`]: FIFOs, devices, sockets and directories are refused by file type
//! before the open (a FIFO would block the open, `/dev/zero` would never end), the open
//! itself cannot block (`O_NONBLOCK`) and the type is checked again on the open handle, and
//! at most `max_bytes` are read even where the file's metadata says otherwise.

use std::fs::{File, Metadata, OpenOptions};
use std::io::{self, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Why a file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum FsioError {
    /// The path exists but is not a regular file (a directory, FIFO, device or socket).
    #[error("{path}: refused, it is {kind}, not a regular file", path = .path.display())]
    NotRegular {
        /// The path as given.
        path: PathBuf,
        /// What it is instead ("a FIFO", "a character device", …).
        kind: &'static str,
    },
    /// The file holds more than the bound for its kind.
    #[error("{path}: refused, it is larger than {max_bytes} bytes", path = .path.display())]
    TooLarge {
        /// The path as given.
        path: PathBuf,
        /// The bound, bytes.
        max_bytes: u64,
    },
    /// The file could not be opened or read.
    #[error("cannot read {path}: {source}", path = .path.display())]
    Read {
        /// The path as given.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// The file could not be written; nothing was replaced and no temporary file is left.
    #[error("cannot write {path}: {source} (nothing was replaced)", path = .path.display())]
    Write {
        /// The path as given.
        path: PathBuf,
        /// The I/O error (of the disk, or of the caller's encoder).
        source: io::Error,
    },
}

impl FsioError {
    /// The I/O error underneath, where there is one.
    pub fn io_error(&self) -> Option<&io::Error> {
        match self {
            FsioError::Read { source, .. } | FsioError::Write { source, .. } => Some(source),
            FsioError::NotRegular { .. } | FsioError::TooLarge { .. } => None,
        }
    }

    /// Whether the request itself was refused (not a regular file, too large), as opposed to
    /// an I/O failure of the disk.
    pub fn is_refusal(&self) -> bool {
        matches!(self, FsioError::NotRegular { .. } | FsioError::TooLarge { .. })
    }
}

/// What a path is, in words, when it is not a regular file.
fn kind_of(meta: &Metadata) -> Option<&'static str> {
    let t = meta.file_type();
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a regular file")
}

/// The metadata of `path` (symbolic links followed) if it is a regular file; FIFOs, devices,
/// sockets and directories are [`FsioError::NotRegular`]. Nothing is opened.
pub fn check_regular(path: &Path) -> Result<Metadata, FsioError> {
    let meta = std::fs::metadata(path).map_err(|source| FsioError::Read { path: path.to_path_buf(), source })?;
    match kind_of(&meta) {
        Some(kind) => Err(FsioError::NotRegular { path: path.to_path_buf(), kind }),
        None => Ok(meta),
    }
}

/// Opens `path` for reading if it is a regular file (symbolic links followed). FIFOs,
/// devices, sockets and directories are refused by their type before the open; the open does
/// not block and the type is checked again on the open handle.
pub fn open_regular(path: &Path) -> Result<File, FsioError> {
    let read_err = |source| FsioError::Read { path: path.to_path_buf(), source };
    check_regular(path)?;
    let mut options = OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Swapped for a FIFO between the check and the open, the open must not block.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path).map_err(read_err)?;
    let meta = file.metadata().map_err(read_err)?;
    if let Some(kind) = kind_of(&meta) {
        return Err(FsioError::NotRegular { path: path.to_path_buf(), kind });
    }
    Ok(file)
}

/// Reads the whole regular file `path`, refusing it ([`FsioError::TooLarge`]) when it holds
/// more than `max_bytes`. At most `max_bytes + 1` bytes are ever read, whatever the file's
/// metadata says.
pub fn read_regular_bounded(path: &Path, max_bytes: u64) -> Result<Vec<u8>, FsioError> {
    let file = open_regular(path)?;
    let hint = file.metadata().map(|m| m.len().min(max_bytes)).unwrap_or(0);
    let mut bytes = Vec::with_capacity(usize::try_from(hint).unwrap_or(0));
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|source| FsioError::Read { path: path.to_path_buf(), source })?;
    if bytes.len() as u64 > max_bytes {
        return Err(FsioError::TooLarge { path: path.to_path_buf(), max_bytes });
    }
    Ok(bytes)
}

/// [`read_regular_bounded`] as UTF-8 text; text that is not UTF-8 is a
/// [`FsioError::Read`] of kind `InvalidData` naming the byte offset.
pub fn read_regular_bounded_string(path: &Path, max_bytes: u64) -> Result<String, FsioError> {
    let bytes = read_regular_bounded(path, max_bytes)?;
    String::from_utf8(bytes).map_err(|e| FsioError::Read {
        path: path.to_path_buf(),
        source: io::Error::new(
            io::ErrorKind::InvalidData,
            format!("not UTF-8 text (invalid byte at offset {})", e.utf8_error().valid_up_to()),
        ),
    })
}

/// Failures to inject into [`write_atomic_with_faults`], for tests and the fuzz target.
/// [`Faults::default`] injects nothing (what [`write_atomic`] uses).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Faults {
    /// Each `write` call to the temporary file takes at most this many bytes (short writes).
    pub max_write_bytes: Option<usize>,
    /// The disk is full (ENOSPC) once this many bytes have reached the temporary file.
    pub enospc_at_byte: Option<u64>,
    /// The fsync of the temporary file fails (EIO).
    pub fail_sync: bool,
    /// The rename over the target fails (EIO).
    pub fail_rename: bool,
}

/// Writes the file `path` atomically: `fill` writes the whole content into a temporary file
/// beside it, which is fsynced and renamed over `path`. On any failure (`fill`'s own error
/// included) the temporary file is removed and `path` is left as it was. A `path` that exists
/// and is not a regular file is refused; a new file gets the old one's permissions.
pub fn write_atomic<F>(path: &Path, fill: F) -> Result<(), FsioError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    write_atomic_with_faults(path, Faults::default(), fill)
}

/// A writer that can also seek, for [`write_atomic_seekable`].
pub trait WriteSeek: Write + Seek {}

impl<T: Write + Seek + ?Sized> WriteSeek for T {}

/// [`write_atomic`] for formats whose writer seeks back (an MCAP file written as it is made,
/// its summary offsets filled in at the end).
pub fn write_atomic_seekable<F>(path: &Path, fill: F) -> Result<(), FsioError>
where
    F: FnOnce(&mut dyn WriteSeek) -> io::Result<()>,
{
    write_atomic_inner(path, Faults::default(), |w| fill(w))
}

/// [`write_atomic`] of `bytes`.
pub fn write_atomic_bytes(path: &Path, bytes: &[u8]) -> Result<(), FsioError> {
    write_atomic(path, |w| w.write_all(bytes))
}

/// Removes the temporary file when dropped unless disarmed (after the rename): every early
/// return and a panic in the caller's `fill` leave no temporary file.
struct TempGuard {
    path: Option<PathBuf>,
}

impl Drop for TempGuard {
    fn drop(&mut self) {
        if let Some(p) = self.path.take() {
            // Cleanup after a failure: that first error is the one reported, and nothing more
            // can be done about a temporary file that cannot be removed.
            match std::fs::remove_file(&p) {
                Ok(()) | Err(_) => {}
            }
        }
    }
}

/// A writer that injects [`Faults`] (short writes, a full disk) on the way to the file.
struct FaultyWriter {
    file: File,
    written_bytes: u64,
    faults: Faults,
}

impl Seek for FaultyWriter {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.file.seek(pos)
    }
}

impl Write for FaultyWriter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let mut n = buf.len();
        if let Some(max) = self.faults.max_write_bytes {
            n = n.min(max.max(1));
        }
        if let Some(full) = self.faults.enospc_at_byte {
            let room = full.saturating_sub(self.written_bytes);
            if room == 0 && n > 0 {
                return Err(io::Error::from_raw_os_error(libc::ENOSPC));
            }
            n = n.min(usize::try_from(room).unwrap_or(usize::MAX));
        }
        let n = self.file.write(&buf[..n])?;
        self.written_bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// The target to replace: `path`, or the file a symbolic link there points to.
fn resolve_target(path: &Path) -> PathBuf {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
        _ => path.to_path_buf(),
    }
}

/// Creates a new temporary file beside `target` (hidden, named after it, never one that exists).
fn create_temp(target: &Path) -> io::Result<(PathBuf, File)> {
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = target
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path names no file"))?
        .to_string_lossy()
        .into_owned();
    let mut last = io::Error::from(io::ErrorKind::AlreadyExists);
    for _ in 0..16 {
        let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(".{name}.{}-{n}.saving", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = e,
            Err(e) => return Err(e),
        }
    }
    Err(last)
}

/// [`write_atomic`] with `faults` injected into the writes, the fsync and the rename.
pub fn write_atomic_with_faults<F>(path: &Path, faults: Faults, fill: F) -> Result<(), FsioError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    write_atomic_inner(path, faults, |w| fill(w))
}

/// The one implementation behind the `write_atomic*` functions.
fn write_atomic_inner<F>(path: &Path, faults: Faults, fill: F) -> Result<(), FsioError>
where
    F: FnOnce(&mut BufWriter<FaultyWriter>) -> io::Result<()>,
{
    let write_err = |source| FsioError::Write { path: path.to_path_buf(), source };
    let target = resolve_target(path);
    let old = match std::fs::metadata(&target) {
        Ok(meta) => {
            if let Some(kind) = kind_of(&meta) {
                return Err(FsioError::NotRegular { path: path.to_path_buf(), kind });
            }
            Some(meta)
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(write_err(e)),
    };
    let (tmp, file) = create_temp(&target).map_err(write_err)?;
    let mut guard = TempGuard { path: Some(tmp.clone()) };
    if let Some(meta) = &old {
        file.set_permissions(meta.permissions()).map_err(write_err)?;
    }
    let mut out = BufWriter::new(FaultyWriter { file, written_bytes: 0, faults });
    fill(&mut out).map_err(write_err)?;
    let file = out.into_inner().map_err(|e| write_err(e.into_error()))?.file;
    if faults.fail_sync {
        return Err(write_err(io::Error::from_raw_os_error(libc::EIO)));
    }
    file.sync_all().map_err(write_err)?;
    drop(file);
    if faults.fail_rename {
        return Err(write_err(io::Error::from_raw_os_error(libc::EIO)));
    }
    std::fs::rename(&tmp, &target).map_err(write_err)?;
    guard.path = None;
    // Make the rename itself durable. The new file is in place whatever this returns, so a
    // failure here is not a failed save.
    if let Some(dir) = target.parent().filter(|d| !d.as_os_str().is_empty()) {
        match File::open(dir).and_then(|d| d.sync_all()) {
            Ok(()) | Err(_) => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;

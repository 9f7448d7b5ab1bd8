//! The fake robot's link: a local (Unix-domain) stream socket instead of a pseudo-terminal.
//!
//! Why (issue 32): bytes written to a pty are handed to the reader by the kernel's tty
//! "flip buffer" work, which runs in a kworker thread at normal priority. On a host with both
//! cores busy (load 6–9 on 2 cores) that kworker waits behind the other processes, so the
//! session and the emulator — both real-time threads — wake in time but their bytes have not
//! arrived: round trips of 60–330 ms were measured (`examples/link_latency.rs`), and the session
//! rightly reported "link lost" every minute or so. A stream socket hands the bytes over in the
//! writer's own system call (no worker), so the emulated board keeps up like independent
//! hardware would. A real board's link (a character device) is untouched.
//!
//! [`SocketPort`] is the host side: a [`serialport::SerialPort`] over a [`UnixStream`], opened
//! by [`crate::ports::open_port`] when the port's path is a socket, so the session's open and
//! re-open rules stay the same. [`SocketServer`] is the emulator's side: it listens on a
//! private path (mode 0600, removed when dropped), serves the newest connection (a host that
//! re-opens the port replaces its old one; the board's state stays), and reads / writes like
//! the pty's master (a read with nothing to read is [`std::io::ErrorKind::TimedOut`]).

use std::io::{self, ErrorKind, Read, Write};
use std::os::fd::AsRawFd;
use std::os::unix::fs::{FileTypeExt, PermissionsExt};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use serialport::{ClearBuffer, DataBits, FlowControl, Parity, SerialPort, StopBits};

use crate::HwError;

/// How long the emulator waits for bytes per read (as on its pty).
const SERVER_READ_TIMEOUT: Duration = Duration::from_millis(2);
/// How long the emulator waits for a host that does not read its replies.
const SERVER_WRITE_TIMEOUT: Duration = Duration::from_millis(100);

/// True when `path` names a Unix-domain socket (the fake robot), not a serial device.
pub fn is_socket(path: &str) -> bool {
    std::fs::metadata(path).is_ok_and(|m| m.file_type().is_socket())
}

fn io_err(e: io::Error) -> serialport::Error {
    serialport::Error::new(serialport::ErrorKind::Io(e.kind()), e.to_string())
}

/// A read or write that found nothing in time is a timeout, as on a serial port.
fn timeout_kind(e: io::Error) -> io::Error {
    if e.kind() == ErrorKind::WouldBlock { io::Error::new(ErrorKind::TimedOut, e) } else { e }
}

/// Waits until `stream` is ready for `events` (`POLLIN` / `POLLOUT`) or `timeout` passed; false
/// on timeout. `ppoll` keeps the session's deadline to the microsecond: a socket's own timeout
/// (`SO_RCVTIMEO`) counts in scheduler ticks (4 ms at 250 Hz) and would make it wake late.
fn wait_ready(stream: &UnixStream, events: libc::c_short, timeout: Duration) -> io::Result<bool> {
    let mut fd = libc::pollfd { fd: stream.as_raw_fd(), events, revents: 0 };
    let rc = poll_one(&mut fd, timeout);
    if rc < 0 {
        let e = io::Error::last_os_error();
        return if e.kind() == ErrorKind::Interrupted { Ok(false) } else { Err(e) };
    }
    // readable, writable, or hung up / failed (the next read or write says which)
    Ok(rc > 0)
}

#[cfg(target_os = "linux")]
fn poll_one(fd: &mut libc::pollfd, timeout: Duration) -> libc::c_int {
    let spec = libc::timespec {
        tv_sec: libc::time_t::try_from(timeout.as_secs()).unwrap_or(libc::time_t::MAX),
        // below 10⁹: fits every c_long
        tv_nsec: timeout.subsec_nanos() as libc::c_long,
    };
    // SAFETY: one valid pollfd, a valid timespec, no signal mask.
    unsafe { libc::ppoll(fd, 1, &spec, std::ptr::null()) }
}

#[cfg(not(target_os = "linux"))]
fn poll_one(fd: &mut libc::pollfd, timeout: Duration) -> libc::c_int {
    let ms = timeout.as_micros().div_ceil(1000);
    // SAFETY: one valid pollfd.
    unsafe { libc::poll(fd, 1, libc::c_int::try_from(ms).unwrap_or(libc::c_int::MAX)) }
}

/// Number of bytes the socket holds, from `ioctl(request)`.
fn queued_bytes(stream: &UnixStream, request: libc::c_ulong) -> serialport::Result<u32> {
    let mut n: libc::c_int = 0;
    // SAFETY: the descriptor is open (owned by `stream`); `n` is a valid c_int for the result.
    let rc = unsafe { libc::ioctl(stream.as_raw_fd(), request as _, &mut n) };
    if rc < 0 {
        return Err(io_err(io::Error::last_os_error()));
    }
    Ok(u32::try_from(n).unwrap_or(0))
}

/// The host's end of the fake robot's link, used as a serial port.
#[derive(Debug)]
pub struct SocketPort {
    path: String,
    stream: UnixStream,
    timeout: Duration,
}

impl SocketPort {
    /// Connects to the emulator listening at `path`.
    pub fn connect(path: &str, timeout: Duration) -> Result<SocketPort, HwError> {
        let stream = UnixStream::connect(path)
            .map_err(|e| HwError::PortOpen { port: path.to_string(), reason: e.to_string() })?;
        // non-blocking: reads and writes wait in `ppoll` (see `wait_ready`)
        stream
            .set_nonblocking(true)
            .map_err(|e| HwError::PortOpen { port: path.to_string(), reason: e.to_string() })?;
        Ok(SocketPort { path: path.to_string(), stream, timeout })
    }
}

/// Reads wait up to the port's timeout for the first byte; nothing → `TimedOut`.
impl Read for SocketPort {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match self.stream.read(buf) {
            Err(e) if e.kind() == ErrorKind::WouldBlock => {}
            other => return other,
        }
        if !wait_ready(&self.stream, libc::POLLIN, self.timeout)? {
            return Err(io::Error::new(ErrorKind::TimedOut, "no bytes within the timeout"));
        }
        self.stream.read(buf).map_err(timeout_kind)
    }
}

/// Writes wait up to the port's timeout for room; none → `TimedOut`.
impl Write for SocketPort {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self.stream.write(buf) {
            Err(e) if e.kind() == ErrorKind::WouldBlock => {}
            other => return other,
        }
        if !wait_ready(&self.stream, libc::POLLOUT, self.timeout)? {
            return Err(io::Error::new(ErrorKind::TimedOut, "no room within the timeout"));
        }
        self.stream.write(buf).map_err(timeout_kind)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.stream.flush()
    }
}

/// A socket has no line settings, modem lines or break: the settings read back as the PAROL6's
/// (3 000 000 baud, 8N1, no flow control), setting them changes nothing, and the lines read as
/// a connected cable.
impl SerialPort for SocketPort {
    fn name(&self) -> Option<String> {
        Some(self.path.clone())
    }
    fn baud_rate(&self) -> serialport::Result<u32> {
        Ok(crate::ports::BAUD_RATE)
    }
    fn data_bits(&self) -> serialport::Result<DataBits> {
        Ok(DataBits::Eight)
    }
    fn flow_control(&self) -> serialport::Result<FlowControl> {
        Ok(FlowControl::None)
    }
    fn parity(&self) -> serialport::Result<Parity> {
        Ok(Parity::None)
    }
    fn stop_bits(&self) -> serialport::Result<StopBits> {
        Ok(StopBits::One)
    }
    fn timeout(&self) -> Duration {
        self.timeout
    }
    fn set_baud_rate(&mut self, _baud_rate: u32) -> serialport::Result<()> {
        Ok(())
    }
    fn set_data_bits(&mut self, _data_bits: DataBits) -> serialport::Result<()> {
        Ok(())
    }
    fn set_flow_control(&mut self, _flow_control: FlowControl) -> serialport::Result<()> {
        Ok(())
    }
    fn set_parity(&mut self, _parity: Parity) -> serialport::Result<()> {
        Ok(())
    }
    fn set_stop_bits(&mut self, _stop_bits: StopBits) -> serialport::Result<()> {
        Ok(())
    }
    fn set_timeout(&mut self, timeout: Duration) -> serialport::Result<()> {
        self.timeout = timeout;
        Ok(())
    }
    fn write_request_to_send(&mut self, _level: bool) -> serialport::Result<()> {
        Ok(())
    }
    fn write_data_terminal_ready(&mut self, _level: bool) -> serialport::Result<()> {
        Ok(())
    }
    fn read_clear_to_send(&mut self) -> serialport::Result<bool> {
        Ok(true)
    }
    fn read_data_set_ready(&mut self) -> serialport::Result<bool> {
        Ok(true)
    }
    fn read_ring_indicator(&mut self) -> serialport::Result<bool> {
        Ok(false)
    }
    fn read_carrier_detect(&mut self) -> serialport::Result<bool> {
        Ok(true)
    }
    fn bytes_to_read(&self) -> serialport::Result<u32> {
        queued_bytes(&self.stream, libc::FIONREAD as libc::c_ulong)
    }
    fn bytes_to_write(&self) -> serialport::Result<u32> {
        // SIOCOUTQ, the same request as TIOCOUTQ
        queued_bytes(&self.stream, libc::TIOCOUTQ as libc::c_ulong)
    }
    fn clear(&self, buffer_to_clear: ClearBuffer) -> serialport::Result<()> {
        if matches!(buffer_to_clear, ClearBuffer::Output) {
            // what was written is already in the peer's queue
            return Ok(());
        }
        let mut scratch = [0u8; 4096];
        let mut stream = &self.stream;
        loop {
            match stream.read(&mut scratch) {
                Ok(0) => return Ok(()),
                Ok(_) => {}
                Err(e) if e.kind() == ErrorKind::WouldBlock => return Ok(()),
                Err(e) => return Err(io_err(e)),
            }
        }
    }
    fn try_clone(&self) -> serialport::Result<Box<dyn SerialPort>> {
        let stream = self.stream.try_clone().map_err(io_err)?;
        Ok(Box::new(SocketPort { path: self.path.clone(), stream, timeout: self.timeout }))
    }
    fn set_break(&self) -> serialport::Result<()> {
        Ok(())
    }
    fn clear_break(&self) -> serialport::Result<()> {
        Ok(())
    }
}

/// The emulator's end: a listening socket and the newest host connection.
#[derive(Debug)]
pub struct SocketServer {
    path: PathBuf,
    listener: UnixListener,
    conn: Option<UnixStream>,
}

/// The start of a fake robot's socket file name: `parol6-fake-robot-PID-N.sock`.
const SOCKET_PREFIX: &str = "parol6-fake-robot-";

/// Removes the socket files in `dir` left by fake robots of processes that have ended without
/// removing theirs (a crash, a kill): a file whose process id names no running process. Files
/// that cannot be read or removed are left as they are: they block nothing.
fn remove_stale_sockets(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|n| n.strip_prefix(SOCKET_PREFIX))
            .and_then(|rest| rest.split('-').next())
            .and_then(|pid| pid.parse::<u32>().ok())
        else {
            continue;
        };
        let is_socket = entry.file_type().is_ok_and(|t| t.is_socket());
        if is_socket && pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists() {
            match std::fs::remove_file(entry.path()) {
                // another user's file, or one removed meanwhile: it blocks nothing
                Ok(()) | Err(_) => {}
            }
        }
    }
}

/// Makes each server's path unique within the process.
static NEXT_SERVER: AtomicU64 = AtomicU64::new(0);

impl SocketServer {
    /// Listens on a new private path in the temporary folder.
    pub fn bind() -> io::Result<SocketServer> {
        let n = NEXT_SERVER.fetch_add(1, Ordering::Relaxed);
        if n == 0 {
            remove_stale_sockets(&std::env::temp_dir());
        }
        let path = std::env::temp_dir().join(format!("{SOCKET_PREFIX}{}-{n}.sock", std::process::id()));
        // a stale file of an earlier process with the same id
        match std::fs::remove_file(&path) {
            Ok(()) => {}
            Err(e) if e.kind() == ErrorKind::NotFound => {}
            Err(e) => return Err(e),
        }
        let listener = UnixListener::bind(&path)?;
        let server = SocketServer { path, listener, conn: None };
        std::fs::set_permissions(&server.path, std::fs::Permissions::from_mode(0o600))?;
        server.listener.set_nonblocking(true)?;
        Ok(server)
    }

    /// The path a host opens as its serial port.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Takes the newest waiting connection, if any (it replaces the current one).
    fn accept_newest(&mut self) -> io::Result<()> {
        loop {
            match self.listener.accept() {
                Ok((stream, _)) => {
                    stream.set_nonblocking(false)?;
                    stream.set_read_timeout(Some(SERVER_READ_TIMEOUT))?;
                    stream.set_write_timeout(Some(SERVER_WRITE_TIMEOUT))?;
                    self.conn = Some(stream);
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => return Ok(()),
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
}

impl Read for SocketServer {
    /// Waits up to 2 ms for bytes of the current host; nothing → `TimedOut`.
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.accept_newest()?;
        let Some(conn) = self.conn.as_mut() else {
            std::thread::sleep(SERVER_READ_TIMEOUT);
            return Err(io::Error::new(ErrorKind::TimedOut, "no host connected"));
        };
        match conn.read(buf) {
            Ok(0) => {
                // the host closed its port
                self.conn = None;
                Err(io::Error::new(ErrorKind::TimedOut, "host closed the port"))
            }
            Ok(n) => Ok(n),
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut | ErrorKind::Interrupted) => {
                Err(io::Error::new(ErrorKind::TimedOut, e))
            }
            Err(e) => {
                self.conn = None;
                Err(e)
            }
        }
    }
}

impl Write for SocketServer {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let Some(conn) = self.conn.as_mut() else {
            return Err(io::Error::new(ErrorKind::NotConnected, "no host connected"));
        };
        match conn.write(buf) {
            Ok(n) => Ok(n),
            Err(e) => {
                if !matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut | ErrorKind::Interrupted) {
                    self.conn = None;
                }
                Err(timeout_kind(e))
            }
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Drop for SocketServer {
    fn drop(&mut self) {
        if let Err(e) = std::fs::remove_file(&self.path) {
            tracing::debug!("fake robot: cannot remove {}: {e}", self.path.display());
        }
    }
}

#[cfg(test)]
mod tests;

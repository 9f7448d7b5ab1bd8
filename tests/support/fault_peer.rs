//! A fault-injecting peer on a pseudo-terminal that sits between a host [`parol6_hw::Session`]
//! and a controller (normally the firmware emulator): the session opens [`FaultPeer::path`],
//! the peer opens the controller's port and forwards both directions.
//!
//! Controller → host (the status stream) it corrupts on purpose, frame by frame: single bit
//! flips, dropped bytes, duplicated frames, swapped (reordered) frames, bursts of junk before a
//! frame, and stalls (no bytes at all for a while; the frames of a stall are either lost or
//! delivered late in one burst). Host → controller it can drop a byte or put a stray `0xFF`
//! before a frame (the firmware's receiver weakness, PROTOCOL.md §6).
//!
//! Before those faults, a [`BoardMode`] can make the controller itself lie: positions far
//! outside the limits, stale frames, a jump to impossible positions, silence after N frames
//! ([`crate::hostile_board`]).
//!
//! It records every host → controller command frame (decoded with the firmware's own receiver,
//! [`CommandParser`], from the clean stream before any fault), each with the controller's true
//! joint positions at that moment (the last uncorrupted status), and every stall it made, so a
//! test can check the host's safety invariants afterwards.

use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use parol6_hw::frame::{ReceivedCommand, STATUS_FRAME_SIZE};
use parol6_hw::{CommandParser, StatusParser};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use serialport::{SerialPort, TTYPort};

use crate::hostile_board::{BoardMode, BoardRewriter};

/// Joints of the arm.
const JOINTS: usize = 6;
/// Read timeout of the forwarding threads.
const POLL: Duration = Duration::from_millis(1);
/// A frame held back for a swap is sent anyway after this long without a successor.
const REORDER_HOLD_MAX: Duration = Duration::from_millis(5);
/// Baud rate given when opening the controller port (no effect on a pty).
const BAUD: u32 = 3_000_000;

/// What the peer does to the streams. Probabilities are per status frame (controller → host)
/// or per chunk the host wrote (host → controller; the session writes whole frames).
#[derive(Debug, Clone, PartialEq)]
pub struct FaultConfig {
    /// Seed of the fault sequence.
    pub seed: u64,
    /// Flip one random bit of the frame.
    pub bit_flip: f64,
    /// Drop 1–3 random bytes of the frame.
    pub drop_bytes: f64,
    /// Send the frame twice.
    pub duplicate: f64,
    /// Hold the frame back and send it after the next one.
    pub reorder: f64,
    /// Send 1–64 random bytes (sometimes with a fake `FF FF FF 38` header) before the frame.
    pub junk_burst: f64,
    /// Start a stall at this frame.
    pub stall: f64,
    /// Stall length range, ms (inclusive).
    pub stall_ms: (u64, u64),
    /// Share of stalls whose frames are delivered late in one burst (the rest are lost).
    pub stall_late_share: f64,
    /// Host → controller: drop one random byte of the chunk.
    pub command_drop_byte: f64,
    /// Host → controller: a stray `0xFF` before the chunk.
    pub command_stray_ff: f64,
    /// What the controller reports about its joints (applied before the faults above).
    pub board: BoardMode,
}

impl FaultConfig {
    /// A peer that forwards everything unchanged.
    pub fn clean(seed: u64) -> Self {
        Self {
            seed,
            bit_flip: 0.0,
            drop_bytes: 0.0,
            duplicate: 0.0,
            reorder: 0.0,
            junk_burst: 0.0,
            stall: 0.0,
            stall_ms: (30, 300),
            stall_late_share: 0.0,
            command_drop_byte: 0.0,
            command_stray_ff: 0.0,
            board: BoardMode::Honest,
        }
    }

    /// Heavy corruption: about a third of the status frames are hit, a 30–300 ms stall every
    /// ~1500 frames, and rare host → controller faults.
    pub fn hostile(seed: u64) -> Self {
        Self {
            seed,
            bit_flip: 0.10,
            drop_bytes: 0.08,
            duplicate: 0.06,
            reorder: 0.05,
            junk_burst: 0.05,
            stall: 1.0 / 1500.0,
            stall_ms: (30, 300),
            stall_late_share: 0.3,
            command_drop_byte: 0.002,
            command_stray_ff: 0.002,
            board: BoardMode::Honest,
        }
    }

    /// The same faults with the controller lying as `board` says.
    pub fn with_board(self, board: BoardMode) -> Self {
        Self { board, ..self }
    }
}

/// Why the peer could not start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FaultPeerError(pub String);

impl std::fmt::Display for FaultPeerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "fault peer: {}", self.0)
    }
}

impl std::error::Error for FaultPeerError {}

/// One host → controller command frame as the peer saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordedCommand {
    /// When its last byte was read.
    pub at: Instant,
    /// The decoded frame.
    pub command: ReceivedCommand,
    /// The controller's joint positions in the last uncorrupted status before it, steps.
    pub true_steps: Option<[i32; JOINTS]>,
}

/// One stall of the status stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StallRecord {
    /// When the peer stopped forwarding.
    pub started: Instant,
    /// When it forwarded again.
    pub ended: Instant,
    /// When it last wrote status bytes before the stall.
    pub last_forward_before: Option<Instant>,
    /// The stall's frames were delivered late (true) or lost (false).
    pub delivered_late: bool,
    /// Status frames held back or lost.
    pub frames: u64,
}

/// What the peer has done so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FaultCounts {
    /// Status frames received from the controller.
    pub status_frames: u64,
    /// Status frames corrupted (bit flip, dropped bytes, duplicated, reordered, junk before).
    pub corrupted: u64,
    /// … with one bit flipped.
    pub bit_flips: u64,
    /// … with bytes dropped.
    pub dropped_bytes: u64,
    /// … sent twice.
    pub duplicated: u64,
    /// … swapped with the next one.
    pub reordered: u64,
    /// … preceded by junk.
    pub junk_bursts: u64,
    /// Stalls started.
    pub stalls: u64,
    /// Status frames lost or delayed by stalls.
    pub stalled_frames: u64,
    /// Command frames recorded.
    pub command_frames: u64,
    /// Host → controller chunks with a fault.
    pub command_faults: u64,
    /// Read / write errors seen (not fatal: the peer keeps forwarding).
    pub io_errors: u64,
}

#[derive(Default)]
struct Counters {
    status_frames: AtomicU64,
    bit_flips: AtomicU64,
    dropped_bytes: AtomicU64,
    duplicated: AtomicU64,
    reordered: AtomicU64,
    junk_bursts: AtomicU64,
    stalls: AtomicU64,
    stalled_frames: AtomicU64,
    command_frames: AtomicU64,
    command_faults: AtomicU64,
    io_errors: AtomicU64,
}

fn bump(c: &AtomicU64) {
    c.fetch_add(1, Ordering::Relaxed);
}

struct Shared {
    stop: AtomicBool,
    counters: Counters,
    true_steps: Mutex<Option<[i32; JOINTS]>>,
    commands: Mutex<Vec<RecordedCommand>>,
    stalls: Mutex<Vec<StallRecord>>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    match m.lock() {
        Ok(g) => g,
        Err(poisoned) => poisoned.into_inner(),
    }
}

/// A running fault peer. [`FaultPeer::stop`] joins its threads and reports their outcome.
pub struct FaultPeer {
    path: String,
    shared: Arc<Shared>,
    threads: Vec<JoinHandle<()>>,
    _host_slave: TTYPort,
}

impl std::fmt::Debug for FaultPeer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaultPeer").field("path", &self.path).finish()
    }
}

impl FaultPeer {
    /// Opens the controller's port `controller_path`, creates the host-side pty and starts
    /// forwarding with `config`'s faults.
    pub fn spawn(controller_path: &str, config: FaultConfig) -> Result<FaultPeer, FaultPeerError> {
        let err = |what: &str, e: &dyn std::fmt::Display| FaultPeerError(format!("{what}: {e}"));
        let (mut host_master, host_slave) = TTYPort::pair().map_err(|e| err("cannot open a pseudo-terminal", &e))?;
        let path = host_slave.name().ok_or_else(|| FaultPeerError("pseudo-terminal has no path".into()))?;
        host_master.set_timeout(POLL).map_err(|e| err("pty timeout", &e))?;
        let controller = serialport::new(controller_path, BAUD)
            .timeout(POLL)
            .open_native()
            .map_err(|e| err(&format!("cannot open the controller port {controller_path}"), &e))?;
        let host_read = host_master.try_clone_native().map_err(|e| err("pty clone", &e))?;
        let controller_read = controller.try_clone_native().map_err(|e| err("controller port clone", &e))?;
        let shared = Arc::new(Shared {
            stop: AtomicBool::new(false),
            counters: Counters::default(),
            true_steps: Mutex::new(None),
            commands: Mutex::new(Vec::new()),
            stalls: Mutex::new(Vec::new()),
        });
        let mut threads = Vec::new();
        let sh = Arc::clone(&shared);
        let cfg = config.clone();
        threads.push(
            std::thread::Builder::new()
                .name("fault-peer-status".into())
                .spawn(move || StatusForwarder::new(cfg, controller_read, host_master, sh).run())
                .map_err(|e| err("thread", &e))?,
        );
        let sh = Arc::clone(&shared);
        threads.push(
            std::thread::Builder::new()
                .name("fault-peer-command".into())
                .spawn(move || forward_commands(config, host_read, controller, &sh))
                .map_err(|e| err("thread", &e))?,
        );
        Ok(FaultPeer { path, shared, threads, _host_slave: host_slave })
    }

    /// Path of the host-side pty: open it as the serial port.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// Counters so far.
    pub fn counts(&self) -> FaultCounts {
        let c = &self.shared.counters;
        let get = |a: &AtomicU64| a.load(Ordering::Relaxed);
        let (bit_flips, dropped_bytes, duplicated, reordered, junk_bursts) =
            (get(&c.bit_flips), get(&c.dropped_bytes), get(&c.duplicated), get(&c.reordered), get(&c.junk_bursts));
        FaultCounts {
            status_frames: get(&c.status_frames),
            corrupted: bit_flips + dropped_bytes + duplicated + reordered + junk_bursts,
            bit_flips,
            dropped_bytes,
            duplicated,
            reordered,
            junk_bursts,
            stalls: get(&c.stalls),
            stalled_frames: get(&c.stalled_frames),
            command_frames: get(&c.command_frames),
            command_faults: get(&c.command_faults),
            io_errors: get(&c.io_errors),
        }
    }

    /// Takes (and clears) the recorded command frames.
    pub fn take_commands(&self) -> Vec<RecordedCommand> {
        std::mem::take(&mut *lock(&self.shared.commands))
    }

    /// The stalls so far.
    pub fn stalls(&self) -> Vec<StallRecord> {
        lock(&self.shared.stalls).clone()
    }

    /// Stops forwarding and joins the threads; `Err` names a thread that panicked.
    pub fn stop(mut self) -> Result<(), FaultPeerError> {
        self.shutdown()
    }

    fn shutdown(&mut self) -> Result<(), FaultPeerError> {
        self.shared.stop.store(true, Ordering::Relaxed);
        let mut result = Ok(());
        for t in self.threads.drain(..) {
            let name = t.thread().name().unwrap_or("fault-peer").to_string();
            if t.join().is_err() {
                result = Err(FaultPeerError(format!("thread {name} panicked")));
            }
        }
        result
    }
}

impl Drop for FaultPeer {
    fn drop(&mut self) {
        let _ = self.shutdown();
    }
}

/// Reads with the port's short timeout; `None` on timeout, error counted.
fn read_some(port: &mut TTYPort, buf: &mut [u8], counters: &Counters) -> Option<usize> {
    match port.read(buf) {
        Ok(0) => None,
        Ok(n) => Some(n),
        Err(e) if matches!(e.kind(), std::io::ErrorKind::TimedOut | std::io::ErrorKind::Interrupted) => None,
        Err(_) => {
            bump(&counters.io_errors);
            std::thread::sleep(POLL);
            None
        }
    }
}

fn write_counted(port: &mut TTYPort, bytes: &[u8], counters: &Counters) {
    if port.write_all(bytes).is_err() {
        bump(&counters.io_errors);
    }
}

/// Host → controller: record every frame, forward, with rare faults.
fn forward_commands(config: FaultConfig, mut host: TTYPort, mut controller: TTYPort, sh: &Shared) {
    let mut rng = StdRng::seed_from_u64(config.seed ^ 0x5eed_c0de);
    let mut parser = CommandParser::new();
    let mut buf = [0u8; 1024];
    while !sh.stop.load(Ordering::Relaxed) {
        let Some(n) = read_some(&mut host, &mut buf, &sh.counters) else { continue };
        let now = Instant::now();
        let truth = *lock(&sh.true_steps);
        for &b in &buf[..n] {
            if let Some(command) = parser.push_byte(b) {
                lock(&sh.commands).push(RecordedCommand { at: now, command, true_steps: truth });
                bump(&sh.counters.command_frames);
            }
        }
        let mut chunk = buf[..n].to_vec();
        if rng.random_bool(config.command_stray_ff) {
            chunk.insert(0, 0xFF);
            bump(&sh.counters.command_faults);
        } else if rng.random_bool(config.command_drop_byte) {
            chunk.remove(rng.random_range(0..chunk.len()));
            bump(&sh.counters.command_faults);
        }
        write_counted(&mut controller, &chunk, &sh.counters);
    }
}

struct Stall {
    started: Instant,
    until: Instant,
    last_forward_before: Option<Instant>,
    late: bool,
    held: Vec<u8>,
    frames: u64,
}

/// Controller → host: parse the clean status stream, corrupt it, forward it.
struct StatusForwarder {
    cfg: FaultConfig,
    rng: StdRng,
    controller: TTYPort,
    host: TTYPort,
    sh: Arc<Shared>,
    parser: StatusParser,
    board: BoardRewriter,
    stall: Option<Stall>,
    swap_held: Option<(Vec<u8>, Instant)>,
    last_forward: Option<Instant>,
}

impl StatusForwarder {
    fn new(cfg: FaultConfig, controller: TTYPort, host: TTYPort, sh: Arc<Shared>) -> Self {
        let rng = StdRng::seed_from_u64(cfg.seed);
        let board = BoardRewriter::new(cfg.board);
        Self {
            cfg,
            rng,
            controller,
            host,
            sh,
            parser: StatusParser::new(),
            board,
            stall: None,
            swap_held: None,
            last_forward: None,
        }
    }

    fn run(mut self) {
        let mut buf = [0u8; 4096];
        while !self.sh.stop.load(Ordering::Relaxed) {
            let n = read_some(&mut self.controller, &mut buf, &self.sh.counters).unwrap_or(0);
            self.parser.push(&buf[..n]);
            while let Some(frame) = self.parser.next_frame() {
                *lock(&self.sh.true_steps) = Some(frame.positions_steps);
                bump(&self.sh.counters.status_frames);
                if let Some(said) = self.board.rewrite(frame) {
                    self.on_frame(said.encode().to_vec());
                }
            }
            self.end_stall_if_due();
            if let Some((held, since)) = self.swap_held.take() {
                if since.elapsed() > REORDER_HOLD_MAX {
                    self.send(&held);
                } else {
                    self.swap_held = Some((held, since));
                }
            }
        }
    }

    fn send(&mut self, bytes: &[u8]) {
        write_counted(&mut self.host, bytes, &self.sh.counters);
        self.last_forward = Some(Instant::now());
    }

    fn end_stall_if_due(&mut self) {
        let now = Instant::now();
        if self.stall.as_ref().is_some_and(|s| now >= s.until)
            && let Some(s) = self.stall.take()
        {
            if s.late && !s.held.is_empty() {
                self.send(&s.held);
            }
            lock(&self.sh.stalls).push(StallRecord {
                started: s.started,
                ended: now,
                last_forward_before: s.last_forward_before,
                delivered_late: s.late,
                frames: s.frames,
            });
        }
    }

    fn on_frame(&mut self, mut bytes: Vec<u8>) {
        let sh = Arc::clone(&self.sh);
        let c = &sh.counters;
        if let Some(s) = self.stall.as_mut() {
            if s.late {
                s.held.extend_from_slice(&bytes);
            }
            s.frames += 1;
            bump(&c.stalled_frames);
            return;
        }
        if self.rng.random_bool(self.cfg.stall) {
            if let Some((held, _)) = self.swap_held.take() {
                self.send(&held);
            }
            let now = Instant::now();
            let ms = self.rng.random_range(self.cfg.stall_ms.0..=self.cfg.stall_ms.1);
            let late = self.rng.random_bool(self.cfg.stall_late_share);
            self.stall = Some(Stall {
                started: now,
                until: now + Duration::from_millis(ms),
                last_forward_before: self.last_forward,
                late,
                held: if late { bytes } else { Vec::new() },
                frames: 1,
            });
            bump(&c.stalls);
            bump(&c.stalled_frames);
            return;
        }
        let r: f64 = self.rng.random();
        let cfg = &self.cfg;
        let mut edge = cfg.bit_flip;
        if r < edge {
            let bit = self.rng.random_range(0..STATUS_FRAME_SIZE * 8);
            bytes[bit / 8] ^= 0x80 >> (bit % 8);
            bump(&c.bit_flips);
            return self.send_then_swapped(&bytes);
        }
        edge += cfg.drop_bytes;
        if r < edge {
            for _ in 0..self.rng.random_range(1..=3) {
                let at = self.rng.random_range(0..bytes.len());
                bytes.remove(at);
            }
            bump(&c.dropped_bytes);
            return self.send_then_swapped(&bytes);
        }
        edge += cfg.duplicate;
        if r < edge {
            let mut twice = bytes.clone();
            twice.extend_from_slice(&bytes);
            bump(&c.duplicated);
            return self.send_then_swapped(&twice);
        }
        edge += cfg.reorder;
        if r < edge && self.swap_held.is_none() {
            self.swap_held = Some((bytes, Instant::now()));
            bump(&c.reordered);
            return;
        }
        edge += cfg.junk_burst;
        if r < edge {
            let mut junk: Vec<u8> = (0..self.rng.random_range(1..=64)).map(|_| self.rng.random()).collect();
            if self.rng.random_bool(0.3) {
                let at = self.rng.random_range(0..=junk.len());
                junk.splice(at..at, [0xFF, 0xFF, 0xFF, 0x38]);
            }
            junk.extend_from_slice(&bytes);
            bump(&c.junk_bursts);
            return self.send_then_swapped(&junk);
        }
        self.send_then_swapped(&bytes);
    }

    /// Sends `bytes`, then the frame held back for a swap, if any.
    fn send_then_swapped(&mut self, bytes: &[u8]) {
        match self.swap_held.take() {
            Some((held, _)) => {
                let mut both = bytes.to_vec();
                both.extend_from_slice(&held);
                self.send(&both);
            }
            None => self.send(bytes),
        }
    }
}

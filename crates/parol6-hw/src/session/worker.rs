//! The session thread: one command frame per period, status parsing, link supervision and
//! publication of the [`Snapshot`] and the [`RobotState`] (computed here, once per tick).

use std::sync::Arc;
use std::time::{Duration, Instant};

use arc_swap::ArcSwap;
use crossbeam_channel::{Receiver, Sender};
use parol6_core::RobotModel;
use parol6_core::motion::{MotionCommand, MotionSample, RobotState};
use parol6_core::parol6::JOINT_COUNT;

use super::config::SessionConfig;
use super::guard::{DisagreementMonitor, PlausibilityFilter, guard_frame, placeholder_positions};
use super::motion::{Homing, Streamer};
use super::snapshot::{HomingState, LinkState, Snapshot};
use crate::frame::{CommandCode, CommandFields, CommandFrame, GripperCommand, IO_OUT1, IO_OUT2};
use crate::parser::StatusParser;

/// How long a motion command waits for the arm to come to rest after IDLE.
const SETTLE_WAIT: std::time::Duration = std::time::Duration::from_millis(500);

/// Gripper command bits: activate.
pub const GRIPPER_ACTIVATE: u8 = 0x80;
/// Gripper command bits: action / move active.
pub const GRIPPER_MOVE: u8 = 0x40;
/// Gripper command bits: E-stop (set while the E-stop is pressed).
pub const GRIPPER_ESTOP: u8 = 0x20;
/// Gripper command bits: forwarded bit the API always sets ("grip enable").
pub const GRIPPER_ENABLE: u8 = 0x10;

/// Tick intervals kept for the snapshot's rate / jitter statistics (the last this many periods).
pub const TIMING_WINDOW: usize = 256;
/// While nothing answers, one frame in this many is written.
const NO_ANSWER_PROBE_EVERY: u64 = 10;
/// Final IDLE frames sent when the session closes.
const CLOSING_FRAMES: u32 = 3;
/// The fault text of an E-stop press (cleared by the ENABLE after its release).
const ESTOP_FAULT: &str = "E-stop pressed: motion stopped, DISABLE sent; enable after release";
/// The fault text of an ENABLE refused while the E-stop is pressed (cleared by a later ENABLE).
const ENABLE_REFUSED_FAULT: &str = "enable refused: E-stop is pressed";

/// Requests from the API to the session thread.
#[derive(Debug, Clone)]
pub(super) enum Request {
    Motion { cmd: MotionCommand, at_s: Option<f64> },
    JogBackInside { joint: usize, fraction: f64 },
    OneShot(CommandCode),
    Home,
    Gripper { position: i16, speed: i16, current_ma: i16 },
    GripperMode(u8),
    Output { index: u8, level: bool },
    Shutdown,
}

/// What the thread publishes.
pub(super) struct Shared {
    pub(super) snapshot: ArcSwap<Snapshot>,
    pub(super) state: ArcSwap<RobotState>,
}

mod publish;
mod recovery;
mod status;

pub use recovery::RECOVERY_SPEED_SHARE;

pub(super) struct Worker {
    port_name: String,
    port: Option<Box<dyn serialport::SerialPort>>,
    cfg: SessionConfig,
    rx: Receiver<Request>,
    shared: Arc<Shared>,
    model: RobotModel,
    parser: StatusParser,
    pub(super) snap: Snapshot,
    streamer: Streamer,
    one_shots: Vec<CommandCode>,
    io_bits: u8,
    gripper: GripperCommand,
    gripper_mode_once: Option<u8>,
    epoch: Instant,
    opened_at: Instant,
    ever_answered: bool,
    last_open_attempt: Instant,
    connected_at: Instant,
    intervals_s: Vec<f64>,
    interval_pos: usize,
    jitter_scratch: Vec<f64>,
    last_tick: Option<Instant>,
    read_buf: Vec<u8>,
    plausibility: PlausibilityFilter,
    disagreement: DisagreementMonitor,
    /// When the first frame written since the last valid status was written.
    first_unanswered_write: Option<Instant>,
    /// Frames without a reply that were sent while the link was down (not counted as missing).
    missing_offset: u64,
    pub(super) write_log: Option<Sender<Instant>>,
    pub(super) tap: Option<Sender<MotionSample>>,
    /// A motion command that arrived while the arm was still settling after IDLE: applied as
    /// soon as the status is steady, refused after [`SETTLE_WAIT`].
    deferred: Option<(MotionCommand, Option<f64>, Instant)>,
    /// A confirmed jog back inside of a joint beyond its limit (JOG frames).
    recovery: Option<recovery::Recovery>,
}

impl Worker {
    pub(super) fn new(
        port_name: String,
        port: Box<dyn serialport::SerialPort>,
        cfg: SessionConfig,
        rx: Receiver<Request>,
        shared: Arc<Shared>,
        model: RobotModel,
        streamer: Streamer,
    ) -> Self {
        let now = Instant::now();
        Self {
            snap: Snapshot::new(&port_name, cfg.rate_hz),
            port_name,
            port: Some(port),
            cfg,
            rx,
            shared,
            model,
            parser: StatusParser::new(),
            streamer,
            one_shots: Vec::with_capacity(16),
            io_bits: 0,
            gripper: GripperCommand::default(),
            gripper_mode_once: None,
            epoch: now,
            opened_at: now,
            ever_answered: false,
            last_open_attempt: now,
            connected_at: now,
            intervals_s: Vec::with_capacity(TIMING_WINDOW),
            interval_pos: 0,
            jitter_scratch: Vec::with_capacity(TIMING_WINDOW),
            last_tick: None,
            read_buf: vec![0u8; 4096],
            plausibility: PlausibilityFilter::default(),
            disagreement: DisagreementMonitor::default(),
            missing_offset: 0,
            first_unanswered_write: None,
            write_log: None,
            tap: None,
            deferred: None,
            recovery: None,
        }
    }

    fn measured(&self) -> Option<([f64; JOINT_COUNT], [i32; JOINT_COUNT])> {
        self.snap.status.map(|_| (self.snap.joint_rad, self.snap.joint_steps))
    }

    fn set_fault(&mut self, msg: impl Into<String>) {
        let msg = msg.into();
        if self.snap.fault.as_deref() != Some(msg.as_str()) {
            tracing::warn!("parol6 session: {msg}");
            self.snap.fault = Some(msg);
        }
    }

    fn fail_homing(&mut self, reason: &str) {
        if !matches!(self.streamer.homing, Homing::None) {
            self.streamer.homing = Homing::None;
            self.snap.homing = HomingState::Failed(reason.to_string());
        }
    }

    /// Stops streaming and homing: IDLE from the next frame, the planner reset.
    fn stop_all(&mut self, homing_reason: &str) {
        self.streamer.stop_streaming();
        self.recovery = None;
        self.disagreement.reset();
        self.fail_homing(homing_reason);
    }

    pub(super) fn run(&mut self) {
        if self.cfg.raise_priority {
            crate::priority::raise_current_thread();
        }
        let period = self.cfg.period();
        let mut next_tick = Instant::now();
        let mut closing: Option<u32> = None;
        loop {
            // Wait for the deadline, reading status bytes as they arrive.
            let spin_from = next_tick.checked_sub(self.cfg.spin_before_deadline).unwrap_or(next_tick);
            loop {
                let now = Instant::now();
                if now >= next_tick {
                    break;
                }
                if now < spin_from {
                    self.read_until(spin_from);
                } else {
                    self.read_available();
                    std::hint::spin_loop();
                }
            }
            // Whatever arrived right at the deadline counts for this tick.
            self.read_available();
            let now = Instant::now();
            self.record_tick(now);
            if now.saturating_duration_since(next_tick) > self.cfg.status_timeout / 2 {
                // This thread was stalled for half the timeout (a frozen host: the board, when
                // emulated, was frozen too): the frames written before the stall do not count
                // toward link loss. A shorter delay (a busy core) changes nothing: the board's
                // answers wait in the port's buffer and were read just above.
                if let Some(t) = self.first_unanswered_write.as_mut() {
                    *t = now;
                }
            }
            if closing.is_none() && self.drain_requests(now) {
                closing = Some(CLOSING_FRAMES);
                self.stop_all("session closed");
            }
            self.check_link(now);
            let t_s = self.streamer.time_s();
            let frame = match closing {
                Some(_) => self.idle_frame(),
                None => self.next_frame(now),
            };
            let sent_target = self.write_frame(frame);
            self.check_disagreement(t_s);
            self.publish(now, t_s);
            self.streamer.end_tick(sent_target);
            if let Some(n) = closing.as_mut() {
                *n -= 1;
                if *n == 0 {
                    break;
                }
            }
            next_tick += period;
            let after = Instant::now();
            if after > next_tick + period {
                // Fell more than a period behind (stalled machine): resynchronise. The motion
                // clock counts frames, so the trajectory is stretched, never skipped.
                next_tick = after;
            }
        }
        self.port = None;
        self.snap.link = LinkState::Closed;
        let t_s = self.streamer.time_s();
        self.publish(Instant::now(), t_s);
    }

    /// Reads and parses until `deadline` (or returns early after an error / when no port).
    fn read_until(&mut self, deadline: Instant) {
        let Some(port) = self.port.as_mut() else {
            std::thread::sleep(deadline.saturating_duration_since(Instant::now()));
            return;
        };
        let wait = deadline.saturating_duration_since(Instant::now());
        if wait.is_zero() {
            return;
        }
        if let Err(e) = port.set_timeout(wait) {
            self.port_failed(&format!("serial port error: {e}"));
            return;
        }
        match port.read(&mut self.read_buf) {
            // EOF on a tty means hang-up.
            Ok(0) => self.port_failed("serial port closed (end of file)"),
            Ok(n) => self.parse(n),
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut || e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => self.port_failed(&format!("serial port closed or failed: {e}")),
        }
    }

    /// Reads and parses whatever is buffered, without waiting.
    fn read_available(&mut self) {
        let Some(port) = self.port.as_mut() else { return };
        match port.bytes_to_read() {
            Ok(0) => {}
            Ok(n) => {
                let n = (n as usize).min(self.read_buf.len());
                match port.read(&mut self.read_buf[..n]) {
                    Ok(got) => self.parse(got),
                    Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                    Err(e) => self.port_failed(&format!("serial port closed or failed: {e}")),
                }
            }
            Err(e) => self.port_failed(&format!("serial port error: {e}")),
        }
    }

    fn parse(&mut self, n: usize) {
        self.parser.push(&self.read_buf[..n]);
        let now = Instant::now();
        while let Some(frame) = self.parser.next_frame() {
            self.on_status(frame, now);
        }
    }

    fn check_disagreement(&mut self, t_s: f64) {
        let (Some(target), true) = (self.snap.target_steps, self.streamer.is_streaming()) else {
            self.disagreement.reset();
            return;
        };
        let tol = self.cfg.disagreement_steps;
        let timeout = self.cfg.disagreement_timeout.as_secs_f64();
        if let Some((j, d)) = self.disagreement.check(&target, &self.snap.joint_steps, t_s, tol, timeout) {
            self.stop_all("disagreement");
            self.set_fault(format!(
                "J{} is {d} steps from its commanded position for more than {:.1} s (tolerance {tol} steps): \
                 motion stopped; is the arm blocked or the board disabled?",
                j + 1,
                timeout
            ));
        }
    }

    /// Handles queued requests; true on shutdown.
    fn drain_requests(&mut self, now: Instant) -> bool {
        while let Ok(r) = self.rx.try_recv() {
            match r {
                Request::Shutdown => return true,
                Request::OneShot(code) => {
                    match code {
                        CommandCode::Enable => {
                            if self.snap.estop_pressed {
                                self.set_fault(ENABLE_REFUSED_FAULT);
                                continue;
                            }
                            self.snap.needs_enable = false;
                            // the E-stop's text is answered by this ENABLE: it must not stay red
                            if matches!(self.snap.fault.as_deref(), Some(ESTOP_FAULT | ENABLE_REFUSED_FAULT)) {
                                self.snap.fault = None;
                            }
                            self.fail_homing("homing cancelled by ENABLE");
                        }
                        CommandCode::Disable => {
                            self.snap.enabled = Some(false);
                            self.stop_all("homing cancelled by DISABLE");
                        }
                        CommandCode::ClearError => {
                            self.snap.fault = None;
                            self.fail_homing("homing cancelled by CLEAR ERROR");
                        }
                        _ => {}
                    }
                    self.one_shots.push(code);
                }
                Request::Home => {
                    if let Err(e) = self.home_allowed() {
                        self.set_fault(format!("home refused: {e}"));
                        continue;
                    }
                    self.streamer.stop_streaming();
                    self.streamer.homing =
                        Homing::Sending { left: self.cfg.home_frames, started: now, seen_unhomed: false };
                    self.snap.homing = HomingState::Sending;
                }
                Request::JogBackInside { joint, fraction } => {
                    if let Err(msg) = self.start_recovery(joint, fraction, now) {
                        self.recovery = None;
                        self.streamer.refuse(msg);
                    }
                }
                Request::Motion { cmd, at_s } => {
                    self.recovery = None;
                    if matches!(cmd, MotionCommand::Stop) && !matches!(self.streamer.homing, Homing::None) {
                        self.one_shots.push(CommandCode::ClearError);
                        self.fail_homing("homing stopped");
                    }
                    let blocked = self.snap.motion_allowed().err().map(|e| e.to_string());
                    // Motion starts only from a confirmed measurement (never a lone frame) of an
                    // arm at rest (identical frames: the latest status may lag a coasting arm).
                    let start_ok = self.plausibility.confirmed() && self.plausibility.steady();
                    if !start_ok && cmd.starts_motion() && !self.streamer.is_streaming() && blocked.is_none() {
                        self.deferred = Some((cmd, at_s, now));
                        continue;
                    }
                    self.deferred = None;
                    let measured = if start_ok { self.measured() } else { None };
                    if let Err(msg) = self.streamer.apply(cmd, at_s, measured, blocked) {
                        tracing::debug!("parol6 session: {msg}");
                        self.streamer.refuse(msg);
                    }
                }
                Request::Gripper { position, speed, current_ma } => {
                    self.gripper.position = position;
                    self.gripper.speed = speed;
                    self.gripper.current_ma = current_ma;
                    self.gripper.command_bits = GRIPPER_ACTIVATE | GRIPPER_MOVE | GRIPPER_ENABLE;
                }
                Request::GripperMode(m) => self.gripper_mode_once = Some(m),
                Request::Output { index, level } => {
                    let bit = if index == 1 { IO_OUT1 } else { IO_OUT2 };
                    if level {
                        self.io_bits |= bit;
                    } else {
                        self.io_bits &= !bit;
                    }
                }
            }
        }
        false
    }

    fn home_allowed(&self) -> Result<(), String> {
        if self.snap.link != LinkState::Connected {
            return Err(format!("link is {:?}", self.snap.link));
        }
        if self.snap.estop_pressed || self.snap.needs_enable || self.snap.enabled == Some(false) {
            return Err("E-stop pressed or controller disabled: enable it first".into());
        }
        Ok(())
    }

    fn base_fields(&self) -> CommandFields {
        let mut gripper = self.gripper;
        if let Some(m) = self.gripper_mode_once {
            gripper.mode = m;
        }
        if self.snap.estop_pressed {
            gripper.command_bits |= GRIPPER_ESTOP;
        }
        let measured = self.snap.status.map(|_| self.snap.joint_steps);
        CommandFields {
            positions_steps: placeholder_positions(measured.as_ref()),
            speeds_steps_s: [0; JOINT_COUNT],
            affected_joints: 0,
            io_bits: self.io_bits,
            timeout: 0,
            gripper,
        }
    }

    fn frame(&self, command: CommandCode) -> CommandFrame {
        CommandFrame { command, fields: self.base_fields() }
    }

    fn idle_frame(&self) -> CommandFrame {
        self.frame(CommandCode::Idle)
    }

    /// Applies a deferred motion command once the arm is at rest, or refuses it when the wait
    /// is over.
    fn start_deferred(&mut self, now: Instant) {
        let Some((cmd, at_s, since)) = self.deferred.take() else { return };
        let blocked = self.snap.motion_allowed().err().map(|e| e.to_string());
        if self.plausibility.confirmed() && self.plausibility.steady() {
            if let Err(msg) = self.streamer.apply(cmd, at_s, self.measured(), blocked) {
                self.streamer.refuse(msg);
            }
        } else if now.duration_since(since) > SETTLE_WAIT || blocked.is_some() {
            let why = blocked.unwrap_or_else(|| "the arm did not come to rest".into());
            self.streamer.refuse(format!("{} refused: {why}", cmd.name()));
        } else {
            self.deferred = Some((cmd, at_s, since));
        }
    }

    fn next_frame(&mut self, now: Instant) -> CommandFrame {
        // E-stop: DISABLE every period while pressed.
        if self.snap.estop_pressed {
            self.stop_all("E-stop pressed during homing");
            return self.frame(CommandCode::Disable);
        }
        if self.snap.link != LinkState::Connected {
            self.stop_all("link lost during homing");
            self.deferred = None;
        }
        self.start_deferred(now);
        let target = match self.streamer.sample_target() {
            Ok(t) => t,
            Err(msg) => {
                self.set_fault(msg);
                None
            }
        };
        if !self.one_shots.is_empty() {
            let code = self.one_shots.remove(0);
            return self.frame(code);
        }
        if let Some(f) = self.homing_frame(now) {
            return f;
        }
        if let Some(f) = self.recovery_frame(now) {
            return f;
        }
        match target {
            Some((steps, speeds)) => {
                let mut f = self.frame(CommandCode::Move);
                f.fields.positions_steps = steps;
                f.fields.speeds_steps_s = speeds;
                f
            }
            None => self.idle_frame(),
        }
    }

    fn homing_frame(&mut self, now: Instant) -> Option<CommandFrame> {
        match &mut self.streamer.homing {
            Homing::Sending { left, started, seen_unhomed } => {
                let (started, seen) = (*started, *seen_unhomed);
                *left = left.saturating_sub(1);
                if *left == 0 {
                    self.streamer.homing = Homing::Waiting { started, seen_unhomed: seen };
                    self.snap.homing = HomingState::Waiting;
                }
                Some(self.frame(CommandCode::Home))
            }
            Homing::Waiting { started, .. } => {
                if now.duration_since(*started) <= self.cfg.home_timeout {
                    return Some(self.idle_frame());
                }
                let homed: Vec<String> = self
                    .snap
                    .homed
                    .iter()
                    .enumerate()
                    .filter(|(_, h)| **h)
                    .map(|(i, _)| format!("J{}", i + 1))
                    .collect();
                let reason = format!(
                    "not all joints homed after {:.0} s (homed: {})",
                    self.cfg.home_timeout.as_secs_f64(),
                    if homed.is_empty() { "none".to_string() } else { homed.join(" ") }
                );
                self.fail_homing(&reason);
                self.set_fault(format!("homing failed: {reason}"));
                // Reset the board's homing state.
                Some(self.frame(CommandCode::ClearError))
            }
            Homing::None => None,
        }
    }

    /// Guards, encodes and writes a frame; returns the MOVE target written. While nothing
    /// answers, only every tenth frame is written (a quiet probe).
    fn write_frame(&mut self, mut frame: CommandFrame) -> Option<[i32; JOINT_COUNT]> {
        if self.snap.link == LinkState::NoAnswer && !self.streamer.tick().is_multiple_of(NO_ANSWER_PROBE_EVERY) {
            return None;
        }
        match guard_frame(&mut frame, self.streamer.reference(), self.cfg.period_s()) {
            Ok(0) => {}
            Ok(n) => self.snap.guard_trips += u64::from(n),
            Err(v) => {
                self.snap.guard_trips += 1;
                self.set_fault(format!("frame blocked by the limit guard: {v}"));
                self.stop_all("frame blocked by the limit guard");
                frame = self.idle_frame();
                if guard_frame(&mut frame, None, self.cfg.period_s()).is_err() {
                    return None;
                }
            }
        }
        let bytes = match frame.encode() {
            Ok(b) => b,
            Err(e) => {
                self.set_fault(format!("cannot encode frame: {e}"));
                return None;
            }
        };
        let port = self.port.as_mut()?;
        match port.write_all(&bytes) {
            Ok(()) => {
                if let Some(log) = &self.write_log {
                    let _ = log.try_send(Instant::now());
                }
                self.snap.frames_sent += 1;
                self.first_unanswered_write.get_or_insert_with(Instant::now);
                self.snap.last_command = Some(frame.command);
                self.gripper_mode_once = None;
                let sent = (frame.command == CommandCode::Move).then_some(frame.fields.positions_steps);
                self.snap.target_steps = sent;
                sent
            }
            Err(e) => {
                self.port_failed(&format!("serial port closed or failed while writing: {e}"));
                None
            }
        }
    }
}

/// How long [`crate::Session::close`] waits for the thread.
pub(super) const CLOSE_WAIT: Duration = Duration::from_secs(1);

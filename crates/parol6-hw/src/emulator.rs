//! A PAROL6 controller emulator that behaves like the public firmware (PROTOCOL.md §5):
//! the MOVE control law, JOG, IDLE, the ENABLE / DISABLE latch, HOME with homed bits (time
//! compressed), one status reply per accepted frame, no timeout, no limit checks. The E-stop
//! and input pins can be toggled from tests.
//!
//! [`ControllerModel`] is the pure state machine; [`EmulatorHandle::spawn`] serves it on the
//! master side of a pseudo-terminal and exposes the slave path for a [`crate::Session`];
//! [`EmulatorHandle::spawn_socket`] serves it on a local socket instead (the fake robot of the
//! window and of `--fake-robot`: no kernel tty worker between host and board, issue 32).
//!
//! Not emulated: the test routine (code 69 is accepted and answered but does not move the
//! arm, and is logged), the homing trajectory itself (joints hold still while the stages run
//! and the counters are then set to standby), and CAN details of the gripper.

use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use arc_swap::ArcSwap;
use parol6_core::motion::stepper::{StepperCommand, Steppers, substeps};
use parol6_core::parol6::JOINT_COUNT;

use crate::frame::{
    CommandCode, IO_ALWAYS_SET, IO_ESTOP_RELEASED, IO_IN1, IO_IN2, IO_OUT1, IO_OUT2, JOINT_BITS_ALWAYS_SET,
    ReceivedCommand, StatusFrame, TIMING_TICKS_PER_S, joint_flags_byte,
};
use crate::units::STANDBY_STEPS;

/// Seek speeds shown while each homing stage runs, steps/s (ROBOT.md §8).
const HOMING_SEEK_STEPS_S: [i32; JOINT_COUNT] = [-2050, -2550, -2550, 5550, -5050, -9550];

/// Emulator settings.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EmulatorConfig {
    /// Duration of the whole (compressed) homing sequence, s.
    pub home_duration_s: f64,
    /// Step counters at power-up (the firmware boots at 0).
    pub initial_steps: [i32; JOINT_COUNT],
    /// Start with all homed bits set.
    pub start_homed: bool,
    /// Keep a log of received commands for [`EmulatorHandle::take_received`] (capped).
    pub log_commands: bool,
    /// Most frames the log keeps until taken (later ones are not logged). The default,
    /// [`LOG_CAP`], holds ~33 minutes of a 100 Hz host (17.6 MB); a long-running host that
    /// seldom takes the log (the window's built-in emulator) keeps fewer.
    pub log_frames_max: usize,
}

impl Default for EmulatorConfig {
    fn default() -> Self {
        Self {
            home_duration_s: 1.0,
            initial_steps: [0; JOINT_COUNT],
            start_homed: false,
            log_commands: true,
            log_frames_max: LOG_CAP,
        }
    }
}

impl EmulatorConfig {
    /// Powered up already homed at the standby pose (handy for demos and the GUI's fake robot).
    pub fn homed_at_standby() -> Self {
        Self { initial_steps: STANDBY_STEPS, start_homed: true, ..Self::default() }
    }
}

/// Progress of the emulated homing sequence.
#[derive(Debug, Clone, Copy, PartialEq)]
struct HomingRun {
    elapsed_s: f64,
}

/// The firmware's state machine without any I/O.
#[derive(Debug, Clone)]
pub struct ControllerModel {
    config: EmulatorConfig,
    /// The drives, stepped by the firmware's law (`parol6_core::motion::stepper`, shared with
    /// the simulation).
    steppers: Steppers,
    homed: [bool; JOINT_COUNT],
    disabled: bool,
    homing: Option<HomingRun>,
    last: Option<ReceivedCommand>,
    out_bits: u8,
    /// E-stop input pressed.
    pub estop_pressed: bool,
    /// INPUT1 level.
    pub in1: bool,
    /// INPUT2 level.
    pub in2: bool,
    last_accept: Option<Instant>,
    timing_ticks: u16,
    gripper_position: i16,
    gripper_current_ma: i16,
    gripper_status: u8,
}

impl ControllerModel {
    /// A board at power-up.
    pub fn new(config: EmulatorConfig) -> Self {
        let homed = [config.start_homed; JOINT_COUNT];
        Self {
            steppers: Steppers::at(config.initial_steps),
            config,
            homed,
            disabled: false,
            homing: None,
            last: None,
            out_bits: 0,
            estop_pressed: false,
            in1: false,
            in2: false,
            last_accept: None,
            timing_ticks: 0,
            gripper_position: 0,
            gripper_current_ma: 2,
            gripper_status: 1,
        }
    }

    /// Step counters, rounded.
    pub fn position_steps(&self) -> [i32; JOINT_COUNT] {
        self.steppers.position_steps()
    }

    /// Current speed set points, steps/s.
    pub fn speed_steps_s(&self) -> [i32; JOINT_COUNT] {
        self.steppers.speed_steps_s().map(|v| v.trunc() as i32)
    }

    /// True while the DISABLE latch is set.
    pub fn is_disabled(&self) -> bool {
        self.disabled
    }

    /// True while the homing sequence runs.
    pub fn is_homing(&self) -> bool {
        self.homing.is_some()
    }

    /// Homed flags.
    pub fn homed(&self) -> [bool; JOINT_COUNT] {
        self.homed
    }

    /// Code of the last accepted frame.
    pub fn last_code(&self) -> Option<u8> {
        self.last.map(|c| c.code)
    }

    /// Accepts one command frame at `now` and returns the status reply (PROTOCOL.md §5).
    pub fn accept(&mut self, cmd: ReceivedCommand, now: Instant) -> StatusFrame {
        if let Some(prev) = self.last_accept {
            let ticks = now.duration_since(prev).as_secs_f64() * TIMING_TICKS_PER_S;
            self.timing_ticks = (ticks as u64 & 0xFFFF) as u16;
        }
        self.last_accept = Some(now);
        self.out_bits = cmd.fields.io_bits & (IO_OUT1 | IO_OUT2);
        match CommandCode::from_byte(cmd.code) {
            Some(CommandCode::Enable) => {
                self.disabled = false;
                self.homing = None;
            }
            Some(CommandCode::Disable) => {
                self.disabled = true;
                self.homing = None;
            }
            Some(CommandCode::ClearError) => self.homing = None,
            Some(CommandCode::Home) => {
                if !self.disabled && self.homing.is_none() {
                    self.start_homing();
                }
            }
            Some(CommandCode::Idle) => {}
            Some(CommandCode::Jog) | Some(CommandCode::Move) => self.homing = None,
            None => {
                if cmd.code == 69 {
                    tracing::warn!("emulator: received code 69 (test routine); not emulated");
                }
                self.homing = None;
            }
        }
        self.update_gripper(&cmd);
        self.last = Some(cmd);
        self.apply_speeds();
        self.status()
    }

    fn start_homing(&mut self) {
        self.homing = Some(HomingRun { elapsed_s: 0.0 });
        self.homed = [false; JOINT_COUNT];
    }

    fn update_gripper(&mut self, cmd: &ReceivedCommand) {
        let g = &cmd.fields.gripper;
        if g.id != 0 {
            return;
        }
        match g.mode {
            1 => self.gripper_status |= 0x01,
            2 => self.gripper_status &= !0x02,
            _ => {
                if g.command_bits & 0x80 != 0 {
                    self.gripper_position = g.position.clamp(0, 255);
                    self.gripper_current_ma = g.current_ma;
                    // activated, at target position, calibrated
                    self.gripper_status = 0x80 | 0x30 | (self.gripper_status & 0x01);
                }
            }
        }
    }

    /// Sets the speed set points the current command implies (called on accept and each
    /// sub-step): the MOVE and JOG laws are `parol6_core::motion::stepper`'s.
    fn apply_speeds(&mut self) {
        let Some(cmd) = self.last else { return };
        if let Some(run) = self.homing {
            let stage = self.homing_stage(run.elapsed_s);
            let speeds =
                std::array::from_fn(|i| if stage_moves(stage, i) { f64::from(HOMING_SEEK_STEPS_S[i]) } else { 0.0 });
            self.steppers.set_command(StepperCommand::Hold);
            self.steppers.set_speeds_steps_s(speeds);
            return;
        }
        let fields = &cmd.fields;
        match CommandCode::from_byte(cmd.code) {
            Some(CommandCode::Idle) => {
                self.steppers.set_command(StepperCommand::Hold);
                self.steppers.set_speeds_steps_s(fields.speeds_steps_s.map(f64::from));
            }
            Some(CommandCode::Jog) if !self.disabled => {
                self.steppers.set_command(StepperCommand::Jog { speed_steps_s: fields.speeds_steps_s });
            }
            Some(CommandCode::Move) if !self.disabled => {
                self.steppers.set_command(StepperCommand::Move {
                    target_steps: fields.positions_steps,
                    speed_steps_s: fields.speeds_steps_s,
                });
            }
            _ => self.steppers.set_command(StepperCommand::Hold),
        }
    }

    /// Homing stage for the elapsed time: 0 = J1–J3, 1 = J4, 2 = J6 and J5, 3 = done.
    fn homing_stage(&self, elapsed_s: f64) -> u8 {
        let d = self.config.home_duration_s.max(1e-3);
        if elapsed_s < 0.4 * d {
            0
        } else if elapsed_s < 0.6 * d {
            1
        } else if elapsed_s < d {
            2
        } else {
            3
        }
    }

    /// Lets `dt_s` seconds of firmware main loop pass.
    pub fn advance(&mut self, dt_s: f64) {
        for h in substeps(dt_s) {
            if let Some(run) = self.homing.as_mut() {
                run.elapsed_s += h;
                let elapsed = run.elapsed_s;
                let stage = self.homing_stage(elapsed);
                if stage >= 1 {
                    self.homed[0..3].fill(true);
                }
                if stage >= 2 {
                    self.homed[3] = true;
                }
                if stage >= 3 {
                    self.homed = [true; JOINT_COUNT];
                    self.steppers.set_position_steps(STANDBY_STEPS.map(f64::from));
                    self.homing = None;
                    // FW restarts homing when the last command is still HOME.
                    if self.last.map(|c| c.code) == Some(CommandCode::Home.byte()) {
                        self.start_homing();
                    }
                }
                self.apply_speeds();
                continue;
            }
            self.apply_speeds();
            let stepping = matches!(
                self.last.and_then(|c| CommandCode::from_byte(c.code)),
                Some(CommandCode::Jog) | Some(CommandCode::Move)
            ) && !self.disabled;
            if stepping {
                self.steppers.integrate(h);
            }
        }
    }

    /// The status frame the board would send now.
    pub fn status(&self) -> StatusFrame {
        let mut io = IO_ALWAYS_SET | self.out_bits;
        if !self.estop_pressed {
            io |= IO_ESTOP_RELEASED;
        }
        if self.in1 {
            io |= IO_IN1;
        }
        if self.in2 {
            io |= IO_IN2;
        }
        StatusFrame {
            positions_steps: self.position_steps(),
            speeds_steps_s: self.speed_steps_s(),
            homed_bits: joint_flags_byte(&self.homed),
            io_bits: io,
            temperature_error_bits: JOINT_BITS_ALWAYS_SET,
            position_error_bits: JOINT_BITS_ALWAYS_SET,
            timing_ticks: self.timing_ticks,
            timeout_error: 100,
            echoed_command: self.last.map_or(CommandCode::Idle.byte(), |c| c.code),
            gripper_id: 0,
            gripper_position: self.gripper_position,
            gripper_speed: 1,
            gripper_current_ma: self.gripper_current_ma,
            gripper_status: self.gripper_status,
            gripper_object_byte: 1,
        }
    }
}

fn stage_moves(stage: u8, joint: usize) -> bool {
    match stage {
        0 => joint < 3,
        1 => joint == 3,
        2 => joint >= 4,
        _ => false,
    }
}

/// One command frame as the emulator received it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReceivedFrame {
    /// When the last byte of the frame was read.
    pub at: Instant,
    /// The decoded frame.
    pub command: ReceivedCommand,
}

/// Emulator state published after every accepted frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EmulatorSnapshot {
    /// Step counters.
    pub position_steps: [i32; JOINT_COUNT],
    /// Speed set points, steps/s.
    pub speed_steps_s: [i32; JOINT_COUNT],
    /// Homed flags.
    pub homed: [bool; JOINT_COUNT],
    /// DISABLE latch set.
    pub disabled: bool,
    /// Homing sequence running.
    pub homing: bool,
    /// Code of the last accepted frame.
    pub last_code: Option<u8>,
    /// OUTPUT1 and OUTPUT2 as the last accepted frame set them.
    pub outputs: [bool; 2],
    /// Frames accepted so far.
    pub frames_accepted: u64,
    /// Frames stored but rejected by the firmware parser.
    pub frames_rejected: u64,
}

/// Alters status replies before they are sent (fault injection for tests: bit flips, garbage,
/// delays). Called with the index of the reply; returns an extra delay before sending it.
pub type StatusCorruptor = Box<dyn FnMut(u64, &mut StatusFrame) -> Duration + Send>;

/// Most received frames kept in the log by default ([`EmulatorConfig::log_frames_max`]).
pub const LOG_CAP: usize = 200_000;

struct Shared {
    stop: AtomicBool,
    estop_pressed: AtomicBool,
    in1: AtomicBool,
    in2: AtomicBool,
    /// Extra latency added before each reply, µs (tests of link loss).
    reply_delay_us: AtomicU64,
    /// When set, frames are accepted but not answered (a silent board).
    mute: AtomicBool,
    log: Mutex<Vec<ReceivedFrame>>,
    snapshot: ArcSwap<EmulatorSnapshot>,
    corruptor: Mutex<Option<StatusCorruptor>>,
}

/// A running emulator on a pseudo-terminal. Dropping it stops the thread and closes the pty.
pub struct EmulatorHandle {
    path: String,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for EmulatorHandle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EmulatorHandle").field("path", &self.path).finish()
    }
}

impl EmulatorHandle {
    /// Opens a pty pair and serves the firmware model on its master side (for hosts in other
    /// processes, `parol6 hw emulate`, and the tests of the serial path). Its bytes pass the
    /// kernel's tty worker, which a very busy host delays by tens of ms: a host in this
    /// process uses [`EmulatorHandle::spawn_socket`].
    #[cfg(unix)]
    pub fn spawn(config: EmulatorConfig) -> Result<EmulatorHandle, crate::HwError> {
        let (mut master, slave) = serialport::TTYPort::pair()
            .map_err(|e| crate::HwError::Emulator(format!("cannot open a pseudo-terminal: {e}")))?;
        let path = serialport::SerialPort::name(&slave)
            .ok_or_else(|| crate::HwError::Emulator("pseudo-terminal has no path".into()))?;
        serialport::SerialPort::set_timeout(&mut master, Duration::from_millis(2))
            .map_err(|e| crate::HwError::Emulator(e.to_string()))?;
        // Keep the slave open so the master never sees a hang-up between host sessions.
        Self::start(path, master, slave, config)
    }

    /// Serves the firmware model on a local socket (the fake robot, `--fake-robot`): its path
    /// opens with [`crate::ports::open_port`] like a serial port, and its bytes reach the other
    /// side without waiting for a kernel worker, so the emulated board answers in time on a
    /// host with every core busy, as a real board would ([`crate::socket_link`]).
    #[cfg(unix)]
    pub fn spawn_socket(config: EmulatorConfig) -> Result<EmulatorHandle, crate::HwError> {
        let server = crate::socket_link::SocketServer::bind()
            .map_err(|e| crate::HwError::Emulator(format!("cannot open the fake robot's socket: {e}")))?;
        let path = server.path().to_str().map(str::to_string);
        let path = path.ok_or_else(|| crate::HwError::Emulator("the socket's path is not UTF-8".into()))?;
        Self::start(path, server, (), config)
    }

    /// Starts the emulator thread on `wire`; `keep` lives as long as the thread.
    #[cfg(unix)]
    fn start<W, K>(path: String, wire: W, keep: K, config: EmulatorConfig) -> Result<EmulatorHandle, crate::HwError>
    where
        W: Read + Write + Send + 'static,
        K: Send + 'static,
    {
        let model = ControllerModel::new(config.clone());
        let shared = Arc::new(Shared {
            stop: AtomicBool::new(false),
            estop_pressed: AtomicBool::new(false),
            in1: AtomicBool::new(false),
            in2: AtomicBool::new(false),
            reply_delay_us: AtomicU64::new(0),
            mute: AtomicBool::new(false),
            log: Mutex::new(Vec::new()),
            snapshot: ArcSwap::from_pointee(snapshot_of(&model, 0, 0)),
            corruptor: Mutex::new(None),
        });
        let sh = Arc::clone(&shared);
        let log_max = if config.log_commands { config.log_frames_max } else { 0 };
        let thread = std::thread::Builder::new()
            .name("parol6-emulator".into())
            .spawn(move || {
                let _keep = keep;
                // The emulated board must answer in time on a loaded desktop, like the real one.
                crate::priority::raise_current_thread();
                serve::serve(wire, model, &sh, log_max);
            })
            .map_err(|e| crate::HwError::Emulator(e.to_string()))?;
        Ok(EmulatorHandle { path, shared, thread: Some(thread) })
    }

    /// Path of the host's side (the pty's slave or the socket): open it as the serial port.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// Presses (true) or releases (false) the E-stop input.
    pub fn set_estop_pressed(&self, pressed: bool) {
        self.shared.estop_pressed.store(pressed, Ordering::Relaxed);
    }

    /// Sets the INPUT1 / INPUT2 levels.
    pub fn set_inputs(&self, in1: bool, in2: bool) {
        self.shared.in1.store(in1, Ordering::Relaxed);
        self.shared.in2.store(in2, Ordering::Relaxed);
    }

    /// Accept frames but stop answering them (true), or answer again (false).
    pub fn set_mute(&self, mute: bool) {
        self.shared.mute.store(mute, Ordering::Relaxed);
    }

    /// Delay added before every reply.
    pub fn set_reply_delay(&self, delay: Duration) {
        self.shared.reply_delay_us.store(delay.as_micros() as u64, Ordering::Relaxed);
    }

    /// Alters every status reply from now on (`None`: answer truthfully again).
    pub fn set_status_corruptor(&self, corruptor: Option<StatusCorruptor>) {
        match self.shared.corruptor.lock() {
            Ok(mut c) => *c = corruptor,
            Err(p) => *p.into_inner() = corruptor,
        }
    }

    /// Latest emulator state.
    pub fn snapshot(&self) -> Arc<EmulatorSnapshot> {
        self.shared.snapshot.load_full()
    }

    /// Takes (and clears) the log of received frames.
    pub fn take_received(&self) -> Vec<ReceivedFrame> {
        match self.shared.log.lock() {
            Ok(mut log) => std::mem::take(&mut *log),
            Err(poisoned) => std::mem::take(&mut *poisoned.into_inner()),
        }
    }

    /// Stops the emulator and closes the pty (a host sees the port vanish).
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for EmulatorHandle {
    fn drop(&mut self) {
        self.shutdown();
    }
}

fn snapshot_of(m: &ControllerModel, accepted: u64, rejected: u64) -> EmulatorSnapshot {
    EmulatorSnapshot {
        position_steps: m.position_steps(),
        speed_steps_s: m.speed_steps_s(),
        homed: m.homed(),
        disabled: m.is_disabled(),
        homing: m.is_homing(),
        last_code: m.last_code(),
        outputs: [m.out_bits & IO_OUT1 != 0, m.out_bits & IO_OUT2 != 0],
        frames_accepted: accepted,
        frames_rejected: rejected,
    }
}

mod serve;

#[cfg(test)]
mod tests;

//! [`SimHandle`]: a [`Simulation`] on its own thread, stepping at a fixed rate of simulated
//! time locked to wall-clock time. Commands arrive through a bounded channel; the sender
//! unparks the thread, which applies them at once (between steps). Between ticks the thread is
//! parked (a futex wait: no spinning). The latest state is published lock-free after every
//! step.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use arc_swap::ArcSwap;
use crossbeam_channel::{Receiver, Sender, TryRecvError, TrySendError};

use super::{SimCommand, SimConfig, SimError, SimSnapshot, Simulation};
use crate::model::RobotModel;
use crate::motion::{BackendError, IoCommand, MotionCommand, MotionSample, RobotBackend, RobotState};
use crate::process::thread_cpu_time_ns;

/// Capacity of the command channel.
pub const COMMAND_QUEUE: usize = 1024;
/// Capacity of the latency log read by [`SimHandle::drain_latencies_ns`].
pub const LATENCY_LOG: usize = 65_536;
/// Steps taken per wake-up of the thread (each is one fixed time step, catching up with the
/// wall clock). Waking costs about 30 µs of CPU on a virtual machine, so waking every step at
/// 1 kHz would cost 3 % of a core alone; commands still wake the thread at once.
const STEPS_PER_WAKE: u32 = 4;
/// When the thread falls this many steps behind wall-clock time it gives up catching up.
const MAX_CATCH_UP_STEPS: u32 = 20;
/// Steps per wake-up while the arm rests with nothing commanded or scheduled
/// ([`Simulation::dormant`]; 100 ms at 1 kHz). Nothing moves, so the published state stays
/// true; every step is still taken (the tap gets a sample every 10 ms); a command still wakes the
/// thread at once, and the thread first brings the simulated clock up to wall-clock time so
/// that the command starts now. Waking every 4 ms cost ~1 % of a core in an idle window.
const DORMANT_STEPS_PER_WAKE: u32 = 100;

struct Envelope {
    cmd: SimCommand,
    created: Instant,
}

/// Counters of the simulation thread.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimStats {
    /// Steps taken.
    pub steps: u64,
    /// Times the thread fell more than 20 steps behind and dropped the backlog.
    pub overruns: u64,
    /// Commands applied (accepted or refused).
    pub commands: u64,
    /// Times the thread woke and stepped (every 4 steps while anything moves, every 100 at rest).
    pub wakes: u64,
    /// CPU time the simulation thread has used, ns (`None` where the OS gives no per-thread
    /// CPU clock).
    pub thread_cpu_ns: Option<u64>,
    /// Wall time since the thread started, ns.
    pub wall_ns: u64,
}

impl SimStats {
    /// Fraction of one core the thread used (CPU time / wall time).
    pub fn cpu_fraction(&self) -> Option<f64> {
        let cpu = self.thread_cpu_ns?;
        (self.wall_ns > 0).then(|| cpu as f64 / self.wall_ns as f64)
    }
}

#[derive(Default)]
struct Counters {
    steps: AtomicU64,
    overruns: AtomicU64,
    commands: AtomicU64,
    wakes: AtomicU64,
    cpu_ns: AtomicU64,
    has_cpu: AtomicBool,
    wall_ns: AtomicU64,
}

struct Shared {
    snapshot: ArcSwap<SimSnapshot>,
    state: ArcSwap<RobotState>,
    stop: AtomicBool,
    counters: Counters,
}

/// A simulation running on its own thread. Dropping it stops the thread.
pub struct SimHandle {
    tx: Sender<Envelope>,
    shared: Arc<Shared>,
    latency_rx: Receiver<u64>,
    join: Option<JoinHandle<()>>,
    sim_thread: std::thread::Thread,
    model: RobotModel,
}

impl std::fmt::Debug for SimHandle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimHandle").field("robot", &self.model.name).finish_non_exhaustive()
    }
}

impl SimHandle {
    /// Builds the simulation (errors are returned here) and starts its thread.
    pub fn spawn(model: RobotModel, config: SimConfig) -> Result<SimHandle, SimError> {
        Self::spawn_with_tap(model, config, None)
    }

    /// [`SimHandle::spawn`] with a tap that receives a [`MotionSample`] of every step, of every
    /// tenth while the arm rests (dropped, never waited for, when full).
    pub fn spawn_with_tap(
        model: RobotModel,
        config: SimConfig,
        tap: Option<Sender<MotionSample>>,
    ) -> Result<SimHandle, SimError> {
        let time_scale = config.time_scale;
        let mut sim = Simulation::new(model.clone(), config)?;
        sim.set_tap(tap);
        let first = sim.snapshot();
        let (tx, rx) = crossbeam_channel::bounded(COMMAND_QUEUE);
        let (latency_tx, latency_rx) = crossbeam_channel::bounded(LATENCY_LOG);
        let shared = Arc::new(Shared {
            state: ArcSwap::from_pointee(first.robot_state()),
            snapshot: ArcSwap::from_pointee(first),
            stop: AtomicBool::new(false),
            counters: Counters::default(),
        });
        let thread_shared = Arc::clone(&shared);
        let join = std::thread::Builder::new()
            .name("parol6-sim".into())
            .spawn(move || run(sim, &rx, &latency_tx, &thread_shared, time_scale))
            .map_err(|e| SimError::Build(format!("cannot start the simulation thread: {e}")))?;
        let sim_thread = join.thread().clone();
        Ok(SimHandle { tx, shared, latency_rx, join: Some(join), sim_thread, model })
    }

    /// Queues a command, stamped with the current instant. Never blocks.
    pub fn send(&self, cmd: SimCommand) -> Result<(), SimError> {
        match self.tx.try_send(Envelope { cmd, created: Instant::now() }) {
            Ok(()) => {
                self.sim_thread.unpark();
                Ok(())
            }
            Err(TrySendError::Full(_)) => Err(SimError::ChannelFull),
            Err(TrySendError::Disconnected(_)) => Err(SimError::ChannelClosed),
        }
    }

    /// The latest published state (lock-free).
    pub fn snapshot(&self) -> Arc<SimSnapshot> {
        self.shared.snapshot.load_full()
    }

    /// The robot model the simulation was built from.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// Thread counters (steps, overruns, CPU time).
    pub fn stats(&self) -> SimStats {
        let c = &self.shared.counters;
        SimStats {
            steps: c.steps.load(Ordering::Relaxed),
            overruns: c.overruns.load(Ordering::Relaxed),
            commands: c.commands.load(Ordering::Relaxed),
            wakes: c.wakes.load(Ordering::Relaxed),
            thread_cpu_ns: c.has_cpu.load(Ordering::Relaxed).then(|| c.cpu_ns.load(Ordering::Relaxed)),
            wall_ns: c.wall_ns.load(Ordering::Relaxed),
        }
    }

    /// Creation → applied latencies (ns) of the commands applied since the last call, oldest
    /// first (at most `LATENCY_LOG` are kept).
    pub fn drain_latencies_ns(&self) -> Vec<u64> {
        self.latency_rx.try_iter().collect()
    }

    /// Stops the thread and waits for it.
    pub fn shutdown(mut self) {
        self.stop_thread();
    }

    fn stop_thread(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        self.sim_thread.unpark();
        if let Some(j) = self.join.take() {
            let _ = j.join();
        }
    }
}

impl Drop for SimHandle {
    fn drop(&mut self) {
        self.stop_thread();
    }
}

fn run(mut sim: Simulation, rx: &Receiver<Envelope>, latency_tx: &Sender<u64>, shared: &Shared, time_scale: f64) {
    let scale = if time_scale.is_finite() && time_scale > 0.0 { time_scale } else { 1.0 };
    let dt = Duration::from_secs_f64(sim.dt_s() / scale);
    let started = Instant::now();
    let cpu_start = thread_cpu_time_ns();
    let mut next = started + dt;
    let mut rate_window = (started, 0u64);
    let c = &shared.counters;
    loop {
        if shared.stop.load(Ordering::Acquire) {
            break;
        }
        if sim.dormant() && !rx.is_empty() {
            // woken from a long sleep: catch up first, so the command is applied at the
            // simulated time of its arrival
            let now = Instant::now();
            let mut n = 0;
            while next <= now && n < DORMANT_STEPS_PER_WAKE + MAX_CATCH_UP_STEPS {
                sim.step();
                next += dt;
                n += 1;
            }
            c.steps.fetch_add(u64::from(n), Ordering::Relaxed);
        }
        // apply whatever has arrived
        loop {
            match rx.try_recv() {
                Ok(env) => {
                    if let Err(e) = sim.apply(env.cmd) {
                        sim.record_error(&e);
                    }
                    let applied = Instant::now();
                    sim.record_latency(env.created, applied);
                    let ns =
                        u64::try_from(applied.saturating_duration_since(env.created).as_nanos()).unwrap_or(u64::MAX);
                    let _ = latency_tx.try_send(ns);
                    c.commands.fetch_add(1, Ordering::Relaxed);
                }
                Err(TryRecvError::Empty) => break,
                // every handle is gone: nobody can read the state any more
                Err(TryRecvError::Disconnected) => return,
            }
        }
        let now = Instant::now();
        let per_wake = if sim.dormant() { DORMANT_STEPS_PER_WAKE } else { STEPS_PER_WAKE };
        let wake_at = next + dt * (per_wake - 1);
        if now < wake_at {
            // woken early by `send` (or spuriously): loop to apply, then wait again
            std::thread::park_timeout(wake_at - now);
            continue;
        }
        let now = Instant::now();
        let mut n = 0;
        // (while dormant, the steps of one wake-up on top of the usual allowance)
        while next <= now && n < MAX_CATCH_UP_STEPS + per_wake - STEPS_PER_WAKE {
            sim.step();
            next += dt;
            n += 1;
        }
        if next <= now {
            next = now + dt;
            c.overruns.fetch_add(1, Ordering::Relaxed);
        }
        c.wakes.fetch_add(1, Ordering::Relaxed);
        let steps = c.steps.fetch_add(u64::from(n), Ordering::Relaxed) + u64::from(n);
        // measured step rate over windows of about half a second
        let since = now.saturating_duration_since(rate_window.0);
        if since >= Duration::from_millis(500) {
            sim.set_step_rate_hz((steps - rate_window.1) as f64 / since.as_secs_f64());
            rate_window = (now, steps);
            c.wall_ns
                .store(u64::try_from(now.duration_since(started).as_nanos()).unwrap_or(u64::MAX), Ordering::Relaxed);
            if let (Some(a), Some(b)) = (cpu_start, thread_cpu_time_ns()) {
                c.cpu_ns.store(b.saturating_sub(a), Ordering::Relaxed);
                c.has_cpu.store(true, Ordering::Relaxed);
            }
        }
        let snap = sim.snapshot();
        shared.state.store(Arc::new(snap.robot_state()));
        shared.snapshot.store(Arc::new(snap));
    }
}

impl RobotBackend for SimHandle {
    fn submit(&self, cmd: MotionCommand, at_s: Option<f64>) -> Result<(), BackendError> {
        cmd.validate(&self.model.limits)?;
        let sc = match at_s {
            None => SimCommand::Motion(cmd),
            Some(at_s) => SimCommand::MotionAt { cmd, at_s },
        };
        self.send(sc).map_err(|e| match e {
            SimError::ChannelFull => BackendError::QueueFull,
            SimError::ChannelClosed => BackendError::Closed,
            other => BackendError::Refused(other.to_string()),
        })
    }

    fn state(&self) -> Arc<RobotState> {
        self.shared.state.load_full()
    }

    fn io(&self, cmd: IoCommand) -> Result<(), BackendError> {
        cmd.validate().map_err(BackendError::Refused)?;
        self.send(SimCommand::Io(cmd)).map_err(|e| match e {
            SimError::ChannelFull => BackendError::QueueFull,
            SimError::ChannelClosed => BackendError::Closed,
            other => BackendError::Refused(other.to_string()),
        })
    }
}

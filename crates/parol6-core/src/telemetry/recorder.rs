//! [`Recorder`]: the telemetry thread. Backends push [`MotionSample`]s into its bounded tap
//! ([`Recorder::tap`], given to `SimHandle::spawn_with_tap` or `Session::open_with_tap`);
//! callers push states, link health, program steps and events through a second bounded
//! channel. Nothing here ever blocks a sender: a full channel drops the message and counts it,
//! and samples a backend could not deliver show up as gaps in its sequence numbers
//! ([`RecorderStats::missing_samples`]).
//!
//! The thread builds a [`TelemetrySample`](super::sample::TelemetrySample) per tick, finds events, keeps the last
//! [`RecorderConfig::live_span_s`] in a [`LiveRing`] published lock-free as a [`LiveView`]
//! ([`Recorder::live`]), and while recording writes an MCAP file through [`McapSink`].
//!
//! Live servers take the samples and events from a [`LiveOutlet`] ([`Recorder::live_outlet`]):
//! a bounded channel the thread `try_send`s every built sample and every event into (every
//! sample while an outlet is open, not only the live view's 250 Hz). A full outlet drops the
//! item and counts it ([`LiveOutlet::dropped`]); the recorder never waits on a live server, and
//! an outlet whose receiver is gone is closed.
//!
//! One recorder serves one backend (one sequence of tick numbers).

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use arc_swap::ArcSwap;
use crossbeam_channel::{Receiver, Sender, TryRecvError, TrySendError, bounded};

use crate::limits::ZoneThresholds;
use crate::model::RobotModel;
use crate::motion::{MotionSample, RobotState};

use super::TelemetryError;
use super::event::{EventDetector, TelemetryEvent};
use super::ring::{LiveRing, LiveView};
use super::sample::{LinkHealth, SampleBuilder};
use super::writer::{McapSink, RecordingInfo, RecordingSummary, SyncedFile};

pub use outlets::{LiveItem, LiveOutlet, RecorderEvents};
use outlets::{Outlet, send_control};

/// Settings of a [`Recorder`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecorderConfig {
    /// Seconds of history the live view keeps (600: ten minutes).
    pub live_span_s: f64,
    /// Highest sample rate the live view keeps, Hz (1 000); files get every sample.
    pub live_rate_hz: f64,
    /// Seconds of the newest history the live view keeps at that rate (60); older samples
    /// are kept as their 4 ms min/max summary (`series::SUMMARY_BUCKET_S`).
    pub live_full_rate_s: f64,
    /// Capacity of the sample tap (16 384: 16 s at 1 kHz; the thread empties it every 20 ms).
    pub tap_capacity: usize,
    /// Capacity of the control channel.
    pub control_capacity: usize,
    /// Limit-zone thresholds of the samples' zones.
    pub thresholds: ZoneThresholds,
    /// How often the live view is published, s.
    pub publish_interval_s: f64,
}

impl Default for RecorderConfig {
    fn default() -> Self {
        Self {
            live_span_s: 600.0,
            live_rate_hz: 1000.0,
            live_full_rate_s: 60.0,
            tap_capacity: 16_384,
            control_capacity: 1024,
            thresholds: ZoneThresholds::default(),
            publish_interval_s: 0.05,
        }
    }
}

/// Counters of the recorder.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RecorderStats {
    /// Samples received.
    pub samples: u64,
    /// Samples missing: gaps in the backend's tick numbers (its tap was full).
    pub missing_samples: u64,
    /// Control messages dropped because the control channel was full.
    pub control_dropped: u64,
    /// Events found or received.
    pub events: u64,
    /// Samples written to the current or last file.
    pub recorded_samples: u64,
    /// CPU time of the recorder thread, ns (0 where the OS gives no per-thread clock).
    pub thread_cpu_ns: u64,
}

enum Control {
    State(Arc<RobotState>),
    Link(LinkHealth),
    ProgramStep(Option<usize>),
    Event(TelemetryEvent),
    /// A file to write from now on; the reply says the thread took it.
    Start(Box<McapSink<SyncedFile>>, Sender<()>),
    Stop(Sender<Result<Option<RecordingSummary>, TelemetryError>>),
    Finish(Sender<Result<Option<RecordingSummary>, TelemetryError>>),
    Outlet(Outlet),
    /// Whether the live view keeps rows ([`Recorder::keep_live_rows`]).
    LiveRows(bool),
}

impl std::fmt::Debug for Control {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Control")
    }
}

impl std::fmt::Debug for Shared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Shared")
    }
}

#[derive(Default)]
struct Counters {
    samples: AtomicU64,
    missing: AtomicU64,
    control_dropped: AtomicU64,
    events: AtomicU64,
    recorded: AtomicU64,
    cpu_ns: AtomicU64,
}

struct Shared {
    live: ArcSwap<LiveView>,
    last_error: ArcSwap<Option<String>>,
    counters: Counters,
}

/// The telemetry recorder. See the module docs. Dropping it stops the thread and finishes a
/// file being written.
pub struct Recorder {
    tap: Sender<MotionSample>,
    control: Sender<Control>,
    shared: Arc<Shared>,
    join: Option<JoinHandle<()>>,
    model: RobotModel,
}

impl std::fmt::Debug for Recorder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Recorder").field("robot", &self.model.name).finish_non_exhaustive()
    }
}

/// The recorder thread takes what has arrived this often.
const TICK: Duration = Duration::from_millis(20);
/// While the last sample shows the arm still, it wakes this seldom instead (about 0.3 % of a
/// core saved in an idle window); a control message (start, stop …) still wakes it at once.
const STILL_TICK: Duration = Duration::from_millis(100);
/// While the arm is still, the live view is published at most this often.
const STILL_PUBLISH: Duration = Duration::from_millis(500);
/// Joint speeds below this count as still, rad/s (the simulation rests below it).
const STILL_QD_RAD_S: f64 = 1e-4;

/// How long start / stop wait for the thread.
const REPLY_TIMEOUT: Duration = Duration::from_secs(10);

impl Recorder {
    /// Starts the recorder thread for `model`'s joints.
    pub fn start(model: RobotModel, config: RecorderConfig) -> Result<Self, TelemetryError> {
        let (tap, tap_rx) = bounded(config.tap_capacity.max(1));
        let (control, control_rx) = bounded(config.control_capacity.max(1));
        let shared = Arc::new(Shared {
            live: ArcSwap::from_pointee(LiveView::default()),
            last_error: ArcSwap::from_pointee(None),
            counters: Counters::default(),
        });
        let worker = Worker {
            builder: SampleBuilder::new(model.clone(), config.thresholds),
            detector: EventDetector::with_limits(model.limits.clone(), config.thresholds),
            ring: LiveRing::new(model.dof(), config.live_span_s, config.live_full_rate_s, config.live_rate_hz),
            sink: None,
            last_seq: None,
            last_time_s: 0.0,
            events: Vec::new(),
            early_events: Vec::new(),
            shared: Arc::clone(&shared),
            publish_every: Duration::from_secs_f64(config.publish_interval_s.clamp(0.001, 10.0)),
            dirty: false,
            still: false,
            outlets: Vec::new(),
        };
        let join = std::thread::Builder::new()
            .name("parol6-recorder".into())
            .spawn(move || worker.run(&tap_rx, &control_rx))
            .map_err(|e| TelemetryError::State(format!("cannot start the recorder thread: {e}")))?;
        Ok(Self { tap, control, shared, join: Some(join), model })
    }

    /// A sender for a backend's sample tap.
    pub fn tap(&self) -> Sender<MotionSample> {
        self.tap.clone()
    }

    fn send(&self, c: Control) {
        send_control(&self.control, &self.shared, c);
    }

    /// A handle that adds events from other threads (the live servers' network commands).
    pub fn events(&self) -> RecorderEvents {
        RecorderEvents { control: self.control.clone(), shared: Arc::clone(&self.shared) }
    }

    /// Opens a live outlet of `capacity` items (see the module docs). The thread takes it with
    /// its next control messages (at once, or within 20 ms while the arm moves).
    pub fn live_outlet(&self, capacity: usize) -> Result<LiveOutlet, TelemetryError> {
        let (tx, rx) = bounded(capacity.max(1));
        let dropped = Arc::new(AtomicU64::new(0));
        self.control
            .send_timeout(Control::Outlet(Outlet { tx, dropped: Arc::clone(&dropped) }), REPLY_TIMEOUT)
            .map_err(|_| TelemetryError::Stopped)?;
        Ok(LiveOutlet { rx, dropped })
    }

    /// Whether the live view keeps its ten minutes (the default) or nothing, for a backend the
    /// window does not show (`LiveRing::set_rows_kept`); files and outlets get every sample.
    pub fn keep_live_rows(&self, on: bool) {
        self.send(Control::LiveRows(on));
    }

    /// The backend's latest state: refusals and blocked/allowed changes become events.
    pub fn observe_state(&self, state: Arc<RobotState>) {
        self.send(Control::State(state));
    }

    /// The link health stamped on the coming samples; E-stop and link-loss changes become events.
    pub fn set_link_health(&self, health: LinkHealth) {
        self.send(Control::Link(health));
    }

    /// The program step stamped on the coming samples.
    pub fn set_program_step(&self, step: Option<usize>) {
        self.send(Control::ProgramStep(step));
    }

    /// Records an event (a NaN time takes the latest sample's).
    pub fn event(&self, event: TelemetryEvent) {
        self.send(Control::Event(event));
    }

    /// Starts writing an MCAP file at `path` (created here: errors are returned at once).
    /// Returns once the thread writes it: every sample delivered after this call is in the file
    /// (samples already waiting in the tap may be too).
    pub fn start_recording(&self, path: &Path, info: &RecordingInfo) -> Result<(), TelemetryError> {
        let sink = McapSink::create_file(path, &self.model, info)?;
        let (tx, rx) = bounded(1);
        self.control
            .send_timeout(Control::Start(Box::new(sink), tx), REPLY_TIMEOUT)
            .map_err(|_| TelemetryError::Stopped)?;
        rx.recv_timeout(REPLY_TIMEOUT).map_err(|_| TelemetryError::Stopped)
    }

    /// Stops writing: closes the file with its summary and index.
    pub fn stop_recording(&self) -> Result<Option<RecordingSummary>, TelemetryError> {
        let (tx, rx) = bounded(1);
        self.control.send_timeout(Control::Stop(tx), REPLY_TIMEOUT).map_err(|_| TelemetryError::Stopped)?;
        rx.recv_timeout(REPLY_TIMEOUT).map_err(|_| TelemetryError::Stopped)?
    }

    /// Takes every sample already delivered, finishes the file (if recording) and stops the
    /// thread.
    pub fn finish(mut self) -> Result<Option<RecordingSummary>, TelemetryError> {
        let (tx, rx) = bounded(1);
        self.control.send_timeout(Control::Finish(tx), REPLY_TIMEOUT).map_err(|_| TelemetryError::Stopped)?;
        let result = rx.recv_timeout(REPLY_TIMEOUT).map_err(|_| TelemetryError::Stopped)?;
        if let Some(j) = self.join.take() {
            let _ = j.join();
        }
        result
    }

    /// As [`Self::finish`], and then the live view with every sample delivered until now: the
    /// last rows of a backend that goes away (a disconnect), up to 50 ms (500 ms while the arm
    /// was still) newer than the last published view.
    pub fn finish_with_live(self) -> (Result<Option<RecordingSummary>, TelemetryError>, Arc<LiveView>) {
        let shared = Arc::clone(&self.shared);
        let finished = self.finish();
        (finished, shared.live.load_full())
    }

    /// The live view (lock-free; published every [`RecorderConfig::publish_interval_s`]).
    pub fn live(&self) -> Arc<LiveView> {
        self.shared.live.load_full()
    }

    /// The counters.
    pub fn stats(&self) -> RecorderStats {
        let c = &self.shared.counters;
        RecorderStats {
            samples: c.samples.load(Ordering::Relaxed),
            missing_samples: c.missing.load(Ordering::Relaxed),
            control_dropped: c.control_dropped.load(Ordering::Relaxed),
            events: c.events.load(Ordering::Relaxed),
            recorded_samples: c.recorded.load(Ordering::Relaxed),
            thread_cpu_ns: c.cpu_ns.load(Ordering::Relaxed),
        }
    }

    /// The last write error (the recording stopped there), if any.
    pub fn last_error(&self) -> Option<String> {
        (**self.shared.last_error.load()).clone()
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        if let Some(j) = self.join.take() {
            let (tx, _rx) = bounded(1);
            let _ = self.control.send_timeout(Control::Finish(tx), REPLY_TIMEOUT);
            let _ = j.join();
        }
    }
}

struct Worker {
    builder: SampleBuilder,
    detector: EventDetector,
    ring: LiveRing,
    sink: Option<McapSink<SyncedFile>>,
    last_seq: Option<u64>,
    last_time_s: f64,
    events: Vec<TelemetryEvent>,
    /// Events raised before the first sample (stamped with its time).
    early_events: Vec<TelemetryEvent>,
    shared: Arc<Shared>,
    publish_every: Duration,
    dirty: bool,
    /// The last sample showed the arm still: nothing commanded, nothing moving.
    still: bool,
    /// Open live outlets.
    outlets: Vec<Outlet>,
}

impl Worker {
    /// Wakes every [`TICK`] and takes whatever has arrived: a wake-up costs tens of µs on a
    /// virtual machine, so waking per sample (or per burst of the simulation) would cost more
    /// than the work.
    fn run(mut self, tap: &Receiver<MotionSample>, control: &Receiver<Control>) {
        let cpu_start = crate::process::thread_cpu_time_ns();
        let mut next_publish = Instant::now() + self.publish_every;
        'run: loop {
            let mut woken_by = None;
            if self.still {
                // a disconnected channel answers at once; the loop below then stops
                woken_by = control.recv_timeout(STILL_TICK).ok();
            } else {
                std::thread::sleep(TICK);
            }
            // control messages first, so that what was sent before a sample applies to it (a
            // program step, a file to write); stopping takes every sample delivered before it
            loop {
                match woken_by.take().map_or_else(|| control.try_recv(), Ok) {
                    Ok(Control::Finish(reply)) => {
                        self.drain(tap);
                        let _ = reply.send(self.stop());
                        break 'run;
                    }
                    Ok(c) => {
                        if matches!(c, Control::Stop(_)) {
                            self.drain(tap);
                        }
                        self.control(c);
                    }
                    Err(TryRecvError::Empty) => break,
                    // the Recorder is gone
                    Err(TryRecvError::Disconnected) => {
                        self.drain(tap);
                        let _ = self.stop();
                        break 'run;
                    }
                }
            }
            self.drain(tap);
            if let Some(sink) = self.sink.as_mut()
                && let Err(e) = sink.flush_if_due(self.last_time_s)
            {
                self.fail(e);
            }
            let now = Instant::now();
            if now >= next_publish {
                // a view copies the newest (unsealed) block: while still, seldom
                next_publish =
                    now + if self.still { self.publish_every.max(STILL_PUBLISH) } else { self.publish_every };
                self.publish();
                if let (Some(a), Some(b)) = (cpu_start, crate::process::thread_cpu_time_ns()) {
                    self.shared.counters.cpu_ns.store(b.saturating_sub(a), Ordering::Relaxed);
                }
            }
        }
        self.publish();
        if let (Some(a), Some(b)) = (cpu_start, crate::process::thread_cpu_time_ns()) {
            self.shared.counters.cpu_ns.store(b.saturating_sub(a), Ordering::Relaxed);
        }
    }

    /// Takes every sample waiting in the tap.
    fn drain(&mut self, tap: &Receiver<MotionSample>) {
        while let Ok(m) = tap.try_recv() {
            self.sample(&m);
        }
    }

    fn sample(&mut self, m: &MotionSample) {
        let c = &self.shared.counters;
        if let Some(last) = self.last_seq {
            if m.seq == last {
                // the same tick published again (a session's closing frame): nothing new
                return;
            }
            if m.seq > last + 1 {
                c.missing.fetch_add(m.seq - last - 1, Ordering::Relaxed);
            }
        }
        self.last_seq = Some(m.seq);
        self.still = m.commanded.qd.iter().all(|v| *v == 0.0) && m.measured_qd.iter().all(|v| v.abs() < STILL_QD_RAD_S);
        c.samples.fetch_add(1, Ordering::Relaxed);
        if self.sink.is_none() && self.outlets.is_empty() && !self.ring.keeps(m.time_s) {
            // neither written nor kept by the live view (one sample per 4 ms): nothing to build
            // (the next built sample's acceleration spans the skipped ones)
            self.last_time_s = m.time_s;
            return;
        }
        let s = self.builder.build(m);
        self.last_time_s = s.time_s;
        for mut e in self.early_events.drain(..) {
            e.time_s = s.time_s;
            self.events.push(e);
        }
        self.ring.push(&s);
        self.detector.observe_sample(&s, &mut self.events);
        if let Some(sink) = self.sink.as_mut() {
            match sink.write_sample(&s) {
                Ok(()) => {
                    c.recorded.fetch_add(1, Ordering::Relaxed);
                }
                Err(e) => self.fail(e),
            }
        }
        if !self.outlets.is_empty() {
            let s = Arc::new(s);
            self.send_to_outlets(|| LiveItem::Sample(Arc::clone(&s)));
        }
        self.take_events();
        self.dirty = true;
    }

    /// `try_send`s an item to every open outlet: a full one drops it (counted), a closed one is
    /// removed.
    fn send_to_outlets(&mut self, item: impl Fn() -> LiveItem) {
        self.outlets.retain(|o| match o.tx.try_send(item()) {
            Ok(()) => true,
            Err(TrySendError::Full(_)) => {
                o.dropped.fetch_add(1, Ordering::Relaxed);
                true
            }
            Err(TrySendError::Disconnected(_)) => false,
        });
    }

    fn control(&mut self, c: Control) {
        match c {
            Control::State(st) => self.detector.observe_state(&st, &mut self.events),
            Control::Link(h) => {
                self.detector.observe_link(self.last_time_s, &h, &mut self.events);
                self.builder.link = Some(h);
            }
            Control::ProgramStep(step) => {
                if step != self.builder.program_step {
                    let message = match step {
                        Some(i) => format!("program step {}", i + 1),
                        None => "program ended".to_string(),
                    };
                    let kind = super::event::EventKind::ProgramStep { step };
                    let event = TelemetryEvent { time_s: self.last_time_s, kind, message };
                    // before the first sample there is no motion time yet: it takes the first's
                    if self.last_seq.is_none() { self.early_events.push(event) } else { self.events.push(event) }
                }
                self.builder.program_step = step;
            }
            Control::Event(mut e) => {
                if !e.time_s.is_finite() {
                    e.time_s = self.last_time_s;
                }
                self.events.push(e);
            }
            Control::Start(sink, reply) => {
                if let Err(e) = self.stop() {
                    self.fail(e);
                }
                self.shared.counters.recorded.store(0, Ordering::Relaxed);
                self.sink = Some(*sink);
                let _ = reply.send(());
            }
            Control::Stop(reply) => {
                let _ = reply.send(self.stop());
            }
            Control::Outlet(o) => self.outlets.push(o),
            Control::LiveRows(on) => {
                self.ring.set_rows_kept(on);
                self.dirty = true;
            }
            Control::Finish(_) => {}
        }
        self.take_events();
    }

    fn take_events(&mut self) {
        if self.events.is_empty() {
            return;
        }
        let events = std::mem::take(&mut self.events);
        for e in &events {
            self.ring.push_event(e);
            self.shared.counters.events.fetch_add(1, Ordering::Relaxed);
            if let Some(sink) = self.sink.as_mut()
                && let Err(err) = sink.write_event(e)
            {
                self.fail(err);
            }
            if !self.outlets.is_empty() {
                self.send_to_outlets(|| LiveItem::Event(e.clone()));
            }
        }
        self.events = events;
        self.events.clear();
        self.dirty = true;
    }

    fn stop(&mut self) -> Result<Option<RecordingSummary>, TelemetryError> {
        self.sink.take().map(McapSink::finish_file).transpose()
    }

    /// A write failed: the recording ends here (what was flushed stays readable).
    fn fail(&mut self, e: TelemetryError) {
        self.shared.last_error.store(Arc::new(Some(format!("recording stopped: {e}"))));
        self.sink = None;
    }

    fn publish(&mut self) {
        if self.dirty {
            self.shared.live.store(Arc::new(self.ring.view()));
            self.dirty = false;
        }
    }
}

mod outlets;
#[cfg(test)]
mod tests;

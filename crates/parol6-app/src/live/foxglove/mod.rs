//! The Foxglove WebSocket server: the official `foxglove` crate's server streaming our MCAP
//! channels live, so Foxglove or Lichtblick ("Open connection", `ws://ADDR`) shows the arm in its
//! 3D panel (URDF from `/robot_description`, links moved by `/tf`) and plots the joints
//! (`/joint_states.position[0]` …).
//!
//! - **Both names of the protocol**: the crate's server answers only `foxglove.sdk.v1` and
//!   listens on a loopback port; [`front`] listens at the public address and lets clients that
//!   offer only the former name `foxglove.websocket.v1` (Lichtblick 1.x) in too.
//! - **Channels**: every [`Channel`] of a recording, with the same topics, schema names, JSON
//!   schemas (`jsonschema`) and `json` messages, made by the same [`TelemetryEncoder`] at the
//!   same rates (`/joint_states`, `/joint_commands` every sample: 1 kHz from the simulation,
//!   100 Hz from the robot; `/tf`, `/tcp_pose` ≤ 100 Hz; `/link`, `/events` as they come).
//!   `/robot_description` is sent to each client when it subscribes to it (a late subscriber
//!   gets the URDF too). Only the channels some client subscribed to are encoded.
//! - **Threads**: a tokio runtime with one worker thread (owned here; no tokio type leaves this
//!   module) runs the server and its front; a pump thread takes the recorder's [`LiveOutlet`] every 20 ms
//!   ([`OUTLET_CAPACITY`] items; the recorder drops and counts when it is full), encodes and
//!   hands each message to the server, which queues it per client without waiting.
//! - **Slow clients are thinned, never waited for**: each client has a queue of
//!   [`CLIENT_BACKLOG`] messages (the crate's `message_backlog_size`); when it is full the
//!   **oldest** message is dropped to make room, so a client that reads too slowly gets a
//!   thinned stream of the newest messages and one that never reads holds at most that many.
//!   Memory per client: ≤ [`CLIENT_BACKLOG`] messages of ≤ 1.5 kB (a `/tf` message; a
//!   `/joint_states` message is ≈ 0.6 kB), ≈ 1.5 MB, plus one copy of the URDF text, plus the
//!   kernel's socket buffer. The crate's control queue (advertisements, status) has the same
//!   bound; a client that lets it fill is disconnected. The crate does not count the messages it
//!   drops for a client; the outlet's drops are counted ([`FoxgloveServer`]'s stats).
//! - **No commands**: the server advertises no client-publish, service or parameter capability,
//!   so a Foxglove client cannot send the arm anything.

use std::collections::BTreeMap;
use std::net::{Ipv4Addr, SocketAddr};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use foxglove::websocket::{ChannelView, Client, ServerListener};
use foxglove::{ChannelBuilder, Context, PartialMetadata, RawChannel, Schema, WebSocketServer, WebSocketServerHandle};
use parol6_core::telemetry::schema::{MESSAGE_ENCODING, SCHEMA_ENCODING};
use parol6_core::telemetry::{Channel, EncodeError, LiveItem, LiveOutlet, TelemetryEncoder};

use super::{LiveServer, LiveSource};

pub mod front;

/// Items the recorder's outlet holds for this server (≈ 4 s of a 1 kHz simulation; the pump
/// empties it continuously).
pub const OUTLET_CAPACITY: usize = 4096;

/// Messages queued per client before the oldest are dropped (the crate's default, ≈ 0.45 s of
/// every channel at full rate).
pub const CLIENT_BACKLOG: usize = 1024;

/// The pump takes what the outlet holds this often (the recorder fills it every 20 ms).
const PUMP_TICK: Duration = Duration::from_millis(20);

/// Its threads' names start with this (the CPU figure sums them).
const THREAD_PREFIX: &str = "parol6-foxglove";

/// Why the server could not start.
#[derive(Debug, thiserror::Error)]
pub enum FoxgloveError {
    /// The runtime, a channel, the listening socket or the pump thread could not be set up.
    #[error("{0}")]
    Start(String),
}

/// Counters shared by the pump, the listener and [`FoxgloveServer::stats`].
#[derive(Debug, Default)]
struct Counters {
    /// Messages handed to the server for at least one subscribed client.
    messages: AtomicU64,
    /// Bytes of those messages (JSON payloads).
    bytes: AtomicU64,
    /// Clients that connected.
    clients_seen: AtomicU64,
    /// `/robot_description` sent to a subscriber.
    descriptions: AtomicU64,
}

/// The channels, by ours.
type Channels = BTreeMap<Channel, Arc<RawChannel>>;

/// The Foxglove WebSocket server. See the module docs. Dropping it stops it.
pub struct FoxgloveServer {
    addr: SocketAddr,
    /// The server and the channels hold it weakly: it lives as long as the server.
    _context: Arc<Context>,
    handle: Option<WebSocketServerHandle>,
    /// The front door's accept loop (see [`front`]).
    front: Option<tokio::task::JoinHandle<()>>,
    runtime: Option<tokio::runtime::Runtime>,
    pump: Option<JoinHandle<()>>,
    stop: Arc<AtomicBool>,
    counters: Arc<Counters>,
    /// When it started, and the CPU its threads had used by then (none: they did not exist).
    started: std::time::Instant,
    /// CPU of its threads over its life, % of one core (set when it stops).
    cpu_percent: Option<f64>,
    outlet_dropped: Arc<dyn Fn() -> u64 + Send + Sync>,
}

impl std::fmt::Debug for FoxgloveServer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FoxgloveServer").field("addr", &self.addr).finish_non_exhaustive()
    }
}

/// Sends `/robot_description` to each client that subscribes to it, and counts clients.
struct Listener {
    description: Arc<RawChannel>,
    urdf_json: Vec<u8>,
    counters: Arc<Counters>,
}

impl ServerListener for Listener {
    fn on_subscribe(&self, client: Client, channel: ChannelView) {
        if channel.id() == self.description.id() {
            let meta = PartialMetadata::with_log_time(parol6_core::telemetry::writer::unix_now_ns());
            self.description.log_with_meta_to_sink(&self.urdf_json, meta, client.sink_id());
            self.counters.descriptions.fetch_add(1, Ordering::Relaxed);
        }
    }

    fn on_client_connect(&self) {
        self.counters.clients_seen.fetch_add(1, Ordering::Relaxed);
    }
}

impl FoxgloveServer {
    /// Starts the server on `source`'s recorder, listening at `addr` (port 0: a free port; see
    /// [`LiveServer::address`]).
    pub fn start(source: &LiveSource<'_>, addr: SocketAddr) -> Result<Self, FoxgloveError> {
        let start_err = |what: &str, e: &dyn std::fmt::Display| FoxgloveError::Start(format!("{what}: {e}"));
        let ctx = Context::new();
        let mut channels = Channels::new();
        for c in Channel::ALL {
            let schema = Schema::new(c.schema_name(), SCHEMA_ENCODING, c.schema_text().into_bytes());
            let channel = ChannelBuilder::new(c.topic())
                .context(&ctx)
                .message_encoding(MESSAGE_ENCODING)
                .schema(schema)
                .build_raw()
                .map_err(|e| start_err(c.topic(), &e))?;
            channels.insert(c, channel);
        }
        let encoder = TelemetryEncoder::new(source.model, Some(source.urdf_text), 0);
        let urdf_json = encoder.robot_description(source.urdf_text).map_err(|e| start_err("URDF", &e))?;
        let description = channels
            .get(&Channel::RobotDescription)
            .cloned()
            .ok_or_else(|| FoxgloveError::Start("no /robot_description channel".into()))?;
        let counters = Arc::new(Counters::default());
        let listener = Arc::new(Listener { description, urdf_json, counters: Arc::clone(&counters) });
        // one worker thread: a few clients at ≈ 2 k messages/s each need no more
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .thread_name(THREAD_PREFIX)
            .enable_all()
            .build()
            .map_err(|e| start_err("cannot start the server's runtime", &e))?;
        // the public address is the front's; the crate's server listens on loopback behind it
        let public =
            runtime.block_on(tokio::net::TcpListener::bind(addr)).map_err(|e| start_err("cannot listen", &e))?;
        let addr = public.local_addr().map_err(|e| start_err("cannot listen", &e))?;
        let server = WebSocketServer::new()
            .name(format!("PAROL6 Studio {} ({})", env!("CARGO_PKG_VERSION"), source.model.name))
            .context(&ctx)
            .bind(Ipv4Addr::LOCALHOST.to_string(), 0)
            .message_backlog_size(CLIENT_BACKLOG)
            .listener(listener);
        let handle = runtime.block_on(server.start()).map_err(|e| start_err("cannot listen on loopback", &e))?;
        let inner = SocketAddr::from((Ipv4Addr::LOCALHOST, handle.port()));
        let front = runtime.spawn(front::serve(public, inner));
        let outlet = source.recorder.live_outlet(OUTLET_CAPACITY).map_err(|e| start_err("recorder", &e))?;
        let dropped = Arc::new(outlet);
        let outlet_dropped: Arc<dyn Fn() -> u64 + Send + Sync> = {
            let o = Arc::clone(&dropped);
            Arc::new(move || o.dropped())
        };
        let stop = Arc::new(AtomicBool::new(false));
        let pump = Pump { channels, encoder, counters: Arc::clone(&counters), stop: Arc::clone(&stop) };
        let pump = std::thread::Builder::new()
            .name(format!("{THREAD_PREFIX}-pump"))
            .spawn(move || pump.run(&dropped))
            .map_err(|e| start_err("cannot start the pump thread", &e))?;
        tracing::info!("Foxglove WebSocket server listening at ws://{addr}");
        Ok(Self {
            addr,
            _context: ctx,
            handle: Some(handle),
            front: Some(front),
            runtime: Some(runtime),
            pump: Some(pump),
            stop,
            counters,
            started: std::time::Instant::now(),
            cpu_percent: None,
            outlet_dropped,
        })
    }

    /// Clients connected now.
    pub fn clients(&self) -> usize {
        self.handle.as_ref().map_or(0, WebSocketServerHandle::client_count)
    }

    /// CPU time of the server's threads (the runtime's worker and the pump) per wall time since
    /// it started, % of one core (`None` where `/proc` does not tell).
    pub fn cpu_percent(&self) -> Option<f64> {
        let wall_s = self.started.elapsed().as_secs_f64();
        self.cpu_percent.or_else(|| super::threads_cpu_s(THREAD_PREFIX).map(|s| s / wall_s.max(1e-9) * 100.0))
    }

    fn shutdown(&mut self) {
        if self.cpu_percent.is_none() && self.pump.is_some() {
            self.cpu_percent = self.cpu_percent();
        }
        self.stop.store(true, Ordering::Release);
        if let Some(p) = self.pump.take()
            && p.join().is_err()
        {
            tracing::warn!("the Foxglove pump thread panicked");
        }
        if let Some(front) = self.front.take() {
            // no new clients; the relays end as the server closes their connections
            front.abort();
        }
        if let (Some(handle), Some(runtime)) = (self.handle.take(), self.runtime.as_ref()) {
            let done = handle.stop();
            // closes every client connection; bounded so a stuck client cannot hold the exit
            let waited = runtime.block_on(async { tokio::time::timeout(Duration::from_secs(2), done.wait()).await });
            if waited.is_err() {
                tracing::warn!("the Foxglove server took over 2 s to close its connections");
            }
        }
        if let Some(rt) = self.runtime.take() {
            rt.shutdown_timeout(Duration::from_secs(1));
        }
    }
}

impl Drop for FoxgloveServer {
    fn drop(&mut self) {
        self.shutdown();
    }
}

impl LiveServer for FoxgloveServer {
    fn name(&self) -> &'static str {
        "foxglove"
    }

    fn address(&self) -> String {
        format!("ws://{}", self.addr)
    }

    fn stats(&self) -> serde_json::Value {
        let c = &self.counters;
        serde_json::json!({
            "address": self.address(),
            "clients": self.clients(),
            "clients_seen": c.clients_seen.load(Ordering::Relaxed),
            "messages_sent": c.messages.load(Ordering::Relaxed),
            "bytes_sent": c.bytes.load(Ordering::Relaxed),
            "robot_descriptions_sent": c.descriptions.load(Ordering::Relaxed),
            "outlet_dropped": (self.outlet_dropped)(),
            "cpu_percent": self.cpu_percent(),
            "client_backlog_messages": CLIENT_BACKLOG,
            "slow_clients": "thinned: the oldest queued messages are dropped",
        })
    }

    fn stop(mut self: Box<Self>) -> serde_json::Value {
        let clients = self.clients();
        self.shutdown();
        let mut stats = self.stats();
        stats["clients"] = serde_json::json!(clients);
        stats
    }
}

/// The pump thread: outlet → encoder → channels.
struct Pump {
    channels: Channels,
    encoder: TelemetryEncoder,
    counters: Arc<Counters>,
    stop: Arc<AtomicBool>,
}

impl Pump {
    /// Wakes every [`PUMP_TICK`] and handles what has arrived: the recorder delivers in bursts
    /// anyway (it wakes every 20 ms), and a wake-up per item cost more than the encoding (half a
    /// per cent of a core with no client at all).
    fn run(mut self, outlet: &LiveOutlet) {
        let mut started = false;
        while !self.stop.load(Ordering::Acquire) {
            std::thread::sleep(PUMP_TICK);
            loop {
                let item = match outlet.rx.try_recv() {
                    Ok(item) => item,
                    Err(crossbeam_channel::TryRecvError::Empty) => break,
                    Err(crossbeam_channel::TryRecvError::Disconnected) => return,
                };
                if !started {
                    // log times: the wall clock at the first sample + motion time since it
                    self.encoder.restart(parol6_core::telemetry::writer::unix_now_ns());
                    started = true;
                }
                self.handle(item);
            }
        }
    }

    /// Encodes one item into the channels some client subscribed to.
    fn handle(&mut self, item: LiveItem) {
        let Self { channels, encoder, counters, .. } = self;
        let mut emit = |c: Channel, log_time: u64, data: &[u8]| {
            if let Some(ch) = channels.get(&c) {
                ch.log_with_meta(data, PartialMetadata::with_log_time(log_time));
                counters.messages.fetch_add(1, Ordering::Relaxed);
                counters.bytes.fetch_add(data.len() as u64, Ordering::Relaxed);
            }
            Ok::<(), EncodeError>(())
        };
        let result = match item {
            LiveItem::Sample(s) => {
                encoder.encode_sample_for(&s, |c| channels.get(&c).is_some_and(|ch| ch.has_sinks()), &mut emit)
            }
            LiveItem::Event(e) if channels.get(&Channel::Events).is_some_and(|ch| ch.has_sinks()) => {
                encoder.encode_event(&e, &mut emit)
            }
            LiveItem::Event(_) => Ok(()),
        };
        if let Err(e) = result {
            tracing::warn!("Foxglove: {e}");
        }
    }
}

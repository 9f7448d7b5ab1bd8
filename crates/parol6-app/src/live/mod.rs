//! Live serving beyond one PC: what the live servers share, and the servers themselves.
//!
//! - [`foxglove`] (cargo feature `foxglove`): the Foxglove WebSocket server (the official
//!   `foxglove` crate) streaming our MCAP channels live;
//! - [`ros2`] (cargo feature `ros2`): ROS 2 over Zenoh in `rmw_zenoh`'s conventions (the `zenoh`
//!   crate, its runtime inside `live::ros2`).
//!
//! The rules every server follows, kept here:
//! - **Bind to localhost unless told otherwise** ([`bind_address`]): an address given without a
//!   host, or no address, binds 127.0.0.1.
//! - **No one drives the arm by accident** ([`RemoteControl`]): a command from the network is
//!   refused unless remote control is on (`--allow-remote-control`, or the window's switch with
//!   its banner), and every one, carried out or refused, is logged to `/events`
//!   ([`RemoteControl::admit`], [`RemoteControl::outcome`]). STOP and the dead-man on the PC
//!   always win: they go to the backend the same way and pre-empt whatever a network command
//!   started.
//! - **Never make the robot wait on the network**: a server reads the recorder's bounded
//!   [`LiveOutlet`](parol6_core::telemetry::LiveOutlet) (the recorder `try_send`s and counts
//!   what it drops), and thins or drops for slow clients, counting it.
//!
//! No async runtime type appears outside the module that owns it (`foxglove` keeps its tokio
//! runtime inside).

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use parol6_core::RobotModel;
use parol6_core::motion::RobotBackend;
use parol6_core::telemetry::{EventKind, Recorder, RecorderEvents, TelemetryEvent};

#[cfg(feature = "foxglove")]
pub mod foxglove;
#[cfg(feature = "ros2")]
pub mod ros2;

/// Default port of the Foxglove WebSocket server (Foxglove's own default).
pub const FOXGLOVE_DEFAULT_PORT: u16 = 8765;

/// The address a server binds: `None` → `127.0.0.1:default_port`; `PORT` → `127.0.0.1:PORT`;
/// `IP` → `IP:default_port`; `IP:PORT`, `[IPv6]:PORT`; `localhost[:PORT]` → 127.0.0.1. Port 0
/// takes a free port. A host name other than `localhost` is refused (give its IP address: the
/// address bound is then plain to see).
pub fn bind_address(given: Option<&str>, default_port: u16) -> Result<SocketAddr, String> {
    let localhost = IpAddr::V4(Ipv4Addr::LOCALHOST);
    let Some(text) = given.map(str::trim) else { return Ok(SocketAddr::new(localhost, default_port)) };
    if let Ok(port) = text.parse::<u16>() {
        return Ok(SocketAddr::new(localhost, port));
    }
    if let Ok(addr) = text.parse::<SocketAddr>() {
        return Ok(addr);
    }
    if let Ok(ip) = text.trim_start_matches('[').trim_end_matches(']').parse::<IpAddr>() {
        return Ok(SocketAddr::new(ip, default_port));
    }
    if text.eq_ignore_ascii_case("localhost") {
        return Ok(SocketAddr::new(localhost, default_port));
    }
    if let Some((host, port)) = text.rsplit_once(':')
        && host.eq_ignore_ascii_case("localhost")
    {
        let port = port.parse::<u16>().map_err(|_| format!("\"{text}\": the port must be 0…65535"))?;
        return Ok(SocketAddr::new(localhost, port));
    }
    Err(format!(
        "\"{text}\" is not an address to bind: give IP:PORT (e.g. 127.0.0.1:8765, 0.0.0.0:8765 for every \
         interface), an IP, a port, or localhost[:PORT]"
    ))
}

/// The remote-control switch and the log of every network command. Cloneable: each server and
/// the window hold one, and they share the switch.
#[derive(Debug, Clone)]
pub struct RemoteControl {
    allowed: Arc<AtomicBool>,
    commands: Arc<AtomicU64>,
    refused: Arc<AtomicU64>,
    events: Option<RecorderEvents>,
}

/// A network command refused because remote control is off.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "refused {what} from {from}: remote control is off (start with --allow-remote-control, or turn on \
     remote control in the window)"
)]
pub struct RemoteRefusal {
    /// Who sent it (`ros2 /parol6/joint_trajectory` …).
    pub from: String,
    /// What was asked.
    pub what: String,
}

impl RemoteControl {
    /// A switch that starts `allowed`, logging to `events` (`None`: log nowhere, for tests).
    pub fn new(allowed: bool, events: Option<RecorderEvents>) -> Self {
        Self {
            allowed: Arc::new(AtomicBool::new(allowed)),
            commands: Arc::new(AtomicU64::new(0)),
            refused: Arc::new(AtomicU64::new(0)),
            events,
        }
    }

    /// The same switch and counters, logging to `events` (the window: the active backend's
    /// recorder).
    pub fn logging_to(&self, events: Option<RecorderEvents>) -> Self {
        Self { events, ..self.clone() }
    }

    /// True while network commands are carried out.
    pub fn allowed(&self) -> bool {
        self.allowed.load(Ordering::Acquire)
    }

    /// Turns remote control on or off (the window's switch); logged to `/events`.
    pub fn set_allowed(&self, allowed: bool) {
        if self.allowed.swap(allowed, Ordering::AcqRel) != allowed {
            let message = if allowed { "remote control turned on" } else { "remote control turned off" };
            self.log(TelemetryEvent { time_s: f64::NAN, kind: EventKind::Note, message: message.into() });
        }
    }

    /// Network commands seen, and how many of them were refused.
    pub fn counts(&self) -> (u64, u64) {
        (self.commands.load(Ordering::Relaxed), self.refused.load(Ordering::Relaxed))
    }

    /// A command `what` arrived from `source`: logged to `/events`; refused unless remote
    /// control is on. Once admitted, its outcome (pre-flight refusal, run, done) is logged with
    /// [`RemoteControl::outcome`].
    pub fn admit(&self, source: &str, what: &str) -> Result<(), RemoteRefusal> {
        self.commands.fetch_add(1, Ordering::Relaxed);
        if self.allowed() {
            self.log_command(true, format!("network command from {source}: {what}"));
            Ok(())
        } else {
            let refusal = RemoteRefusal { from: source.to_string(), what: what.to_string() };
            self.refused.fetch_add(1, Ordering::Relaxed);
            self.log_command(false, refusal.to_string());
            Err(refusal)
        }
    }

    /// Logs what became of an admitted command (`accepted` false: refused, e.g. by pre-flight).
    pub fn outcome(&self, source: &str, what: &str, accepted: bool, detail: &str) {
        if !accepted {
            self.refused.fetch_add(1, Ordering::Relaxed);
        }
        let verdict = if accepted { "carried out" } else { "refused" };
        self.log_command(accepted, format!("network command from {source}: {what}: {verdict}: {detail}"));
    }

    fn log_command(&self, accepted: bool, message: String) {
        tracing::info!("{message}");
        self.log(TelemetryEvent { time_s: f64::NAN, kind: EventKind::NetworkCommand { accepted }, message });
    }

    fn log(&self, event: TelemetryEvent) {
        if let Some(events) = &self.events {
            events.event(event);
        }
    }
}

/// What a live server is started on: the robot, its URDF text (for `/robot_description`), the
/// recorder of the backend served (its live outlet), the shared remote-control switch and the
/// backend itself (where admitted network commands go).
pub struct LiveSource<'a> {
    /// The robot.
    pub model: &'a RobotModel,
    /// Its URDF text.
    pub urdf_text: &'a str,
    /// The backend's recorder.
    pub recorder: &'a Recorder,
    /// The remote-control switch.
    pub remote: RemoteControl,
    /// The backend served (the simulation or the controller's session).
    pub backend: Arc<dyn RobotBackend>,
}

impl std::fmt::Debug for LiveSource<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveSource").field("robot", &self.model.name).finish_non_exhaustive()
    }
}

/// CPU time (user + system) of this process's threads whose name starts with `prefix`, s
/// (`None` where `/proc` does not tell: not Linux). Thread names are cut to 15 bytes.
pub fn threads_cpu_s(prefix: &str) -> Option<f64> {
    let tasks = std::fs::read_dir("/proc/self/task").ok()?;
    let mut total = 0.0;
    for task in tasks.flatten() {
        let comm = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
        if comm.trim_end().starts_with(prefix)
            && let Ok(stat) = std::fs::read_to_string(task.path().join("stat"))
        {
            total += stat_cpu_s(&stat).unwrap_or(0.0);
        }
    }
    Some(total)
}

/// CPU time (user + system) of this process, s (`None` where `/proc` does not tell).
pub fn process_cpu_s() -> Option<f64> {
    stat_cpu_s(&std::fs::read_to_string("/proc/self/stat").ok()?)
}

/// utime + stime of a `/proc/…/stat` line, s (clock ticks of 1/100 s, Linux's USER_HZ).
fn stat_cpu_s(stat: &str) -> Option<f64> {
    // the name (2nd field) is in parentheses and may hold spaces: count from the last ')'
    let rest = &stat[stat.rfind(')')? + 1..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((utime + stime) / 100.0)
}

/// Zenoh endpoints as given (`--ros2-connect`, the window's router field), each checked to be
/// `tcp/ADDRESS:PORT`, the only transport built in; the error names `what` and the endpoint.
pub fn tcp_endpoints(what: &str, endpoints: &[String]) -> Result<Vec<String>, String> {
    for e in endpoints {
        let Some(addr) = e.strip_prefix("tcp/") else {
            return Err(format!("{what} {e}: only tcp/ADDRESS:PORT endpoints are built in (e.g. tcp/127.0.0.1:7447)"));
        };
        if addr.rsplit_once(':').is_none_or(|(_, port)| port.parse::<u16>().is_err()) {
            return Err(format!("{what} {e}: give tcp/ADDRESS:PORT (e.g. tcp/127.0.0.1:7447)"));
        }
    }
    Ok(endpoints.to_vec())
}

/// A running live server.
pub trait LiveServer: Send {
    /// Its protocol (`foxglove`, `ros2`).
    fn name(&self) -> &'static str;
    /// Where clients connect (`ws://127.0.0.1:8765` …).
    fn address(&self) -> String;
    /// Its counters as JSON (clients, messages sent, dropped …).
    fn stats(&self) -> serde_json::Value;
    /// Stops it; its final counters.
    fn stop(self: Box<Self>) -> serde_json::Value;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn servers_bind_localhost_unless_an_address_is_given() {
        let local = |port| SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), port);
        assert_eq!(bind_address(None, 8765), Ok(local(8765)));
        assert_eq!(bind_address(Some("9000"), 8765), Ok(local(9000)));
        assert_eq!(bind_address(Some("localhost"), 8765), Ok(local(8765)));
        assert_eq!(bind_address(Some("localhost:0"), 8765), Ok(local(0)));
        assert_eq!(bind_address(Some("0.0.0.0:8765"), 1).map(|a| a.ip().is_unspecified()), Ok(true));
        assert_eq!(bind_address(Some("192.168.1.5"), 8765).map(|a| a.port()), Ok(8765));
        assert_eq!(bind_address(Some("[::1]:7"), 8765).map(|a| a.port()), Ok(7));
        for bad in ["example.org:80", "localhost:99999", "", "1.2.3.4:x"] {
            assert!(bind_address(Some(bad), 8765).is_err(), "{bad}");
        }
    }

    #[test]
    fn cpu_times_are_read_from_proc() {
        let line = "42 (a b) S 1 2 3 4 5 6 7 8 9 10 150 50 0 0";
        assert_eq!(stat_cpu_s(line), Some(2.0));
        if cfg!(target_os = "linux") {
            assert!(process_cpu_s().is_some_and(|s| s >= 0.0));
            assert!(threads_cpu_s("no-such-thread").is_some_and(|s| s == 0.0));
        }
    }

    #[test]
    fn network_commands_are_refused_unless_remote_control_is_on() {
        let remote = RemoteControl::new(false, None);
        let e = remote.admit("ros2 /parol6/joint_trajectory", "a trajectory of 3 points").expect_err("off");
        assert!(e.to_string().contains("--allow-remote-control"), "{e}");
        remote.set_allowed(true);
        assert!(remote.admit("ros2 /parol6/joint_trajectory", "a trajectory of 3 points").is_ok());
        assert_eq!(remote.counts(), (2, 1));
    }

    /// Every network command, refused or carried out, is an `/events` entry of the recorder.
    #[test]
    fn every_network_command_is_logged_to_events() {
        let rec =
            Recorder::start(RobotModel::parol6(), parol6_core::telemetry::RecorderConfig::default()).expect("recorder");
        let remote = RemoteControl::new(false, Some(rec.events()));
        assert!(remote.admit("ros2 /parol6/joint_trajectory", "a trajectory of 2 points").is_err());
        remote.set_allowed(true);
        assert!(remote.admit("ros2 /parol6/joint_trajectory", "a trajectory of 3 points").is_ok());
        remote.outcome(
            "ros2 /parol6/joint_trajectory",
            "a trajectory of 3 points",
            false,
            "pre-flight: J2 out of range",
        );
        let mut events = Vec::new();
        for _ in 0..300 {
            events = rec.live().events.to_vec();
            if events.len() >= 4 {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        let kinds: Vec<(EventKind, u8)> = events.iter().map(|e| (e.kind.clone(), e.log_level())).collect();
        assert_eq!(
            kinds,
            vec![
                (EventKind::NetworkCommand { accepted: false }, 3),
                (EventKind::Note, 2),
                (EventKind::NetworkCommand { accepted: true }, 2),
                (EventKind::NetworkCommand { accepted: false }, 3),
            ],
            "{events:?}"
        );
        assert!(events[0].message.contains("remote control is off"), "{}", events[0].message);
        assert!(events[3].message.contains("pre-flight: J2 out of range"), "{}", events[3].message);
    }
}

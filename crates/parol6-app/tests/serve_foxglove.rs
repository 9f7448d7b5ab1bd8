//! Issue 30: `parol6 serve --foxglove`, checked by an independent client: a Python Foxglove
//! WebSocket client (`tests/peers/foxglove_client.py`, `websockets` only, its own protocol
//! decoding and its own quaternion arithmetic) on loopback with a free port.
//!
//! - the channels advertised are those of our MCAP files (topics, schema names, encodings);
//! - `/joint_states` and `/tf` arrive while the simulation moves, at their rates, and the flange
//!   chained from `/tf` is where `parol6 fk` puts it for the `/joint_states` of the same stamp;
//! - `/robot_description` reaches a client that subscribes after the server started;
//! - a client that reads nothing does not slow the 1 kHz simulation: no sample is lost on the
//!   way to the server, the process's memory stays bounded, and the client is thinned.
//!
//! Outside CI a missing `python3` / `websockets` skips these tests with a notice; in CI
//! (`CI` set) it fails them (`.ci/run` installs `websockets`).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::io::{BufRead, BufReader, Read};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use cli_support::{exe, run, workspace_root};

fn peer() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peers/foxglove_client.py")
}

/// True when python3 with `websockets` is here; otherwise a notice (outside CI) or a failure
/// (in CI).
fn python_ready(test: &str) -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import websockets"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        assert!(std::env::var_os("CI").is_none(), "{test}: python3 with `websockets` is missing in CI (.ci/run)");
        parol6_tests::skip_notice(&format!("SKIPPED {test}: python3 with the `websockets` package is not installed"));
    }
    ok
}

/// A running `parol6 serve`, its first stdout line read.
struct Serving {
    child: Child,
    url: String,
    stdout: BufReader<std::process::ChildStdout>,
    stderr: Option<std::thread::JoinHandle<String>>,
}

impl Serving {
    fn start(args: &[&str]) -> Self {
        let mut child = Command::new(exe())
            .arg("serve")
            .args(args)
            .current_dir(workspace_root())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("parol6 serve starts");
        let mut err = child.stderr.take().unwrap();
        let stderr = std::thread::spawn(move || {
            let mut s = String::new();
            let _ = err.read_to_string(&mut s);
            s
        });
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut line = String::new();
        stdout.read_line(&mut line).unwrap();
        let v: serde_json::Value =
            serde_json::from_str(line.trim()).unwrap_or_else(|e| panic!("listening line {line:?}: {e}"));
        let url = v["listening"]["foxglove"].as_str().unwrap_or_else(|| panic!("no address in {v}")).to_string();
        assert!(url.starts_with("ws://127.0.0.1:") && !url.ends_with(":0"), "{url}");
        Self { child, url, stdout, stderr: Some(stderr) }
    }

    /// Waits (at most `limit`) for the exit; the summary JSON.
    fn finish(mut self, limit: Duration) -> serde_json::Value {
        let t0 = Instant::now();
        let status = loop {
            if let Some(st) = self.child.try_wait().unwrap() {
                break st;
            }
            assert!(t0.elapsed() < limit, "parol6 serve did not end in {limit:?}");
            std::thread::sleep(Duration::from_millis(20));
        };
        let mut rest = String::new();
        self.stdout.read_to_string(&mut rest).unwrap();
        let stderr = self.stderr.take().unwrap().join().unwrap();
        assert!(status.success(), "serve: {status}: {rest}\n{stderr}");
        serde_json::from_str(rest.trim()).unwrap_or_else(|e| panic!("summary {rest:?}: {e}\n{stderr}"))
    }

    fn pid(&self) -> u32 {
        self.child.id()
    }
}

impl Drop for Serving {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Runs the Python client; its JSON.
fn client(mode: &str, url: &str, seconds: f64) -> serde_json::Value {
    client_offering(mode, url, seconds, &[], "foxglove.sdk.v1,foxglove.websocket.v1")
}

/// The client in `mode` with `args` after the seconds, offering the `subprotocols`
/// (comma-separated).
fn client_offering(mode: &str, url: &str, seconds: f64, args: &[&str], subprotocols: &str) -> serde_json::Value {
    let out = Command::new("python3")
        .arg(peer())
        .args([mode, url, &seconds.to_string()])
        .args(args)
        .env("FOXGLOVE_SUBPROTOCOLS", subprotocols)
        .output()
        .unwrap();
    assert!(out.status.success(), "client {mode}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("client {mode} output: {e}"))
}

/// The flange position `parol6 fk` gives for `q`, m.
fn fk_flange(q: &[f64]) -> [f64; 3] {
    let joints: Vec<String> = q.iter().map(|v| format!("{v:.17}")).collect();
    let v = run(&["fk", "--joints", &joints.join(",")]).json("fk");
    let p = &v["tcp"]["position_m"];
    [0, 1, 2].map(|i| p[i].as_f64().unwrap())
}

#[test]
fn foxglove_client_gets_our_channels_and_tf_agrees_with_fk() {
    let test = "foxglove_client_gets_our_channels_and_tf_agrees_with_fk";
    if !python_ready(test) {
        return;
    }
    let serving = Serving::start(&["--foxglove", "127.0.0.1:0", "--demo", "--seconds", "7"]);
    // a late subscriber: the server has been running a moment
    std::thread::sleep(Duration::from_millis(300));
    let got = client("receive", &serving.url, 4.0);
    let summary = serving.finish(Duration::from_secs(30));

    // the channels of a recording
    let mut advertised: Vec<(String, String, String, String)> = got["advertised"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let s = |k: &str| c[k].as_str().unwrap().to_string();
            (s("topic"), s("schemaName"), s("encoding"), s("schemaEncoding"))
        })
        .collect();
    advertised.sort();
    let expected = [
        ("/events", "foxglove.Log"),
        ("/joint_commands", "parol6.JointState"),
        ("/joint_states", "parol6.JointState"),
        ("/link", "parol6.LinkHealth"),
        ("/robot_description", "std_msgs/String"),
        ("/tcp_pose", "foxglove.PoseInFrame"),
        ("/tf", "foxglove.FrameTransforms"),
    ]
    .map(|(t, s)| (t.to_string(), s.to_string(), "json".to_string(), "jsonschema".to_string()));
    assert_eq!(advertised, expected);

    // the URDF, though the client subscribed after the server started
    let urdf = parol6_core::model::PAROL6_URDF;
    assert_eq!(got["robot_description_len"].as_u64(), Some(urdf.chars().count() as u64), "{got}");
    assert_eq!(got["joint_names"], serde_json::json!(["J1", "J2", "J3", "J4", "J5", "J6"]));

    // rates: /tf at most 100 Hz, /joint_states every sample (1 kHz while moving, 100 Hz at rest)
    let count = |t: &str| got["counts"][t].as_f64().unwrap_or(0.0);
    let span = |t: &str| got["span_s"][t].as_f64().unwrap_or(0.0);
    assert!(span("/tf") > 2.5, "{got}");
    let tf_hz = (count("/tf") - 1.0) / span("/tf");
    assert!((60.0..=101.0).contains(&tf_hz), "/tf at {tf_hz} Hz: {got}");
    assert!(count("/joint_states") > 3.0 * count("/tf"), "{got}");
    // one command per state sample; the client's listening window can cut between the pair
    assert!((count("/joint_states") - count("/joint_commands")).abs() <= 2.0, "{got}");

    // the /tf chain of each pair against parol6 fk, over a motion
    let pairs = got["pairs"].as_array().unwrap();
    assert!(pairs.len() >= 8, "{got}");
    let mut moved = 0.0_f64;
    let q0: Vec<f64> = pairs[0]["q"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    for p in pairs {
        let q: Vec<f64> = p["q"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        moved = moved.max(q.iter().zip(&q0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max));
        let flange: Vec<f64> = p["flange_m"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let fk = fk_flange(&q);
        let err = (0..3).map(|i| (flange[i] - fk[i]).powi(2)).sum::<f64>().sqrt();
        assert!(err < 1e-6, "flange from /tf {flange:?} vs fk {fk:?} at q {q:?}: {err} m");
    }
    assert!(moved > 0.01, "the arm did not move while the client listened ({moved} rad)");

    let fox = &summary["servers"]["foxglove"];
    assert_eq!(fox["clients_seen"], 1, "{summary}");
    assert_eq!(fox["robot_descriptions_sent"], 1, "{summary}");
    assert_eq!(fox["outlet_dropped"], 0, "{summary}");
    assert!(fox["messages_sent"].as_u64().unwrap() >= count("/joint_states") as u64, "{summary}");
    assert_eq!(summary["missing_samples"], 0, "{summary}");
}

/// VmRSS of `pid`, kB.
fn rss_kb(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or(0)
}

#[test]
fn a_client_that_never_reads_does_not_slow_the_simulation() {
    let test = "a_client_that_never_reads_does_not_slow_the_simulation";
    if !python_ready(test) {
        return;
    }
    let serving = Serving::start(&["--foxglove", "127.0.0.1:0", "--demo", "--seconds", "16"]);
    let url = serving.url.clone();
    let slow = std::thread::spawn(move || client("slow", &url, 10.0));
    // memory once the socket buffers and the client's queue have had time to fill, and later
    std::thread::sleep(Duration::from_secs(5));
    let rss_early_kb = rss_kb(serving.pid());
    std::thread::sleep(Duration::from_secs(5));
    let rss_late_kb = rss_kb(serving.pid());
    let got = slow.join().unwrap();
    let summary = serving.finish(Duration::from_secs(30));
    // the simulation kept its 1 kHz and lost no sample on the way to the server
    let sim = &summary["sim"];
    let rate = sim["steps_per_s"].as_f64().unwrap();
    assert!((950.0..=1050.0).contains(&rate), "sim at {rate} steps/s: {summary}");
    assert_eq!(summary["missing_samples"], 0, "{summary}");
    assert_eq!(summary["servers"]["foxglove"]["outlet_dropped"], 0, "{summary}");
    // bounded: the client's queue holds at most 1024 messages (≈ 1.5 MB)
    if rss_early_kb > 0 {
        let grew_kb = rss_late_kb.saturating_sub(rss_early_kb);
        assert!(grew_kb < 16 * 1024, "RSS grew {grew_kb} kB in 5 s (from {rss_early_kb} kB): {summary}");
    }
    // and the client was thinned: the oldest messages were dropped for it
    assert!(got["joint_states"].as_u64().unwrap() > 0, "{got}");
    assert!(got["seq_gaps"].as_u64().unwrap() > 0, "no message was dropped for the slow client: {got}");
}

/// What the server answers a raw HTTP request (its status line), read for at most 10 s.
fn http_status(url: &str, request: &[u8], close_write: bool) -> (String, Duration) {
    use std::io::Write;
    let addr = url.trim_start_matches("ws://");
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let t0 = Instant::now();
    s.write_all(request).unwrap();
    if close_write {
        s.shutdown(std::net::Shutdown::Write).unwrap();
    }
    let mut answer = String::new();
    if let Err(e) = BufReader::new(s).read_line(&mut answer) {
        answer = format!("(no answer: {e})");
    }
    (answer.trim().to_string(), t0.elapsed())
}

/// Lichtblick 1.x (and every client on `@foxglove/ws-protocol` 0.7) offers only the protocol's
/// former name `foxglove.websocket.v1`, which the `foxglove` crate's server refused with
/// HTTP 400. The front door lets it in under that name; hostile or idle handshakes get an
/// answer and never hold the server.
#[test]
fn a_client_offering_only_the_old_protocol_name_connects_as_lichtblick_does() {
    let test = "a_client_offering_only_the_old_protocol_name_connects_as_lichtblick_does";
    if !python_ready(test) {
        return;
    }
    let serving = Serving::start(&["--foxglove", "127.0.0.1:0", "--demo", "--seconds", "16"]);
    // a client that sends half a head and waits is answered 400 after 5 s, not held forever
    let stall = {
        let url = serving.url.clone();
        std::thread::spawn(move || http_status(&url, b"GET / HTTP/1.1\r\nHost: x\r\n", false))
    };
    // a protocol neither server knows: the crate's own refusal passes through
    let (status, _) = http_status(
        &serving.url,
        b"GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: chat\r\n\r\n",
        false,
    );
    assert!(status.starts_with("HTTP/1.1 400"), "{status:?}");
    // a head that ends the connection early, and one that never ends
    let (status, _) = http_status(&serving.url, b"GET / HTTP/1.1\r\n", true);
    assert!(status.starts_with("HTTP/1.1 400"), "{status:?}");
    let old = client_offering("receive", &serving.url, 2.0, &["/joint_states"], "foxglove.websocket.v1");
    assert_eq!(old["subprotocol"], "foxglove.websocket.v1", "{old}");
    assert!(old["counts"]["/joint_states"].as_u64().unwrap_or(0) > 50, "{old}");
    let new = client_offering("receive", &serving.url, 1.0, &["/joint_states"], "foxglove.sdk.v1");
    assert_eq!(new["subprotocol"], "foxglove.sdk.v1", "{new}");
    assert!(new["counts"]["/joint_states"].as_u64().unwrap_or(0) > 20, "{new}");
    let (status, waited) = stall.join().unwrap();
    assert!(status.starts_with("HTTP/1.1 400"), "{status:?}");
    assert!(waited >= Duration::from_secs(4) && waited < Duration::from_secs(9), "answered after {waited:?}");
    let summary = serving.finish(Duration::from_secs(30));
    assert_eq!(summary["servers"]["foxglove"]["clients_seen"], 2, "{summary}");
    assert_eq!(summary["missing_samples"], 0, "{summary}");
}

#[test]
fn serve_refuses_nothing_to_serve_and_bad_addresses() {
    run(&["serve"]).assert_refused("serve", "nothing to serve");
    run(&["serve", "--foxglove", "example.org:80"]).assert_refused("serve --foxglove host", "not an address");
    run(&["serve", "--foxglove", "--demo", "--fake-robot"]).assert_refused("serve --demo --fake-robot", "--demo");
}

#[test]
fn serve_runs_until_sigint_and_exits_130_with_its_summary() {
    let mut serving = Serving::start(&["--foxglove", "127.0.0.1:0"]);
    std::thread::sleep(Duration::from_millis(500));
    let sent = Command::new("kill").args(["-INT", &serving.pid().to_string()]).status().unwrap();
    assert!(sent.success());
    let t0 = Instant::now();
    let status = loop {
        if let Some(st) = serving.child.try_wait().unwrap() {
            break st;
        }
        assert!(t0.elapsed() < Duration::from_secs(20), "serve did not end after SIGINT");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(status.code(), Some(130));
    let mut rest = String::new();
    serving.stdout.read_to_string(&mut rest).unwrap();
    let summary: serde_json::Value = serde_json::from_str(rest.trim()).unwrap_or_else(|e| panic!("{rest:?}: {e}"));
    assert_eq!(summary["interrupted"], "SIGINT", "{summary}");
    assert_eq!(summary["servers"]["foxglove"]["clients_seen"], 0, "{summary}");
}

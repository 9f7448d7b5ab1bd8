//! Issue 29, items 3, 4 and 7, through the built binary:
//! - SIGINT / SIGTERM end `record`, `hw jog|move --record`, `program run --record` and
//!   `hw emulate` cleanly: exit 130, motion stopped (hold, then IDLE on the robot), the
//!   recording closed with its summary and its last sample within 0.3 s of the signal;
//! - `hw jog|move --record FILE` leaves an existing FILE alone when the request is refused or
//!   the port cannot be opened;
//! - a `pause` step (G-code `M0`) is refused headless unless `--skip-pauses`, never a hang.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use cli_support::{exe, run, run_in, workspace_root};

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("parol6-cli-signals-{}-{name}", std::process::id()))
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

fn unix_now_s() -> f64 {
    SystemTime::now().duration_since(UNIX_EPOCH).unwrap().as_secs_f64()
}

/// A running `parol6`, its output read on threads.
struct Running {
    child: Child,
    stdin: Option<ChildStdin>,
    stdout: Option<std::thread::JoinHandle<Vec<u8>>>,
    stderr: Option<std::thread::JoinHandle<Vec<u8>>>,
}

/// How a signalled run ended.
#[derive(Debug)]
struct Ended {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    /// From the signal to the exit, s.
    exit_after_s: f64,
    /// Unix time of the signal, s.
    signalled_unix_s: f64,
}

fn spawn(args: &[&str], keep_stdout: bool) -> Running {
    let mut child = Command::new(exe())
        .args(args)
        .current_dir(workspace_root())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the parol6 binary starts");
    let stdin = child.stdin.take();
    let stdout = if keep_stdout {
        None
    } else {
        let mut out = child.stdout.take().unwrap();
        Some(std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = out.read_to_end(&mut v);
            v
        }))
    };
    let mut err = child.stderr.take().unwrap();
    let stderr = Some(std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = err.read_to_end(&mut v);
        v
    }));
    Running { child, stdin, stdout, stderr }
}

impl Drop for Running {
    /// A failed test leaves no process behind (`hw emulate` would serve forever).
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

impl Running {
    /// Sends `signal` ("INT", "TERM") after `after`, then waits (at most 20 s) for the exit.
    fn signal_after(self, after: Duration, signal: &str) -> Ended {
        self.try_signal_after(after, signal).unwrap_or_else(|e| panic!("{e}"))
    }

    /// [`Running::signal_after`], or `Err` with its output when it ended before the signal.
    fn try_signal_after(mut self, after: Duration, signal: &str) -> Result<Ended, String> {
        std::thread::sleep(after);
        if let Some(st) = self.child.try_wait().unwrap() {
            let out = self.stdout.take().map(|h| h.join().unwrap()).unwrap_or_default();
            let err = self.stderr.take().map(|h| h.join().unwrap()).unwrap_or_default();
            return Err(format!(
                "ended ({st}) before the signal: {}\n{}",
                String::from_utf8_lossy(&out),
                String::from_utf8_lossy(&err)
            ));
        }
        let signalled_unix_s = unix_now_s();
        let t0 = Instant::now();
        let sent = Command::new("kill").args([format!("-{signal}"), self.child.id().to_string()]).status().unwrap();
        assert!(sent.success(), "kill -{signal}");
        let status = loop {
            if let Some(st) = self.child.try_wait().unwrap() {
                break Some(st);
            }
            if t0.elapsed() > Duration::from_secs(20) {
                let _ = self.child.kill();
                let _ = self.child.wait();
                break None;
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        let exit_after_s = t0.elapsed().as_secs_f64();
        drop(self.stdin.take());
        let stdout = self.stdout.take().map(|h| h.join().unwrap()).unwrap_or_default();
        let stderr = self.stderr.take().map(|h| h.join().unwrap()).unwrap_or_default();
        Ok(Ended {
            code: status.and_then(|s| s.code()),
            stdout: String::from_utf8_lossy(&stdout).into_owned(),
            stderr: String::from_utf8_lossy(&stderr).into_owned(),
            exit_after_s,
            signalled_unix_s,
        })
    }
}

/// True when `hw jog|move` report that the link was already lost when the signal came.
fn lost_link_at_signal(end: &Ended) -> bool {
    serde_json::from_str::<serde_json::Value>(end.stdout.trim())
        .is_ok_and(|v| v["stopping"]["link"].as_str().is_some_and(|l| l != "Connected"))
}

/// Runs `parol6 args…` and signals it after 1.5 s. A run against a controller that lost its
/// link before the signal (the emulator starved of CPU on a loaded machine: see the README's
/// serial-session row), so that there was nothing to hold, is tried again, at most 3 times.
fn signalled(args: &[&str], signal: &str) -> Ended {
    let mut early = Vec::new();
    for _ in 0..3 {
        match spawn(args, false).try_signal_after(Duration::from_millis(1500), signal) {
            Ok(end) if lost_link_at_signal(&end) => early.push(format!("{end:#?}")),
            Ok(end) => return end,
            Err(e) if e.contains("link") => early.push(e),
            Err(e) => panic!("{args:?}: {e}"),
        }
    }
    panic!("{args:?}: the link was lost before the signal 3 times: {early:#?}");
}

impl Ended {
    /// Exit 130, the one line on stderr, the JSON on stdout (with `"interrupted"`).
    fn assert_interrupted(&self, what: &str, signal: &str) -> serde_json::Value {
        assert_eq!(self.code, Some(130), "{what}: {self:#?}");
        assert!(self.stderr.contains(&format!("interrupted by {signal}")), "{what}: {self:#?}");
        assert!(!self.stderr.contains("panicked"), "{what}: {self:#?}");
        assert!(self.exit_after_s < 5.0, "{what}: took {:.2} s to stop: {self:#?}", self.exit_after_s);
        let out: serde_json::Value = serde_json::from_str(self.stdout.trim())
            .unwrap_or_else(|e| panic!("{what}: stdout is not JSON ({e}): {self:#?}"));
        assert_eq!(out["interrupted"], signal, "{what}: {out}");
        out
    }
}

/// Asserts `file` is a whole recording (its summary written, nothing cut off) whose last joint
/// sample is within 0.3 s of `signalled_unix_s`; returns `mcap info`'s JSON.
fn assert_closed_recording(file: &Path, signalled_unix_s: f64, what: &str) -> serde_json::Value {
    let info = run(&["mcap", "info", &s(file)]).json(&format!("{what}: mcap info"));
    assert_eq!(info["truncated"], false, "{what}: {info}");
    assert_eq!(info["warnings"].as_array().map(Vec::len), Some(0), "{what}: {info}");
    assert!(info["samples"].as_u64().unwrap() > 20, "{what}: {info}");
    let bytes = std::fs::read(file).unwrap();
    let mut last_s = f64::NEG_INFINITY;
    parol6_core::telemetry::reader::scan_recording(&bytes, &mut |topic, m| {
        if topic == "/joint_states" {
            last_s = last_s.max(f64::from(m.header.stamp.sec) + f64::from(m.header.stamp.nsec) * 1e-9);
        }
    })
    .unwrap();
    let gap = (last_s - signalled_unix_s).abs();
    assert!(gap <= 0.3, "{what}: the last sample is {gap:.3} s from the signal: {info}");
    info
}

/// Regression (issue 29, item 4): Ctrl-C during `parol6 record` killed the process; the file
/// had no summary and lost the open chunk (about the last second).
#[test]
fn sigint_during_record_closes_the_recording_and_exits_130() {
    let file = temp("record.mcap");
    let running = spawn(&["record", "--seconds", "60", "-o", &s(&file), "--demo"], false);
    let end = running.signal_after(Duration::from_millis(1500), "INT");
    let out = end.assert_interrupted("record", "SIGINT");
    assert!(out["samples"].as_u64().unwrap() > 20, "{out}");
    assert_closed_recording(&file, end.signalled_unix_s, "record");
    let _ = std::fs::remove_file(&file);
}

/// Starts `parol6 hw emulate --homed`; returns it and its port.
fn emulator() -> (Running, String) {
    let mut emu = spawn(&["hw", "emulate", "--homed"], true);
    let mut lines = BufReader::new(emu.child.stdout.take().unwrap());
    let mut port = String::new();
    lines.read_line(&mut port).unwrap();
    let port = port.trim().to_string();
    assert!(port.starts_with("/dev/"), "hw emulate printed {port:?}");
    // the rest of its stdout: one JSON line per stdin command
    let (tx, rx) = std::sync::mpsc::channel::<String>();
    std::thread::spawn(move || {
        for line in lines.lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    EMU_LINES.with(|l| *l.borrow_mut() = Some(rx));
    (emu, port)
}

thread_local! {
    static EMU_LINES: std::cell::RefCell<Option<std::sync::mpsc::Receiver<String>>> = const { std::cell::RefCell::new(None) };
}

/// The emulator's `state` (its last received command, speeds, positions).
fn emulator_state(emu: &mut Running) -> serde_json::Value {
    let stdin = emu.stdin.as_mut().unwrap();
    stdin.write_all(b"state\n").unwrap();
    stdin.flush().unwrap();
    let line = EMU_LINES
        .with(|l| l.borrow().as_ref().unwrap().recv_timeout(Duration::from_secs(5)))
        .expect("hw emulate answers `state`");
    serde_json::from_str(&line).unwrap()
}

/// Regression (issue 29, item 4): Ctrl-C during `hw jog` killed the process mid-jog without a
/// closing frame (the last MOVE target kept advancing on the board) and lost the recording's
/// end. Now the jog holds, then the session closes with IDLE frames; the board (here `hw
/// emulate`, itself ended by SIGINT with 130) last received IDLE and stands still.
#[test]
fn sigterm_during_hw_jog_holds_then_idles_and_closes_the_recording() {
    let (mut emu, port) = emulator();
    let file = temp("jog.mcap");
    let args =
        ["hw", "jog", "--port", &port, "--joint", "1", "--speed", "-0.2", "--seconds", "30", "--record", &s(&file)];
    let end = signalled(&args, "TERM");
    let out = end.assert_interrupted("hw jog", "SIGTERM");
    assert!(out["stopping"]["hold_frames"].as_u64().unwrap() >= 1, "held before closing: {out}");
    assert_eq!(out["stopping"]["then"], "IDLE", "{out}");
    assert!(out["recording"]["samples"].as_u64().unwrap() > 20, "{out}");
    assert_closed_recording(&file, end.signalled_unix_s, "hw jog");
    // the board: last command IDLE (255), no speed, not moving
    let a = emulator_state(&mut emu);
    std::thread::sleep(Duration::from_millis(300));
    let b = emulator_state(&mut emu);
    assert_eq!(a["last_code"], 255, "the last frame was IDLE: {a}");
    assert!(a["speed_steps_s"].as_array().unwrap().iter().all(|v| v == 0), "{a}");
    assert_eq!(a["position_steps"], b["position_steps"], "the arm stands still");
    let emu_end = emu.signal_after(Duration::ZERO, "INT");
    assert_eq!(emu_end.code, Some(130), "hw emulate on SIGINT: {emu_end:#?}");
    assert!(emu_end.stderr.contains("interrupted by SIGINT"), "{emu_end:#?}");
    let _ = std::fs::remove_file(&file);
}

/// Regression (issue 29, item 4): `hw move` (here with `--fake-robot`) stops on SIGINT too.
#[test]
fn sigint_during_hw_move_holds_then_idles_and_closes_the_recording() {
    let file = temp("move.mcap");
    let args = [
        "hw",
        "move",
        "--joints",
        "-60,-90,180,0,0,180",
        "--deg",
        "--speed",
        "0.05",
        "--fake-robot",
        "--record",
        &s(&file),
    ];
    let end = signalled(&args, "INT");
    let out = end.assert_interrupted("hw move", "SIGINT");
    assert!(out["stopping"]["hold_frames"].as_u64().unwrap() >= 1, "held before closing: {out}");
    assert_eq!(out["stopping"]["then"], "IDLE", "{out}");
    assert_closed_recording(&file, end.signalled_unix_s, "hw move");
    let _ = std::fs::remove_file(&file);
}

/// Regression (issue 29, item 4): Ctrl-C during `program run --record` lost the recording's
/// end and summary. On the robot (the fake one) the run is stopped (hold, then IDLE).
#[test]
fn sigint_during_program_run_stops_and_closes_the_recording() {
    let file = temp("run.mcap");
    let program = workspace_root().join("assets/programs/triangle.json");
    let args = ["program", "run", &s(&program), "--fake-robot", "--record", &s(&file)];
    let end = signalled(&args, "INT");
    let out = end.assert_interrupted("program run", "SIGINT");
    assert_eq!(out["state"], "interrupted", "{out}");
    assert!(out["recording"]["samples"].as_u64().unwrap() > 20, "{out}");
    assert_closed_recording(&file, end.signalled_unix_s, "program run");
    // the simulation, in real time, gets STOP
    let sim = spawn(&["program", "run", &s(&program), "--realtime", "--record", &s(&file)], false)
        .signal_after(Duration::from_millis(1500), "TERM");
    let out = sim.assert_interrupted("program run (simulation)", "SIGTERM");
    assert_eq!(out["state"], "interrupted", "{out}");
    assert_closed_recording(&file, sim.signalled_unix_s, "program run (simulation)");
    let _ = std::fs::remove_file(&file);
}

/// Issue 29, item 4: `path-test` and `iso9283` on the robot (the fake one) abort their
/// measurement on a signal (the arm stops) and exit 130.
#[test]
fn sigint_during_a_measurement_stops_the_arm_and_exits_130() {
    let cube = ["--center-mm", "0,250,220", "--edge-mm", "60", "--orientation-deg", "90,0,0", "--fake-robot"];
    for (cmd, signal) in [("path-test", "INT"), ("iso9283", "TERM")] {
        let mut args = vec![cmd];
        args.extend(cube);
        let end = signalled(&args, signal);
        assert_eq!(end.code, Some(130), "{cmd}: {end:#?}");
        assert!(end.stderr.contains(&format!("interrupted by SIG{signal}")), "{cmd}: {end:#?}");
        assert!(end.stderr.contains("the arm stopped"), "{cmd}: {end:#?}");
        assert!(end.exit_after_s < 5.0, "{cmd}: {end:#?}");
    }
}

/// A recording-like file that must survive a refused command untouched.
fn precious(name: &str) -> (PathBuf, Vec<u8>) {
    let file = temp(name);
    let bytes = b"an earlier recording that must not be replaced".to_vec();
    std::fs::write(&file, &bytes).unwrap();
    (file, bytes)
}

/// Regression (issue 29, item 3): `hw move|jog --record FILE` replaced FILE with an empty
/// recording before the target was checked and before the port was opened.
#[test]
fn hw_record_keeps_an_existing_file_when_refused_or_the_port_cannot_be_opened() {
    let (file, bytes) = precious("keep.mcap");
    // a target beyond J1's limit: refused (2)
    let r = run(&["hw", "move", "--joints", "400,-90,180,0,0,180", "--deg", "--fake-robot", "--record", &s(&file)]);
    assert_eq!(r.code(), Some(2), "{r:?}");
    assert!(std::fs::read(&file).unwrap() == bytes, "hw move, refused target: the file was replaced");
    // a port that cannot be opened: a device failure (1)
    for cmd in [
        vec!["hw", "move", "--joints", "80,-90,180,0,0,180", "--deg"],
        vec!["hw", "jog", "--joint", "1", "--speed", "0.5", "--seconds", "1"],
        vec!["program", "run", "assets/programs/triangle.json"],
    ] {
        let mut args = cmd.clone();
        let f = s(&file);
        args.extend(["--port", "/nonexistent/ttyACM9", "--record", &f]);
        let r = run(&args);
        assert_eq!(r.code(), Some(1), "{cmd:?}: {r:?}");
        assert!(std::fs::read(&file).unwrap() == bytes, "{cmd:?} on a bad port: the file was replaced");
    }
    let _ = std::fs::remove_file(&file);
}

/// Runs `parol6 args…` with a 60 s limit: a hang fails the test instead of stalling the suite.
fn run_bounded(args: &[&str]) -> cli_support::Run {
    let r = run_in(workspace_root(), args, Duration::from_secs(60));
    assert!(r.status.is_some(), "{args:?} hung (killed after 60 s): {r:?}");
    r
}

/// Regression (issue 29, item 7): a `pause` step (G-code `M0`) made `program run` wait
/// forever headless. It is refused before anything moves, naming the line and
/// `--skip-pauses`; with `--skip-pauses` the run goes through and reports the skipped pauses.
#[test]
fn program_run_with_a_pause_step_is_refused_headless_or_skipped() {
    let gcode = temp("pause.gcode");
    std::fs::write(&gcode, "G21 G90\nG4 P100\nM0\nG4 P100\n").unwrap();
    let native = temp("pause.json");
    std::fs::write(
        &native,
        r#"{
  "format": "parol6-program",
  "version": 1,
  "name": "with a pause",
  "steps": [
    {"type": "dwell", "seconds": 0.1},
    {"type": "pause"},
    {"type": "dwell", "seconds": 0.1}
  ]
}
"#,
    )
    .unwrap();
    for (file, line) in [(&gcode, 3), (&native, 7)] {
        let r = run_bounded(&["program", "run", &s(file)]);
        r.assert_refused("a pause step headless", "--skip-pauses");
        assert!(r.stderr.contains(&format!("{}:{line}", s(file))), "names the line: {r:?}");
        let out = run_bounded(&["program", "run", &s(file), "--skip-pauses"]).json("--skip-pauses");
        assert_eq!(out["state"], "done", "{out}");
        assert_eq!(out["steps_done"], out["steps"], "{out}");
        assert_eq!(out["skipped_pauses"], serde_json::json!([{"step": 2, "line": line}]), "{out}");
        // on the robot too (the fake one)
        let r = run_bounded(&["program", "run", &s(file), "--fake-robot"]);
        r.assert_refused("a pause step on the robot, headless", "--skip-pauses");
    }
    let _ = std::fs::remove_file(&gcode);
    let _ = std::fs::remove_file(&native);
}

fn on_path(cmd: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(cmd).is_file()))
}

/// The `parol6` process started by `xvfb-run` (pid `parent`).
fn child_parol6(parent: u32) -> Option<u32> {
    std::fs::read_dir("/proc").ok()?.flatten().find_map(|e| {
        let pid: u32 = e.file_name().to_str()?.parse().ok()?;
        let stat = std::fs::read_to_string(e.path().join("stat")).ok()?;
        // pid (comm) state ppid …
        let (comm, rest) = stat.split_once(") ")?;
        let ppid: u32 = rest.split_whitespace().nth(1)?.parse().ok()?;
        (ppid == parent && comm.ends_with("(parol6")).then_some(pid)
    })
}

/// Starts the window recording to `file` under `xvfb-run`; returns `xvfb-run`, the window's
/// pid and its stderr once the recording has begun, or the stderr when it did not start.
fn start_window(
    dir: &Path,
    runtime: &Path,
    file: &Path,
) -> Result<(Child, u32, std::thread::JoinHandle<String>), String> {
    let mut xvfb = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24", exe(), "--record", &s(file)])
        .env("PAROL6_SETTINGS", dir.join("settings.json"))
        .env("XDG_RUNTIME_DIR", runtime)
        .env_remove("WAYLAND_DISPLAY")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = xvfb.stderr.take().unwrap();
    let stderr = std::thread::spawn(move || {
        let mut v = String::new();
        let _ = err.read_to_string(&mut v);
        v
    });
    // the window records from its first frame: wait for the file
    let t0 = Instant::now();
    loop {
        if let Some(pid) = child_parol6(xvfb.id())
            && std::fs::metadata(file).is_ok_and(|m| m.len() > 0)
        {
            return Ok((xvfb, pid, stderr));
        }
        if t0.elapsed() > Duration::from_secs(60) || xvfb.try_wait().unwrap().is_some() {
            let _ = xvfb.kill();
            let _ = xvfb.wait();
            return Err(stderr.join().unwrap());
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Issue 29, item 4, the window: SIGTERM closes it the way its close button does (the
/// recording it makes with `--record` is closed with its summary) and the process exits 130.
/// Runs under `xvfb-run` (skipped without it, outside CI).
#[test]
fn sigterm_closes_the_window_and_its_recording() {
    if !on_path("xvfb-run") {
        assert!(std::env::var_os("CI").is_none(), "xvfb-run is missing (install xvfb xauth) and CI is set");
        parol6_tests::skip_notice("SKIPPED sigterm_closes_the_window_and_its_recording: no xvfb-run");
        return;
    }
    let dir = temp("gui");
    let runtime = dir.join("xdg");
    std::fs::create_dir_all(&runtime).unwrap();
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&runtime, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
    let file = dir.join("window.mcap");
    // `xvfb-run -a` can lose its display to another test starting one at the same time: again
    let mut failures = Vec::new();
    let (mut xvfb, pid, stderr) = loop {
        match start_window(&dir, &runtime, &file) {
            Ok(started) => break started,
            Err(e) if e.contains("X server") && failures.len() < 2 => failures.push(e),
            Err(e) => panic!("the window did not start recording within 60 s: {e} (before: {failures:#?})"),
        }
    };
    std::thread::sleep(Duration::from_secs(1));
    assert!(Command::new("kill").args(["-TERM", &pid.to_string()]).status().unwrap().success());
    let t1 = Instant::now();
    let status = loop {
        if let Some(st) = xvfb.try_wait().unwrap() {
            break st;
        }
        if t1.elapsed() > Duration::from_secs(20) {
            let _ = Command::new("kill").args(["-KILL", &pid.to_string()]).status();
            let _ = xvfb.wait();
            panic!("the window did not close within 20 s of SIGTERM: {}", stderr.join().unwrap());
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = stderr.join().unwrap();
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted by SIGTERM: the window closed"), "{stderr}");
    let info = run(&["mcap", "info", &s(&file)]).json("mcap info of the window's recording");
    assert_eq!(info["truncated"], false, "{info}");
    assert!(info["samples"].as_u64().unwrap() > 20, "{info}");
    let _ = std::fs::remove_dir_all(&dir);
}

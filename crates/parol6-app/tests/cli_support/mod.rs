//! Running the built `parol6` binary from the command-line tests: bounded in time, stdin
//! given (`quit` ends `hw emulate`), output captured.

#![allow(dead_code)]

use std::io::{Read, Write};
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// What one run of the binary did.
#[derive(Debug)]
pub struct Run {
    /// Exit status; `None` when it was killed for running past its time.
    pub status: Option<ExitStatus>,
    pub stdout: String,
    pub stderr: String,
    pub elapsed: Duration,
}

impl Run {
    /// The exit code, `None` when killed by a signal or the time limit.
    pub fn code(&self) -> Option<i32> {
        self.status.and_then(|s| s.code())
    }

    /// Panics with the whole record when the run panicked, aborted or died from a signal.
    pub fn assert_no_panic(&self, what: &str) {
        assert!(!self.stderr.contains("panicked at"), "{what}: panicked: {self:?}");
        assert!(self.code().is_some(), "{what}: killed (signal, abort or time limit): {self:?}");
    }

    /// Asserts exit 2 with `needle` in the one-line-or-clap error on stderr.
    pub fn assert_refused(&self, what: &str, needle: &str) {
        self.assert_no_panic(what);
        assert_eq!(self.code(), Some(2), "{what}: {self:?}");
        assert!(self.stderr.contains(needle), "{what}: stderr should mention {needle:?}: {self:?}");
        assert!(self.stdout.is_empty(), "{what}: nothing on stdout when refused: {self:?}");
    }

    /// The stdout as JSON, asserting success.
    pub fn json(&self, what: &str) -> serde_json::Value {
        assert_eq!(self.code(), Some(0), "{what}: {self:?}");
        serde_json::from_str(self.stdout.trim())
            .unwrap_or_else(|e| panic!("{what}: stdout is not JSON ({e}): {self:?}"))
    }
}

/// The built binary.
pub fn exe() -> &'static str {
    env!("CARGO_BIN_EXE_parol6")
}

/// The workspace root (where README.md and assets/ are).
pub fn workspace_root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// Runs `parol6 args…` in `dir` with "quit" on stdin, killing it after `limit`.
pub fn run_in<S: AsRef<std::ffi::OsStr>>(dir: &Path, args: &[S], limit: Duration) -> Run {
    let mut command = Command::new(exe());
    command.args(args).current_dir(dir);
    run_command(command, limit)
}

/// Runs a prepared command (program, arguments, directory, environment) with "quit" on stdin,
/// killing it after `limit`.
pub fn run_command(mut command: Command, limit: Duration) -> Run {
    let started = Instant::now();
    let mut child = command
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the parol6 binary starts");
    if let Some(mut stdin) = child.stdin.take() {
        let _ = stdin.write_all(b"quit\n");
    }
    let mut out = child.stdout.take().expect("stdout");
    let mut err = child.stderr.take().expect("stderr");
    let out_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = out.read_to_end(&mut s);
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err.read_to_end(&mut s);
        s
    });
    let status = loop {
        match child.try_wait().expect("wait for parol6") {
            Some(status) => break Some(status),
            None if started.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            None => std::thread::sleep(Duration::from_millis(5)),
        }
    };
    let stdout = String::from_utf8_lossy(&out_reader.join().unwrap_or_default()).into_owned();
    let stderr = String::from_utf8_lossy(&err_reader.join().unwrap_or_default()).into_owned();
    Run { status, stdout, stderr, elapsed: started.elapsed() }
}

/// Runs `parol6 args…` in the workspace root with a 60 s limit.
pub fn run<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Run {
    run_in(workspace_root(), args, Duration::from_secs(60))
}

/// True (after printing SKIPPED outside CI) when a render command failed for want of a
/// graphics adapter; in CI that is a failure.
pub fn no_adapter(run: &Run, test: &str) -> bool {
    let missing =
        run.code() == Some(1) && (run.stderr.contains("graphics adapter") || run.stderr.contains("graphics device"));
    if missing {
        assert!(std::env::var_os("CI").is_none(), "{test}: no usable graphics adapter in CI: {run:?}");
        parol6_tests::skip_notice(&format!("SKIPPED {test}: {}", run.stderr.trim()));
    }
    missing
}

/// True when python3 with the `eclipse-zenoh` package can run the ROS 2 peer scripts; otherwise
/// says SKIPPED, and in CI (`CI=true`, where `.ci/run` installs it) fails.
pub fn zenoh_peer_available() -> bool {
    let ok = std::process::Command::new("python3")
        .args(["-c", "import zenoh, zenoh.ext"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI: python3 with the eclipse-zenoh package is required (.ci/run installs it)"
        );
        eprintln!("SKIPPED: python3 with the `zenoh` module (pip install eclipse-zenoh==1.10.2) is not installed");
    }
    ok
}

/// Runs the peer script `crates/parol6-app/tests/ros2/SCRIPT` against `parol6 serve --ros2` on a
/// free loopback port (`--remote`: with remote control allowed); its JSON report, which must say ok.
pub fn run_zenoh_peer(script: &str, remote: bool) -> serde_json::Value {
    run_zenoh_peer_with(script, remote, &[])
}

/// [`run_zenoh_peer`] with more arguments for the script.
pub fn run_zenoh_peer_with(script: &str, remote: bool, extra: &[&str]) -> serde_json::Value {
    let script = workspace_root().join("crates/parol6-app/tests/ros2").join(script);
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free loopback port")
        .port()
        .to_string();
    let mut args = vec![script.to_str().expect("a UTF-8 path"), "--exe", exe(), "--port", &port];
    if remote {
        args.push("--remote");
    }
    args.extend_from_slice(extra);
    let out = std::process::Command::new("python3").args(&args).output().expect("python3 runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let report: serde_json::Value = serde_json::from_str(stdout.trim().lines().last().unwrap_or("null"))
        .unwrap_or_else(|e| panic!("the peer's report is not JSON ({e}): {stdout}\n{stderr}"));
    assert!(out.status.success() && report["ok"] == true, "peer failed: {report:#}\n{stderr}");
    report
}

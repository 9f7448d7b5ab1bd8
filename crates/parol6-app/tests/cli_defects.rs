//! Regression tests for command-line defects, each named after the defect, run through the
//! built binary. Exit status: 0 ok, 2 bad input or refused, 1 device or I/O failure.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::process::{Command, Stdio};
use std::time::Duration;

use cli_support::{no_adapter, run, run_in};

const STANDBY_DEG: &str = "90,-90,180,0,0,180";

#[test]
fn broken_pipe_panicked_instead_of_ending_quietly() {
    // The reader closes the pipe before the command writes: the write fails with EPIPE.
    for args in [
        vec!["fk", "--joints", STANDBY_DEG, "--deg"],
        vec!["bench", "fk", "--n", "1000"],
        vec!["hw", "status", "--fake-robot"],
        vec!["hw", "emulate"],
    ] {
        // The pipe's reader is closed before the child starts, so its first write fails
        // whatever the scheduling (closing it after the spawn raced with a fast first write,
        // and `hw emulate`, which then waits for `quit`, hung the test on a loaded machine).
        let (reader, writer) = std::io::pipe().expect("pipe");
        drop(reader);
        let child = Command::new(cli_support::exe())
            .args(&args)
            .stdin(Stdio::piped())
            .stdout(writer)
            .stderr(Stdio::piped())
            .spawn()
            .expect("parol6 starts");
        // `hw emulate` reads stdin after its first line; closing stdin ends nothing there, the
        // failed first write does.
        let out = child.wait_with_output().expect("parol6 ends");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(!err.contains("Broken pipe"), "{args:?}: quiet: {err}");
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
    }
}

#[test]
fn global_options_were_refused_before_the_subcommand() {
    let after = run(&["fk", "--joints", STANDBY_DEG, "--deg", "--tool", "ssg48"]).json("after");
    let before = run(&["--tool", "ssg48", "fk", "--joints", STANDBY_DEG, "--deg"]).json("before");
    assert_eq!(after, before);
    let bare = run(&["fk", "--joints", STANDBY_DEG, "--deg"]).json("bare");
    assert_ne!(bare["tcp"], before["tcp"], "the tool moved the TCP");
    let urdf = run(&["--urdf", "assets/parol6/parol6.urdf", "--tip", "L6", "fk", "--joints", STANDBY_DEG, "--deg"]);
    assert_eq!(urdf.json("--urdf before")["tcp"]["position_m"], bare["tcp"]["position_m"]);
    let status = run(&["--fake-robot", "hw", "status"]).json("--fake-robot before hw");
    assert_eq!(status["link"], "Connected");
    // A global option the subcommand would ignore is refused, wherever it stands.
    run(&["--tool", "ssg48", "bench", "fk", "--n", "10"]).assert_refused("--tool on bench fk", "does not apply");
    run(&["hw", "ports", "--fake-robot"]).assert_refused("--fake-robot on hw ports", "does not apply");
    run(&["--port", "/dev/null", "--fake-robot", "hw", "status"]).assert_refused("both", "cannot be used with");
}

#[test]
fn ik_position_in_mm_without_mm_gave_no_hint() {
    let r = run(&["ik", "--pose", "200,100,300,180,0,0", "--deg"]);
    r.assert_refused("mm without --mm", "did you mean --mm?");
    // The same position with --mm solves.
    let ok = run(&["ik", "--pose", "0,236.77,334,90,-90,0", "--mm", "--deg"]);
    assert!(!ok.json("--mm")["solutions"].as_array().expect("solutions").is_empty());
}

#[test]
fn hw_home_reported_enabled_null() {
    let v = run(&["hw", "home", "--fake-robot"]).json("hw home");
    assert_eq!(v["state"]["enabled"], true, "{v}");
    // known after homing: from the homing itself or from an ENABLE echo seen on the way
    let basis = v["state"]["enabled_basis"].as_str().unwrap_or_default().to_string();
    assert!(basis == "homed" || basis == "commanded", "{v}");
    let v = run(&["hw", "disable", "--fake-robot"]).json("hw disable");
    assert_eq!((&v["state"]["enabled"], &v["state"]["enabled_basis"]), (&false.into(), &"commanded".into()), "{v}");
    let v = run(&["hw", "status", "--fake-robot"]).json("hw status");
    assert_eq!((&v["enabled"], &v["enabled_basis"]), (&serde_json::Value::Null, &"unknown".into()), "{v}");
}

#[test]
fn screenshot_printed_the_xdg_warning_twice() {
    let dir = std::env::temp_dir().join(format!("parol6-xdg-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let out = Command::new(cli_support::exe())
        .args(["screenshot", "shot.png", "--size", "64x48"])
        .current_dir(&dir)
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("parol6 runs");
    let run = cli_support::Run {
        status: Some(out.status),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        elapsed: Duration::ZERO,
    };
    if !no_adapter(&run, "screenshot_printed_the_xdg_warning_twice") {
        run.json("screenshot");
        assert!(!run.stderr.contains("XDG_RUNTIME_DIR"), "{}", run.stderr);
        assert!(dir.join("shot.png").is_file());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each: the arguments, the refused option, and the range the refusal (and the option's
/// --help) must state.
const HUGE_AND_NONSENSE: &[(&[&str], &str, &str)] = &[
    (&["bench", "fk", "--n", "18446744073709551615"], "--n", "1..=10000000"),
    (&["bench", "fk", "--n", "100000000000"], "--n", "1..=10000000"),
    (&["bench", "fk", "--n", "0"], "--n", "1..=10000000"),
    (&["bench", "ik", "--n", "18446744073709551615"], "--n", "1..=1000000"),
    (&["bench", "ik", "--n", "0"], "--n", "1..=1000000"),
    (&["bench", "physics", "--n", "18446744073709551615"], "--n", "1..=1000000"),
    (&["bench", "physics", "--cpu-seconds", "1e300"], "--cpu-seconds", "0…600"),
    (&["bench", "latency", "--n", "18446744073709551615"], "--n", "1..=1000000"),
    (&["bench", "latency", "--interval-us", "18446744073709551615"], "--interval-us", "0..=100000"),
    (&["bench", "latency", "--interval-us", "18446744073709551614"], "--interval-us", "0..=100000"),
    (&["bench", "serial", "--presses", "18446744073709551615"], "--presses", "1..=1000"),
    (&["bench", "serial", "--seconds", "1e300"], "--seconds", "> 0 and ≤ 600"),
    (&["bench", "serial", "--rate", "5000"], "--rate", "50…500"),
    (&["bench", "render", "--seconds", "0"], "--seconds", "> 0 and ≤ 600"),
    (&["screenshot", "x.png", "--repeat", "18446744073709551615"], "--repeat", "1..=10000"),
    (&["hw", "move", "--fake-robot", "--joints", STANDBY_DEG, "--deg", "--speed", "1e-300"], "--speed", "0.05…1"),
    (&["hw", "move", "--fake-robot", "--joints", STANDBY_DEG, "--deg", "--speed", "1e-4"], "--speed", "0.05…1"),
    (&["hw", "move", "--fake-robot", "--joints", STANDBY_DEG, "--deg", "--speed", "5"], "--speed", "0.05…1"),
    (&["hw", "move", "--fake-robot", "--joints", STANDBY_DEG, "--deg", "--speed", "NaN"], "--speed", "finite"),
    (&["hw", "jog", "--fake-robot", "--joint", "7", "--speed", "0.1", "--seconds", "1"], "--joint", "1..=6"),
    (&["hw", "jog", "--fake-robot", "--joint", "1", "--speed", "2", "--seconds", "1"], "--speed", "-1…1"),
    (
        &["hw", "jog", "--fake-robot", "--joint", "1", "--speed", "0.1", "--seconds", "1e300"],
        "--seconds",
        "> 0 and ≤ 60",
    ),
    (&["hw", "status", "--fake-robot", "--rate", "10"], "--rate", "50…500"),
    (&["hw", "emulate", "--home-seconds", "0"], "--home-seconds", "> 0 and ≤ 60"),
];

#[test]
fn huge_numbers_panicked_and_nonsense_was_accepted() {
    for (args, option, range) in HUGE_AND_NONSENSE {
        let r = run(args);
        r.assert_refused(&format!("{args:?}"), range);
        assert!(r.elapsed < Duration::from_secs(10), "{args:?} refused at once: {:?}", r.elapsed);
        // The option's --help states the same range (clap writes "a..=b" for integers).
        let sub: Vec<&str> = args.iter().copied().take_while(|a| !a.starts_with('-') && !a.ends_with(".png")).collect();
        let help = run(&[sub.as_slice(), &["--help"]].concat());
        // the option's line and its description (clap moves a long description to the lines
        // below the option when the option column is wide)
        let lines: Vec<&str> = help.stdout.lines().collect();
        let at = lines
            .iter()
            .position(|line| line.trim_start().starts_with(&format!("{option} ")))
            .unwrap_or_else(|| panic!("{option} in the help of {sub:?}: {}", help.stdout));
        let more = lines[at + 1..].iter().take_while(|l| !l.trim_start().starts_with('-') && !l.trim().is_empty());
        let help_line = std::iter::once(lines[at]).chain(more.copied()).collect::<Vec<_>>().join(" ");
        let hi = range.split_once("..=").or_else(|| range.split_once('…')).map_or(*range, |(_, hi)| hi);
        let digits = |s: &str| s.chars().filter(char::is_ascii_digit).collect::<String>();
        let help_digits = digits(&help_line.replace(' ', ""));
        assert!(help_digits.contains(&digits(hi)), "{option} help {help_line:?} states the range {range}");
    }
}

#[test]
fn screenshot_dash_wrote_a_file_named_dash() {
    let dir = std::env::temp_dir().join(format!("parol6-dash-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    run_in(&dir, &["screenshot", "-", "--size", "8x8"], Duration::from_secs(30))
        .assert_refused("screenshot -", "stdout carries the JSON");
    assert!(!dir.join("-").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn silent_port_was_reported_as_link_lost() {
    // A fresh pseudo-terminal master: it opens, and nothing ever answers.
    let r = run(&["hw", "status", "--port", "/dev/ptmx"]);
    r.assert_no_panic("silent port");
    assert_eq!(r.code(), Some(1), "{r:?}");
    assert!(r.stderr.contains("no PAROL6 answered on /dev/ptmx within 3 s"), "{r:?}");
    assert!(!r.stderr.contains("link lost"), "{r:?}");
    // A port that does not exist is a device failure too.
    let r = run(&["hw", "status", "--port", "/nonexistent/ttyACM9"]);
    assert_eq!(r.code(), Some(1), "{r:?}");
}

#[test]
fn hw_commands_run_against_the_fake_robot() {
    let v = run(&["hw", "jog", "--fake-robot", "--joint", "1", "--speed", "0.5", "--seconds", "0.3"]).json("jog");
    let (a, b) = (v["start_deg"][0].as_f64().expect("deg"), v["end_deg"][0].as_f64().expect("deg"));
    assert!(b > a + 0.1, "J1 moved: {v}");
    let v =
        run(&["hw", "move", "--fake-robot", "--joints", "80,-90,180,0,0,180", "--deg", "--speed", "1"]).json("move");
    assert!((v["state"]["joint_deg"][0].as_f64().expect("deg") - 80.0).abs() < 0.1, "{v}");
    // Outside the limits: refused before the port is opened.
    run(&["hw", "move", "--fake-robot", "--joints", "0,0,0,0,0,0"]).assert_refused("outside limits", "limit");
}

#[test]
fn jog_into_a_limit_was_reported_as_refused() {
    // J1 from standby (90°) at full jog speed reaches its limit (123°) well within 3 s.
    let v = run(&["hw", "jog", "--fake-robot", "--joint", "1", "--speed", "1", "--seconds", "3"]).json("jog");
    assert_eq!(v["stopped_at_limit"], true, "{v}");
    assert!(v["end_deg"][0].as_f64().expect("deg") > 122.9, "{v}");
}

#[test]
fn fake_robot_link_dropped_on_a_busy_host_through_its_pty() {
    // Issue 32: a pty's bytes wait for a kernel worker that a busy host starves; `--fake-robot`
    // now talks to its emulator over a local socket (removed when the command ends).
    let v = run(&["hw", "status", "--fake-robot"]).json("hw status");
    let port = v["port"].as_str().expect("port");
    assert!(!port.starts_with("/dev/"), "the fake robot is a terminal device: {port}");
    assert!(port.contains("parol6-fake-robot-") && !std::path::Path::new(port).exists(), "{port}");
}

//! Starting the window without a display (e.g. over SSH) says so once, in plain words, and
//! exits 1 (issue 32 minor: it printed a winit source path and an XDG_RUNTIME_DIR complaint,
//! each twice).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::process::Command;

#[test]
fn the_window_without_a_display_says_so_once_and_exits_1() {
    let out = Command::new(env!("CARGO_BIN_EXE_parol6"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .env("PAROL6_SETTINGS", std::env::temp_dir().join("parol6-no-display-settings.json"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one message: {err}");
    for said in ["no display", "ssh -X", "parol6 --help", "parol6 screenshot"] {
        assert!(err.contains(said), "does not say {said}: {err}");
    }
    for not_said in ["winit", "XDG_RUNTIME_DIR", ".rs:"] {
        assert!(!err.contains(not_said), "says {not_said}: {err}");
    }
}

/// A display number nobody serves here (no X socket, no lock file), away from the numbers the
/// hand trials use.
fn unserved_display() -> String {
    let free = (150..400)
        .find(|n| {
            !std::path::Path::new(&format!("/tmp/.X11-unix/X{n}")).exists()
                && !std::path::Path::new(&format!("/tmp/.X{n}-lock")).exists()
        })
        .expect("a free display number");
    format!(":{free}")
}

/// Runs the window with `display` / `wayland` as DISPLAY / WAYLAND_DISPLAY (`None`: unset) and
/// checks that it says once, in plain words, that no display could be reached, and exits 1.
fn says_no_display_once(display: Option<&str>, wayland: Option<&str>) {
    let runtime = std::env::temp_dir().join(format!("parol6-no-display-runtime-{}", std::process::id()));
    std::fs::create_dir_all(&runtime).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_parol6"));
    cmd.env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY").env_remove("WAYLAND_SOCKET");
    cmd.env("XDG_RUNTIME_DIR", &runtime)
        .env("PAROL6_SETTINGS", std::env::temp_dir().join("parol6-no-display-settings.json"));
    if let Some(d) = display {
        cmd.env("DISPLAY", d);
    }
    if let Some(w) = wayland {
        cmd.env("WAYLAND_DISPLAY", w);
    }
    let out = cmd.output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let what = format!("DISPLAY={display:?} WAYLAND_DISPLAY={wayland:?}");
    assert_eq!(out.status.code(), Some(1), "{what}: {err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{what}: one message: {err}");
    for said in ["no display", "ssh -X", "parol6 --help", "parol6 screenshot"] {
        assert!(err.contains(said), "{what}: does not say {said}: {err}");
    }
    for named in display.into_iter().chain(wayland) {
        assert!(err.contains(named), "{what}: does not name {named}: {err}");
    }
    for not_said in ["winit", "XDG_RUNTIME_DIR", ".rs:", "os error"] {
        assert!(!err.contains(not_said), "{what}: says {not_said}: {err}");
    }
}

/// Issue 32's last minor: with DISPLAY set to a display nobody serves (an SSH session whose X
/// forwarding went away), the window's error was winit's, with its source path. It says, as
/// without a display, that none could be reached and what to do, and exits 1.
#[test]
fn the_window_with_an_unreachable_x_display_says_so_once_and_exits_1() {
    says_no_display_once(Some(&unserved_display()), None);
}

/// The same for a Wayland socket that is not there (alone, and with an unreachable X display).
#[test]
fn the_window_with_a_missing_wayland_socket_says_so_once_and_exits_1() {
    says_no_display_once(None, Some("parol6-no-such-wayland-socket"));
    says_no_display_once(Some(&unserved_display()), Some("parol6-no-such-wayland-socket"));
}

/// trial10 n4: every failure of the window system's start was reported as "no display was found",
/// also when a display answered and something else failed, hiding the cause. With WAYLAND_DISPLAY
/// naming a socket that accepts and hangs up (a display server that fails, not a missing one), the
/// window names that failure with its cause, not a missing display, and exits 1.
#[test]
fn a_window_system_failure_that_is_not_a_missing_display_is_named() {
    let runtime = std::env::temp_dir().join(format!("parol6-failing-wayland-{}", std::process::id()));
    std::fs::create_dir_all(&runtime).unwrap();
    let socket = runtime.join("parol6-hangs-up");
    if socket.exists() {
        std::fs::remove_file(&socket).unwrap();
    }
    let listener = std::os::unix::net::UnixListener::bind(&socket).unwrap();
    // each connection is accepted and closed at once
    std::thread::spawn(move || {
        for conn in listener.incoming() {
            drop(conn);
        }
    });
    let out = Command::new(env!("CARGO_BIN_EXE_parol6"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .env("WAYLAND_DISPLAY", "parol6-hangs-up")
        .env("XDG_RUNTIME_DIR", &runtime)
        .env("PAROL6_SETTINGS", std::env::temp_dir().join("parol6-no-display-settings.json"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let last = err.lines().rfind(|l| !l.trim().is_empty()).unwrap_or_default();
    assert!(!err.contains("no display"), "a display that fails is not a missing display: {err}");
    assert!(last.starts_with("error: cannot open the window at WAYLAND_DISPLAY=parol6-hangs-up: "), "{err}");
    assert!(last.contains("Broken pipe") || last.contains("Connection reset"), "keeps the cause: {err}");
    assert!(!last.contains(".rs:"), "no source path: {err}");
}

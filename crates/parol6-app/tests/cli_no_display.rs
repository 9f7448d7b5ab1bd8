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

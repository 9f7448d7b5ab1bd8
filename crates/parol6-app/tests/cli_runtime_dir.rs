//! Issue 32 minor: every start printed "error: XDG_RUNTIME_DIR is invalid or not set in the
//! environment." several times under Xvfb (libwayland-client, asked for the default Wayland
//! display by Mesa's Vulkan device-select layer while wgpu lists the adapters): 6 lines for the
//! window, 2 for `parol6 bench ui-actions`. Every command that opens a graphics adapter now runs
//! with a private runtime directory when none is set; here a headless one, with the variable
//! unset and with a relative path (libwayland's "invalid").

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::process::Command;
use std::time::Duration;

use cli_support::{exe, no_adapter, run_command, workspace_root};

/// `bench program-load` (the window, headless, on a 10-line program) with `XDG_RUNTIME_DIR`
/// set to `runtime` (`None`: unset).
fn program_load(runtime: Option<&str>) -> cli_support::Run {
    let mut command = Command::new(exe());
    command
        .args(["bench", "program-load", "--lines", "10", "--size", "320x240"])
        .current_dir(workspace_root())
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET");
    match runtime {
        Some(dir) => command.env("XDG_RUNTIME_DIR", dir),
        None => command.env_remove("XDG_RUNTIME_DIR"),
    };
    run_command(command, Duration::from_secs(240))
}

#[test]
fn a_headless_window_without_a_runtime_dir_prints_no_wayland_complaint() {
    for runtime in [None, Some("relative/run")] {
        let r = program_load(runtime);
        if no_adapter(&r, "a_headless_window_without_a_runtime_dir_prints_no_wayland_complaint") {
            return;
        }
        r.assert_no_panic("bench program-load");
        assert_eq!(r.code(), Some(0), "XDG_RUNTIME_DIR={runtime:?}: {r:?}");
        assert!(!r.stderr.contains("XDG_RUNTIME_DIR"), "XDG_RUNTIME_DIR={runtime:?}: stderr: {}", r.stderr);
    }
}

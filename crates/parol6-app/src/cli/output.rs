//! Everything the command line writes: JSON on stdout, warnings and errors on stderr. No
//! write panics: a closed stdout (the reader went away, `parol6 … | head`) ends the command
//! quietly, and stderr failures are ignored.

use std::io::Write;
use std::path::PathBuf;

use super::{CliError, CliResult};

/// Prints `value` as one line of JSON on stdout and flushes it.
pub fn print_json(value: &serde_json::Value) -> CliResult {
    print_line(&value.to_string())
}

/// Prints one line on stdout and flushes it; a closed stdout becomes [`CliError::stdout_closed`].
pub fn print_line(line: &str) -> CliResult {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{line}").and_then(|()| out.flush()).map_err(|e| match e.kind() {
        std::io::ErrorKind::BrokenPipe => CliError::stdout_closed(),
        _ => CliError::runtime(format!("cannot write to stdout: {e}")),
    })
}

/// Prints `warning: …` on stderr.
pub fn warn(message: impl std::fmt::Display) {
    let _ = writeln!(std::io::stderr(), "warning: {message}");
}

/// Prints a progress line on stderr.
pub fn progress(message: impl std::fmt::Display) {
    let _ = writeln!(std::io::stderr(), "{message}");
}

/// Prints `error: …` on stderr.
pub fn error_line(message: &str) {
    let _ = writeln!(std::io::stderr(), "error: {message}");
}

/// A private `XDG_RUNTIME_DIR` for the commands that open a graphics adapter (the window
/// included) when none is set. Mesa's Vulkan device-select layer (`VK_LAYER_MESA_device_select`)
/// asks libwayland-client for the default Wayland display each time the adapters are listed,
/// and libwayland prints "error: XDG_RUNTIME_DIR is invalid or not set in the environment." when
/// the variable is unset or not an absolute path (twice per adapter request: 6 lines at the
/// window's start under Xvfb). No Wayland display can be reached without it, so an empty
/// private directory loses nothing: the probe there fails quietly, the layer goes on with X11,
/// and every backend (Vulkan, GL) stays. A Wayland session always sets the variable (then this
/// does nothing), and an absolute `WAYLAND_DISPLAY` does not read it. `.ci/run` does the same
/// for the tests. Removed when dropped.
#[derive(Debug)]
pub struct PrivateRuntimeDir {
    path: PathBuf,
}

impl PrivateRuntimeDir {
    /// Creates and exports the directory when `XDG_RUNTIME_DIR` is unset or not a directory.
    /// Must be called before any thread is started.
    pub fn ensure() -> Option<Self> {
        // libwayland's test: set and absolute; a directory, or nothing could live there
        if std::env::var_os("XDG_RUNTIME_DIR").map(PathBuf::from).is_some_and(|d| d.is_absolute() && d.is_dir()) {
            return None;
        }
        let path = std::env::temp_dir().join(format!("parol6-runtime-{}", std::process::id()));
        let mut builder = std::fs::DirBuilder::new();
        #[cfg(unix)]
        std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
        builder.create(&path).ok()?;
        // SAFETY: called from `main` before any other thread exists, so nothing reads the
        // environment concurrently.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &path) };
        Some(Self { path })
    }
}

impl Drop for PrivateRuntimeDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}

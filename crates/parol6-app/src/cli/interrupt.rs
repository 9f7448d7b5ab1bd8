//! SIGINT (Ctrl-C) and SIGTERM: one process-wide "interrupted" flag, set by a handler that
//! [`install`] registers (from [`super::main`], for the commands that run until stopped), and
//! polled by every long-running loop: `record`, `hw jog|move` (with or without `--record`),
//! `program run`, `hw emulate`, `iso9283` and `path-test` on a backend, and the window.
//!
//! On the first signal each of them stops motion the normal way (the robot holds, then the
//! session closes with IDLE frames, as on link loss; the simulation gets STOP), closes its
//! recording with its summary (the open chunk is written), prints its JSON with
//! `"interrupted": "SIGINT"` and one line on stderr, and exits with [`EXIT_INTERRUPTED`]. A
//! second signal while it shuts down ends the process at once with the same status (the
//! recording may then lack its summary).
//!
//! The handlers only set atomics ([`signal_hook::flag`]); nothing else runs in a handler.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use signal_hook::consts::signal::{SIGINT, SIGTERM};

use super::CliError;

/// Exit status of a command ended by SIGINT or SIGTERM (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// How often the waits of this module look at the flag.
pub const POLL: Duration = Duration::from_millis(20);

/// The flags the handlers set.
struct Flags {
    /// Set by the first signal; arms the immediate exit on the second.
    armed: Arc<AtomicBool>,
    /// The number of the last signal received (0: none).
    signal: Arc<AtomicUsize>,
}

fn flags() -> &'static Flags {
    static FLAGS: OnceLock<Flags> = OnceLock::new();
    FLAGS.get_or_init(|| Flags { armed: Arc::new(AtomicBool::new(false)), signal: Arc::new(AtomicUsize::new(0)) })
}

/// Installs the SIGINT and SIGTERM handlers (once per process; later calls do nothing new).
pub fn install() -> Result<(), CliError> {
    static INSTALLED: OnceLock<Result<(), String>> = OnceLock::new();
    let result = INSTALLED.get_or_init(|| {
        let f = flags();
        for sig in [SIGINT, SIGTERM] {
            // The order matters: the exit is registered first, so the first signal only arms it.
            let registered = signal_hook::flag::register_conditional_shutdown(
                sig,
                i32::from(EXIT_INTERRUPTED),
                Arc::clone(&f.armed),
            )
            .and_then(|_| signal_hook::flag::register(sig, Arc::clone(&f.armed)))
            .and_then(|_| signal_hook::flag::register_usize(sig, Arc::clone(&f.signal), sig as usize));
            if let Err(e) = registered {
                return Err(format!("cannot install the handler of {}: {e}", name_of(sig)));
            }
        }
        Ok(())
    });
    result.clone().map_err(CliError::runtime)
}

fn name_of(sig: i32) -> &'static str {
    match sig {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        _ => "a signal",
    }
}

/// True once SIGINT or SIGTERM has arrived.
pub fn requested() -> bool {
    flags().signal.load(Ordering::SeqCst) != 0
}

/// The signal that arrived (`"SIGINT"`, `"SIGTERM"`), if any.
pub fn signal() -> Option<&'static str> {
    match flags().signal.load(Ordering::SeqCst) {
        0 => None,
        n => Some(name_of(i32::try_from(n).unwrap_or(0))),
    }
}

/// Sleeps for `duration`, or less when a signal arrives; true when one did.
pub fn sleep(duration: Duration) -> bool {
    let end = Instant::now() + duration;
    loop {
        if requested() {
            return true;
        }
        let now = Instant::now();
        if now >= end {
            return false;
        }
        std::thread::sleep(POLL.min(end - now));
    }
}

/// The error that ends an interrupted command: `"interrupted by SIGINT: {what}"`, exit 130.
pub fn error(what: impl std::fmt::Display) -> CliError {
    CliError { status: EXIT_INTERRUPTED, message: format!("interrupted by {}: {what}", signal().unwrap_or("a signal")) }
}

/// `{"signal": …}` for the JSON of an interrupted command (`null` when not interrupted).
pub fn json() -> serde_json::Value {
    signal().map_or(serde_json::Value::Null, |s| serde_json::Value::String(s.into()))
}

/// Closes the window when a signal arrives (a thread polls the flag and sends the close request
/// to the viewport; the window then closes the way its close button does).
pub fn close_window_on_signal(ctx: &eframe::egui::Context) {
    let ctx = ctx.clone();
    let spawned = std::thread::Builder::new().name("parol6-signals".into()).spawn(move || {
        while !requested() {
            std::thread::sleep(POLL);
        }
        ctx.send_viewport_cmd(eframe::egui::ViewportCommand::Close);
        ctx.request_repaint();
    });
    if let Err(e) = spawned {
        super::warn(format!("Ctrl-C will not close the window: cannot start its thread: {e}"));
    }
}

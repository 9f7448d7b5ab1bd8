//! How `hw jog|move` and `hw emulate` end on SIGINT / SIGTERM ([`super::interrupt`]): the arm
//! held, then the session closed with IDLE frames; the emulator's command ended with 130.

use std::time::Duration;

use parol6_hw::frame::CommandCode;
use parol6_hw::session::{MotionState, Snapshot};
use serde_json::json;

use super::hw::Link;
use super::{CliError, CliResult, interrupt};

/// MOVE frames at a fixed target the session sends, after a signal, before it closes.
const HOLD_FRAMES: u64 = 3;

/// After a signal: stops the motion (the session holds the commanded position of this
/// instant), waits until [`HOLD_FRAMES`] hold frames are on the wire (at most 0.5 s), then
/// closes the session, which leaves the board with IDLE frames (the emulator, if any, after
/// it). Returns `out` with `"interrupted"` and `"stopping"` (`hold_frames`, `held_steps`, the
/// `link` state at the signal, `then: "IDLE"`).
pub(super) fn hold_before_closing(link: Link, mut out: serde_json::Value) -> serde_json::Value {
    let session = &link.session;
    // a lost link has already stopped motion (IDLE): there is nothing to hold
    let link_state = session.snapshot().link;
    let stop = session.stop().map_err(|e| e.to_string());
    let holding = |s: &Snapshot| s.motion == MotionState::Holding && s.last_command == Some(CommandCode::Move);
    let first = session.wait_until(Duration::from_millis(400), holding).ok();
    let held = first.as_ref().and_then(|f| {
        let from = f.frames_sent;
        session.wait_until(Duration::from_millis(100), |s| holding(s) && s.frames_sent >= from + HOLD_FRAMES).ok()
    });
    let hold_frames = match (&first, &held) {
        (Some(f), Some(h)) => h.frames_sent - f.frames_sent + 1,
        (Some(_), None) => 1,
        _ => 0,
    };
    let held_steps = held.or(first).and_then(|s| s.target_steps);
    drop(link);
    out["interrupted"] = interrupt::json();
    out["stopping"] = json!({
        "hold_frames": hold_frames,
        "held_steps": held_steps,
        "stop_error": stop.err(),
        "link": link_state,
        "then": "IDLE",
    });
    out
}

/// `hw emulate` until `quit` or a signal: the emulator serves its stdin on a thread of its own
/// (a read of stdin cannot be interrupted); a signal ends the command with 130 (the process
/// exit closes the pseudo-terminal).
pub(super) fn emulate_until_signal(homed: bool, home_seconds: f64) -> CliResult {
    let (done_tx, done_rx) = crossbeam_channel::bounded(1);
    std::thread::Builder::new()
        .name("parol6-emulate".into())
        .spawn(move || {
            // the receiver is gone only once the command has ended
            if done_tx.send(super::hw::emulate(homed, home_seconds)).is_err() {
                tracing::debug!("hw emulate ended after its command");
            }
        })
        .map_err(|e| CliError::runtime(format!("cannot start the emulator thread: {e}")))?;
    loop {
        match done_rx.recv_timeout(interrupt::POLL) {
            Ok(result) => return result,
            Err(crossbeam_channel::RecvTimeoutError::Timeout) if interrupt::requested() => {
                return Err(interrupt::error("emulator stopped"));
            }
            Err(crossbeam_channel::RecvTimeoutError::Timeout) => {}
            Err(crossbeam_channel::RecvTimeoutError::Disconnected) => {
                return Err(CliError::runtime("the emulator thread ended without a result"));
            }
        }
    }
}

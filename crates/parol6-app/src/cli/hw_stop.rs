//! How `hw jog|move` and `hw emulate` end on SIGINT / SIGTERM ([`super::interrupt`]): the arm
//! held, then the session closed with IDLE frames; the emulator's command ended with 130.

use std::time::Duration;

use parol6_hw::frame::CommandCode;
use parol6_hw::session::{MotionState, Snapshot};
use serde_json::json;

use super::common::Link;
use super::interrupt;

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

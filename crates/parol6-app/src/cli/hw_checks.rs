//! What `parol6 hw jog` / `hw move` decide about the controller before and after motion, and
//! the stdin lines of `hw emulate`: device and link events are exit 1 naming their cause
//! (issue 29 item 12), the user's input stays exit 2.

use std::io::BufRead;
use std::time::{Duration, Instant};

use parol6_hw::HwError;
use parol6_hw::session::{LinkState, Session, Snapshot, impossible_answers};

use super::CliError;
use super::common::hw_err;

/// A jog whose commanded position moved this many steps or more must show in the measured one.
const JOG_EXPECTED_STEPS: i64 = 20;

/// Exit 1 naming the cause when the controller cannot move now for a device reason (link down,
/// impossible positions); a refusal for the user's request stays for the command itself.
pub fn ready_to_move(s: &Snapshot) -> Result<(), CliError> {
    match s.motion_allowed() {
        Err(e @ HwError::Device(_)) => Err(hw_err(e)),
        _ => Ok(()),
    }
}

/// A fault the session reported since `start` (a new one, not the one it began with).
pub fn new_fault(start: &Snapshot, now: &Snapshot) -> Option<String> {
    now.fault.clone().filter(|f| start.fault.as_ref() != Some(f))
}

/// How a jog ended, as far as the loop knows.
#[derive(Debug, Clone, Default)]
pub struct JogEnd {
    /// The session refused to go on with the commanded position at the joint's limit.
    pub stopped_at_limit: bool,
    /// A fault the session reported during the jog (motion was stopped).
    pub fault: Option<String>,
}

/// Checks a finished jog of `joint` (0-based): exit 1 naming the cause for a link loss,
/// impossible positions, a fault during the jog or an arm that did not follow
/// (`commanded_steps`: where the session's commanded position ended).
pub fn jog_outcome(
    joint: usize,
    start: &Snapshot,
    end: &Snapshot,
    commanded_steps: Option<i32>,
    how: &JogEnd,
) -> Result<(), CliError> {
    if end.link != LinkState::Connected {
        return Err(CliError::runtime(format!("link lost during the jog: {}", end.fault.clone().unwrap_or_default())));
    }
    if let Some(b) = end.limit_breach.filter(|b| b.impossible) {
        return Err(CliError::runtime(impossible_answers(&b)));
    }
    let from = start.joint_steps.get(joint).copied().unwrap_or(0);
    let to = end.joint_steps.get(joint).copied().unwrap_or(0);
    let moved = (i64::from(to) - i64::from(from)).abs();
    let commanded = commanded_steps.map(|c| (i64::from(c) - i64::from(from)).abs()).unwrap_or(0);
    let fault = how.fault.clone().or_else(|| new_fault(start, end));
    // A jog that reached the limit started inside it (else it is refused): the joint moved.
    let still = (commanded >= JOG_EXPECTED_STEPS && moved * 2 < commanded)
        || ((fault.is_some() || how.stopped_at_limit) && moved < 3);
    if still {
        let why = fault.clone().map(|f| format!("; {f}")).unwrap_or_default();
        return Err(CliError::runtime(format!(
            "the arm did not move: J{} stayed at {from} → {to} steps while {commanded} steps were commanded{why}; \
             the board does not report its enable latch: is the controller disabled (parol6 hw enable) or the \
             arm blocked?",
            joint + 1
        )));
    }
    if let Some(f) = fault {
        return Err(CliError::runtime(format!("the jog stopped: {f}")));
    }
    Ok(())
}

/// `hw jog --beyond-limit`: the operator's confirmed jog of `joint` (0-based), measured a
/// little beyond one of its limits, back inside (JOG speed frames, inward only) for at most
/// `duration`. True when the joint is within its limits at the end.
pub fn jog_back_inside(session: &Session, joint: usize, speed: f64, duration: Duration) -> Result<bool, CliError> {
    let end = Instant::now() + duration;
    let beyond = |s: &Snapshot| s.limit_breach.is_some_and(|b| b.joint == joint + 1);
    session.jog_back_inside(joint, speed).map_err(hw_err)?;
    while Instant::now() < end {
        std::thread::sleep(Duration::from_millis(50));
        let s = session.snapshot();
        if !beyond(&s) {
            break;
        }
        if s.link != LinkState::Connected || s.estop_pressed {
            return Err(CliError::runtime(format!(
                "the jog back inside stopped: {}",
                s.fault.clone().unwrap_or_default()
            )));
        }
        session.jog_back_inside(joint, speed).map_err(hw_err)?;
    }
    // The session ends the JOG frames itself once the joint is inside (or at the dead-man).
    std::thread::sleep(Duration::from_millis(300));
    Ok(!beyond(&session.snapshot()))
}

/// One stdin line of `hw emulate`, read as bytes so that invalid UTF-8 cannot stop the reader
/// (issue 29 item 10). `Ok(None)` at the end of input; `Ok(Some(Err(msg)))` for a line that is
/// not UTF-8, naming it (line number and the offending byte offset).
pub fn read_command_line(
    input: &mut impl BufRead,
    line_no: u64,
    buf: &mut Vec<u8>,
) -> std::io::Result<Option<Result<String, String>>> {
    buf.clear();
    if input.read_until(b'\n', buf)? == 0 {
        return Ok(None);
    }
    Ok(Some(match std::str::from_utf8(buf) {
        Ok(text) => Ok(text.trim_end_matches(['\n', '\r']).to_string()),
        Err(e) => {
            Err(format!("stdin line {line_no} is not UTF-8 (invalid byte at offset {}): ignored", e.valid_up_to()))
        }
    }))
}

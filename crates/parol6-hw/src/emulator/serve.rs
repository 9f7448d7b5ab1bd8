//! The emulator's thread: reads command frames from its wire (the pty's master side or the
//! fake robot's socket), lets the firmware model run, answers each accepted frame.

use std::io::{Read, Write};
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use super::{ControllerModel, ReceivedFrame, Shared, snapshot_of};
use crate::parser::CommandParser;

/// Serves `model` on `wire` until stopped: one status reply per accepted frame. A read that
/// finds nothing within its timeout (2 ms) returns [`std::io::ErrorKind::TimedOut`].
pub(super) fn serve<W: Read + Write>(mut wire: W, mut model: ControllerModel, sh: &Shared, log_max: usize) {
    let mut parser = CommandParser::new();
    let mut buf = [0u8; 4096];
    let mut last = Instant::now();
    let mut replies = 0u64;
    while !sh.stop.load(Ordering::Relaxed) {
        let n = match wire.read(&mut buf) {
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => 0,
            Err(e) => {
                tracing::debug!("emulator read: {e}");
                std::thread::sleep(Duration::from_millis(2));
                0
            }
        };
        model.estop_pressed = sh.estop_pressed.load(Ordering::Relaxed);
        model.in1 = sh.in1.load(Ordering::Relaxed);
        model.in2 = sh.in2.load(Ordering::Relaxed);
        for &b in &buf[..n] {
            let Some(cmd) = parser.push_byte(b) else { continue };
            let now = Instant::now();
            model.advance(now.duration_since(last).as_secs_f64());
            last = now;
            let status = model.accept(cmd, now);
            if log_max > 0 {
                let mut log = match sh.log.lock() {
                    Ok(l) => l,
                    Err(p) => p.into_inner(),
                };
                if log.len() < log_max {
                    log.push(ReceivedFrame { at: now, command: cmd });
                }
            }
            let st = parser.stats();
            sh.snapshot.store(Arc::new(snapshot_of(&model, st.accepted, st.rejected)));
            if sh.mute.load(Ordering::Relaxed) {
                continue;
            }
            let mut status = status;
            let mut delay = Duration::from_micros(sh.reply_delay_us.load(Ordering::Relaxed));
            if let Some(corrupt) = match sh.corruptor.lock() {
                Ok(c) => c,
                Err(p) => p.into_inner(),
            }
            .as_mut()
            {
                delay += corrupt(replies, &mut status);
            }
            replies += 1;
            if !delay.is_zero() {
                std::thread::sleep(delay);
            }
            if let Err(e) = wire.write_all(&status.encode()) {
                tracing::debug!("emulator write: {e}");
            }
        }
        let now = Instant::now();
        model.advance(now.duration_since(last).as_secs_f64());
        last = now;
    }
}

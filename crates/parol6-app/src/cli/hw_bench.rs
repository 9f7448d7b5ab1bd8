//! `parol6 bench serial`: the real serial session against the in-process controller emulator.

use std::time::{Duration, Instant};

use parol6_hw::emulator::{EmulatorConfig, EmulatorHandle};
use parol6_hw::frame::CommandCode;
use parol6_hw::session::{Session, SessionConfig};
use parol6_hw::units;
use serde_json::json;

use super::common::NsStats;
use super::common::{CONNECT_TIMEOUT, hw_err};
use super::{CliError, CliResult, print_json};

/// `parol6 bench serial`: runs the real session against the in-process emulator over a pty
/// and measures the period jitter (as the controller receives the frames) and the latency
/// from a jog press to the first changed MOVE target on the wire.
pub fn bench_serial(seconds: f64, rate_hz: f64, presses: usize) -> CliResult {
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= 600.0) {
        return Err(CliError::usage("--seconds must be > 0 and ≤ 600"));
    }
    if !(1..=1000).contains(&presses) {
        return Err(CliError::usage("--presses must be within 1–1000"));
    }
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).map_err(hw_err)?;
    let config = SessionConfig { rate_hz, write_log_capacity: 1 << 16, ..SessionConfig::default() };
    let session = Session::open(emu.path(), config).map_err(hw_err)?;
    session.wait_connected(CONNECT_TIMEOUT).map_err(hw_err)?;
    let period_s = 1.0 / rate_hz;

    // 1. Period jitter while idle: host write times (the session's period) and the
    //    controller's receive times (adds pty transfer and emulator wake-up).
    let _ = emu.take_received();
    let _ = session.take_write_times();
    std::thread::sleep(Duration::from_secs_f64(seconds));
    let frames = emu.take_received();
    let writes = session.take_write_times();
    let mut write_dev_ns: Vec<f64> =
        writes.windows(2).map(|w| (w[1].duration_since(w[0]).as_secs_f64() - period_s).abs() * 1e9).collect();
    let write_jitter = NsStats::from_samples(&mut write_dev_ns);
    let write_jitter_max_ns = write_dev_ns.last().copied().unwrap_or(0.0);
    let mut dev_ns: Vec<f64> =
        frames.windows(2).map(|w| (w[1].at.duration_since(w[0].at).as_secs_f64() - period_s).abs() * 1e9).collect();
    let achieved_hz = if frames.len() >= 2 {
        (frames.len() - 1) as f64 / frames[frames.len() - 1].at.duration_since(frames[0].at).as_secs_f64()
    } else {
        0.0
    };
    let jitter = NsStats::from_samples(&mut dev_ns);
    let session_jitter_p99_ms = session.snapshot().period_jitter_p99_ms;

    // 2. Jog press → first changed target on the wire.
    let mut lat_ns = Vec::with_capacity(presses);
    // J1 target of the last frame seen before each press.
    let mut last_known = frames.last().map(|f| f.command.fields.positions_steps[0]);
    for k in 0..presses {
        // Spread the press over the period.
        std::thread::sleep(Duration::from_secs_f64(period_s * (k % 7) as f64 / 7.0));
        let before = emu.take_received();
        if let Some(f) = before.last() {
            last_known = Some(f.command.fields.positions_steps[0]);
        }
        let last_target = last_known;
        let pressed = Instant::now();
        let dir = if k % 2 == 0 { 1.0 } else { -1.0 };
        session.jog(0, dir).map_err(hw_err)?;
        let deadline = pressed + Duration::from_secs(1);
        let mut found = None;
        let mut seen = Vec::new();
        while found.is_none() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(1));
            seen.extend(emu.take_received());
            let mut prev = last_target;
            for f in &seen {
                let t = f.command.fields.positions_steps[0];
                if f.at >= pressed && f.command.code == CommandCode::Move.byte() && prev.is_some_and(|p| p != t) {
                    found = Some(f.at);
                    break;
                }
                prev = Some(t);
            }
        }
        session.jog_release().map_err(hw_err)?;
        std::thread::sleep(Duration::from_millis(150));
        seen.extend(emu.take_received());
        last_known = seen.last().map(|f| f.command.fields.positions_steps[0]).or(last_known);
        let Some(at) = found else {
            return Err(CliError::runtime("a jog press never reached the wire within 1 s"));
        };
        lat_ns.push(at.duration_since(pressed).as_secs_f64() * 1e9);
    }
    let latency = NsStats::from_samples(&mut lat_ns);
    let lat_max_ns = lat_ns.last().copied().unwrap_or(0.0);
    let jitter_max_ns = dev_ns.last().copied().unwrap_or(0.0);
    let s = session.snapshot();
    print_json(&json!({
        "bench": "serial",
        "rate_hz": rate_hz,
        "period_ms": period_s * 1e3,
        "achieved_rate_hz": achieved_hz,
        "frames": frames.len(),
        "period_jitter": write_jitter.json(),
        "period_jitter_p99_ms": write_jitter.p99_ns / 1e6,
        "period_jitter_max_ms": write_jitter_max_ns / 1e6,
        "received_period_jitter": jitter.json(),
        "received_period_jitter_p99_ms": jitter.p99_ns / 1e6,
        "received_period_jitter_max_ms": jitter_max_ns / 1e6,
        "session_snapshot_jitter_p99_ms": session_jitter_p99_ms,
        "jog_latency": latency.json(),
        "jog_latency_max_ms": lat_max_ns / 1e6,
        "jog_within_one_period": lat_max_ns <= period_s * 1e9,
        "jitter_p99_within_1ms": write_jitter.p99_ns <= 1e6,
        "missing_replies": s.missing_replies,
        "invalid_frames": s.invalid_frames,
        "jog_max_steps_s_j1": units::jog_max_speed_steps_s()[0],
    }))
}

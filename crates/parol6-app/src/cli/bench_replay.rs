//! `parol6 bench replay`: writes a synthetic recording (every joint moving, a program step
//! event every 10 s) of `--minutes` at `--rate` Hz, then opens it for replay the way the
//! window does ([`read_replay_file`]) and prints the open time (`open_ms_median`,
//! target ≤ 1000 ms for ten minutes).

use std::io::Cursor;
use std::time::Instant;

use parol6_core::RobotModel;
use parol6_core::limits::ZoneThresholds;
use parol6_core::model::PAROL6_URDF;
use parol6_core::motion::{JointDrive, MotionSample, Setpoint, home_position};
use parol6_core::telemetry::{
    EventKind, McapSink, ReadPath, RecordingInfo, SampleBuilder, TelemetryEvent, read_replay_file,
    replay::REPLAY_RATE_HZ,
};
use serde_json::json;

use super::{CliError, CliResult, print_json};

/// The open time a ten-minute recording must meet, ms.
pub const TARGET_OPEN_MS: f64 = 1000.0;

/// Tick `k` of a source at `rate_hz` moving every joint (commanded slightly ahead).
fn motion(k: u64, rate_hz: f64, home: &[f64]) -> MotionSample {
    let t = k as f64 / rate_hz;
    let wave = |i: usize, lag_s: f64| 0.3 * (0.4 * (t - lag_s) + i as f64).sin();
    let q: Vec<f64> = home.iter().enumerate().map(|(i, h)| h + wave(i, 0.004)).collect();
    let cmd: Vec<f64> = home.iter().enumerate().map(|(i, h)| h + wave(i, 0.0)).collect();
    let qd: Vec<f64> = (0..home.len()).map(|i| 0.12 * (0.4 * t + i as f64).cos()).collect();
    MotionSample {
        seq: k,
        time_s: t,
        commanded: Setpoint { q: cmd, qd: qd.clone(), qdd: vec![0.0; home.len()] },
        measured_q: q,
        measured_qd: qd,
        drive: JointDrive::TorqueNm((0..home.len()).map(|i| (t + i as f64).sin()).collect()),
    }
}

/// Writes the synthetic recording into memory.
pub fn synthetic_recording(model: &RobotModel, minutes: f64, rate_hz: f64) -> Result<Vec<u8>, CliError> {
    write_synthetic_recording(Cursor::new(Vec::new()), model, minutes, rate_hz).map(Cursor::into_inner)
}

/// Writes the synthetic recording to `path` as it is made (a ten-minute one is ~60 MB: not
/// held in memory, so a benchmark's peak memory is the app's), atomically: a failed write
/// leaves no file, and a target that is not a regular file is refused.
pub fn write_synthetic_recording_file(
    path: &std::path::Path,
    model: &RobotModel,
    minutes: f64,
    rate_hz: f64,
) -> Result<(), CliError> {
    let mut failed: Option<CliError> = None;
    let written = parol6_core::fsio::write_atomic_seekable(path, |w| {
        write_synthetic_recording(&mut *w, model, minutes, rate_hz).map(drop).map_err(|e| {
            let message = e.message.clone();
            failed = Some(e);
            std::io::Error::other(message)
        })
    });
    match (failed, written) {
        (Some(e), _) => Err(e),
        (None, written) => Ok(written?),
    }
}

/// [`synthetic_recording`] into any writer; gives the writer back.
fn write_synthetic_recording<W: std::io::Write + std::io::Seek>(
    writer: W,
    model: &RobotModel,
    minutes: f64,
    rate_hz: f64,
) -> Result<W, CliError> {
    let info = RecordingInfo {
        app_version: env!("CARGO_PKG_VERSION").into(),
        tool: "none".into(),
        program: "synthetic".into(),
        urdf_text: PAROL6_URDF.into(),
        tracking: String::new(),
    };
    let mut sink = McapSink::new(writer, model, &info).map_err(CliError::runtime)?;
    let mut builder = SampleBuilder::new(model.clone(), ZoneThresholds::default());
    let home = home_position(model);
    let ticks = (minutes * 60.0 * rate_hz).round() as u64;
    let per_step = (10.0 * rate_hz).round().max(1.0) as u64;
    for k in 0..ticks {
        if k % per_step == 0 {
            let step = (k / per_step) as usize;
            builder.program_step = Some(step);
            let e = TelemetryEvent {
                time_s: k as f64 / rate_hz,
                kind: EventKind::ProgramStep { step: Some(step) },
                message: format!("program step {}", step + 1),
            };
            sink.write_event(&e).map_err(CliError::runtime)?;
        }
        let s = builder.build(&motion(k, rate_hz, &home));
        sink.write_sample(&s).map_err(CliError::runtime)?;
    }
    let (_, writer) = sink.finish_into_inner().map_err(CliError::runtime)?;
    Ok(writer)
}

/// Runs `parol6 bench replay`.
pub fn bench_replay(minutes: f64, rate_hz: f64, repeats: usize, keep: Option<&std::path::Path>) -> CliResult {
    let model = RobotModel::parol6();
    let path = match keep {
        Some(p) => p.to_path_buf(),
        None => std::env::temp_dir().join(format!("parol6-bench-replay-{}.mcap", std::process::id())),
    };
    let t0 = Instant::now();
    write_synthetic_recording_file(&path, &model, minutes, rate_hz)?;
    let write_s = t0.elapsed().as_secs_f64();
    let mut open_ms = Vec::new();
    let mut open_cpu_ms = Vec::new();
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        let cpu0 = parol6_core::process::process_cpu_time_ns();
        let replay = read_replay_file(&path, &model).map_err(CliError::runtime);
        open_ms.push(t.elapsed().as_secs_f64() * 1e3);
        if let (Some(a), Some(b)) = (cpu0, parol6_core::process::process_cpu_time_ns()) {
            open_cpu_ms.push(b.saturating_sub(a) as f64 * 1e-6);
        }
        last = Some(replay?);
    }
    let bytes_on_disk = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    if keep.is_none() {
        let _ = std::fs::remove_file(&path);
    }
    let replay = last.ok_or_else(|| CliError::runtime("nothing was opened"))?;
    open_ms.sort_by(f64::total_cmp);
    open_cpu_ms.sort_by(f64::total_cmp);
    let median = parol6_core::stats::percentile(&open_ms, 0.5).unwrap_or(0.0);
    let cpu_median = parol6_core::stats::percentile(&open_cpu_ms, 0.5);
    let ten_minutes = minutes >= 10.0;
    print_json(&json!({
        "target": "replay",
        "minutes": minutes,
        "rate_hz": rate_hz,
        "file_bytes": bytes_on_disk,
        "kept_at": keep.map(|p| p.display().to_string()),
        "samples_in_file": replay.samples_in_file,
        "samples_kept": replay.store.len(),
        "kept_rate_hz": REPLAY_RATE_HZ,
        "events": replay.events.len(),
        "read_path": match replay.read_path {
            ReadPath::Parallel { threads, chunks } => json!({ "parallel": { "threads": threads, "chunks": chunks } }),
            ReadPath::Linear => json!("linear"),
        },
        "write_s": write_s,
        "open_ms": open_ms,
        "open_ms_median": median,
        // the process's CPU time (all the decoding threads): the work the open costs
        "open_cpu_ms_median": cpu_median,
        "target_open_ms": TARGET_OPEN_MS,
        "pass": !ten_minutes || median <= TARGET_OPEN_MS,
    }))
}

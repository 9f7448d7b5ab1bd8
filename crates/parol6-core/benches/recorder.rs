//! Recorder CPU: Criterion times one 1 kHz simulation sample through the sample builder and
//! the MCAP writer (JSON, zstd chunks); then `recorder_10_min` pushes ten minutes of 1 kHz
//! samples (600 000) through a running [`Recorder`] writing a file, and prints the recorder
//! thread's CPU time as a share of one core over those ten minutes of real time.

#![allow(clippy::expect_used)] // a failed setup ends the benchmark with its reason
use std::hint::black_box;
use std::io::Cursor;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group};
use parol6_core::RobotModel;
use parol6_core::limits::ZoneThresholds;
use parol6_core::model::PAROL6_URDF;
use parol6_core::motion::{JointDrive, MotionSample, Setpoint, home_position};
use parol6_core::telemetry::{McapSink, Recorder, RecorderConfig, RecordingInfo, SampleBuilder};

fn info() -> RecordingInfo {
    RecordingInfo {
        app_version: "bench".into(),
        tool: "none".into(),
        program: String::new(),
        urdf_text: PAROL6_URDF.into(),
        tracking: String::new(),
    }
}

/// Tick `k` of a 1 kHz simulation moving every joint slowly.
fn motion(k: u64, home: &[f64]) -> MotionSample {
    let t = k as f64 * 1e-3;
    let q: Vec<f64> = home.iter().map(|h| h + 0.1 * (0.5 * t).sin()).collect();
    let qd: Vec<f64> = home.iter().map(|_| 0.05 * (0.5 * t).cos()).collect();
    MotionSample {
        seq: k,
        time_s: t,
        commanded: Setpoint { q: q.clone(), qd: qd.clone(), qdd: vec![0.0; q.len()] },
        measured_q: q,
        measured_qd: qd,
        drive: JointDrive::TorqueNm(vec![1.0; 6]),
    }
}

fn per_sample(c: &mut Criterion) {
    let model = RobotModel::parol6();
    let home = home_position(&model);
    let mut builder = SampleBuilder::new(model.clone(), ZoneThresholds::default());
    let mut sink = McapSink::new(Cursor::new(Vec::new()), &model, &info()).expect("sink");
    let mut k = 0u64;
    c.bench_function("recorder_sample_to_mcap", |b| {
        b.iter(|| {
            k += 1;
            let s = builder.build(&motion(k, &home));
            sink.write_sample(black_box(&s)).expect("write");
        })
    });
}

fn recorder_10_min() {
    let model = RobotModel::parol6();
    let home = home_position(&model);
    let rec = Recorder::start(model, RecorderConfig::default()).expect("recorder");
    let path = std::env::temp_dir().join(format!("parol6-bench-recorder-{}.mcap", std::process::id()));
    rec.start_recording(&path, &info()).expect("file");
    let tap = rec.tap();
    let n = 600_000u64;
    let t0 = Instant::now();
    for k in 1..=n {
        let mut m = motion(k, &home);
        while let Err(e) = tap.try_send(m) {
            m = e.into_inner();
            std::thread::sleep(Duration::from_micros(200));
        }
    }
    while rec.stats().samples < n {
        std::thread::sleep(Duration::from_millis(5));
    }
    let stats = rec.stats();
    let summary = rec.finish().expect("finish").expect("recording");
    let wall = t0.elapsed().as_secs_f64();
    let bytes = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    let _ = std::fs::remove_file(&path);
    let cpu_s = stats.thread_cpu_ns as f64 * 1e-9;
    println!(
        "recorder_10_min: {n} samples ({} written, {} missing) in {wall:.1} s wall; recorder thread CPU {cpu_s:.2} s = {:.2} % of one core over 600 s of 1 kHz data; file {:.1} MB",
        summary.samples,
        stats.missing_samples,
        cpu_s / 600.0 * 100.0,
        bytes as f64 / 1e6
    );
}

criterion_group!(benches, per_sample);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    recorder_10_min();
}

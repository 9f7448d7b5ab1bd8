//! Test hooks driven by `PAROL6_TEST_SCRIPT`: the GUI smoke test and the window sweep benchmark
//! (the soak run is in `app::soak`), all behind the app's one [`Hook`] field. The PNG and memory
//! figures they write come from the leaf module [`crate::artifacts`].

use eframe::egui;
use std::path::PathBuf;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::Parol6App;
use crate::panels::PanelContext;
use crate::panels::joints::JointsPanel;

/// Test hook driven by `PAROL6_TEST_SCRIPT` (used by the GUI smoke test).
#[derive(Debug, Clone, PartialEq)]
pub enum TestScript {
    /// `smoke:OUT.png`: screenshot, move joint 1 through the slider path, wait for the
    /// simulation to follow, screenshot again (`OUT.png`; the first one beside it as
    /// `OUT.before.png`), print a JSON line, exit 0 (1 on failure).
    Smoke(PathBuf),
    /// `sweep:SECONDS`: run the joint sweep for that long in the window, print frame statistics
    /// as JSON (`fps_median`, `frame_ms_p50`, `frame_ms_p99`, `ui_cpu_ms_p50`, `first_frame_ms`,
    /// `rss_mb_peak`) and exit.
    Sweep(f64),
    /// `soak:SECONDS[:PROGRAM]`: loop a built-in program for that long, sampling memory, the
    /// link and the recorder (see `app::soak`), print a summary and exit (1 when not ok).
    Soak(f64, Option<String>),
}

impl TestScript {
    /// Parses `PAROL6_TEST_SCRIPT`; `Err` for an unknown script.
    pub fn from_env() -> anyhow::Result<Option<Self>> {
        match std::env::var("PAROL6_TEST_SCRIPT") {
            Err(_) => Ok(None),
            Ok(s) => match s.split_once(':') {
                Some(("smoke", path)) if !path.is_empty() => Ok(Some(TestScript::Smoke(PathBuf::from(path)))),
                Some(("sweep", secs)) => match secs.parse::<f64>() {
                    Ok(v) if v.is_finite() && v > 0.0 => Ok(Some(TestScript::Sweep(v))),
                    _ => anyhow::bail!("PAROL6_TEST_SCRIPT: sweep needs seconds > 0, got \"{secs}\""),
                },
                Some(("soak", rest)) => {
                    let (secs, program) = match rest.split_once(':') {
                        Some((secs, name)) if !name.is_empty() => (secs, Some(name.to_string())),
                        _ => (rest, None),
                    };
                    match secs.parse::<f64>() {
                        Ok(v) if v.is_finite() && v > 0.0 => Ok(Some(TestScript::Soak(v, program))),
                        _ => anyhow::bail!("PAROL6_TEST_SCRIPT: soak needs seconds > 0, got \"{secs}\""),
                    }
                }
                _ => anyhow::bail!(
                    "PAROL6_TEST_SCRIPT: unknown script \"{s}\" (expected smoke:OUT.png, sweep:SECONDS or \
                     soak:SECONDS[:PROGRAM])"
                ),
            },
        }
    }
}

/// The script a window runs (at most one): the app's one field for its test hooks.
pub(super) enum Hook {
    /// The smoke test.
    Smoke(TestRunner),
    /// The window sweep benchmark.
    Sweep(SweepRun),
    /// The soak run.
    Soak(super::soak::SoakRun),
}

impl Hook {
    /// The hook state of `script`, before its first frame.
    pub(super) fn new(script: TestScript) -> Self {
        match script {
            TestScript::Smoke(out) => Hook::Smoke(TestRunner {
                out,
                step: SmokeStep::Warmup,
                frames: 0,
                q_before: 0.0,
                target: 0.0,
                first_frame_ms: None,
            }),
            TestScript::Sweep(seconds) => Hook::Sweep(SweepRun { seconds, ..Default::default() }),
            TestScript::Soak(seconds, program) => Hook::Soak(super::soak::SoakRun::new(seconds, program)),
        }
    }

    /// True for the scripts that measure or screenshot every frame (no frame reuse for them).
    pub(super) fn full_frames(&self) -> bool {
        matches!(self, Hook::Smoke(_) | Hook::Sweep(_))
    }
}

type Shot = Arc<Mutex<Option<Arc<egui::ColorImage>>>>;

#[derive(Debug)]
pub(super) enum SmokeStep {
    Warmup,
    ShotBefore(Shot),
    Move,
    Wait { target: f64, since: Instant },
    ShotAfter(Shot, Instant),
    Done,
}

pub(super) struct TestRunner {
    pub(super) out: PathBuf,
    pub(super) step: SmokeStep,
    pub(super) frames: u64,
    pub(super) q_before: f64,
    pub(super) target: f64,
    pub(super) first_frame_ms: Option<f64>,
}

/// Window frame statistics collected by the `sweep:SECONDS` test script.
#[derive(Debug, Default)]
pub(super) struct SweepRun {
    pub(super) seconds: f64,
    pub(super) frames: u64,
    pub(super) started: Option<Instant>,
    pub(super) last: Option<Instant>,
    pub(super) first_frame_ms: Option<f64>,
    pub(super) frame_ms: Vec<f64>,
    pub(super) ui_ms: Vec<f64>,
    pub(super) moving_frames: usize,
}

fn pct(sorted: &[f64], q: f64) -> f64 {
    parol6_core::stats::percentile(sorted, q).unwrap_or(0.0)
}

impl Parol6App {
    pub(super) fn test_step(
        t: &mut TestRunner,
        ctx: &egui::Context,
        joints: &mut JointsPanel,
        pctx: &mut PanelContext<'_>,
        exit_code: &Arc<AtomicI32>,
        started: Instant,
    ) {
        const TIMEOUT: Duration = Duration::from_secs(20);
        let fail = |msg: String| {
            eprintln!("smoke test failed: {msg}");
            exit_code.store(1, Ordering::SeqCst);
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        };
        if t.first_frame_ms.is_none() {
            t.first_frame_ms = Some(started.elapsed().as_secs_f64() * 1000.0);
        }
        let request = |ctx: &egui::Context| -> Shot {
            let shot: Shot = Arc::new(Mutex::new(None));
            let s2 = Arc::clone(&shot);
            ctx.request_screenshot(move |img| {
                if let Ok(mut g) = s2.lock() {
                    *g = Some(img);
                }
            });
            shot
        };
        let take = |shot: &Shot| shot.lock().ok().and_then(|mut g| g.take());
        match &mut t.step {
            SmokeStep::Warmup => {
                if t.frames >= 5 && !pctx.robot.moving {
                    t.step = SmokeStep::ShotBefore(request(ctx));
                }
            }
            SmokeStep::ShotBefore(shot) => {
                if let Some(img) = take(shot) {
                    let before = t.out.with_extension("before.png");
                    if let Err(e) = crate::artifacts::write_color_image(&before, &img) {
                        return fail(format!("{e:#}"));
                    }
                    t.step = SmokeStep::Move;
                }
            }
            SmokeStep::Move => {
                // Joint 1 by +30° (or −30° if that would leave the range), through the slider path.
                let q0 = pctx.robot.q.first().copied().unwrap_or(0.0);
                let delta = 30f64.to_radians();
                let target = match pctx.model.limits.get(0) {
                    Some(l) if l.is_bounded() && q0 + delta > l.max => q0 - delta,
                    _ => q0 + delta,
                };
                t.q_before = q0;
                t.target = target;
                joints.set_joint(0, target, pctx);
                t.step = SmokeStep::Wait { target, since: Instant::now() };
            }
            SmokeStep::Wait { target, since } => {
                let q = pctx.robot.q.first().copied().unwrap_or(0.0);
                if (q - *target).abs() < 0.5f64.to_radians() && !pctx.robot.moving {
                    t.step = SmokeStep::ShotAfter(request(ctx), Instant::now());
                } else if since.elapsed() > TIMEOUT {
                    fail(format!("joint 1 did not reach {target:.4} rad (at {q:.4} rad)"));
                }
            }
            SmokeStep::ShotAfter(shot, since) => {
                if let Some(img) = take(shot) {
                    if let Err(e) = crate::artifacts::write_color_image(&t.out, &img) {
                        return fail(format!("{e:#}"));
                    }
                    let q = pctx.robot.q.first().copied().unwrap_or(0.0);
                    println!(
                        "{}",
                        serde_json::json!({
                            "smoke": "ok",
                            "joint": 1,
                            "q_before_rad": t.q_before,
                            "target_rad": t.target,
                            "q_after_rad": q,
                            "screenshot": t.out.display().to_string(),
                            "first_frame_ms": t.first_frame_ms,
                            "frames": t.frames,
                        })
                    );
                    t.step = SmokeStep::Done;
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                } else if since.elapsed() > TIMEOUT {
                    fail("no screenshot arrived".to_string());
                }
            }
            SmokeStep::Done => {}
        }
    }

    pub(super) fn sweep_step(&mut self, ctx: &egui::Context, now: Instant, moving: bool) {
        let Some(Hook::Sweep(sw)) = &mut self.hook else {
            return;
        };
        sw.frames += 1;
        if sw.first_frame_ms.is_none() {
            sw.first_frame_ms = Some(self.started.elapsed().as_secs_f64() * 1000.0);
        }
        if sw.frames == 5 {
            self.start_program("Joint sweep", true);
            return;
        }
        if sw.frames < 10 {
            return;
        }
        let started = *sw.started.get_or_insert(now);
        if let Some(last) = sw.last {
            sw.frame_ms.push(now.duration_since(last).as_secs_f64() * 1000.0);
            sw.ui_ms.push(self.perf.ui_cpu_ms);
            if moving {
                sw.moving_frames += 1;
            }
        }
        sw.last = Some(now);
        if now.duration_since(started).as_secs_f64() >= sw.seconds {
            let mut f = sw.frame_ms.clone();
            let mut u = sw.ui_ms.clone();
            f.sort_by(f64::total_cmp);
            u.sort_by(f64::total_cmp);
            let p50 = pct(&f, 0.5);
            println!(
                "{}",
                serde_json::json!({
                    "target": "window",
                    "seconds": now.duration_since(started).as_secs_f64(),
                    "frames": f.len(),
                    "moving_frames": sw.moving_frames,
                    "fps_median": if p50 > 0.0 { 1000.0 / p50 } else { 0.0 },
                    "frame_ms_p50": p50,
                    "frame_ms_p99": pct(&f, 0.99),
                    "ui_cpu_ms_p50": pct(&u, 0.5),
                    "ui_cpu_ms_p99": pct(&u, 0.99),
                    "first_frame_ms": sw.first_frame_ms,
                    "rss_mb_peak": crate::artifacts::peak_rss_mb(),
                })
            );
            self.hook = None;
            self.stop_program();
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }
}

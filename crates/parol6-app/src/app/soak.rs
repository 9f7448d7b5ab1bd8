//! The `soak:SECONDS[:PROGRAM]` test script (`PAROL6_TEST_SCRIPT`): runs a built-in program
//! (default "Pick & place") in a loop on the window's backend — the robot or the built-in
//! emulator with `--fake-robot`, else the simulation — for SECONDS, sampling the resident
//! memory (and what the allocator holds: in use, freed and kept, mapped on its own), the link
//! and the telemetry recorder every 10 s (one JSON line each on stdout), then
//! prints a summary line, stops the program and closes the window (which ends a `--record`
//! file). A program that stops (a link loss ends it) is counted and started again.
//!
//! Summary keys: `seconds`, `frames`, `rss_mb_first`, `rss_mb_min`, `rss_mb_max`,
//! `rss_mb_last`, `rss_spread_pct` (max − min over min, after the first 11 minutes: the live view's
//! ten-minute ring is full by then), `link_losses`,
//! `missing_replies`, `recorder_samples`, `missing_samples`, `control_dropped`,
//! `recorded_samples`, `program_starts`, `ok` (spread ≤ 10 %, no loss, nothing dropped).

use eframe::egui;
use serde_json::json;
use std::time::{Duration, Instant};

use super::Parol6App;
use crate::artifacts::rss_mb;

/// Bytes in a MB (as the resident size is counted).
const MB: f64 = 1024.0 * 1024.0;
/// How often the soak samples.
const SAMPLE_EVERY: Duration = Duration::from_secs(10);
/// Samples before this time are the warm-up and not in the spread: the live view keeps the
/// last ten minutes of telemetry (the plots' ring buffer), so memory grows until it is full.
const WARM_UP: Duration = Duration::from_secs(660);
/// Largest RSS spread after the warm-up, %.
pub const MAX_RSS_SPREAD_PCT: f64 = 10.0;
/// The program looped when none is named.
pub const DEFAULT_PROGRAM: &str = "Pick & place";

/// One sample of the soak.
#[derive(Debug, Clone, Copy)]
struct SoakSample {
    t_s: f64,
    rss_mb: f64,
}

/// The state of a `soak:` run.
#[derive(Debug)]
pub(super) struct SoakRun {
    seconds: f64,
    program: String,
    frames: u64,
    started: Option<Instant>,
    next_sample: Option<Instant>,
    samples: Vec<SoakSample>,
    program_starts: u64,
    link_losses_at_start: Option<u64>,
}

impl SoakRun {
    pub(super) fn new(seconds: f64, program: Option<String>) -> Self {
        Self {
            seconds,
            program: program.unwrap_or_else(|| DEFAULT_PROGRAM.to_string()),
            frames: 0,
            started: None,
            next_sample: None,
            samples: Vec::new(),
            program_starts: 0,
            link_losses_at_start: None,
        }
    }
}

impl Parol6App {
    /// The soak run, when that is the window's script.
    fn soak_mut(&mut self) -> Option<&mut SoakRun> {
        match &mut self.hook {
            Some(super::test_hooks::Hook::Soak(s)) => Some(s),
            _ => None,
        }
    }

    /// One frame of the soak script.
    pub(super) fn soak_step(&mut self, ctx: &egui::Context, now: Instant) {
        let Some(soak) = self.soak_mut() else { return };
        soak.frames += 1;
        if soak.frames < 10 {
            return;
        }
        let link = self.hw.as_ref().map(|l| l.session.snapshot());
        let soak = match self.soak_mut() {
            Some(s) => s,
            None => return,
        };
        let started = *soak.started.get_or_insert(now);
        if soak.link_losses_at_start.is_none() {
            soak.link_losses_at_start = Some(link.as_ref().map_or(0, |s| s.link_losses));
        }
        let link_ok = link.as_ref().is_none_or(|s| s.link == parol6_hw::LinkState::Connected);
        let name = soak.program.clone();
        let last_state = self.state.program.as_ref().map(|p| format!("{:?}", p.state));
        if !self.program_running() && link_ok {
            let Some(soak) = self.soak_mut() else { return };
            soak.program_starts += 1;
            if soak.program_starts > 1 {
                let t_s = now.duration_since(started).as_secs_f64();
                let line = json!({ "soak": "program ended; started again", "t_s": t_s, "ended": last_state });
                println!("{line}");
            }
            if !self.start_program(&name, true) {
                eprintln!("soak: no built-in program named \"{name}\"");
                self.exit_code.store(1, std::sync::atomic::Ordering::SeqCst);
                self.hook = None;
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                return;
            }
        }
        let stats = self.active_recorder().map(|r| r.stats());
        let Some(soak) = self.soak_mut() else { return };
        let t_s = now.duration_since(started).as_secs_f64();
        let due = soak.next_sample.is_none_or(|at| now >= at);
        let finished = t_s >= soak.seconds;
        if !due && !finished {
            return;
        }
        soak.next_sample = Some(now + SAMPLE_EVERY);
        let rss = rss_mb().unwrap_or(0.0);
        soak.samples.push(SoakSample { t_s, rss_mb: rss });
        let losses = link.as_ref().map_or(0, |s| s.link_losses).saturating_sub(soak.link_losses_at_start.unwrap_or(0));
        let recorder = stats.map(|s| {
            json!({
                "samples": s.samples,
                "missing_samples": s.missing_samples,
                "control_dropped": s.control_dropped,
                "recorded_samples": s.recorded_samples,
            })
        });
        let line = json!({
            "soak_t_s": t_s,
            "frames": soak.frames,
            "rss_mb": rss,
            "heap": parol6_core::process::heap_stats().map(|h| json!({
                "in_use_mb": h.in_use_bytes as f64 / MB,
                "free_mb": h.free_bytes as f64 / MB,
                "mapped_mb": h.mapped_bytes as f64 / MB,
            })),
            "link": link.as_ref().map(|s| format!("{:?}", s.link)),
            "link_losses": losses,
            "missing_replies": link.as_ref().map(|s| s.missing_replies),
            "recorder": recorder,
            "program_starts": soak.program_starts,
        });
        println!("{line}");
        if !finished {
            return;
        }
        let settled: Vec<f64> =
            soak.samples.iter().filter(|s| s.t_s >= WARM_UP.as_secs_f64()).map(|s| s.rss_mb).collect();
        let settled = if settled.is_empty() { vec![rss] } else { settled };
        let min = settled.iter().copied().fold(f64::INFINITY, f64::min);
        let max = settled.iter().copied().fold(0.0, f64::max);
        let spread_pct = if min > 0.0 { (max - min) / min * 100.0 } else { 0.0 };
        let (missing_samples, control_dropped) = stats.map_or((0, 0), |s| (s.missing_samples, s.control_dropped));
        let ok = spread_pct <= MAX_RSS_SPREAD_PCT && losses == 0 && missing_samples == 0 && control_dropped == 0;
        println!(
            "{}",
            json!({
                "soak": "done",
                "seconds": t_s,
                "frames": soak.frames,
                "rss_mb_first": settled.first(),
                "rss_mb_min": min,
                "rss_mb_max": max,
                "rss_mb_last": rss,
                "rss_spread_pct": spread_pct,
                "link_losses": losses,
                "missing_replies": link.as_ref().map(|s| s.missing_replies),
                "recorder_samples": stats.map(|s| s.samples),
                "missing_samples": missing_samples,
                "control_dropped": control_dropped,
                "recorded_samples": stats.map(|s| s.recorded_samples),
                "program_starts": soak.program_starts,
                "ok": ok,
            })
        );
        if !ok {
            self.exit_code.store(1, std::sync::atomic::Ordering::SeqCst);
        }
        self.hook = None;
        self.stop_program();
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }
}

//! The performance figures of the status bar: frames per second and the simulation's rate,
//! step time and command latency.

use std::time::{Duration, Instant};

use parol6_core::sim::SimSnapshot;

use super::Parol6App;

impl Parol6App {
    pub(super) fn update_perf(&mut self, now: Instant, snap: &SimSnapshot) {
        self.frame_starts.push_back(now);
        // the last second's frames, and at least the one before this (an idle window draws one
        // frame every IDLE_REPAINT)
        while self.frame_starts.len() > 2
            && self.frame_starts.front().is_some_and(|t| now.duration_since(*t) > Duration::from_secs(1))
        {
            self.frame_starts.pop_front();
        }
        let n = self.frame_starts.len();
        self.perf.fps = match (self.frame_starts.front(), n) {
            (Some(first), n) if n > 1 => (n - 1) as f64 / now.duration_since(*first).as_secs_f64().max(1e-6),
            _ => 0.0,
        };
        self.perf.physics_rate_hz = snap.step_rate_hz;
        self.perf.physics_step_us = snap.last_step_ns as f64 / 1000.0;
        self.perf.command_latency_ms = snap.last_command_latency_ns.map(|ns| ns as f64 / 1e6);
    }
}

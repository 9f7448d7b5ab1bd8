//! Watches the hypervisor's steal time (`/proc/stat`, per CPU) while a timing test runs.
//!
//! On a virtual machine the host can take a vCPU away for tens of milliseconds (seen here:
//! about 100 ms at a time, when both vCPUs are busy, like a host CPU quota). Every thread on
//! that vCPU freezes, real-time ones included, so an emulated board running there stops
//! answering. A timing test asks [`StealLog::stolen_near`] whether such a freeze happened
//! around an event before it counts the event against the code under test. On bare metal
//! (no steal) or without `/proc/stat` it reports nothing stolen, so nothing is excused.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How often `/proc/stat` is read.
const SAMPLE_EVERY: Duration = Duration::from_millis(5);
/// `/proc/stat` counts in USER_HZ ticks: 100 per second on Linux.
const TICK: Duration = Duration::from_millis(10);

/// Steal time of one CPU that grew between two readings.
#[derive(Debug, Clone, Copy)]
pub struct StealEvent {
    /// When the growth was seen (the vCPU has run again by then).
    pub seen_at: Instant,
    /// Which CPU.
    pub cpu: usize,
    /// How much was stolen since the previous reading.
    pub stolen: Duration,
}

/// A thread reading the per-CPU steal counters until dropped or [`StealWatch::finish`]ed.
#[derive(Debug)]
pub struct StealWatch {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<Vec<StealEvent>>>,
}

/// Per-CPU steal ticks of `/proc/stat` (the 8th number of each `cpuN` line).
fn read_steal_ticks() -> Option<Vec<u64>> {
    let text = std::fs::read_to_string("/proc/stat").ok()?;
    let mut ticks = Vec::new();
    for line in text.lines() {
        let mut fields = line.split_whitespace();
        let Some(name) = fields.next() else { continue };
        if name.len() > 3 && name.starts_with("cpu") {
            ticks.push(fields.nth(7)?.parse().ok()?);
        }
    }
    Some(ticks)
}

impl StealWatch {
    /// Starts watching.
    pub fn start() -> StealWatch {
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread = std::thread::Builder::new()
            .name("steal-watch".into())
            .spawn(move || {
                let mut events = Vec::new();
                let Some(mut last) = read_steal_ticks() else { return events };
                while !flag.load(Ordering::Relaxed) {
                    std::thread::sleep(SAMPLE_EVERY);
                    let Some(now) = read_steal_ticks() else { break };
                    let seen_at = Instant::now();
                    for (cpu, (&a, &b)) in last.iter().zip(&now).enumerate() {
                        if b > a {
                            let ticks = u32::try_from(b - a).unwrap_or(u32::MAX);
                            events.push(StealEvent { seen_at, cpu, stolen: TICK * ticks });
                        }
                    }
                    last = now;
                }
                events
            })
            .ok();
        StealWatch { stop, thread }
    }

    /// Stops watching and returns what was seen.
    pub fn finish(mut self) -> StealLog {
        self.stop.store(true, Ordering::Relaxed);
        let events = self.thread.take().and_then(|t| t.join().ok()).unwrap_or_default();
        StealLog { events }
    }
}

impl Drop for StealWatch {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// What a [`StealWatch`] saw.
#[derive(Debug, Clone, Default)]
pub struct StealLog {
    /// Every growth of a CPU's steal time, in time order.
    pub events: Vec<StealEvent>,
}

impl StealLog {
    /// The most time stolen from any one CPU among the growths seen in `[at − before, at + after]`.
    pub fn stolen_near(&self, at: Instant, before: Duration, after: Duration) -> Duration {
        let from = at.checked_sub(before).unwrap_or(at);
        let to = at + after;
        let mut per_cpu: Vec<Duration> = Vec::new();
        for e in self.events.iter().filter(|e| e.seen_at >= from && e.seen_at <= to) {
            if per_cpu.len() <= e.cpu {
                per_cpu.resize(e.cpu + 1, Duration::ZERO);
            }
            per_cpu[e.cpu] += e.stolen;
        }
        per_cpu.into_iter().max().unwrap_or(Duration::ZERO)
    }

    /// All the time stolen, summed over CPUs.
    pub fn total(&self) -> Duration {
        self.events.iter().map(|e| e.stolen).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stolen_time_is_summed_per_cpu_within_the_window() {
        let t0 = Instant::now();
        let ms = Duration::from_millis;
        let log = StealLog {
            events: vec![
                StealEvent { seen_at: t0, cpu: 0, stolen: ms(30) },
                StealEvent { seen_at: t0 + ms(20), cpu: 0, stolen: ms(70) },
                StealEvent { seen_at: t0 + ms(20), cpu: 1, stolen: ms(40) },
                StealEvent { seen_at: t0 + ms(900), cpu: 1, stolen: ms(500) },
            ],
        };
        assert_eq!(log.stolen_near(t0 + ms(10), ms(50), ms(50)), ms(100));
        assert_eq!(log.stolen_near(t0 + ms(500), ms(50), ms(50)), Duration::ZERO);
        assert_eq!(log.total(), ms(640));
    }
}

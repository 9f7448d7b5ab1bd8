//! The adversarial run's checks over what the fault peer recorded: every command frame the host
//! wrote (limits, codes, speed, joints nobody commanded) and every stall of the status stream
//! (reported as link loss, in time).

use std::time::{Duration, Instant};

use parol6_core::parol6::JOINT_COUNT;
use parol6_hw::frame::CommandCode;
use parol6_hw::session::LinkState;
use parol6_hw::units::{limits_steps, max_speed_steps_s};
use parol6_tests::fault_peer::{RecordedCommand, StallRecord};
use parol6_tests::steal_watch::StealLog;

use super::driver::{DriverLog, Phase};

/// A frame is attributed to every driver phase active within this time before it was written.
const PHASE_SLACK: Duration = Duration::from_millis(30);
/// How far back the motion clock's lag behind the wall clock is measured.
const LAG_LOOKBACK: Duration = Duration::from_millis(600);
/// Link loss must be reported within this time of the last valid status.
const LINK_REPORT_MAX: Duration = Duration::from_millis(100);
/// Stalls at least this much longer than the status timeout must be reported as link loss.
const STALL_MARGIN: Duration = Duration::from_millis(20);
/// How often the link monitor polls the sessions' snapshots, with room for a late poll.
const MONITOR_POLL: Duration = Duration::from_millis(5);
/// Examples kept per kind of violation.
const EXAMPLES: usize = 5;
/// A late or missing link-loss report is the host's when the hypervisor took this much of a
/// vCPU away meanwhile (steal time): the session thread was frozen.
const STEAL_EXCUSES: Duration = Duration::from_millis(40);

/// A change of a session's link state as the monitor saw it.
#[derive(Debug, Clone)]
pub struct LinkEvent {
    pub published_at: Instant,
    pub link: LinkState,
    pub last_status_at: Option<Instant>,
    pub fault: Option<String>,
}

/// Violations of one kind: how many, the worst (by excess) and a few examples.
#[derive(Debug, Default)]
pub struct Violations {
    pub count: u64,
    pub worst: f64,
    pub examples: Vec<String>,
}

impl Violations {
    pub fn add(&mut self, excess: f64, what: impl FnOnce() -> String) {
        self.count += 1;
        if excess > self.worst {
            self.worst = excess;
        }
        if self.examples.len() < EXAMPLES {
            self.examples.push(what());
        }
    }

    pub fn summary(&self, name: &str) -> String {
        format!("{name}: {} (worst excess {:.0}); e.g. {:?}", self.count, self.worst, self.examples)
    }
}

#[derive(Debug, Default)]
pub struct LaneReport {
    pub frames: u64,
    pub move_frames: u64,
    pub write_times_aligned: bool,
    pub limits: Violations,
    pub codes: Violations,
    pub rate: Violations,
    pub uncommanded: Violations,
    pub stalls_checked: u64,
    pub stalls_skipped: u64,
    /// Long stalls outside the monitor's watch (before it started or too close to its end).
    pub stalls_unwatched: u64,
    pub link_missed: Violations,
    pub link_late: Violations,
    pub link_latency_max_ms: f64,
    pub link_excused: u64,
    pub lost_events: u64,
    pub lost_unexplained: Violations,
}

/// Union of the joint masks of the phases active at any time in `[t − PHASE_SLACK − lag, t]`:
/// `lag` is how far the session's motion clock (which counts frames) fell behind the wall
/// clock just before `t` (a stalled host): a dead-man or a stop acts on the motion clock.
pub fn commanded_joints(phases: &[Phase], t: Instant, lag: Duration) -> u8 {
    let early = t.checked_sub(PHASE_SLACK + lag).unwrap_or(t);
    let lo = phases.partition_point(|p| p.from <= early);
    let hi = phases.partition_point(|p| p.from <= t);
    phases[lo.saturating_sub(1)..hi].iter().fold(0, |m, p| m | p.joints)
}

/// Write time of each frame when the session's write log lines up with the recorded frames.
pub fn frame_times(frames: &[RecordedCommand], log: &DriverLog) -> (Vec<Instant>, bool) {
    let arrivals: Vec<Instant> = frames.iter().map(|f| f.at).collect();
    let Some(drained) = log.last_drain else { return (arrivals, false) };
    let n = log.write_times.len();
    let arrived_before = frames.partition_point(|f| f.at <= drained);
    let aligned = n <= frames.len() && arrived_before.abs_diff(n) <= 1 && n > 0;
    if !aligned {
        return (arrivals, false);
    }
    let mut times = log.write_times.clone();
    times.extend_from_slice(&arrivals[n..]);
    (times, true)
}

/// How far the frames written in the [`LAG_LOOKBACK`] before frame `k` fell behind one per
/// period (wall time − frames × period, at least zero).
pub fn motion_clock_lag(times: &[Instant], k: usize, period: Duration) -> Duration {
    let from = times[k].checked_sub(LAG_LOOKBACK).unwrap_or(times[k]);
    let j = times[..k].partition_point(|t| *t < from);
    let wall = times[k].saturating_duration_since(times[j]);
    wall.saturating_sub(period * u32::try_from(k - j).unwrap_or(u32::MAX))
}

/// Checks every recorded command frame. With a lying board (`honest` false) the controller's
/// true position is not what the host saw, so a MOVE after a non-MOVE frame is compared with
/// nothing (the step limits still hold for it).
pub fn check_frames(frames: &[RecordedCommand], log: &DriverLog, period: Duration, honest: bool, r: &mut LaneReport) {
    let lim = limits_steps();
    let vmax = max_speed_steps_s();
    let (times, aligned) = frame_times(frames, log);
    r.write_times_aligned = aligned;
    r.frames = frames.len() as u64;
    for (k, f) in frames.iter().enumerate() {
        let c = &f.command;
        let p = c.fields.positions_steps;
        for i in 0..JOINT_COUNT {
            let (lo, hi) = lim[i];
            if !(lo..=hi).contains(&p[i]) {
                let excess = f64::from((lo - p[i]).max(p[i] - hi));
                r.limits
                    .add(excess, || format!("frame {k} code {} J{} target {} outside {lo}..{hi}", c.code, i + 1, p[i]));
            }
        }
        let bad_code = c.code == 69 || c.code == CommandCode::Jog.byte() || c.command().is_none();
        let speeds = c.fields.speeds_steps_s;
        if bad_code || speeds.iter().any(|&v| v != 0) {
            r.codes.add(1.0, || format!("frame {k} code {} speeds {speeds:?}", c.code));
        }
        if c.code != CommandCode::Move.byte() {
            continue;
        }
        r.move_frames += 1;
        let previous = k.checked_sub(1).map(|j| &frames[j]);
        let (reference, dt, against) = match previous {
            Some(prev) if prev.command.code == CommandCode::Move.byte() => {
                let dt = times[k].saturating_duration_since(times[k - 1]).max(period);
                (prev.command.fields.positions_steps, dt, "previous target")
            }
            _ if !honest => continue,
            _ => match f.true_steps {
                Some(truth) => (truth, period, "measured position after a non-MOVE frame"),
                None => continue,
            },
        };
        let lag = motion_clock_lag(&times, k, period);
        let mask = commanded_joints(&log.phases, times[k], lag);
        for i in 0..JOINT_COUNT {
            let delta = (p[i] - reference[i]).abs();
            let allowed = f64::from(vmax[i]) * dt.as_secs_f64() + 1.0;
            if f64::from(delta) > allowed {
                r.rate.add(f64::from(delta) - allowed, || {
                    format!(
                        "frame {k} J{} target {} vs {against} {}: {delta} steps in {:.1} ms > {allowed:.0}",
                        i + 1,
                        p[i],
                        reference[i],
                        dt.as_secs_f64() * 1e3
                    )
                });
            }
            if mask & (1 << i) == 0 && delta != 0 {
                r.uncommanded.add(f64::from(delta), || {
                    let recent: Vec<String> = log.phases[..log.phases.partition_point(|p| p.from <= times[k])]
                        .iter()
                        .rev()
                        .take(3)
                        .map(|p| format!("{:#08b} {:.0} ms before", p.joints, (times[k] - p.from).as_secs_f64() * 1e3))
                        .collect();
                    format!(
                        "frame {k} J{} not commanded (joints {mask:#08b}) target {} vs {against} {}; motion clock \
                         {:.1} ms behind; last phases {recent:?}",
                        i + 1,
                        p[i],
                        reference[i],
                        lag.as_secs_f64() * 1e3
                    )
                });
            }
        }
    }
}

pub fn check_link(
    stalls: &[StallRecord],
    events: &[LinkEvent],
    watched: std::ops::Range<Instant>,
    timeout: Duration,
    steal: &StealLog,
    r: &mut LaneReport,
) {
    for st in stalls {
        let duration = st.ended.saturating_duration_since(st.started);
        if duration < timeout + STALL_MARGIN {
            continue;
        }
        // The monitor saw link changes only within `watched`: a stall whose report could come
        // after it stopped (the peer stalls on while the drivers wind down) is not checked.
        if st.started < watched.start || st.ended + STALL_MARGIN + MONITOR_POLL > watched.end {
            r.stalls_unwatched += 1;
            continue;
        }
        let before = events.iter().rev().find(|e| e.published_at <= st.started);
        if before.is_some_and(|e| e.link != LinkState::Connected) {
            r.stalls_skipped += 1;
            continue;
        }
        r.stalls_checked += 1;
        let window_end = st.ended + STALL_MARGIN;
        let lost = events
            .iter()
            .find(|e| e.link == LinkState::Lost && e.published_at > st.started && e.published_at <= window_end);
        let Some(e) = lost else {
            let stolen = steal.stolen_near(st.ended, duration + STALL_MARGIN, STALL_MARGIN);
            if stolen >= STEAL_EXCUSES {
                r.link_excused += 1;
                continue;
            }
            let nearby: Vec<String> = events
                .iter()
                .filter(|e| e.published_at + Duration::from_millis(300) >= st.started && e.published_at <= window_end)
                .map(|e| {
                    let at_ms = if e.published_at >= st.started {
                        e.published_at.duration_since(st.started).as_secs_f64() * 1e3
                    } else {
                        -(st.started.duration_since(e.published_at).as_secs_f64() * 1e3)
                    };
                    format!("{:?} at {at_ms:.0} ms", e.link)
                })
                .collect();
            r.link_missed.add(duration.as_secs_f64() * 1e3, || {
                format!(
                    "stall of {:.0} ms ({} frames, delivered late {}) never reported; link changes from 300 ms \
                     before: {nearby:?}; steal {stolen:?}",
                    duration.as_secs_f64() * 1e3,
                    st.frames,
                    st.delivered_late
                )
            });
            continue;
        };
        let last_valid = match (e.last_status_at, st.last_forward_before) {
            (Some(a), Some(b)) => a.min(b),
            (a, b) => a.or(b).unwrap_or(st.started),
        };
        let latency = e.published_at.saturating_duration_since(last_valid);
        let ms = latency.as_secs_f64() * 1e3;
        r.link_latency_max_ms = r.link_latency_max_ms.max(ms);
        if latency > LINK_REPORT_MAX && steal.stolen_near(e.published_at, latency, STALL_MARGIN) >= STEAL_EXCUSES {
            r.link_excused += 1;
        } else if latency > LINK_REPORT_MAX {
            r.link_late.add(ms, || {
                format!(
                    "stall of {:.0} ms reported {ms:.1} ms after the last valid status",
                    duration.as_secs_f64() * 1e3
                )
            });
        }
    }
    for e in events.iter().filter(|e| e.link == LinkState::Lost) {
        r.lost_events += 1;
        let explained = stalls.iter().any(|st| {
            e.published_at + Duration::from_millis(10) >= st.started
                && e.published_at <= st.ended + Duration::from_millis(60)
        });
        if !explained {
            r.lost_unexplained.add(0.0, || format!("{:?}", e.fault));
        }
    }
}

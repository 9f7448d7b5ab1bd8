//! [`TimeWarp`]: pause and resume a planned trajectory *on its path*. Pausing ramps the
//! path's time rate from 1 to 0, resuming from 0 to 1, each linearly over `ramp_s`; the joints
//! never leave the planned path (a paused MoveL stops on its line) and the motion stays a pure
//! function of the command times, so a pause means the same on every backend.

/// Time along a trajectory as a function of the motion clock, with pauses and resumes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum TimeWarp {
    /// Path time = clock − start.
    Normal,
    /// Slowing to a stop (stopped once the ramp has ended): from clock `t_s` at path time
    /// `tau_s`, over `ramp_s` (also the ramp of the resume).
    Pausing { t_s: f64, tau_s: f64, ramp_s: f64 },
    /// Speeding up again: from clock `t_s` at path time `tau_s`, over `ramp_s`.
    Resuming { t_s: f64, tau_s: f64, ramp_s: f64 },
}

/// The shortest pause / resume ramp, s.
pub(super) const MIN_RAMP_S: f64 = 0.05;
/// The longest pause / resume ramp, s.
pub(super) const MAX_RAMP_S: f64 = 2.0;

impl TimeWarp {
    /// Path time and its rate (d path time / d clock) and the rate's derivative at clock `t`
    /// for a trajectory started at `t0`.
    pub(super) fn at(&self, t0: f64, t: f64) -> (f64, f64, f64) {
        match *self {
            TimeWarp::Normal => ((t - t0).max(0.0), 1.0, 0.0),
            TimeWarp::Pausing { t_s, tau_s, ramp_s } => {
                let dt = (t - t_s).max(0.0);
                if dt < ramp_s {
                    (tau_s + dt - dt * dt / (2.0 * ramp_s), 1.0 - dt / ramp_s, -1.0 / ramp_s)
                } else {
                    (tau_s + ramp_s / 2.0, 0.0, 0.0)
                }
            }
            TimeWarp::Resuming { t_s, tau_s, ramp_s } => {
                let dt = (t - t_s).max(0.0);
                if dt < ramp_s {
                    (tau_s + dt * dt / (2.0 * ramp_s), dt / ramp_s, 1.0 / ramp_s)
                } else {
                    (tau_s + ramp_s / 2.0 + (dt - ramp_s), 1.0, 0.0)
                }
            }
        }
    }

    /// True once the path has stopped (a pause whose ramp has ended).
    pub(super) fn is_stopped(&self, t: f64) -> bool {
        match *self {
            TimeWarp::Pausing { t_s, ramp_s, .. } => t - t_s >= ramp_s,
            _ => false,
        }
    }

    /// True while paused or pausing.
    pub(super) fn is_pausing(&self) -> bool {
        matches!(self, TimeWarp::Pausing { .. })
    }

    /// The clock time at which path time reaches `duration_s`, if it does.
    pub(super) fn end_clock(&self, t0: f64, duration_s: f64) -> Option<f64> {
        match *self {
            TimeWarp::Normal => Some(t0 + duration_s),
            TimeWarp::Pausing { t_s, tau_s, ramp_s } => {
                // tau(dt) = tau_s + dt − dt²/2R reaches duration before the ramp ends?
                let need = duration_s - tau_s;
                if need <= 0.0 {
                    return Some(t_s);
                }
                if need > ramp_s / 2.0 {
                    return None;
                }
                let disc = (1.0 - 2.0 * need / ramp_s).max(0.0);
                Some(t_s + ramp_s * (1.0 - disc.sqrt()))
            }
            TimeWarp::Resuming { t_s, tau_s, ramp_s } => {
                let need = duration_s - tau_s;
                if need <= ramp_s / 2.0 {
                    Some(t_s + (2.0 * ramp_s * need.max(0.0)).sqrt())
                } else {
                    Some(t_s + ramp_s + (need - ramp_s / 2.0))
                }
            }
        }
    }
}

/// A ramp long enough that slowing the path speed `qd` (per joint, rad/s) to zero takes at
/// most half of each joint's acceleration cap (the path's own acceleration keeps the rest).
pub(super) fn ramp_for(qd: &[f64], accel_cap: &[f64]) -> f64 {
    let need = qd.iter().zip(accel_cap).map(|(v, a)| 2.0 * v.abs() / a).fold(0.0, f64::max);
    need.clamp(MIN_RAMP_S, MAX_RAMP_S)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pause_slows_to_a_stop_and_a_resume_picks_up_where_it_stopped() {
        let p = TimeWarp::Pausing { t_s: 1.0, tau_s: 0.5, ramp_s: 0.4 };
        let (tau, rate, _) = p.at(0.5, 1.0);
        assert!((tau - 0.5).abs() < 1e-12 && (rate - 1.0).abs() < 1e-12);
        let (tau, rate, _) = p.at(0.5, 1.5);
        assert!((tau - 0.7).abs() < 1e-12 && rate == 0.0);
        assert!(p.is_stopped(1.41) && !p.is_stopped(1.3));
        // continuity of path time and rate across the ramp ends
        let (a, ra, _) = p.at(0.5, 1.4 - 1e-9);
        assert!((a - 0.7).abs() < 1e-8 && ra < 1e-8);
        let r = TimeWarp::Resuming { t_s: 3.0, tau_s: 0.7, ramp_s: 0.4 };
        let (tau, rate, _) = r.at(0.5, 3.0);
        assert!((tau - 0.7).abs() < 1e-12 && rate == 0.0);
        let (tau, rate, _) = r.at(0.5, 3.6);
        assert!((tau - (0.7 + 0.2 + 0.2)).abs() < 1e-12 && rate == 1.0);
    }

    #[test]
    fn the_end_clock_is_where_path_time_reaches_the_duration() {
        for w in [
            TimeWarp::Normal,
            TimeWarp::Pausing { t_s: 1.0, tau_s: 0.9, ramp_s: 0.4 },
            TimeWarp::Resuming { t_s: 3.0, tau_s: 0.7, ramp_s: 0.4 },
            TimeWarp::Resuming { t_s: 3.0, tau_s: 0.95, ramp_s: 0.4 },
        ] {
            let end = w.end_clock(0.0, 1.0).expect("reaches the end");
            let (tau, _, _) = w.at(0.0, end);
            assert!((tau - 1.0).abs() < 1e-9, "{w:?}: tau {tau} at {end}");
        }
        assert_eq!(TimeWarp::Pausing { t_s: 1.0, tau_s: 0.5, ramp_s: 0.4 }.end_clock(0.0, 1.0), None);
    }

    #[test]
    fn the_ramp_keeps_half_the_acceleration_budget() {
        assert!((ramp_for(&[1.0, 0.0], &[4.0, 1.0]) - 0.5).abs() < 1e-12);
        assert_eq!(ramp_for(&[0.0], &[1.0]), MIN_RAMP_S);
        assert_eq!(ramp_for(&[100.0], &[1.0]), MAX_RAMP_S);
    }
}

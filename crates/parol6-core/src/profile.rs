//! Joint-space point-to-point motion profiles, shared by the simulation and the serial session.
//!
//! Two kinds ([`ProfileKind`]):
//! - **Trapezoidal**: per joint the time-optimal trapezoid (or triangle) under its speed and
//!   acceleration caps; the slowest joint sets the duration and every other joint is slowed to
//!   a trapezoid of exactly that duration (same acceleration, lower cruise speed).
//! - **Jerk-limited**: a quintic (minimum-jerk) polynomial `10s³ − 15s⁴ + 6s⁵` with zero speed
//!   and acceleration at both ends; its duration is the shortest one that keeps every joint
//!   under its speed, acceleration and jerk caps.
//!
//! All joints start and finish together. Speed, acceleration and jerk caps are all scaled by
//! the speed fraction (0 < f ≤ 1; values above 1 are clamped to 1).

use serde::{Deserialize, Serialize};

/// Peak of `|d/ds (10s³ − 15s⁴ + 6s⁵)|` (at s = ½).
const QUINTIC_PEAK_VEL: f64 = 1.875;
/// Peak of `|d²/ds² (10s³ − 15s⁴ + 6s⁵)|` = 10/√3 (at s = (3 ∓ √3)/6).
const QUINTIC_PEAK_ACC: f64 = 5.773_502_691_896_258;
/// Peak of `|d³/ds³ (10s³ − 15s⁴ + 6s⁵)|` (at s = 0 and 1).
const QUINTIC_PEAK_JERK: f64 = 60.0;
/// Jerk cap as a multiple of the acceleration cap when none is given (ROBOT.md §5: 10 × acc).
const DEFAULT_JERK_PER_ACC: f64 = 10.0;

/// Which profile shape to plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum ProfileKind {
    /// Time-optimal trapezoidal velocity profile (bounded speed and acceleration).
    #[default]
    Trapezoidal,
    /// Quintic minimum-jerk profile (bounded speed, acceleration and jerk).
    JerkLimited,
}

/// Why a move could not be planned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// The speed fraction is NaN, zero or negative.
    #[error("speed fraction must be a number > 0 (got {0})")]
    BadSpeedFraction(f64),
    /// The per-joint slices have different lengths.
    #[error("start has {start} joints, goal {goal}, max_vel {max_vel}, max_acc {max_acc}: all must match")]
    LengthMismatch {
        /// Joints in `start`.
        start: usize,
        /// Joints in `goal`.
        goal: usize,
        /// Entries in `max_vel`.
        max_vel: usize,
        /// Entries in `max_acc`.
        max_acc: usize,
    },
    /// A start or goal value is NaN or infinite.
    #[error("joint {joint_index} start/goal is not finite")]
    NotFinite {
        /// 1-based joint number.
        joint_index: usize,
    },
    /// A speed, acceleration or jerk cap is not a finite number > 0.
    #[error("joint {joint_index} has an invalid {what} cap {value}")]
    BadLimit {
        /// 1-based joint number.
        joint_index: usize,
        /// "velocity", "acceleration" or "jerk".
        what: &'static str,
        /// The value.
        value: f64,
    },
}

/// Position, velocity and acceleration of every joint at one instant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointSample {
    /// Joint positions, rad.
    pub q: Vec<f64>,
    /// Joint velocities, rad/s.
    pub qd: Vec<f64>,
    /// Joint accelerations, rad/s².
    pub qdd: Vec<f64>,
}

/// One joint's trapezoid: signed direction, accel-phase length and cruise speed.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Trapezoid {
    dir: f64,
    distance: f64,
    cruise_vel: f64,
    accel: f64,
}

impl Trapezoid {
    /// (displacement from start, velocity, acceleration) at `t` of a move lasting `total_s`.
    fn eval(&self, t: f64, total_s: f64) -> (f64, f64, f64) {
        if self.distance <= 0.0 || self.cruise_vel <= 0.0 || self.accel <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let ta = self.cruise_vel / self.accel;
        let (p, v, a) = if t <= 0.0 {
            (0.0, 0.0, 0.0)
        } else if t >= total_s {
            (self.distance, 0.0, 0.0)
        } else if t < ta {
            (0.5 * self.accel * t * t, self.accel * t, self.accel)
        } else if t <= total_s - ta {
            (0.5 * self.accel * ta * ta + self.cruise_vel * (t - ta), self.cruise_vel, 0.0)
        } else {
            let r = total_s - t;
            (self.distance - 0.5 * self.accel * r * r, self.accel * r, -self.accel)
        };
        (self.dir * p.min(self.distance), self.dir * v, self.dir * a)
    }
}

/// A planned point-to-point joint move. Sample it with [`JointMove::sample`].
#[derive(Debug, Clone, PartialEq)]
pub struct JointMove {
    kind: ProfileKind,
    start: Vec<f64>,
    goal: Vec<f64>,
    duration_s: f64,
    trapezoids: Vec<Trapezoid>,
}

/// Shortest time for `distance` under (`v`, `a`) with a trapezoid.
fn trapezoid_min_time(distance: f64, v: f64, a: f64) -> f64 {
    if distance <= 0.0 {
        0.0
    } else if distance >= v * v / a {
        distance / v + v / a
    } else {
        2.0 * (distance / a).sqrt()
    }
}

/// Cruise speed of a trapezoid with acceleration `a` covering `distance` in exactly `total_s`
/// (`total_s` at least the minimum time). Numerically stable root of `v²/a − vT + d = 0`.
fn trapezoid_cruise_for_time(distance: f64, a: f64, total_s: f64) -> f64 {
    if distance <= 0.0 || total_s <= 0.0 {
        return 0.0;
    }
    let disc = (total_s * total_s - 4.0 * distance / a).max(0.0);
    2.0 * distance / (total_s + disc.sqrt())
}

fn check_limit(values: &[f64], what: &'static str) -> Result<(), ProfileError> {
    for (i, &v) in values.iter().enumerate() {
        if !(v.is_finite() && v > 0.0) {
            return Err(ProfileError::BadLimit { joint_index: i + 1, what, value: v });
        }
    }
    Ok(())
}

impl JointMove {
    /// Plans a synchronised move from `start` to `goal` (rad) under per-joint caps `max_vel`
    /// (rad/s) and `max_acc` (rad/s²), scaled by `speed_fraction`. For
    /// [`ProfileKind::JerkLimited`] the jerk cap is 10 × `max_acc` (ROBOT.md §5); use
    /// [`JointMove::plan_with_jerk`] to give one.
    pub fn plan(
        start: &[f64],
        goal: &[f64],
        max_vel: &[f64],
        max_acc: &[f64],
        speed_fraction: f64,
        kind: ProfileKind,
    ) -> Result<JointMove, ProfileError> {
        let max_jerk: Vec<f64> = max_acc.iter().map(|a| a * DEFAULT_JERK_PER_ACC).collect();
        Self::plan_with_jerk(start, goal, max_vel, max_acc, &max_jerk, speed_fraction, kind)
    }

    /// Like [`JointMove::plan`] with an explicit per-joint jerk cap (rad/s³), used only by
    /// [`ProfileKind::JerkLimited`].
    pub fn plan_with_jerk(
        start: &[f64],
        goal: &[f64],
        max_vel: &[f64],
        max_acc: &[f64],
        max_jerk: &[f64],
        speed_fraction: f64,
        kind: ProfileKind,
    ) -> Result<JointMove, ProfileError> {
        if speed_fraction.is_nan() || speed_fraction <= 0.0 {
            return Err(ProfileError::BadSpeedFraction(speed_fraction));
        }
        let f = speed_fraction.min(1.0);
        let n = start.len();
        if goal.len() != n || max_vel.len() != n || max_acc.len() != n || max_jerk.len() != n {
            return Err(ProfileError::LengthMismatch {
                start: n,
                goal: goal.len(),
                max_vel: max_vel.len(),
                max_acc: max_acc.len(),
            });
        }
        for i in 0..n {
            if !(start[i].is_finite() && goal[i].is_finite()) {
                return Err(ProfileError::NotFinite { joint_index: i + 1 });
            }
        }
        check_limit(max_vel, "velocity")?;
        check_limit(max_acc, "acceleration")?;
        check_limit(max_jerk, "jerk")?;

        let distances: Vec<f64> = start.iter().zip(goal).map(|(s, g)| (g - s).abs()).collect();
        let vel: Vec<f64> = max_vel.iter().map(|v| v * f).collect();
        let acc: Vec<f64> = max_acc.iter().map(|a| a * f).collect();
        let jerk: Vec<f64> = max_jerk.iter().map(|j| j * f).collect();

        let (duration_s, trapezoids) = match kind {
            ProfileKind::Trapezoidal => {
                let duration_s = (0..n).map(|i| trapezoid_min_time(distances[i], vel[i], acc[i])).fold(0.0, f64::max);
                let traps = (0..n)
                    .map(|i| Trapezoid {
                        dir: (goal[i] - start[i]).signum(),
                        distance: distances[i],
                        cruise_vel: trapezoid_cruise_for_time(distances[i], acc[i], duration_s).min(vel[i]),
                        accel: acc[i],
                    })
                    .collect();
                (duration_s, traps)
            }
            ProfileKind::JerkLimited => {
                let duration_s = (0..n)
                    .map(|i| {
                        let d = distances[i];
                        (QUINTIC_PEAK_VEL * d / vel[i])
                            .max((QUINTIC_PEAK_ACC * d / acc[i]).sqrt())
                            .max((QUINTIC_PEAK_JERK * d / jerk[i]).cbrt())
                    })
                    .fold(0.0, f64::max);
                (duration_s, Vec::new())
            }
        };
        Ok(JointMove { kind, start: start.to_vec(), goal: goal.to_vec(), duration_s, trapezoids })
    }

    /// Plans a PAROL6 move with the API caps of ROBOT.md §5
    /// ([`crate::parol6::max_speed_rad_s`], [`crate::parol6::max_accel_rad_s2`],
    /// [`crate::parol6::max_jerk_rad_s3`]).
    pub fn parol6(
        start: &[f64],
        goal: &[f64],
        speed_fraction: f64,
        kind: ProfileKind,
    ) -> Result<JointMove, ProfileError> {
        Self::plan_with_jerk(
            start,
            goal,
            &crate::parol6::max_speed_rad_s(),
            &crate::parol6::max_accel_rad_s2(),
            &crate::parol6::max_jerk_rad_s3(),
            speed_fraction,
            kind,
        )
    }

    /// Total duration, s (0 when start equals goal).
    pub fn duration_s(&self) -> f64 {
        self.duration_s
    }

    /// The profile kind.
    pub fn kind(&self) -> ProfileKind {
        self.kind
    }

    /// Start position, rad.
    pub fn start(&self) -> &[f64] {
        &self.start
    }

    /// Goal position, rad.
    pub fn goal(&self) -> &[f64] {
        &self.goal
    }

    /// Number of joints.
    pub fn joint_count(&self) -> usize {
        self.start.len()
    }

    /// True once `t_s` is at or past the end of the move.
    pub fn is_finished(&self, t_s: f64) -> bool {
        t_s >= self.duration_s
    }

    /// State at time `t_s` since the start (clamped to `[0, duration]`; NaN reads as 0).
    /// At and after the end it is exactly the goal with zero speed and acceleration.
    pub fn sample(&self, t_s: f64) -> JointSample {
        let n = self.start.len();
        let mut out = JointSample { q: vec![0.0; n], qd: vec![0.0; n], qdd: vec![0.0; n] };
        self.sample_into(t_s, &mut out.q, &mut out.qd, &mut out.qdd);
        out
    }

    /// Positions every `dt_s` from the start, the last one the goal: `ceil(duration / dt_s) + 1`
    /// samples (at least 2). The one place a joint move becomes the sampled path a program or
    /// the bench runs; check the count first where it may be huge ([`JointMove::sample_count`]).
    pub fn positions_every(&self, dt_s: f64) -> Vec<Vec<f64>> {
        let n = self.sample_count(dt_s) - 1;
        let joints = self.start.len();
        let (mut qd, mut qdd) = (vec![0.0; joints], vec![0.0; joints]);
        (0..=n)
            .map(|k| {
                let mut q = vec![0.0; joints];
                self.sample_into((k as f64 * dt_s).min(self.duration_s), &mut q, &mut qd, &mut qdd);
                q
            })
            .collect()
    }

    /// How many samples [`JointMove::positions_every`] gives for `dt_s` (saturating; at least 2).
    pub fn sample_count(&self, dt_s: f64) -> usize {
        ((self.duration_s / dt_s).ceil().max(1.0) as usize).saturating_add(1)
    }

    /// [`JointMove::sample`] into caller-owned slices (no allocation: the 1 kHz loops use it).
    /// Each slice must hold [`JointMove::joint_count`] values; extra entries are left alone.
    pub fn sample_into(&self, t_s: f64, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
        let n = self.start.len().min(q.len()).min(qd.len()).min(qdd.len());
        let t = if t_s.is_nan() { 0.0 } else { t_s.clamp(0.0, self.duration_s) };
        if t >= self.duration_s {
            q[..n].copy_from_slice(&self.goal[..n]);
            qd[..n].fill(0.0);
            qdd[..n].fill(0.0);
            return;
        }
        match self.kind {
            ProfileKind::Trapezoidal => {
                for (i, tr) in self.trapezoids.iter().enumerate().take(n) {
                    let (p, v, a) = tr.eval(t, self.duration_s);
                    q[i] = self.start[i] + p;
                    qd[i] = v;
                    qdd[i] = a;
                }
            }
            ProfileKind::JerkLimited => {
                let big_t = self.duration_s;
                let s = t / big_t;
                let s2 = s * s;
                let pos = s2 * s * (10.0 - 15.0 * s + 6.0 * s2);
                let vel = 30.0 * s2 * (1.0 - 2.0 * s + s2) / big_t;
                let acc = 60.0 * s * (1.0 - 3.0 * s + 2.0 * s2) / (big_t * big_t);
                for i in 0..n {
                    let d = self.goal[i] - self.start[i];
                    q[i] = self.start[i] + d * pos;
                    qd[i] = d * vel;
                    qdd[i] = d * acc;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const TOL: f64 = 1e-9;

    fn caps() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        (
            crate::parol6::max_speed_rad_s().to_vec(),
            crate::parol6::max_accel_rad_s2().to_vec(),
            crate::parol6::max_jerk_rad_s3().to_vec(),
        )
    }

    /// Checks bounds, endpoints, synchronisation and still joints for one move.
    fn check_move(m: &JointMove, start: &[f64], goal: &[f64], f: f64) {
        let (v, a, _) = caps();
        let f = f.min(1.0);
        let t_end = m.duration_s();
        let s0 = m.sample(0.0);
        let s1 = m.sample(t_end);
        for i in 0..start.len() {
            assert!((s0.q[i] - start[i]).abs() < 1e-9, "start joint {i}");
            assert!(s0.qd[i].abs() < 1e-9);
            assert_eq!(s1.q[i], goal[i], "end joint {i}");
            assert_eq!(s1.qd[i], 0.0);
        }
        let steps = 400;
        let dt = t_end / steps as f64;
        let mut prev = s0.clone();
        for k in 1..=steps {
            let t = k as f64 * dt;
            let s = m.sample(t);
            for i in 0..start.len() {
                let vtol = 1e-9 + 1e-9 * v[i];
                assert!(s.qd[i].abs() <= v[i] * f + vtol, "vel joint {i} at {t}: {} > {}", s.qd[i], v[i] * f);
                assert!(s.qdd[i].abs() <= a[i] * f * (1.0 + 1e-9) + TOL, "acc joint {i} at {t}");
                if start[i] == goal[i] {
                    assert_eq!(s.q[i], start[i], "still joint {i} moved");
                }
                // Position stays between start and goal (no overshoot).
                let (lo, hi) = if start[i] <= goal[i] { (start[i], goal[i]) } else { (goal[i], start[i]) };
                assert!(s.q[i] >= lo - 1e-9 && s.q[i] <= hi + 1e-9, "overshoot joint {i}");
                // Finite-difference speed agrees with the reported speed bound.
                if dt > 0.0 {
                    let fd = (s.q[i] - prev.q[i]) / dt;
                    assert!(fd.abs() <= v[i] * f * (1.0 + 1e-6) + 1e-6, "fd vel joint {i}");
                }
            }
            prev = s;
        }
        // Synchronised: every moving joint is still moving shortly before the end.
        if t_end > 1e-6 {
            let s = m.sample(t_end * 0.99);
            for i in 0..start.len() {
                if (goal[i] - start[i]).abs() > 1e-6 {
                    assert!(s.qd[i] * (goal[i] - start[i]) > 0.0, "joint {i} finished early");
                    assert!((s.q[i] - goal[i]).abs() > 0.0);
                }
            }
        }
    }

    #[test]
    fn trapezoid_single_joint_matches_closed_form() {
        let m = JointMove::plan(&[0.0], &[10.0], &[2.0], &[1.0], 1.0, ProfileKind::Trapezoidal).unwrap();
        // 2 s accel (2 m), 3 s cruise (6 m)... d = v²/a + v·tc → 10 = 4 + 2·tc → tc = 3, T = 7.
        assert!((m.duration_s() - 7.0).abs() < 1e-12);
        let s = m.sample(1.0);
        assert!((s.q[0] - 0.5).abs() < 1e-12 && (s.qd[0] - 1.0).abs() < 1e-12 && (s.qdd[0] - 1.0).abs() < 1e-12);
        let s = m.sample(3.5);
        assert!((s.qd[0] - 2.0).abs() < 1e-12 && s.qdd[0] == 0.0);
        let s = m.sample(6.0);
        assert!((s.q[0] - 9.5).abs() < 1e-12 && (s.qdd[0] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn triangle_when_distance_is_short() {
        let m = JointMove::plan(&[1.0], &[0.0], &[2.0], &[1.0], 1.0, ProfileKind::Trapezoidal).unwrap();
        assert!((m.duration_s() - 2.0).abs() < 1e-12);
        assert!((m.sample(1.0).qd[0] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn slower_joint_sets_duration_and_others_finish_together() {
        let (v, a, _) = caps();
        let start = crate::parol6::standby_rad().to_vec();
        let mut goal = start.clone();
        goal[0] += 1.5;
        goal[1] -= 0.2;
        goal[4] += 0.01;
        for kind in [ProfileKind::Trapezoidal, ProfileKind::JerkLimited] {
            let m = JointMove::plan(&start, &goal, &v, &a, 0.5, kind).unwrap();
            check_move(&m, &start, &goal, 0.5);
        }
    }

    #[test]
    fn speed_fraction_scales_duration() {
        let start = [0.0; 6];
        let goal = [1.0, 0.5, 0.3, 0.2, 0.1, 1.0];
        let fast = JointMove::parol6(&start, &goal, 1.0, ProfileKind::Trapezoidal).unwrap();
        let slow = JointMove::parol6(&start, &goal, 0.25, ProfileKind::Trapezoidal).unwrap();
        assert!(slow.duration_s() > 2.0 * fast.duration_s());
        let clamped = JointMove::parol6(&start, &goal, 5.0, ProfileKind::Trapezoidal).unwrap();
        assert_eq!(clamped.duration_s(), fast.duration_s());
    }

    #[test]
    fn rejects_bad_input() {
        let z = [0.0; 6];
        for f in [0.0, -0.5, f64::NAN] {
            assert!(matches!(
                JointMove::parol6(&z, &z, f, ProfileKind::Trapezoidal),
                Err(ProfileError::BadSpeedFraction(_))
            ));
        }
        assert!(matches!(
            JointMove::parol6(&z, &[0.0; 5], 1.0, ProfileKind::Trapezoidal),
            Err(ProfileError::LengthMismatch { .. })
        ));
        let mut g = z;
        g[2] = f64::INFINITY;
        assert!(matches!(
            JointMove::parol6(&z, &g, 1.0, ProfileKind::JerkLimited),
            Err(ProfileError::NotFinite { joint_index: 3 })
        ));
        assert!(matches!(
            JointMove::plan(&[0.0], &[1.0], &[0.0], &[1.0], 1.0, ProfileKind::Trapezoidal),
            Err(ProfileError::BadLimit { what: "velocity", .. })
        ));
    }

    #[test]
    fn zero_move_has_zero_duration() {
        let q = crate::parol6::standby_rad();
        let m = JointMove::parol6(&q, &q, 1.0, ProfileKind::JerkLimited).unwrap();
        assert_eq!(m.duration_s(), 0.0);
        assert_eq!(m.sample(0.0).q, q.to_vec());
        assert_eq!(m.sample(f64::NAN).q, q.to_vec());
    }

    #[test]
    fn positions_every_starts_at_start_ends_at_goal_and_matches_sample() {
        let (v, a, j) = caps();
        let start = [0.1, -0.2, 0.3, 0.0, 0.5, -0.6];
        let goal = [0.4, 0.1, -0.2, 0.3, 0.2, 0.0];
        let m = JointMove::plan_with_jerk(&start, &goal, &v, &a, &j, 0.5, ProfileKind::JerkLimited).unwrap();
        let dt = 0.01;
        let q = m.positions_every(dt);
        assert_eq!(q.len(), m.sample_count(dt));
        assert_eq!(q.len(), (m.duration_s() / dt).ceil() as usize + 1);
        assert_eq!(q[0], start.to_vec());
        assert_eq!(q[q.len() - 1], goal.to_vec());
        for k in [1, q.len() / 2, q.len() - 2] {
            assert_eq!(q[k], m.sample(k as f64 * dt).q, "sample {k}");
        }
        // a move of no length is two samples, and an absurd period saturates instead of overflowing
        let still = JointMove::plan_with_jerk(&start, &start, &v, &a, &j, 1.0, ProfileKind::JerkLimited).unwrap();
        assert_eq!(still.positions_every(dt).len(), 2);
        assert_eq!(m.sample_count(0.0), usize::MAX);
    }

    #[test]
    fn jerk_limited_respects_jerk_cap() {
        let (v, a, j) = caps();
        let start = [0.0; 6];
        let goal = [0.001, 0.0, 0.0, 0.0, 0.0, 0.0];
        let m = JointMove::plan_with_jerk(&start, &goal, &v, &a, &j, 1.0, ProfileKind::JerkLimited).unwrap();
        // A tiny move is jerk-bound: peak jerk 60·d/T³ equals the cap.
        let peak_jerk = QUINTIC_PEAK_JERK * 0.001 / m.duration_s().powi(3);
        assert!((peak_jerk - j[0]).abs() / j[0] < 1e-9);
        let dt = 1e-5;
        let a0 = m.sample(0.0).qdd[0];
        let a1 = m.sample(dt).qdd[0];
        assert!(((a1 - a0) / dt).abs() <= j[0] * (1.0 + 1e-3));
    }

    proptest! {
        #[test]
        fn random_moves_respect_bounds(
            start in proptest::collection::vec(-3.0f64..3.0, 6),
            delta in proptest::collection::vec(-3.0f64..3.0, 6),
            still in proptest::collection::vec(any::<bool>(), 6),
            f in 0.01f64..1.5,
            jerk in any::<bool>(),
        ) {
            let goal: Vec<f64> = (0..6).map(|i| if still[i] { start[i] } else { start[i] + delta[i] }).collect();
            let kind = if jerk { ProfileKind::JerkLimited } else { ProfileKind::Trapezoidal };
            let m = JointMove::parol6(&start, &goal, f, kind).unwrap();
            check_move(&m, &start, &goal, f);
        }
    }
}

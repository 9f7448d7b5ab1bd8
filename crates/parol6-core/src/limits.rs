//! Joint limits, limit zones (the LED system) and the enforcement policy.
//!
//! This is the single place where the thresholds **and colours** of the LED / limit system are
//! defined: [`ZoneThresholds::default`] (amber within 10 % of the range, red within 5 %; the old
//! HMI's 15 % lit J1 amber at standby, 33° from its limit) and [`LimitZone::rgba`]. The app, the
//! simulation and the serial session all call [`JointLimits::enforce`] before a target reaches a
//! motor. The swing bound of Cartesian motion near singular poses (how far a joint may turn per mm
//! of TCP travel) is [`swing`].

use serde::{Deserialize, Serialize};

pub mod swing;

/// Tolerance used when comparing a value against a limit (absorbs rounding of deg↔rad).
pub const LIMIT_EPSILON_RAD: f64 = 1e-9;

/// Plausibility bounds on numbers a user types or a file gives (command line, URDF). They are
/// not joint limits: a value beyond them is a mistake (a typo, `1e308`, an overflowed `1e400`),
/// refused as bad input before any computation, so nothing downstream prints `null` or a
/// 300-digit number. Values within them but outside the joint limits still compute, with the
/// usual limit warning.
pub mod plausible {
    /// Largest joint position magnitude, rad (ten turns; metres for a prismatic joint).
    pub const JOINT_POSITION_MAX_ABS_RAD: f64 = 20.0 * std::f64::consts::PI;
    /// Largest joint velocity magnitude, rad/s.
    pub const JOINT_VELOCITY_MAX_ABS_RAD_S: f64 = 1.0e3;
    /// Largest joint acceleration magnitude, rad/s².
    pub const JOINT_ACCELERATION_MAX_ABS_RAD_S2: f64 = 1.0e5;
    /// Largest Cartesian coordinate magnitude, m (a pose, a URDF origin or a shape size).
    pub const LENGTH_MAX_ABS_M: f64 = 1.0e3;
    /// Largest orientation angle magnitude, rad (ten turns).
    pub const ANGLE_MAX_ABS_RAD: f64 = 20.0 * std::f64::consts::PI;
    /// Largest link mass, kg, and largest inertia-tensor entry, kg·m².
    pub const MASS_MAX_KG: f64 = 1.0e5;

    /// `value` is finite and its magnitude at most `max_abs`.
    pub fn within(value: f64, max_abs: f64) -> bool {
        value.is_finite() && value.abs() <= max_abs
    }
}

/// One joint's position range (and speed / acceleration caps where known).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointLimit {
    /// Joint name (as in the URDF).
    pub name: String,
    /// Lower position limit, rad (or m for prismatic joints). `-inf` when unlimited.
    pub min: f64,
    /// Upper position limit, rad (or m). `+inf` when unlimited.
    pub max: f64,
    /// Max speed, rad/s (or m/s). `+inf` when unknown.
    pub max_velocity: f64,
}

impl JointLimit {
    /// Range width (`max − min`); infinite for an unlimited joint.
    pub fn range(&self) -> f64 {
        self.max - self.min
    }

    /// True when the joint has finite limits on both sides.
    pub fn is_bounded(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    /// True when `value` lies within the limits (with [`LIMIT_EPSILON_RAD`]).
    pub fn contains(&self, value: f64) -> bool {
        value.is_finite() && value >= self.min - LIMIT_EPSILON_RAD && value <= self.max + LIMIT_EPSILON_RAD
    }

    /// `value` clamped into the limits.
    pub fn clamp(&self, value: f64) -> f64 {
        value.clamp(self.min, self.max)
    }

    /// Distance to the nearest limit as a fraction of the range (0 at a limit, 0.5 mid-range).
    /// `None` for an unbounded joint.
    pub fn margin_fraction(&self, value: f64) -> Option<f64> {
        if !self.is_bounded() || self.range() <= 0.0 {
            return None;
        }
        let d = (value - self.min).min(self.max - value);
        Some((d / self.range()).max(0.0))
    }

    /// Seconds until the joint reaches the limit it is moving toward at `velocity`; `None`
    /// when standing still, moving away from the limits, or unbounded on that side.
    pub fn time_to_limit_s(&self, value: f64, velocity: f64) -> Option<f64> {
        if velocity > 1e-9 && self.max.is_finite() {
            Some(((self.max - value) / velocity).max(0.0))
        } else if velocity < -1e-9 && self.min.is_finite() {
            Some(((value - self.min) / -velocity).max(0.0))
        } else {
            None
        }
    }

    /// Seconds until the joint reaches the limit it is *nearest to* at `velocity`; `None`
    /// when standing still, moving away from that limit (toward the far one), or unbounded.
    /// This is the time to show next to a "near limit" warning: a joint near its lower limit
    /// that moves up is getting safer, whatever its time to the upper limit.
    pub fn time_to_nearest_limit_s(&self, value: f64, velocity: f64) -> Option<f64> {
        if !self.is_bounded() {
            return None;
        }
        let nearer_max = self.max - value < value - self.min;
        let toward_max = velocity > 1e-9;
        let toward_min = velocity < -1e-9;
        if (nearer_max && toward_max) || (!nearer_max && toward_min) {
            self.time_to_limit_s(value, velocity)
        } else {
            None
        }
    }
}

/// How close a joint is to one of its limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum LimitZone {
    /// Comfortably inside the range (green).
    Safe,
    /// Near a limit (amber).
    Warning,
    /// At or very near a limit (red).
    Critical,
}

impl LimitZone {
    /// The LED colour of this zone, sRGB with alpha. The one place zone colours are defined.
    pub const fn rgba(self) -> [u8; 4] {
        match self {
            LimitZone::Safe => [46, 204, 64, 255],
            LimitZone::Warning => [255, 176, 0, 255],
            LimitZone::Critical => [230, 40, 40, 255],
        }
    }

    /// Short label for UIs.
    pub const fn label(self) -> &'static str {
        match self {
            LimitZone::Safe => "safe",
            LimitZone::Warning => "near limit",
            LimitZone::Critical => "at limit",
        }
    }
}

/// Zone thresholds, as fractions of each joint's range, plus the prediction horizon.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ZoneThresholds {
    /// Amber when the distance to a limit is below this fraction of the range (default 0.10).
    pub warning_fraction: f64,
    /// Red when the distance to a limit is below this fraction of the range (default 0.05).
    pub critical_fraction: f64,
    /// A moving joint whose time to limit drops below this is raised one zone (default 0.5 s).
    pub predict_horizon_s: f64,
}

impl Default for ZoneThresholds {
    fn default() -> Self {
        Self { warning_fraction: 0.10, critical_fraction: 0.05, predict_horizon_s: 0.5 }
    }
}

impl ZoneThresholds {
    /// Zone of a joint at `value` (position only).
    pub fn zone(&self, limit: &JointLimit, value: f64) -> LimitZone {
        if !value.is_finite() || !limit.contains(value) {
            return LimitZone::Critical;
        }
        match limit.margin_fraction(value) {
            None => LimitZone::Safe,
            Some(m) if m <= self.critical_fraction => LimitZone::Critical,
            Some(m) if m <= self.warning_fraction => LimitZone::Warning,
            Some(_) => LimitZone::Safe,
        }
    }

    /// Zone with prediction: the position zone, raised one step when the joint will reach a
    /// limit within [`Self::predict_horizon_s`] at its current `velocity`.
    pub fn predictive_zone(&self, limit: &JointLimit, value: f64, velocity: f64) -> ZoneReport {
        let zone = self.zone(limit, value);
        let time_to_limit_s = limit.time_to_limit_s(value, velocity);
        let raised = match time_to_limit_s {
            Some(t) if t < self.predict_horizon_s => match zone {
                LimitZone::Safe => LimitZone::Warning,
                _ => LimitZone::Critical,
            },
            _ => zone,
        };
        let time_to_nearest_limit_s = limit.time_to_nearest_limit_s(value, velocity);
        ZoneReport { zone: raised, position_zone: zone, time_to_limit_s, time_to_nearest_limit_s }
    }
}

/// A joint's zone with its prediction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ZoneReport {
    /// Zone to display (position zone, raised by the prediction).
    pub zone: LimitZone,
    /// Zone from the position alone.
    pub position_zone: LimitZone,
    /// Seconds until the limit being approached is reached, if moving toward one.
    pub time_to_limit_s: Option<f64>,
    /// Seconds until the limit the joint is nearest to is reached, only while moving toward
    /// it (see [`JointLimit::time_to_nearest_limit_s`]); what a "near limit" warning shows.
    #[serde(default)]
    pub time_to_nearest_limit_s: Option<f64>,
}

impl ZoneReport {
    /// True when this joint is a real risk now: in the critical zone, or moving toward a limit
    /// it reaches within the prediction horizon (the zone was raised by the prediction).
    /// Sitting still in the warning band is information, not an alarm.
    pub fn is_alarm(&self) -> bool {
        self.position_zone == LimitZone::Critical || self.zone > self.position_zone
    }
}

/// What to do with a target outside the limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum LimitPolicy {
    /// Refuse the whole target, naming the joint and the limit.
    #[default]
    Reject,
    /// Clamp each joint into its range. Non-finite values are still rejected.
    Clamp,
}

/// Which side of the range was violated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum LimitSide {
    /// Below the lower limit.
    Lower,
    /// Above the upper limit.
    Upper,
}

/// A target refused by the limit policy.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimitViolation {
    /// A joint value lies outside its range.
    #[error(
        "joint {joint_index} ({name}) target {value_deg:.3}° ({value:.5} rad) is {} its {} limit {limit_deg:.3}° ({limit:.5} rad)",
        if *side == LimitSide::Lower { "below" } else { "above" },
        if *side == LimitSide::Lower { "lower" } else { "upper" },
        value_deg = value.to_degrees(),
        limit_deg = limit.to_degrees()
    )]
    OutOfRange {
        /// 1-based joint number (J1 = 1).
        joint_index: usize,
        /// Joint name.
        name: String,
        /// The requested value, rad.
        value: f64,
        /// The limit that was passed, rad.
        limit: f64,
        /// Which limit.
        side: LimitSide,
    },
    /// A joint value is NaN or infinite.
    #[error("joint {joint_index} ({name}) target is not a finite number ({value})")]
    NotFinite {
        /// 1-based joint number.
        joint_index: usize,
        /// Joint name.
        name: String,
        /// The value.
        value: f64,
    },
    /// The target has the wrong number of joints.
    #[error("expected {expected} joint values, got {got}")]
    WrongLength {
        /// Joints of the robot.
        expected: usize,
        /// Values given.
        got: usize,
    },
}

/// The position limits of every joint of a chain, in chain order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointLimits {
    joints: Vec<JointLimit>,
}

impl JointLimits {
    /// Limits from per-joint entries (chain order).
    pub fn new(joints: Vec<JointLimit>) -> Self {
        Self { joints }
    }

    /// The PAROL6 limits of ROBOT.md §3 with the API speed limits of §5.
    pub fn parol6() -> Self {
        let v = crate::parol6::max_speed_rad_s();
        Self::new(
            (0..crate::parol6::JOINT_COUNT)
                .map(|i| JointLimit {
                    name: crate::parol6::JOINT_NAMES[i].to_string(),
                    min: crate::parol6::LIMITS_RAD[i].0,
                    max: crate::parol6::LIMITS_RAD[i].1,
                    max_velocity: v[i],
                })
                .collect(),
        )
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.joints.len()
    }

    /// True when there are no joints.
    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
    }

    /// Limit of joint `i` (0-based).
    pub fn get(&self, i: usize) -> Option<&JointLimit> {
        self.joints.get(i)
    }

    /// All joints' limits.
    pub fn iter(&self) -> std::slice::Iter<'_, JointLimit> {
        self.joints.iter()
    }

    /// Mutable access, e.g. to tighten a range.
    pub fn joints_mut(&mut self) -> &mut [JointLimit] {
        &mut self.joints
    }

    /// True when every value lies within its limits.
    pub fn contains(&self, q: &[f64]) -> bool {
        q.len() == self.joints.len() && self.joints.iter().zip(q).all(|(l, &v)| l.contains(v))
    }

    /// Ok when every value lies within its limits; else the first violation.
    pub fn check(&self, q: &[f64]) -> Result<(), LimitViolation> {
        if q.len() != self.joints.len() {
            return Err(LimitViolation::WrongLength { expected: self.joints.len(), got: q.len() });
        }
        for (i, (l, &v)) in self.joints.iter().zip(q).enumerate() {
            if !v.is_finite() {
                return Err(LimitViolation::NotFinite { joint_index: i + 1, name: l.name.clone(), value: v });
            }
            if !l.contains(v) {
                let (limit, side) = if v < l.min { (l.min, LimitSide::Lower) } else { (l.max, LimitSide::Upper) };
                return Err(LimitViolation::OutOfRange {
                    joint_index: i + 1,
                    name: l.name.clone(),
                    value: v,
                    limit,
                    side,
                });
            }
        }
        Ok(())
    }

    /// Applies `policy` to a target: the (possibly clamped) target, or the violation.
    /// The result always lies within the limits.
    pub fn enforce(&self, q: &[f64], policy: LimitPolicy) -> Result<Vec<f64>, LimitViolation> {
        match policy {
            LimitPolicy::Reject => {
                self.check(q)?;
                Ok(self.joints.iter().zip(q).map(|(l, &v)| l.clamp(v)).collect())
            }
            LimitPolicy::Clamp => {
                if q.len() != self.joints.len() {
                    return Err(LimitViolation::WrongLength { expected: self.joints.len(), got: q.len() });
                }
                self.joints
                    .iter()
                    .zip(q)
                    .enumerate()
                    .map(|(i, (l, &v))| {
                        if v.is_finite() {
                            Ok(l.clamp(v))
                        } else {
                            Err(LimitViolation::NotFinite { joint_index: i + 1, name: l.name.clone(), value: v })
                        }
                    })
                    .collect()
            }
        }
    }

    /// Position zone of every joint.
    pub fn zones(&self, q: &[f64], thresholds: &ZoneThresholds) -> Vec<LimitZone> {
        self.joints.iter().zip(q).map(|(l, &v)| thresholds.zone(l, v)).collect()
    }

    /// Predictive zone report of every joint.
    pub fn zone_reports(&self, q: &[f64], qd: &[f64], thresholds: &ZoneThresholds) -> Vec<ZoneReport> {
        self.joints.iter().zip(q.iter().zip(qd)).map(|(l, (&v, &w))| thresholds.predictive_zone(l, v, w)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn j2() -> JointLimit {
        JointLimits::parol6().get(1).cloned().expect("J2")
    }

    /// Regression (issue 32): at standby the J1 LED was amber ("nearest limit") 33° from its
    /// limit, and every recording opened with a "J1 near limit" event.
    #[test]
    fn standby_is_safe_on_every_joint() {
        let t = ZoneThresholds::default();
        assert_eq!((t.warning_fraction, t.critical_fraction), (0.10, 0.05));
        let limits = JointLimits::parol6();
        for (j, q) in crate::parol6::standby_rad().iter().enumerate() {
            let l = limits.get(j).cloned().expect("six joints");
            assert_eq!(t.zone(&l, *q), LimitZone::Safe, "J{} at standby", j + 1);
        }
    }

    #[test]
    fn zones_follow_distance_to_limit() {
        let t = ZoneThresholds::default();
        let l = j2();
        let r = l.range();
        assert_eq!(t.zone(&l, l.min + 0.5 * r), LimitZone::Safe);
        assert_eq!(t.zone(&l, l.min + 0.08 * r), LimitZone::Warning);
        assert_eq!(t.zone(&l, l.max - 0.08 * r), LimitZone::Warning);
        assert_eq!(t.zone(&l, l.min + 0.02 * r), LimitZone::Critical);
        assert_eq!(t.zone(&l, l.max), LimitZone::Critical);
        assert_eq!(t.zone(&l, l.max + 0.1), LimitZone::Critical);
        assert_eq!(t.zone(&l, f64::NAN), LimitZone::Critical);
    }

    #[test]
    fn thresholds_are_configurable() {
        let t = ZoneThresholds { warning_fraction: 0.3, critical_fraction: 0.2, predict_horizon_s: 0.0 };
        let l = j2();
        assert_eq!(t.zone(&l, l.min + 0.25 * l.range()), LimitZone::Warning);
        assert_eq!(t.zone(&l, l.min + 0.15 * l.range()), LimitZone::Critical);
    }

    #[test]
    fn prediction_raises_the_zone_when_approaching() {
        let t = ZoneThresholds::default();
        let l = j2();
        let mid = l.min + 0.5 * l.range();
        let toward = t.predictive_zone(&l, mid, 10.0);
        assert_eq!(toward.position_zone, LimitZone::Safe);
        assert_eq!(toward.zone, LimitZone::Warning);
        let tt = toward.time_to_limit_s.expect("moving toward max");
        assert!((tt - (l.max - mid) / 10.0).abs() < 1e-12);
        let slow = t.predictive_zone(&l, mid, 0.01);
        assert_eq!(slow.zone, LimitZone::Safe);
        assert_eq!(t.predictive_zone(&l, mid, 0.0).time_to_limit_s, None);
    }

    #[test]
    fn time_to_nearest_limit_only_while_moving_toward_it() {
        let t = ZoneThresholds::default();
        let l = j2();
        let near_min = l.min + 0.10 * l.range();
        // Moving away from the lower limit it is near: no time to show (the upper limit is far).
        let away = t.predictive_zone(&l, near_min, 0.5);
        assert_eq!(away.position_zone, LimitZone::Warning);
        assert!(away.time_to_limit_s.is_some(), "still heading for the upper limit");
        assert_eq!(away.time_to_nearest_limit_s, None);
        assert!(!away.is_alarm());
        // Moving toward it: the time to the lower limit.
        let toward = t.predictive_zone(&l, near_min, -0.5);
        let tt = toward.time_to_nearest_limit_s.expect("toward the lower limit");
        assert!((tt - 0.10 * l.range() / 0.5).abs() < 1e-12);
        // Near the upper limit, the same by symmetry.
        let near_max = l.max - 0.10 * l.range();
        assert_eq!(t.predictive_zone(&l, near_max, -0.5).time_to_nearest_limit_s, None);
        assert!(t.predictive_zone(&l, near_max, 0.5).time_to_nearest_limit_s.is_some());
        // Still: nothing.
        assert_eq!(t.predictive_zone(&l, near_min, 0.0).time_to_nearest_limit_s, None);
    }

    #[test]
    fn alarm_only_for_red_zone_or_predicted_contact() {
        let t = ZoneThresholds::default();
        let l = j2();
        assert!(!t.predictive_zone(&l, l.min + 0.10 * l.range(), 0.0).is_alarm(), "amber at rest is information");
        assert!(t.predictive_zone(&l, l.min + 0.02 * l.range(), 0.0).is_alarm(), "red zone");
        let fast = t.predictive_zone(&l, l.min + 0.10 * l.range(), -10.0);
        assert!(fast.is_alarm(), "reaches the limit within the horizon: {fast:?}");
    }

    #[test]
    fn reject_names_joint_and_limit() {
        let lim = JointLimits::parol6();
        let mut q = crate::parol6::standby_rad().to_vec();
        q[1] = -3.0;
        let err = lim.enforce(&q, LimitPolicy::Reject).expect_err("J2 below min");
        match &err {
            LimitViolation::OutOfRange { joint_index, side, limit, .. } => {
                assert_eq!(*joint_index, 2);
                assert_eq!(*side, LimitSide::Lower);
                assert_eq!(*limit, crate::parol6::LIMITS_RAD[1].0);
            }
            other => panic!("unexpected {other:?}"),
        }
        let msg = err.to_string();
        assert!(msg.contains("joint 2 (J2)") && msg.contains("lower limit"), "{msg}");
    }

    #[test]
    fn clamp_pulls_into_range_and_rejects_nan() {
        let lim = JointLimits::parol6();
        let mut q = crate::parol6::standby_rad().to_vec();
        q[5] = 7.0;
        let c = lim.enforce(&q, LimitPolicy::Clamp).expect("clamped");
        assert_eq!(c[5], crate::parol6::LIMITS_RAD[5].1);
        q[0] = f64::NAN;
        assert!(matches!(lim.enforce(&q, LimitPolicy::Clamp), Err(LimitViolation::NotFinite { joint_index: 1, .. })));
        assert!(matches!(lim.enforce(&q[..3], LimitPolicy::Clamp), Err(LimitViolation::WrongLength { .. })));
    }

    #[test]
    fn standby_is_inside_the_limits() {
        assert!(JointLimits::parol6().contains(&crate::parol6::standby_rad()));
        assert!(JointLimits::parol6().contains(&crate::parol6::park_rad()));
    }

    proptest! {
        #[test]
        fn enforce_output_is_always_within_limits(q in proptest::collection::vec(-10.0f64..10.0, 6), clamp in any::<bool>()) {
            let lim = JointLimits::parol6();
            let policy = if clamp { LimitPolicy::Clamp } else { LimitPolicy::Reject };
            if let Ok(out) = lim.enforce(&q, policy) {
                prop_assert!(lim.contains(&out));
            } else {
                prop_assert!(!clamp);
                prop_assert!(!lim.contains(&q));
            }
        }
    }
}

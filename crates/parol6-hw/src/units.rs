//! Motor steps ↔ joint angles (ROBOT.md §2) and the step-unit limits of §3 and §5.
//!
//! `rad = steps · 2π / (6400 · ratio)`, no offset, no sign flip. Angle → steps rounds half to
//! even (the API's `np.rint`); speed → steps/s truncates toward zero (as the API does).

use parol6_core::parol6::{
    GEAR_RATIOS, JOINT_COUNT, LIMITS_STEPS, MAX_ACCEL_STEPS_S2, MAX_SPEED_STEPS_S, MICROSTEPS_PER_MOTOR_REV,
    STANDBY_DEG, rad_per_step,
};

use crate::frame::{I24_MAX, I24_MIN};

/// Degrees per motor step before the gear ratio (360 / 6400).
pub const DEG_PER_MOTOR_STEP: f64 = 360.0 / MICROSTEPS_PER_MOTOR_REV;
/// Firmware speed clamp for JOG and MOVE, steps/s (AccelStepper max speed; the stepper law's,
/// `parol6_core::motion::stepper`).
pub const FW_MAX_SPEED_STEPS_S: i32 = parol6_core::motion::stepper::FW_MAX_SPEED_STEPS_S as i32;
/// Minimum jog speed, steps/s (API `JOG_MIN_STEPS`).
pub const JOG_MIN_SPEED_STEPS_S: f64 = 100.0;
/// Jog max speed as a fraction of the max speed (API: 0.8).
pub const JOG_MAX_FRACTION: f64 = 0.8;
/// Standby (= home) pose in steps, written by the firmware when homing ends (ROBOT.md §4).
pub const STANDBY_STEPS: [i32; JOINT_COUNT] = [10240, -32000, 57905, 0, 0, 32000];

/// A value that cannot be converted to steps.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UnitError {
    /// Joint index out of range (0-based).
    #[error("joint index {0} out of range (0..6)")]
    BadJoint(usize),
    /// NaN or infinite.
    #[error("joint {joint} value {value} is not finite")]
    NotFinite {
        /// 1-based joint.
        joint: usize,
        /// The value.
        value: f64,
    },
    /// Does not fit the 24-bit wire field.
    #[error("joint {joint} value {value} is outside the 24-bit step range")]
    OutOfRange {
        /// 1-based joint.
        joint: usize,
        /// The value, steps.
        value: f64,
    },
}

fn check_joint(joint: usize) -> Result<(), UnitError> {
    if joint < JOINT_COUNT { Ok(()) } else { Err(UnitError::BadJoint(joint)) }
}

fn to_i24(joint: usize, steps: f64) -> Result<i32, UnitError> {
    if !steps.is_finite() {
        return Err(UnitError::NotFinite { joint: joint + 1, value: steps });
    }
    if steps < f64::from(I24_MIN) || steps > f64::from(I24_MAX) {
        return Err(UnitError::OutOfRange { joint: joint + 1, value: steps });
    }
    Ok(steps as i32)
}

/// Steps → joint angle, rad.
pub fn steps_to_rad(joint: usize, steps: i32) -> f64 {
    f64::from(steps) * rad_per_step(joint.min(JOINT_COUNT - 1))
}

/// Steps → joint angle, degrees.
pub fn steps_to_deg(joint: usize, steps: i32) -> f64 {
    f64::from(steps) * DEG_PER_MOTOR_STEP / GEAR_RATIOS[joint.min(JOINT_COUNT - 1)]
}

/// Joint angle (rad) → steps, rounded half to even.
pub fn rad_to_steps(joint: usize, rad: f64) -> Result<i32, UnitError> {
    check_joint(joint)?;
    to_i24(joint, parol6_core::motion::stepper::steps_of_rad(joint, rad))
}

/// Joint angle (deg) → steps, `round(deg / 0.05625 × ratio)` half to even.
pub fn deg_to_steps(joint: usize, deg: f64) -> Result<i32, UnitError> {
    check_joint(joint)?;
    to_i24(joint, (deg / DEG_PER_MOTOR_STEP * GEAR_RATIOS[joint]).round_ties_even())
}

/// Joint speed (rad/s) → steps/s, truncated toward zero.
pub fn rad_s_to_steps_s(joint: usize, rad_s: f64) -> Result<i32, UnitError> {
    check_joint(joint)?;
    to_i24(joint, (rad_s / rad_per_step(joint)).trunc())
}

/// Steps/s → rad/s.
pub fn steps_s_to_rad_s(joint: usize, steps_s: i32) -> f64 {
    steps_to_rad(joint, steps_s)
}

/// All six joints, steps → rad.
pub fn joints_steps_to_rad(steps: &[i32; JOINT_COUNT]) -> [f64; JOINT_COUNT] {
    std::array::from_fn(|i| steps_to_rad(i, steps[i]))
}

/// All six joints, rad → steps.
pub fn joints_rad_to_steps(rad: &[f64]) -> Result<[i32; JOINT_COUNT], UnitError> {
    if rad.len() != JOINT_COUNT {
        return Err(UnitError::BadJoint(rad.len()));
    }
    let mut out = [0; JOINT_COUNT];
    for i in 0..JOINT_COUNT {
        out[i] = rad_to_steps(i, rad[i])?;
    }
    Ok(out)
}

/// Joint limits in steps, `(min, max)` per joint: the API `rint` row of ROBOT.md §3
/// ([`LIMITS_STEPS`], the one source of truth of the joint limits).
pub fn limits_steps() -> [(i32, i32); JOINT_COUNT] {
    LIMITS_STEPS
}

/// Standby pose computed from its angles (equals [`STANDBY_STEPS`]).
pub fn standby_steps_from_deg() -> [i32; JOINT_COUNT] {
    std::array::from_fn(|i| (STANDBY_DEG[i] / DEG_PER_MOTOR_STEP * GEAR_RATIOS[i]).round_ties_even() as i32)
}

/// API max speed per joint, steps/s.
pub fn max_speed_steps_s() -> [i32; JOINT_COUNT] {
    MAX_SPEED_STEPS_S.map(|v| v as i32)
}

/// API max acceleration per joint, steps/s².
pub fn max_accel_steps_s2() -> [i32; JOINT_COUNT] {
    MAX_ACCEL_STEPS_S2.map(|v| v as i32)
}

/// API jog max speed per joint (0.8 × max), steps/s.
pub fn jog_max_speed_steps_s() -> [f64; JOINT_COUNT] {
    MAX_SPEED_STEPS_S.map(|v| v * JOG_MAX_FRACTION)
}

/// Jog speed for a fraction `f` in −1…1 (clamped; NaN reads as 0):
/// `|v| = 100 + (jog_max − 100)·|f|` steps/s with the sign of `f`, and 0 for `f = 0`.
pub fn jog_speed_steps_s(joint: usize, fraction: f64) -> Result<f64, UnitError> {
    check_joint(joint)?;
    let f = if fraction.is_nan() { 0.0 } else { fraction.clamp(-1.0, 1.0) };
    if f == 0.0 {
        return Ok(0.0);
    }
    let max = jog_max_speed_steps_s()[joint];
    Ok(f.signum() * (JOG_MIN_SPEED_STEPS_S + (max - JOG_MIN_SPEED_STEPS_S) * f.abs()))
}

/// True when `steps` lies within the joint's step limits.
pub fn steps_within_limits(joint: usize, steps: i32) -> bool {
    joint < JOINT_COUNT && {
        let (lo, hi) = limits_steps()[joint];
        (lo..=hi).contains(&steps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use parol6_core::parol6::LIMITS_RAD;
    use proptest::prelude::*;

    #[test]
    fn standby_steps_match_robot_md() {
        assert_eq!(standby_steps_from_deg(), STANDBY_STEPS);
        assert_eq!(STANDBY_STEPS, [10240, -32000, 57905, 0, 0, 32000]);
        assert!((steps_to_deg(2, 57905) - 180.0007).abs() < 1e-4);
    }

    #[test]
    fn limit_steps_match_robot_md_api_row() {
        assert_eq!(
            limits_steps(),
            [(-14000, 14000), (-51559, -1200), (34700, 92605), (-7500, 7500), (-6400, 6400), (0, 64000)]
        );
    }

    #[test]
    fn radian_limits_round_into_step_limits() {
        // A target clamped to the radian limits must pass the step guard after rounding.
        let lim = limits_steps();
        for i in 0..JOINT_COUNT {
            let lo = rad_to_steps(i, LIMITS_RAD[i].0).unwrap();
            let hi = rad_to_steps(i, LIMITS_RAD[i].1).unwrap();
            assert!(lo >= lim[i].0 && hi <= lim[i].1, "joint {i}: {lo}..{hi} vs {:?}", lim[i]);
        }
    }

    #[test]
    fn degrees_per_step_match_robot_md() {
        let expected = [0.0087890625, 0.0028125, 0.0031085526, 0.0140625, 0.0140625, 0.005625];
        for (i, e) in expected.iter().enumerate() {
            assert!((steps_to_deg(i, 1) - e).abs() < 1e-9);
        }
    }

    #[test]
    fn rounding_is_half_to_even_and_speed_truncates() {
        // J4: 1 step = 0.0140625°. 2.5 steps → 2, 3.5 steps → 4.
        assert_eq!(deg_to_steps(3, 2.5 * 0.0140625).unwrap(), 2);
        assert_eq!(deg_to_steps(3, 3.5 * 0.0140625).unwrap(), 4);
        assert_eq!(rad_s_to_steps_s(3, steps_to_rad(3, 10) * 0.99).unwrap(), 9);
        assert_eq!(rad_s_to_steps_s(3, -steps_to_rad(3, 10) * 0.99).unwrap(), -9);
    }

    #[test]
    fn speeds_and_jog_match_robot_md() {
        assert_eq!(max_speed_steps_s(), [15000, 25000, 32000, 10000, 10000, 27000]);
        assert_eq!(max_accel_steps_s2(), [45000, 75000, 96000, 30000, 30000, 81000]);
        assert_eq!(jog_max_speed_steps_s(), [12000.0, 20000.0, 25600.0, 8000.0, 8000.0, 21600.0]);
        assert_eq!(jog_speed_steps_s(0, 1.0).unwrap(), 12000.0);
        assert_eq!(jog_speed_steps_s(0, -1.0).unwrap(), -12000.0);
        assert_eq!(jog_speed_steps_s(0, 0.0).unwrap(), 0.0);
        assert_eq!(jog_speed_steps_s(1, 0.5).unwrap(), 100.0 + 19900.0 * 0.5);
        assert_eq!(jog_speed_steps_s(1, 7.0).unwrap(), 20000.0);
        assert!(jog_speed_steps_s(6, 1.0).is_err());
    }

    #[test]
    fn bad_values_are_errors() {
        assert!(matches!(rad_to_steps(0, f64::NAN), Err(UnitError::NotFinite { .. })));
        assert!(matches!(rad_to_steps(0, 1e9), Err(UnitError::OutOfRange { .. })));
        assert!(matches!(rad_to_steps(9, 0.0), Err(UnitError::BadJoint(9))));
    }

    proptest! {
        #[test]
        fn steps_round_trip(joint in 0usize..6, steps in -1_000_000i32..1_000_000) {
            prop_assert_eq!(rad_to_steps(joint, steps_to_rad(joint, steps)).unwrap(), steps);
            prop_assert_eq!(deg_to_steps(joint, steps_to_deg(joint, steps)).unwrap(), steps);
        }
    }
}

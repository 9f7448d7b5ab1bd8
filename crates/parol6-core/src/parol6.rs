//! PAROL6 facts from the reference pack (`ROBOT.md`): joint limits, standby pose, speed and
//! acceleration limits, tools. Joint values are the controller's *software angles*
//! (`rad = steps · 2π / (6400 · ratio)`), which are also the joint variables of the embedded
//! URDF (`assets/parol6/parol6.urdf`).

use std::f64::consts::PI;

/// Number of joints of the PAROL6.
pub const JOINT_COUNT: usize = 6;

/// Joint names used by the embedded URDF, J1 (base) … J6 (flange).
pub const JOINT_NAMES: [&str; JOINT_COUNT] = ["J1", "J2", "J3", "J4", "J5", "J6"];

/// Joint limits in motor steps, ROBOT.md §3 (the API `rint` row): **the one source of truth**
/// for the joint limits. The degree and radian limits below are derived from it.
pub const LIMITS_STEPS: [(i32, i32); JOINT_COUNT] =
    [(-14_000, 14_000), (-51_559, -1_200), (34_700, 92_605), (-7_500, 7_500), (-6_400, 6_400), (0, 64_000)];

/// How far the radian limits reach beyond the step limits, in steps: just under half a step,
/// the rounding band of `steps = round(rad / rad_per_step)`. Every angle inside the radian
/// limits rounds to a step count inside [`LIMITS_STEPS`], and every step count inside
/// [`LIMITS_STEPS`] is strictly inside the radian limits, so an arm standing on (or pushed to)
/// its step limit never reads as "outside", and ROBOT.md's degree values (which round to the
/// step limits) are accepted.
pub const LIMIT_ROUNDING_BAND_STEPS: f64 = 0.499;

/// Joint limits in degrees as ROBOT.md §3 lists them (API / GUI values; they round to
/// [`LIMITS_STEPS`]). For display and reference only: limits are enforced with [`LIMITS_RAD`].
pub const LIMITS_DEG: [(f64, f64); JOINT_COUNT] = [
    (-123.046875, 123.046875),
    (-145.0088, -3.375),
    (107.866, 287.8675),
    (-105.46975, 105.46975),
    (-90.0, 90.0),
    (0.0, 360.0),
];

/// Joint limits in radians, derived from [`LIMITS_STEPS`]:
/// `(steps ∓ LIMIT_ROUNDING_BAND_STEPS) · 2π / (6400 · ratio)`. The embedded URDF writes the
/// limits rounded (within 2e-4 rad, half a step).
pub const LIMITS_RAD: [(f64, f64); JOINT_COUNT] = {
    let mut out = [(0.0, 0.0); JOINT_COUNT];
    let mut j = 0;
    while j < JOINT_COUNT {
        let rps = rad_per_step(j);
        out[j] = (
            (LIMITS_STEPS[j].0 as f64 - LIMIT_ROUNDING_BAND_STEPS) * rps,
            (LIMITS_STEPS[j].1 as f64 + LIMIT_ROUNDING_BAND_STEPS) * rps,
        );
        j += 1;
    }
    out
};

/// Standby = home pose, degrees (ROBOT.md §4).
pub const STANDBY_DEG: [f64; JOINT_COUNT] = [90.0, -90.0, 180.0, 0.0, 0.0, 180.0];

/// GUI "Park" pose, degrees (ROBOT.md §4).
pub const PARK_DEG: [f64; JOINT_COUNT] = [90.0, -144.683, 108.171, 2.222, 25.003, 180.0];

/// Gear reduction (motor turns per joint turn), ROBOT.md §1.
pub const GEAR_RATIOS: [f64; JOINT_COUNT] = [6.4, 20.0, 20.0 * 38.0 / 42.0, 4.0, 4.0, 10.0];

/// Motor microsteps per motor revolution (200 full steps × 32).
pub const MICROSTEPS_PER_MOTOR_REV: f64 = 6400.0;

/// API max joint speed in motor steps/s, ROBOT.md §5.
pub const MAX_SPEED_STEPS_S: [f64; JOINT_COUNT] = [15000.0, 25000.0, 32000.0, 10000.0, 10000.0, 27000.0];

/// API max joint acceleration in motor steps/s² (3 × max speed), ROBOT.md §5.
pub const MAX_ACCEL_STEPS_S2: [f64; JOINT_COUNT] = [45000.0, 75000.0, 96000.0, 30000.0, 30000.0, 81000.0];

/// API max joint jerk in motor steps/s³ (10 × max acceleration), ROBOT.md §5.
pub const MAX_JERK_STEPS_S3: [f64; JOINT_COUNT] = [450000.0, 750000.0, 960000.0, 300000.0, 300000.0, 810000.0];

/// Holding torque of each joint's stepper motor, N·m. Source: the PAROL6 bill of materials
/// (`BOM/BOM.md` of the official PAROL6-Desktop-robot-arm repository, not in our reference
/// pack): one 17HS08-1004S (16 N·cm, 1 A), three 17HS16-2004S1 (45 N·cm, 2 A), two
/// 17HS24-2104S (65 N·cm, 2.1 A). The BOM does not say which motor drives which joint: the
/// 1 A motor is taken for J6 (the only joint with a current setting near 1 A, 965 mA, ROBOT.md
/// §1), and J1–J5 get the weakest of the other motors, 45 N·cm, so that a warning is never
/// missed.
pub const MOTOR_HOLDING_TORQUE_NM: [f64; JOINT_COUNT] = [0.45, 0.45, 0.45, 0.45, 0.45, 0.16];

/// Joint torque limits, N·m (*derived*): motor holding torque × gear reduction (ROBOT.md §1),
/// `MOTOR_HOLDING_TORQUE_NM[i] · GEAR_RATIOS[i]`. An upper bound: it ignores gearbox losses,
/// the FW's current setting (×0.85 of the rated current, ROBOT.md §1) and a stepper's torque
/// falling off with speed, so a torque near it is already a risk of lost steps.
pub fn joint_torque_limits_nm() -> [f64; JOINT_COUNT] {
    std::array::from_fn(|i| MOTOR_HOLDING_TORQUE_NM[i] * GEAR_RATIOS[i])
}

/// Radians per motor step for joint `i` (`2π / (6400 · ratio)`).
pub const fn rad_per_step(joint: usize) -> f64 {
    2.0 * PI / (MICROSTEPS_PER_MOTOR_REV * GEAR_RATIOS[joint])
}

/// Standby pose in radians.
pub fn standby_rad() -> [f64; JOINT_COUNT] {
    STANDBY_DEG.map(f64::to_radians)
}

/// Park pose in radians.
pub fn park_rad() -> [f64; JOINT_COUNT] {
    PARK_DEG.map(f64::to_radians)
}

/// API max joint speeds in rad/s.
pub fn max_speed_rad_s() -> [f64; JOINT_COUNT] {
    std::array::from_fn(|i| MAX_SPEED_STEPS_S[i] * rad_per_step(i))
}

/// API max joint accelerations in rad/s².
pub fn max_accel_rad_s2() -> [f64; JOINT_COUNT] {
    std::array::from_fn(|i| MAX_ACCEL_STEPS_S2[i] * rad_per_step(i))
}

/// API max joint jerks in rad/s³.
pub fn max_jerk_rad_s3() -> [f64; JOINT_COUNT] {
    std::array::from_fn(|i| MAX_JERK_STEPS_S3[i] * rad_per_step(i))
}

/// Radius of the solid sphere a tool's inertia is modelled as, m ([`Tool::inertia_kg_m2`]).
pub const TOOL_INERTIA_RADIUS_M: f64 = 0.03;

/// A tool fitted to the flange, ROBOT.md §7. The TCP is a pure translation in the L6 frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize)]
pub enum Tool {
    /// Bare flange.
    #[default]
    None,
    /// Pneumatic gripper, vertical mount (API default variant).
    PneumaticVertical,
    /// Pneumatic gripper, horizontal mount.
    PneumaticHorizontal,
    /// SSG-48 electric gripper (finger and pinch variants share the TCP).
    Ssg48,
    /// MSG electric gripper (100/150/200 mm rails share the TCP).
    Msg,
    /// Vacuum gripper.
    Vacuum,
}

impl Tool {
    /// Every tool, in menu order.
    pub const ALL: [Tool; 6] =
        [Tool::None, Tool::PneumaticVertical, Tool::PneumaticHorizontal, Tool::Ssg48, Tool::Msg, Tool::Vacuum];

    /// TCP offset in the L6 (flange) frame, metres.
    pub fn tcp_offset_m(self) -> [f64; 3] {
        match self {
            Tool::None => [0.0, 0.0, 0.0],
            Tool::PneumaticVertical => [-0.055, 0.0, -0.027],
            Tool::PneumaticHorizontal => [0.0, 0.0, -0.082],
            Tool::Ssg48 => [0.0, 0.0, -0.105],
            Tool::Msg => [-0.029, 0.0, -0.103],
            Tool::Vacuum => [0.0, 0.0, -0.037],
        }
    }

    /// Mass of the tool, kg. Our reference pack gives no tool masses; these are the values used
    /// for inverse dynamics, pre-flight torques and the simulation:
    /// - MSG: 0.40 kg, the maker's "Weight: 400 g" (Source Robotics, MSG gripper docs,
    ///   *About the gripper*);
    /// - SSG-48: 0.30 kg, *estimated* (no published figure found): a compact stepper gripper of
    ///   printed PETG, lighter than the MSG, heavier than the pneumatic grippers;
    /// - pneumatic grippers: 0.20 kg, vacuum gripper: 0.10 kg, *estimated* (printed bodies with a
    ///   small valve or cup; the air lines are carried by the arm).
    ///
    /// An estimate errs heavy, so that a torque warning is not missed.
    pub fn mass_kg(self) -> f64 {
        match self {
            Tool::None => 0.0,
            Tool::PneumaticVertical | Tool::PneumaticHorizontal => 0.20,
            Tool::Ssg48 => 0.30,
            Tool::Msg => 0.40,
            Tool::Vacuum => 0.10,
        }
    }

    /// Centre of mass of the tool in the L6 (flange) frame, m: halfway from the flange to the
    /// TCP (*assumed*: a body of even density between the two).
    pub fn com_m(self) -> [f64; 3] {
        self.tcp_offset_m().map(|v| 0.5 * v)
    }

    /// Inertia of the tool about its centre of mass, kg·m² (the same about every axis): a solid
    /// sphere of radius [`TOOL_INERTIA_RADIUS_M`] of its mass (*assumed*; its effect on the
    /// torques is small next to the mass on its lever).
    pub fn inertia_kg_m2(self) -> f64 {
        0.4 * self.mass_kg() * TOOL_INERTIA_RADIUS_M * TOOL_INERTIA_RADIUS_M
    }

    /// Command-line / config name.
    pub fn name(self) -> &'static str {
        match self {
            Tool::None => "none",
            Tool::PneumaticVertical => "pneumatic-vertical",
            Tool::PneumaticHorizontal => "pneumatic-horizontal",
            Tool::Ssg48 => "ssg48",
            Tool::Msg => "msg",
            Tool::Vacuum => "vacuum",
        }
    }

    /// Human label.
    pub fn label(self) -> &'static str {
        match self {
            Tool::None => "None (bare flange)",
            Tool::PneumaticVertical => "Pneumatic, vertical",
            Tool::PneumaticHorizontal => "Pneumatic, horizontal",
            Tool::Ssg48 => "SSG-48 electric gripper",
            Tool::Msg => "MSG electric gripper",
            Tool::Vacuum => "Vacuum gripper",
        }
    }

    /// Parse a tool name (as printed by [`Tool::name`]), normalised: ASCII case and surrounding
    /// white space are ignored, and the aliases `flange` (none), `pneumatic` (pneumatic-vertical)
    /// and `ssg-48` (ssg48) are accepted. Anything else is `None`, which callers refuse.
    pub fn from_name(name: &str) -> Option<Tool> {
        let n = name.trim().to_ascii_lowercase();
        match n.as_str() {
            "none" | "flange" => Some(Tool::None),
            "pneumatic" | "pneumatic-vertical" => Some(Tool::PneumaticVertical),
            "pneumatic-horizontal" => Some(Tool::PneumaticHorizontal),
            "ssg48" | "ssg-48" => Some(Tool::Ssg48),
            "msg" => Some(Tool::Msg),
            "vacuum" => Some(Tool::Vacuum),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tool_names_are_normalised_as_documented() {
        for (typed, tool) in
            [("NONE", Tool::None), ("none ", Tool::None), ("ssg-48", Tool::Ssg48), (" SSG48", Tool::Ssg48)]
        {
            assert_eq!(Tool::from_name(typed), Some(tool), "{typed:?}");
        }
        for bad in ["", "ssg 48", "n0ne", "vacuum2"] {
            assert_eq!(Tool::from_name(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn limits_deg_and_rad_agree() {
        for (d, r) in LIMITS_DEG.iter().zip(LIMITS_RAD.iter()) {
            // within half a step (at most 1.3e-4 rad, J4)
            assert!((d.0.to_radians() - r.0).abs() < 2e-4);
            assert!((d.1.to_radians() - r.1).abs() < 2e-4);
        }
    }

    /// Regression: "jogging J1 (either end), J2 (lower) or J3 (upper) into its limit locks out
    /// all motion until re-homing" — the radian limits were narrower than the step limits.
    #[test]
    fn jogging_into_the_limit_locks_out_motion_every_step_limit_is_inside() {
        for j in 0..JOINT_COUNT {
            let (lo, hi) = LIMITS_STEPS[j];
            for steps in [lo, lo + 1, hi - 1, hi] {
                let q = f64::from(steps) * rad_per_step(j);
                assert!(q >= LIMITS_RAD[j].0 && q <= LIMITS_RAD[j].1, "J{} {steps} steps = {q} rad", j + 1);
            }
            // Angles inside the radian limits round to step counts inside the step limits.
            let r = (LIMITS_RAD[j].0 / rad_per_step(j)).round_ties_even() as i32;
            let s = (LIMITS_RAD[j].1 / rad_per_step(j)).round_ties_even() as i32;
            assert_eq!((r, s), (lo, hi), "J{}", j + 1);
        }
    }

    /// ROBOT.md's degree limits (`hw move --joints 123.046875,… --deg`) are accepted.
    #[test]
    fn jogging_into_the_limit_locks_out_motion_robot_md_degrees_are_inside() {
        for j in 0..JOINT_COUNT {
            for d in [LIMITS_DEG[j].0, LIMITS_DEG[j].1] {
                let q = d.to_radians();
                assert!(q >= LIMITS_RAD[j].0 && q <= LIMITS_RAD[j].1, "J{} {d}°", j + 1);
            }
        }
    }

    #[test]
    fn api_speeds_in_rad_s_match_robot_md() {
        let v = max_speed_rad_s();
        let expected = [2.3010, 1.2272, 1.7361, 2.4544, 2.4544, 2.6507];
        for (a, b) in v.iter().zip(expected) {
            assert!((a - b).abs() < 1e-3, "{a} vs {b}");
        }
    }

    #[test]
    fn tool_names_round_trip() {
        for t in Tool::ALL {
            assert_eq!(Tool::from_name(t.name()), Some(t));
        }
        assert_eq!(Tool::from_name("bogus"), None);
    }
}

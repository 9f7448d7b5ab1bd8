//! A running `FollowJointTrajectory` goal's tolerances, as control_msgs defines them and a
//! ros2_control `joint_trajectory_controller` enforces them:
//!
//! - `path_tolerance`: while the trajectory runs, every joint's measured position and velocity
//!   stay within their tolerances of the commanded (desired) ones, else the goal aborts with
//!   `PATH_TOLERANCE_VIOLATED` ([`worst_violation`]);
//! - `goal_tolerance` and `goal_time_tolerance`: after the trajectory's end, the joints must be
//!   within their goal tolerances of its last point (at rest: velocity 0) no later than
//!   `goal_time_tolerance` after that end, else the goal aborts with `GOAL_TOLERANCE_VIOLATED`
//!   ([`goal_end`]).
//!
//! A tolerance of 0 is "the server's default" and -1 "none" (control_msgs). Our defaults: no
//! tolerance is checked for a joint that has none (0 or -1, or not listed), and a
//! `goal_time_tolerance` of 0 is [`DEFAULT_GOAL_TIME_TOLERANCE_S`]. Acceleration tolerances are
//! checked for their value (finite, -1, 0 or positive) and not enforced: the arm measures no
//! acceleration (its steppers report position and speed), and `joint_trajectory_controller`
//! likewise checks acceleration only on hardware with an acceleration state interface.

use super::msgs::Duration;

/// How long after the trajectory's end the goal tolerance may still be reached when the goal's
/// `goal_time_tolerance` is 0, s (MoveIt's default `allowed_goal_duration_margin`).
pub const DEFAULT_GOAL_TIME_TOLERANCE_S: f64 = 0.5;

/// What a tolerance bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Joint position, rad.
    Position,
    /// Joint velocity, rad/s.
    Velocity,
}

impl Quantity {
    /// The unit of its values and tolerances.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Position => "rad",
            Quantity::Velocity => "rad/s",
        }
    }
}

/// One tolerance list's (path or goal) per-joint tolerances, robot order (`None`: not checked).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointTolerances {
    /// Position tolerances, rad.
    pub position_rad: Vec<Option<f64>>,
    /// Velocity tolerances, rad/s.
    pub velocity_rad_s: Vec<Option<f64>>,
}

impl JointTolerances {
    /// No joint checked, for `joints` joints.
    pub fn none(joints: usize) -> Self {
        JointTolerances { position_rad: vec![None; joints], velocity_rad_s: vec![None; joints] }
    }

    /// True when no tolerance is checked.
    pub fn is_empty(&self) -> bool {
        self.position_rad.iter().chain(&self.velocity_rad_s).all(Option::is_none)
    }
}

/// Joint positions and velocities, robot order.
#[derive(Debug, Clone, Copy)]
pub struct JointMotion<'a> {
    /// Positions, rad.
    pub q_rad: &'a [f64],
    /// Velocities, rad/s.
    pub qd_rad_s: &'a [f64],
}

/// A joint outside its tolerance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Violation {
    /// 0-based joint, robot order.
    pub joint: usize,
    /// Position or velocity.
    pub quantity: Quantity,
    /// Measured minus wanted value, in the quantity's unit (NaN for a value that is not a number).
    pub deviation: f64,
    /// The tolerance, in the quantity's unit.
    pub tolerance: f64,
}

impl Violation {
    /// `J2 is 0.012340 rad from its desired position (path_tolerance 0.01 rad)` or
    /// `J2 is 0.250000 rad/s from its desired velocity (path_tolerance 0.1 rad/s)`, naming the
    /// joint from `names` (robot order); `what` is the tolerance's field.
    pub fn describe(&self, names: &[&str], what: &str, wanted: &str) -> String {
        let (noun, unit) = match self.quantity {
            Quantity::Position => ("position", self.quantity.unit()),
            Quantity::Velocity => ("velocity", self.quantity.unit()),
        };
        format!(
            "{} is {:.6} {unit} from its {wanted} {noun} ({what} {} {unit})",
            names.get(self.joint).copied().unwrap_or("?"),
            self.deviation.abs(),
            self.tolerance
        )
    }

    fn excess(&self) -> f64 {
        let e = self.deviation.abs() - self.tolerance;
        if e.is_nan() { f64::INFINITY } else { e }
    }
}

/// The joint furthest outside its tolerance of one quantity.
fn worst_of(quantity: Quantity, tolerance: &[Option<f64>], wanted: &[f64], actual: &[f64]) -> Option<Violation> {
    tolerance
        .iter()
        .zip(wanted.iter().zip(actual))
        .enumerate()
        .filter_map(|(joint, (tol, (w, a)))| {
            let tolerance = (*tol)?;
            let deviation = a - w;
            if deviation.abs() <= tolerance { None } else { Some(Violation { joint, quantity, deviation, tolerance }) }
        })
        .max_by(|a, b| a.excess().total_cmp(&b.excess()))
}

/// The joint furthest outside its tolerance (`tolerances`) with the arm moving as `actual`
/// where it should move as `wanted`; `None` when every checked joint is within its tolerances
/// (a deviation equal to the tolerance is within). A position violation is reported before a
/// velocity one (their units differ); a value that is not a number is outside every tolerance.
pub fn worst_violation(
    tolerances: &JointTolerances,
    wanted: JointMotion<'_>,
    actual: JointMotion<'_>,
) -> Option<Violation> {
    worst_of(Quantity::Position, &tolerances.position_rad, wanted.q_rad, actual.q_rad)
        .or_else(|| worst_of(Quantity::Velocity, &tolerances.velocity_rad_s, wanted.qd_rad_s, actual.qd_rad_s))
}

/// What becomes of a goal whose trajectory has ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GoalEnd {
    /// Every joint within its goal tolerances: SUCCEEDED.
    Reached,
    /// Not yet, but `goal_time_tolerance` has not passed: look again.
    Waiting,
    /// Still outside once `goal_time_tolerance` has passed: `GOAL_TOLERANCE_VIOLATED`.
    Violated(Violation),
}

/// The goal's end `since_end_s` after its trajectory's end, with the arm moving as `actual`,
/// its last point at `final_q_rad` (at rest) and `goal_time_tolerance_s` of leeway.
pub fn goal_end(
    tolerances: &JointTolerances,
    final_q_rad: &[f64],
    actual: JointMotion<'_>,
    since_end_s: f64,
    goal_time_tolerance_s: f64,
) -> GoalEnd {
    let at_rest = vec![0.0; final_q_rad.len()];
    let wanted = JointMotion { q_rad: final_q_rad, qd_rad_s: &at_rest };
    match worst_violation(tolerances, wanted, actual) {
        None => GoalEnd::Reached,
        Some(_) if since_end_s <= goal_time_tolerance_s => GoalEnd::Waiting,
        Some(v) => GoalEnd::Violated(v),
    }
}

/// The leeway a goal's `goal_time_tolerance` gives, s: 0 is [`DEFAULT_GOAL_TIME_TOLERANCE_S`]
/// (a duration that is not valid, which the goal's checks refuse, too).
pub fn goal_time_tolerance_s(d: &Duration) -> f64 {
    match d.as_secs_f64() {
        Some(s) if s > 0.0 && s.is_finite() => s,
        _ => DEFAULT_GOAL_TIME_TOLERANCE_S,
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    const NAMES: [&str; 6] = ["J1", "J2", "J3", "J4", "J5", "J6"];
    const STILL: [f64; 6] = [0.0; 6];

    fn positions_only(position_rad: Vec<Option<f64>>) -> JointTolerances {
        JointTolerances { velocity_rad_s: vec![None; position_rad.len()], position_rad }
    }

    fn at(q_rad: &[f64]) -> JointMotion<'_> {
        JointMotion { q_rad, qd_rad_s: &STILL }
    }

    #[test]
    fn path_tolerance_violation_names_the_joint_and_the_deviation() {
        let tol = positions_only(vec![None, Some(0.01), None, None, None, None]);
        let mut actual = [0.0; 6];
        actual[1] = -0.0123;
        actual[0] = 5.0; // J1 has no tolerance
        let v = worst_violation(&tol, at(&[0.0; 6]), at(&actual)).unwrap();
        assert_eq!((v.joint, v.quantity, v.tolerance), (1, Quantity::Position, 0.01));
        assert!((v.deviation + 0.0123).abs() < 1e-12);
        let text = v.describe(&NAMES, "path_tolerance", "desired");
        assert_eq!(text, "J2 is 0.012300 rad from its desired position (path_tolerance 0.01 rad)");
    }

    #[test]
    fn path_tolerance_a_deviation_equal_to_it_is_within_and_nan_is_outside() {
        let tol = positions_only(vec![Some(0.5); 6]);
        assert_eq!(worst_violation(&tol, at(&[0.0; 6]), at(&[0.5, -0.5, 0.0, 0.25, 0.0, 0.0])), None);
        let mut actual = [0.0; 6];
        actual[4] = f64::NAN;
        actual[0] = 0.9;
        assert_eq!(worst_violation(&tol, at(&[0.0; 6]), at(&actual)).unwrap().joint, 4);
    }

    /// Issue 30: a velocity tolerance was validated and then ignored; it is now enforced
    /// against the commanded velocity while moving, and against rest at the goal.
    #[test]
    fn a_velocity_tolerance_is_enforced_on_the_path_and_at_the_goal() {
        let mut tol = JointTolerances::none(6);
        tol.velocity_rad_s[2] = Some(0.1);
        let q = [0.0; 6];
        let wanted_qd = [0.0, 0.0, 0.5, 0.0, 0.0, 0.0];
        let within = [0.0, 9.0, 0.58, 0.0, 0.0, 0.0]; // J2 has no velocity tolerance
        let outside = [0.0, 0.0, 0.25, 0.0, 0.0, 0.0];
        let wanted = JointMotion { q_rad: &q, qd_rad_s: &wanted_qd };
        assert_eq!(worst_violation(&tol, wanted, JointMotion { q_rad: &q, qd_rad_s: &within }), None);
        let v = worst_violation(&tol, wanted, JointMotion { q_rad: &q, qd_rad_s: &outside }).unwrap();
        assert_eq!((v.joint, v.quantity), (2, Quantity::Velocity));
        assert_eq!(
            v.describe(&NAMES, "path_tolerance", "desired"),
            "J3 is 0.250000 rad/s from its desired velocity (path_tolerance 0.1 rad/s)"
        );
        // at the goal the arm must be at rest within the tolerance
        let end = |qd: &[f64]| goal_end(&tol, &q, JointMotion { q_rad: &q, qd_rad_s: qd }, 1.0, 0.5);
        assert!(matches!(end(&wanted_qd), GoalEnd::Violated(v) if v.quantity == Quantity::Velocity));
        assert_eq!(end(&[0.0, 0.0, 0.09, 0.0, 0.0, 0.0]), GoalEnd::Reached);
    }

    #[test]
    fn a_position_violation_is_reported_before_a_velocity_one() {
        let tol = JointTolerances { position_rad: vec![Some(0.01); 6], velocity_rad_s: vec![Some(0.01); 6] };
        let q = [0.0, 0.0, 0.0, 0.0, 0.02, 0.0];
        let qd = [5.0; 6];
        let v = worst_violation(&tol, at(&[0.0; 6]), JointMotion { q_rad: &q, qd_rad_s: &qd }).unwrap();
        assert_eq!((v.joint, v.quantity), (4, Quantity::Position));
    }

    #[test]
    fn goal_time_tolerance_waits_until_it_has_passed() {
        let tol = positions_only(vec![Some(0.01), None, None, None, None, None]);
        let far = [0.1, 0.0, 0.0, 0.0, 0.0, 0.0];
        assert_eq!(goal_end(&tol, &[0.0; 6], at(&far), 0.2, 0.5), GoalEnd::Waiting);
        assert_eq!(goal_end(&tol, &[0.0; 6], at(&far), 0.5, 0.5), GoalEnd::Waiting);
        assert!(matches!(goal_end(&tol, &[0.0; 6], at(&far), 0.51, 0.5), GoalEnd::Violated(v) if v.joint == 0));
        assert_eq!(goal_end(&tol, &[0.0; 6], at(&[0.005, 0.0, 0.0, 0.0, 0.0, 0.0]), 3.0, 0.5), GoalEnd::Reached);
    }

    #[test]
    fn goal_time_tolerance_of_zero_is_our_default() {
        assert_eq!(goal_time_tolerance_s(&Duration::default()), DEFAULT_GOAL_TIME_TOLERANCE_S);
        assert_eq!(goal_time_tolerance_s(&Duration { sec: 2, nanosec: 250_000_000 }), 2.25);
        assert_eq!(goal_time_tolerance_s(&Duration { sec: 0, nanosec: 2_000_000_000 }), DEFAULT_GOAL_TIME_TOLERANCE_S);
    }

    fn tolerances() -> impl Strategy<Value = Vec<Option<f64>>> {
        prop::collection::vec(prop::option::of(0.0001f64..1.0), 6)
    }

    fn values() -> impl Strategy<Value = Vec<f64>> {
        prop::collection::vec(-3.0f64..3.0, 6)
    }

    /// The checked joints outside their tolerance: (joint, excess).
    fn outside(tol: &[Option<f64>], wanted: &[f64], actual: &[f64]) -> Vec<(usize, f64)> {
        (0..6)
            .filter_map(|j| tol[j].map(|t| (j, (actual[j] - wanted[j]).abs() - t)))
            .filter(|(_, e)| *e > 0.0)
            .collect()
    }

    proptest! {
        /// A violation is reported exactly when some checked joint is outside its position or
        /// velocity tolerance; it is a position one when there is one, the one furthest outside.
        #[test]
        fn path_tolerance_is_violated_exactly_when_a_checked_joint_is_outside(
            tol_q in tolerances(), tol_qd in tolerances(), wanted in values(), actual in values(),
            wanted_qd in values(), actual_qd in values()
        ) {
            let tol = JointTolerances { position_rad: tol_q.clone(), velocity_rad_s: tol_qd.clone() };
            let out_q = outside(&tol_q, &wanted, &actual);
            let out_qd = outside(&tol_qd, &wanted_qd, &actual_qd);
            let v = worst_violation(
                &tol,
                JointMotion { q_rad: &wanted, qd_rad_s: &wanted_qd },
                JointMotion { q_rad: &actual, qd_rad_s: &actual_qd },
            );
            match v {
                None => prop_assert!(out_q.is_empty() && out_qd.is_empty()),
                Some(v) => {
                    let (out, w, a) = match v.quantity {
                        Quantity::Position => (&out_q, &wanted, &actual),
                        Quantity::Velocity => {
                            prop_assert!(out_q.is_empty(), "a position violation comes first");
                            (&out_qd, &wanted_qd, &actual_qd)
                        }
                    };
                    let worst = out.iter().map(|(_, e)| *e).fold(f64::NEG_INFINITY, f64::max);
                    prop_assert!(out.iter().any(|(j, _)| *j == v.joint));
                    prop_assert_eq!(v.deviation.abs() - v.tolerance, worst);
                    prop_assert_eq!(v.deviation, a[v.joint] - w[v.joint]);
                }
            }
        }

        /// Within the goal time tolerance a goal is never violated; after it, a goal outside its
        /// tolerance always is; inside its tolerance it is reached whenever it is looked at.
        #[test]
        fn goal_tolerance_verdict_follows_the_goal_time_tolerance(
            tol_q in tolerances(), tol_qd in tolerances(), wanted in values(), actual in values(),
            actual_qd in values(), since in 0.0f64..5.0, gtt in 0.0f64..5.0
        ) {
            let tol = JointTolerances { position_rad: tol_q, velocity_rad_s: tol_qd };
            let actual = JointMotion { q_rad: &actual, qd_rad_s: &actual_qd };
            let inside = worst_violation(&tol, JointMotion { q_rad: &wanted, qd_rad_s: &STILL }, actual).is_none();
            match goal_end(&tol, &wanted, actual, since, gtt) {
                GoalEnd::Reached => prop_assert!(inside),
                GoalEnd::Waiting => prop_assert!(!inside && since <= gtt),
                GoalEnd::Violated(_) => prop_assert!(!inside && since > gtt),
            }
        }
    }
}

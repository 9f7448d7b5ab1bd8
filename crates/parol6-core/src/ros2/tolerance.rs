//! A running `FollowJointTrajectory` goal's tolerances, as control_msgs defines them and a
//! ros2_control `joint_trajectory_controller` enforces them:
//!
//! - `path_tolerance`: while the trajectory runs, every joint's measured position stays within
//!   its tolerance of the commanded (desired) one, else the goal aborts with
//!   `PATH_TOLERANCE_VIOLATED` ([`worst_violation`]);
//! - `goal_tolerance` and `goal_time_tolerance`: after the trajectory's end, the joints must be
//!   within their goal tolerance of its last point no later than `goal_time_tolerance` after
//!   that end, else the goal aborts with `GOAL_TOLERANCE_VIOLATED` ([`goal_end`]).
//!
//! A tolerance of 0 is "the server's default" and -1 "none" (control_msgs). Our defaults: no
//! position tolerance is checked for a joint that has none (0 or -1, or not listed), and a
//! `goal_time_tolerance` of 0 is [`DEFAULT_GOAL_TIME_TOLERANCE_S`]. Velocity and acceleration
//! tolerances are checked for their value (finite, -1, 0 or positive) and not enforced.

use super::msgs::Duration;

/// How long after the trajectory's end the goal tolerance may still be reached when the goal's
/// `goal_time_tolerance` is 0, s (MoveIt's default `allowed_goal_duration_margin`).
pub const DEFAULT_GOAL_TIME_TOLERANCE_S: f64 = 0.5;

/// A joint outside its position tolerance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Violation {
    /// 0-based joint, robot order.
    pub joint: usize,
    /// Measured minus wanted position, rad (NaN for a position that is not a number).
    pub deviation_rad: f64,
    /// The tolerance, rad.
    pub tolerance_rad: f64,
}

impl Violation {
    /// `J2 is 0.01234 rad from its desired position (path_tolerance 0.01 rad)`, naming the joint
    /// from `names` (robot order); `what` is the tolerance's field.
    pub fn describe(&self, names: &[&str], what: &str, wanted: &str) -> String {
        format!(
            "{} is {:.6} rad from its {wanted} position ({what} {} rad)",
            names.get(self.joint).copied().unwrap_or("?"),
            self.deviation_rad.abs(),
            self.tolerance_rad
        )
    }

    fn excess(&self) -> f64 {
        let e = self.deviation_rad.abs() - self.tolerance_rad;
        if e.is_nan() { f64::INFINITY } else { e }
    }
}

/// The joint furthest outside its tolerance (`tolerance_rad[j]`, `None`: not checked) with
/// the arm at `actual` (rad) where it should be at `wanted` (rad); `None` when every checked
/// joint is within it (a deviation equal to the tolerance is within). A position that is not
/// a number is outside every tolerance.
pub fn worst_violation(tolerance_rad: &[Option<f64>], wanted: &[f64], actual: &[f64]) -> Option<Violation> {
    tolerance_rad
        .iter()
        .zip(wanted.iter().zip(actual))
        .enumerate()
        .filter_map(|(joint, (tol, (w, a)))| {
            let tolerance_rad = (*tol)?;
            let deviation_rad = a - w;
            if deviation_rad.abs() <= tolerance_rad {
                None
            } else {
                Some(Violation { joint, deviation_rad, tolerance_rad })
            }
        })
        .max_by(|a, b| a.excess().total_cmp(&b.excess()))
}

/// What becomes of a goal whose trajectory has ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GoalEnd {
    /// Every joint within its goal tolerance: SUCCEEDED.
    Reached,
    /// Not yet, but `goal_time_tolerance` has not passed: look again.
    Waiting,
    /// Still outside once `goal_time_tolerance` has passed: `GOAL_TOLERANCE_VIOLATED`.
    Violated(Violation),
}

/// The goal's end `since_end_s` after its trajectory's end, with the arm at `actual` (rad),
/// its last point at `final_q` (rad) and `goal_time_tolerance_s` of leeway.
pub fn goal_end(
    tolerance_rad: &[Option<f64>],
    final_q: &[f64],
    actual: &[f64],
    since_end_s: f64,
    goal_time_tolerance_s: f64,
) -> GoalEnd {
    match worst_violation(tolerance_rad, final_q, actual) {
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

    #[test]
    fn path_tolerance_violation_names_the_joint_and_the_deviation() {
        let tol = [None, Some(0.01), None, None, None, None];
        let wanted = [0.0; 6];
        let mut actual = [0.0; 6];
        actual[1] = -0.0123;
        actual[0] = 5.0; // J1 has no tolerance
        let v = worst_violation(&tol, &wanted, &actual).unwrap();
        assert_eq!((v.joint, v.tolerance_rad), (1, 0.01));
        assert!((v.deviation_rad + 0.0123).abs() < 1e-12);
        let text = v.describe(&NAMES, "path_tolerance", "desired");
        assert_eq!(text, "J2 is 0.012300 rad from its desired position (path_tolerance 0.01 rad)");
    }

    #[test]
    fn path_tolerance_a_deviation_equal_to_it_is_within_and_nan_is_outside() {
        let tol = [Some(0.5); 6];
        assert_eq!(worst_violation(&tol, &[0.0; 6], &[0.5, -0.5, 0.0, 0.25, 0.0, 0.0]), None);
        let mut actual = [0.0; 6];
        actual[4] = f64::NAN;
        actual[0] = 0.9;
        assert_eq!(worst_violation(&tol, &[0.0; 6], &actual).unwrap().joint, 4);
    }

    #[test]
    fn goal_time_tolerance_waits_until_it_has_passed() {
        let tol = [Some(0.01), None, None, None, None, None];
        let far = [0.1, 0.0, 0.0, 0.0, 0.0, 0.0];
        assert_eq!(goal_end(&tol, &[0.0; 6], &far, 0.2, 0.5), GoalEnd::Waiting);
        assert_eq!(goal_end(&tol, &[0.0; 6], &far, 0.5, 0.5), GoalEnd::Waiting);
        assert!(matches!(goal_end(&tol, &[0.0; 6], &far, 0.51, 0.5), GoalEnd::Violated(v) if v.joint == 0));
        assert_eq!(goal_end(&tol, &[0.0; 6], &[0.005, 0.0, 0.0, 0.0, 0.0, 0.0], 3.0, 0.5), GoalEnd::Reached);
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

    fn positions() -> impl Strategy<Value = Vec<f64>> {
        prop::collection::vec(-3.0f64..3.0, 6)
    }

    proptest! {
        /// A violation is reported exactly when some checked joint is outside its tolerance, and
        /// it is the one furthest outside.
        #[test]
        fn path_tolerance_is_violated_exactly_when_a_checked_joint_is_outside(
            tol in tolerances(), wanted in positions(), actual in positions()
        ) {
            let outside: Vec<(usize, f64)> = (0..6)
                .filter_map(|j| tol[j].map(|t| (j, (actual[j] - wanted[j]).abs() - t)))
                .filter(|(_, e)| *e > 0.0)
                .collect();
            match worst_violation(&tol, &wanted, &actual) {
                None => prop_assert!(outside.is_empty()),
                Some(v) => {
                    let worst = outside.iter().map(|(_, e)| *e).fold(f64::NEG_INFINITY, f64::max);
                    prop_assert!(outside.iter().any(|(j, _)| *j == v.joint));
                    prop_assert_eq!(v.deviation_rad.abs() - v.tolerance_rad, worst);
                    prop_assert_eq!(v.deviation_rad, actual[v.joint] - wanted[v.joint]);
                }
            }
        }

        /// Within the goal time tolerance a goal is never violated; after it, a goal outside its
        /// tolerance always is; inside its tolerance it is reached whenever it is looked at.
        #[test]
        fn goal_tolerance_verdict_follows_the_goal_time_tolerance(
            tol in tolerances(), wanted in positions(), actual in positions(), since in 0.0f64..5.0, gtt in 0.0f64..5.0
        ) {
            let inside = worst_violation(&tol, &wanted, &actual).is_none();
            let end = goal_end(&tol, &wanted, &actual, since, gtt);
            match end {
                GoalEnd::Reached => prop_assert!(inside),
                GoalEnd::Waiting => prop_assert!(!inside && since <= gtt),
                GoalEnd::Violated(_) => prop_assert!(!inside && since > gtt),
            }
        }
    }
}

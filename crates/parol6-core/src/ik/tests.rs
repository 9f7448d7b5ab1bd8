use super::*;
use proptest::prelude::*;
use std::f64::consts::{PI, TAU};

fn in_limits() -> impl Strategy<Value = Vec<f64>> {
    let l = crate::parol6::LIMITS_RAD;
    (l[0].0..l[0].1, l[1].0..l[1].1, l[2].0..l[2].1, l[3].0..l[3].1, l[4].0..l[4].1, l[5].0..l[5].1)
        .prop_map(|(a, b, c, d, e, f)| vec![a, b, c, d, e, f])
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn standby_round_trip_lists_labelled_branches() {
    let m = RobotModel::parol6();
    let q = crate::parol6::standby_rad().to_vec();
    let sols = solve_parol6(&m, &m.tcp_isometry(&q), &q).expect("standby is reachable");
    assert!(dist(&sols[0].joints_rad, &q) < 1e-9, "best first: {:?}", sols[0]);
    let labels: std::collections::HashSet<String> = sols.iter().filter_map(|s| s.branch.map(|b| b.label())).collect();
    assert_eq!(labels.len(), sols.len(), "branches are distinct");
}

#[test]
fn far_target_is_unreachable() {
    let m = RobotModel::parol6();
    let t = crate::kinematics::iso_from_xyz_rpy([1.0, 0.0, 0.3], [0.0, 0.0, 0.0]);
    let seed = crate::parol6::standby_rad();
    assert!(matches!(solve_parol6(&m, &t, &seed), Err(IkError::Unreachable(_))));
    assert!(matches!(solve_numeric(&m, &t, &seed, &NumericIkOptions::default()), Err(IkError::Unreachable(_))));
}

#[test]
fn pose_behind_the_base_breaks_the_limits() {
    let m = RobotModel::parol6();
    // J1 = 180° is outside ±123°, and every other branch needs J2/J3 outside their ranges.
    let mut q = crate::parol6::standby_rad().to_vec();
    q[0] = PI;
    let t = m.tcp_isometry(&q);
    let r = solve_parol6(&m, &t, &crate::parol6::standby_rad());
    assert!(matches!(r, Err(IkError::NoSolutionWithinLimits { .. })), "{r:?}");
}

#[test]
fn bad_input_is_a_typed_error() {
    let m = RobotModel::parol6();
    let t = m.tcp_isometry(&crate::parol6::standby_rad());
    assert!(matches!(solve_parol6(&m, &t, &[0.0; 3]), Err(IkError::InvalidInput(_))));
    assert!(matches!(solve_parol6(&m, &t, &[f64::NAN; 6]), Err(IkError::InvalidInput(_))));
}

#[test]
fn wrist_singularity_keeps_seed_j4() {
    let m = RobotModel::parol6();
    let mut q = crate::parol6::standby_rad().to_vec();
    q[3] = 0.4;
    q[4] = 0.0;
    q[5] = 2.0;
    let sols = solve_parol6(&m, &m.tcp_isometry(&q), &q).expect("reachable");
    assert!(sols[0].singular);
    assert!(dist(&sols[0].joints_rad, &q) < 1e-9, "{:?}", sols[0]);
}

#[test]
fn j6_wrap_prefers_the_seed_side() {
    let m = RobotModel::parol6();
    let mut q = crate::parol6::standby_rad().to_vec();
    q[5] = 0.0;
    let t = m.tcp_isometry(&q);
    let mut seed = q.clone();
    seed[5] = 6.2;
    let sols = solve_parol6(&m, &t, &seed).expect("reachable");
    // J5 = 0: only J4 + J6 is fixed; the split nearest the seed keeps J6 on the seed's side
    // of the turn (near 2π, not near 0) and shares the rest with J4
    let q = &sols[0].joints_rad;
    assert!((q[5] - TAU).abs() < 0.1 && q[5] > 6.2, "{q:?}");
    assert!(((q[3] + q[5]) - TAU).abs() < 1e-9, "{q:?}");
    let (ep, er) = pose_error(&m.tcp_isometry(q), &t);
    assert!(ep < 1e-9 && er < 1e-9);
}

/// Regression (CI, commander_frame): a commander pose of joints at full stretch lay 0.2 µm
/// beyond our reach (the two tables' offsets differ by 0.7 µm), and the only branch left needed
/// J1 = 180°: "no solution within the limits" for joints that are within them.
#[test]
fn a_target_a_fraction_of_a_micrometre_beyond_full_stretch_is_solved_at_the_stretch() {
    let m = RobotModel::parol6();
    let o = m.joints[3].origin.translation;
    // J3 at which the upper arm and the forearm are in line (k = 1)
    let stretched_j3 = (-o.y.atan2(o.x)).rem_euclid(TAU);
    let q = vec![0.0, -112f64.to_radians(), stretched_j3, 0.0, 0.5, 0.01];
    assert!(m.limits.contains(&q), "{q:?}");
    let base = m.tcp_isometry(&q);
    let moved = |dir: usize, sign: f64, by_m: f64| {
        let mut t = base;
        t.translation.vector[dir] += sign * by_m;
        t
    };
    let mut beyond = None;
    for dir in 0..3 {
        for sign in [1.0, -1.0] {
            let t = moved(dir, sign, 0.5e-6);
            let sols = solve_parol6(&m, &t, &q).expect("0.5 µm off full stretch is solved");
            let (ep, er) = pose_error(&m.tcp_isometry(&sols[0].joints_rad), &t);
            assert!(ep <= 0.6e-6 && er < 1e-9, "{dir} {sign}: {ep} m {er} rad");
            assert!(dist(&sols[0].joints_rad, &q) < 0.01, "{dir} {sign}: {:?}", sols[0]);
            if ep > 1e-7 {
                beyond = Some((dir, sign));
            }
        }
    }
    // one of the six moves went outside the reach (else this test proves nothing) ...
    let (dir, sign) = beyond.expect("a move beyond full stretch");
    // ... and 5 µm that way is beyond the slack
    assert!(solve_parol6(&m, &moved(dir, sign, 5e-6), &q).is_err());
}

#[test]
fn numeric_success_rate_on_random_poses() {
    use rand::{Rng, SeedableRng};
    let m = RobotModel::parol6();
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let n = 400;
    let mut ok = 0;
    for _ in 0..n {
        let q: Vec<f64> = crate::parol6::LIMITS_RAD.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
        let t = m.tcp_isometry(&q);
        if let Ok(s) = solve_numeric(&m, &t, &crate::parol6::standby_rad(), &NumericIkOptions::default()) {
            let (ep, er) = pose_error(&m.tcp_isometry(&s.joints_rad), &t);
            assert!(ep < 1e-6 && er < 1e-6);
            ok += 1;
        }
    }
    assert!(ok as f64 >= 0.98 * n as f64, "numeric IK solved {ok}/{n}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    #[test]
    fn closed_form_reproduces_pose_and_contains_generator(q in in_limits(), tool_idx in 0usize..6) {
        let mut m = RobotModel::parol6();
        m.set_tool(crate::parol6::Tool::ALL[tool_idx]);
        let target = m.tcp_isometry(&q);
        let seed = crate::parol6::standby_rad();
        let sols = solve_parol6(&m, &target, &seed);
        prop_assert!(sols.is_ok(), "{:?} for {:?}", sols, q);
        let sols = sols.unwrap_or_default();
        for s in &sols {
            let (ep, er) = pose_error(&m.tcp_isometry(&s.joints_rad), &target);
            prop_assert!(ep < 1e-6 && er < 1e-6, "{:?}: {} {}", s, ep, er);
            prop_assert!(m.limits.contains(&s.joints_rad));
        }
        for w in sols.windows(2) {
            prop_assert!(w[0].distance_to_seed <= w[1].distance_to_seed);
        }
        let near_singular = q[4].abs() < 1e-6;
        if !near_singular {
            // J6's range is a whole turn plus a rounding band: 0 and 2π are both within it, and
            // the solution lists the one nearer the seed (a whole turn apart is the same pose)
            let same_up_to_turns = |a: &[f64]| {
                a.iter().zip(&q).all(|(x, y)| {
                    let d = (x - y).rem_euclid(TAU);
                    d.min(TAU - d) < 1e-6
                })
            };
            prop_assert!(sols.iter().any(|s| same_up_to_turns(&s.joints_rad)), "generator {:?} not in {:?}", q, sols);
        }
    }

    #[test]
    fn numeric_reproduces_pose(q in in_limits()) {
        let m = RobotModel::parol6();
        let target = m.tcp_isometry(&q);
        let s = solve_numeric(&m, &target, &crate::parol6::standby_rad(), &NumericIkOptions::default());
        if let Ok(s) = s {
            let (ep, er) = pose_error(&m.tcp_isometry(&s.joints_rad), &target);
            prop_assert!(ep < 1e-6 && er < 1e-6);
            prop_assert!(m.limits.contains(&s.joints_rad));
        }
    }
}

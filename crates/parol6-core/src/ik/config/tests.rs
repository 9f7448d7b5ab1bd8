use super::*;
use crate::kinematics::iso_from_xyz_rpy;
use crate::parol6::{LIMITS_RAD, standby_rad};
use proptest::prelude::*;
use std::f64::consts::PI;

fn in_limits() -> impl Strategy<Value = Vec<f64>> {
    let l = LIMITS_RAD;
    (l[0].0..l[0].1, l[1].0..l[1].1, l[2].0..l[2].1, l[3].0..l[3].1, l[4].0..l[4].1, l[5].0..l[5].1)
        .prop_map(|(a, b, c, d, e, f)| vec![a, b, c, d, e, f])
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

fn reaches(m: &RobotModel, q: &[f64], target: &Isometry3<f64>) -> bool {
    let (dp, dr) = super::super::pose_error(&m.tcp_isometry(q), target);
    dp < 1e-7 && dr < 1e-7 && m.limits.check(q).is_ok()
}

/// Tool-down poses (the flange's orientation the identity, as G-code `A0 B0 C0` reads), and
/// the same poses turned over (Rx(π)), at the front (+X: the middle of J1's range), the sides
/// (±Y; standby faces +Y) and the back of the workspace.
fn workspace_poses() -> Vec<(&'static str, Isometry3<f64>)> {
    let mut out = Vec::new();
    for (name, p) in [
        ("front", [0.22, 0.0, 0.20]),
        ("front low", [0.25, 0.0, 0.10]),
        ("front left", [0.15, 0.20, 0.15]),
        ("side +Y", [0.0, 0.22, 0.20]),
        ("side -Y", [0.0, -0.22, 0.20]),
        ("back left", [-0.1, 0.2, 0.15]),
        ("back right", [-0.1, -0.2, 0.15]),
        ("behind", [-0.22, 0.0, 0.20]),
    ] {
        out.push((name, iso_from_xyz_rpy(p, [0.0, 0.0, 0.0])));
        out.push((name, iso_from_xyz_rpy(p, [PI, 0.0, 0.0])));
    }
    out
}

#[test]
fn labels_parse_back() {
    for s in [ShoulderBranch::Front, ShoulderBranch::Back] {
        for e in [ElbowBranch::Up, ElbowBranch::Down] {
            for w in [WristBranch::NoFlip, WristBranch::Flip] {
                let b = Branch { shoulder: s, elbow: e, wrist: w };
                assert_eq!(b.label().parse::<Branch>(), Ok(b));
            }
        }
    }
    assert_eq!(" Front / UP / noflip ".parse::<Branch>().map(|b| b.label()), Ok("front/up/no-flip".to_string()));
    for bad in ["", "front/up", "front/up/no-flip/x", "left/up/flip", "front/sideways/flip", "front/up/maybe"] {
        let e = bad.parse::<Branch>().expect_err(bad);
        assert!(e.to_string().contains("front/up/no-flip"), "{e}");
    }
}

#[test]
fn standby_is_on_the_wrist_border() {
    let m = RobotModel::parol6();
    let q = standby_rad();
    let rule = ConfigRule::of_start(&m, &q);
    assert!(rule.shoulder.is_some() && rule.elbow.is_some());
    assert_eq!(rule.wrist, None, "J5 = 0: either wrist");
    assert!(rule.to_string().ends_with("/any"), "{rule}");
    // a little way off the border the wrist is fixed
    let mut off = q.to_vec();
    off[4] = -0.2;
    let sol = solve_nearest(&m, &m.tcp_isometry(&off), &off, rule).expect("reachable");
    let settled = rule.settled_by(&sol);
    assert_eq!(settled.wrist, Some(WristBranch::Flip));
    assert!(settled.is_fixed());
}

/// Regression (issue 28): `G28` then `G0 X220 Y0 Z200 A0 B0 C0` was refused ("front/down/no-flip
/// branch needs J4 = 180.00°") because the joint move kept standby's branch label.
#[test]
fn tool_down_poses_are_reached_from_standby() {
    let m = RobotModel::parol6();
    let q0 = standby_rad();
    for (name, target) in workspace_poses() {
        let any = super::super::solve_parol6(&m, &target, &q0);
        let nearest = solve_nearest(&m, &target, &q0, ConfigRule::ANY);
        match any {
            Ok(all) => {
                let best = nearest.unwrap_or_else(|e| panic!("{name}: {e}"));
                assert!(reaches(&m, &best.joints_rad, &target), "{name}: {best:?}");
                let d = distance(&best.joints_rad, &q0);
                for s in &all {
                    assert!(d <= distance(&s.joints_rad, &q0) + 1e-12, "{name}: not the nearest");
                }
            }
            Err(e) => assert!(nearest.is_err(), "{name}: the closed form says {e}"),
        }
    }
    // the pose (in front: J1 = 0 points along +X), both sides and the back corners
    // within J1's ±123° must be reachable
    for p in [[0.22, 0.0, 0.20], [0.0, 0.22, 0.20], [0.0, -0.22, 0.20], [-0.1, 0.2, 0.15], [-0.1, -0.2, 0.15]] {
        let t = iso_from_xyz_rpy(p, [0.0, 0.0, 0.0]);
        let sol = solve_nearest(&m, &t, &q0, ConfigRule::ANY).unwrap_or_else(|e| panic!("{p:?}: {e}"));
        assert!(reaches(&m, &sol.joints_rad, &t));
    }
}

#[test]
fn a_named_configuration_is_kept_or_refused_naming_the_others() {
    let m = RobotModel::parol6();
    let q0 = standby_rad();
    let target = iso_from_xyz_rpy([0.22, 0.0, 0.20], [0.0, 0.0, 0.0]);
    let all = super::super::solve_parol6(&m, &target, &q0).expect("reachable");
    for s in &all {
        let b = s.branch.expect("closed form");
        let got = solve_nearest(&m, &target, &q0, ConfigRule::exactly(b)).expect("its own branch");
        assert!(ConfigRule::exactly(b).admits(&got));
        assert!(reaches(&m, &got.joints_rad, &target));
    }
    let reached: std::collections::HashSet<String> = all.iter().filter_map(|s| s.branch.map(|b| b.label())).collect();
    for label in ["front/up/no-flip", "front/up/flip", "back/down/flip", "back/up/no-flip", "front/down/flip"] {
        if reached.contains(label) {
            continue;
        }
        let b: Branch = label.parse().expect("label");
        match solve_nearest(&m, &target, &q0, ConfigRule::exactly(b)) {
            Err(IkError::OtherConfiguration { wanted, reachable }) => {
                assert_eq!(wanted, label);
                assert!(!reachable.is_empty());
                let msg = IkError::OtherConfiguration { wanted, reachable: reachable.clone() }.to_string();
                assert!(msg.contains(&reachable[0]), "{msg}");
            }
            other => panic!("{label}: {other:?}"),
        }
    }
}

/// At J5 = 0 only J4 + J6 is fixed: the split nearest the seed is taken, not J4 = seed.
#[test]
fn singular_wrist_takes_the_nearest_split() {
    let m = RobotModel::parol6();
    let q0 = standby_rad();
    let mut goal = q0.to_vec();
    goal[0] = 0.3;
    goal[3] = 0.4;
    goal[4] = 0.0;
    goal[5] = q0[5] - 0.4 + 1.0;
    let target = m.tcp_isometry(&goal);
    let sol = solve_nearest(&m, &target, &q0, ConfigRule::ANY).expect("reachable");
    assert!(reaches(&m, &sol.joints_rad, &target));
    // J4 + J6 moved by 1 rad in all: shared equally between them
    assert!((sol.joints_rad[3] - q0[3] - 0.5).abs() < 1e-6, "{:?}", sol.joints_rad);
    assert!((sol.joints_rad[5] - q0[5] - 0.5).abs() < 1e-6, "{:?}", sol.joints_rad);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// Any reachable pose (the FK of joints within the limits) is accepted from any start
    /// within the limits, and the solution is no farther from the start than the joints that
    /// made the pose.
    #[test]
    fn random_reachable_poses_take_the_nearest_solution(goal in in_limits(), start in in_limits()) {
        let m = RobotModel::parol6();
        let target = m.tcp_isometry(&goal);
        let sol = solve_nearest(&m, &target, &start, ConfigRule::ANY);
        prop_assert!(sol.is_ok(), "{:?} from {:?}: {:?}", goal, start, sol);
        let sol = sol.expect("checked");
        prop_assert!(reaches(&m, &sol.joints_rad, &target));
        prop_assert!(
            distance(&sol.joints_rad, &start) <= distance(&goal, &start) + 1e-6,
            "{:?} is farther from {:?} than {:?}", sol.joints_rad, start, goal
        );
        // the configuration the goal is in accepts it too
        if let Some(b) = configuration_of(&m, &goal) {
            let same = solve_nearest(&m, &target, &start, ConfigRule::exactly(b));
            prop_assert!(same.is_ok(), "{}: {:?}", b.label(), same);
        }
    }
}

/// What [`configuration_of`] answered before it tried one configuration at a time: all eight
/// solved together, the nearest that reproduces the joints.
fn configuration_of_all_eight(m: &RobotModel, q: &[f64]) -> Option<Branch> {
    let pose = m.tcp_isometry(q);
    let sols = super::super::solve_parol6(m, &pose, q).ok()?;
    sols.into_iter().find(|s| s.distance_to_seed < SAME_JOINTS_RAD).and_then(|s| s.branch)
}

/// Joints on and near every border between configurations: the wrist (J5 = 0, and a hair off
/// it), full stretch (the CI case of `commander_frame`) and the shoulder axis.
fn border_joints() -> Vec<Vec<f64>> {
    let stretch = vec![0.0, -112.04f64.to_radians(), 256.22f64.to_radians(), 0.0, 0.0, 0.497f64.to_radians()];
    let mut out = vec![standby_rad().to_vec(), stretch.clone()];
    for q5 in [0.0, 1e-7, -1e-7, 1e-5, -1e-5, 0.3, -0.3] {
        let mut q = standby_rad().to_vec();
        q[4] = q5;
        out.push(q);
        let mut s = stretch.clone();
        s[4] = q5;
        out.push(s);
    }
    out
}

/// One configuration at a time (first the one found last) gives what solving all eight gave,
/// on the borders and after a different configuration was found last.
#[test]
fn configuration_of_one_at_a_time_agrees_with_all_eight_on_the_borders() {
    let m = RobotModel::parol6();
    let joints = border_joints();
    // each pair in both orders: every answer found after every other one
    for a in &joints {
        for b in &joints {
            assert_eq!(configuration_of(&m, a), configuration_of_all_eight(&m, a), "{a:?}");
            assert_eq!(configuration_of(&m, b), configuration_of_all_eight(&m, b), "{b:?} after {a:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]
    /// Anywhere within the limits, after any other joints were asked first.
    #[test]
    fn configuration_of_one_at_a_time_agrees_with_all_eight(q in in_limits(), before in in_limits()) {
        let m = RobotModel::parol6();
        prop_assert_eq!(configuration_of(&m, &before), configuration_of_all_eight(&m, &before));
        prop_assert_eq!(configuration_of(&m, &q), configuration_of_all_eight(&m, &q));
    }
}

/// [`solve_nearest`] as it was before it stopped building the list: the closed form's whole
/// list (sorted nearest the seed first), then the first solution the rule admits.
fn nearest_from_the_list(
    m: &RobotModel,
    target: &Isometry3<f64>,
    seed: &[f64],
    rule: ConfigRule,
) -> Option<IkSolution> {
    let sols = super::super::solve_parol6_in(m, target, seed, rule.branch()).ok()?;
    sols.into_iter().find(|s| rule.admits(s))
}

/// Every rule: any configuration, each of the eight, each with the wrist left free.
fn every_rule() -> Vec<ConfigRule> {
    let mut rules = vec![ConfigRule::ANY];
    for shoulder in [ShoulderBranch::Front, ShoulderBranch::Back] {
        for elbow in [ElbowBranch::Up, ElbowBranch::Down] {
            for wrist in [WristBranch::NoFlip, WristBranch::Flip] {
                let rule = ConfigRule::exactly(Branch { shoulder, elbow, wrist });
                rules.push(rule);
                rules.push(ConfigRule { wrist: None, ..rule });
            }
        }
    }
    rules
}

/// The same solution, bit for bit, as the list gave (or none where it gave none), for `q`'s
/// pose from seeds at `q`, near it and at `other`.
fn assert_nearest_as_from_the_list(m: &RobotModel, q: &[f64], other: &[f64]) {
    let target = m.tcp_isometry(q);
    let near: Vec<f64> = q.iter().enumerate().map(|(i, v)| v + 0.01 * (i as f64 - 2.5)).collect();
    for seed in [q, near.as_slice(), other] {
        for rule in every_rule() {
            let fast = solve_nearest(m, &target, seed, rule).ok();
            assert_eq!(fast, nearest_from_the_list(m, &target, seed, rule), "{q:?} from {seed:?} in {rule}");
        }
    }
}

/// On the borders between configurations (ties and singular branches included).
#[test]
fn solve_nearest_picks_what_the_sorted_list_gave_on_the_borders() {
    let m = RobotModel::parol6();
    let joints = border_joints();
    for q in &joints {
        for other in &joints {
            assert_nearest_as_from_the_list(&m, q, other);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// Anywhere within the limits.
    #[test]
    fn solve_nearest_picks_what_the_sorted_list_gave(q in in_limits(), other in in_limits()) {
        assert_nearest_as_from_the_list(&RobotModel::parol6(), &q, &other);
    }
}

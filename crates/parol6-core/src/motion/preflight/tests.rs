use super::*;
use crate::profile::{JointMove, ProfileKind};
use crate::scene::KeepOutShape;
use proptest::prelude::*;

fn deg(q: [f64; 6]) -> Vec<f64> {
    q.iter().map(|d| d.to_radians()).collect()
}

fn parol6() -> (RobotModel, MotionCaps) {
    let model = RobotModel::parol6();
    let caps = MotionCaps::of(&model);
    (model, caps)
}

/// A profiled joint move sampled every 10 ms.
fn joint_traj(from: &[f64], to: &[f64], fraction: f64) -> Arc<SampledTrajectory> {
    let mv = JointMove::parol6(from, to, fraction, ProfileKind::JerkLimited).expect("plans");
    let n = (mv.duration_s() / 0.01).ceil() as usize;
    Arc::new(SampledTrajectory::new(0.01, (0..=n).map(|k| mv.sample(k as f64 * 0.01).q).collect()))
}

fn planned(index: usize, kind: MoveKind, trajectory: Arc<SampledTrajectory>) -> PlannedMove {
    PlannedMove { index, line: 10 + index, label: format!("move {index}"), kind, trajectory }
}

fn station(i: usize) -> Vec<f64> {
    deg(bench_program::STATIONS_DEG[i])
}

#[test]
fn a_clean_move_has_no_issues() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &bench_program::bench_scene()).expect("builds");
    let traj = joint_traj(&station(0), &station(3), 0.8);
    let r = pf.check(&[planned(0, MoveKind::Joint, traj.clone())]);
    assert!(r.issues.is_empty(), "{:#?}", r.issues);
    assert!(r.ok());
    assert_eq!(r.moves, 1);
    assert!((r.duration_s - traj.duration_s()).abs() < 1e-12);
    assert!(r.path.len() > 10 && r.path.iter().all(|p| p.status == CheckStatus::Ok));
    // the path runs from start to end, points at most about the spacing apart
    let first = model.tcp_isometry(&station(0)).translation.vector;
    let last = model.tcp_isometry(&station(3)).translation.vector;
    let p0 = r.path[0].tcp_m;
    let pn = r.path[r.path.len() - 1].tcp_m;
    assert!((nalgebra::Vector3::from(p0) - first).norm() < 1e-9);
    assert!((nalgebra::Vector3::from(pn) - last).norm() < 1e-9);
    for w in r.path.windows(2) {
        let d = (nalgebra::Vector3::from(w[1].tcp_m) - nalgebra::Vector3::from(w[0].tcp_m)).norm();
        assert!(d < 2.0 * PATH_SPACING_M, "{d}");
    }
}

#[test]
fn the_bench_program_is_clean() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &bench_program::bench_scene()).expect("builds");
    let program = bench_program::bench_program(&model, 40).expect("plans");
    assert_eq!(program.len(), 40);
    let r = pf.check(&program);
    assert!(r.issues.is_empty(), "{:#?}", r.issues);
    assert!(bench_program::bench_program(&RobotModel::parol6_with_tool(crate::Tool::None), 3).is_ok());
}

/// First time along `traj` at which `pf`'s pieces touch anything, by brute force (0.05 ms steps).
fn first_contact_s(pf: &Preflight, traj: &SampledTrajectory) -> Option<f64> {
    let mut c = clearance::Clearance::default();
    let steps = (traj.duration_s() / 5e-5).ceil() as usize;
    (0..=steps).map(|k| k as f64 * 5e-5).find(|&t| {
        pf.world.evaluate(&pf.model.link_poses(&traj.sample(t).q), &mut c);
        !c.contacts.is_empty()
    })
}

#[test]
fn a_move_through_a_keep_out_box_names_link_shape_and_place() {
    let (model, caps) = parol6();
    let traj = joint_traj(&station(0), &station(3), 0.8);
    // a 40 mm box where the wrist (L5) is half way through the move
    let mid = traj.sample(0.5 * traj.duration_s()).q;
    let l5 = model.link_poses(&mid)[model.link_index("L5").expect("L5")].translation.vector * 1000.0;
    let fixture = KeepOut::new(
        "fixture",
        KeepOutShape::Box { center_mm: [l5.x, l5.y, l5.z], size_mm: [40.0; 3], rpy_deg: [0.0, 0.0, 20.0] },
    );
    let pf = Preflight::new(&model, &caps, &[fixture]).expect("builds");
    let r = pf.check(&[planned(0, MoveKind::Joint, traj.clone())]);
    assert!(!r.ok());
    let hits: Vec<_> = r.issues.iter().filter(|i| matches!(&i.kind, IssueKind::KeepOut { .. })).collect();
    assert!(!hits.is_empty(), "{:#?}", r.issues);
    let first = hits[0];
    let IssueKind::KeepOut { link, shape } = &first.kind else { unreachable!() };
    assert_eq!(shape, "fixture");
    assert!(["L4", "L5", "L6"].contains(&link.as_str()), "{link}");
    assert_eq!((first.move_index, first.line, first.severity), (0, 10, Severity::Error));
    assert!(first.message.contains(link.as_str()) && first.message.contains("'fixture'"), "{}", first.message);
    assert!(first.message.contains("line 10") && first.message.contains("TCP ("), "{}", first.message);
    // the TCP given is the TCP at that time
    let tcp = model.tcp_isometry(&traj.sample(first.t_s).q).translation.vector * 1000.0;
    assert!((nalgebra::Vector3::from(first.tcp_mm) - tcp).norm() < 1e-6);
    // found where it really starts: no later than 1 mrad of joint travel after the truth
    let truth = first_contact_s(&pf, &traj).expect("touches");
    let earliest =
        r.issues.iter().filter(|i| i.kind != IssueKind::Singularity).map(|i| i.t_s).fold(f64::INFINITY, f64::min);
    assert!(earliest >= truth - 1e-4 && earliest <= truth + 1e-3 / caps.speed_rad_s[0] + 1e-4, "{earliest} vs {truth}");
    // each link makes one issue (consecutive samples collapse), and the path turns red there
    let mut links: Vec<&str> =
        hits.iter().map(|i| if let IssueKind::KeepOut { link, .. } = &i.kind { link.as_str() } else { "" }).collect();
    let n = links.len();
    links.dedup();
    assert_eq!(links.len(), n, "{links:?}");
    assert!(r.path.iter().any(|p| p.status == CheckStatus::Error));
    assert!(r.path.first().is_some_and(|p| p.status == CheckStatus::Ok));
    assert!(r.path.last().is_some_and(|p| p.status == CheckStatus::Ok));
}

#[test]
fn a_move_into_the_floor_is_an_error() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let traj = joint_traj(&station(2), &deg([90.0, -10.0, 180.0, 0.0, 45.0, 180.0]), 0.5);
    let r = pf.check(&[planned(3, MoveKind::Joint, traj.clone())]);
    let ground: Vec<_> = r.issues.iter().filter(|i| matches!(i.kind, IssueKind::Ground { .. })).collect();
    assert!(!ground.is_empty(), "{:#?}", r.issues);
    assert!(ground[0].message.contains("below the floor") && ground[0].message.contains("move 3"));
    let truth = first_contact_s(&pf, &traj).expect("touches the floor");
    assert!((ground[0].t_s - truth).abs() < 2e-3, "{} vs {truth}", ground[0].t_s);
}

/// The manual motions' floor rule (`CollisionGuard::floor_contact`) is pre-flight's: a move to
/// the pose of trial 12 n-d is refused by both, naming the same link in the same words.
#[test]
fn preflight_and_the_manual_floor_rule_name_the_same_link() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let goal = crate::collision::floor_tests::under_the_floor();
    let r = pf.check(&[planned(1, MoveKind::Joint, joint_traj(&station(2), &goal, 0.5))]);
    let c = crate::collision::CollisionGuard::new(&model).floor_contact(&model, &goal).expect("below the floor");
    let named = |i: &&PreflightIssue| matches!(&i.kind, IssueKind::Ground { link } if *link == c.link);
    let issue = r.issues.iter().find(named).unwrap_or_else(|| panic!("{c} not in {:#?}", r.issues));
    assert!(issue.message.contains(&crate::collision::below_floor_text(&c.link)), "{}", issue.message);
}

#[test]
fn a_joint_beyond_its_limit_is_one_error() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let mut a = station(1);
    a[1] = (-20f64).to_radians();
    let mut b = a.clone();
    b[1] = 0.0; // J2's upper limit is −3.375°
    let r = pf.check(&[planned(0, MoveKind::Joint, joint_traj(&a, &b, 0.5))]);
    let limits: Vec<_> = r.issues.iter().filter(|i| matches!(i.kind, IssueKind::JointLimit { .. })).collect();
    assert_eq!(limits.len(), 1, "{:#?}", r.issues);
    assert_eq!(limits[0].kind, IssueKind::JointLimit { joint: 2 });
    assert!(limits[0].message.contains("J2") && limits[0].message.contains("upper limit"), "{}", limits[0].message);
    assert!(!r.ok());
}

#[test]
fn j4_and_j6_together_can_overrun_motor_6() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    // J4 at 1.0 rad/s and J6 at 2.4 rad/s: each under its cap (2.45, 2.65 rad/s), but motor 6
    // turns at (2.4·10 + 1.0·4) / (2π/6400) ≈ 28 521 steps/s > 27 000
    assert!(1.0 < caps.speed_rad_s[3] && 2.4 < caps.speed_rad_s[5]);
    assert!(walk::parol6_motor6_steps_s(1.0, 2.4) > 27_000.0);
    let q0 = station(1);
    let samples = (0..=20)
        .map(|k| {
            let mut q = q0.clone();
            q[3] += 0.01 * k as f64;
            q[5] += 0.024 * k as f64;
            q
        })
        .collect();
    let r = pf.check(&[planned(0, MoveKind::Joint, Arc::new(SampledTrajectory::new(0.01, samples)))]);
    assert_eq!(r.issues.len(), 1, "{:#?}", r.issues);
    assert_eq!(r.issues[0].kind, IssueKind::MotorSpeed { motor: 6 });
    assert!(r.issues[0].message.contains("motor 6"), "{}", r.issues[0].message);
    // slower J4: fine
    let samples =
        (0..=20).map(|k| [q0[0], q0[1], q0[2], q0[3] + 0.002 * k as f64, q0[4], q0[5] + 0.024 * k as f64].to_vec());
    let r = pf.check(&[planned(0, MoveKind::Joint, Arc::new(SampledTrajectory::new(0.01, samples.collect())))]);
    assert!(r.issues.is_empty(), "{:#?}", r.issues);
}

#[test]
fn the_motor_6_coupling_is_only_the_parol6s() {
    let (mut model, caps) = parol6();
    model.is_parol6 = false;
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let q0 = station(1);
    let samples =
        (0..=20).map(|k| [q0[0], q0[1], q0[2], q0[3] + 0.01 * k as f64, q0[4], q0[5] + 0.024 * k as f64].to_vec());
    let r = pf.check(&[planned(0, MoveKind::Joint, Arc::new(SampledTrajectory::new(0.01, samples.collect())))]);
    assert!(r.issues.is_empty(), "{:#?}", r.issues);
}

#[test]
fn joint_speed_over_the_cap_is_an_error() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let q0 = station(1);
    let samples = (0..=10).map(|k| [q0[0] + 0.03 * k as f64, q0[1], q0[2], q0[3], q0[4], q0[5]].to_vec());
    let r = pf.check(&[planned(0, MoveKind::Joint, Arc::new(SampledTrajectory::new(0.01, samples.collect())))]);
    assert_eq!(r.issues.len(), 1, "{:#?}", r.issues);
    assert_eq!(r.issues[0].kind, IssueKind::JointSpeed { joint: 1 });
    assert!((r.issues[0].t_s - 0.01).abs() < 1e-12);
}

#[test]
fn thresholds_match_the_parol6_wrist() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let reference = pf.reference_manipulability().expect("not singular everywhere");
    for i in 0..4 {
        let ratio_at = |j5_deg: f64| {
            let mut q = station(i);
            q[4] = j5_deg.to_radians();
            singularity::manipulability(&model, &q) / reference
        };
        assert!(ratio_at(4.0) < SINGULARITY_WARN_RATIO && ratio_at(7.0) > SINGULARITY_WARN_RATIO, "station {i}");
        assert!(ratio_at(0.4) < SINGULARITY_ERROR_RATIO && ratio_at(0.7) > SINGULARITY_ERROR_RATIO, "station {i}");
        assert!(ratio_at(40.0) > 1.0);
    }
}

#[test]
fn a_joint_move_through_the_wrist_singularity_warns() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let mut a = station(1);
    a[4] = -0.3;
    let mut b = a.clone();
    b[4] = 0.3;
    let traj = joint_traj(&a, &b, 0.5);
    let r = pf.check(&[planned(0, MoveKind::Joint, traj.clone())]);
    assert_eq!(r.issues.len(), 1, "{:#?}", r.issues);
    let w = &r.issues[0];
    assert_eq!((w.kind.clone(), w.severity), (IssueKind::Singularity, Severity::Warning));
    assert!(r.ok(), "a warning does not stop the program");
    let j5 = traj.sample(w.t_s).q[4];
    assert!(j5.abs() < 6f64.to_radians() && j5 < 0.0, "{j5}");
    assert!(r.path.iter().any(|p| p.status == CheckStatus::Warning));
    // the same samples on a TCP path: an error at the singular pose
    let r = pf.check(&[planned(0, MoveKind::Cartesian, traj)]);
    assert!(
        r.issues.iter().any(|i| i.kind == IssueKind::Singularity && i.severity == Severity::Error),
        "{:#?}",
        r.issues
    );
}

#[test]
fn unusable_trajectories_are_errors_not_panics() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let q = station(0);
    let cases = [
        SampledTrajectory::new(0.01, vec![q.clone(), q[..5].to_vec()]),
        SampledTrajectory::new(0.01, vec![q.clone(), vec![f64::NAN; 6]]),
        SampledTrajectory::new(0.01, vec![]),
        SampledTrajectory::new(0.0, vec![q.clone(), q.clone()]),
        SampledTrajectory::new(f64::NAN, vec![q.clone()]),
    ];
    for traj in cases {
        let r = pf.check(&[planned(0, MoveKind::Joint, Arc::new(traj.clone()))]);
        assert_eq!(r.issues.len(), 1, "{traj:?}: {:#?}", r.issues);
        assert_eq!(r.issues[0].kind, IssueKind::InvalidTrajectory);
        assert!(!r.ok() && r.duration_s.is_finite());
    }
    let r = pf.check(&[planned(
        0,
        MoveKind::Joint,
        Arc::new(SampledTrajectory::new(0.01, vec![q.clone(), q[..5].to_vec()])),
    )]);
    assert!(r.issues[0].message.contains("sample 1 has 5 joint values"), "{}", r.issues[0].message);
}

#[test]
fn a_move_must_start_where_the_previous_one_ends() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let first = joint_traj(&station(0), &station(1), 0.8);
    let second = joint_traj(&station(2), &station(3), 0.8);
    let r = pf.check(&[planned(0, MoveKind::Joint, first.clone()), planned(1, MoveKind::Joint, second.clone())]);
    assert_eq!(r.issues.len(), 1, "{:#?}", r.issues);
    assert_eq!((r.issues[0].move_index, r.issues[0].kind.clone()), (1, IssueKind::Discontinuity { joint: 1 }));
    let joined = joint_traj(&station(1), &station(2), 0.8);
    let r = pf.check(&[planned(0, MoveKind::Joint, first), planned(1, MoveKind::Joint, joined)]);
    assert!(r.ok() && r.issues.is_empty(), "{:#?}", r.issues);
    assert_eq!(r.moves, 2);
}

#[test]
fn bad_scenes_and_caps_are_refused() {
    let (model, caps) = parol6();
    let bad = KeepOut::new("post", KeepOutShape::Sphere { center_mm: [0.0; 3], radius_mm: -1.0 });
    let e = Preflight::new(&model, &caps, &[bad]).expect_err("negative radius").to_string();
    assert!(e.contains("'post'") && e.contains("radius_mm"), "{e}");
    let mut short = caps.clone();
    short.speed_rad_s.pop();
    assert!(Preflight::new(&model, &short, &[]).is_err());
    let mut zero = caps;
    zero.speed_rad_s[2] = 0.0;
    assert!(Preflight::new(&model, &zero, &[]).expect_err("zero cap").to_string().contains("joint 3"));
}

#[test]
fn issues_serialise_with_their_kind() {
    let (model, caps) = parol6();
    let pf = Preflight::new(&model, &caps, &[]).expect("builds");
    let r = pf.check(&[planned(0, MoveKind::Joint, Arc::new(SampledTrajectory::new(0.01, vec![vec![0.0; 3]])))]);
    let json = serde_json::to_value(&r).expect("serialises");
    assert_eq!(json["issues"][0]["kind"]["kind"], "invalid_trajectory");
    assert_eq!(json["issues"][0]["severity"], "error");
    let back: PreflightReport = serde_json::from_value(json).expect("reads back");
    assert_eq!(back, r);
}

proptest! {
    /// The reach bound holds: no point within a piece's bounding sphere moves more than
    /// `Σ reach × |Δq|` along the straight joint-space line.
    #[test]
    fn pieces_move_no_more_than_their_reach_allows(
        q in proptest::collection::vec(-3.0f64..3.0, 6),
        dq in proptest::collection::vec(-0.2f64..0.2, 6),
    ) {
        let (model, caps) = parol6();
        let pf = Preflight::new(&model, &caps, &[]).expect("builds");
        let q2: Vec<f64> = q.iter().zip(&dq).map(|(a, d)| a + d).collect();
        let (pa, pb) = (model.link_poses(&q), model.link_poses(&q2));
        let guard = crate::collision::CollisionGuard::new(&model);
        for (p, (link, local, shape)) in guard.pieces().enumerate() {
            let sphere = shape.compute_local_bounding_sphere();
            let c = sphere.center();
            let r = f64::from(sphere.radius());
            let bound: f64 = pf.world.reach_m(p).iter().zip(&dq).map(|(reach, d)| reach * d.abs()).sum();
            for off in [[0.0, 0.0, 0.0], [r, 0.0, 0.0], [0.0, -r, 0.0], [0.0, 0.0, r]] {
                let local_pt = nalgebra::Point3::new(f64::from(c.x) + off[0], f64::from(c.y) + off[1], f64::from(c.z) + off[2]);
                let a = pa[link] * local * local_pt;
                let b = pb[link] * local * local_pt;
                prop_assert!((b - a).norm() <= bound + 1e-9, "piece {p}: moved {} > bound {bound}", (b - a).norm());
            }
        }
        let tcp_bound: f64 = pf.tcp_reach_m.iter().zip(&dq).map(|(reach, d)| reach * d.abs()).sum();
        let moved = (model.tcp_isometry(&q2).translation.vector - model.tcp_isometry(&q).translation.vector).norm();
        prop_assert!(moved <= tcp_bound + 1e-9);
    }
}

fn garbage_move() -> impl Strategy<Value = (f64, Vec<Vec<f64>>, bool)> {
    let sample = prop_oneof![
        9 => proptest::collection::vec(-10.0f64..10.0, 6),
        1 => proptest::collection::vec(-10.0f64..10.0, 0..9),
    ];
    (prop_oneof![Just(0.01), 0.0005f64..0.1], proptest::collection::vec(sample, 0..12), any::<bool>())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn check_never_panics(moves in proptest::collection::vec(garbage_move(), 1..4), box_mm in -400.0f64..400.0) {
        let (model, caps) = parol6();
        let scene = [KeepOut::new("box", KeepOutShape::Box { center_mm: [box_mm, 150.0, 150.0], size_mm: [80.0; 3], rpy_deg: [0.0, 10.0, 0.0] })];
        let pf = Preflight::new(&model, &caps, &scene).expect("builds");
        let planned: Vec<PlannedMove> = moves
            .iter()
            .enumerate()
            .map(|(i, (dt, q, cart))| {
                let kind = if *cart { MoveKind::Cartesian } else { MoveKind::Joint };
                PlannedMove { index: i, line: i + 1, label: "garbage".into(), kind, trajectory: Arc::new(SampledTrajectory::new(*dt, q.clone())) }
            })
            .collect();
        let r = pf.check(&planned);
        prop_assert_eq!(r.moves, moves.len());
        let malformed = moves.iter().any(|(_, q, _)| q.is_empty() || q.iter().any(|s| s.len() != 6));
        if malformed {
            prop_assert!(!r.ok());
            prop_assert!(r.issues.iter().any(|i| i.kind == IssueKind::InvalidTrajectory));
        }
        for i in &r.issues {
            prop_assert!(i.t_s.is_finite() && i.tcp_mm.iter().all(|v| v.is_finite()));
            prop_assert!(!i.message.is_empty());
        }
    }
}

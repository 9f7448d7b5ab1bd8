//! Unit tests of the simulation core (deterministic: no thread, no wall-clock assertions).

use crate::limits::LimitViolation;
use crate::motion::MotionCommand;
use crate::profile::{JointMove, ProfileKind};
use rand::{Rng, SeedableRng};

use super::*;
use crate::collision;
use crate::limits::LimitSide;
use crate::parol6::standby_rad;

pub(super) fn parol6() -> RobotModel {
    RobotModel::parol6()
}

pub(super) fn sim(mode: SimMode) -> Simulation {
    let config = SimConfig { mode, ..SimConfig::default() };
    Simulation::new(parol6(), config).expect("embedded model builds")
}

/// Ideal motors (`ServoModel::Ideal`): for the tests of the planner's setpoint through the
/// simulation (exact profiles, jogs, stops), which the firmware servo's 25 ms lag and whole steps
/// would blur; the firmware servo is tested in `motion::stepper` and `tests/servo_tracking.rs`.
pub(super) fn ideal_sim(mode: SimMode) -> Simulation {
    let config = SimConfig { mode, servo: super::ServoModel::Ideal, ..SimConfig::default() };
    Simulation::new(parol6(), config).expect("embedded model builds")
}

pub(super) fn run_s(sim: &mut Simulation, seconds: f64) {
    let steps = (seconds / sim.dt_s()).round() as usize;
    for _ in 0..steps {
        sim.step();
    }
}

pub(super) fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

pub(super) fn random_free_config(
    model: &RobotModel,
    guard: &CollisionGuard,
    rng: &mut impl Rng,
    margin: f64,
) -> Vec<f64> {
    loop {
        let q: Vec<f64> = model.limits.iter().map(|l| rng.random_range(l.min + margin..=l.max - margin)).collect();
        if guard.check(model, &q).is_none() {
            return q;
        }
    }
}

/// A configuration where L6 hits L1 (found by sampling the joint space).
const Q_L1_L6: [f64; 6] = [-0.3594746, -0.3803705, 1.8966812, -0.1275214, -1.4898114, 2.1549427];
/// A configuration where L5 and L6 hit the base.
const Q_BASE_L5: [f64; 6] = [0.6721034, -0.2145956, 1.9471948, 0.7005027, -1.2785315, 2.0326010];
/// A configuration where the wrist is below the ground plane.
const Q_GROUND: [f64; 6] = [1.2781498, -0.0653485, 2.6772428, 0.3309554, 0.6916926, 1.1726027];

// ---------------------------------------------------------------- multibody

#[test]
fn multibody_has_one_dof_per_joint_and_colliders() {
    let p = Physics::build(&parol6(), 1e-3).expect("builds");
    assert_eq!(p.ndofs(), 6);
    assert_eq!(p.collider_count(), parol6().links.iter().map(|l| l.collisions.len()).sum::<usize>());
}

#[test]
fn multibody_limits_are_the_model_limits_j6_included() {
    let model = parol6();
    let p = Physics::build(&model, 1e-3).expect("builds");
    let lims = p.multibody_limits();
    assert_eq!(lims.len(), 6);
    for (l, m) in model.limits.iter().zip(&lims) {
        let [lo, hi] = m.unwrap_or_else(|| panic!("joint {} has no multibody limit", l.name));
        assert!((lo - l.min).abs() < 1e-6 && (hi - l.max).abs() < 1e-6, "{}: {lo}..{hi}", l.name);
    }
}

#[test]
fn multibody_joint_values_equal_the_model_kinematics() {
    let model = parol6();
    let mut p = Physics::build(&model, 1e-3).expect("builds");
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    for _ in 0..50 {
        let q: Vec<f64> = model.limits.iter().map(|l| rng.random_range(l.min..=l.max)).collect();
        p.teleport(&q);
        let (mut q_read, mut qd) = (vec![0.0; 6], vec![0.0; 6]);
        p.read_state(&mut q_read, &mut qd);
        assert!(max_abs_diff(&q, &q_read) < 1e-6, "{q:?} vs {q_read:?}");
        let frames = model.chain_frames(&q);
        for (k, f) in frames.iter().enumerate() {
            let b = p.body_pose(k).expect("body");
            assert!((b.translation.vector - f.translation.vector).norm() < 1e-5, "body {k} position");
            assert!(b.rotation.angle_to(&f.rotation) < 1e-5, "body {k} rotation");
        }
    }
}

/// Motors alone (no feedforward) hold every sampled configuration within 1 mrad.
#[test]
fn motors_alone_hold_against_gravity_within_1_mrad() {
    let model = parol6();
    let guard = CollisionGuard::new(&model);
    let mut p = Physics::build(&model, 1e-3).expect("builds");
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    let mut configs = vec![standby_rad().to_vec()];
    configs.extend((0..10).map(|_| random_free_config(&model, &guard, &mut rng, 0.05)));
    for q0 in configs {
        p.teleport(&q0);
        p.set_motor_targets(&q0, &[0.0; 6]);
        for _ in 0..1000 {
            p.step();
        }
        let (mut q, mut qd) = (vec![0.0; 6], vec![0.0; 6]);
        p.read_state(&mut q, &mut qd);
        let err = max_abs_diff(&q, &q0);
        assert!(err <= 1e-3, "steady error {err} rad at {q0:?}");
    }
}

/// The simulation (motors + inverse-dynamics feedforward) holds within 1 mrad (≈ 1e-6 in practice).
#[test]
fn simulation_holds_standby_under_gravity() {
    let mut s = sim(SimMode::Dynamic);
    run_s(&mut s, 1.0);
    let err = max_abs_diff(s.q(), &standby_rad());
    assert!(err <= 1e-3, "steady error {err}");
}

/// A 0.5 rad step on every joint, ending exactly on its limit, settles within 2 mrad in
/// 0.3 s and never passes the limit by more than 1 mrad.
#[test]
fn half_radian_step_settles_in_0_3_s_without_passing_the_limit() {
    let model = parol6();
    let guard = CollisionGuard::new(&model);
    let mut p = Physics::build(&model, 1e-3).expect("builds");
    let mut rng = rand::rngs::StdRng::seed_from_u64(17);
    for j in 0..6 {
        for upper in [true, false] {
            let l = model.limits.get(j).expect("joint");
            let (start_v, goal_v) = if upper { (l.max - 0.5, l.max) } else { (l.min + 0.5, l.min) };
            // other joints anywhere, as long as the step sweeps nothing into the ground or the arm
            let (start, goal) = loop {
                let mut start = random_free_config(&model, &guard, &mut rng, 0.1);
                start[j] = start_v;
                let mut goal = start.clone();
                goal[j] = goal_v;
                let clear = (0..=50).all(|i| {
                    let mut q = start.clone();
                    q[j] = start_v + (goal_v - start_v) * f64::from(i) / 50.0;
                    guard.check(&model, &q).is_none()
                });
                if clear {
                    break (start, goal);
                }
            };
            p.teleport(&start);
            p.set_motor_targets(&goal, &[0.0; 6]);
            let (mut q, mut qd) = (vec![0.0; 6], vec![0.0; 6]);
            let mut settled_at = None;
            let mut worst_pass = 0.0f64;
            for step in 1..=600 {
                p.step();
                p.read_state(&mut q, &mut qd);
                worst_pass = worst_pass.max(q[j] - l.max).max(l.min - q[j]);
                let err = (q[j] - goal_v).abs();
                if err > 2e-3 {
                    settled_at = None;
                } else if settled_at.is_none() {
                    settled_at = Some(step);
                }
            }
            let t = settled_at.map(|s| s as f64 * 1e-3);
            assert!(t.is_some_and(|t| t <= 0.3), "J{} to {goal_v}: settled at {t:?}, q {q:?}", j + 1);
            assert!(worst_pass <= 1e-3, "J{} passed its limit by {worst_pass}", j + 1);
        }
    }
}

// ---------------------------------------------------------------- commands and limits

#[test]
fn new_simulation_rests_at_standby() {
    let mut s = sim(SimMode::Dynamic);
    let snap = s.snapshot();
    // the measured joints are the drives' whole steps (J3's standby is 0.24 step off a step)
    assert!(max_abs_diff(&snap.q, &standby_rad()) < 3e-5);
    assert_eq!(snap.link_poses.len(), parol6().links.len());
    assert_eq!(snap.zones.len(), 6);
    assert!(snap.collision.is_none());
    assert!(!snap.moving);
}

#[test]
fn kinematic_move_follows_the_profile_exactly() {
    let mut s = ideal_sim(SimMode::Kinematic);
    let start = standby_rad().to_vec();
    let goal = vec![1.2, -1.2, 2.8, 0.3, -0.4, 2.0];
    s.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal.clone(),
        speed_fraction: 0.8,
        profile: ProfileKind::JerkLimited,
    }))
    .expect("free move");
    let mv = JointMove::parol6(&start, &goal, 0.8, ProfileKind::JerkLimited).expect("plans");
    for k in 1..=200 {
        s.step();
        let expect = mv.sample(k as f64 * 1e-3);
        assert!(max_abs_diff(s.q(), &expect.q) < 1e-12, "step {k}");
    }
    run_s(&mut s, mv.duration_s());
    assert!(max_abs_diff(s.q(), &goal) < 1e-12);
    assert!(!s.is_moving());
}

#[test]
fn dynamic_move_tracks_the_profile_and_reaches_the_goal() {
    let mut s = sim(SimMode::Dynamic);
    let goal = vec![1.2, -1.2, 2.8, 0.3, -0.4, 2.0];
    s.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal.clone(),
        speed_fraction: 1.0,
        profile: ProfileKind::Trapezoidal,
    }))
    .expect("free move");
    let mv = JointMove::parol6(&standby_rad(), &goal, 1.0, ProfileKind::Trapezoidal).expect("plans");
    let steps = (mv.duration_s() / 1e-3).ceil() as usize;
    let mut worst = 0.0f64;
    for k in 1..=steps {
        s.step();
        worst = worst.max(max_abs_diff(s.q(), &mv.sample(k as f64 * 1e-3).q));
    }
    run_s(&mut s, 0.3);
    assert!(worst < 5e-3, "tracking error {worst}");
    assert!(max_abs_diff(s.q(), &goal) < 1e-3);
}

#[test]
fn home_returns_to_standby() {
    for mode in [SimMode::Kinematic, SimMode::Dynamic] {
        let mut s = sim(mode);
        s.apply(SimCommand::Teleport(vec![0.5, -1.0, 2.5, 0.5, 0.5, 1.0])).expect("free teleport");
        s.apply(SimCommand::Motion(MotionCommand::home())).expect("home");
        assert!(s.is_moving());
        run_s(&mut s, 6.0);
        assert!(max_abs_diff(s.q(), &standby_rad()) < 1e-3, "{mode:?}: {:?}", s.q());
        assert!(!s.snapshot().moving);
    }
}

#[test]
fn jog_targets_move_at_the_speed_limit() {
    let mut s = ideal_sim(SimMode::Kinematic);
    let mut goal = standby_rad().to_vec();
    goal[0] += 0.5;
    s.apply(SimCommand::Motion(MotionCommand::follow(goal.clone()))).expect("in range");
    s.step();
    let v = motion_caps(s.model()).0[0];
    assert!((s.qd()[0] - v).abs() < 1e-9, "{} vs {v}", s.qd()[0]);
    run_s(&mut s, 0.5 / v + 0.01);
    assert!(max_abs_diff(s.q(), &goal) < 1e-12);
}

#[test]
fn stop_holds_where_the_robot_is() {
    let mut s = ideal_sim(SimMode::Kinematic);
    s.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: vec![1.0, -1.2, 2.8, 0.3, -0.4, 2.0],
        speed_fraction: 1.0,
        profile: ProfileKind::Trapezoidal,
    }))
    .expect("move");
    run_s(&mut s, 0.2);
    s.apply(SimCommand::Motion(MotionCommand::Stop)).expect("stop");
    let here = s.q().to_vec();
    run_s(&mut s, 0.2);
    assert!(max_abs_diff(s.q(), &here) < 1e-12);
    assert!(!s.is_moving());
}

#[test]
fn reject_policy_names_the_joint_and_limit() {
    let mut s = sim(SimMode::Dynamic);
    let mut q = standby_rad().to_vec();
    q[1] = 0.5; // J2 above its upper limit
    let err = s.apply(SimCommand::Motion(MotionCommand::follow(q.clone()))).expect_err("out of range");
    match &err {
        SimError::Limit(LimitViolation::OutOfRange { joint_index, side, .. }) => {
            assert_eq!(*joint_index, 2);
            assert_eq!(*side, LimitSide::Upper);
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("J2"), "{err}");
    for cmd in [
        SimCommand::Motion(MotionCommand::MoveJoints {
            goal_rad: q.clone(),
            speed_fraction: 0.5,
            profile: ProfileKind::Trapezoidal,
        }),
        SimCommand::Teleport(q.clone()),
    ] {
        assert!(matches!(s.apply(cmd), Err(SimError::Limit(_))));
    }
    // refused commands leave the target unchanged
    assert!(max_abs_diff(&s.snapshot().target_q, &standby_rad()) < 1e-12);
}

#[test]
fn clamp_policy_clamps_into_range() {
    let config = SimConfig { policy: LimitPolicy::Clamp, mode: SimMode::Kinematic, ..SimConfig::default() };
    let mut s = Simulation::new(parol6(), config).expect("builds");
    let mut q = standby_rad().to_vec();
    q[5] = 9.0; // J6 above 2π
    s.apply(SimCommand::Motion(MotionCommand::follow(q))).expect("clamped");
    let max = s.model().limits.get(5).expect("J6").max;
    assert!((max - std::f64::consts::TAU).abs() < 1e-3);
    assert!((s.snapshot().target_q[5] - max).abs() < 1e-12);
}

#[test]
fn malformed_commands_are_refused_without_panicking() {
    let mut s = sim(SimMode::Dynamic);
    let bad = [
        SimCommand::Motion(MotionCommand::follow(vec![0.0; 3])),
        SimCommand::Motion(MotionCommand::follow(vec![f64::NAN; 6])),
        SimCommand::Teleport(vec![f64::INFINITY; 6]),
        SimCommand::Teleport(vec![]),
        SimCommand::Motion(MotionCommand::MoveJoints {
            goal_rad: standby_rad().to_vec(),
            speed_fraction: f64::NAN,
            profile: ProfileKind::Trapezoidal,
        }),
        SimCommand::Motion(MotionCommand::MoveJoints {
            goal_rad: standby_rad().to_vec(),
            speed_fraction: -1.0,
            profile: ProfileKind::JerkLimited,
        }),
        SimCommand::Motion(MotionCommand::MoveJoints {
            goal_rad: vec![1.0; 7],
            speed_fraction: 0.5,
            profile: ProfileKind::JerkLimited,
        }),
        SimCommand::ApplyJointTorques(vec![0.0; 5]),
        SimCommand::ApplyJointTorques(vec![f64::NAN; 6]),
    ];
    for cmd in bad {
        assert!(s.apply(cmd.clone()).is_err(), "{cmd:?} accepted");
    }
    run_s(&mut s, 0.05);
    assert!(max_abs_diff(s.q(), &standby_rad()) < 1e-3);
    let mut k = sim(SimMode::Kinematic);
    assert!(matches!(k.apply(SimCommand::ApplyJointTorques(vec![0.0; 6])), Err(SimError::InvalidCommand(_))));
}

#[test]
fn bad_configs_are_refused() {
    for rate_hz in [0.0, -5.0, f64::NAN, 1e9] {
        let c = SimConfig { rate_hz, ..SimConfig::default() };
        assert!(matches!(Simulation::new(parol6(), c), Err(SimError::Config(_))));
    }
}

#[test]
fn mode_switch_keeps_the_pose() {
    let mut s = sim(SimMode::Kinematic);
    let q = vec![0.4, -1.0, 2.6, 0.2, 0.3, 1.0];
    s.apply(SimCommand::Teleport(q.clone())).expect("free");
    s.apply(SimCommand::SetMode(SimMode::Dynamic)).expect("switch");
    run_s(&mut s, 0.5);
    assert_eq!(s.mode(), SimMode::Dynamic);
    assert!(max_abs_diff(s.q(), &q) < 1e-3);
    s.apply(SimCommand::SetMode(SimMode::Kinematic)).expect("switch back");
    run_s(&mut s, 0.1);
    assert!(max_abs_diff(s.q(), &q) < 1e-3);
}

// ---------------------------------------------------------------- collision guard

#[test]
fn guard_skips_adjacent_and_never_colliding_pairs() {
    let model = parol6();
    let pairs = CollisionGuard::new(&model).pair_names();
    let has = |a: &str, b: &str| pairs.iter().any(|(x, y)| (x == a && y == b) || (x == b && y == a));
    for (a, b) in [("base_link", "L1"), ("L1", "L2"), ("L2", "L3"), ("L3", "L4"), ("L4", "L5"), ("L5", "L6")] {
        assert!(!has(a, b), "adjacent {a}-{b} tested");
    }
    for (a, b) in collision::PAROL6_NEVER_COLLIDE {
        assert!(!has(a, b), "never-colliding {a}-{b} tested");
    }
    for (a, b) in [("L1", "L6"), ("base_link", "L5"), ("base_link", "L6")] {
        assert!(has(a, b), "{a}-{b} not tested");
    }
}

#[test]
fn known_collisions_are_found_and_named() {
    let model = parol6();
    let guard = CollisionGuard::new(&model);
    let all = guard.all_contacts(&model, &Q_L1_L6);
    assert!(all.iter().any(|c| c.link_a == "L1" && c.link_b == "L6"), "{all:?}");
    assert!(guard.check(&model, &Q_L1_L6).is_some());
    let all = guard.all_contacts(&model, &Q_BASE_L5);
    assert!(all.iter().any(|c| c.link_a == "base_link" && c.link_b == "L5"), "{all:?}");
    let g = guard.check(&model, &Q_GROUND).expect("below ground");
    assert_eq!(g.link_b, collision::GROUND);
    assert!(guard.check(&model, &standby_rad()).is_none());
    assert!(guard.check(&model, &crate::parol6::park_rad()).is_none());
}

#[test]
fn colliding_targets_are_refused() {
    let mut s = sim(SimMode::Dynamic);
    for q in [Q_L1_L6, Q_BASE_L5, Q_GROUND] {
        match s.apply(SimCommand::Teleport(q.to_vec())) {
            Err(SimError::Collision { at_s, .. }) => assert_eq!(at_s, 0.0),
            other => panic!("expected a collision refusal, got {other:?}"),
        }
        // a jog target: refused at the latest when the path reaches it
        match s.apply(SimCommand::Motion(MotionCommand::follow(q.to_vec()))) {
            Err(SimError::Collision { at_s, .. }) => assert!(at_s >= 0.0),
            other => panic!("expected a collision refusal, got {other:?}"),
        }
    }
    let free = vec![0.3, -1.1, 2.9, 0.1, 0.2, 1.0];
    s.apply(SimCommand::Motion(MotionCommand::follow(free))).expect("free target accepted");
}

#[test]
fn a_move_through_a_collision_is_refused_with_the_time() {
    let mut s = sim(SimMode::Kinematic);
    // from a free start, J2 forward with the wrist folded down sweeps the wrist into the ground
    let start = vec![1.2781498, -1.2, 2.6772428, 0.3309554, 0.6916926, 1.1726027];
    assert!(s.guard().check(s.model(), &start).is_none(), "start must be free");
    s.apply(SimCommand::Teleport(start.clone())).expect("free start");
    let mut goal = start.clone();
    goal[1] = -0.0653485;
    let err = s
        .apply(SimCommand::Motion(MotionCommand::MoveJoints {
            goal_rad: goal.clone(),
            speed_fraction: 0.5,
            profile: ProfileKind::Trapezoidal,
        }))
        .expect_err("sweeps through the ground");
    let SimError::Collision { link_a, link_b, at_s } = err else { panic!("expected a collision") };
    let mv = JointMove::parol6(&start, &goal, 0.5, ProfileKind::Trapezoidal).expect("plans");
    assert!(at_s > 0.0 && at_s < mv.duration_s(), "at {at_s} of {}", mv.duration_s());
    assert_eq!(link_b, collision::GROUND);
    assert!(!link_a.is_empty());
    // the state just before the reported time is free, the one at it is not
    assert!(s.guard().check(s.model(), &mv.sample(at_s).q).is_some());
    assert!(s.guard().check(s.model(), &mv.sample(at_s - 0.02).q).is_none());
    assert!(!s.is_moving(), "the refused move must not start");
    // a move that stays clear is accepted
    let mut back = start.clone();
    back[1] = -1.0;
    s.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: back,
        speed_fraction: 0.5,
        profile: ProfileKind::Trapezoidal,
    }))
    .expect("free");
}

#[test]
fn a_jog_through_a_collision_is_refused() {
    let mut s = sim(SimMode::Kinematic);
    let start = vec![1.2781498, -1.2, 2.6772428, 0.3309554, 0.6916926, 1.1726027];
    s.apply(SimCommand::Teleport(start.clone())).expect("free start");
    let mut through = start.clone();
    through[1] = -0.0653485; // the wrist ends below the ground
    let err = s.apply(SimCommand::Motion(MotionCommand::follow(through))).expect_err("collides");
    let SimError::Collision { link_b, at_s, .. } = err else { panic!("expected a collision") };
    assert_eq!(link_b, collision::GROUND);
    assert!(at_s > 0.0);
    let mut near = start.clone();
    near[1] = -1.1;
    s.apply(SimCommand::Motion(MotionCommand::follow(near))).expect("clear jog");
}

#[test]
fn collision_checks_can_be_turned_off() {
    let config = SimConfig { check_collisions: false, mode: SimMode::Kinematic, ..SimConfig::default() };
    let mut s = Simulation::new(parol6(), config).expect("builds");
    s.apply(SimCommand::Teleport(Q_L1_L6.to_vec())).expect("accepted without the guard");
    run_s(&mut s, 0.02);
    assert!(s.snapshot().collision.is_some(), "the status still reports the contact");
}

/// Regression: rapier's narrow phase computed contacts for every overlapping link pair each
/// step (about 4.5 % of the step) though the multibody's self-contacts are off and the guard
/// owns self-collision; now links meet only the ground there. Regression too: the ground was
/// a half-space, whose bounding box is infinite, so every link was paired with it at every step
/// (about 6 % of the step's instructions); now only a link near the ground is.
#[test]
fn rapier_pairs_links_only_with_the_ground_and_only_near_it() {
    let mut s = sim(SimMode::Dynamic);
    // a move, so the physics is stepped (at rest it is not)
    let mut goal = standby_rad().to_vec();
    goal[0] += 0.5;
    s.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal,
        speed_fraction: 1.0,
        profile: ProfileKind::Trapezoidal,
    }))
    .expect("move accepted");
    run_s(&mut s, 0.2);
    assert_eq!(
        s.physics.narrow_phase_pairs(),
        (0, 0),
        "(link–link, link–ground) pairs at standby, far above the ground"
    );
    // the wrist on the ground (the guard off): rapier meets it there
    let config = SimConfig { check_collisions: false, mode: SimMode::Dynamic, ..SimConfig::default() };
    let mut s = Simulation::new(parol6(), config).expect("builds");
    s.apply(SimCommand::Teleport(Q_GROUND.to_vec())).expect("accepted without the guard");
    run_s(&mut s, 0.05);
    let (robot, ground) = s.physics.narrow_phase_pairs();
    assert_eq!(robot, 0, "link–link pairs in rapier's narrow phase");
    assert!(ground > 0, "no link–ground pair: the ground no longer touches the robot");
}

/// J1 turns about the vertical, so the base and L1 keep their heights: they are never paired
/// with the ground, wherever the arm is (`frames_at_fixed_height`).
#[test]
fn links_turned_only_about_the_vertical_are_never_paired_with_the_ground() {
    let model = parol6();
    let level = super::multibody::frames_at_fixed_height(&model, &model.chain_frames(&[0.0; 6]));
    assert_eq!(level, vec![true, true, false, false, false, false, false], "base and L1 only");
}

#[test]
fn derived_never_colliding_pairs_hold() {
    let model = parol6();
    let all = CollisionGuard::with_disabled_pairs(&model, &[]);
    let mut rng = rand::rngs::StdRng::seed_from_u64(2024);
    for _ in 0..20_000 {
        let q: Vec<f64> = model.limits.iter().map(|l| rng.random_range(l.min..=l.max)).collect();
        for c in all.all_contacts(&model, &q) {
            let listed = collision::PAROL6_NEVER_COLLIDE
                .iter()
                .any(|(a, b)| (c.link_a == *a && c.link_b == *b) || (c.link_a == *b && c.link_b == *a));
            assert!(!listed, "{c} at {q:?}");
        }
    }
}

#[test]
fn srdf_pairs_are_skipped() {
    let mut model = parol6();
    model.is_parol6 = false; // only the SRDF list, not the embedded one
    let before = CollisionGuard::new(&model).pair_names().len();
    let n = model.apply_srdf(r#"<robot><disable_collisions link1="L1" link2="L6" reason="Never"/></robot>"#);
    assert_eq!(n, 1);
    let pairs = CollisionGuard::new(&model).pair_names();
    assert_eq!(pairs.len(), before - 1);
    assert!(!pairs.iter().any(|(a, b)| a == "L1" && b == "L6"));
}

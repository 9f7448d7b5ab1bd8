//! The simulation of another URDF: the reference pack's python-API PAROL6 (STL meshes →
//! convex hulls) with its SRDF's disabled pairs.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use parol6_core::RobotModel;
use parol6_core::collision::CollisionGuard;
use parol6_core::motion::MotionCommand;
use parol6_core::sim::{SimCommand, SimConfig, SimMode, Simulation};

#[test]
fn mesh_robot_with_srdf_builds_and_steps() {
    let Some(shared) = parol6_tests::shared_dir() else { return };
    let dir = shared.join("urdf").join("python-api");
    let mut model = RobotModel::from_urdf_file(&dir.join("PAROL6.urdf"), Some("L6")).expect("loads");
    let srdf = std::fs::read_to_string(dir.join("PAROL6.srdf")).expect("SRDF");
    let n = model.apply_srdf(&srdf);
    assert!(n > 0);
    let guard = CollisionGuard::new(&model);
    for (a, b) in &model.disabled_collision_pairs {
        assert!(
            !guard.pair_names().iter().any(|(x, y)| (x == a && y == b) || (x == b && y == a)),
            "{a}-{b} is disabled by the SRDF but tested"
        );
    }
    let config = SimConfig { mode: SimMode::Dynamic, check_collisions: false, ..SimConfig::default() };
    let mut sim = Simulation::new(model.clone(), config).expect("builds");
    let meshes: usize = model.links.iter().map(|l| l.collisions.len()).sum();
    assert!(meshes > 0);
    assert_eq!(sim.physics().collider_count(), meshes, "every collision mesh became a convex hull");
    assert_eq!(sim.physics().ndofs(), model.dof());
    let start = sim.q().to_vec();
    for _ in 0..500 {
        sim.step();
    }
    let drift = sim.q().iter().zip(&start).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-3, "holds its pose under gravity, drift {drift}");
    let goal: Vec<f64> = model.limits.iter().map(|l| l.clamp(0.5 * (l.min + l.max) + 0.1)).collect();
    sim.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal.clone(),
        speed_fraction: 1.0,
        profile: Default::default(),
    }))
    .expect("move");
    for _ in 0..10_000 {
        sim.step();
        if !sim.is_moving() {
            break;
        }
    }
    for _ in 0..300 {
        sim.step();
    }
    let err = sim.q().iter().zip(&goal).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-3, "reached the goal, error {err}");
}

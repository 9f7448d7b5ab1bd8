//! Criterion: one simulation step (dynamic mode with colliders, kinematic mode), the inverse
//! dynamics, the collision guard at one configuration and along a move, and a snapshot.
use criterion::{Criterion, criterion_group, criterion_main};
use parol6_core::RobotModel;
use parol6_core::collision::CollisionGuard;
use parol6_core::dynamics::InverseDynamics;
use parol6_core::motion::MotionCommand;
use parol6_core::profile::{JointMove, ProfileKind};
use parol6_core::sim::{SimCommand, SimConfig, SimMode, Simulation};
use std::hint::black_box;

fn physics(c: &mut Criterion) {
    let model = RobotModel::parol6();
    let a = parol6_core::parol6::standby_rad().to_vec();
    let b = vec![1.2, -1.2, 2.8, 0.3, -0.4, 2.0];
    for mode in [SimMode::Dynamic, SimMode::Kinematic] {
        let config = SimConfig { mode, ..SimConfig::default() };
        let Ok(mut sim) = Simulation::new(model.clone(), config) else { panic!("embedded model builds") };
        let mut to_b = true;
        c.bench_function(&format!("sim_step_{mode:?}").to_lowercase(), |bench| {
            bench.iter(|| {
                if !sim.is_moving() {
                    let goal = if to_b { b.clone() } else { a.clone() };
                    to_b = !to_b;
                    let _ = sim.apply(SimCommand::Motion(MotionCommand::MoveJoints {
                        goal_rad: goal,
                        speed_fraction: 1.0,
                        profile: ProfileKind::Trapezoidal,
                    }));
                }
                sim.step();
            })
        });
        c.bench_function(&format!("sim_snapshot_{mode:?}").to_lowercase(), |bench| {
            bench.iter(|| black_box(sim.snapshot()))
        });
    }
    let mut id = InverseDynamics::new(&model);
    let mut out = vec![0.0; 6];
    c.bench_function("inverse_dynamics_rnea", |bench| {
        bench.iter(|| id.compute_into(&model, black_box(&b), black_box(&[0.5; 6]), black_box(&[1.0; 6]), &mut out))
    });
    let guard = CollisionGuard::new(&model);
    c.bench_function("collision_guard_check", |bench| bench.iter(|| guard.check(&model, black_box(&b))));
    let Ok(mv) = JointMove::parol6(&a, &b, 1.0, ProfileKind::Trapezoidal) else { panic!("plans") };
    c.bench_function("collision_guard_sweep_move", |bench| bench.iter(|| guard.check_move(&model, black_box(&mv))));
}

criterion_group!(benches, physics);
criterion_main!(benches);

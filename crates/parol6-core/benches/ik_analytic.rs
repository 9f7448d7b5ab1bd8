//! Criterion: closed-form PAROL6 IK, all branches; and the joint move's choice, the solution
//! nearest the start in any configuration (`ik::solve_nearest`, issue target ≤ 5 µs), from an
//! ordinary start and from standby (on the wrist border).
use criterion::{Criterion, criterion_group, criterion_main};
use parol6_core::ik::ConfigRule;
use parol6_core::kinematics::iso_from_xyz_rpy;
use parol6_core::{RobotModel, ik};
use std::hint::black_box;

fn ik_analytic(c: &mut Criterion) {
    let model = RobotModel::parol6();
    let target = model.tcp_isometry(&[0.3, -1.2, 3.0, 0.4, -0.7, 2.0]);
    let seed = parol6_core::parol6::standby_rad();
    c.bench_function("ik_analytic_all_branches", |b| b.iter(|| ik::solve_parol6(&model, black_box(&target), &seed)));
    c.bench_function("ik_nearest_configuration", |b| {
        b.iter(|| ik::solve_nearest(&model, black_box(&target), &seed, ConfigRule::ANY))
    });
    let tool_down = iso_from_xyz_rpy([0.22, 0.0, 0.20], [0.0, 0.0, 0.0]);
    c.bench_function("ik_nearest_configuration_tool_down_from_standby", |b| {
        b.iter(|| ik::solve_nearest(&model, black_box(&tool_down), &seed, ConfigRule::ANY))
    });
}

criterion_group!(benches, ik_analytic);
criterion_main!(benches);

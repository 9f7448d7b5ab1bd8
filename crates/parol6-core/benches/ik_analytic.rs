//! Criterion: closed-form PAROL6 IK, all branches.
use criterion::{Criterion, criterion_group, criterion_main};
use parol6_core::{RobotModel, ik};
use std::hint::black_box;

fn ik_analytic(c: &mut Criterion) {
    let model = RobotModel::parol6();
    let target = model.tcp_isometry(&[0.3, -1.2, 3.0, 0.4, -0.7, 2.0]);
    let seed = parol6_core::parol6::standby_rad();
    c.bench_function("ik_analytic_all_branches", |b| b.iter(|| ik::solve_parol6(&model, black_box(&target), &seed)));
}

criterion_group!(benches, ik_analytic);
criterion_main!(benches);

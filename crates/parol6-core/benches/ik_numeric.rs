//! Criterion: numeric (Levenberg–Marquardt) IK on the PAROL6 chain.
use criterion::{Criterion, criterion_group, criterion_main};
use parol6_core::RobotModel;
use parol6_core::ik::{self, NumericIkOptions};
use std::hint::black_box;

fn ik_numeric(c: &mut Criterion) {
    let model = RobotModel::parol6();
    let target = model.tcp_isometry(&[0.3, -1.2, 3.0, 0.4, -0.7, 2.0]);
    let seed = parol6_core::parol6::standby_rad();
    let opts = NumericIkOptions::default();
    c.bench_function("ik_numeric", |b| b.iter(|| ik::solve_numeric(&model, black_box(&target), &seed, &opts)));
}

criterion_group!(benches, ik_numeric);
criterion_main!(benches);

//! Criterion: forward kinematics of the embedded PAROL6 (TCP only, and every link).
use criterion::{Criterion, criterion_group, criterion_main};
use parol6_core::RobotModel;
use std::hint::black_box;

fn fk(c: &mut Criterion) {
    let model = RobotModel::parol6();
    let q = [0.3, -1.2, 3.0, 0.4, -0.7, 2.0];
    c.bench_function("fk_tcp", |b| b.iter(|| model.tcp_isometry(black_box(&q))));
    c.bench_function("fk_all_links", |b| b.iter(|| model.link_poses(black_box(&q))));
    c.bench_function("jacobian", |b| b.iter(|| model.jacobian(black_box(&q))));
}

criterion_group!(benches, fk);
criterion_main!(benches);

//! Criterion: pre-flight validation of a 1 000-move pick-and-place program (joint moves and
//! short straight lines sampled every 10 ms, three keep-out shapes), planned beforehand; the
//! issue's target is ≤ 50 ms.
use criterion::{Criterion, criterion_group, criterion_main};
use parol6_core::RobotModel;
use parol6_core::motion::MotionCaps;
use parol6_core::motion::preflight::Preflight;
use parol6_core::motion::preflight::bench_program::{bench_program, bench_scene};
use std::hint::black_box;

fn preflight(c: &mut Criterion) {
    let model = RobotModel::parol6();
    let caps = MotionCaps::of(&model);
    let Ok(program) = bench_program(&model, 1000) else { panic!("the bench program plans") };
    let Ok(checker) = Preflight::new(&model, &caps, &bench_scene()) else { panic!("the bench scene is valid") };
    assert!(checker.check(&program).ok(), "the bench program is clean");
    let mut group = c.benchmark_group("preflight");
    group.sample_size(20);
    group.bench_function("check_1000_moves", |b| b.iter(|| checker.check(black_box(&program))));
    group.bench_function("new_with_scene", |b| b.iter(|| Preflight::new(black_box(&model), &caps, &bench_scene())));
    group.finish();
}

criterion_group!(benches, preflight);
criterion_main!(benches);

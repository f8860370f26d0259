//! Criterion benches of the core's step on the shower and the gas at 1k, 10k and 100k spheres.
//! Each iteration steps a warmed-up world once (the world keeps evolving between iterations).

use criterion::{Criterion, criterion_group, criterion_main};
use sphere_bench::scenes;

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("step");
    group.sample_size(10);
    for n in [1_000u32, 10_000, 100_000] {
        for (name, scene) in [("shower", scenes::shower(n, 1)), ("gas", scenes::gas(n, 1))] {
            let mut world = scene.build().expect("valid");
            for _ in 0..15 {
                world.step(1.0 / 60.0).expect("valid dt");
            }
            group.bench_function(format!("{name}/{n}"), |b| {
                b.iter(|| world.step(1.0 / 60.0).expect("valid dt").collisions)
            });
        }
    }
    group.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);

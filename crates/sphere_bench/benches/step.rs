//! Criterion benches of the core's step on the shower and the gas at 1k, 10k and 100k spheres,
//! and on the gas of 10k 2e8 m from the origin.
//! Each iteration times one step of the scene's first second, as the bench's table does: steps
//! 2 to 61, the world built anew (off the clock) after its 61st. (Until the sixty-third session
//! the world went on evolving through criterion's iterations: tens of thousands of steps at 1k,
//! where the shower's spheres had long fallen far below the dome, and a few seconds at 100k,
//! so that each size measured another phase of the scene.)
//! Also: one step of a shell of 40 000 spheres landing at one instant on one central sphere
//! (one simultaneous group of 40 000 impacts: it took 0.35 to 0.41 s while groups were solved
//! in quadratic time, 0.08 to 0.11 s since), and of a 200 × 200 sheet of spheres settling at
//! one instant, each onto its own fixed sphere (40 000 resting impacts, each its own part of
//! one group). And, with sleeping on, a ball rolling for a second among 10 000 marbles asleep
//! apart on a floor, each its own island (the step leaves out the islands beyond the ball's
//! reach, and the islands it takes change as it rolls), and a step after one of those
//! marbles is woken (the bodies asleep change at every step). And a step of 60 balls in a pit
//! held inside a fixed sphere of radius 1e4 put over them (its centre just above the pit), by
//! the pit's floor and walls: every step falls back, and its contacts cannot all be met.

use std::time::{Duration, Instant};

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use sphere_bench::scenes;
use sphere_physics::{Settings, Sleep, SphereDesc, World, glam::DVec3};

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("step");
    group.sample_size(10);
    for n in [1_000u32, 10_000, 100_000] {
        for (name, scene) in [("shower", scenes::shower(n, 1)), ("gas", scenes::gas(n, 1))] {
            group.bench_function(format!("{name}/{n}"), |b| first_second(b, &scene));
        }
    }
    // The gas 2e8 m out along each axis: as fast as at the origin (it was quadratic).
    let far = scenes::far_gas(10_000, 1);
    group.bench_function("far gas/10000", |b| first_second(b, &far));
    group.finish();
}

/// Times `scene`'s steps 2 to 61 (of 1/60 s), one an iteration, over and over: the world is
/// built and stepped once off the clock, and again after its 61st step.
fn first_second(b: &mut criterion::Bencher, scene: &sphere_physics::SceneDesc) {
    let warmed = || {
        let mut world: World = scene.build().expect("valid");
        world.step(1.0 / 60.0).expect("valid dt");
        world
    };
    let (mut world, mut taken) = (warmed(), 0u32);
    b.iter_custom(|iterations| {
        let mut spent = Duration::ZERO;
        for _ in 0..iterations {
            if taken == 60 {
                (world, taken) = (warmed(), 0);
            }
            let started = Instant::now();
            std::hint::black_box(world.step(1.0 / 60.0).expect("valid dt").collisions);
            spent += started.elapsed();
            taken += 1;
        }
        spent
    });
}

/// 40 000 balls 0.03 from a central sphere of radius 10, all moving straight at it at 3 m/s.
fn shell(centre: SphereDesc) -> World {
    let n = 40_000;
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    world.add_sphere(centre).expect("valid");
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    for i in 0..n {
        let y = 1.0 - 2.0 * (f64::from(i) + 0.5) / f64::from(n);
        let r = (1.0 - y * y).sqrt();
        let phi = golden * f64::from(i);
        let d = DVec3::new(r * phi.cos(), y, r * phi.sin());
        let ball = SphereDesc::new(0.05).at(d * 10.08).moving(-d * 3.0);
        world.add_sphere(ball).expect("valid");
    }
    world
}

/// 200 × 200 spheres at rest 1 mm above their own fixed spheres, under gravity.
fn resting_sheet() -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    for i in 0..200 {
        for j in 0..200 {
            let floor = DVec3::new(f64::from(i) * 1.5, 0.0, f64::from(j) * 1.5);
            world
                .add_sphere(SphereDesc::new(0.5).at(floor).fixed())
                .expect("valid");
            world
                .add_sphere(SphereDesc::new(0.5).at(floor + DVec3::Y * 1.001))
                .expect("valid");
        }
    }
    world
}

/// 60 balls of radius 0.05 settled for two seconds in a pit 0.6 m across (a floor and four
/// walls, fixed spheres of radius 1e4), then a fixed sphere of radius 1e4 put over them, its
/// centre 0.6 m above the floor: they lie 10 km deep inside it, held there by the pit.
fn held() -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    let (wall, half) = (1.0e4, 0.3);
    for at in [
        DVec3::new(0.0, -wall, 0.0),
        DVec3::new(-wall - half, 0.0, 0.0),
        DVec3::new(wall + half, 0.0, 0.0),
        DVec3::new(0.0, 0.0, -wall - half),
        DVec3::new(0.0, 0.0, wall + half),
    ] {
        world
            .add_sphere(SphereDesc::new(wall).at(at).fixed())
            .expect("valid");
    }
    for i in 0..60u32 {
        let at = DVec3::new(
            f64::from(i % 5) * 0.11 - 0.22,
            0.05 + f64::from(i / 25) * 0.11,
            f64::from((i / 5) % 5) * 0.11 - 0.22,
        );
        world
            .add_sphere(SphereDesc::new(0.05).at(at))
            .expect("valid");
    }
    for _ in 0..120 {
        world.step(1.0 / 60.0).expect("valid dt");
    }
    world
        .add_sphere(
            SphereDesc::new(wall)
                .at(DVec3::new(0.0, 0.6, -0.15))
                .fixed(),
        )
        .expect("valid");
    for _ in 0..5 {
        world.step(1.0 / 60.0).expect("valid dt");
    }
    world
}

fn simultaneous(c: &mut Criterion) {
    let mut group = c.benchmark_group("simultaneous");
    group.sample_size(10);
    for (name, centre) in [
        ("shell_on_fixed", SphereDesc::new(10.0).fixed()),
        ("shell_on_heavy", SphereDesc::new(10.0).with_density(1e3)),
    ] {
        group.bench_function(name, |b| {
            b.iter_batched_ref(
                || shell(centre.clone()),
                |w| w.step(1.0 / 60.0).expect("valid dt").collisions,
                BatchSize::LargeInput,
            )
        });
    }
    group.bench_function("resting_sheet", |b| {
        b.iter_batched_ref(
            resting_sheet,
            |w| w.step(1.0 / 60.0).expect("valid dt").collisions,
            BatchSize::LargeInput,
        )
    });
    group.finish();
    let mut group = c.benchmark_group("held");
    group.sample_size(20);
    let mut world = held();
    group.bench_function("60", |b| {
        b.iter(|| world.step(1.0 / 60.0).expect("valid dt").collisions)
    });
    group.finish();
}

/// 100 × 100 marbles of radius 0.1, 0.5 m apart, asleep on a wide floor, and a ball rolling
/// among them at 3 m/s (returned: the world and the ball's id).
fn marbles_asleep() -> (World, sphere_physics::BodyId) {
    let mut world = World::new(Settings {
        sleep: Some(Sleep::default()),
        ..Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0))
    });
    world
        .add_sphere(SphereDesc::new(1e5).at(DVec3::NEG_Y * 1e5).fixed())
        .expect("valid");
    for i in 0..100 {
        for j in 0..100 {
            let at = DVec3::new(f64::from(i) * 0.5, 0.1, f64::from(j) * 0.5);
            let marble = SphereDesc::new(0.1).at(at).with_restitution(0.5);
            world.add_sphere(marble).expect("valid");
        }
    }
    for _ in 0..300 {
        world.step(1.0 / 60.0).expect("valid dt");
    }
    assert_eq!(world.stats().asleep, 10_000, "the marbles fall asleep");
    let ball = world.add_sphere(SphereDesc::new(0.1)).expect("valid");
    (world, ball)
}

fn sleeping(c: &mut Criterion) {
    let mut group = c.benchmark_group("sleeping");
    group.sample_size(10);
    let (mut world, ball) = marbles_asleep();
    // Each iteration rolls the ball for a second (60 steps) between two rows of marbles (it
    // grazes none; the islands within its reach change as it rolls), a different pair of rows
    // each time.
    let mut row = 0;
    group.bench_function("rolling among marbles/10000", |b| {
        b.iter(|| {
            row = (row + 7) % 99;
            let z = f64::from(row) * 0.5 + 0.25;
            world
                .set_position(ball, DVec3::new(-1.0, 0.1, z))
                .expect("valid");
            world.set_velocity(ball, DVec3::X * 3.0).expect("valid");
            (0..60)
                .map(|_| world.step(1.0 / 60.0).expect("valid dt").collisions)
                .sum::<u32>()
        })
    });
    // Each iteration wakes one marble (a different one each time) and takes one step: the
    // set of bodies asleep changes at every step (each marble woken falls asleep again a
    // second later), which the index of the bodies asleep follows.
    let (mut world, _) = marbles_asleep();
    let marbles: Vec<_> = world
        .bodies()
        .iter()
        .filter(|b| !b.is_fixed())
        .map(|b| b.id())
        .collect();
    let mut next = 0;
    group.bench_function("a marble woken among marbles/10000", |b| {
        b.iter(|| {
            next = (next + 37) % marbles.len();
            world.wake(marbles[next]).expect("a marble");
            world.step(1.0 / 60.0).expect("valid dt").asleep
        })
    });
    group.finish();
}

criterion_group!(benches, step, simultaneous, sleeping);
criterion_main!(benches);

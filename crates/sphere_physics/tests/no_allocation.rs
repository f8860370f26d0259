//! Once warmed up, a step allocates nothing: a counting allocator watches steps of a shower
//! piling onto a dome (resting contacts, simultaneous groups, bodies leaving the grid), of a
//! gas in a box of wall spheres, of a gas without walls spreading out, of a crowd placed
//! overlapping with no gravity moved apart, and of a pit with sleeping on, woken and falling
//! asleep again; nor do the setters
//! a game calls every frame (velocity, force, position).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use sphere_physics::{BodyId, SceneDesc, Settings, SphereDesc, World, glam::DVec3};

/// Counts allocations made while `COUNTING` is set.
struct Counting;

static COUNTING: AtomicBool = AtomicBool::new(false);
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: the caller's contract is passed on.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract is passed on.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: the caller's contract is passed on.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by `steps` steps of `world` after `warm` steps.
fn allocations(world: &mut World, warm: u32, steps: u32) -> usize {
    for _ in 0..warm {
        world.step(1.0 / 60.0).unwrap();
    }
    ALLOCATIONS.store(0, Ordering::Relaxed);
    COUNTING.store(true, Ordering::Relaxed);
    for _ in 0..steps {
        world.step(1.0 / 60.0).unwrap();
    }
    COUNTING.store(false, Ordering::Relaxed);
    ALLOCATIONS.load(Ordering::Relaxed)
}

// One test, so no other test's allocations are counted.
#[test]
fn a_warmed_up_step_allocates_nothing() {
    let shower = SceneDesc::from_ron(
        r#"(name: "shower", gravity: (0.0, -9.81, 0.0), restitution: 0.5,
            spheres: [(name: "dome", position: (0.0, 0.0, 0.0), radius: 1.0, fixed: true)],
            generate: [Shower(count: 1500, seed: 7, min: (-0.8, 1.2, -0.8), max: (0.8, 2.4, 0.8),
                              radius: 0.04)])"#,
    )
    .unwrap();
    let mut world = shower.build().unwrap();
    // Warm up through the landing, then watch the pile.
    let shower_allocations = allocations(&mut world, 60, 30);
    assert!(
        world.stats().resting_contacts > 0,
        "the pile rests on the dome"
    );
    let gas = SceneDesc::from_ron(
        r#"(name: "gas", generate: [
            Gas(count: 1500, seed: 3, min: (-1.0, -1.0, -1.0), max: (1.0, 1.0, 1.0), radius: 0.04,
                speed: 2.0)])"#,
    )
    .unwrap();
    let mut world = gas.build().unwrap();
    let gas_allocations = allocations(&mut world, 30, 30);
    // A gas without walls spreads out: its grid's block first outgrows what the grid may span
    // (64 cells per sphere) after the warm-up, from then on trimmed, with the stragglers in
    // the hierarchy. The buffers for those keep room from the start.
    let spreading = SceneDesc::from_ron(
        r#"(name: "spreading gas", gravity: (0.0, 0.0, 0.0), generate: [
            Gas(count: 200, seed: 5, min: (-0.4, -0.4, -0.4), max: (0.4, 0.4, 0.4), radius: 0.04,
                speed: 2.0, walls: false)])"#,
    )
    .unwrap();
    let mut world = spreading.build().unwrap();
    let spreading_allocations = allocations(&mut world, 10, 50);
    // With no gravity, a crowd placed overlapping at rest is moved apart step after step
    // (125 spheres: the broad phase's grid finds the pairs).
    let mut world = World::new(Settings::default());
    for i in 0..125 {
        let at = DVec3::new(f64::from(i % 5), f64::from(i / 5 % 5), f64::from(i / 25)) * 0.6;
        world.add_sphere(SphereDesc::new(0.5).at(at)).unwrap();
    }
    let crowd_allocations = allocations(&mut world, 3, 20);
    assert!(world.stats().separated > 0, "still moving apart");
    // A pit with sleeping on: warmed up until it is asleep, then woken, and watched through
    // its calm second until it falls asleep again (the grouping's buffers, the quiet steps).
    let pit = SceneDesc::from_ron(
        r#"(name: "pit", gravity: (0.0, -9.81, 0.0), restitution: 0.5, sleep: (),
            spheres: [
                (position: (0.0, -10000.0, 0.0), radius: 10000.0, fixed: true),
                (position: (-10000.3, 0.0, 0.0), radius: 10000.0, fixed: true),
                (position: (10000.3, 0.0, 0.0), radius: 10000.0, fixed: true),
                (position: (0.0, 0.0, -10000.3), radius: 10000.0, fixed: true),
                (position: (0.0, 0.0, 10000.3), radius: 10000.0, fixed: true)],
            generate: [Shower(count: 150, seed: 2, min: (-0.3, 0.0, -0.3), max: (0.3, 1.0, 0.3),
                              radius: 0.05)])"#,
    )
    .unwrap();
    let mut world = pit.build().unwrap();
    let _ = allocations(&mut world, 900, 0);
    assert_eq!(world.stats().asleep, 150, "the pit fell asleep");
    let first = world.bodies()[5].id();
    world.wake(first).unwrap();
    let pit_allocations = allocations(&mut world, 0, 150);
    assert_eq!(world.stats().asleep, 150, "the pit fell asleep again");
    // Regression (found by review): the grid's buffers were sized to its share of the
    // bodies, and the pairs' buffers to the most candidates any body had had near it, so a
    // step allocated when either grew past what it had been: here 48 fast spheres, their
    // swept boxes too large for the grid's cells, are slowed and join the grid (4 allocations
    // in 5 steps). Both are now sized to all the bodies.
    let mut world = World::new(Settings::default());
    let lattice = |i: u32| f64::from(i);
    for i in 0..343 {
        let at = DVec3::new(lattice(i % 7), lattice(i / 7 % 7), lattice(i / 49));
        let slow = DVec3::new(0.01, 0.0, 0.0);
        world
            .add_sphere(SphereDesc::new(0.05).at(at).moving(slow))
            .unwrap();
    }
    // In lanes between the lattice's rows, never near a sphere of it or of another lane.
    let fast: Vec<BodyId> = (0..48)
        .map(|i| {
            let at = DVec3::new(lattice(i % 6) + 0.5, lattice(i / 6 % 6) + 0.5, 0.0);
            let desc = SphereDesc::new(0.05)
                .at(at)
                .moving(DVec3::new(0.0, 0.0, 30.0));
            world.add_sphere(desc).unwrap()
        })
        .collect();
    let _ = allocations(&mut world, 5, 0);
    for &id in &fast {
        world.set_velocity(id, DVec3::new(0.0, 0.0, 0.01)).unwrap();
    }
    let joining_allocations = allocations(&mut world, 0, 5);
    assert_eq!(world.stats().collisions, 0);
    // A game that sets every sphere's velocity, force and position each frame: no allocation
    // either (each change used to be checked on a copy of the sphere's description, name and
    // all: 300 allocations here), once the first frame has sized the list of places where
    // bodies were changed (see `Settings::sleep`), which each step empties.
    let mut world = World::new(Settings::default());
    let ids: Vec<BodyId> = (0..100)
        .map(|i| {
            let desc = SphereDesc::new(0.1)
                .at(DVec3::X * f64::from(i))
                .named(format!("ball {i}"));
            world.add_sphere(desc).unwrap()
        })
        .collect();
    let set_all = |world: &mut World| {
        for &id in &ids {
            let position = world.body(id).unwrap().position();
            world.set_velocity(id, DVec3::X).unwrap();
            world.set_force(id, DVec3::Y).unwrap();
            world.set_position(id, position + DVec3::Z).unwrap();
        }
    };
    set_all(&mut world);
    world.step(1.0 / 60.0).unwrap();
    ALLOCATIONS.store(0, Ordering::Relaxed);
    COUNTING.store(true, Ordering::Relaxed);
    set_all(&mut world);
    COUNTING.store(false, Ordering::Relaxed);
    let setter_allocations = ALLOCATIONS.load(Ordering::Relaxed);
    assert_eq!(
        (
            shower_allocations,
            gas_allocations,
            spreading_allocations,
            crowd_allocations,
            pit_allocations,
            joining_allocations,
            setter_allocations
        ),
        (0, 0, 0, 0, 0, 0, 0)
    );
}

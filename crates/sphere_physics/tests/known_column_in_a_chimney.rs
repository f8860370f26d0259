//! Known, not yet fixed (README: "Where rapier wins: a ball pit"): eight spheres dropped into a
//! chimney a centimetre wider than they are never come to rest. Each step the resting solve
//! leaves out the contacts with the chimney's walls (sideways, nothing of the spheres' own
//! presses them), so the column's weight, pushed sideways through its zig-zag, is passed back
//! and forth as impacts at restitution 0.5: about 380 collisions a step, 47 per sphere, for
//! ever. The smallest case of the ball pit's failure (`sphere-bench --scenes pile`), kept here
//! to be un-ignored when it is fixed. Both diffs in docs/experiments bring this column to rest
//! (24 collisions a step, the resting solve's), but neither is on main (see why there).

use sphere_physics::SceneDesc;

#[test]
#[ignore = "known: a column in a chimney chases its sideways load as impacts (README, ball pit)"]
fn a_column_in_a_chimney_comes_to_rest() {
    let wall = 1.0e4;
    // One lattice cell of the generator's spacing (10% over a diameter) across, 16 high.
    let cell = 2.0 * 0.05 * 1.1;
    let (half, height) = (0.5 * cell, 16.0 * cell);
    let scene = SceneDesc::from_ron(&format!(
        "(name: \"chimney\", gravity: (0.0, -9.81, 0.0), restitution: 0.5,
          spheres: [
            (name: \"floor\", position: (0.0, {f:?}, 0.0), radius: {wall:?}, fixed: true),
            (name: \"wall x-\", position: ({n:?}, 0.0, 0.0), radius: {wall:?}, fixed: true),
            (name: \"wall x+\", position: ({p:?}, 0.0, 0.0), radius: {wall:?}, fixed: true),
            (name: \"wall z-\", position: (0.0, 0.0, {n:?}), radius: {wall:?}, fixed: true),
            (name: \"wall z+\", position: (0.0, 0.0, {p:?}), radius: {wall:?}, fixed: true)],
          generate: [Shower(count: 8, seed: 1, min: ({lo:?}, 0.0, {lo:?}),
                            max: ({half:?}, {height:?}, {half:?}), radius: 0.05)])",
        f = -wall,
        n = -half - wall,
        p = half + wall,
        lo = -half,
    ))
    .unwrap();
    let mut world = scene.build().unwrap();
    for _ in 0..180 {
        world.step(1.0 / 60.0).unwrap();
    }
    // At rest: each step only the resting solve's contacts (the floor, the walls, the column's
    // seven joints: at most 5 per sphere), nothing deferred, no overlap past the creep.
    for _ in 0..60 {
        let stats = *world.step(1.0 / 60.0).unwrap();
        assert!(
            stats.collisions <= 40,
            "{} collisions in a step of a column at rest",
            stats.collisions
        );
        assert_eq!(stats.collisions_deferred, 0);
        assert!(stats.max_overlap < 1e-4, "overlap {}", stats.max_overlap);
    }
}

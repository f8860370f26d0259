//! The benchmark scenes, sized by sphere count: a shower onto a fixed dome, a gas in a box, a
//! pile in an open box, showers side by side (a sparse scene) and two gases far apart.

use sphere_physics::{SceneDesc, SphereSpec};

/// Radius of the small spheres in both scenes.
pub const RADIUS: f64 = 0.05;

/// Side of a lattice cube holding `capacity` cells of the generators' spacing.
fn side_for(capacity: f64) -> f64 {
    let cell = 2.0 * RADIUS * 1.1;
    cell * capacity.cbrt().ceil()
}

/// `n` spheres of radius 0.05 (restitution 0.5) raining from a cube with one lattice cell in
/// eight filled, just above a fixed dome wider than the cube, under gravity: the first reach
/// the dome in about 0.2 s and the rest keep landing on it, bouncing off one another and
/// sliding off its (frictionless) sides for the rest of the run.
pub fn shower(n: u32, seed: u64) -> SceneDesc {
    let side = side_for(8.0 * f64::from(n));
    let dome = 0.75 * side;
    let bottom = dome + 0.2;
    SceneDesc::from_ron(&format!(
        "(name: \"shower {n}\", gravity: (0.0, -9.81, 0.0), restitution: 0.5,
          spheres: [(name: \"dome\", position: (0.0, 0.0, 0.0), radius: {dome:?}, fixed: true)],
          generate: [Shower(count: {n}, seed: {seed}, min: ({lo:?}, {bottom:?}, {lo:?}),
                            max: ({hi:?}, {top:?}, {hi:?}), radius: {RADIUS:?})])",
        lo = -side / 2.0,
        hi = side / 2.0,
        top = bottom + side,
    ))
    .expect("the shower scene is valid")
}

/// How many spheres each of [`showers`]' tiles holds at most: the 1k shower's.
pub const TILE: u32 = 1000;

/// The gap between neighbouring tiles' domes in [`showers`], in metres: spheres sliding off a
/// dome fly up to a few metres in a second (with 1 m, 343 of the 32 000 collisions of four
/// tiles' first second were between tiles; with 3 m one; with 4 m none).
pub const TILE_GAP: f64 = 4.0;

/// `n` spheres as copies of the 1k [`shower`] side by side, each raining onto its own dome:
/// `ceil(n / 1000)` tiles (seeds `seed`, `seed + 1`, ...) of as equal counts as add up to `n`,
/// on a square lattice, their domes [`TILE_GAP`] apart. Every sphere meets what a sphere of the
/// 1k shower meets, at every `n`, but the spheres are spread thin: 100 tiles at 100k span
/// 73 m by 73 m, most of it empty (a game's level with groups of spheres here and there), and
/// the hundred domes are large fixed spheres apart from the rest.
pub fn showers(n: u32, seed: u64) -> SceneDesc {
    let tiles = n.div_ceil(TILE).max(1);
    let across = f64::from(tiles).sqrt().ceil() as u32;
    let side = side_for(8.0 * f64::from(TILE));
    let dome = 0.75 * side;
    let bottom = dome + 0.2;
    let spacing = 2.0 * dome + TILE_GAP;
    let (mut domes, mut rain) = (Vec::new(), Vec::new());
    for t in 0..tiles {
        let count = n / tiles + u32::from(t < n % tiles);
        let (x, z) = (
            f64::from(t % across) * spacing,
            f64::from(t / across) * spacing,
        );
        domes.push(format!(
            "(name: \"dome {t}\", position: ({x:?}, 0.0, {z:?}), radius: {dome:?}, fixed: true)"
        ));
        rain.push(format!(
            "Shower(count: {count}, seed: {s}, min: ({x0:?}, {bottom:?}, {z0:?}), \
             max: ({x1:?}, {top:?}, {z1:?}), radius: {RADIUS:?})",
            s = seed + u64::from(t),
            x0 = x - side / 2.0,
            x1 = x + side / 2.0,
            z0 = z - side / 2.0,
            z1 = z + side / 2.0,
            top = bottom + side,
        ));
    }
    SceneDesc::from_ron(&format!(
        "(name: \"showers {n}\", gravity: (0.0, -9.81, 0.0), restitution: 0.5,
          spheres: [{}], generate: [{}])",
        domes.join(", "),
        rain.join(", ")
    ))
    .expect("the showers scene is valid")
}

/// `n` spheres of radius 0.05 at speed 1 in random directions, a quarter of the lattice filled,
/// in a box closed by six fixed wall spheres; elastic, no gravity.
pub fn gas(n: u32, seed: u64) -> SceneDesc {
    walled_gas("gas", n, seed, 4)
}

/// How many lattice sites [`sparse`] has per sphere: one in a thousand filled, about a metre
/// (ten diameters) between neighbours.
pub const SPARSE: u32 = 1000;

/// `n` spheres as the [`gas`]'s (radius 0.05, speed 1, elastic, walls), but spread thin
/// through their box: one lattice site in [`SPARSE`] filled. Scattered evenly, with no empty
/// slab between groups to leave out: a grid of cells the spheres' size spans some 800 cells a
/// sphere.
pub fn sparse(n: u32, seed: u64) -> SceneDesc {
    walled_gas("sparse", n, seed, SPARSE)
}

/// The [`gas`] of `n` spheres named `name` with one lattice site in `sites` filled.
fn walled_gas(name: &str, n: u32, seed: u64, sites: u32) -> SceneDesc {
    walled_gas_at(name, n, seed, sites, 0.0)
}

/// How far out [`far_gas`] lies on each axis, in metres: 2e9 cells of its spheres' size, past
/// the two billion cells a grid counted from the origin can number.
pub const FAR: f64 = 2.0e8;

/// The [`gas`] of `n` spheres moved [`FAR`] metres out along each axis: its cost per sphere
/// should be the gas's (until the fifty-sixth session its cells were all clamped to one, and
/// every two spheres were compared: 2000 of them stepped 28 times slower).
pub fn far_gas(n: u32, seed: u64) -> SceneDesc {
    walled_gas_at("far gas", n, seed, 4, FAR)
}

/// [`walled_gas`] centred at `at` on every axis.
fn walled_gas_at(name: &str, n: u32, seed: u64, sites: u32, at: f64) -> SceneDesc {
    let side = side_for(f64::from(sites) * f64::from(n));
    SceneDesc::from_ron(&format!(
        "(name: \"{name} {n}\", gravity: (0.0, 0.0, 0.0), restitution: 1.0,
          generate: [Gas(count: {n}, seed: {seed}, min: ({lo:?}, {lo:?}, {lo:?}),
                         max: ({hi:?}, {hi:?}, {hi:?}), radius: {RADIUS:?}, speed: 1.0)])",
        lo = at - side / 2.0,
        hi = at + side / 2.0,
    ))
    .expect("the gas scenes are valid")
}

/// The distance between [`apart`]'s two groups, in metres.
pub const APART: f64 = 1000.0;

/// `n` spheres as two gases of half as many (`seed` and `seed + 1`; the first takes the odd
/// one), each as the [`gas`] of its count would be (its box, lattice and speed), the two boxes
/// [`APART`] metres apart along x, with no walls (over a second a gas spreads by a metre):
/// groups of spheres far apart, which one block of grid cells cannot span without squeezing
/// out the empty space between them.
pub fn apart(n: u32, seed: u64) -> SceneDesc {
    let half = n / 2;
    let side = side_for(4.0 * f64::from(n - half));
    let gas = |count: u32, seed: u64, x: f64| {
        format!(
            "Gas(count: {count}, seed: {seed}, min: ({x0:?}, {lo:?}, {lo:?}),
                 max: ({x1:?}, {hi:?}, {hi:?}), radius: {RADIUS:?}, speed: 1.0, walls: false)",
            x0 = x - side / 2.0,
            x1 = x + side / 2.0,
            lo = -side / 2.0,
            hi = side / 2.0,
        )
    };
    SceneDesc::from_ron(&format!(
        "(name: \"apart {n}\", gravity: (0.0, 0.0, 0.0), restitution: 1.0,
          generate: [{}, {}])",
        gas(n - half, seed, 0.0),
        gas(half, seed + 1, APART)
    ))
    .expect("the apart scene is valid")
}

/// `n` spheres of radius 0.05 (restitution 0.5) dropped into an open box under gravity: a
/// lattice 16 cells deep, one cell in two filled, over a square floor sized so that the pile
/// is as deep at every `n` (about six spheres), walled on four sides. The floor and walls are
/// fixed spheres of radius 1e4 touching the box's faces. The spheres land within about 0.6 s
/// and then jostle in a dense bed: a ball pit, the case an event-driven engine finds hardest
/// (every sphere collides many times per step).
pub fn pile(n: u32, seed: u64) -> SceneDesc {
    let cell = 2.0 * RADIUS * 1.1;
    let layers = 16.0;
    let across = (2.0 * f64::from(n) / layers).sqrt().ceil();
    let (half, height) = (0.5 * cell * across, cell * layers);
    let wall = 1.0e4;
    let walls = [
        ("floor", [0.0, -wall, 0.0]),
        ("wall x-", [-half - wall, 0.0, 0.0]),
        ("wall x+", [half + wall, 0.0, 0.0]),
        ("wall z-", [0.0, 0.0, -half - wall]),
        ("wall z+", [0.0, 0.0, half + wall]),
    ]
    .map(|(name, [x, y, z])| {
        format!(
            "(name: \"{name}\", position: ({x:?}, {y:?}, {z:?}), radius: {wall:?}, fixed: true)"
        )
    })
    .join(", ");
    SceneDesc::from_ron(&format!(
        "(name: \"pile {n}\", gravity: (0.0, -9.81, 0.0), restitution: 0.5,
          spheres: [{walls}],
          generate: [Shower(count: {n}, seed: {seed}, min: ({lo:?}, 0.0, {lo:?}),
                            max: ({hi:?}, {height:?}, {hi:?}), radius: {RADIUS:?})])",
        lo = -half,
        hi = half,
    ))
    .expect("the pile scene is valid")
}

/// The share of [`table`]'s floor its spheres cover.
pub const TABLE_COVER: f64 = 0.25;

/// `n` spheres of radius 0.05 (restitution 0.9) resting on a floor under gravity, a quarter of
/// it covered, each sliding at 1 m/s in a random horizontal direction (frictionless: they
/// slide, they do not roll), in a square walled box: marbles or billiards, spheres that rest
/// on the ground while they meet one another, a game's usual case under gravity. One sphere to
/// each cell of a square lattice (three and a half diameters apart), jittered within it. The
/// floor and walls are fixed spheres of radius 1e4 touching the box's faces, as the
/// [`pile`]'s; each sphere starts touching the floor (its centre `RADIUS` above the floor's
/// curved surface), so every sphere has a resting contact at every step.
pub fn table(n: u32, seed: u64) -> SceneDesc {
    let wall = 1.0e4;
    let spacing = (std::f64::consts::PI * RADIUS * RADIUS / TABLE_COVER).sqrt();
    let across = f64::from(n).sqrt().ceil() as u32;
    let half = 0.5 * spacing * f64::from(across);
    // splitmix64: the jitter and the directions, the same for a seed on every machine.
    let mut state = seed;
    let mut uniform = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as f64 / (u64::MAX as f64 + 1.0)
    };
    let fixed = |name: &str, position: [f64; 3]| SphereSpec {
        name: Some(name.to_owned()),
        position,
        velocity: [0.0; 3],
        radius: wall,
        density: 1.0,
        restitution: None,
        force: [0.0; 3],
        fixed: true,
        tether: None,
        never_sleeps: false,
    };
    let mut spheres = vec![
        fixed("floor", [0.0, -wall, 0.0]),
        fixed("wall x-", [-half - wall, 0.0, 0.0]),
        fixed("wall x+", [half + wall, 0.0, 0.0]),
        fixed("wall z-", [0.0, 0.0, -half - wall]),
        fixed("wall z+", [0.0, 0.0, half + wall]),
    ];
    let room = 0.5 * spacing - RADIUS * 1.01;
    for k in 0..n {
        let (i, j) = (k % across, k / across);
        let at = |cell: u32| -half + spacing * (f64::from(cell) + 0.5);
        let x = at(i) + room * (2.0 * uniform() - 1.0);
        let z = at(j) + room * (2.0 * uniform() - 1.0);
        let angle = std::f64::consts::TAU * uniform();
        // On the floor's sphere: its top is at 0, and 1e4 m of radius falls away by
        // (x² + z²) / 2e4 at (x, z).
        let y = ((wall + RADIUS).powi(2) - x * x - z * z).sqrt() - wall;
        spheres.push(SphereSpec {
            name: None,
            position: [x, y, z],
            velocity: [angle.cos(), 0.0, angle.sin()],
            radius: RADIUS,
            density: 1.0,
            restitution: None,
            force: [0.0; 3],
            fixed: false,
            tether: None,
            never_sleeps: false,
        });
    }
    SceneDesc {
        name: format!("table {n}"),
        description: String::new(),
        gravity: [0.0, -9.81, 0.0],
        restitution: 0.9,
        method: None,
        integrator: None,
        dt: None,
        substeps: None,
        sleep: None,
        spheres,
        generate: Vec::new(),
        view: None,
    }
}

/// Adds to `scene` a ball of radius 0.05 dropped from 1 m onto a fixed sphere of radius 0.1
/// whose top is 6.1 m above the origin, both of restitution 1, the ball exactly above the
/// sphere's centre: it bounces straight up and down for ever, far above the scenes' beds
/// (the pile's is under a metre deep). A world with one sphere that never sleeps, as a game's
/// always has something moving.
pub fn add_bouncer(scene: &mut SceneDesc) {
    let sphere = |name: &str, y: f64, radius: f64, fixed: bool| SphereSpec {
        name: Some(name.to_owned()),
        position: [0.0, y, 0.0],
        velocity: [0.0; 3],
        radius,
        density: 1.0,
        restitution: Some(1.0),
        force: [0.0; 3],
        fixed,
        tether: None,
        never_sleeps: false,
    };
    scene
        .spheres
        .push(sphere("bouncer's stand", 6.0, 0.1, true));
    scene.spheres.push(sphere("bouncer", 7.15, 0.05, false));
}

//! Spheres scattered evenly and far apart (a metre or more between neighbours, no empty slab to
//! squeeze out) would need a grid block of hundreds of cells a sphere; the broad phase then
//! makes its cells up to eight times larger on each side instead of sending most of them to
//! its general tier, and goes back to cells of the spheres' size if the larger ones would
//! crowd a dense group among them. Every meeting must still be found wherever the larger
//! cells' edges fall, in the step's first pass and in the queries after an impact: here
//! triples, a head-on pair closing its gap within the first step and a third sphere at rest
//! just behind one of them, which only that sphere's rebound reaches (a query the grid got
//! wrong would let it pass into the third), scattered at every density from a lattice a
//! metre apart to one triple in thousands of cubic metres, alone and around a dense group.

mod common;

use common::{head_on_lattice, head_on_pair};
use proptest::prelude::*;
use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const RADIUS: f64 = 0.1;
const SPEED: f64 = 1.0;
const GAP: f64 = 0.004;
/// Between the pair's first sphere and the third, at rest behind it.
const BEHIND: f64 = 0.005;
const DT: f64 = 1.0 / 60.0;
const AXES: [DVec3; 3] = [DVec3::X, DVec3::Y, DVec3::Z];

/// A head-on pair around `centre` along `axis` and a sphere at rest [`BEHIND`] the first.
fn triple(centre: DVec3, axis: DVec3) -> [SphereDesc; 3] {
    let [a, b] = head_on_pair(centre, axis, RADIUS, GAP, SPEED);
    let behind = SphereDesc::new(RADIUS).at(a.position - axis * (2.0 * RADIUS + BEHIND));
    [a, b, behind]
}

/// Steps `triples` and head-on `pairs` (equal masses, elastic, no gravity) once and checks
/// that each triple passed its blow on (the pair's first sphere at rest, the second moving
/// away, the third moving off with the first's rebound) and each pair collided: two
/// collisions a triple and one a pair, no overlap. Says what is wrong, if anything.
fn step_triples(triples: &[[SphereDesc; 3]], pairs: &[[SphereDesc; 2]]) -> Result<(), String> {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let ids: Vec<_> = triples
        .iter()
        .map(|t| t.clone().map(|s| world.add_sphere(s).unwrap()))
        .collect();
    for s in pairs.iter().flatten() {
        world.add_sphere(s.clone()).unwrap();
    }
    let stats = *world.step(DT).unwrap();
    let expected = 2 * triples.len() + pairs.len();
    if stats.collisions as usize != expected {
        return Err(format!("{} collisions, not {expected}", stats.collisions));
    }
    if stats.max_overlap > 1e-12 {
        return Err(format!("overlap {}", stats.max_overlap));
    }
    for (ids, [a, b, _]) in ids.iter().zip(triples) {
        let v = ids.map(|id| world.body(id).unwrap().velocity());
        if (v[0].length() + (v[1] - a.velocity).length() + (v[2] - b.velocity).length()) > 1e-12 {
            return Err(format!("velocities {v:?} in the triple at {}", a.position));
        }
    }
    Ok(())
}

/// Triples on `side`³ lattice sites `spacing` apart (at least a metre) from `origin`, every
/// site taken, along x, y and z in turn, each site shifted by a different fraction of the
/// spacing (so that they fall at every place within a cell, large or small).
fn lattice(origin: DVec3, side: u32, spacing: f64) -> Vec<[SphereDesc; 3]> {
    let mut triples = Vec::new();
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                let n = triples.len() as f64;
                // Fractions spread evenly over [0, 1) (multiples of irrational numbers).
                let shift = DVec3::new(
                    (n * 0.618_033_988_7).fract(),
                    (n * 0.754_877_666_2).fract(),
                    (n * 0.569_840_290_9).fract(),
                ) * (spacing - 0.9);
                let site = DVec3::new(f64::from(i), f64::from(j), f64::from(k)) * spacing;
                let axis = AXES[(i + j + k) as usize % 3];
                triples.push(triple(origin + site + shift, axis));
            }
        }
    }
    triples
}

/// Head-on pairs 0.3 m apart, 6 by 6 by 6, from `origin`: a dense group.
fn dense_pairs(origin: DVec3) -> Vec<[SphereDesc; 2]> {
    head_on_lattice(origin, 6, 0.3, RADIUS, GAP, SPEED)
}

#[test]
fn triples_scattered_evenly_pass_their_blows_on_at_every_spacing() {
    // From a block of under 64 cells a sphere (1 m) through cells two, four and eight times
    // larger to a scatter too thin even for those (40 m: the block trimmed, its edges sent to
    // the general tier).
    for spacing in [1.0, 2.0, 3.0, 5.0, 8.0, 13.0, 40.0] {
        let triples = lattice(DVec3::new(-7.3, 2.1, 0.4), 6, spacing);
        step_triples(&triples, &[]).unwrap_or_else(|e| panic!("spacing {spacing} m: {e}"));
    }
}

#[test]
fn a_dense_group_among_scattered_spheres_is_found_whole() {
    // A dense group of pairs (the larger cells would hold dozens of its spheres each) in a
    // thin scatter of triples.
    for spacing in [2.0, 5.0, 13.0] {
        let group = dense_pairs(DVec3::new(0.35, -0.2, 0.1));
        let triples = lattice(DVec3::new(-20.0, -15.0, -10.0), 5, spacing);
        step_triples(&triples, &group)
            .unwrap_or_else(|e| panic!("group in spacing {spacing} m: {e}"));
    }
}

proptest! {
    #![proptest_config(common::proptest_config(48, common::SEED))]
    /// 22 to 150 triples on random sites of a lattice 12 sites a side, `spacing` apart (1 m
    /// to 30 m), each shifted at random within its site, with or without a dense group of 216
    /// head-on pairs 0.3 m apart at one corner: every triple passes its blow on, and every
    /// pair collides.
    #[test]
    fn scattered_triples_pass_their_blows_on(
        scattered in prop::collection::vec(
            (0usize..1728, [0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64], 0usize..3),
            22..150,
        ),
        spacing in 1.0..30.0f64,
        group in any::<bool>(),
    ) {
        let mut taken = [false; 1728];
        let mut triples = Vec::new();
        for &(site, shift, axis) in &scattered {
            if std::mem::replace(&mut taken[site], true) {
                continue;
            }
            let at = DVec3::new((site % 12) as f64, (site / 12 % 12) as f64, (site / 144) as f64);
            let shift = DVec3::from_array(shift) * (spacing - 0.9);
            triples.push(triple(at * spacing + shift, AXES[axis]));
        }
        let pairs = if group { dense_pairs(DVec3::splat(-3.0)) } else { Vec::new() };
        let checked = step_triples(&triples, &pairs);
        prop_assert!(checked.is_ok(), "{} triples, spacing {}: {:?}", triples.len(), spacing, checked);
    }
}

//! When a step's collision budget runs out (`Settings::max_collisions_per_body`), the rest of
//! the step is solved at once, as the resting contacts are: a crowd of spheres crushed
//! together (a ball of 343 spheres in zero gravity, every one moving towards the centre, with
//! a budget of one collision per sphere) keeps its momentum exactly, gains no energy, and ends
//! the step with no two spheres closer than touching.

mod common;

const DT: f64 = 1.0 / 60.0;

#[test]
fn a_crushed_crowd_keeps_its_momentum_and_gains_no_energy() {
    let mut world = common::crushed_crowd(1);
    let (momentum, energy) = (world.momentum(), world.kinetic_energy());
    let stats = *world.step(DT).unwrap();
    assert!(stats.fell_back, "{stats:?}");
    let scale = world
        .bodies()
        .iter()
        .map(|b| b.momentum().length())
        .sum::<f64>();
    assert!(
        (world.momentum() - momentum).length() <= 1e-12 * scale,
        "{} -> {}",
        momentum,
        world.momentum()
    );
    assert!(
        world.kinetic_energy() <= energy,
        "{energy} -> {}",
        world.kinetic_energy()
    );
    assert!(world.bodies().iter().all(|b| b.position().is_finite()));
    // The solve stops each pair half a contact band short of touching, give or take how far
    // its sweeps converge: none is deeper than the band (the bound was 1e-3 m, 2% of a
    // radius, until a review).
    let deepest = common::deepest_beyond_band(&world);
    assert!(deepest <= 0.0, "{deepest:e} beyond the band; {stats:?}");
}

#[test]
fn the_same_crowd_with_the_budget_it_needs_falls_back_never() {
    let mut world = common::crushed_crowd(65_536);
    let stats = *world.step(DT).unwrap();
    assert!(!stats.fell_back, "{stats:?}");
}

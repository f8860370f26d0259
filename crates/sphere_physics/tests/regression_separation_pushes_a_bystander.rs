//! Regression: under gravity, the separation that moves a pair with a sphere on a string back
//! to 2% of the smaller radius at a step's end moved the pair's other sphere into a third one
//! and left it there.
//!
//! Found by `sphere-fuzz --strings fast` at seed 21 002: a sphere of 0.1 g on a string of 24
//! cm, whipped round at up to 146 m/s by a free one of 634 kg that swallows its anchor,
//! ended a step deep in it; the separation moved the large sphere back by up to a tenth of its
//! radius (the small one, held by its string, takes none of such a move), into a free sphere
//! of 0.7 g resting against it, which ended the step 35% of its radius deep. Under gravity a
//! pair without a string was never moved, so nothing undid what the move did. Now no pair is
//! left deeper by the separation than the step left it: the sphere pushed is carried as far
//! as the larger cap of the two (what one's cap leaves undone the other takes), so here the
//! third sphere is carried along and the strung pair is back at 2% after the first step.
//!
//! This is the fuzz scene reduced to its three spheres, placed so: the large sphere (radius
//! 0.7 m, 575 kg) free, a small one (radius 5 cm, 0.1 g) hanging on a string of 24 cm whose
//! anchor lies inside the large one, a radius of the small one into it, and a free sphere
//! (radius 4.7 cm) 5 mm above the large one. Before, the first step's separation left the
//! third sphere 88% of its radius into the large one (and with the third sphere moved back
//! only as far as its own cap let it, a tenth of its radius, the strung pair took five steps
//! to come apart).

use sphere_physics::glam::DVec3;
use sphere_physics::{Body, BodyId, Settings, SphereDesc, World};

/// How deep `a` and `b` are into each other, as a fraction of the smaller radius.
fn depth(world: &World, a: BodyId, b: BodyId) -> f64 {
    let (a, b): (&Body, &Body) = (world.body(a).unwrap(), world.body(b).unwrap());
    (a.radius() + b.radius() - (b.position() - a.position()).length()) / a.radius().min(b.radius())
}

#[test]
fn regression_the_separation_does_not_push_a_strung_pairs_sphere_into_a_third() {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    let (big, small, length) = (0.7, 0.05, 0.24);
    let hanging = DVec3::new(0.0, -big, 0.0);
    let anchor = hanging + DVec3::Y * length;
    let large = world
        .add_sphere(SphereDesc::new(big).with_density(400.0))
        .unwrap();
    let strung = world
        .add_sphere(
            SphereDesc::new(small)
                .at(hanging)
                .with_density(0.2)
                .tethered(anchor, length),
        )
        .unwrap();
    let third = world
        .add_sphere(SphereDesc::new(0.047).at(DVec3::new(0.0, big + 0.047 + 0.005, 0.0)))
        .unwrap();
    assert!((depth(&world, large, strung) - 1.0).abs() < 1e-12);

    let mut apart_from = None;
    for step in 0..8 {
        world.step(1.0 / 60.0).unwrap();
        for body in world.bodies() {
            assert!(body.position().is_finite() && body.velocity().is_finite());
        }
        let to_anchor = (world.body(strung).unwrap().position() - anchor).length();
        assert!(
            to_anchor <= length * (1.0 + 1e-9),
            "step {step}: {to_anchor}"
        );
        let pushed = depth(&world, large, third);
        assert!(
            pushed <= 0.02,
            "step {step}: the third sphere {pushed} deep"
        );
        let pair = depth(&world, large, strung);
        if apart_from.is_some() {
            assert!(
                pair <= 0.02 + 1e-9,
                "step {step}: the strung pair {pair} deep again"
            );
        } else if pair <= 0.02 + 1e-9 {
            apart_from = Some(step);
        }
    }
    assert_eq!(
        apart_from,
        Some(0),
        "the strung pair apart from step {apart_from:?}"
    );
}

//! `World::remove_bodies`: many bodies out of the world in one pass, the same as removing
//! them one by one with `World::remove_body`, in any order.

mod common;

use proptest::prelude::*;
use sphere_physics::{BodyId, Settings, Sleep, SphereDesc, World, glam::DVec3};

const DT: f64 = 1.0 / 60.0;

/// Marbles on a floor of radius 1e4 (some touching in pairs), sleeping on, stepped `settle`
/// steps (some asleep, some awake, some falling), and a ball falling onto them; and the id
/// of a body added and removed (of no body).
fn marbles(count: usize, settle: u32) -> (World, BodyId) {
    let (mut world, _) = common::sleeping_on_a_floor(1e4);
    for k in 0..count {
        let (x, z) = ((k % 8) as f64 * 0.3, (k / 8) as f64 * 0.3);
        let at = DVec3::new(x, 0.05 + 0.01 * (k % 3) as f64, z);
        world.add_sphere(SphereDesc::new(0.05).at(at)).unwrap();
        if k % 4 == 0 {
            world
                .add_sphere(SphereDesc::new(0.05).at(at + DVec3::X * 0.1))
                .unwrap();
        }
    }
    // Fixed stands beside them in a row, each with a marble on it.
    for k in 0..12 {
        let at = DVec3::new(-0.5, 0.0, 0.3 * f64::from(k));
        world
            .add_sphere(SphereDesc::new(0.1).at(at).fixed())
            .unwrap();
        world
            .add_sphere(SphereDesc::new(0.05).at(at + DVec3::Y * 0.15))
            .unwrap();
    }
    for _ in 0..settle {
        world.step(DT).unwrap();
    }
    world
        .add_sphere(SphereDesc::new(0.05).at(DVec3::new(0.3, 0.5, 0.3)))
        .unwrap();
    let ghost = world.add_sphere(SphereDesc::new(0.05)).unwrap();
    world.remove_body(ghost).unwrap();
    (world, ghost)
}

fn state(world: &World) -> String {
    format!("{:?} {:?}", world.bodies(), world.stats())
}

proptest! {
    #![proptest_config(common::proptest_config(24, common::SEED))]

    /// Any bodies (fixed ones, the floor, stands with the marbles on them, bodies asleep
    /// and awake, ids of no body and ids given twice among them) removed at once leave the
    /// same world as removed one by one in any order, return the same bodies, and the steps
    /// after are the same, bit for bit.
    #[test]
    fn removing_at_once_is_removing_one_by_one(
        count in 40usize..80,
        settle in prop_oneof![0u32..10, 100u32..200],
        picks in proptest::collection::vec(0usize..130, 0..60),
        stands in any::<bool>(),
        order in proptest::collection::vec(any::<u32>(), 80),
    ) {
        let (mut at_once, ghost) = marbles(count, settle);
        let (mut one_by_one, _) = marbles(count, settle);
        prop_assert_eq!(state(&at_once), state(&one_by_one));
        // Picks past the last body are the id of no body; and, in half the cases, every
        // stand (more than the few whose neighbours are looked for one by one).
        let mut ids: Vec<BodyId> = picks
            .iter()
            .map(|&k| at_once.bodies().get(k).map_or(ghost, |b| b.id()))
            .collect();
        if stands {
            ids.extend(
                at_once
                    .bodies()
                    .iter()
                    .filter(|b| b.is_fixed() && b.radius() < 1.0)
                    .map(|b| b.id()),
            );
        }
        let removed = at_once.remove_bodies(&ids);
        let mut expected: Vec<BodyId> = ids.iter().copied().filter(|&id| id != ghost).collect();
        expected.sort_unstable();
        expected.dedup();
        prop_assert_eq!(removed.iter().map(|b| b.id()).collect::<Vec<_>>(), expected);
        // One by one, in a shuffled order.
        let mut shuffled = ids.clone();
        for (k, &r) in order.iter().enumerate().take(shuffled.len()) {
            let j = k + r as usize % (shuffled.len() - k);
            shuffled.swap(k, j);
        }
        let mut one_by_one_removed: Vec<_> =
            shuffled.into_iter().filter_map(|id| one_by_one.remove_body(id)).collect();
        one_by_one_removed.sort_by_key(|b| b.id());
        prop_assert_eq!(format!("{removed:?}"), format!("{one_by_one_removed:?}"));
        prop_assert_eq!(state(&at_once), state(&one_by_one));
        for step in 0..90 {
            at_once.step(DT).unwrap();
            one_by_one.step(DT).unwrap();
            prop_assert_eq!(state(&at_once), state(&one_by_one), "step {}", step);
        }
    }
}

/// Removing nothing, or ids of no body, changes nothing.
#[test]
fn removing_no_body_changes_nothing() {
    let mut world = World::new(Settings {
        sleep: Some(Sleep::default()),
        ..Settings::default()
    });
    let id = world.add_sphere(SphereDesc::new(1.0)).unwrap();
    assert!(world.remove_bodies(&[]).is_empty());
    world.remove_body(id).unwrap();
    assert!(world.remove_bodies(&[id, id]).is_empty());
    assert!(world.remove_body(id).is_none());
    assert!(world.is_empty());
}

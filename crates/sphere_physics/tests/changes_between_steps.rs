//! A world changed through its public API between steps, at random: spheres added, removed,
//! replaced, moved, pushed and woken, settings changed (gravity, sleeping, substeps, the
//! collision budget, the time-of-impact method), good values and bad. Every call that is
//! refused must leave the world as it was, and leave no trace a later step shows (the same
//! calls without the refused ones give the same world); nothing may panic; every step leaves
//! finite motion, asleep spheres without speed, and the statistics agreeing with the bodies;
//! and the same calls give the same world, bit for bit. (Removing a sphere that others rested on once crashed the
//! next step: `regression_removing_a_body_under_load.rs`.)

mod common;

use proptest::prelude::*;
use sphere_physics::glam::DVec3;
use sphere_physics::{
    BodyId, CombineRule, IntegratorKind, Settings, Sleep, SphereDesc, ToiMethod, World, WorldError,
};

/// A value for a field: good, or one of the ways it can be bad.
#[derive(Clone, Debug)]
enum Value {
    Good(f64),
    Nan,
    Infinite,
    Negative,
    Zero,
}

impl Value {
    fn get(&self) -> f64 {
        match *self {
            Value::Good(v) => v,
            Value::Nan => f64::NAN,
            Value::Infinite => f64::INFINITY,
            Value::Negative => -1.0,
            Value::Zero => 0.0,
        }
    }
}

fn good(range: std::ops::Range<f64>) -> impl Strategy<Value = Value> {
    range.prop_map(Value::Good)
}

/// Mostly good, now and then bad.
fn value(range: std::ops::Range<f64>) -> impl Strategy<Value = Value> {
    prop_oneof![
        12 => good(range),
        1 => Just(Value::Nan),
        1 => Just(Value::Infinite),
        1 => Just(Value::Negative),
        1 => Just(Value::Zero),
    ]
}

fn vector(scale: f64) -> impl Strategy<Value = DVec3> {
    (-scale..scale, -scale..scale, -scale..scale).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// A vector, now and then with a component that is not finite.
fn maybe_bad_vector(scale: f64) -> impl Strategy<Value = DVec3> {
    prop_oneof![
        12 => vector(scale),
        1 => vector(scale).prop_map(|v| DVec3::new(f64::NAN, v.y, v.z)),
        1 => vector(scale).prop_map(|v| DVec3::new(v.x, f64::INFINITY, v.z)),
    ]
}

#[derive(Clone, Debug)]
struct Desc {
    radius: Value,
    density: Value,
    restitution: Value,
    position: DVec3,
    velocity: DVec3,
    force: DVec3,
    fixed: bool,
    tether: Option<(DVec3, Value)>,
}

impl Desc {
    fn build(&self) -> SphereDesc {
        let mut desc = SphereDesc::new(self.radius.get())
            .at(self.position)
            .moving(self.velocity)
            .with_density(self.density.get())
            .with_restitution(self.restitution.get())
            .with_force(self.force);
        if self.fixed {
            desc = desc.fixed();
        }
        if let Some((anchor, length)) = &self.tether {
            desc = desc.tethered(*anchor, length.get());
        }
        desc
    }
}

/// Spheres of 0.03 to 0.12 over the pit (and now and then beside it), mostly slow.
fn desc() -> impl Strategy<Value = Desc> {
    (
        value(0.03..0.12),
        value(0.5..20.0),
        prop_oneof![
            good(0.0..1.0),
            Just(Value::Good(1.0)),
            Just(Value::Nan),
            Just(Value::Good(1.5))
        ],
        (vector(0.4), 0.0..1.5).prop_map(|(v, y)| DVec3::new(v.x, y, v.z)),
        prop_oneof![4 => vector(1.0), 1 => vector(20.0), 1 => maybe_bad_vector(1.0)],
        prop_oneof![6 => Just(DVec3::ZERO), 1 => maybe_bad_vector(30.0)],
        prop::bool::weighted(0.1),
        prop::option::weighted(0.15, (vector(1.5), value(0.3..2.0))),
    )
        .prop_map(
            |(radius, density, restitution, position, velocity, force, fixed, tether)| Desc {
                radius,
                density,
                restitution,
                position,
                velocity,
                force,
                fixed,
                tether,
            },
        )
}

#[derive(Clone, Debug)]
enum Op {
    Add(Desc),
    /// Ids are picked among every id ever handed out (removed ones too), by index modulo.
    Remove(usize),
    SetDesc(usize, Desc),
    SetVelocity(usize, DVec3),
    SetPosition(usize, DVec3),
    SetForce(usize, DVec3),
    Wake(usize),
    Gravity(DVec3),
    Sleep(Option<(Value, Value)>),
    Substeps(u32),
    Budget(u32),
    Method(Option<u32>),
    Integrator(bool),
    Combine(u8),
    Resting(Value),
    Creep(Value),
    Step(Value),
    Steps(u32),
}

fn op() -> impl Strategy<Value = Op> {
    let id = 0..64usize;
    prop_oneof![
        6 => desc().prop_map(Op::Add),
        3 => id.clone().prop_map(Op::Remove),
        2 => (id.clone(), desc()).prop_map(|(i, d)| Op::SetDesc(i, d)),
        2 => (id.clone(), maybe_bad_vector(5.0)).prop_map(|(i, v)| Op::SetVelocity(i, v)),
        2 => (id.clone(), maybe_bad_vector(0.4)).prop_map(|(i, v)| Op::SetPosition(i, v)),
        1 => (id.clone(), maybe_bad_vector(30.0)).prop_map(|(i, v)| Op::SetForce(i, v)),
        1 => id.prop_map(Op::Wake),
        1 => prop_oneof![
            Just(DVec3::new(0.0, -9.81, 0.0)),
            Just(DVec3::ZERO),
            maybe_bad_vector(20.0),
        ]
        .prop_map(Op::Gravity),
        2 => prop::option::of((value(0.05..0.5), value(0.1..1.0))).prop_map(Op::Sleep),
        1 => prop_oneof![Just(1u32), 2..5u32, Just(0u32)].prop_map(Op::Substeps),
        1 => prop_oneof![Just(16u32), 1..4u32, Just(0u32)].prop_map(Op::Budget),
        1 => prop::option::of(prop_oneof![0..16u32, Just(65u32)]).prop_map(Op::Method),
        1 => any::<bool>().prop_map(Op::Integrator),
        1 => (0..4u8).prop_map(Op::Combine),
        1 => value(0.0..3.0).prop_map(Op::Resting),
        1 => prop_oneof![good(0.0..0.1), Just(Value::Good(2.0)), Just(Value::Nan)].prop_map(Op::Creep),
        8 => prop_oneof![
            8 => good(0.004..0.05),
            1 => Just(Value::Nan),
            1 => Just(Value::Zero),
            1 => Just(Value::Negative),
        ]
        .prop_map(Op::Step),
        4 => (1..90u32).prop_map(Op::Steps),
    ]
}

/// Everything a refused call must leave as it was.
fn snapshot(world: &World) -> String {
    format!(
        "{:?} {:?} {} {} {:?} {:?}",
        world.bodies(),
        world.settings(),
        world.time(),
        world.steps(),
        world.stats(),
        world.collisions()
    )
}

/// The world after a step: finite, asleep spheres still, the statistics true.
fn check_step(world: &mut World) -> Result<(), TestCaseError> {
    let mut asleep = 0;
    for body in world.bodies() {
        prop_assert!(
            body.position().is_finite() && body.velocity().is_finite(),
            "{body:?}"
        );
        if body.is_asleep() {
            asleep += 1;
            prop_assert!(!body.is_fixed(), "{body:?}");
            prop_assert_eq!(body.velocity(), DVec3::ZERO, "{:?}", body);
        }
    }
    let stats = *world.stats();
    prop_assert_eq!(stats.asleep, asleep);
    prop_assert!(stats.kinetic_energy.is_finite() && stats.momentum.is_finite());
    prop_assert_eq!(stats.kinetic_energy, world.kinetic_energy());
    prop_assert_eq!(stats.momentum, world.momentum());
    prop_assert_eq!(stats.max_overlap, world.max_overlap());
    Ok(())
}

/// A pit of `count` spheres (and its floor and walls) after `settle` steps of 1/60 s, with
/// sleeping on or off.
#[derive(Clone, Debug)]
struct Start {
    count: u32,
    seed: u64,
    restitution: f64,
    sleep: Option<Sleep>,
    settle: u32,
}

fn start() -> impl Strategy<Value = Start> {
    (
        5u32..60,
        0u64..1000,
        0.0..0.9f64,
        prop::option::weighted(
            0.7,
            prop_oneof![
                Just(Sleep::default()),
                (0.05..0.3f64, 0.1..0.5f64).prop_map(|(speed, time)| Sleep { speed, time })
            ],
        ),
        prop_oneof![Just(0u32), 0..60u32, 60..400u32],
    )
        .prop_map(|(count, seed, restitution, sleep, settle)| Start {
            count,
            seed,
            restitution,
            sleep,
            settle,
        })
}

/// Applies `ops` to the pit of `start`, checking as it goes; returns the world's snapshot and,
/// for each op, whether it was refused whole (every call it made returned an error or `None`).
fn play(start: &Start, ops: &[Op]) -> Result<(String, Vec<bool>), TestCaseError> {
    let mut world = common::pit(start.count, start.seed, start.restitution, 0.05, 1.0);
    world.settings_mut().sleep = start.sleep;
    for _ in 0..start.settle {
        let before = snapshot(&world);
        step(&mut world, 1.0 / 60.0, &before)?;
    }
    let mut ids: Vec<BodyId> = world.bodies().iter().map(|b| b.id()).collect();
    let mut live = ids.clone();
    let pick = |ids: &[BodyId], i: usize| ids[i % ids.len()];
    let mut refusals = Vec::with_capacity(ops.len());
    for op in ops {
        let before = snapshot(&world);
        // `Err` from a call: it must have changed nothing.
        let refused =
            |world: &World, result: Result<(), WorldError>| -> Result<bool, TestCaseError> {
                if let Err(error) = &result {
                    prop_assert_eq!(snapshot(world), before.clone(), "{}", error);
                }
                Ok(result.is_err())
            };
        let was_refused = match op {
            Op::Add(desc) => match world.add_sphere(desc.build()) {
                Ok(id) => {
                    ids.push(id);
                    live.push(id);
                    false
                }
                Err(error) => {
                    prop_assert_eq!(snapshot(&world), before, "{}", error);
                    true
                }
            },
            Op::Remove(i) => {
                let id = pick(&ids, *i);
                let removed = world.remove_body(id);
                prop_assert_eq!(removed.is_some(), live.contains(&id));
                if removed.is_none() {
                    prop_assert_eq!(snapshot(&world), before);
                }
                live.retain(|&l| l != id);
                removed.is_none()
            }
            Op::SetDesc(i, desc) => {
                let result = world.set_desc(pick(&ids, *i), desc.build());
                refused(&world, result)?
            }
            Op::SetVelocity(i, v) => {
                let result = world.set_velocity(pick(&ids, *i), *v);
                refused(&world, result)?
            }
            Op::SetPosition(i, v) => {
                let result = world.set_position(pick(&ids, *i), *v);
                refused(&world, result)?
            }
            Op::SetForce(i, v) => {
                let result = world.set_force(pick(&ids, *i), *v);
                refused(&world, result)?
            }
            Op::Wake(i) => {
                let id = pick(&ids, *i);
                let result = world.wake(id);
                prop_assert_eq!(result.is_ok(), live.contains(&id));
                let was_refused = refused(&world, result)?;
                if let Some(body) = world.body(id) {
                    prop_assert!(!body.is_asleep());
                }
                was_refused
            }
            Op::Step(dt) => !step(&mut world, dt.get(), &before)?,
            Op::Steps(n) => {
                let mut taken = false;
                for _ in 0..*n {
                    let before = snapshot(&world);
                    taken |= step(&mut world, 1.0 / 60.0, &before)?;
                }
                !taken
            }
            setting => {
                change_setting(world.settings_mut(), setting);
                false
            }
        };
        refusals.push(was_refused);
        prop_assert_eq!(world.len(), live.len());
        for id in &ids {
            prop_assert_eq!(world.body(*id).is_some(), live.contains(id));
        }
    }
    Ok((snapshot(&world), refusals))
}

/// Applies an op that changes a setting (which is never refused: a bad setting refuses the next
/// step instead).
fn change_setting(settings: &mut Settings, op: &Op) {
    match op {
        Op::Gravity(g) => settings.gravity = *g,
        Op::Sleep(sleep) => {
            settings.sleep = sleep.as_ref().map(|(speed, time)| Sleep {
                speed: speed.get(),
                time: time.get(),
            })
        }
        Op::Substeps(n) => settings.substeps = *n,
        Op::Budget(n) => settings.max_collisions_per_body = *n,
        Op::Method(m) => {
            settings.method = match m {
                None => ToiMethod::Exact,
                Some(max_iterations) => ToiMethod::Bisection {
                    max_iterations: *max_iterations,
                },
            }
        }
        Op::Integrator(leapfrog) => {
            settings.integrator = if *leapfrog {
                IntegratorKind::Leapfrog
            } else {
                IntegratorKind::SemiImplicitEuler
            }
        }
        Op::Combine(c) => {
            settings.restitution_combine = match c {
                0 => CombineRule::Min,
                1 => CombineRule::Max,
                2 => CombineRule::Average,
                _ => CombineRule::Multiply,
            }
        }
        Op::Resting(v) => settings.resting_factor = v.get(),
        Op::Creep(v) => settings.creep_fraction = v.get(),
        other => unreachable!("not a setting: {other:?}"),
    }
}

/// One step: taken and checked (`true`), or refused with nothing changed (`false`).
fn step(world: &mut World, dt: f64, before: &str) -> Result<bool, TestCaseError> {
    let valid = world.settings().validate().is_ok() && dt.is_normal() && dt > 0.0;
    match world.step(dt) {
        Ok(_) => {
            prop_assert!(
                valid,
                "a step of {} with {:?} was taken",
                dt,
                world.settings()
            );
            check_step(world)?;
            Ok(true)
        }
        Err(error) => {
            // A refused step changes nothing, and only bad input (or motion leaving the finite
            // range, which these scenes do not reach) is refused.
            prop_assert_eq!(snapshot(world), before, "{}", error);
            prop_assert!(!valid, "a valid step was refused: {}", error);
            Ok(false)
        }
    }
}

proptest! {
    #![proptest_config(common::proptest_config(32, common::SEED))]

    #[test]
    fn changes_between_steps_are_safe_and_repeat(
        start in start(),
        ops in prop::collection::vec(op(), 1..60),
    ) {
        let (first, refusals) = play(&start, &ops)?;
        let (second, _) = play(&start, &ops)?;
        prop_assert_eq!(&first, &second);
        // A refused call leaves no trace, not even in what the snapshot does not show (how long
        // each sphere has been calm, say): the same calls without the refused ones give the
        // same world.
        let taken: Vec<Op> = ops
            .iter()
            .zip(&refusals)
            .filter(|(_, refused)| !**refused)
            .map(|(op, _)| op.clone())
            .collect();
        let (without, _) = play(&start, &taken)?;
        prop_assert_eq!(first, without);
    }
}

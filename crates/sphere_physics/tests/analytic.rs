//! Analytic answers through the public API.
use sphere_physics::{
    Bisection, ExactToi, Settings, SphereDesc, TimeOfImpact, Tolerance, World, glam::DVec3,
};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

fn cradle(n: usize, striker_density: f64, reverse: bool) -> Vec<f64> {
    let mut world = World::new(Settings::default());
    let mut order: Vec<usize> = (0..n).collect();
    if reverse {
        order.reverse();
    }
    let mut ids = vec![None; n];
    for i in order {
        let (v, rho) = if i == 0 {
            (DVec3::X, striker_density)
        } else {
            (DVec3::ZERO, 1.0)
        };
        let desc = SphereDesc::new(0.5)
            .at(DVec3::new(i as f64, 0.0, 0.0))
            .moving(v)
            .with_density(rho);
        ids[i] = Some(world.add_sphere(desc).unwrap());
    }
    world.step(1.0 / 60.0).unwrap();
    ids.iter()
        .map(|id| world.body(id.unwrap()).unwrap().velocity().x)
        .collect()
}

#[test]
fn touching_cradle_sends_one_ball_out_any_order() {
    for n in [2, 3, 5, 12] {
        for reverse in [false, true] {
            let v = cradle(n, 1.0, reverse);
            assert_eq!(v[n - 1], 1.0, "n={n}");
            assert!(v[..n - 1].iter().all(|&x| x == 0.0), "n={n} {v:?}");
        }
    }
}

#[test]
fn double_mass_striker_gives_sequential_answer() {
    for reverse in [false, true] {
        let v = cradle(5, 2.0, reverse);
        let want = [1.0 / 81.0, 4.0 / 81.0, 4.0 / 27.0, 4.0 / 9.0, 4.0 / 3.0];
        for (got, want) in v.iter().zip(want) {
            assert!(close(*got, want, 1e-12), "{v:?}");
        }
    }
}

#[test]
fn head_on_elastic_density_ratios() {
    for (ra, rb) in [(1.0, 2.0), (1.0, 3.0), (2.0, 3.0), (1.0, 1e6)] {
        let mut world = World::new(Settings::default());
        let a = world
            .add_sphere(SphereDesc::new(0.5).moving(DVec3::X).with_density(ra))
            .unwrap();
        let b = world
            .add_sphere(
                SphereDesc::new(0.5)
                    .at(DVec3::new(1.5, 0.0, 0.0))
                    .moving(-DVec3::X)
                    .with_density(rb),
            )
            .unwrap();
        world.step(1.0).unwrap();
        let (ma, mb) = (ra, rb);
        // Analytic 1D elastic answer for va = +1, vb = -1.
        let va = (ma - 3.0 * mb) / (ma + mb);
        let vb = (3.0 * ma - mb) / (ma + mb);
        let got_a = world.body(a).unwrap().velocity().x;
        let got_b = world.body(b).unwrap().velocity().x;
        assert!(
            close(got_a, va, 1e-12) && close(got_b, vb, 1e-12),
            "{ra}:{rb}"
        );
        // Collision at t = 0.25 (gap 0.5 closing at 2): positions exact.
        let pa = 0.25 + va * 0.75;
        assert!(close(world.body(a).unwrap().position().x, pa, 1e-12));
    }
}

#[test]
fn fast_small_sphere_never_tunnels() {
    let mut world = World::new(Settings::default());
    let bullet = world
        .add_sphere(SphereDesc::new(0.01).moving(DVec3::new(1e5, 0.0, 0.0)))
        .unwrap();
    world
        .add_sphere(SphereDesc::new(0.01).at(DVec3::new(10.0, 0.0, 0.0)).fixed())
        .unwrap();
    let dt = 1.0 / 60.0;
    world.step(dt).unwrap();
    assert_eq!(world.stats().collisions, 1);
    // It strikes the fixed sphere at x = 9.98 (after 9.98e-5 s), elastically, and flies back
    // for the rest of the step.
    let body = world.body(bullet).unwrap();
    assert_eq!(body.velocity(), DVec3::new(-1e5, 0.0, 0.0));
    let x = 9.98 - 1e5 * (dt - 9.98e-5);
    assert!(close(body.position().x, x, 1e-12), "{}", body.position());
    assert_eq!(world.collisions()[0].time, 9.98e-5);
}

#[test]
fn exact_toi_mid_step_and_bisection_converges() {
    let tol = Tolerance::DEFAULT;
    let (d, w) = (DVec3::new(3.0, 0.0, 0.0), DVec3::new(-4.0, 0.0, 0.0));
    let exact = ExactToi.time_of_impact(d, w, 1.0, 1.0, tol).time.unwrap();
    assert!(close(exact, 0.5, 1e-15));
    let mut last = f64::INFINITY;
    for n in [4, 8, 16, 24] {
        let t = Bisection { max_iterations: n }
            .time_of_impact(d + DVec3::new(0.1, 0.0, 0.0), w, 1.0, 1.0, tol)
            .time
            .unwrap();
        let err = (t - 0.525).abs();
        assert!(err <= 1.0 / f64::from(1u32 << n) && err <= last);
        last = err;
    }
}

#[test]
fn bad_input_is_a_typed_error_naming_body_and_field() {
    let mut world = World::new(Settings::default());
    let err = world
        .add_sphere(SphereDesc::new(-1.0).named("x"))
        .unwrap_err();
    assert_eq!(err.field, sphere_physics::Field::Radius);
    assert!(err.to_string().contains("'x'"));
    assert!(world.is_empty());
    assert!(world.step(f64::NAN).is_err());
}

#[test]
fn bouncing_ball_settles_on_fixed_sphere() {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world
        .add_sphere(
            SphereDesc::new(10.0)
                .at(DVec3::new(0.0, -10.0, 0.0))
                .fixed(),
        )
        .unwrap();
    let ball = world
        .add_sphere(
            SphereDesc::new(0.5)
                .at(DVec3::new(0.0, 2.0, 0.0))
                .with_restitution(0.5),
        )
        .unwrap();
    for _ in 0..600 {
        world.step(1.0 / 60.0).unwrap();
    }
    let b = world.body(ball).unwrap();
    assert!((b.position().y - 0.5).abs() < 1e-9, "{}", b.position().y);
    assert!(world.stats().max_overlap < 1e-9);
    assert_eq!(world.stats().collisions_deferred, 0);
}

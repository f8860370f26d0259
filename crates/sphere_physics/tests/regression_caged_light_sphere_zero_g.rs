//! Regression: a light sphere caged between heavy ones, placed overlapping with no gravity,
//! took over four seconds to come apart.
//!
//! With nothing accelerating, spheres placed overlapping are moved apart at each step's end,
//! pair by pair, each body in proportion to its inverse mass (Gauss–Seidel sweeps). A small,
//! light sphere caught between heavy ones that overlap it from nearly opposite sides can only
//! be freed by the heavy ones moving apart, and each pair's move gives them a share as small
//! as the mass ratio (290 here): with 8 sweeps a step the last overlap shrank by 3.5% a step,
//! and this crowd (the separation property test's case with `PROPTEST_RNG_SEED=11` and 3 000
//! cases) was still 0.14 mm deep after the test's 2 s, apart after 289 steps. With 32 sweeps
//! (they stop as soon as nothing moves) it is apart after 71.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

/// Position, radius and density of each sphere, as the property test drew them.
const CROWD: [(f64, f64, f64, f64, f64); 26] = [
    (
        -0.18073677154592668,
        -0.08437591052199558,
        0.09917162762003781,
        0.05884490190296282,
        0.5,
    ),
    (
        0.4988641231219386,
        -0.7986945803450126,
        -0.09287136160118416,
        0.4662306915045919,
        0.9224480510737445,
    ),
    (
        0.2981211270641022,
        0.868947108983501,
        -0.12651126548059557,
        0.3164694028425852,
        2.760897029923412,
    ),
    (
        -0.6945762209665777,
        0.9056415928732525,
        0.8045987387289049,
        0.4028366937318076,
        4.993136818745888,
    ),
    (
        -0.023421487333140895,
        -0.1408530917619984,
        0.3768700343683997,
        0.37165176558310076,
        0.5848821562363854,
    ),
    (
        -0.801311448788684,
        -0.5157980537665435,
        0.33671820230610655,
        0.36717513383450096,
        3.3885662313979212,
    ),
    (
        -0.2759364662452544,
        -0.5637470065118956,
        -0.35410733938789196,
        0.16566507336012415,
        1.2696161025920172,
    ),
    (
        0.8388166782832923,
        0.8542522417168763,
        -0.1378518059278924,
        0.4071374630875214,
        1.5794607217727883,
    ),
    (
        -0.7310980009620305,
        0.30839527698027724,
        -0.8443744386378551,
        0.4665464689369396,
        4.651966973366867,
    ),
    (
        0.21905080941229443,
        0.2619591496710719,
        -0.42228524437321197,
        0.17263118920385637,
        4.117098884111796,
    ),
    (
        0.07643031711049426,
        -0.15882494396502334,
        -0.14419754612624547,
        0.2523817243976773,
        1.5767716792609185,
    ),
    (
        0.0,
        -0.35898998812853683,
        0.502937491303119,
        0.26215372128975484,
        3.250315154112156,
    ),
    (
        -0.8138478908765373,
        -0.05065190362577994,
        -0.3134461989378334,
        0.2928894387639203,
        4.66342912664154,
    ),
    (
        -0.49022550059113346,
        -0.09525477543835868,
        -0.5124170977455321,
        0.2906714892615437,
        3.9102951193474698,
    ),
    (
        -0.7033224841038618,
        0.6592655102006192,
        0.21337135959199768,
        0.30011206124489004,
        3.7256146218991644,
    ),
    (
        0.5817749101071621,
        -0.9317327507248875,
        0.3184957872174364,
        0.3797761532045229,
        2.417812605450794,
    ),
    (
        0.4081107778821121,
        0.450125688657415,
        0.6546181198011568,
        0.39801332557476105,
        2.339092836626544,
    ),
    (
        -0.6630464313933635,
        0.3933454347683317,
        0.4862144379375966,
        0.45883503337959675,
        4.4808440647414365,
    ),
    (
        0.07515460401580458,
        -0.9288199073939549,
        -0.3686344224294672,
        0.487014315539911,
        1.8801379094119395,
    ),
    (
        -0.11091304451102385,
        -0.09376153243363923,
        0.215247118963794,
        0.20650680842603117,
        3.4796242681204275,
    ),
    (
        -0.6520877606935194,
        0.20243129221313616,
        -0.22413831571847972,
        0.28775207782472223,
        3.3693355846172,
    ),
    (
        0.3769471234379671,
        0.5106117765150207,
        0.257690333057263,
        0.2434846693548554,
        1.8671738308921515,
    ),
    (
        -0.5714010079320277,
        0.29856399972111813,
        0.5363155633042372,
        0.299303976505123,
        1.0240395124243424,
    ),
    (
        0.2856187981379654,
        0.2093151714799679,
        0.35778314171957737,
        0.29850581430701223,
        2.6383330426662783,
    ),
    (
        0.17372514619307852,
        -0.5610154967287079,
        0.5794838604372472,
        0.4997171991494715,
        0.937481939891124,
    ),
    (
        0.006322991493744631,
        0.8971340399092438,
        0.6408600397233083,
        0.39221637008436083,
        0.9451409127137732,
    ),
];

#[test]
fn a_caged_light_sphere_comes_apart_within_two_seconds() {
    let mut world = World::new(Settings::default());
    for &(x, y, z, radius, density) in &CROWD {
        world
            .add_sphere(
                SphereDesc::new(radius)
                    .at(DVec3::new(x, y, z))
                    .with_density(density),
            )
            .unwrap();
    }
    let mass: f64 = world.bodies().iter().map(|b| b.mass()).sum();
    let centre = |world: &World| {
        world
            .bodies()
            .iter()
            .map(|b| b.position() * b.mass())
            .sum::<DVec3>()
            / mass
    };
    let start = centre(&world);
    let deepest = |world: &World| {
        let bodies = world.bodies();
        let mut worst = 0.0f64;
        for (i, a) in bodies.iter().enumerate() {
            for b in &bodies[i + 1..] {
                let reach = a.radius() + b.radius();
                let band = 2e-6 * a.radius().min(b.radius()) + 1e-9 * (1.0 + reach);
                worst = worst.max(reach - (b.position() - a.position()).length() - band);
            }
        }
        worst
    };
    let mut apart = false;
    for _ in 0..120 {
        world.step(1.0 / 60.0).unwrap();
        assert!(world.bodies().iter().all(|b| b.velocity() == DVec3::ZERO));
        assert!((centre(&world) - start).length() <= 1e-12);
        if deepest(&world) <= 0.0 {
            apart = true;
            break;
        }
    }
    assert!(apart, "still {} m deep after 2 s", deepest(&world));
}

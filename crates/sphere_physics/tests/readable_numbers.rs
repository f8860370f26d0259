//! Error messages print numbers readably: a huge or tiny value in exponent form, not hundreds
//! of digits (a radius of 1e200 printed 201 digits until the fifty-fifth session; found by
//! review).

use sphere_physics::{Readable, SphereDesc, World, WorldError};

#[test]
fn plain_in_range_exponent_beyond() {
    let shown = |x: f64| Readable(x).to_string();
    assert_eq!(shown(-1.0), "-1");
    assert_eq!(shown(0.25), "0.25");
    assert_eq!(shown(1.0 / 60.0), "0.016666666666666666");
    assert_eq!(shown(123456.0), "123456");
    assert_eq!(shown(1e300), "1e300");
    assert_eq!(shown(-1e-320), "-1e-320");
    assert_eq!(shown(f64::MAX), "1.7976931348623157e308");
    assert_eq!(shown(f64::NAN), "NaN");
    assert_eq!(shown(f64::NEG_INFINITY), "-inf");
    assert_eq!(shown(-0.0), "-0");
}

#[test]
fn errors_print_huge_and_tiny_values_in_exponent_form() {
    let mut world = World::new(Default::default());
    let error = world.add_sphere(SphereDesc::new(1e200)).unwrap_err();
    let message = error.to_string();
    assert!(message.ends_with("got 1e200"), "{message}");
    let error = world.step(1e-310).unwrap_err();
    assert_eq!(error, WorldError::InvalidTimeStep(1e-310));
    let message = error.to_string();
    assert!(message.ends_with("got 1e-310"), "{message}");
}

/// Review of the fifty-seventh session: the generators' and the settings' messages still
/// printed hundreds of digits (a generated sphere's density of 1e300, a sleeping speed of
/// -1e-300).
#[test]
fn generator_and_setting_messages_print_numbers_readably() {
    let message =
        |ron: &str| sphere_physics::SceneDesc::from_ron(ron).and_then(|s| s.build().map(|_| ()));
    let shower = |extra: &str| {
        format!(
            "(name: \"x\", generate: [Shower(count: 1, seed: 1, min: (0.0, 0.0, 0.0),
              max: (1.0, 1.0, 1.0), radius: 0.1{extra})])"
        )
    };
    for (ron, wanted) in [
        (shower(", density: 1e300"), "got 1e300"),
        (shower(", density: 1e-300"), "got 1e-300"),
        (
            shower(", velocity: (1e300, 0.0, 0.0), restitution: -1e-300"),
            "got -1e-300",
        ),
        (
            "(name: \"x\", generate: [Gas(count: 1, seed: 1, min: (0.0, 0.0, 0.0),
              max: (1.0, 1.0, 1.0), radius: 0.1, speed: -1e300)])"
                .to_string(),
            "got -1e300",
        ),
        (
            "(name: \"x\", generate: [Shower(count: 1, seed: 1, min: (0.0, 0.0, 1e-300),
              max: (1.0, 1.0, 0.0), radius: 0.1)])"
                .to_string(),
            "0 <= 1e-300",
        ),
        (
            "(name: \"x\", sleep: (speed: -1e-300), spheres: [])".to_string(),
            "got -1e-300",
        ),
        (
            "(name: \"x\", sleep: (speed: 1.0, time: -1e300), spheres: [])".to_string(),
            "got -1e300",
        ),
    ] {
        let text = message(&ron).unwrap_err().to_string();
        assert!(text.contains(wanted) && text.len() < 200, "{ron}: {text}");
    }
    let settings = sphere_physics::Settings {
        gravity: sphere_physics::glam::DVec3::new(1e300, f64::NAN, 0.0),
        ..Default::default()
    };
    let text = settings.validate().unwrap_err().to_string();
    assert!(text.contains("[1e300, NaN, 0]"), "{text}");
}

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

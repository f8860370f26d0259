//! Main job (for now): a touching 5-ball Newton's cradle in the core, printed step by step.
use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut world = World::new(Settings::default());
    for i in 0..5 {
        let v = if i == 0 { DVec3::X } else { DVec3::ZERO };
        world.add_sphere(
            SphereDesc::new(0.5)
                .at(DVec3::new(i as f64, 0.0, 0.0))
                .moving(v),
        )?;
    }
    let stats = *world.step(1.0 / 60.0)?;
    println!("after one step of 1/60 s: {} collisions", stats.collisions);
    for body in world.bodies() {
        println!(
            "  ball {}: velocity {:?}",
            body.id(),
            body.velocity().to_array()
        );
    }
    Ok(())
}

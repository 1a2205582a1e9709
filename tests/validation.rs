//! Every setter and generator rejects what it cannot simulate, with a message that
//! names the field and its valid range, and leaves the world as it was (issue 8,
//! item 6; Box2D's `test_invalid_input` idea). One test per setter.

use glam::Vec3;
use particle_lab::physics::*;

/// A world with one movable particle (id 0) and one immovable one (id 1), stepped once.
fn world() -> World {
    let mut world = World::new();
    world.add_particle(ParticleDesc { position: Vec3::Y, ..ParticleDesc::default() }).unwrap();
    world.add_particle(ParticleDesc { immovable: true, ..ParticleDesc::default() }).unwrap();
    world.add_contact_generator(SphereCollisions::elastic(0.5)).unwrap();
    world.step(1.0 / 60.0).unwrap();
    world
}

/// Everything a rejected call must leave alone.
fn state(world: &World) -> (Vec<Vec3>, Vec<Vec3>, Vec<f32>, usize, u64, SolverSettings, ContactResolver) {
    let p = &world.particles;
    (
        p.positions().to_vec(),
        p.velocities().to_vec(),
        p.inverse_masses().to_vec(),
        world.forces.len() + 1000 * world.links().len(),
        world.steps(),
        *world.solver(),
        *world.resolver(),
    )
}

/// Runs `change` on a fresh world: it must fail with a message containing every one of
/// `words`, and leave the world's state unchanged.
fn rejects<T: std::fmt::Debug>(words: &[&str], change: impl FnOnce(&mut World) -> Result<T, PhysicsError>) {
    let mut world = world();
    let before = state(&world);
    let result = change(&mut world);
    let message = match result {
        Err(error) => error.to_string(),
        Ok(value) => panic!("accepted, returned {value:?}; expected an error naming {words:?}"),
    };
    for word in words {
        assert!(message.contains(word), "message {message:?} should mention {word:?}");
    }
    assert!(!message.contains('\n'), "one line: {message:?}");
    assert!(before == state(&world), "a rejected call changed the world ({message})");
}

#[test]
fn add_particle_rejects_bad_descriptions() {
    let desc = ParticleDesc::default();
    // A mass whose inverse overflows single precision (NaN after one step before).
    rejects(&["mass", "2e-39", "valid range"], |w| w.add_particle(ParticleDesc { mass: 2e-39, ..desc }));
    rejects(&["mass", "valid range"], |w| w.add_particle(ParticleDesc { mass: f32::NAN, ..desc }));
    rejects(&["mass"], |w| w.add_particle(ParticleDesc { mass: 0.0, ..desc }));
    rejects(&["position"], |w| w.add_particle(ParticleDesc { position: Vec3::NAN, ..desc }));
    rejects(&["damping"], |w| w.add_particle(ParticleDesc { damping: 1.5, ..desc }));
    rejects(&["radius"], |w| w.add_particle(ParticleDesc { radius: -1.0, ..desc }));
}

#[test]
fn set_mass_rejects_bad_masses_and_immovable_particles() {
    rejects(&["mass", "valid range"], |w| w.particles.set_mass(ParticleId(0), f32::NAN));
    rejects(&["mass", "valid range"], |w| w.particles.set_mass(ParticleId(0), 2e-39));
    rejects(&["mass", "valid range"], |w| w.particles.set_mass(ParticleId(0), f32::INFINITY));
    // An immovable particle is not set free by a mass: that takes set_movable.
    rejects(&["immovable", "set_movable"], |w| w.particles.set_mass(ParticleId(1), 2.0));
    rejects(&["no particle"], |w| w.particles.set_mass(ParticleId(99), 2.0));
}

#[test]
fn set_movable_is_the_explicit_call_and_checks_its_mass() {
    rejects(&["mass", "valid range"], |w| w.particles.set_movable(ParticleId(1), Some(-1.0)));
    let mut world = world();
    world.particles.set_movable(ParticleId(1), Some(2.0)).unwrap();
    assert_eq!(world.particles.mass(1), 2.0);
    world.particles.set_movable(ParticleId(0), None).unwrap();
    assert_eq!(world.particles.inverse_masses()[0], 0.0);
}

#[test]
fn set_damping_rejects_values_outside_zero_to_one() {
    rejects(&["damping"], |w| w.particles.set_damping(ParticleId(0), 1.01));
    rejects(&["damping"], |w| w.particles.set_damping(ParticleId(0), f32::NAN));
}

#[test]
fn set_position_and_velocity_reject_non_finite_values() {
    rejects(&["position"], |w| w.particles.set_position(ParticleId(0), Vec3::new(0.0, f32::NAN, 0.0)));
    rejects(&["velocity"], |w| w.particles.set_velocity(ParticleId(0), Vec3::INFINITY));
    rejects(&["velocity", "immovable"], |w| w.particles.set_velocity(ParticleId(1), Vec3::X));
}

#[test]
fn set_acceleration_all_rejects_nan_gravity() {
    rejects(&["acceleration"], |w| w.set_acceleration_all(Vec3::new(0.0, f32::NAN, 0.0)));
}

#[test]
fn step_rejects_durations_outside_zero_to_one_second() {
    for dt in [1e30, 1.5, 0.0, -0.01, f32::NAN, f32::INFINITY] {
        rejects(&["dt", "valid range"], |w| w.step(dt));
    }
}

#[test]
fn set_solver_rejects_each_bad_field() {
    let good = SolverSettings::default();
    rejects(&["substeps", "valid range"], |w| w.set_solver(SolverSettings { substeps: 0, ..good }));
    rejects(&["contact_hertz"], |w| w.set_solver(SolverSettings { contact_hertz: f32::NAN, ..good }));
    rejects(&["max_push_speed"], |w| w.set_solver(SolverSettings { max_push_speed: -1.0, ..good }));
    rejects(&["restitution_threshold"], |w| {
        w.set_solver(SolverSettings { restitution_threshold: -0.1, ..good })
    });
    rejects(&["speculative_distance"], |w| {
        w.set_solver(SolverSettings { speculative_distance: f32::NAN, ..good })
    });
}

#[test]
fn set_resolver_rejects_each_bad_field() {
    let good = ContactResolver::default();
    rejects(&["max_iterations", "valid range"], |w| {
        w.set_resolver(ContactResolver { max_iterations: 0, ..good })
    });
    rejects(&["slop", "valid range"], |w| w.set_resolver(ContactResolver { slop: -0.01, ..good }));
    rejects(&["velocity_epsilon"], |w| {
        w.set_resolver(ContactResolver { velocity_epsilon: f32::NAN, ..good })
    });
    rejects(&["restitution_threshold"], |w| {
        w.set_resolver(ContactResolver { restitution_threshold: f32::NEG_INFINITY, ..good })
    });
    rejects(&["position_passes", "valid range"], |w| w.set_position_passes(65));
}

#[test]
fn add_force_rejects_bad_generators() {
    let (a, b) = (ParticleId(0), ParticleId(1));
    rejects(&["spring k", "valid range"], |w| w.add_force(Spring::between(a, b, f32::NAN, 1.0)));
    rejects(&["spring rest_length"], |w| w.add_force(Spring::between(a, b, 10.0, -1.0)));
    rejects(&["bungee k"], |w| w.add_force(Spring::anchored(a, Vec3::ZERO, -5.0, 1.0).as_bungee()));
    rejects(&["spring anchor"], |w| w.add_force(Spring::anchored(a, Vec3::NAN, 5.0, 1.0)));
    rejects(&["gravity"], |w| {
        w.add_force(Gravity { gravity: Vec3::new(0.0, f32::NAN, 0.0), targets: vec![a] })
    });
    rejects(&["drag k1"], |w| w.add_force(Drag { k1: -1.0, k2: 0.0, targets: vec![a] }));
    rejects(&["drag k2"], |w| w.add_force(Drag { k1: 0.0, k2: f32::NAN, targets: vec![a] }));
    let float =
        Buoyancy { target: a, surface: 0.0, half_height: 0.5, volume: 0.01, density: 1000.0, g: 9.81 };
    rejects(&["buoyancy density"], |w| w.add_force(Buoyancy { density: f32::NAN, ..float }));
    rejects(&["buoyancy g"], |w| w.add_force(Buoyancy { g: -1.0, ..float }));
    // No gravity is a valid world (springForces with g = 0): the float is weightless and feels no buoyancy.
    world().add_force(Buoyancy { g: 0.0, ..float }).expect("g = 0 is a world without weight");
    rejects(&["stiff spring k"], |w| w.add_force(StiffSpring::new(a, Vec3::ZERO, f32::NAN, 0.1)));
    rejects(&["stiff spring damping_ratio"], |w| {
        w.add_force(StiffSpring::new(a, Vec3::ZERO, 10.0, f32::INFINITY))
    });
}

#[test]
fn replacing_a_force_checks_the_new_one_and_keeps_the_old() {
    let mut world = world();
    let id = world.add_force(Spring::anchored(ParticleId(0), Vec3::ZERO, 10.0, 1.0)).unwrap();
    let bad = Box::new(Spring::anchored(ParticleId(0), Vec3::ZERO, f32::NAN, 1.0));
    assert!(world.forces.replace(id, bad).is_err());
    assert_eq!(world.links()[0].tension, 0.0, "the old spring (at rest length) is still there");
}

#[test]
fn add_contact_generator_rejects_bad_surfaces_and_links() {
    let a = ParticleId(0);
    // Restitution 2 took a bouncing world from 21.6 J to 247 J in 2 s.
    rejects(&["restitution", "2", "valid range"], |w| {
        w.add_contact_generator(SphereCollisions::elastic(2.0))
    });
    rejects(&["friction"], |w| w.add_contact_generator(SphereCollisions::new(0.5, -1.0)));
    rejects(&["restitution"], |w| w.add_contact_generator(Plane::ground(0.0, 2.0, 0.0)));
    rejects(&["restitution"], |w| {
        w.add_contact_generator(GroundPlane { height: 0.0, restitution: f32::NAN })
    });
    rejects(&["plane offset"], |w| w.add_contact_generator(Plane::ground(f32::INFINITY, 0.5, 0.0)));
    rejects(&["rod length", "valid range"], |w| {
        w.add_contact_generator(Constraint::rod(a, ParticleId(1), f32::NAN))
    });
    rejects(&["cable length"], |w| {
        w.add_contact_generator(Constraint::support_cable(a, Vec3::ZERO, 0.0, 0.5))
    });
    rejects(&["cable restitution"], |w| {
        w.add_contact_generator(Constraint::cable(a, ParticleId(1), 1.0, 2.0))
    });
    rejects(&["rod anchor"], |w| w.add_contact_generator(Constraint::support_rod(a, Vec3::NAN, 1.0)));
}

#[test]
fn plane_new_rejects_bad_normals_points_and_surfaces() {
    let err = |r: Result<Plane, PhysicsError>| r.unwrap_err().to_string();
    assert!(err(Plane::new(Vec3::ZERO, Vec3::ZERO, 0.5, 0.0)).contains("normal"));
    assert!(err(Plane::new(Vec3::Y, Vec3::NAN, 0.5, 0.0)).contains("point"));
    assert!(err(Plane::new(Vec3::Y, Vec3::ZERO, 2.0, 0.0)).contains("restitution"));
}

#[test]
fn the_checks_accept_the_edges_of_their_ranges() {
    // Each check is a range, not a blanket refusal: its edges are accepted.
    let mut world = world();
    world
        .add_particle(ParticleDesc { mass: 1e-9, damping: 0.0, radius: 0.0, ..ParticleDesc::default() })
        .unwrap();
    world.step(1.0).unwrap();
    world.add_contact_generator(SphereCollisions::elastic(1.0)).unwrap();
    world.add_force(Drag { k1: 0.0, k2: 0.0, targets: vec![ParticleId(0)] }).unwrap();
    world.add_force(StiffSpring::new(ParticleId(0), Vec3::ZERO, 1e9, 0.0)).unwrap();
    world
        .set_resolver(ContactResolver { max_iterations: 1, slop: 0.0, ..ContactResolver::default() })
        .unwrap();
    world.set_position_passes(64).unwrap();
    assert!(world.is_finite());
}

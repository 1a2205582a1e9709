//! Property tests: for any finite input in sane ranges, no generator or contact makes NaN.

use glam::Vec3;
use particle_lab::physics::*;
use proptest::prelude::*;

fn vec3(range: f32) -> impl Strategy<Value = Vec3> {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Positions that are often exactly equal, to hit zero-length normals.
fn position() -> impl Strategy<Value = Vec3> {
    prop_oneof![Just(Vec3::ZERO), Just(Vec3::ONE), vec3(10.0)]
}

/// One particle's start: position, velocity, mass and whether it is immovable.
type Start = (Vec3, Vec3, f32, bool);

fn two_particles(a: Start, b: Start, radius: f32, kind: SolverKind) -> (World, ParticleId, ParticleId) {
    let mut world = World::new();
    world.set_solver(SolverSettings { kind, ..SolverSettings::default() }).unwrap();
    let mut add = |(position, velocity, mass, immovable): Start| {
        let acceleration = Vec3::new(0.0, -9.81, 0.0);
        let desc = ParticleDesc { position, velocity, mass, immovable, radius, damping: 0.99, acceleration };
        world.add_particle(desc).unwrap()
    };
    let a = add(a);
    let b = add(b);
    (world, a, b)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn no_generator_or_contact_produces_nan(
        pa in position(), pb in position(), va in vec3(50.0), vb in vec3(50.0),
        ma in 0.01f32..1000.0, mb in 0.01f32..1000.0,
        fixed_a in proptest::bool::weighted(0.2), fixed_b in proptest::bool::weighted(0.2),
        k in 0.0f32..1.0e6, rest in 0.0f32..5.0, radius in 0.0f32..2.0,
        restitution in 0.0f32..=1.0, dt in 1.0e-4f32..0.1, zeta in 0.0f32..5.0,
        paper in proptest::bool::ANY,
    ) {
        let kind = if paper { SolverKind::Paper } else { SolverKind::Soft };
        let (mut world, a, b) = two_particles((pa, va, ma, fixed_a), (pb, vb, mb, fixed_b), radius, kind);
        // Explicit springs are stable for ω·h < 2 (h the step, or the substep for the
        // soft solver). Past that they are meant to explode, and an explosion can
        // overflow to infinity within one step: then only "no panic" is asked of the
        // soft solver, whose substeps compound the growth (the paper's stays finite).
        let h = if paper { dt } else { dt / world.solver().substeps as f32 };
        let lightest = if fixed_a { mb } else if fixed_b { ma } else { ma.min(mb) };
        // Two springs share a particle pair; the stiffest mode is about 4k / m.
        let stable = (4.0 * k / lightest).sqrt() * h < 2.0;
        world.add_force(Gravity { gravity: Vec3::new(0.0, -9.81, 0.0), targets: vec![a, b] }).unwrap();
        world.add_force(Drag { k1: 0.1, k2: 0.01, targets: vec![a, b] }).unwrap();
        world.add_force(Spring::between(a, b, k, rest)).unwrap();
        world.add_force(Spring::between(a, b, k, rest).as_bungee()).unwrap();
        world.add_force(Spring::anchored(b, pa, k, rest)).unwrap();
        world.add_force(Spring::anchored(a, pb, k, rest).as_bungee()).unwrap();
        world.add_force(Buoyancy { target: a, surface: 0.5, half_height: radius, volume: 0.1, density: 1000.0, g: 9.81 }).unwrap();
        world.add_force(StiffSpring::new(b, pa, k.max(1.0), zeta)).unwrap();
        world.add_contact_generator(GroundPlane { height: 0.0, restitution }).unwrap();
        world.add_contact_generator(SphereCollisions::elastic(restitution)).unwrap();
        world.add_contact_generator(Constraint::rod(a, b, rest)).unwrap();
        world.add_contact_generator(Constraint::cable(a, b, rest, restitution)).unwrap();
        world.add_contact_generator(Constraint::support_rod(a, pb, rest)).unwrap();
        world.add_contact_generator(Constraint::support_cable(b, pa, rest, restitution)).unwrap();
        // Several steps: the stiff spring's remembered velocity and repeated contacts
        // are exercised too. Explicit springs may legitimately grow; NaN never.
        for _ in 0..5 {
            world.step(dt).unwrap();
            if !world.particles.positions().iter().all(|p| p.length() < 1.0e15) {
                break;
            }
        }
        if !paper && !stable {
            return Ok(());
        }
        prop_assert!(world.is_finite(), "state after a step: {:?}", world.particles);
        for contact in world.contacts() {
            prop_assert!(contact.normal.is_finite() && contact.penetration.is_finite());
            prop_assert!((contact.normal.length() - 1.0).abs() < 1e-3, "normal {:?}", contact.normal);
        }
        let energy = world.energy();
        prop_assert!(energy.kinetic.is_finite() && energy.potential.is_finite());
        for link in world.links() {
            prop_assert!(link.length.is_finite() && link.tension.is_finite());
        }
    }

    #[test]
    fn collisions_never_gain_energy(
        pa in vec3(0.4), va in vec3(20.0), vb in vec3(20.0),
        ma in 0.01f32..100.0, mb in 0.01f32..100.0, restitution in 0.0f32..=1.0,
    ) {
        let mut world = World::new();
        let mut add = |position, velocity, mass| {
            world.add_particle(ParticleDesc { position, velocity, mass, radius: 0.5, ..ParticleDesc::default() }).unwrap()
        };
        add(pa, va, ma);
        add(Vec3::ZERO, vb, mb);
        world.add_contact_generator(SphereCollisions::elastic(restitution)).unwrap();
        let before = world.energy().kinetic;
        world.step(1e-3).unwrap();
        let after = world.energy().kinetic;
        prop_assert!(after <= before * (1.0 + 1e-4) + 1e-4, "kinetic energy rose from {before} to {after}");
    }
}

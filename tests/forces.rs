//! Every force generator against a force worked out by hand.

use glam::{DVec3, Vec3};
use particle_lab::physics::stiff_spring::damped_oscillator;
use particle_lab::physics::*;

fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    (a - b).length() <= tolerance
}

fn world_with(positions: &[Vec3], velocities: &[Vec3], mass: f32) -> (World, Vec<ParticleId>) {
    let mut world = World::new();
    let ids = positions
        .iter()
        .zip(velocities)
        .map(|(&position, &velocity)| {
            world.add_particle(ParticleDesc { position, velocity, mass, ..ParticleDesc::default() }).unwrap()
        })
        .collect();
    (world, ids)
}

/// Applies one generator to fresh force accumulators and returns the forces.
fn forces_of(world: &mut World, generator: &mut dyn ForceGenerator) -> Vec<Vec3> {
    world.particles.clear_forces();
    generator.apply(&mut world.particles, 0.01);
    world.particles.forces().to_vec()
}

#[test]
fn gravity_is_mass_times_field() {
    let (mut world, ids) = world_with(&[Vec3::ZERO], &[Vec3::ZERO], 3.0);
    let mut gravity = Gravity { gravity: Vec3::new(0.0, -9.81, 0.0), targets: ids.clone() };
    let f = forces_of(&mut world, &mut gravity);
    assert!(close(f[0], Vec3::new(0.0, -29.43, 0.0), 1e-4), "{f:?}");
    // Potential energy m g h at 2 m up.
    world.particles.set_position(ids[0], Vec3::new(0.0, 2.0, 0.0)).unwrap();
    assert!((gravity.potential_energy(&world.particles) - 3.0 * 9.81 * 2.0).abs() < 1e-3);
}

#[test]
fn gravity_skips_immovable_particles() {
    let mut world = World::new();
    let ids = vec![world.add_particle(ParticleDesc { immovable: true, ..ParticleDesc::default() }).unwrap()];
    let mut gravity = Gravity { gravity: Vec3::new(0.0, -9.81, 0.0), targets: ids };
    assert_eq!(forces_of(&mut world, &mut gravity)[0], Vec3::ZERO);
}

#[test]
fn drag_is_linear_plus_quadratic_against_velocity() {
    // |v| = 5 along (3, 4, 0)/5; k1 = 0.5, k2 = 0.1: magnitude 0.5*5 + 0.1*25 = 5.
    let v = Vec3::new(3.0, 4.0, 0.0);
    let (mut world, ids) = world_with(&[Vec3::ZERO], &[v], 1.0);
    let mut drag = Drag { k1: 0.5, k2: 0.1, targets: ids.clone() };
    assert!(close(drag.force(v), Vec3::new(-3.0, -4.0, 0.0), 1e-5), "{:?}", drag.force(v));
    // Over a step of 0.01 s the generator applies the backward-Euler force: with
    // a = k1/m = 0.5, b = k2/m = 0.1, t = 0.01, the new speed s solves
    // 0.001 s² + 1.005 s - 5 = 0, s = 4.950737, so F = (4.950737 - 5) / 0.01 = -4.9263 N.
    let f = forces_of(&mut world, &mut drag);
    assert!(close(f[0], Vec3::new(3.0, 4.0, 0.0) / 5.0 * -4.9263, 1e-3), "{f:?}");
    // At rest: no force and no NaN.
    world.particles.set_velocity(ids[0], Vec3::ZERO).unwrap();
    assert_eq!(forces_of(&mut world, &mut drag)[0], Vec3::ZERO);
}

#[test]
fn spring_pulls_when_stretched_and_pushes_when_compressed() {
    // Rest length 2, k = 10. Stretched to 3: 10 N pulling a towards b.
    let (mut world, ids) = world_with(&[Vec3::ZERO, Vec3::new(3.0, 0.0, 0.0)], &[Vec3::ZERO; 2], 1.0);
    let mut spring = Spring::between(ids[0], ids[1], 10.0, 2.0);
    let f = forces_of(&mut world, &mut spring);
    assert!(close(f[0], Vec3::new(10.0, 0.0, 0.0), 1e-5), "stretched: {f:?}");
    assert!(close(f[1], Vec3::new(-10.0, 0.0, 0.0), 1e-5), "stretched: {f:?}");
    // Compressed to 1.5: 5 N pushing apart (Cyclone's abs() would pull).
    world.particles.set_position(ids[1], Vec3::new(1.5, 0.0, 0.0)).unwrap();
    let f = forces_of(&mut world, &mut spring);
    assert!(close(f[0], Vec3::new(-5.0, 0.0, 0.0), 1e-5), "compressed: {f:?}");
    assert!(close(f[1], Vec3::new(5.0, 0.0, 0.0), 1e-5), "compressed: {f:?}");
    assert!((spring.potential_energy(&world.particles) - 0.5 * 10.0 * 0.25).abs() < 1e-5);
}

#[test]
fn anchored_spring_acts_towards_and_away_from_anchor() {
    let anchor = Vec3::new(0.0, 5.0, 0.0);
    // 4 m below the anchor, rest 3, k 2: 2 N upwards.
    let (mut world, ids) = world_with(&[Vec3::new(0.0, 1.0, 0.0)], &[Vec3::ZERO], 1.0);
    let mut spring = Spring::anchored(ids[0], anchor, 2.0, 3.0);
    assert!(close(forces_of(&mut world, &mut spring)[0], Vec3::new(0.0, 2.0, 0.0), 1e-5));
    // 1 m below: compressed by 2, pushed 4 N down.
    world.particles.set_position(ids[0], Vec3::new(0.0, 4.0, 0.0)).unwrap();
    assert!(close(forces_of(&mut world, &mut spring)[0], Vec3::new(0.0, -4.0, 0.0), 1e-5));
}

#[test]
fn bungee_pulls_only_when_stretched() {
    let (mut world, ids) = world_with(&[Vec3::ZERO, Vec3::new(0.0, 0.0, 4.0)], &[Vec3::ZERO; 2], 1.0);
    let mut bungee = Spring::between(ids[0], ids[1], 3.0, 2.0).as_bungee();
    let f = forces_of(&mut world, &mut bungee);
    assert!(close(f[0], Vec3::new(0.0, 0.0, 6.0), 1e-5), "stretched: {f:?}");
    assert!(close(f[1], Vec3::new(0.0, 0.0, -6.0), 1e-5), "stretched: {f:?}");
    world.particles.set_position(ids[1], Vec3::new(0.0, 0.0, 1.0)).unwrap();
    let f = forces_of(&mut world, &mut bungee);
    assert_eq!(f, vec![Vec3::ZERO, Vec3::ZERO], "slack bungee must not push");
    assert_eq!(bungee.potential_energy(&world.particles), 0.0);
}

#[test]
fn anchored_bungee_pulls_only_when_stretched() {
    let anchor = Vec3::new(1.0, 0.0, 0.0);
    let (mut world, ids) = world_with(&[Vec3::new(4.0, 0.0, 0.0)], &[Vec3::ZERO], 1.0);
    let mut bungee = Spring::anchored(ids[0], anchor, 5.0, 1.0).as_bungee();
    assert!(close(forces_of(&mut world, &mut bungee)[0], Vec3::new(-10.0, 0.0, 0.0), 1e-5));
    world.particles.set_position(ids[0], Vec3::new(1.5, 0.0, 0.0)).unwrap();
    assert_eq!(forces_of(&mut world, &mut bungee)[0], Vec3::ZERO);
}

#[test]
fn buoyancy_follows_archimedes_in_all_three_cases() {
    let (mut world, ids) = world_with(&[Vec3::new(0.0, 5.0, 0.0)], &[Vec3::ZERO], 1.0);
    let mut buoyancy =
        Buoyancy { target: ids[0], surface: 2.0, half_height: 0.5, volume: 0.01, density: 1000.0, g: 10.0 };
    // Fully out (bottom at 4.5 > 2): nothing.
    assert_eq!(forces_of(&mut world, &mut buoyancy)[0], Vec3::ZERO);
    // Centre at the surface: half submerged, 0.5 * 1000 * 0.01 * 10 = 50 N up.
    world.particles.set_position(ids[0], Vec3::new(0.0, 2.0, 0.0)).unwrap();
    assert!(close(forces_of(&mut world, &mut buoyancy)[0], Vec3::new(0.0, 50.0, 0.0), 1e-3));
    // A quarter submerged: centre 0.25 above the surface -> 25 N (the paper's sign gives -25).
    world.particles.set_position(ids[0], Vec3::new(0.0, 2.25, 0.0)).unwrap();
    assert!(close(forces_of(&mut world, &mut buoyancy)[0], Vec3::new(0.0, 25.0, 0.0), 1e-3));
    // Fully under: 100 N.
    world.particles.set_position(ids[0], Vec3::new(0.0, -3.0, 0.0)).unwrap();
    assert!(close(forces_of(&mut world, &mut buoyancy)[0], Vec3::new(0.0, 100.0, 0.0), 1e-3));
}

#[test]
fn coincident_spring_ends_push_as_their_energy_and_tension_say() {
    // Issue 8, item 7: the spring reported 50 J and -100 N of tension but pushed
    // nothing. Force, tension and energy now agree: it pushes `a` up by k L.
    let (mut world, ids) = world_with(&[Vec3::ONE, Vec3::ONE], &[Vec3::ZERO; 2], 1.0);
    let mut spring = Spring::between(ids[0], ids[1], 100.0, 1.0);
    let f = forces_of(&mut world, &mut spring);
    assert_eq!(f, vec![Vec3::new(0.0, 100.0, 0.0), Vec3::new(0.0, -100.0, 0.0)], "pushes apart, no NaN");
    assert_eq!(spring.tension(&world.particles), -100.0);
    assert_eq!(spring.potential_energy(&world.particles), 50.0);
    // The same anchored: the particle is pushed up off the anchor.
    let mut anchored = Spring::anchored(ids[0], Vec3::ONE, 100.0, 1.0);
    assert_eq!(forces_of(&mut world, &mut anchored)[0], Vec3::new(0.0, 100.0, 0.0));
    // A bungee is slack there: no force, no tension, no energy.
    let mut bungee = Spring::between(ids[0], ids[1], 100.0, 0.0).as_bungee();
    assert_eq!(forces_of(&mut world, &mut bungee), vec![Vec3::ZERO, Vec3::ZERO]);
    assert_eq!((bungee.tension(&world.particles), bungee.potential_energy(&world.particles)), (0.0, 0.0));
}

#[test]
fn buoyancy_energy_is_minus_the_integral_of_its_force() {
    let (mut world, ids) = world_with(&[Vec3::ZERO], &[Vec3::ZERO], 1.0);
    let buoyancy =
        Buoyancy { target: ids[0], surface: 2.0, half_height: 0.5, volume: 0.01, density: 1000.0, g: 10.0 };
    // F = -dU/dy everywhere: check by central differences across all three regimes.
    for y in [3.0_f32, 2.4, 2.0, 1.7, 1.2, -1.0] {
        let h = 1e-3;
        let mut energy_at = |y: f32| {
            world.particles.set_position(ids[0], Vec3::new(0.0, y, 0.0)).unwrap();
            buoyancy.potential_energy(&world.particles)
        };
        let slope = (energy_at(y + h) - energy_at(y - h)) / (2.0 * h);
        let force = buoyancy.force(y).y;
        assert!((slope + force).abs() < 0.5, "y {y}: dU/dy {slope} vs -F {}", -force);
    }
}

#[test]
fn damped_oscillator_matches_its_differential_equation() {
    // Check y'' + 2ζω y' + ω² y = 0 numerically at a few times, in every damping regime.
    for zeta in [0.0, 0.3, 1.0, 2.5] {
        let omega = 7.0;
        let (y0, v0) = (DVec3::new(1.0, -0.5, 0.2), DVec3::new(0.3, 2.0, -1.0));
        for t in [0.1, 0.37, 1.2] {
            let h = 1e-4;
            let (y, v) = damped_oscillator(y0, v0, omega, zeta, t);
            let (_, v_plus) = damped_oscillator(y0, v0, omega, zeta, t + h);
            let (_, v_minus) = damped_oscillator(y0, v0, omega, zeta, t - h);
            let (y_plus, _) = damped_oscillator(y0, v0, omega, zeta, t + h);
            let (y_minus, _) = damped_oscillator(y0, v0, omega, zeta, t - h);
            let acceleration = (v_plus - v_minus) / (2.0 * h);
            let residual = acceleration + 2.0 * zeta * omega * v + omega * omega * y;
            assert!(residual.length() < 1e-4, "zeta {zeta} t {t}: residual {residual:?}");
            assert!(((y_plus - y_minus) / (2.0 * h) - v).length() < 1e-5, "v is y' (zeta {zeta})");
        }
        let (y, v) = damped_oscillator(y0, v0, omega, zeta, 0.0);
        assert!((y - y0).length() < 1e-12 && (v - v0).length() < 1e-12);
    }
}

#[test]
fn stiff_spring_first_step_lands_on_the_closed_form_despite_damping() {
    // The integrator's damping factor must be the one the spring planned with, also on
    // the very first step.
    let anchor = Vec3::ZERO;
    let start = Vec3::new(0.5, 0.0, 0.0);
    let (k, dt) = (400.0_f32, 0.01_f32);
    // Solved in one piece per step: the paper's solver. (The soft solver solves it per
    // substep, where damping acts between substeps; see the test below.)
    let mut world = World::new();
    world.set_solver(SolverSettings { kind: SolverKind::Paper, ..SolverSettings::default() }).unwrap();
    let id = world
        .add_particle(ParticleDesc { position: start, damping: 0.5, ..ParticleDesc::default() })
        .unwrap();
    world.add_force(StiffSpring::new(id, anchor, k, 0.0)).unwrap();
    world.step(dt).unwrap();
    let (expected, _) =
        damped_oscillator(start.as_dvec3(), DVec3::ZERO, f64::from(k).sqrt(), 0.0, f64::from(dt));
    let got = world.particles.positions()[0].as_dvec3();
    assert!((got - expected).length() < 1e-6, "got {got:?}, expected {expected:?}");
}

#[test]
fn stiff_spring_under_gravity_oscillates_about_the_shifted_rest_point() {
    let anchor = Vec3::new(0.0, 5.0, 0.0);
    let (k, mass, g, dt) = (100.0_f32, 1.0_f32, 9.81_f32, 1.0 / 60.0);
    let mut world = World::new();
    let id = world
        .add_particle(ParticleDesc {
            position: anchor,
            acceleration: Vec3::new(0.0, -g, 0.0),
            mass,
            ..ParticleDesc::default()
        })
        .unwrap();
    world.add_force(StiffSpring::new(id, anchor, k, 0.0)).unwrap();
    let omega = f64::from(k / mass).sqrt();
    let rest = anchor.as_dvec3() - DVec3::Y * f64::from(g * mass / k);
    let (mut y, mut v) = (anchor.as_dvec3() - rest, DVec3::ZERO);
    for _ in 0..600 {
        world.step(dt).unwrap();
        (y, v) = damped_oscillator(y, v, omega, 0.0, f64::from(dt));
    }
    let got = world.particles.positions()[0].as_dvec3();
    assert!((got - (rest + y)).length() < 1e-3, "got {got:?}, expected {:?}", rest + y);
}

#[test]
fn stiff_spring_lands_the_particle_on_the_closed_form() {
    // No gravity, no damping: after one step the particle is exactly where damped
    // harmonic motion puts it.
    let anchor = Vec3::new(0.0, 2.0, 0.0);
    let start = Vec3::new(0.5, 2.0, 0.0);
    let (k, mass, zeta, dt) = (400.0_f32, 2.0_f32, 0.1_f32, 0.01_f32);
    let mut world = World::new();
    let id = world.add_particle(ParticleDesc { position: start, mass, ..ParticleDesc::default() }).unwrap();
    world.add_force(StiffSpring::new(id, anchor, k, zeta)).unwrap();
    let omega = f64::from(k / mass).sqrt();
    let mut expected = (start - anchor).as_dvec3();
    let mut velocity = DVec3::ZERO;
    for _ in 0..50 {
        world.step(dt).unwrap();
        (expected, velocity) = damped_oscillator(expected, velocity, omega, f64::from(zeta), f64::from(dt));
    }
    let got = world.particles.positions()[0] - anchor;
    assert!((got.as_dvec3() - expected).length() < 1e-4, "got {got:?}, expected {expected:?}");
}

#[test]
fn stiff_spring_in_substeps_composes_to_the_closed_form() {
    // Undamped particle: four substeps of the exact solution are the exact solution.
    let (anchor, start, k) = (Vec3::ZERO, Vec3::new(0.5, 0.0, 0.0), 400.0_f32);
    let mut world = World::new();
    let id = world.add_particle(ParticleDesc { position: start, ..ParticleDesc::default() }).unwrap();
    world.add_force(StiffSpring::new(id, anchor, k, 0.1)).unwrap();
    for step in 1..=50 {
        world.step(0.01).unwrap();
        let t = 0.01 * f64::from(step);
        let (expected, _) = damped_oscillator(start.as_dvec3(), DVec3::ZERO, f64::from(k).sqrt(), 0.1, t);
        let got = world.particles.positions()[0].as_dvec3();
        assert!((got - expected).length() < 1e-4, "step {step}: got {got:?}, expected {expected:?}");
    }
}

#[test]
fn drag_is_stable_for_any_coefficient_and_reaches_terminal_speed() {
    // Regression: a 4 g particle with k1 = 2 N·s/m under explicit drag reached 2.2e8 m/s
    // in 1 s. Terminal speed is m g / k1 = 0.004 x 9.81 / 2 = 0.019620 m/s (linear), and
    // for k2 alone sqrt(m g / k2) = sqrt(0.03924 / 2) = 0.14007 m/s (quadratic).
    for (k1, k2, terminal) in [(2.0, 0.0, 0.019_62), (0.0, 2.0, 0.140_07), (2.0, 2.0, 0.0)] {
        let mut world = World::new();
        let id = world
            .add_particle(ParticleDesc {
                mass: 0.004,
                velocity: Vec3::new(30.0, 0.0, 0.0),
                acceleration: Vec3::new(0.0, -9.81, 0.0),
                ..ParticleDesc::default()
            })
            .unwrap();
        world.add_force(Drag { k1, k2, targets: vec![id] }).unwrap();
        for _ in 0..240 {
            world.step(1.0 / 240.0).unwrap();
            let v = world.particles.velocities()[0];
            assert!(v.is_finite() && v.x >= 0.0, "k1 {k1} k2 {k2}: velocity {v} reversed or blew up");
        }
        let speed = world.particles.velocities()[0].length();
        // Both terms: k1 s + k2 s² = m g, s = (-k1 + sqrt(k1² + 4 k2 m g)) / (2 k2).
        let terminal = if terminal > 0.0 {
            terminal
        } else {
            (-k1 + (k1 * k1 + 4.0 * k2 * 0.03924f32).sqrt()) / (2.0 * k2)
        };
        assert!((speed / terminal - 1.0).abs() < 0.01, "k1 {k1} k2 {k2}: {speed} m/s vs terminal {terminal}");
    }
}

#[test]
fn linear_drag_decay_follows_the_exponential() {
    // No gravity: v(t) = v0 e^{-k1 t / m}; exact per step, so within 1% at any step size.
    for dt in [1.0 / 240.0, 1.0 / 30.0] {
        let mut world = World::new();
        let id = world
            .add_particle(ParticleDesc {
                mass: 0.5,
                velocity: Vec3::new(4.0, 0.0, 0.0),
                ..ParticleDesc::default()
            })
            .unwrap();
        world.add_force(Drag { k1: 1.5, k2: 0.0, targets: vec![id] }).unwrap();
        for step in 1..=30 {
            world.step(dt).unwrap();
            let exact = 4.0 * (-1.5 * step as f32 * dt / 0.5).exp();
            let got = world.particles.velocities()[0].x;
            assert!((got / exact - 1.0).abs() < 0.01, "dt {dt} step {step}: {got} vs {exact}");
        }
    }
}

/// The free-body diagram's forces: each generator's `force_on` is what `apply` adds for
/// the generators whose step uses the instantaneous force, on every particle it names,
/// and `None` on the others; drag and the stiff spring report their physical forces.
#[test]
fn force_on_matches_what_each_generator_applies() {
    let positions = [Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.5, 3.0, 0.2), Vec3::new(4.0, 0.0, 0.0)];
    let velocities = [Vec3::new(1.0, -2.0, 0.5), Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO];
    let (mut world, ids) = world_with(&positions, &velocities, 2.0);
    let mut generators: Vec<Box<dyn ForceGenerator>> = vec![
        Box::new(Gravity { gravity: Vec3::new(0.0, -9.81, 0.0), targets: vec![ids[0], ids[1]] }),
        Box::new(Spring::between(ids[0], ids[1], 30.0, 1.0)),
        Box::new(Spring::anchored(ids[1], Vec3::new(0.0, 5.0, 0.0), 10.0, 0.5).as_bungee()),
        Box::new(Buoyancy {
            target: ids[0],
            surface: 1.2,
            half_height: 0.5,
            volume: 0.01,
            density: 1000.0,
            g: 9.81,
        }),
    ];
    for generator in &mut generators {
        let applied = forces_of(&mut world, generator.as_mut());
        for (i, &id) in ids.iter().enumerate() {
            let reported = generator.force_on(&world.particles, i);
            if generator.involves(id) {
                let reported =
                    reported.unwrap_or_else(|| panic!("{} reports nothing on {i}", generator.name()));
                assert!(
                    close(reported, applied[i], 1e-4),
                    "{}: {reported} vs {}",
                    generator.name(),
                    applied[i]
                );
            } else {
                assert_eq!(reported, None, "{} on {i}", generator.name());
            }
        }
    }
    let names: Vec<&str> = generators.iter().map(|g| g.name()).collect();
    assert_eq!(names, ["gravity", "spring", "bungee", "buoyancy"]);

    let drag = Drag { k1: 0.5, k2: 0.1, targets: vec![ids[0]] };
    let v = velocities[0];
    let expected = -v * (0.5 + 0.1 * v.length());
    assert!(close(drag.force_on(&world.particles, 0).unwrap(), expected, 1e-5));
    let stiff = StiffSpring::new(ids[1], Vec3::new(0.0, 2.0, 0.0), 50.0, 0.3);
    let c = 2.0 * 0.3 * (50.0f32 * 2.0).sqrt();
    let expected = -(positions[1] - Vec3::new(0.0, 2.0, 0.0)) * 50.0 - velocities[1] * c;
    assert!(close(stiff.force_on(&world.particles, 1).unwrap(), expected, 1e-4));
    assert_eq!(stiff.force_on(&world.particles, 0), None);
}

/// `World::forces_on` lists a particle's generators by name, in registration order.
#[test]
fn world_lists_the_forces_on_a_particle() {
    let (mut world, ids) = world_with(&[Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO], &[Vec3::ZERO; 2], 1.0);
    world.add_force(Spring::anchored(ids[0], Vec3::new(0.0, 4.0, 0.0), 20.0, 1.0)).unwrap();
    world.add_force(Drag { k1: 1.0, k2: 0.0, targets: vec![ids[0]] }).unwrap();
    world.add_force(Spring::between(ids[1], ids[1], 1.0, 0.0)).unwrap();
    let forces = world.forces_on(ids[0]);
    assert_eq!(forces.len(), 2, "{forces:?}");
    assert_eq!(forces[0].0, "spring");
    // Stretched by 1 m towards the anchor above: 20 N up.
    assert!(close(forces[0].1, Vec3::new(0.0, 20.0, 0.0), 1e-4), "{forces:?}");
    assert_eq!(forces[1], ("drag", Vec3::ZERO));
    assert!(world.forces_on(ParticleId(99)).is_empty());
}

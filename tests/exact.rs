//! The closed forms of `physics::exact` against the engine: they agree to the
//! integrators' known orders, so the lab can draw them as the exact answer.

use glam::DVec3;
use particle_lab::physics::exact;
use particle_lab::physics::*;

/// Largest distance (m) between a simulated particle and a closed form over `seconds`
/// at `hz` steps per second (1 substep, so the step is the integrator's).
fn worst_error(
    desc: ParticleDesc,
    integrator: Integrator,
    hz: f64,
    seconds: f64,
    setup: impl Fn(&mut World, ParticleId),
    exact_at: impl Fn(f64) -> DVec3,
) -> f64 {
    let mut world = World::new();
    let settings = SolverSettings { substeps: 1, integrator, ..SolverSettings::default() };
    world.set_solver(settings).unwrap();
    let id = world.add_particle(desc).unwrap();
    setup(&mut world, id);
    let mut worst = 0.0_f64;
    for step in 1..=(seconds * hz).round() as usize {
        world.step((1.0 / hz) as f32).unwrap();
        let got = world.particles.positions()[0].as_dvec3();
        worst = worst.max(got.distance(exact_at(step as f64 / hz)));
    }
    worst
}

#[test]
fn the_drag_free_parabola_is_what_verlet_and_rk4_compute() {
    let (p0, v0, g) = (DVec3::new(0.0, 1.5, 0.0), DVec3::new(20.0, 15.0, 0.0), DVec3::new(0.0, -20.0, 0.0));
    let desc = ParticleDesc {
        position: p0.as_vec3(),
        velocity: v0.as_vec3(),
        acceleration: g.as_vec3(),
        radius: 0.0,
        ..ParticleDesc::default()
    };
    let exact_at = |t: f64| exact::projectile(p0, v0, g, 0.0, t).0;
    for integrator in [Integrator::Verlet, Integrator::Rk4] {
        let error = worst_error(desc, integrator, 60.0, 1.5, |_, _| {}, exact_at);
        assert!(error < 1e-4, "{integrator:?}: {error} m");
    }
    // Semi-implicit Euler is first order: off by g h t / 2, halving with the step.
    let coarse = worst_error(desc, Integrator::SemiImplicitEuler, 60.0, 1.5, |_, _| {}, exact_at);
    let fine = worst_error(desc, Integrator::SemiImplicitEuler, 120.0, 1.5, |_, _| {}, exact_at);
    assert!((coarse - 20.0 / 60.0 * 1.5 / 2.0).abs() < 1e-3, "coarse {coarse} m");
    assert!((coarse / fine - 2.0).abs() < 0.05, "{coarse} / {fine}");
}

#[test]
fn damping_and_linear_drag_follow_the_exponential_closed_form() {
    let (p0, v0, g) = (DVec3::new(0.0, 1.5, 0.0), DVec3::new(25.0, 25.0, 0.0), DVec3::new(0.0, -20.0, 0.0));
    let base = ParticleDesc {
        position: p0.as_vec3(),
        velocity: v0.as_vec3(),
        acceleration: g.as_vec3(),
        mass: 2.0,
        radius: 0.0,
        ..ParticleDesc::default()
    };
    // The projectile scene's damping 0.99 is a decay rate of -ln 0.99 per second.
    let damped = ParticleDesc { damping: 0.5, ..base };
    let lambda = exact::damping_rate(0.5);
    let exact_at = |t: f64| exact::projectile(p0, v0, g, lambda, t).0;
    let coarse = worst_error(damped, Integrator::Rk4, 240.0, 2.0, |_, _| {}, exact_at);
    let fine = worst_error(damped, Integrator::Rk4, 480.0, 2.0, |_, _| {}, exact_at);
    // Damping is applied once a step, after the integrator: first order whatever it is.
    assert!(coarse < 0.1 && (coarse / fine - 2.0).abs() < 0.1, "damping: {coarse} m, then {fine} m");
    // Linear drag k1 = 3 N·s/m on 2 kg: λ = 1.5 /s; drag solves its own velocity exactly.
    let drag = |world: &mut World, id| {
        world.add_force(Drag { k1: 3.0, k2: 0.0, targets: vec![id] }).unwrap();
    };
    let exact_at = |t: f64| exact::projectile(p0, v0, g, 1.5, t).0;
    let coarse = worst_error(base, Integrator::SemiImplicitEuler, 240.0, 2.0, drag, exact_at);
    let fine = worst_error(base, Integrator::SemiImplicitEuler, 480.0, 2.0, drag, exact_at);
    assert!(coarse < 0.1 && (coarse / fine - 2.0).abs() < 0.1, "drag: {coarse} m, then {fine} m");
    // And the closed form reaches the terminal velocity g / λ.
    let (_, v) = exact::projectile(p0, v0, g, 1.5, 30.0);
    assert!((v - g / 1.5).length() < 1e-6, "{v}");
}

#[test]
fn a_mass_on_a_spring_follows_the_damped_oscillator() {
    // A 1 kg bob hanging on a 2 m spring (k = 20 N/m) from (0, 7, 0), released at rest at
    // the spring's rest length, as in springForces; undamped and damped (0.8 a second).
    let (anchor, k, m, g) = (DVec3::new(0.0, 7.0, 0.0), 20.0, 1.0, DVec3::new(0.0, -9.81, 0.0));
    let rest = DVec3::new(0.0, -2.0, 0.0);
    let p0 = anchor + rest;
    for damping in [1.0_f32, 0.8] {
        let desc = ParticleDesc {
            position: p0.as_vec3(),
            acceleration: g.as_vec3(),
            damping,
            radius: 0.0,
            ..ParticleDesc::default()
        };
        let spring = |world: &mut World, id| {
            world.add_force(Spring::anchored(id, anchor.as_vec3(), k as f32, 2.0)).unwrap();
        };
        let lambda = exact::damping_rate(damping);
        let motion = exact::SpringMotion { anchor, rest_offset: rest, k, m, g, lambda };
        let exact_at = |t: f64| motion.at(p0, DVec3::ZERO, t).0;
        let rk4 = worst_error(desc, Integrator::Rk4, 240.0, 5.0, spring, exact_at);
        let coarse = worst_error(desc, Integrator::SemiImplicitEuler, 240.0, 5.0, spring, exact_at);
        let fine = worst_error(desc, Integrator::SemiImplicitEuler, 480.0, 5.0, spring, exact_at);
        let case = format!("damping {damping}: rk4 {rk4} m, semi-implicit {coarse} m then {fine} m");
        // Undamped, RK4 is fourth order; damping costs it its order (applied after it).
        let rk4_bound = if damping == 1.0 { 1e-4 } else { 0.01 };
        assert!(rk4 < rk4_bound, "{case}");
        assert!(coarse < 0.05 && (coarse / fine - 2.0).abs() < 0.15, "{case}");
    }
    // The closed form hangs at rest where the spring holds the weight: 7 - 2 - 0.4905.
    let motion = exact::SpringMotion { anchor, rest_offset: rest, k, m, g, lambda: 0.0 };
    assert!((motion.equilibrium().y - 4.5095).abs() < 1e-9);
    let (p, v) = motion.at(motion.equilibrium(), DVec3::ZERO, 3.0);
    assert!((p - motion.equilibrium()).length() < 1e-9 && v.length() < 1e-9, "{p} {v}");
}

//! The four integrators against closed forms, on both solvers, alone and with contacts
//! and links.

use glam::Vec3;
use particle_lab::physics::*;

const G: f32 = 9.81;

fn new_world(integrator: Integrator, kind: SolverKind) -> World {
    let mut world = World::new();
    world.set_solver(SolverSettings { integrator, kind, ..SolverSettings::default() }).unwrap();
    world
}

#[test]
fn names_parse_and_round_trip() {
    for integrator in Integrator::ALL {
        assert_eq!(Integrator::parse(integrator.name()), Ok(integrator));
    }
    assert_eq!(Integrator::parse(" RK4 "), Ok(Integrator::Rk4));
    let error = Integrator::parse("leapfrog").unwrap_err();
    assert!(error.contains("explicit-euler, semi-implicit-euler, verlet, rk4"), "{error}");
    assert_eq!(SolverSettings::default().integrator, Integrator::SemiImplicitEuler);
}

/// Height after `n` (sub)steps of `h` of a particle thrown up at `v0` from `y0`, as each
/// integrator computes it (their closed forms under constant gravity).
fn free_fall_height(integrator: Integrator, y0: f64, v0: f64, h: f64, n: f64) -> f64 {
    let g = f64::from(G);
    match integrator {
        // Position moves with the velocity before the kick: n(n-1)/2 kicks count.
        Integrator::ExplicitEuler => y0 + v0 * n * h - g * h * h * n * (n - 1.0) / 2.0,
        // With the velocity after it: n(n+1)/2.
        Integrator::SemiImplicitEuler => y0 + v0 * n * h - g * h * h * n * (n + 1.0) / 2.0,
        // Exact for a constant force.
        Integrator::Verlet | Integrator::Rk4 => y0 + v0 * n * h - g * (n * h).powi(2) / 2.0,
    }
}

#[test]
fn free_fall_follows_each_integrators_closed_form_on_both_solvers() {
    let (y0, v0, dt) = (100.0_f64, 3.0_f64, 1.0 / 60.0_f64);
    for kind in SolverKind::ALL {
        let substeps = if kind == SolverKind::Soft { 4.0 } else { 1.0 };
        for integrator in Integrator::ALL {
            let mut world = new_world(integrator, kind);
            world
                .add_particle(ParticleDesc {
                    position: Vec3::new(0.0, y0 as f32, 0.0),
                    velocity: Vec3::new(0.0, v0 as f32, 0.0),
                    acceleration: Vec3::new(0.0, -G, 0.0),
                    ..ParticleDesc::default()
                })
                .unwrap();
            for step in 1..=120_u32 {
                world.step(dt as f32).unwrap();
                let n = f64::from(step) * substeps;
                let expected = free_fall_height(integrator, y0, v0, dt / substeps, n);
                let got = f64::from(world.particles.positions()[0].y);
                assert!(
                    (got - expected).abs() < 2e-3,
                    "{kind:?} {integrator:?} step {step}: {got} vs {expected}"
                );
            }
            // The closed forms differ by more than the tolerance after 2 s, so the test
            // tells the integrators apart.
            let n = 120.0 * substeps;
            let spread = free_fall_height(Integrator::SemiImplicitEuler, y0, v0, dt / substeps, n)
                - free_fall_height(Integrator::Verlet, y0, v0, dt / substeps, n);
            assert!(spread.abs() > 0.01, "{spread}");
        }
    }
}

/// A 1 kg mass on an anchored spring (k = 20 N/m, rest 0) released 1 m out, no gravity,
/// stepped for 10 s at 60 Hz; returns (energy at the end / at the start, largest
/// distance from the exact x(t) = cos(ωt)).
fn spring_run(integrator: Integrator, kind: SolverKind) -> (f64, f64) {
    let (k, dt) = (20.0_f32, 1.0 / 60.0);
    let mut world = new_world(integrator, kind);
    let id = world.add_particle(ParticleDesc { position: Vec3::X, ..ParticleDesc::default() }).unwrap();
    world.add_force(Spring::anchored(id, Vec3::ZERO, k, 0.0)).unwrap();
    let energy = |w: &World| {
        let (p, v) = (w.particles.positions()[0], w.particles.velocities()[0]);
        0.5 * f64::from(v.length_squared()) + 0.5 * f64::from(k) * f64::from(p.length_squared())
    };
    let start = energy(&world);
    let omega = f64::from(k).sqrt();
    let mut worst = 0.0_f64;
    for step in 1..=600 {
        world.step(dt).unwrap();
        let exact = (omega * f64::from(step) * f64::from(dt)).cos();
        worst = worst.max((f64::from(world.particles.positions()[0].x) - exact).abs());
    }
    (energy(&world) / start, worst)
}

#[test]
fn a_spring_shows_each_integrators_character() {
    for kind in SolverKind::ALL {
        let (explicit, _) = spring_run(Integrator::ExplicitEuler, kind);
        let (semi, semi_error) = spring_run(Integrator::SemiImplicitEuler, kind);
        let (verlet, verlet_error) = spring_run(Integrator::Verlet, kind);
        let (rk4, rk4_error) = spring_run(Integrator::Rk4, kind);
        let case = format!(
            "{kind:?}: energy ratios explicit {explicit:.4}, semi {semi:.4}, verlet {verlet:.4}, rk4 {rk4:.6}; \
             errors semi {semi_error:.4}, verlet {verlet_error:.5}, rk4 {rk4_error:.6}"
        );
        // Explicit Euler multiplies the energy by (1 + ω²h²) every step: it grows.
        assert!(explicit > 1.2, "{case}");
        // Semi-implicit Euler and Verlet keep it, within a few ωh.
        assert!((semi - 1.0).abs() < 0.1 && (verlet - 1.0).abs() < 0.01, "{case}");
        // RK4 is fourth order: tiny energy drift and a tiny error in phase.
        assert!((rk4 - 1.0).abs() < 1e-4 && rk4_error < 1e-3, "{case}");
        assert!(verlet_error < semi_error, "{case}");
    }
}

#[test]
fn every_integrator_keeps_contacts_and_links() {
    // With contacts and links each integrator gives the solver its moving velocity;
    // what the solver changes is added to the end velocity (see `integrator.rs`).
    for integrator in Integrator::ALL {
        // A ball dropped on the ground with e = 0.5 ends at rest on it.
        let mut world = new_world(integrator, SolverKind::Soft);
        world
            .add_particle(ParticleDesc {
                position: Vec3::new(0.0, 2.0, 0.0),
                acceleration: Vec3::new(0.0, -G, 0.0),
                radius: 0.25,
                ..ParticleDesc::default()
            })
            .unwrap();
        world.add_contact_generator(Plane::ground(0.0, 0.5, 0.0)).unwrap();
        for _ in 0..300 {
            world.step(1.0 / 60.0).unwrap();
        }
        let (p, v) = (world.particles.positions()[0], world.particles.velocities()[0]);
        assert!((p.y - 0.25).abs() < 0.005 && v.length() < 0.05, "{integrator:?}: resting ball at {p}, {v}");

        // A pendulum on a support rod keeps its length and nearly all its energy.
        let mut world = new_world(integrator, SolverKind::Soft);
        let bob = world
            .add_particle(ParticleDesc {
                position: Vec3::X,
                acceleration: Vec3::new(0.0, -G, 0.0),
                ..ParticleDesc::default()
            })
            .unwrap();
        world.add_contact_generator(Constraint::support_rod(bob, Vec3::ZERO, 1.0)).unwrap();
        let mut longest = 0.0_f32;
        for _ in 0..600 {
            world.step(1.0 / 60.0).unwrap();
            longest = longest.max((world.particles.positions()[0].length() - 1.0).abs());
        }
        let (p, v) = (world.particles.positions()[0], world.particles.velocities()[0]);
        let energy = 0.5 * v.length_squared() + G * p.y;
        assert!(longest < 0.01, "{integrator:?}: rod length off by {longest} m");
        assert!(energy.abs() < 0.05 * G, "{integrator:?}: pendulum energy {energy} J of swing {G} J");
    }
}

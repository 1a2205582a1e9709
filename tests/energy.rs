//! The energy budget: kinetic + potential + dissipated - work stays at its start value
//! up to the integrator's error, which the world reports as such.

use glam::Vec3;
use particle_lab::physics::*;

const G: f32 = 9.81;

fn particle(position: Vec3, velocity: Vec3) -> ParticleDesc {
    ParticleDesc { position, velocity, radius: 0.0, ..ParticleDesc::default() }
}

#[test]
fn free_fall_error_is_semi_implicit_eulers_known_loss() {
    // Semi-implicit Euler loses exactly g²h²/2 per unit mass every (sub)step under
    // constant gravity: 100 steps of 4 substeps of 1/240 s, 2 kg.
    let mut world = World::new();
    let desc = particle(Vec3::new(0.0, 100.0, 0.0), Vec3::new(3.0, 5.0, 0.0));
    world.add_particle(ParticleDesc { mass: 2.0, acceleration: Vec3::new(0.0, -G, 0.0), ..desc }).unwrap();
    for _ in 0..100 {
        world.step(1.0 / 60.0).unwrap();
    }
    let energy = world.energy();
    let h = 1.0 / 240.0_f64;
    let expected = -0.5 * f64::from(G).powi(2) * h * h * 2.0 * 400.0;
    assert_eq!((energy.dissipated, energy.work), (0.0, 0.0), "nothing dissipates in free fall");
    assert!(
        (f64::from(energy.error) - expected).abs() < 1e-3,
        "error {} J, expected {expected} J",
        energy.error
    );
}

#[test]
fn an_undamped_springs_budget_balances_within_the_integrators_error() {
    // k = 20 N/m, 1 kg, 1 m out, 10 s at 60 Hz: semi-implicit Euler's energy oscillates
    // by about ωh (0.019) of itself and does not drift.
    let mut world = World::new();
    let id = world.add_particle(particle(Vec3::X, Vec3::ZERO)).unwrap();
    world.add_force(Spring::anchored(id, Vec3::ZERO, 20.0, 0.0)).unwrap();
    let start = world.energy();
    let mut worst = 0.0_f32;
    for _ in 0..600 {
        world.step(1.0 / 60.0).unwrap();
        let e = world.energy();
        assert_eq!((e.dissipated, e.work), (0.0, 0.0));
        worst = worst.max(e.error.abs());
    }
    let total = start.kinetic + start.potential;
    assert!(worst <= 0.02 * total, "error up to {worst} J of {total} J");
}

#[test]
fn a_bouncing_balls_dissipated_energy_is_its_lost_mechanical_energy() {
    // Within the integrator's error, which shrinks with the step: 2% at 60 Hz, 0.5% at
    // 240 Hz (measured 1.4% and 0.36%).
    for (hz, tolerance) in [(60.0, 0.02), (240.0, 0.005)] {
        bouncing_ball(hz, tolerance);
    }
}

fn bouncing_ball(hz: f32, tolerance: f32) {
    let mut world = World::new();
    let desc = particle(Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO);
    world.add_particle(ParticleDesc { acceleration: Vec3::new(0.0, -G, 0.0), radius: 0.1, ..desc }).unwrap();
    world.add_contact_generator(Plane::ground(0.0, 0.5, 0.0)).unwrap();
    let start = world.energy();
    for _ in 0..(4.0 * hz) as usize {
        world.step(1.0 / hz).unwrap();
    }
    let end = world.energy();
    let lost = (start.kinetic + start.potential) - (end.kinetic + end.potential);
    assert!(lost > 30.0, "it bounced and settled: lost {lost} J");
    // The bounces' losses are measured at the contacts; the rest is the integrator's
    // small error (its free-fall loss, and a bounce's shadow-energy correction).
    let case = format!("{hz} Hz: dissipated {} J, lost {lost} J, {end:?}", end.dissipated);
    assert!((end.dissipated - lost).abs() <= tolerance * lost, "{case}");
    assert!(end.error.abs() <= tolerance * lost, "{case}");
}

#[test]
fn damping_and_drag_are_counted_as_dissipated() {
    for drag in [false, true] {
        let mut world = World::new();
        let damping = if drag { 1.0 } else { 0.5 };
        let id = world
            .add_particle(ParticleDesc { damping, ..particle(Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)) })
            .unwrap();
        if drag {
            world.add_force(Drag { k1: 0.7, k2: 0.2, targets: vec![id] }).unwrap();
        }
        let start = world.energy().kinetic;
        for _ in 0..120 {
            world.step(1.0 / 60.0).unwrap();
        }
        let end = world.energy();
        let lost = start - end.kinetic;
        assert!(lost > 4.0, "drag {drag}: lost only {lost} J");
        assert!(
            (end.dissipated - lost).abs() <= 1e-3 * start,
            "drag {drag}: dissipated {} vs {lost}",
            end.dissipated
        );
    }
}

#[test]
fn what_changes_between_steps_is_work_and_a_removed_particle_takes_its_energy_away() {
    let mut world = World::new();
    let a = world.add_particle(particle(Vec3::ZERO, Vec3::ZERO)).unwrap();
    let b = world.add_particle(particle(Vec3::Y, Vec3::new(0.0, 0.0, 2.0))).unwrap();
    world.step(0.01).unwrap();
    // A push by hand (as the mouse gives): 0.5 * 1 * 3² = 4.5 J of work.
    world.particles.set_velocity(a, Vec3::new(3.0, 0.0, 0.0)).unwrap();
    world.step(0.01).unwrap();
    let e = world.energy();
    assert!((e.work - 4.5).abs() < 1e-4 && e.error.abs() < 1e-4, "{e:?}");
    // Removing b (2 J of kinetic energy) is neither work nor loss.
    world.remove_particle(b);
    world.step(0.01).unwrap();
    let e = world.energy();
    assert!((e.work - 4.5).abs() < 1e-4 && e.dissipated == 0.0 && e.error.abs() < 1e-4, "{e:?}");
}

#[test]
fn a_pendulums_rod_does_almost_no_work() {
    // Charging the rod with the kinetic energy it removes from gravity's kick would say
    // it took 0.165 J out in 10 s; the pendulum's energy really changes by 0.007 J. What
    // the rod does is its error, booked as the constraint term: nothing is dissipated.
    let mut world = World::new();
    let desc = ParticleDesc { acceleration: Vec3::new(0.0, -G, 0.0), ..particle(Vec3::X, Vec3::ZERO) };
    let bob = world.add_particle(desc).unwrap();
    world.add_contact_generator(Constraint::support_rod(bob, Vec3::ZERO, 1.0)).unwrap();
    for _ in 0..(10 * 240) {
        world.step(1.0 / 240.0).unwrap();
    }
    let e = world.energy();
    let change = e.kinetic + e.potential;
    assert_eq!(e.dissipated, 0.0, "{e:?}");
    assert!(e.constraint.abs() < 1e-3 * G && e.error.abs() < 1e-3 * G, "{e:?}");
    assert!((e.constraint + change).abs() < 1e-4, "the rod's work is the pendulum's change: {e:?}");
}

//! The energy ledger, booked once per step under every integrator (issue 18, items 1
//! and 2), checked against the closed form of the damped harmonic oscillator.
//!
//! Before the ledger was booked once per step, Verlet and RK4 booked drag's loss at
//! each of their force evaluations (2 and 4 a step): the same motion showed twice and
//! four times semi-implicit Euler's dissipation, and an error of the same size. The
//! closed-form stiff spring lost most of its energy under both without booking it.

use glam::{DVec3, Vec3};
use particle_lab::physics::stiff_spring::damped_oscillator;
use particle_lab::physics::*;

const HZ: f32 = 240.0;
const SECONDS: f32 = 10.0;
const SMOOTH: [Integrator; 3] = [Integrator::SemiImplicitEuler, Integrator::Verlet, Integrator::Rk4];

fn world_with(integrator: Integrator, kind: SolverKind) -> World {
    let mut world = World::new();
    let settings = SolverSettings { integrator, kind, ..SolverSettings::default() };
    world.set_solver(settings).unwrap();
    world
}

fn run(world: &mut World) -> Energy {
    for _ in 0..(SECONDS * HZ) as usize {
        world.step(1.0 / HZ).unwrap();
    }
    world.energy()
}

/// Mechanical energy of the damped oscillator `m x'' + c x' + k x = 0` after `t`, from
/// its closed form: `½ m v² + ½ k x²`.
fn oscillator_energy(m: f64, k: f64, c: f64, x0: f64, t: f64) -> f64 {
    let omega = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let (x, v) = damped_oscillator(DVec3::new(x0, 0.0, 0.0), DVec3::ZERO, omega, zeta, t);
    0.5 * m * v.length_squared() + 0.5 * k * x.length_squared()
}

#[test]
fn a_spring_with_drag_books_the_same_loss_under_every_integrator_and_it_is_the_closed_forms() {
    // 1 kg on a 20 N/m spring, 1 m out, linear drag k1 = 0.3 N·s/m: ζ = 0.034.
    let (m, k, c, x0) = (1.0, 20.0, 0.3, 1.0);
    let start = 0.5 * k * x0 * x0;
    let lost = start - oscillator_energy(m, k, c, x0, f64::from(SECONDS));
    let mut errors = Vec::new();
    for kind in [SolverKind::Soft, SolverKind::Paper] {
        for integrator in SMOOTH {
            let mut world = world_with(integrator, kind);
            let id = world
                .add_particle(ParticleDesc {
                    position: Vec3::X * x0 as f32,
                    radius: 0.0,
                    ..Default::default()
                })
                .unwrap();
            world.add_force(Spring::anchored(id, Vec3::ZERO, k as f32, 0.0)).unwrap();
            world.add_force(Drag { k1: c as f32, k2: 0.0, targets: vec![id] }).unwrap();
            let energy = run(&mut world);
            let case = format!("{kind:?} {integrator:?}: {energy:?}, closed form lost {lost:.4} J");
            let dissipated = f64::from(energy.dissipated);
            assert!((dissipated - lost).abs() <= 0.01 * lost, "{case}");
            // The reported error is the integrator's own: what the motion lost beyond
            // the closed form's energy, which the ledger did not book.
            assert!(f64::from(energy.error.abs()) <= 0.01 + 0.01 * dissipated, "{case}");
            let actual = f64::from(energy.kinetic + energy.potential);
            let exact = start - lost;
            assert!(
                (actual + dissipated - start - f64::from(energy.error)).abs() < 1e-3,
                "error = total + dissipated - start, {case}"
            );
            errors.push((kind, integrator, f64::from(energy.error.abs()), (actual - exact).abs()));
        }
    }
    // On a smooth problem the fourth-order method is never reported as worse.
    for kind in [SolverKind::Soft, SolverKind::Paper] {
        let of = |i: Integrator| errors.iter().find(|e| e.0 == kind && e.1 == i).unwrap().2;
        assert!(of(Integrator::Rk4) <= of(Integrator::SemiImplicitEuler) + 1e-4, "{kind:?}: {errors:?}");
    }
}

/// A particle under gravity on a closed-form stiff spring; returns (start total, end).
fn stiff(integrator: Integrator, kind: SolverKind, zeta: f32) -> (f64, Energy) {
    let mut world = world_with(integrator, kind);
    let id = world
        .add_particle(ParticleDesc {
            position: Vec3::new(0.5, 0.0, 0.0),
            mass: 2.0,
            acceleration: Vec3::new(0.0, -9.81, 0.0),
            radius: 0.0,
            ..Default::default()
        })
        .unwrap();
    world.add_force(StiffSpring::new(id, Vec3::ZERO, 3000.0, zeta)).unwrap();
    let start = world.energy();
    let end = run(&mut world);
    (f64::from(start.kinetic + start.potential), end)
}

#[test]
fn the_stiff_spring_keeps_its_energy_under_every_integrator_undamped_and_books_its_damping_loss() {
    for kind in [SolverKind::Soft, SolverKind::Paper] {
        for integrator in SMOOTH {
            // Undamped: the closed form keeps the energy; 37.5 J of spring, plus weight.
            let (start, end) = stiff(integrator, kind, 0.0);
            let total = f64::from(end.kinetic + end.potential);
            let case = format!("{kind:?} {integrator:?} undamped: start {start} J, {end:?}");
            assert!((total - start).abs() <= 0.01 * start.abs().max(1.0), "{case}");
            assert!(end.dissipated.abs() < 1e-3, "{case}");
            // Damped, ζ = 0.02: what it lost is booked, and it is the closed form's loss
            // about the rest point its weight sets.
            let (start, end) = stiff(integrator, kind, 0.02);
            let total = f64::from(end.kinetic + end.potential);
            let case = format!("{kind:?} {integrator:?} damped: start {start} J, {end:?}");
            let booked = total + f64::from(end.dissipated);
            assert!((booked - start).abs() <= 0.01 * start.abs().max(1.0), "{case}");
            let (m, k) = (2.0, 3000.0_f64);
            let sag = m * 9.81 / k;
            let c = 2.0 * 0.02 * (k * m).sqrt();
            // The oscillation about the sagged rest point, 0.5 m across and `sag` down.
            let amplitude = (0.25 + sag * sag).sqrt();
            let lost =
                0.5 * k * amplitude * amplitude - oscillator_energy(m, k, c, amplitude, f64::from(SECONDS));
            assert!((f64::from(end.dissipated) - lost).abs() <= 0.01 * lost, "{case}; closed form {lost} J");
        }
    }
}

/// Each particle's kinetic and gravitational energy (J) by id, from its state:
/// `½ m v² − m a·p` (the particles' constant acceleration is gravity here).
fn energies_by_id(world: &World) -> std::collections::HashMap<u32, f64> {
    let p = &world.particles;
    (0..p.len())
        .filter(|&i| p.inverse_masses()[i] > 0.0)
        .map(|i| {
            let m = f64::from(p.mass(i));
            let (v, x, a) =
                (p.velocities()[i].as_dvec3(), p.positions()[i].as_dvec3(), p.accelerations()[i].as_dvec3());
            (p.ids()[i].0, 0.5 * m * v.length_squared() - m * a.dot(x))
        })
        .collect()
}

/// Issue 18, item 3: the projectile's rounds come (fired between steps: work put in)
/// and go (removed when they land: energy carried out). The budget's total stays level
/// through both, the removed line is what each round had when it went, and nothing
/// reads −0 once the sky is empty.
#[test]
fn rounds_that_come_and_go_keep_the_budget_closed_with_a_removed_line() {
    use particle_lab::scenes::{self, SceneAction};
    let entry = scenes::find("projectile").unwrap();
    let mut scene = scenes::build_entry(entry, &[]).unwrap();
    let dt = entry.info().dt;
    let budget = |e: &Energy| f64::from(e.kinetic + e.potential + e.dissipated + e.removed - e.work);
    let start = budget(&scene.world().energy());
    let (mut removed, mut fired_energy) = (0.0_f64, 0.0_f64);
    // Semi-implicit Euler loses m g² h² / 2 per substep from a body in free fall (see
    // tests/energy.rs): the error the budget must show, and nothing more.
    let (m, g, h) = (200.0_f64, 20.0_f64, f64::from(dt) / 4.0);
    let mut integrator_loss = 0.0;
    for step in 0..2400 {
        if step == 100 || step == 250 || step == 900 {
            let before = energies_by_id(scene.world());
            assert!(scene.act(SceneAction::Fire));
            let after = energies_by_id(scene.world());
            fired_energy +=
                after.iter().filter(|(id, _)| !before.contains_key(id)).map(|(_, e)| e).sum::<f64>();
        }
        let before = energies_by_id(scene.world());
        integrator_loss += before.len() as f64 * 4.0 * 0.5 * m * g * g * h * h;
        scene.step(dt).unwrap();
        let after = energies_by_id(scene.world());
        // What the rounds that went carried, from their last state seen (their last
        // step's damping and integrator error are far below the tolerance).
        removed += before.iter().filter(|(id, _)| !after.contains_key(id)).map(|(_, e)| e).sum::<f64>();
        let e = scene.world().energy();
        let case = format!("step {step}: {e:?}, start {start}");
        let drift = budget(&e) - start;
        assert!((drift + integrator_loss).abs() <= 0.02 * integrator_loss + 1.0, "the budget moved: {case}");
        assert!((drift - f64::from(e.error)).abs() <= 0.05, "the error is the budget's drift: {case}");
        assert!((f64::from(e.removed) - removed).abs() <= 0.001 * removed.max(1.0), "{case}; seen {removed}");
        assert!((f64::from(e.work) - fired_energy).abs() <= 0.001 * fired_energy.max(1.0), "{case}");
    }
    let e = scene.world().energy();
    assert_eq!(scene.world().particles.len(), 0, "every round landed and went");
    assert!(removed > 100_000.0, "four rounds of 200 kg at 25 m/s went: {removed} J");
    for (name, value) in
        [("kinetic", e.kinetic), ("potential", e.potential), ("gravitational", e.gravitational)]
    {
        assert!(value == 0.0 && value.is_sign_positive(), "{name} reads {value:?} in an empty world");
    }
}

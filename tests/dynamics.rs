//! Integration, collisions, links and whole scenes against closed forms.

use glam::Vec3;
use particle_lab::physics::*;
use particle_lab::scenes;

const G: f32 = 9.81;

fn particle(position: Vec3, velocity: Vec3, mass: f32) -> ParticleDesc {
    ParticleDesc { position, velocity, mass, ..ParticleDesc::default() }
}

/// An empty world using the given solver.
fn world_on(kind: SolverKind) -> World {
    let mut world = World::new();
    world.set_solver(SolverSettings { kind, ..SolverSettings::default() }).unwrap();
    world
}

#[test]
fn free_fall_equals_the_closed_form_of_semi_implicit_euler() {
    for (kind, substeps) in [(SolverKind::Paper, 1.0), (SolverKind::Soft, 4.0)] {
        free_fall(kind, substeps);
    }
}

/// Semi-implicit Euler in steps of h = dt / substeps is exact in closed form.
fn free_fall(kind: SolverKind, substeps: f64) {
    let (y0, v0, dt) = (100.0_f64, 3.0_f64, 1.0 / 60.0_f64);
    let mut world = world_on(kind);
    world
        .add_particle(ParticleDesc {
            acceleration: Vec3::new(0.0, -G, 0.0),
            ..particle(Vec3::new(0.0, y0 as f32, 0.0), Vec3::new(0.0, v0 as f32, 0.0), 1.0)
        })
        .unwrap();
    let h = dt / substeps;
    for n in 1..=120_u32 {
        world.step(dt as f32).unwrap();
        let n = f64::from(n) * substeps;
        // y_n = y0 + v0 n h - g h² n(n+1)/2: the new velocity moves the position.
        let expected = y0 + v0 * n * h - f64::from(G) * h * h * n * (n + 1.0) / 2.0;
        let got = f64::from(world.particles.positions()[0].y);
        assert!((got - expected).abs() < 1e-3, "{kind:?} substep {n}: {got} vs {expected}");
    }
}

#[test]
fn damping_keeps_that_fraction_of_velocity_per_second() {
    let mut world = World::new();
    world
        .add_particle(ParticleDesc { damping: 0.5, ..particle(Vec3::ZERO, Vec3::new(8.0, 0.0, 0.0), 1.0) })
        .unwrap();
    for _ in 0..240 {
        world.step(1.0 / 240.0).unwrap();
    }
    // One second at damping 0.5 halves the speed, whatever the step.
    assert!((world.particles.velocities()[0].x - 4.0).abs() < 1e-3, "{}", world.particles.velocities()[0].x);
}

/// Runs the projectile scene's first round and returns (peak height, distance when it
/// comes back down to launch height), interpolating between steps.
fn fly(settings: &[&str]) -> (f32, f32) {
    let assignments: Vec<String> = settings.iter().map(|s| s.to_string()).collect();
    let mut scene = scenes::build("projectile", &assignments).unwrap();
    assert!(scenes::fire_at_start(scene.as_mut()), "a headless run's first round");
    let dt = 1.0 / 1000.0;
    let h = scene.params().get("height");
    let round = scene.world().particles.id(0).unwrap();
    let mut peak = f32::MIN;
    let mut previous = scene.world().particles.positions()[0];
    for _ in 0..100_000 {
        scene.step(dt).unwrap();
        let world = scene.world();
        let Some(i) = world.particles.index(round) else { break };
        let p = world.particles.positions()[i];
        peak = peak.max(p.y);
        if previous.y >= h && p.y < h && world.particles.velocities()[i].y < 0.0 {
            let t = (previous.y - h) / (previous.y - p.y);
            return (peak, previous.x + t * (p.x - previous.x));
        }
        previous = p;
    }
    panic!("the round never came back to launch height");
}

#[test]
fn projectile_peak_and_range_match_the_closed_forms() {
    for (speed, angle, g) in [(25.0_f32, 45.0_f32, 20.0_f32), (30.0, 40.0, 9.81), (15.0, 20.0, 5.0)] {
        let (peak, range) = fly(&[
            &format!("speed={speed}"),
            &format!("angle={angle}"),
            &format!("g={g}"),
            "damping=1",
            "height=1.5",
        ]);
        let theta = angle.to_radians();
        let expected_peak = 1.5 + (speed * theta.sin()).powi(2) / (2.0 * g);
        let expected_range = speed * speed * (2.0 * theta).sin() / g;
        assert!((peak - expected_peak).abs() / expected_peak < 0.01, "peak {peak} vs {expected_peak}");
        assert!((range - expected_range).abs() / expected_range < 0.01, "range {range} vs {expected_range}");
    }
}

#[test]
fn projectile_damping_shortens_the_flight() {
    let (_, free) = fly(&["damping=1"]);
    let (_, damped) = fly(&["damping=0.9"]);
    assert!(damped < free * 0.97, "damped {damped} vs free {free}");
}

#[test]
fn spring_period_matches_two_pi_root_m_over_k() {
    for (k, mass) in [(20.0_f32, 1.0_f32), (100.0, 2.5), (5.0, 0.5)] {
        let mut scene = scenes::build(
            "springForces",
            &[format!("k={k}"), format!("mass={mass}"), "damping=1".into(), "g=9.81".into()],
        )
        .unwrap();
        let dt = 1.0 / 1000.0;
        // The bob (particle 0) starts at rest; its velocity changes sign every half period.
        let mut crossings = Vec::new();
        let mut previous = 0.0_f32;
        let mut t = 0.0_f64;
        while crossings.len() < 5 {
            scene.step(dt).unwrap();
            t += f64::from(dt);
            let vy = scene.world().particles.velocities()[0].y;
            if previous < 0.0 && vy >= 0.0 {
                crossings.push(t);
            }
            previous = vy;
            assert!(t < 60.0, "no oscillation found");
        }
        let measured = (crossings[4] - crossings[0]) / 4.0;
        let expected = std::f64::consts::TAU * f64::from(mass / k).sqrt();
        assert!((measured - expected).abs() / expected < 0.01, "k {k} m {mass}: {measured} vs {expected}");
    }
}

#[test]
fn undamped_spring_keeps_its_energy() {
    let mut world = World::new();
    let id = world.add_particle(particle(Vec3::new(1.0, 0.0, 0.0), Vec3::ZERO, 1.0)).unwrap();
    world.add_force(Spring::anchored(id, Vec3::ZERO, 50.0, 0.0)).unwrap();
    let start = world.energy();
    let mut worst = 0.0_f32;
    for _ in 0..2400 {
        world.step(1.0 / 240.0).unwrap();
        let e = world.energy();
        worst = worst.max(((e.kinetic + e.potential) - (start.kinetic + start.potential)).abs());
    }
    // Semi-implicit Euler conserves a shadow energy: the drift stays bounded (2% here).
    assert!(worst < 0.02 * start.potential, "energy drifted by {worst} J of {}", start.potential);
}

/// Two spheres of radius 0.5 approaching head-on along x; returns the world after the
/// collision has been resolved and the masses.
fn head_on(kind: SolverKind, mass_ratio: f32, restitution: f32) -> (f32, f32, Vec3, Vec3, Vec3, Vec3) {
    let (ma, mb) = (1.0, mass_ratio);
    let (va, vb) = (Vec3::new(3.0, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.0));
    let mut world = world_on(kind);
    world
        .add_particle(ParticleDesc { radius: 0.5, ..particle(Vec3::new(-0.505, 0.0, 0.0), va, ma) })
        .unwrap();
    world.add_particle(ParticleDesc { radius: 0.5, ..particle(Vec3::new(0.505, 0.0, 0.0), vb, mb) }).unwrap();
    world.add_contact_generator(SphereCollisions::elastic(restitution)).unwrap();
    for _ in 0..5 {
        world.step(0.01).unwrap();
    }
    (ma, mb, va, vb, world.particles.velocities()[0], world.particles.velocities()[1])
}

#[test]
fn head_on_collisions_conserve_momentum_and_apply_restitution() {
    for (kind, ratio, e) in solvers_ratios_restitutions() {
        {
            let (ma, mb, ua, ub, va, vb) = head_on(kind, ratio, e);
            let before = ua * ma + ub * mb;
            let after = va * ma + vb * mb;
            let relative = (after - before).length() / before.length();
            assert!(relative < 1e-5, "{kind:?} ratio {ratio} e {e}: momentum off by {relative}");
            let closing = (ua - ub).x; // 4 m/s
            let separating = (vb - va).x;
            assert!(
                (separating - e * closing).abs() < 0.02,
                "{kind:?} ratio {ratio} e {e}: separating {separating}, expected {}",
                e * closing
            );
        }
    }
}

fn solvers_ratios_restitutions() -> impl Iterator<Item = (SolverKind, f32, f32)> {
    SolverKind::ALL.into_iter().flat_map(|kind| {
        [1.0, 10.0, 100.0].into_iter().flat_map(move |ratio| [0.0, 0.5, 1.0].map(|e| (kind, ratio, e)))
    })
}

#[test]
fn interpenetration_is_removed_in_proportion_to_inverse_mass() {
    // The paper's resolver moves positions at once.
    let mut world = world_on(SolverKind::Paper);
    world.add_particle(ParticleDesc { radius: 1.0, ..particle(Vec3::ZERO, Vec3::ZERO, 1.0) }).unwrap();
    world
        .add_particle(ParticleDesc { radius: 1.0, ..particle(Vec3::new(1.0, 0.0, 0.0), Vec3::ZERO, 3.0) })
        .unwrap();
    world.add_contact_generator(SphereCollisions::elastic(0.5)).unwrap();
    world.step(1e-3).unwrap();
    let (a, b) = (world.particles.positions()[0].x, world.particles.positions()[1].x);
    let slop = world.resolver().slop;
    // Overlap 1 m (less the slop): the 1 kg sphere moves 3/4 of it, the 3 kg one 1/4.
    assert!((a + 0.75 * (1.0 - slop)).abs() < 1e-4, "a moved to {a}");
    assert!((b - 1.0 - 0.25 * (1.0 - slop)).abs() < 1e-4, "b moved to {b}");

    // The soft solver pushes apart with velocity (no faster than its push speed), so the
    // overlap is gone after a while, the moves still 3 : 1, momentum zero throughout.
    let mut world = world_on(SolverKind::Soft);
    world.set_solver(SolverSettings { sleep: false, ..*world.solver() }).unwrap();
    world.add_particle(ParticleDesc { radius: 1.0, ..particle(Vec3::ZERO, Vec3::ZERO, 1.0) }).unwrap();
    world
        .add_particle(ParticleDesc { radius: 1.0, ..particle(Vec3::new(1.0, 0.0, 0.0), Vec3::ZERO, 3.0) })
        .unwrap();
    world.add_contact_generator(SphereCollisions::elastic(0.5)).unwrap();
    for _ in 0..240 {
        world.step(1.0 / 240.0).unwrap();
        let momentum = world.particles.velocities()[0] + 3.0 * world.particles.velocities()[1];
        assert!(momentum.length() < 1e-4, "momentum {momentum}");
    }
    let (a, b) = (world.particles.positions()[0].x, world.particles.positions()[1].x);
    assert!(b - a >= 2.0 - 1e-3, "still overlapping: {}", 2.0 - (b - a));
    assert!((a / (b - 1.0) + 3.0).abs() < 1e-3, "moves {a} and {} are not 3 : 1", b - 1.0);
}

#[test]
fn ball_comes_to_rest_on_the_ground_without_jitter() {
    for kind in SolverKind::ALL {
        ball_rests(kind);
    }
}

fn ball_rests(kind: SolverKind) {
    let mut world = world_on(kind);
    world
        .add_particle(ParticleDesc {
            acceleration: Vec3::new(0.0, -G, 0.0),
            radius: 0.5,
            ..particle(Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, 1.0)
        })
        .unwrap();
    world.add_contact_generator(GroundPlane { height: 0.0, restitution: 0.5 }).unwrap();
    let mut first_bounce_speed = 0.0_f32;
    for _ in 0..(240 * 5) {
        world.step(1.0 / 240.0).unwrap();
        first_bounce_speed = first_bounce_speed.max(world.particles.velocities()[0].y);
    }
    // It bounced (restitution), then settled: at rest, resting on its radius.
    assert!(first_bounce_speed > 2.0, "{kind:?} never bounced: {first_bounce_speed}");
    for _ in 0..240 {
        world.step(1.0 / 240.0).unwrap();
        let (p, v) = (world.particles.positions()[0], world.particles.velocities()[0]);
        assert!(v.length() < 1e-3, "{kind:?}: resting ball moves at {v:?}");
        assert!((p.y - 0.5).abs() < 1e-3, "{kind:?}: resting ball at height {}", p.y);
    }
}

#[test]
fn rods_keep_their_length_and_cables_never_overstretch() {
    for kind in SolverKind::ALL {
        swinging_chain(kind);
    }
}

/// A swinging chain: anchor -rod- a -cable- b -rod- c, flung sideways.
fn flung_chain(kind: SolverKind) -> World {
    let mut world = world_on(kind);
    let gravity = Vec3::new(0.0, -G, 0.0);
    let mut add = |position: Vec3, velocity: Vec3| {
        world
            .add_particle(ParticleDesc { acceleration: gravity, ..particle(position, velocity, 1.0) })
            .unwrap()
    };
    let a = add(Vec3::new(1.5, 5.0, 0.0), Vec3::new(0.0, 0.0, 4.0));
    let b = add(Vec3::new(3.0, 5.0, 0.0), Vec3::new(2.0, 3.0, 0.0));
    let c = add(Vec3::new(3.0, 3.5, 0.0), Vec3::new(-3.0, 0.0, 1.0));
    world.add_contact_generator(Constraint::support_rod(a, Vec3::new(0.0, 5.0, 0.0), 1.5)).unwrap();
    world.add_contact_generator(Constraint::cable(a, b, 1.6, 0.3)).unwrap();
    world.add_contact_generator(Constraint::rod(b, c, 1.5)).unwrap();
    world
}

fn swinging_chain(kind: SolverKind) {
    let mut world = flung_chain(kind);
    for step in 0..2400 {
        world.step(1.0 / 240.0).unwrap();
        for link in world.links() {
            let strain = (link.length - link.spec.rest) / link.spec.rest;
            match link.spec.kind {
                LinkKind::Rod | LinkKind::SupportRod => {
                    assert!(strain.abs() < 1e-3, "{kind:?} step {step}: rod strain {strain}")
                }
                LinkKind::Cable => assert!(strain < 0.01, "{kind:?} step {step}: cable stretched {strain}"),
                other => panic!("unexpected link {other:?}"),
            }
        }
    }
}

#[test]
fn bridge_with_load_settles_and_stays_up() {
    // Cyclone's damping 0.9 lets the deck sway for a while: give it 80 s.
    for (kind, load) in
        SolverKind::ALL.into_iter().flat_map(|k| [(k, ("load_x", "2.5")), (k, ("load_x", "0"))])
    {
        let mut scene =
            scenes::build("bridge", &[format!("{}={}", load.0, load.1), "load_mass=30".into()]).unwrap();
        scene.world_mut().set_solver(SolverSettings { kind, ..SolverSettings::default() }).unwrap();
        for _ in 0..(240 * 80) {
            scene.step(1.0 / 240.0).unwrap();
        }
        let world = scene.world();
        let fastest = world.particles.velocities().iter().map(|v| v.length()).fold(0.0, f32::max);
        let lowest = world.particles.positions().iter().map(|p| p.y).fold(f32::MAX, f32::min);
        assert!(fastest < 0.02, "{kind:?} {load:?}: still moving at {fastest} m/s");
        assert!(lowest > 1.5, "{kind:?} {load:?}: deck fell to {lowest} m");
        for link in world.links() {
            let strain = (link.length - link.spec.rest) / link.spec.rest;
            assert!(strain < 0.01, "{kind:?} {load:?}: {:?} stretched by {strain}", link.spec.kind);
        }
    }
}

#[test]
fn bridge_load_makes_nearby_cables_carry_more() {
    let tension_at = |x: &str| {
        let mut scene = scenes::build("bridge", &[format!("load_x={x}"), "load_mass=40".into()]).unwrap();
        for _ in 0..(240 * 20) {
            scene.step(1.0 / 240.0).unwrap();
        }
        let links = scene.world().links();
        let supports: Vec<f32> =
            links.iter().filter(|l| l.spec.kind == LinkKind::SupportCable).map(|l| l.tension).collect();
        (supports[0] + supports[1], supports[10] + supports[11])
    };
    let (left_near, right_far) = tension_at("0");
    let (left_far, right_near) = tension_at("5");
    assert!(left_near > 2.0 * left_far, "left supports: {left_near} N loaded vs {left_far} N");
    assert!(right_near > 2.0 * right_far, "right supports: {right_near} N loaded vs {right_far} N");
}

#[test]
fn stiff_spring_stays_finite_at_a_million_newtons_per_metre() {
    for zeta in [0.0, 0.05, 1.0, 3.0] {
        let mut world = World::new();
        let id = world
            .add_particle(ParticleDesc {
                acceleration: Vec3::new(0.0, -G, 0.0),
                ..particle(Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 5.0, 0.0), 1.0)
            })
            .unwrap();
        world.add_force(StiffSpring::new(id, Vec3::ZERO, 1.0e6, zeta)).unwrap();
        let start = world.particles.positions()[0].length();
        for _ in 0..6000 {
            world.step(1.0 / 60.0).unwrap();
            assert!(world.is_finite());
            assert!(world.particles.positions()[0].length() <= start * 1.01 + 0.01, "zeta {zeta} grew");
        }
    }
}

#[test]
fn explicit_stiff_spring_explodes_where_the_closed_form_does_not() {
    // The failure the paper describes, pinned down: ω·dt = 1000/60 ≫ 2.
    let mut world = World::new();
    let id = world.add_particle(particle(Vec3::new(1.0, 0.0, 0.0), Vec3::ZERO, 1.0)).unwrap();
    world.add_force(Spring::anchored(id, Vec3::ZERO, 1.0e6, 0.0)).unwrap();
    for _ in 0..20 {
        world.step(1.0 / 60.0).unwrap();
    }
    assert!(!world.is_finite() || world.particles.positions()[0].length() > 1e6);
}

#[test]
fn invalid_particles_and_steps_are_errors_not_panics() {
    let mut world = World::new();
    for mass in [0.0, -1.0, f32::NAN, f32::NEG_INFINITY, f32::INFINITY] {
        let result = world.add_particle(ParticleDesc { mass, ..ParticleDesc::default() });
        assert!(matches!(result, Err(PhysicsError::InvalidParticle(_))), "mass {mass}: {result:?}");
    }
    for damping in [-0.1, 1.5, f32::NAN] {
        let result = world.add_particle(ParticleDesc { damping, ..ParticleDesc::default() });
        assert!(result.is_err(), "damping {damping} accepted");
    }
    let bad_position = ParticleDesc { position: Vec3::new(f32::NAN, 0.0, 0.0), ..ParticleDesc::default() };
    assert!(world.add_particle(bad_position).is_err());
    assert!(world.particles.is_empty(), "nothing rejected was added");
    world.add_particle(ParticleDesc { immovable: true, ..ParticleDesc::default() }).unwrap();
    for dt in [0.0, -0.01, f32::NAN, f32::INFINITY] {
        let result = world.step(dt);
        assert!(matches!(result, Err(PhysicsError::InvalidTimeStep(_))), "dt {dt}: {result:?}");
    }
    assert_eq!(world.steps(), 0);
}

#[test]
fn immovable_particles_do_not_move() {
    let mut world = World::new();
    world
        .add_particle(ParticleDesc {
            immovable: true,
            acceleration: Vec3::new(0.0, -G, 0.0),
            ..particle(Vec3::ONE, Vec3::X, 1.0)
        })
        .unwrap();
    world.step(0.1).unwrap();
    assert_eq!(world.particles.positions()[0], Vec3::ONE);
    assert_eq!(world.particles.velocities()[0], Vec3::ZERO, "contacts must not see a velocity it never uses");
}

#[test]
fn removing_one_target_keeps_a_shared_field_on_the_others() {
    let mut world = World::new();
    let a = world.add_particle(particle(Vec3::ZERO, Vec3::X, 1.0)).unwrap();
    let b = world.add_particle(particle(Vec3::ONE, Vec3::X, 1.0)).unwrap();
    world.add_force(Drag { k1: 1.0, k2: 0.0, targets: vec![a, b] }).unwrap();
    world.remove_particle(a);
    assert_eq!(world.forces.len(), 1, "drag still acts on b");
    world.step(0.1).unwrap();
    assert!(
        world.particles.velocities()[0].x < 1.0,
        "b was not slowed: {:?}",
        world.particles.velocities()[0]
    );
    world.remove_particle(b);
    assert!(world.forces.is_empty(), "drag with no targets left is dropped");
}

#[test]
fn a_float_keeps_its_energy_while_bobbing() {
    let mut world = World::new();
    let id = world
        .add_particle(ParticleDesc {
            acceleration: Vec3::new(0.0, -G, 0.0),
            ..particle(Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, 1.0)
        })
        .unwrap();
    world
        .add_force(Buoyancy {
            target: id,
            surface: 1.0,
            half_height: 0.3,
            volume: 0.002,
            density: 1000.0,
            g: G,
        })
        .unwrap();
    let total = |w: &World| {
        let e = w.energy();
        e.kinetic + e.potential
    };
    let start = total(&world);
    let mut lowest = f32::MAX;
    for _ in 0..(240 * 10) {
        world.step(1.0 / 240.0).unwrap();
        lowest = lowest.min(world.particles.positions()[0].y);
        let drift = (total(&world) - start).abs();
        assert!(drift < 0.01 * start.abs().max(1.0), "energy drifted by {drift} J");
    }
    assert!(lowest < 1.0, "it went into the water");
}

#[test]
fn removing_a_particle_keeps_other_ids_and_drops_its_links() {
    let mut world = World::new();
    let ids: Vec<_> = (0..4)
        .map(|i| world.add_particle(particle(Vec3::new(i as f32, 0.0, 0.0), Vec3::ZERO, 1.0)).unwrap())
        .collect();
    world.add_force(Spring::between(ids[0], ids[1], 1.0, 1.0)).unwrap();
    world.add_contact_generator(Constraint::rod(ids[2], ids[3], 1.0)).unwrap();
    assert!(world.remove_particle(ids[0]));
    assert!(!world.remove_particle(ids[0]), "second removal is a no-op");
    assert_eq!(world.particles.len(), 3);
    for &id in &ids[1..] {
        let i = world.particles.index(id).unwrap();
        assert_eq!(world.particles.positions()[i].x, id.0 as f32, "id {id:?} lost its particle");
    }
    let links = world.links();
    assert_eq!(links.len(), 1, "the spring went with its particle");
    assert_eq!(links[0].spec.kind, LinkKind::Rod);
    world.step(0.01).unwrap();
}

#[test]
fn force_registry_adds_removes_and_clears() {
    let mut world = World::new();
    let id = world.add_particle(particle(Vec3::ZERO, Vec3::ZERO, 1.0)).unwrap();
    let up = world.add_force(Gravity { gravity: Vec3::Y, targets: vec![id] }).unwrap();
    let side = world.add_force(Gravity { gravity: Vec3::X, targets: vec![id] }).unwrap();
    world.step(1.0).unwrap();
    assert_eq!(world.particles.velocities()[0], Vec3::new(1.0, 1.0, 0.0));
    assert!(world.forces.remove(up));
    assert!(!world.forces.remove(up));
    world.step(1.0).unwrap();
    assert_eq!(world.particles.velocities()[0], Vec3::new(2.0, 1.0, 0.0));
    world.forces.clear();
    assert!(world.forces.is_empty());
    assert!(!world.forces.remove(side));
    world.step(1.0).unwrap();
    assert_eq!(world.particles.velocities()[0], Vec3::new(2.0, 1.0, 0.0));
}

#[test]
fn the_same_run_gives_the_same_bits() {
    let run = || {
        let mut scene = scenes::build("bridge", &["load_x=1.7".into()]).unwrap();
        for _ in 0..2000 {
            scene.step(1.0 / 240.0).unwrap();
        }
        let p = &scene.world().particles;
        p.positions()
            .iter()
            .chain(p.velocities())
            .flat_map(|v| v.to_array())
            .map(f32::to_bits)
            .collect::<Vec<_>>()
    };
    assert_eq!(run(), run());
}

#[test]
fn every_scene_runs_its_default_steps_and_stays_finite() {
    for entry in scenes::SCENES {
        let mut scene = entry.create_default();
        // As a headless run starts: the projectile's round fired at step 0.
        scenes::fire_at_start(scene.as_mut());
        assert!(!scene.world().particles.is_empty(), "{} starts empty", entry.info().name);
        for _ in 0..entry.info().default_steps {
            scene.step(entry.info().dt).unwrap();
        }
        assert!(scene.world().is_finite(), "{} blew up", entry.info().name);
    }
}

#[test]
fn soft_rods_hold_their_length_better_than_the_papers() {
    // The flung chain over 10 s: the largest rod strain, per solver (measured: soft
    // 2.4e-4, paper 3.4e-4).
    let rod_strain = |kind: SolverKind| {
        let mut world = flung_chain(kind);
        let mut worst = 0.0f32;
        for _ in 0..2400 {
            world.step(1.0 / 240.0).unwrap();
            for link in
                world.links().iter().filter(|l| matches!(l.spec.kind, LinkKind::Rod | LinkKind::SupportRod))
            {
                worst = worst.max(((link.length - link.spec.rest) / link.spec.rest).abs());
            }
        }
        worst
    };
    let (soft, paper) = (rod_strain(SolverKind::Soft), rod_strain(SolverKind::Paper));
    println!("largest rod strain: soft {soft:e}, paper {paper:e}");
    assert!(soft < paper, "soft {soft} vs paper {paper}");
}

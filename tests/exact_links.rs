//! The exact link solve (`LinkSolver::Exact`, the default): rods and cables solved
//! together each substep (see `src/physics/solver/soft/link_network/`). What it must keep
//! besides energy (tests/joint_energy.rs): tensions a tearing cloth can trust, cables
//! that never push, and rows of rods pulled straight between pins held still.

use glam::Vec3;
use particle_lab::physics::*;

const G: f32 = 9.81;
const DT: f32 = 1.0 / 240.0;

fn bead(world: &mut World, position: Vec3, mass: f32, immovable: bool) -> ParticleId {
    let desc = ParticleDesc {
        position,
        acceleration: Vec3::new(0.0, -G, 0.0),
        mass,
        immovable,
        radius: 0.0,
        ..ParticleDesc::default()
    };
    world.add_particle(desc).unwrap()
}

fn strain(world: &World) -> f32 {
    world.links().iter().map(|l| (l.length - l.spec.rest).abs() / l.spec.rest).fold(0.0, f32::max)
}

#[test]
fn a_hanging_chain_reads_the_weight_below_each_rod() {
    // Five 0.2 kg beads hanging still from an anchor by 0.5 m rods: rod k carries the
    // weight of the beads below it, which is what tearing compares with its limit.
    let mut world = World::new();
    let mut above = None;
    for k in 1..=5 {
        let id = bead(&mut world, Vec3::new(0.0, -0.5 * k as f32, 0.0), 0.2, false);
        let rod = match above {
            None => Constraint::support_rod(id, Vec3::ZERO, 0.5),
            Some(up) => Constraint::rod(id, up, 0.5),
        };
        world.add_contact_generator(rod).unwrap();
        above = Some(id);
    }
    for _ in 0..240 {
        world.step(DT).unwrap();
    }
    let links = world.links();
    for (k, link) in links.iter().enumerate() {
        let below = (5 - k) as f32 * 0.2 * G;
        assert!(
            (link.tension - below).abs() < 1e-3 * below,
            "rod {k}: {} N, the weight below is {below} N",
            link.tension
        );
    }
    assert!(strain(&world) < 1e-6, "strain {}", strain(&world));
}

#[test]
fn a_cable_never_pushes_and_never_stretches() {
    // A bead on a 1 m cable from an anchor, thrown up past the anchor's height: the
    // cable goes slack (it flies free: no tension) and catches it as it falls back.
    let mut world = World::new();
    let id = bead(&mut world, Vec3::new(0.6, -0.8, 0.0), 1.0, false);
    world.particles.set_velocity(id, Vec3::new(0.0, 4.0, 0.0)).unwrap();
    world.add_contact_generator(Constraint::support_cable(id, Vec3::ZERO, 1.0, 0.0)).unwrap();
    let (mut slack_steps, mut longest) = (0, 0.0f32);
    for _ in 0..480 {
        world.step(DT).unwrap();
        let link = world.links()[0];
        assert!(link.tension >= 0.0, "the cable pushed: {} N", link.tension);
        longest = longest.max(link.length);
        if link.length < 0.999 {
            slack_steps += 1;
            assert_eq!(link.tension, 0.0, "a slack cable pulled");
        }
    }
    assert!(slack_steps > 20, "the cable was slack for {slack_steps} steps");
    assert!(longest <= 1.0 + 1e-5, "the cable stretched to {longest} m");
}

/// A straight row of `rods` rods of 0.25 m between two pins, the pins `span` apart,
/// and a 0.5 kg bead hanging by a 1 m rod from the row's middle bead, pulled aside.
fn row_with_pendulum(span: f32, rods: usize) -> (World, Vec<ParticleId>, ParticleId) {
    let mut world = World::new();
    let row: Vec<_> = (0..=rods)
        .map(|i| {
            let x = span * i as f32 / rods as f32;
            bead(&mut world, Vec3::new(x, 2.0, 0.0), 0.1, i == 0 || i == rods)
        })
        .collect();
    for pair in row.windows(2) {
        world.add_contact_generator(Constraint::rod(pair[0], pair[1], 0.25)).unwrap();
    }
    let middle = row[rods / 2];
    let anchor = world.particles.positions()[world.particles.index(middle).unwrap()];
    let bob = bead(&mut world, anchor + Vec3::new(0.6, -0.8, 0.0), 0.5, false);
    world.add_contact_generator(Constraint::rod(bob, middle, 1.0)).unwrap();
    (world, row, bob)
}

#[test]
fn a_row_of_rods_pulled_straight_between_pins_holds_still() {
    // The row's rods add up to exactly the span: rigid rods cannot let it move at all
    // (the triangle inequality), so the bead hanging from it swings from a fixed
    // point, keeping its energy; the row's own rods read no tension (their self-stress
    // is beyond a rigid model), the hanging rod its share of the swing.
    let (mut world, row, bob) = row_with_pendulum(2.0, 8);
    let start: Vec<Vec3> = world.particles.positions().to_vec();
    let energy = |w: &World| f64::from(w.energy().kinetic) + f64::from(w.energy().gravitational);
    let before = energy(&world);
    for _ in 0..2400 {
        world.step(DT).unwrap();
    }
    for &id in &row {
        let i = world.particles.index(id).unwrap();
        assert_eq!(world.particles.positions()[i], start[i], "a bead of the row moved");
    }
    let after = energy(&world);
    assert!((after - before).abs() < 1e-3 * G as f64 * 0.5, "energy {before} J, then {after} J");
    let links = world.links();
    assert!(links[..8].iter().all(|l| l.tension == 0.0), "the held row reads a tension");
    let hanging = links[8].tension;
    assert!(hanging > 0.5 * G * 0.8 && hanging < 3.0 * 0.5 * G, "the pendulum's rod pulls {hanging} N");
    let i = world.particles.index(bob).unwrap();
    assert!(world.particles.velocities()[i].length() > 0.1, "the pendulum stopped");
}

#[test]
fn a_row_with_slack_sags_and_keeps_its_lengths() {
    // The same row, its pins 1% closer than its length (it starts straight, its rods
    // 1% short, and buckles): it swings and sags under the pendulum, solved (not
    // held): its rods keep their length and pull.
    let (mut world, row, _) = row_with_pendulum(1.98, 8);
    for _ in 0..240 {
        world.step(DT).unwrap();
    }
    let middle = world.particles.index(row[4]).unwrap();
    let mut lowest = f32::INFINITY;
    for _ in 0..480 {
        world.step(DT).unwrap();
        lowest = lowest.min(world.particles.positions()[middle].y);
        assert!(strain(&world) < 1e-4, "strain {}", strain(&world));
        assert!(world.links()[..8].iter().all(|l| l.tension > 0.0), "a rod of the sagging row does not pull");
    }
    // Hanging still, it would sag by 2 m × √(3 · 1% / 8) = 0.12 m.
    assert!(lowest < 1.92, "the row did not sag: lowest {lowest} m");
}

#[test]
fn soft_links_are_still_there_and_still_lose_energy() {
    // The soft link solver (Box2D's soft step) is kept for comparison: the 3-link
    // pendulum of tests/joint_energy.rs kept 99.89% with it at 240 Hz, and it stretches.
    let mut world = World::new();
    let settings = SolverSettings { link_solver: LinkSolver::Soft, ..SolverSettings::default() };
    world.set_solver(settings).unwrap();
    let mut above = None;
    for k in 1..=3 {
        let id = bead(&mut world, Vec3::new(k as f32, 0.0, 0.0), 1.0, false);
        let rod = match above {
            None => Constraint::support_rod(id, Vec3::ZERO, 1.0),
            Some(up) => Constraint::rod(id, up, 1.0),
        };
        world.add_contact_generator(rod).unwrap();
        above = Some(id);
    }
    let mut worst = 0.0f32;
    for _ in 0..240 {
        world.step(DT).unwrap();
        worst = worst.max(strain(&world));
    }
    assert!(worst > 1e-4, "soft rods stretch: {worst}");
}

#[test]
fn soft_links_replay_the_hashes_pinned_before_the_exact_solve() {
    // `LinkSolver::Soft` is the solver every link scene ran on before: it must still
    // give their pinned states of then, to the bit (tests/state_hashes.rs, 600 steps,
    // semi-implicit Euler, at the commit before the exact solve), with the contacts of
    // then (60 Hz, damping ratio 10; issue 39 made them 100 Hz and 5).
    use particle_lab::scenes::{self, SceneAction, snapshot::hash_text};
    let pinned = [
        ("bridge", "40f64b60aa7167bc"),
        ("pendulum", "e34ee4889934861b"),
        ("cradle", "9088c6ff37fe1823"),
        ("chain", "17a3c85d6ebe12e3"),
        ("platform", "8d98e75edd5f777c"),
    ];
    for (name, hash) in pinned {
        let mut scene = scenes::build(name, &[]).unwrap();
        let settings = SolverSettings {
            link_solver: LinkSolver::Soft,
            contact_hertz: 60.0,
            contact_damping_ratio: 10.0,
            ..*scene.world().solver()
        };
        scene.world_mut().set_solver(settings).unwrap();
        let dt = scene.info().dt;
        for step in 0..600 {
            if step == 0 || step == 200 {
                scene.act(SceneAction::Fire);
            }
            scene.step(dt).unwrap();
        }
        assert_eq!(hash_text(scene.world().state_hash()), hash, "{name}");
    }
}

#[test]
fn one_thread_and_two_threads_solve_a_long_chain_to_the_same_bits() {
    // 20,001 beads: the particle loops split across threads; the network is solved
    // in one fixed order.
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut world = World::new();
            let rods = 20_000;
            let ids: Vec<_> = (0..=rods)
                .map(|i| bead(&mut world, Vec3::new(0.01 * i as f32, 3.0, 0.0), 0.1, i == 0 || i == rods))
                .collect();
            for pair in ids.windows(2) {
                // 1% slack: the chain falls into its sag and is solved, not held.
                world.add_contact_generator(Constraint::rod(pair[0], pair[1], 0.0101)).unwrap();
            }
            for _ in 0..20 {
                world.step(DT).unwrap();
            }
            let p = &world.particles;
            let bits = |v: &[Vec3]| v.iter().flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>();
            (bits(p.positions()), bits(p.velocities()))
        })
    };
    let one = run(1);
    let lowest = one.0.chunks(3).map(|p| f32::from_bits(p[1])).fold(f32::INFINITY, f32::min);
    assert!(lowest < 2.99, "the chain should be falling: lowest bead at {lowest} m");
    assert!(one == run(2), "1 thread and 2 threads differ");
}

//! Work is bounded by what the user asked for (issue 17): spheres piled onto one point
//! cost memory and time linear in their number, and a chain of 200,000 rods (the most
//! a scene file makes) steps in linear time.

use std::time::{Duration, Instant};

use glam::Vec3;
use particle_lab::physics::broad_phase::{PAIRS_PER_SPHERE, all_pairs, pair_budget};
use particle_lab::physics::{
    BroadPhase, Constraint, ParticleDesc, Plane, SolverKind, SolverSettings, SphereCollisions, World,
};

/// `count` spheres of radius 0.1 at one point above a ground, colliding.
fn coincident(count: usize) -> World {
    let mut world = World::new();
    for _ in 0..count {
        let desc = ParticleDesc {
            position: Vec3::new(0.0, 1.0, 0.0),
            acceleration: Vec3::new(0.0, -9.81, 0.0),
            radius: 0.1,
            ..ParticleDesc::default()
        };
        world.add_particle(desc).unwrap();
    }
    world.add_contact_generator(Plane::ground(0.0, 0.0, 0.5)).unwrap();
    world.add_contact_generator(SphereCollisions::new(0.0, 0.3)).unwrap();
    world
}

#[test]
fn coincident_spheres_make_a_bounded_number_of_pairs() {
    let n = 10_000;
    let positions = vec![Vec3::splat(0.5); n];
    let reach = vec![0.1; n];
    let mut pairs = Vec::new();
    let mut grid = BroadPhase::new();
    let started = Instant::now();
    grid.find_pairs(&positions, &reach, &mut pairs);
    let took = started.elapsed();
    // Every pair touches: without a bound that is n(n-1)/2 = 49,995,000 of them.
    assert!(pairs.len() <= 32 * n, "{} pairs from {n} coincident spheres", pairs.len());
    assert!(took < Duration::from_secs(2), "the search took {took:?}");
    // Exactly the budget, reported as hit, and the first pairs of the full list.
    assert_eq!(PAIRS_PER_SPHERE, 32);
    assert_eq!(pairs.len(), pair_budget(n));
    assert!(grid.budget_hit());
    assert_eq!(pairs[..3], [(0, 1), (0, 2), (0, 3)]);
    assert!(pairs.windows(2).all(|w| w[0] < w[1]), "pairs out of order");
    // Spread out, the same spheres make every pair and report nothing.
    let spread: Vec<Vec3> = (0..n).map(|i| Vec3::new(0.15 * i as f32, 0.0, 0.0)).collect();
    grid.find_pairs(&spread, &reach, &mut pairs);
    assert_eq!((pairs.len(), grid.budget_hit()), (n - 1, false));
}

#[test]
fn past_the_budget_the_pairs_are_the_full_list_cut_short() {
    // Coincident clusters among spread spheres, above the threaded size: the kept pairs
    // are the reference's first ones, whatever the threads did.
    let n = 12_000;
    let positions: Vec<Vec3> = (0..n)
        .map(|i| if i % 3 == 0 { Vec3::splat((i % 4) as f32) } else { Vec3::new(0.3 * i as f32, 5.0, 0.0) })
        .collect();
    let reach = vec![0.1; n];
    let (mut found, mut expected) = (Vec::new(), Vec::new());
    let mut grid = BroadPhase::new();
    grid.find_pairs(&positions, &reach, &mut found);
    all_pairs(&positions, &reach, &mut expected);
    assert!(expected.len() > pair_budget(n), "the test should exceed the budget");
    assert!(grid.budget_hit());
    assert_eq!(found[..], expected[..pair_budget(n)]);
}

#[test]
fn three_thousand_coincident_spheres_step_quickly() {
    let n = 3_000;
    let mut world = coincident(n);
    let started = Instant::now();
    for _ in 0..10 {
        world.step(1.0 / 240.0).unwrap();
    }
    let took = started.elapsed();
    // Sphere pairs are capped; the ground adds one contact per sphere.
    let contacts = world.contact_count();
    assert!(contacts <= 32 * n + n, "{contacts} contacts from {n} coincident spheres");
    assert!(world.is_finite());
    // The spheres are pushed apart: the pile is no longer one point.
    let p = &world.particles;
    let spread = p.positions().iter().map(|q| q.distance(p.positions()[0])).fold(0.0, f32::max);
    assert!(spread > 0.01, "after 10 steps the spheres are at most {spread} m apart");
    assert!(took < Duration::from_secs(10), "10 steps took {took:?}");
}

#[test]
fn ten_thousand_coincident_spheres_cost_linear_memory_on_both_solvers() {
    for kind in [SolverKind::Soft, SolverKind::Paper] {
        let mut counts = Vec::new();
        for n in [10_000, 20_000] {
            let mut world = coincident(n);
            world.set_solver(SolverSettings { kind, ..SolverSettings::default() }).unwrap();
            let started = Instant::now();
            world.step(1.0 / 240.0).unwrap();
            let took = started.elapsed();
            let contacts = world.contact_count();
            assert!(contacts <= 32 * n + n, "{kind:?}: {contacts} contacts from {n} coincident spheres");
            assert!(world.last_report().pair_budget_hit, "{kind:?}: the budget was not reported");
            assert!(world.is_finite(), "{kind:?}: {n} spheres");
            assert!(took < Duration::from_secs(10), "{kind:?}: a step of {n} spheres took {took:?}");
            counts.push(contacts as f64);
        }
        // Twice the spheres, about twice the contacts (not four times).
        let ratio = counts[1] / counts[0];
        assert!(ratio < 2.5, "{kind:?}: contacts grew {ratio} times for twice the spheres");
    }
}

/// A chain of `rods` rods of 1 cm in a row, pinned at both ends, under gravity.
fn chain(rods: usize, kind: SolverKind) -> World {
    chain_of(rods, kind, 0.01)
}

/// The same row of beads joined by rods of `length` (m): longer than 1 cm, the chain
/// has slack and sags; at 1 cm it is pulled straight between its pins, and rigid rods
/// hold it still (the exact link solve then has nothing to solve).
fn chain_of(rods: usize, kind: SolverKind, length: f32) -> World {
    let mut world = World::new();
    world.set_solver(SolverSettings { kind, ..SolverSettings::default() }).unwrap();
    let ids: Vec<_> = (0..=rods)
        .map(|i| {
            let desc = ParticleDesc {
                position: Vec3::new(0.01 * i as f32, 3.0, 0.0),
                acceleration: Vec3::new(0.0, -9.81, 0.0),
                mass: 0.1,
                immovable: i == 0 || i == rods,
                damping: 0.8,
                radius: 0.004,
                ..ParticleDesc::default()
            };
            world.add_particle(desc).unwrap()
        })
        .collect();
    for pair in ids.windows(2) {
        world.add_contact_generator(Constraint::rod(pair[0], pair[1], length)).unwrap();
    }
    world
}

/// The fastest of a few steps of a chain, after one to warm its buffers (and, with the
/// soft solver, its warm start: the links' impulses of the step before).
fn step_time(rods: usize, kind: SolverKind) -> Duration {
    step_time_of(chain(rods, kind))
}

fn step_time_of(mut world: World) -> Duration {
    world.step(1.0 / 240.0).unwrap();
    let fastest = (0..5)
        .map(|_| {
            let started = Instant::now();
            world.step(1.0 / 240.0).unwrap();
            started.elapsed()
        })
        .min()
        .unwrap();
    assert!(world.is_finite());
    fastest
}

#[test]
fn a_chain_of_200000_rods_steps_in_linear_time() {
    // The soft solver took 6.5 s a step at 200,000 rods (0.45 s at 50,000: quadratic);
    // the issue asks for at most 1 s here, and it takes about 0.15 s. Only the bound is
    // asserted, with room for a loaded machine: a ratio of step times between sizes
    // swings with the caches (4x to 13x from 50,000 to 200,000 in runs here), so it is
    // printed, not asserted; the benchmarks are where speed is measured.
    let small = step_time(50_000, SolverKind::Soft);
    let large = step_time(200_000, SolverKind::Soft);
    println!("50,000 rods {small:?} a step, 200,000 rods {large:?}");
    assert!(large < Duration::from_secs(2), "a step of 200,000 rods took {large:?} (50,000: {small:?})");
    // The paper's resolver (its worst-first search is timed on coincident spheres
    // above): 20,000 rods fit in the caches, so only a bound on the large chain.
    let large = step_time(200_000, SolverKind::Paper);
    assert!(large < Duration::from_secs(3), "paper: a step of 200,000 rods took {large:?}");
}

#[test]
fn a_slack_chain_of_200000_rods_is_solved_in_linear_time() {
    // The straight chain above is held still by its rigid rods; with 0.1% slack it
    // sags, and the exact link solve works on all 200,000 rods at once: its matrix is
    // tridiagonal, its factorization linear (about 0.3 s a step here, 0.09 s at
    // 50,000; the soft solve of the same chain 0.08 s).
    let small = step_time_of(chain_of(50_000, SolverKind::Soft, 0.01001));
    let large = step_time_of(chain_of(200_000, SolverKind::Soft, 0.01001));
    println!("slack: 50,000 rods {small:?} a step, 200,000 rods {large:?}");
    assert!(large < Duration::from_secs(2), "a step of 200,000 rods took {large:?} (50,000: {small:?})");
}

/// The budget is said, not only kept: `simulate` warns once, on one line, at the first
/// step that hits it, and the window's status line says it.
#[test]
fn a_run_that_hits_the_pair_budget_says_so_once() {
    let dir = std::env::temp_dir().join(format!("particle-lab-budget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("heap.toml");
    std::fs::write(
        &file,
        "[scene]\nname = \"heap\"\n\n[[row]]\nname = \"heap\"\ncount = 3000\nstart = [0, 1, 0]\nstep = [0, 0, 0]\n\
         radius = 0.5\n\n[ground]\n\n[collisions]\n",
    )
    .unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--scene-file", file.to_str().unwrap(), "--steps", "3", "--every", "3"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("budget")).collect();
    assert_eq!(warnings.len(), 1, "one warning for the run: {stderr}");
    assert!(warnings[0].starts_with("particle-lab: warning: at step 1,"), "{stderr}");
    let entry = particle_lab::scenes::file::load_path(&file).unwrap();
    let mut lab = particle_lab::ui::Lab::from_entry(&entry, &[], Default::default()).unwrap();
    lab.run_steps(1);
    assert!(lab.status.contains(particle_lab::physics::broad_phase::BUDGET_HIT_MESSAGE), "{}", lab.status);
    std::fs::remove_dir_all(&dir).ok();
}

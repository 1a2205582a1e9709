//! One world step of 1,000,000 free particles under gravity and damping, next to a
//! plain copy of the bytes the step reads and writes, measured in the same run; and a
//! step of chains of rods at 50,000 and 200,000 rods on both solvers (issue 17: the
//! longest chain a file may make took 7 s a step when the soft solver's warm start
//! searched a list per link; linear, the two sizes are 4x apart).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use particle_lab::physics::{Constraint, ParticleDesc, SolverKind, SolverSettings, World};

const N: usize = 1_000_000;
const DT: f32 = 1.0 / 240.0;

fn world() -> World {
    let mut world = World::new();
    world.particles = particle_lab::physics::Particles::with_capacity(N);
    for i in 0..N {
        let f = i as f32;
        world
            .add_particle(ParticleDesc {
                position: Vec3::new(f.sin() * 100.0, 1000.0 + f.cos() * 100.0, f * 1e-3),
                velocity: Vec3::new(1.0, f.sin(), -1.0),
                acceleration: Vec3::new(0.0, -9.81, 0.0),
                mass: 1.0 + (i % 7) as f32,
                damping: 0.99,
                radius: 0.0,
                immovable: false,
            })
            .expect("valid particle");
    }
    world
}

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_1m_particles");
    group.throughput(Throughput::Elements(N as u64));
    group.sample_size(20);

    let mut w = world();
    w.step(DT).expect("valid dt");
    group.bench_function("world_step", |b| b.iter(|| black_box(&mut w).step(DT).expect("valid dt")));

    // The step reads position, velocity, acceleration, force, inverse mass and the
    // damping factor, and writes position, velocity and force: copy those same arrays.
    let p = &w.particles;
    let source = (
        p.positions().to_vec(),
        p.velocities().to_vec(),
        p.accelerations().to_vec(),
        p.forces().to_vec(),
        p.inverse_masses().to_vec(),
        p.inverse_masses().to_vec(),
    );
    let mut target = source.clone();
    group.bench_function("plain_copy_same_bytes", |b| {
        b.iter(|| {
            let (s, t) = (black_box(&source), &mut target);
            t.0.copy_from_slice(&s.0);
            t.1.copy_from_slice(&s.1);
            t.2.copy_from_slice(&s.2);
            t.3.copy_from_slice(&s.3);
            t.4.copy_from_slice(&s.4);
            t.5.copy_from_slice(&s.5);
            black_box(&target);
        })
    });
    group.finish();
}

/// A horizontal chain of `rods` rods of 1 cm pinned at both ends, falling into its sag.
fn chain(rods: usize, kind: SolverKind) -> World {
    let mut world = World::new();
    world.set_solver(SolverSettings { kind, ..SolverSettings::default() }).expect("valid settings");
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
            world.add_particle(desc).expect("valid particle")
        })
        .collect();
    for pair in ids.windows(2) {
        world.add_contact_generator(Constraint::rod(pair[0], pair[1], 0.01)).expect("valid rod");
    }
    world
}

fn chains(c: &mut Criterion) {
    let mut group = c.benchmark_group("chain_of_rods");
    group.sample_size(10);
    for kind in [SolverKind::Soft, SolverKind::Paper] {
        for rods in [50_000, 200_000] {
            let mut w = chain(rods, kind);
            w.step(DT).expect("valid dt");
            let name = format!("{}/{rods}", kind.name());
            group.bench_function(name, |b| b.iter(|| black_box(&mut w).step(DT).expect("valid dt")));
        }
    }
    group.finish();
}

criterion_group!(benches, step, chains);
criterion_main!(benches);

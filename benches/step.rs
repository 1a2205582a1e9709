//! One world step of 1,000,000 free particles under gravity and damping, next to a
//! plain copy of the bytes the step reads and writes, measured in the same run.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use particle_lab::physics::{ParticleDesc, World};

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

criterion_group!(benches, step);
criterion_main!(benches);

//! Granular matter (issue 21): spheres that roll fall off each other. A tower of
//! frictional spheres that stands as point masses collapses once they roll, and the
//! heap it leaves rests at a physical angle of repose (20–35° for μ = 0.5 with the
//! default rolling resistance; flatter for less friction).
//!
//! The angle is measured from the heap's surface: the highest sphere top in rings
//! around the heap's axis, fitted by a straight line over the flank (between a fifth
//! and four fifths of the heap's radius), so stray spheres rolled far out and the
//! rounded top do not count.

use glam::Vec3;
use particle_lab::physics::*;

const RADIUS: f32 = 0.5;
const G: f32 = 9.81;
const DT: f32 = 1.0 / 60.0;

/// A column of `side × side × layers` spheres stacked on open ground, jittered by up to
/// 2 cm sideways (a fixed pattern), with friction `mu` and rolling resistance `mu_r`.
fn tower(side: usize, layers: usize, mu: f32, mu_r: f32, rolls: bool) -> World {
    let mut world = World::new();
    world.add_contact_generator(Plane::ground(0.0, 0.0, mu).with_rolling_resistance(mu_r)).unwrap();
    let mut spheres = SphereCollisions::new(0.0, mu);
    spheres.rolling_resistance = mu_r;
    world.add_contact_generator(spheres).unwrap();
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let mut jitter = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        ((seed >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * 0.02
    };
    let offset = (side as f32 - 1.0) * RADIUS;
    for layer in 0..layers {
        for row in 0..side {
            for column in 0..side {
                let x = column as f32 * 2.0 * RADIUS - offset + jitter();
                let z = row as f32 * 2.0 * RADIUS - offset + jitter();
                let y = RADIUS + layer as f32 * 2.0 * RADIUS * 1.001;
                let desc = ParticleDesc {
                    position: Vec3::new(x, y, z),
                    acceleration: Vec3::new(0.0, -G, 0.0),
                    radius: RADIUS,
                    ..ParticleDesc::default()
                };
                let id = world.add_particle(desc).unwrap();
                world.particles.set_rolling(id, rolls).unwrap();
            }
        }
    }
    world
}

/// Pours `count` spheres onto open ground, one every `every` steps, each dropped at
/// rest from just above the heap's top (within 0.2 m of its axis), then lets the heap
/// settle. Friction `mu`, rolling resistance `mu_r`.
fn pour(count: usize, mu: f32, mu_r: f32, rolls: bool) -> World {
    let mut world = tower(1, 0, mu, mu_r, rolls);
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut jitter = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        ((seed >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * 0.2
    };
    let every = 4;
    for step in 0..count * every {
        if step % every == 0 {
            // Above the heap's top: the highest sphere that has landed (slow).
            let p = &world.particles;
            let landed = p.positions().iter().zip(p.velocities()).filter(|(_, v)| v.length() < 0.5);
            let y = landed.map(|(p, _)| p.y + RADIUS).fold(0.0, f32::max) + 2.0 * RADIUS;
            let desc = ParticleDesc {
                position: Vec3::new(jitter(), y, jitter()),
                acceleration: Vec3::new(0.0, -G, 0.0),
                radius: RADIUS,
                ..ParticleDesc::default()
            };
            let id = world.add_particle(desc).unwrap();
            world.particles.set_rolling(id, rolls).unwrap();
        }
        world.step(DT).unwrap();
    }
    settle(&mut world, 20.0);
    world
}

/// Steps until every sphere sleeps (or `seconds` pass); returns the seconds taken.
fn settle(world: &mut World, seconds: f32) -> f32 {
    let mut t = 0.0;
    while t < seconds {
        world.step(DT).unwrap();
        t += DT;
        if world.particles.asleep_count() == world.particles.len() {
            break;
        }
    }
    t
}

/// Highest sphere top (m).
fn height(world: &World) -> f32 {
    world.particles.positions().iter().map(|p| p.y + RADIUS).fold(0.0, f32::max)
}

/// The heap's angle of repose (degrees), from its surface profile (see the file's doc).
fn angle_of_repose(world: &World) -> f32 {
    particle_lab::scenes::pile::angle_of_repose(world.particles.positions(), RADIUS)
}

#[test]
fn a_tower_of_rolling_spheres_falls_where_point_masses_stand() {
    // The tower: 4 × 4 × 125 spheres, 2 cm jitter, μ = 0.5.
    let start = height(&tower(4, 125, 0.5, DEFAULT_ROLLING_RESISTANCE, true));
    let mut standing = tower(4, 125, 0.5, DEFAULT_ROLLING_RESISTANCE, false);
    settle(&mut standing, 40.0);
    let mut falling = tower(4, 125, 0.5, DEFAULT_ROLLING_RESISTANCE, true);
    settle(&mut falling, 40.0);
    let (stands, falls) = (height(&standing), height(&falling));
    println!("tower {start:.1} m: point masses {stands:.1} m, rolling spheres {falls:.1} m");
    assert!(stands > 0.95 * start, "the point-mass tower fell to {stands} m of {start}");
    assert!(falls < 0.1 * start, "the rolling tower still stands {falls} m of {start}");
    assert_eq!(
        falling.particles.asleep_count(),
        falling.particles.len(),
        "the fallen tower never came to rest"
    );
}

#[test]
fn a_poured_heap_rests_at_a_physical_angle_and_flatter_with_less_friction() {
    let heap = |mu: f32, rolls: bool| {
        let world = pour(1000, mu, DEFAULT_ROLLING_RESISTANCE, rolls);
        assert_eq!(
            world.particles.asleep_count(),
            world.particles.len(),
            "μ = {mu}: the heap never came to rest"
        );
        angle_of_repose(&world)
    };
    let (rolling, slippery, points) = (heap(0.5, true), heap(0.2, true), heap(0.5, false));
    println!(
        "angle of repose: μ 0.5 rolling {rolling:.1}°, μ 0.2 rolling {slippery:.1}°, μ 0.5 point masses {points:.1}°"
    );
    assert!((20.0..=35.0).contains(&rolling), "μ = 0.5 heap of rolling spheres at {rolling}°");
    assert!(slippery < rolling - 3.0, "μ = 0.2 heap at {slippery}°, not flatter than μ = 0.5's {rolling}°");
    assert!(points > 50.0, "point masses at {points}°: the glue-like heap the issue measured is gone?");
}

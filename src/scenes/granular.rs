//! What the granular scenes (the pile and the hourglass) share: the open box of five
//! planes they stand in, the collisions between their spheres, the spheres
//! themselves, and the seeded random numbers that jitter where they start.

use std::borrow::Cow;

use glam::Vec3;

use super::{ParamTable, SceneInfo};
use crate::physics::{ParticleDesc, Plane, SphereCollisions, World};

/// How a granular scene is shown, the part of its [`SceneInfo`] they share: no presets
/// or actions, no trails (thousands of grains would smear the view), grains coloured
/// by speed (what matters is which still move). Name, summary, step, steps and
/// parameters are blank here: each scene gives its own (`..granular::LOOK`).
pub(super) const LOOK: SceneInfo = SceneInfo {
    name: Cow::Borrowed(""),
    summary: Cow::Borrowed(""),
    dt: 0.0,
    default_steps: 0,
    params: ParamTable::Static(&[]),
    presets: &[],
    actions: &[],
    trails: false,
    color_by_speed: true,
};

/// The surfaces' material: restitution, Coulomb friction and rolling resistance, the
/// same for the walls, the floor and every pair of spheres.
#[derive(Clone, Copy, Debug)]
pub(super) struct Material {
    pub restitution: f32,
    pub friction: f32,
    pub rolling_resistance: f32,
}

/// Adds the box: a floor at height `floor` (m) facing up, and four walls facing in at
/// ±`width`/2 on x and z, in that order (the order is part of the scenes' state
/// hashes).
pub(super) fn add_box(world: &mut World, floor: f32, width: f32, material: Material) {
    let half = width / 2.0;
    let walls = [
        (Vec3::Y, Vec3::new(0.0, floor, 0.0)),
        (Vec3::X, Vec3::new(-half, 0.0, 0.0)),
        (Vec3::NEG_X, Vec3::new(half, 0.0, 0.0)),
        (Vec3::Z, Vec3::new(0.0, 0.0, -half)),
        (Vec3::NEG_Z, Vec3::new(0.0, 0.0, half)),
    ];
    for (normal, point) in walls {
        let plane = Plane::new(normal, point, material.restitution, material.friction)
            .expect("parameter ranges keep planes valid")
            .with_rolling_resistance(material.rolling_resistance);
        world.add_contact_generator(plane).expect("a plane from Plane::new is valid");
    }
}

/// Adds the collisions between every pair of spheres.
pub(super) fn add_sphere_collisions(world: &mut World, material: Material) {
    world
        .add_contact_generator(SphereCollisions {
            rolling_resistance: material.rolling_resistance,
            ..SphereCollisions::new(material.restitution, material.friction)
        })
        .expect("parameter ranges keep restitution and friction valid");
}

/// Adds a sphere of `mass` (kg) and `radius` (m) at each of `positions`, at rest under
/// gravity `g` (m/s², downwards), undamped; solid spheres that roll if `rolls`.
pub(super) fn add_spheres(
    world: &mut World,
    positions: &[Vec3],
    mass: f32,
    radius: f32,
    g: f32,
    rolls: bool,
) {
    for &position in positions {
        let id = world
            .add_particle(ParticleDesc {
                position,
                acceleration: Vec3::new(0.0, -g, 0.0),
                mass,
                radius,
                damping: 1.0,
                ..ParticleDesc::default()
            })
            .expect("parameter ranges keep every sphere valid");
        world.particles.set_rolling(id, rolls).expect("every sphere has a radius");
    }
}

/// A tiny, well-mixed random number generator (Steele, Lea and Flood's SplitMix64):
/// enough to jitter a starting grid, with a fixed seed so every run is the same.
pub(super) struct SplitMix64(pub u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
}

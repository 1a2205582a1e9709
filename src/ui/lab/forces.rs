//! The forces the inspector lists and the arrows draw: each force on a particle now,
//! their sum, which particles get arrows, and the arrows' scale.

use glam::Vec3;

use super::limits::LONGEST_FORCE_ARROW;
use super::model::Lab;
use crate::physics::ParticleId;
use crate::physics::inspect;
use crate::render::frame::VECTOR_PARTICLE_LIMIT;

/// The smallest of 1, 2 or 5 times a power of ten that is at least `x` (at least 0.001),
/// as the float nearest that decimal, so it prints as one ("0.05", not 0.049999997
/// as `5.0 * 10f32.powf(-2.0)` would).
#[must_use]
pub fn round_scale(x: f32) -> f32 {
    let x = if x.is_finite() { x.max(1e-3) } else { 1e-3 };
    let exponent = x.log10().floor() as i32;
    let decimal = |m: u32, e: i32| format!("{m}e{e}").parse::<f32>().unwrap_or(f32::MAX);
    [1, 2, 5, 10]
        .into_iter()
        .map(|m| decimal(m, exponent))
        .find(|&s| s >= x * 0.9999)
        .unwrap_or_else(|| decimal(1, exponent + 1))
}

/// What the inspector shows of a sphere that rolls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spin {
    /// Angular velocity (rad/s).
    pub angular_velocity: Vec3,
    /// Kinetic energy of its rotation, `½ I ω²` with `I = 2/5 m r²` (J).
    pub energy: f32,
    /// Speed of its surface relative to its centre at the equator of the spin, `|ω| r`
    /// (m/s): equal to its speed while it rolls without slipping on still ground.
    pub surface_speed: f32,
}

impl Lab {
    /// The spin of a sphere that rolls; `None` for a point mass or an unknown particle.
    #[must_use]
    pub fn spin(&self, id: ParticleId) -> Option<Spin> {
        let particles = &self.scene.world().particles;
        let i = particles.index(id)?;
        let inverse_inertia = particles.inverse_inertias()[i];
        if inverse_inertia == 0.0 {
            return None;
        }
        let w = particles.angular_velocities()[i];
        Some(Spin {
            angular_velocity: w,
            energy: 0.5 * w.length_squared() / inverse_inertia + 0.0,
            surface_speed: w.length() * particles.radii()[i],
        })
    }

    /// The forces on a particle now, one by one (N): from the current state, its
    /// weight, each force generator's and damping's ([`World::free_body`]); and, for the
    /// selected particle while a contact or link acts on it, what they did over the
    /// last step ([`Self::constraint_force`]), or for one asleep (at rest) what they hold.
    /// Empty for an immovable or unknown particle.
    #[must_use]
    pub fn free_body(&self, id: ParticleId) -> Vec<(&'static str, Vec3)> {
        let world = self.scene.world();
        if self.selected == Some(id) {
            inspect::forces_on(world, id, self.constraint_force)
        } else {
            world.free_body(id)
        }
    }

    /// The net force on a particle (N): the sum of [`Self::free_body`]. Computed from
    /// the state, so it is right the moment a particle is selected, paused or not.
    #[must_use]
    pub fn net_force(&self, id: ParticleId) -> Vec3 {
        self.free_body(id).iter().map(|(_, f)| *f).sum()
    }

    /// The particles that get arrows: the selected one, or with "all vectors" on every
    /// movable particle of a scene of at most [`VECTOR_PARTICLE_LIMIT`].
    #[must_use]
    pub fn vector_particles(&self) -> Vec<ParticleId> {
        let particles = &self.scene.world().particles;
        if self.view.all_vectors && particles.len() <= VECTOR_PARTICLE_LIMIT {
            let movable = particles.ids().iter().zip(particles.inverse_masses());
            movable.filter(|(_, w)| **w > 0.0).map(|(id, _)| *id).collect()
        } else {
            self.selected.into_iter().collect()
        }
    }

    /// The force arrows' scale (N per metre of arrow): from 1, 2, 5 times a power of
    /// ten, the smallest that keeps the largest force on the particles with arrows
    /// within [`LONGEST_FORCE_ARROW`].
    #[must_use]
    pub fn force_scale(&self) -> f32 {
        let largest = self
            .vector_particles()
            .into_iter()
            .flat_map(|id| self.free_body(id))
            .map(|(_, f)| f.length())
            .fold(0.0, f32::max);
        round_scale(largest / LONGEST_FORCE_ARROW)
    }
}

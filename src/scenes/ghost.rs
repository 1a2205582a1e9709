//! Ghosts of the exact answer: where a particle would be if the closed form of its
//! motion held, drawn beside the simulated particle, with the distance between the two.

use glam::{DVec3, Vec3};

use crate::physics::exact::{self, SpringMotion};
use crate::physics::{ParticleId, World};

/// The closed form a ghost follows.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Motion {
    /// Constant acceleration `g` with velocity decay `lambda` (1/s).
    Projectile {
        /// Acceleration (m/s²).
        g: DVec3,
        /// Velocity decay rate (1/s).
        lambda: f64,
    },
    /// A mass on a spring.
    Spring(SpringMotion),
}

/// A particle's exact twin: its closed form, started from the particle's state at
/// `start`. When something outside the closed form moves the particle (the mouse, a
/// changed parameter) the ghost starts again from where the particle is.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ghost {
    /// The particle it shadows.
    pub particle: ParticleId,
    motion: Motion,
    start: f64,
    p0: DVec3,
    v0: DVec3,
    /// The particle's state after the last step, to notice moves from outside.
    last: (Vec3, Vec3),
}

impl Ghost {
    /// A ghost of `particle` from its current state and the world's time.
    #[must_use]
    pub fn new(world: &World, particle: ParticleId, motion: Motion) -> Option<Self> {
        let (p, v) = state(world, particle)?;
        Some(Self { particle, motion, start: world.time(), p0: p.as_dvec3(), v0: v.as_dvec3(), last: (p, v) })
    }

    /// The closed form it follows.
    #[must_use]
    pub fn motion(&self) -> Motion {
        self.motion
    }

    /// Starts again from the particle's current state with another closed form.
    pub fn restart(&mut self, world: &World, motion: Motion) {
        if let Some(fresh) = Self::new(world, self.particle, motion) {
            *self = fresh;
        }
    }

    /// Call before a step: starts again if the particle was moved from outside.
    pub fn before_step(&mut self, world: &World) {
        if state(world, self.particle).is_some_and(|now| now != self.last) {
            self.restart(world, self.motion);
        }
    }

    /// Call after a step: remembers the state the step left.
    pub fn after_step(&mut self, world: &World) {
        if let Some(now) = state(world, self.particle) {
            self.last = now;
        }
    }

    /// Where the closed form puts the particle now (m).
    #[must_use]
    pub fn position(&self, world: &World) -> Vec3 {
        let t = world.time() - self.start;
        let p = match self.motion {
            Motion::Projectile { g, lambda } => exact::projectile(self.p0, self.v0, g, lambda, t).0,
            Motion::Spring(spring) => spring.at(self.p0, self.v0, t).0,
        };
        p.as_vec3()
    }

    /// Distance between the particle and its ghost (m), if the particle is still there.
    #[must_use]
    pub fn error(&self, world: &World) -> Option<f32> {
        state(world, self.particle).map(|(p, _)| p.distance(self.position(world)))
    }
}

fn state(world: &World, id: ParticleId) -> Option<(Vec3, Vec3)> {
    let i = world.particles.index(id)?;
    Some((world.particles.positions()[i], world.particles.velocities()[i]))
}

/// The colour ghosts are drawn in: a pale blue-white, unlike any particle.
pub const GHOST_COLOR: [f32; 3] = [0.78, 0.86, 1.0];

//! Hooke's-law springs and bungees, between two particles or to an anchor.

use glam::Vec3;

use super::generator::ForceGenerator;
use crate::physics::error::{COEFFICIENT, LENGTH, POINT, PhysicsError, check, coefficient, length, point};
use crate::physics::ids::ParticleId;
use crate::physics::links::{LinkEnd, LinkKind, LinkSpec, direction_or_zero, end_position};
use crate::physics::particles::Particles;

/// Hooke's law between a particle and the other end: a spring pushes when compressed
/// and pulls when stretched; a bungee only pulls, and only when stretched.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Spring {
    /// The particle the force acts on.
    pub a: ParticleId,
    /// The other end: a particle (which gets the opposite force) or a fixed anchor.
    pub b: LinkEnd,
    /// Spring constant (N/m).
    pub k: f32,
    /// Length at which the spring exerts no force (m).
    pub rest_length: f32,
    /// A bungee exerts no force when shorter than its rest length.
    pub bungee: bool,
}

impl Spring {
    /// A spring between two particles.
    #[must_use]
    pub fn between(a: ParticleId, b: ParticleId, k: f32, rest_length: f32) -> Self {
        Self { a, b: LinkEnd::Particle(b), k, rest_length, bungee: false }
    }

    /// A spring from a particle to a fixed anchor point.
    #[must_use]
    pub fn anchored(a: ParticleId, anchor: Vec3, k: f32, rest_length: f32) -> Self {
        Self { a, b: LinkEnd::Anchor(anchor), k, rest_length, bungee: false }
    }

    /// The same link, as a bungee.
    #[must_use]
    pub fn as_bungee(mut self) -> Self {
        self.bungee = true;
        self
    }

    /// Force on end `a` (N) given the two end positions; `b` gets the opposite.
    #[inline]
    #[must_use]
    pub fn force(&self, a: Vec3, b: Vec3) -> Vec3 {
        let (direction, length) = direction_or_zero(a - b);
        let extension = length - self.rest_length;
        if self.bungee && extension <= 0.0 {
            return Vec3::ZERO;
        }
        // Coincident ends have no direction; a compressed spring there still stores
        // k L²/2 and still pushes, so it pushes `a` up (+y), as contacts and links do.
        let direction = if direction == Vec3::ZERO { Vec3::Y } else { direction };
        -self.k * extension * direction
    }

    fn extension(&self, particles: &Particles) -> Option<f32> {
        let a = end_position(particles, LinkEnd::Particle(self.a))?;
        let b = end_position(particles, self.b)?;
        let extension = (a - b).length() - self.rest_length;
        Some(if self.bungee { extension.max(0.0) } else { extension })
    }
}

impl ForceGenerator for Spring {
    fn validate(&self) -> Result<(), PhysicsError> {
        let name = if self.bungee { "bungee" } else { "spring" };
        check(coefficient(self.k), &format!("{name} k"), self.k, COEFFICIENT)?;
        check(length(self.rest_length), &format!("{name} rest_length"), self.rest_length, LENGTH)?;
        if let LinkEnd::Anchor(anchor) = self.b {
            check(point(anchor), &format!("{name} anchor"), anchor, POINT)?;
        }
        Ok(())
    }

    fn apply(&mut self, particles: &mut Particles, _dt: f32) {
        let Some(ia) = particles.index(self.a) else { return };
        let Some(b) = end_position(particles, self.b) else { return };
        let force = self.force(particles.position[ia], b);
        particles.force[ia] += force;
        if let LinkEnd::Particle(id) = self.b
            && let Some(ib) = particles.index(id)
        {
            particles.force[ib] -= force;
        }
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.a == id || self.b == LinkEnd::Particle(id)
    }

    fn name(&self) -> &'static str {
        if self.bungee { "bungee" } else { "spring" }
    }

    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        let id = particles.ids()[i];
        let force =
            self.force(end_position(particles, LinkEnd::Particle(self.a))?, end_position(particles, self.b)?);
        if id == self.a { Some(force) } else { (self.b == LinkEnd::Particle(id)).then_some(-force) }
    }

    fn potential_energy(&self, particles: &Particles) -> f32 {
        self.extension(particles).map_or(0.0, |x| 0.5 * self.k * x * x)
    }

    fn link(&self) -> Option<LinkSpec> {
        let kind = if self.bungee { LinkKind::Bungee } else { LinkKind::Spring };
        Some(LinkSpec { kind, a: self.a, b: self.b, rest: self.rest_length })
    }

    fn tension(&self, particles: &Particles) -> f32 {
        self.extension(particles).map_or(0.0, |x| self.k * x)
    }
}

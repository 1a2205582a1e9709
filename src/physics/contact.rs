//! A contact: one or two particles touching, or a link at its limit, as the paper's
//! resolver and the debug view see it.

use glam::Vec3;

use super::particles::Particles;

/// A contact source value meaning "not from a link" (ground, particle collisions).
pub const NO_SOURCE: u32 = u32::MAX;

/// One or two particles touching (or a link reaching its limit).
///
/// `normal` is the unit direction in which `a` must move to separate; `b` moves the
/// opposite way. A positive `penetration` is overlap still to remove (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Dense index of the first particle.
    pub a: usize,
    /// Dense index of the second particle, or `None` against scenery.
    pub b: Option<usize>,
    /// Unit contact normal, pointing the way `a` is pushed.
    pub normal: Vec3,
    /// Overlap along the normal (m); positive needs resolving.
    pub penetration: f32,
    /// Coefficient of restitution in [0, 1].
    pub restitution: f32,
    /// Coulomb friction coefficient, >= 0 (one for static and kinetic friction).
    pub friction: f32,
    /// Index of the contact generator that made it, or [`NO_SOURCE`].
    pub source: u32,
    /// True when the impulse on this contact pulls the ends together (a stretched link):
    /// it then counts as tension, otherwise as compression.
    pub pulls: bool,
    /// Impulse applied along the normal during resolution (N·s), always >= 0.
    pub impulse: f32,
    /// Friction impulse applied across the normal during resolution (N·s): on `a`, and
    /// its opposite on `b`; never longer than `friction * impulse`.
    pub tangent_impulse: Vec3,
    /// Separating velocity the resolver aims for (m/s); set by the resolver.
    pub target: f32,
}

impl Contact {
    /// A contact with no source link and no impulse yet.
    #[must_use]
    pub fn new(a: usize, b: Option<usize>, normal: Vec3, penetration: f32, restitution: f32) -> Self {
        Self {
            a,
            b,
            normal,
            penetration,
            restitution,
            friction: 0.0,
            source: NO_SOURCE,
            pulls: false,
            impulse: 0.0,
            tangent_impulse: Vec3::ZERO,
            target: 0.0,
        }
    }

    /// The same contact with Coulomb friction `friction` (>= 0).
    #[must_use]
    pub fn with_friction(self, friction: f32) -> Self {
        Self { friction, ..self }
    }

    /// Velocity of separation along the normal (m/s); negative means closing.
    #[inline]
    #[must_use]
    pub fn separating_velocity(&self, particles: &Particles) -> f32 {
        let mut relative = particles.velocity[self.a];
        if let Some(b) = self.b {
            relative -= particles.velocity[b];
        }
        relative.dot(self.normal)
    }
}

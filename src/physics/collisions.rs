//! Contact generators: planes (the ground, walls), sphere-sphere collisions found
//! through the broad phase, and the links that act like contacts (rods and cables).
//!
//! A world holds a list of [`ContactGenerator`]s, a closed set of kinds so that every
//! solver can match on them and a snapshot can name them.

use glam::Vec3;

use super::broad_phase::BroadPhase;
use super::contacts::{Contact, ResolverScratch};
use super::links::{Constraint, LinkSpec, direction_or_zero};
use super::particles::{ParticleId, Particles};
use super::{NON_NEGATIVE, PhysicsError, UNIT, check, non_negative};

/// An infinite plane that particles rest on by their radius: the ground, or a wall.
/// Points `p` with `normal · p > offset` are on the free side.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plane {
    /// Unit normal, pointing to the free side.
    pub normal: Vec3,
    /// `normal · p` for any point `p` of the plane (m).
    pub offset: f32,
    /// Coefficient of restitution against the plane, in [0, 1].
    pub restitution: f32,
    /// Coulomb friction coefficient against the plane, >= 0.
    pub friction: f32,
}

impl Plane {
    /// The plane through `point` with the free side towards `normal` (any length > 0).
    pub fn new(normal: Vec3, point: Vec3, restitution: f32, friction: f32) -> Result<Self, PhysicsError> {
        let unit = normal.try_normalize().ok_or_else(|| {
            PhysicsError::InvalidSetting(format!("plane normal must be finite and non-zero, got {normal}"))
        })?;
        if !point.is_finite() {
            return Err(PhysicsError::InvalidSetting(format!("plane point must be finite, got {point}")));
        }
        check_surface(restitution, friction)?;
        Ok(Self { normal: unit, offset: unit.dot(point), restitution, friction })
    }

    /// The horizontal plane `y = height`, free side up.
    #[must_use]
    pub fn ground(height: f32, restitution: f32, friction: f32) -> Self {
        Self { normal: Vec3::Y, offset: height, restitution, friction }
    }

    /// Signed distance of a point from the plane, positive on the free side (m).
    #[inline]
    #[must_use]
    pub fn distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p) - self.offset
    }

    fn generate(&self, particles: &Particles, out: &mut Vec<Contact>) {
        let positions = particles.position.iter().zip(&particles.radius);
        for (i, ((&p, &r), &inverse_mass)) in positions.zip(&particles.inverse_mass).enumerate() {
            let penetration = r - self.distance(p);
            if penetration > 0.0 && inverse_mass > 0.0 {
                out.push(
                    Contact::new(i, None, self.normal, penetration, self.restitution)
                        .with_friction(self.friction),
                );
            }
        }
    }
}

/// Checks a restitution and friction pair.
pub(crate) fn check_surface(restitution: f32, friction: f32) -> Result<(), PhysicsError> {
    check((0.0..=1.0).contains(&restitution), "restitution", restitution, UNIT)?;
    check(non_negative(friction), "friction", friction, NON_NEGATIVE)
}

/// The horizontal plane `y = height` with no friction: the paper's ground.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GroundPlane {
    /// Height of the plane (m).
    pub height: f32,
    /// Coefficient of restitution against the ground.
    pub restitution: f32,
}

/// Collisions between every pair of particles with a radius, found through the
/// broad phase's grid.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SphereCollisions {
    /// Coefficient of restitution between particles, in [0, 1].
    pub restitution: f32,
    /// Coulomb friction coefficient between particles, >= 0.
    pub friction: f32,
}

impl SphereCollisions {
    /// Frictionless collisions with the given restitution (the paper's).
    #[must_use]
    pub fn elastic(restitution: f32) -> Self {
        Self { restitution, friction: 0.0 }
    }

    fn generate(
        &self,
        particles: &Particles,
        broad_phase: &mut BroadPhase,
        scratch: &mut Scratch,
        out: &mut Vec<Contact>,
    ) {
        scratch.reach.clear();
        scratch.reach.extend_from_slice(&particles.radius);
        broad_phase.find_pairs(&particles.position, &scratch.reach, &mut scratch.pairs);
        scratch.pair_budget_hit |= broad_phase.budget_hit();
        for &(a, b) in &scratch.pairs {
            let (a, b) = (a as usize, b as usize);
            if particles.inverse_mass[a] + particles.inverse_mass[b] <= 0.0 {
                continue;
            }
            let reach = particles.radius[a] + particles.radius[b];
            let (normal, distance) = direction_or_zero(particles.position[a] - particles.position[b]);
            // Coincident centres have no direction: separate them vertically.
            let normal = if normal == Vec3::ZERO { Vec3::Y } else { normal };
            out.push(
                Contact::new(a, Some(b), normal, reach - distance, self.restitution)
                    .with_friction(self.friction),
            );
        }
    }
}

/// Buffers the generators reuse between steps.
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    /// Reach of each particle for the broad phase (m).
    pub reach: Vec<f32>,
    /// Pairs from the broad phase.
    pub pairs: Vec<(u32, u32)>,
    /// Set when a search of the broad phase hit its pair budget (spheres piled onto
    /// each other: see [`super::broad_phase::pair_budget`]); the world clears it at
    /// the start of a step and reports it.
    pub pair_budget_hit: bool,
    /// The paper resolver's buffers.
    pub resolver: ResolverScratch,
}

/// Something that looks at the particles each step and makes contacts.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ContactGenerator {
    /// A plane: ground or wall.
    Plane(Plane),
    /// Sphere-sphere collisions between all particles with a radius.
    Spheres(SphereCollisions),
    /// A rod or cable, between particles or to an anchor.
    Link(Constraint),
}

impl ContactGenerator {
    /// Checks every setting; the error names the field and its valid range. The world
    /// calls it before accepting the generator.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        match self {
            Self::Plane(plane) => {
                let unit = plane.normal.is_finite() && (plane.normal.length() - 1.0).abs() < 1e-4;
                check(unit, "plane normal", plane.normal, "a unit vector")?;
                check(plane.offset.is_finite(), "plane offset", plane.offset, "a finite distance (m)")?;
                check_surface(plane.restitution, plane.friction)
            }
            Self::Spheres(spheres) => check_surface(spheres.restitution, spheres.friction),
            Self::Link(link) => link.validate(),
        }
    }

    /// Appends the paper resolver's contacts (overlaps only). `source` is this
    /// generator's index in the world, stored in contacts that belong to a link.
    pub fn generate(
        &self,
        particles: &Particles,
        source: u32,
        broad_phase: &mut BroadPhase,
        scratch: &mut Scratch,
        out: &mut Vec<Contact>,
    ) {
        match self {
            Self::Plane(plane) => plane.generate(particles, out),
            Self::Spheres(spheres) => spheres.generate(particles, broad_phase, scratch, out),
            Self::Link(link) => link.generate(particles, source, out),
        }
    }

    /// Whether this generator refers to the particle (and must go with it).
    #[must_use]
    pub fn involves(&self, id: ParticleId) -> bool {
        match self {
            Self::Link(link) => link.involves(id),
            Self::Plane(_) | Self::Spheres(_) => false,
        }
    }

    /// The generator seen as a link, if it is one.
    #[must_use]
    pub fn link(&self) -> Option<LinkSpec> {
        match self {
            Self::Link(link) => Some(link.spec()),
            Self::Plane(_) | Self::Spheres(_) => None,
        }
    }
}

impl From<Plane> for ContactGenerator {
    fn from(plane: Plane) -> Self {
        Self::Plane(plane)
    }
}

impl From<GroundPlane> for ContactGenerator {
    fn from(ground: GroundPlane) -> Self {
        Self::Plane(Plane::ground(ground.height, ground.restitution, 0.0))
    }
}

impl From<SphereCollisions> for ContactGenerator {
    fn from(spheres: SphereCollisions) -> Self {
        Self::Spheres(spheres)
    }
}

impl From<Constraint> for ContactGenerator {
    fn from(link: Constraint) -> Self {
        Self::Link(link)
    }
}

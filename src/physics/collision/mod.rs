//! Collision detection: what makes contacts each step.
//!
//! A world holds a list of [`ContactGenerator`]s, a closed set of kinds so that every
//! solver can match on them and a snapshot can name them:
//! - [`broad_phase`]: the grid that finds candidate sphere pairs;
//! - [`narrow_phase`]: planes and sphere pairs as contacts;
//! - [`constraints`]: rods and cables as contacts (the paper's resolver).
//!
//! Imports the ground floor, particles, links and contacts; nothing above.

pub mod broad_phase;
pub mod constraints;
pub mod narrow_phase;

pub use broad_phase::{BroadPhase, Scratch};
pub use narrow_phase::{DEFAULT_ROLLING_RESISTANCE, Extent, GroundPlane, Plane, Plate, SphereCollisions};

use crate::physics::contact::Contact;
use crate::physics::error::{PhysicsError, check};
use crate::physics::ids::ParticleId;
use crate::physics::links::{Constraint, LinkSpec};
use crate::physics::particles::Particles;
use narrow_phase::check_surface;

/// Something that looks at the particles each step and makes contacts.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ContactGenerator {
    /// A plane: ground or wall.
    Plane(Plane),
    /// A thin plate with a round opening: a silo's or an hourglass's floor.
    Plate(Plate),
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
                if let Some(e) = &plane.extent {
                    let unit = e.along.is_finite() && (e.along.length() - 1.0).abs() < 1e-4;
                    check(
                        unit && e.along.dot(plane.normal).abs() < 1e-3,
                        "wall direction",
                        e.along,
                        "a unit vector in the plane",
                    )?;
                    check(e.center.is_finite(), "wall centre", e.center, "a finite point (m)")?;
                    let size = glam::Vec3::new(e.half_along, e.half_across, 0.0);
                    check(
                        size.is_finite() && e.half_along > 0.0 && e.half_across > 0.0,
                        "wall half sizes",
                        size,
                        "lengths > 0 (m)",
                    )?;
                }
                check_surface(plane.restitution, plane.friction, plane.rolling_resistance)
            }
            Self::Plate(plate) => plate.validate(),
            Self::Spheres(spheres) => {
                check_surface(spheres.restitution, spheres.friction, spheres.rolling_resistance)
            }
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
            Self::Plate(plate) => plate.generate(particles, out),
            Self::Spheres(spheres) => spheres.generate(particles, broad_phase, scratch, out),
            Self::Link(link) => link.generate(particles, source, out),
        }
    }

    /// Whether this generator refers to the particle (and must go with it).
    #[must_use]
    pub fn involves(&self, id: ParticleId) -> bool {
        match self {
            Self::Link(link) => link.involves(id),
            Self::Plane(_) | Self::Plate(_) | Self::Spheres(_) => false,
        }
    }

    /// The generator seen as a link, if it is one.
    #[must_use]
    pub fn link(&self) -> Option<LinkSpec> {
        match self {
            Self::Link(link) => Some(link.spec()),
            Self::Plane(_) | Self::Plate(_) | Self::Spheres(_) => None,
        }
    }
}

impl From<Plane> for ContactGenerator {
    fn from(plane: Plane) -> Self {
        Self::Plane(plane)
    }
}

impl From<Plate> for ContactGenerator {
    fn from(plate: Plate) -> Self {
        Self::Plate(plate)
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

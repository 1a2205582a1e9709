//! Links between two points: what they are (kinds, ends, specs, states), and rods and
//! cables, which are constraints rather than forces.
//!
//! With the paper's resolver a rod or cable checks its length each step and, when it is
//! off, emits a contact that the resolver treats like a collision (see
//! `collision/constraints.rs`). The soft solver reads the same [`Constraint`] and solves
//! it on the exact geometry every substep.

use glam::Vec3;

use super::error::{POINT, PhysicsError, UNIT, check, point, positive};
use super::ids::ParticleId;
use super::particles::Particles;

/// Unit vector of `d` and its length, or zero and the length when `d` is (nearly) zero:
/// coincident ends exert no directed force instead of producing NaN.
#[inline]
#[must_use]
pub fn direction_or_zero(d: Vec3) -> (Vec3, f32) {
    let length = d.length();
    if length > 1e-12 && length.is_finite() {
        (d / length, length)
    } else {
        (Vec3::ZERO, length.min(f32::MAX))
    }
}

/// Position of a link end: a particle's position or a fixed anchor.
#[inline]
pub(crate) fn end_position(particles: &Particles, end: LinkEnd) -> Option<Vec3> {
    match end {
        LinkEnd::Particle(id) => particles.index(id).map(|i| particles.position[i]),
        LinkEnd::Anchor(p) => Some(p),
    }
}

/// What a link between two points is, for output and drawing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum LinkKind {
    /// Keeps two particles at a fixed distance.
    Rod,
    /// Keeps two particles at most a distance apart.
    Cable,
    /// Hooke's law, pushes and pulls.
    Spring,
    /// Hooke's law when stretched, slack otherwise.
    Bungee,
    /// Closed-form damped spring to an anchor.
    StiffSpring,
    /// A rod to a fixed anchor.
    SupportRod,
    /// A cable to a fixed anchor.
    SupportCable,
}

impl LinkKind {
    /// The name used in the command line's JSON output.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Rod => "rod",
            Self::Cable => "cable",
            Self::Spring => "spring",
            Self::Bungee => "bungee",
            Self::StiffSpring => "stiff_spring",
            Self::SupportRod => "support_rod",
            Self::SupportCable => "support_cable",
        }
    }
}

/// The second end of a link: another particle or a fixed point in space.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum LinkEnd {
    /// A particle.
    Particle(ParticleId),
    /// A fixed anchor (m).
    Anchor(Vec3),
}

/// A link as declared: its kind, ends and rest length (max length for a cable).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkSpec {
    /// What sort of link.
    pub kind: LinkKind,
    /// First end.
    pub a: ParticleId,
    /// Second end.
    pub b: LinkEnd,
    /// Rest length, or maximum length for a cable (m).
    pub rest: f32,
}

/// A link in the current state, with both end positions resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkState {
    /// The declaration.
    pub spec: LinkSpec,
    /// Position of end `a` (m).
    pub from: Vec3,
    /// Position of end `b` (m).
    pub to: Vec3,
    /// Current distance between the ends (m).
    pub length: f32,
    /// Tension (N): positive pulls the ends together, negative pushes them apart. For
    /// rods and cables it is the impulse the resolver applied last step over the step.
    pub tension: f32,
}

/// A rod (fixed length) or cable (maximum length) from a particle to another particle
/// or to a fixed anchor.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Constraint {
    /// First end.
    pub a: ParticleId,
    /// Second end.
    pub b: LinkEnd,
    /// Rod length, or cable maximum length (m).
    pub length: f32,
    /// True for a rod, false for a cable.
    pub rigid: bool,
    /// Restitution when a cable snaps taut (rods use 0).
    pub restitution: f32,
}

impl Constraint {
    /// A rod of the given length between two particles.
    #[must_use]
    pub fn rod(a: ParticleId, b: ParticleId, length: f32) -> Self {
        Self { a, b: LinkEnd::Particle(b), length, rigid: true, restitution: 0.0 }
    }

    /// A cable of the given maximum length between two particles.
    #[must_use]
    pub fn cable(a: ParticleId, b: ParticleId, max_length: f32, restitution: f32) -> Self {
        Self { a, b: LinkEnd::Particle(b), length: max_length, rigid: false, restitution }
    }

    /// A rod from a particle to a fixed anchor.
    #[must_use]
    pub fn support_rod(a: ParticleId, anchor: Vec3, length: f32) -> Self {
        Self { a, b: LinkEnd::Anchor(anchor), length, rigid: true, restitution: 0.0 }
    }

    /// A cable from a particle to a fixed anchor.
    #[must_use]
    pub fn support_cable(a: ParticleId, anchor: Vec3, max_length: f32, restitution: f32) -> Self {
        Self { a, b: LinkEnd::Anchor(anchor), length: max_length, rigid: false, restitution }
    }
}

impl Constraint {
    /// Checks the link's settings; the error names the field and its valid range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let name = if self.rigid { "rod" } else { "cable" };
        let length = positive(self.length) && self.length <= crate::physics::error::MAX_COORDINATE;
        check(length, &format!("{name} length"), self.length, "more than 0, at most 1e9 m")?;
        check(
            (0.0..=1.0).contains(&self.restitution),
            &format!("{name} restitution"),
            self.restitution,
            UNIT,
        )?;
        if let LinkEnd::Anchor(anchor) = self.b {
            check(point(anchor), &format!("{name} anchor"), anchor, POINT)?;
        }
        Ok(())
    }

    /// Whether this link refers to the particle.
    #[must_use]
    pub fn involves(&self, id: ParticleId) -> bool {
        self.a == id || self.b == LinkEnd::Particle(id)
    }

    /// The link's declaration.
    #[must_use]
    pub fn spec(&self) -> LinkSpec {
        let kind = match (self.rigid, self.b) {
            (true, LinkEnd::Particle(_)) => LinkKind::Rod,
            (false, LinkEnd::Particle(_)) => LinkKind::Cable,
            (true, LinkEnd::Anchor(_)) => LinkKind::SupportRod,
            (false, LinkEnd::Anchor(_)) => LinkKind::SupportCable,
        };
        LinkSpec { kind, a: self.a, b: self.b, rest: self.length }
    }
}

/// Resolves a link's end positions and length.
pub(crate) fn link_geometry(particles: &Particles, spec: &LinkSpec) -> Option<(Vec3, Vec3, f32)> {
    let from = end_position(particles, LinkEnd::Particle(spec.a))?;
    let to = end_position(particles, spec.b)?;
    Some((from, to, from.distance(to)))
}

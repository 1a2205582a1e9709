//! Contact generators: the ground, particle-particle collisions, rods and cables.
//!
//! Rods and cables are not forces: each step they check their length and, when it is
//! off, emit a contact that the resolver treats like a collision.

use glam::Vec3;

use super::contacts::Contact;
use super::forces::{direction_or_zero, end_position};
use super::particles::{ParticleId, Particles};

/// What a link between two points is, for output and drawing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
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
#[derive(Clone, Copy, Debug, PartialEq)]
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

/// Something that looks at the particles each step and emits contacts.
pub trait ContactGenerator {
    /// Appends this step's contacts. `source` is this generator's index in the world,
    /// to be stored in contacts that belong to a link.
    fn generate(&self, particles: &Particles, source: u32, out: &mut Vec<Contact>);

    /// Whether this generator refers to the particle.
    fn involves(&self, _id: ParticleId) -> bool {
        false
    }

    /// The generator seen as a link, if it is one.
    fn link(&self) -> Option<LinkSpec> {
        None
    }
}

/// The horizontal plane `y = height`: every movable particle rests on it by its radius.
#[derive(Clone, Debug)]
pub struct GroundPlane {
    /// Height of the plane (m).
    pub height: f32,
    /// Coefficient of restitution against the ground.
    pub restitution: f32,
}

impl ContactGenerator for GroundPlane {
    fn generate(&self, particles: &Particles, _source: u32, out: &mut Vec<Contact>) {
        let positions = particles.position.iter().zip(&particles.radius);
        for (i, ((p, &r), &inverse_mass)) in positions.zip(&particles.inverse_mass).enumerate() {
            let penetration = self.height + r - p.y;
            if penetration > 0.0 && inverse_mass > 0.0 {
                out.push(Contact::new(i, None, Vec3::Y, penetration, self.restitution));
            }
        }
    }
}

/// Sphere-sphere collisions between every pair of particles with a radius (all pairs:
/// fine for the scenes' few dozen particles).
#[derive(Clone, Debug)]
pub struct SphereCollisions {
    /// Coefficient of restitution between particles.
    pub restitution: f32,
}

impl ContactGenerator for SphereCollisions {
    fn generate(&self, particles: &Particles, _source: u32, out: &mut Vec<Contact>) {
        let n = particles.len();
        for a in 0..n {
            let (pa, ra) = (particles.position[a], particles.radius[a]);
            if ra <= 0.0 {
                continue;
            }
            for b in a + 1..n {
                let reach = ra + particles.radius[b];
                let d = pa - particles.position[b];
                if particles.radius[b] <= 0.0 || d.length_squared() >= reach * reach {
                    continue;
                }
                if particles.inverse_mass[a] + particles.inverse_mass[b] <= 0.0 {
                    continue;
                }
                let (normal, distance) = direction_or_zero(d);
                // Coincident centres have no direction: separate them vertically.
                let normal = if normal == Vec3::ZERO { Vec3::Y } else { normal };
                out.push(Contact::new(a, Some(b), normal, reach - distance, self.restitution));
            }
        }
    }
}

/// A rod (fixed length) or cable (maximum length) from a particle to another particle
/// or to a fixed anchor.
#[derive(Clone, Debug)]
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

impl ContactGenerator for Constraint {
    fn generate(&self, particles: &Particles, source: u32, out: &mut Vec<Contact>) {
        let Some(a) = particles.index(self.a) else { return };
        let (b, other) = match self.b {
            LinkEnd::Particle(id) => match particles.index(id) {
                Some(i) => (Some(i), particles.position[i]),
                None => return,
            },
            LinkEnd::Anchor(p) => (None, p),
        };
        if b == Some(a) {
            return; // a link from a particle to itself constrains nothing
        }
        let (towards_b, current) = direction_or_zero(other - particles.position[a]);
        let error = current - self.length;
        let too_long = error > 0.0;
        let too_short = self.rigid && error < 0.0;
        if !(too_long || too_short) {
            return;
        }
        // Coincident ends give no direction; any fixed axis will do to push them apart.
        let towards_b = if towards_b == Vec3::ZERO { Vec3::NEG_Y } else { towards_b };
        let (normal, restitution) = if too_long { (towards_b, self.restitution) } else { (-towards_b, 0.0) };
        out.push(Contact { source, pulls: too_long, ..Contact::new(a, b, normal, error.abs(), restitution) });
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.a == id || self.b == LinkEnd::Particle(id)
    }

    fn link(&self) -> Option<LinkSpec> {
        let kind = match (self.rigid, self.b) {
            (true, LinkEnd::Particle(_)) => LinkKind::Rod,
            (false, LinkEnd::Particle(_)) => LinkKind::Cable,
            (true, LinkEnd::Anchor(_)) => LinkKind::SupportRod,
            (false, LinkEnd::Anchor(_)) => LinkKind::SupportCable,
        };
        Some(LinkSpec { kind, a: self.a, b: self.b, rest: self.length })
    }
}

/// Resolves a link's end positions and length.
pub(crate) fn link_geometry(particles: &Particles, spec: &LinkSpec) -> Option<(Vec3, Vec3, f32)> {
    let from = end_position(particles, LinkEnd::Particle(spec.a))?;
    let to = end_position(particles, spec.b)?;
    Some((from, to, from.distance(to)))
}

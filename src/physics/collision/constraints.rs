//! Rods and cables as the paper's resolver sees them: a link that is off its length
//! emits a contact, which the resolver treats like a collision.

use glam::Vec3;

use crate::physics::contact::Contact;
use crate::physics::links::{Constraint, LinkEnd, direction_or_zero};
use crate::physics::particles::Particles;

impl Constraint {
    /// Emits the paper resolver's contact when the link is too long (or, for a rod, too
    /// short). `source` is this link's generator index, kept for its tension.
    pub fn generate(&self, particles: &Particles, source: u32, out: &mut Vec<Contact>) {
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
}

//! Contacts and the paper's iterative impulse resolver.
//!
//! This is the resolver the paper describes, kept as the `paper` solver so the lab can
//! show why the soft step exists. It handles one contact at a time, always the worst:
//! each pass scans every contact, so a step costs iterations x contacts and a large
//! pile stops at the iteration cap before it converges (it never comes to rest). Its
//! known behaviour: restitution is applied against the step-end closing speed (an
//! `e = 1` bounce loses a little height each time), rods and cables are corrected by
//! moving positions, which takes energy out of a swinging chain, and nothing stops a
//! fast particle passing through another within a step.

use glam::Vec3;

use super::particles::Particles;
use super::{NON_NEGATIVE, PhysicsError, check, non_negative};

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
    /// Index of the contact generator that made it, or [`NO_SOURCE`].
    pub source: u32,
    /// True when the impulse on this contact pulls the ends together (a stretched link):
    /// it then counts as tension, otherwise as compression.
    pub pulls: bool,
    /// Impulse applied along the normal during resolution (N·s), always >= 0.
    pub impulse: f32,
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
            source: NO_SOURCE,
            pulls: false,
            impulse: 0.0,
            target: 0.0,
        }
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

    fn total_inverse_mass(&self, particles: &Particles) -> f32 {
        particles.inverse_mass[self.a] + self.b.map_or(0.0, |b| particles.inverse_mass[b])
    }

    /// The separating velocity this contact should end the step with: `-e` times the
    /// closing velocity, not counting the part this step's acceleration built up (so a
    /// particle resting on something does not bounce). Slow contacts do not bounce.
    fn target_velocity(&self, particles: &Particles, dt: f32, restitution_threshold: f32) -> f32 {
        let separating = self.separating_velocity(particles);
        if separating >= 0.0 {
            return 0.0;
        }
        let restitution = if -separating < restitution_threshold { 0.0 } else { self.restitution };
        let mut built_up = particles.step_acceleration(self.a);
        if let Some(b) = self.b {
            built_up -= particles.step_acceleration(b);
        }
        let built_up_velocity = built_up.dot(self.normal) * dt;
        let closing = if built_up_velocity < 0.0 { separating - built_up_velocity } else { separating };
        (-closing * restitution).max(0.0)
    }

    /// How far this contact is from its target: positive when it still needs a push,
    /// negative when an earlier push overshot and may be partly taken back (m/s).
    fn velocity_error(&self, particles: &Particles) -> f32 {
        let error = self.target - self.separating_velocity(particles);
        if error < 0.0 { error.max(-self.impulse * self.total_inverse_mass(particles)) } else { error }
    }

    /// Applies the impulse that brings the separating velocity to the target, keeping
    /// the total impulse of this contact a push (never a pull).
    fn resolve_velocity(&mut self, particles: &mut Particles) {
        let total_inverse_mass = self.total_inverse_mass(particles);
        if total_inverse_mass <= 0.0 {
            return;
        }
        let wanted = (self.target - self.separating_velocity(particles)) / total_inverse_mass;
        let impulse = wanted.max(-self.impulse);
        self.impulse += impulse;
        let impulse_vector = self.normal * impulse;
        particles.velocity[self.a] += impulse_vector * particles.inverse_mass[self.a];
        if let Some(b) = self.b {
            particles.velocity[b] -= impulse_vector * particles.inverse_mass[b];
        }
    }

    /// Moves the particles apart along the normal in proportion to inverse mass.
    /// Returns how far `a` and `b` moved.
    fn resolve_penetration(&mut self, particles: &mut Particles, slop: f32) -> (Vec3, Vec3) {
        let total_inverse_mass = self.total_inverse_mass(particles);
        let depth = self.penetration - slop;
        if depth <= 0.0 || total_inverse_mass <= 0.0 {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        let per_inverse_mass = self.normal * (depth / total_inverse_mass);
        let move_a = per_inverse_mass * particles.inverse_mass[self.a];
        particles.position[self.a] += move_a;
        let move_b = match self.b {
            Some(b) => {
                let m = -per_inverse_mass * particles.inverse_mass[b];
                particles.position[b] += m;
                m
            }
            None => Vec3::ZERO,
        };
        (move_a, move_b)
    }
}

/// What one call of [`ContactResolver::resolve`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ResolveReport {
    /// Contacts handled in the velocity phase.
    pub velocity_iterations: usize,
    /// Contacts handled in the interpenetration phase.
    pub position_iterations: usize,
    /// Largest penetration left after resolution (m); 0 if none.
    pub max_penetration: f32,
    /// Contacts handled (with the soft solver, speculative ones included).
    pub contacts: usize,
    /// Particles asleep after the step (soft solver).
    pub asleep: usize,
    /// True when spheres overlapped so much that the broad phase made only its budget
    /// of pairs ([`super::broad_phase::pair_budget`]: 32 per sphere) and left the rest
    /// out: the step went on with those contacts alone, and the UI or command line
    /// should say so.
    pub pair_budget_hit: bool,
}

impl ResolveReport {
    /// Total iterations used, both phases.
    #[must_use]
    pub fn iterations(&self) -> usize {
        self.velocity_iterations + self.position_iterations
    }
}

/// Most iterations [`ContactResolver::max_iterations`] accepts.
pub const MAX_RESOLVER_ITERATIONS: usize = 1_000_000;

/// Resolves contacts one at a time, the most urgent first: the largest closing velocity
/// in the velocity phase, then the deepest penetration in the position phase.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactResolver {
    /// Most contacts handled per phase per step.
    pub max_iterations: usize,
    /// Closing speed below which a contact counts as resolved (m/s).
    pub velocity_epsilon: f32,
    /// Penetration left in place (m). A contact resting this deep stays a contact
    /// every step instead of flickering between touching and apart, which is what
    /// makes resting stacks and taut cables jitter.
    pub slop: f32,
    /// Closing speeds below this bounce with no restitution (m/s): slow contacts are
    /// resting ones, and bouncing them only feeds jitter.
    pub restitution_threshold: f32,
}

impl Default for ContactResolver {
    fn default() -> Self {
        Self { max_iterations: 1024, velocity_epsilon: 1e-4, slop: 5e-4, restitution_threshold: 0.0 }
    }
}

impl ContactResolver {
    /// Checks every setting; the error names the field and its valid range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let iterations = self.max_iterations;
        // Bounded: each iteration scans every contact, and a step must end.
        let ok = (1..=MAX_RESOLVER_ITERATIONS).contains(&iterations);
        check(ok, "resolver max_iterations", iterations, "a whole number from 1 to 1000000")?;
        check(
            non_negative(self.velocity_epsilon),
            "resolver velocity_epsilon",
            self.velocity_epsilon,
            NON_NEGATIVE,
        )?;
        check(non_negative(self.slop), "resolver slop", self.slop, NON_NEGATIVE)?;
        let threshold = self.restitution_threshold;
        check(non_negative(threshold), "resolver restitution_threshold", threshold, NON_NEGATIVE)
    }
    /// Resolves `contacts` in place over a step of `dt` seconds: velocities, then
    /// interpenetration.
    pub fn resolve(&self, contacts: &mut [Contact], particles: &mut Particles, dt: f32) -> ResolveReport {
        let mut report = ResolveReport {
            velocity_iterations: self.resolve_velocities(contacts, particles, dt),
            ..ResolveReport::default()
        };
        let (iterations, max_penetration) = self.resolve_positions(contacts, particles);
        report.position_iterations = iterations;
        report.max_penetration = max_penetration;
        report
    }

    /// The velocity phase: repeatedly handles the contact furthest from its target
    /// separating velocity (at first, the one closing fastest). Impulses accumulate per
    /// contact and may be partly taken back when a later one overshoots, but a contact
    /// never pulls; that is what lets chains of links come to rest instead of jittering.
    /// Returns the number of contacts handled.
    pub fn resolve_velocities(&self, contacts: &mut [Contact], particles: &mut Particles, dt: f32) -> usize {
        for contact in contacts.iter_mut() {
            contact.target = contact.target_velocity(particles, dt, self.restitution_threshold);
            contact.impulse = 0.0;
        }
        let mut iterations = 0;
        while iterations < self.max_iterations {
            let mut worst = None;
            let mut largest = self.velocity_epsilon;
            for (i, contact) in contacts.iter().enumerate() {
                let error = contact.velocity_error(particles).abs();
                if error > largest && contact.total_inverse_mass(particles) > 0.0 {
                    largest = error;
                    worst = Some(i);
                }
            }
            let Some(i) = worst else { break };
            contacts[i].resolve_velocity(particles);
            iterations += 1;
        }
        iterations
    }

    /// The position phase: repeatedly removes the deepest penetration, updating the
    /// (linearised) penetration of every contact that shares a moved particle. Returns
    /// the contacts handled and the largest penetration left (m).
    pub fn resolve_positions(&self, contacts: &mut [Contact], particles: &mut Particles) -> (usize, f32) {
        let mut iterations = 0;
        while iterations < self.max_iterations {
            let mut worst = None;
            // A little past the slop, so round-off does not keep picking the same one.
            let mut deepest = self.slop * 1.01 + 1e-7;
            for (i, contact) in contacts.iter().enumerate() {
                if contact.penetration > deepest && contact.total_inverse_mass(particles) > 0.0 {
                    deepest = contact.penetration;
                    worst = Some(i);
                }
            }
            let Some(i) = worst else { break };
            let (a, b) = (contacts[i].a, contacts[i].b);
            let (move_a, move_b) = contacts[i].resolve_penetration(particles, self.slop);
            // Every contact sharing a moved particle now overlaps by a different amount.
            for contact in contacts.iter_mut() {
                for (moved, shift) in [(Some(a), move_a), (b, move_b)] {
                    if moved == Some(contact.a) {
                        contact.penetration -= shift.dot(contact.normal);
                    }
                    if moved.is_some() && moved == contact.b {
                        contact.penetration += shift.dot(contact.normal);
                    }
                }
            }
            iterations += 1;
        }
        let max_penetration = contacts
            .iter()
            .filter(|c| c.total_inverse_mass(particles) > 0.0)
            .map(|c| c.penetration)
            .fold(0.0, f32::max);
        (iterations, max_penetration)
    }
}

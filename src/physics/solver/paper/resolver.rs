//! The paper's iterative impulse resolver: how it works on [`Contact`]s.
//!
//! This is the resolver the paper describes, kept as the `paper` solver so the lab can
//! show why the soft step exists. It handles one contact at a time, always the worst,
//! and a large pile stops at the iteration cap before it converges (it never comes to
//! rest). Cyclone finds the worst by scanning every contact each iteration, which made
//! a step cost iterations x contacts (half a second for a chain of 200,000 rods, 14 s
//! for 10,000 spheres at one point); here a tournament tree over the contacts finds it
//! and only the contacts that share a particle with the one just handled are looked
//! at again, so a step costs contacts + iterations x (its neighbours' contacts) x log
//! contacts. The choices are the scan's (the largest, the first of equals), so the
//! results are the same bits. Its
//! known behaviour: restitution is applied against the step-end closing speed (an
//! `e = 1` bounce loses a little height each time), rods and cables are corrected by
//! moving positions, which takes energy out of a swinging chain, and nothing stops a
//! fast particle passing through another within a step. Contacts with friction get
//! Coulomb friction each time they are handled (see `Contact::friction_impulse`).

use glam::Vec3;

use crate::physics::contact::Contact;
use crate::physics::error::{NON_NEGATIVE, PhysicsError, check, non_negative};
use crate::physics::particles::Particles;
use crate::physics::solver::report::ResolveReport;

impl Contact {
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
        let mut impulse_vector = self.normal * impulse;
        if self.friction > 0.0 {
            impulse_vector += self.friction_impulse(particles, impulse_vector, total_inverse_mass);
        }
        particles.velocity[self.a] += impulse_vector * particles.inverse_mass[self.a];
        if let Some(b) = self.b {
            particles.velocity[b] -= impulse_vector * particles.inverse_mass[b];
        }
    }

    /// Coulomb friction after a normal impulse `normal_impulse` (not yet applied): the
    /// change of this contact's friction impulse that stops its sliding, with the total
    /// kept within `friction` times the normal impulse the contact has applied this
    /// step. A contact that can be stopped within it sticks (static friction); one that
    /// cannot is slowed by the whole of it (kinetic). A resting contact's normal impulse
    /// includes the part that cancels the velocity gravity built up over the step, so
    /// its friction can hold the same part of gravity along a slope.
    fn friction_impulse(
        &mut self,
        particles: &Particles,
        normal_impulse: Vec3,
        total_inverse_mass: f32,
    ) -> Vec3 {
        let mut relative = particles.velocity[self.a] + normal_impulse * particles.inverse_mass[self.a];
        if let Some(b) = self.b {
            relative -= particles.velocity[b] - normal_impulse * particles.inverse_mass[b];
        }
        let sliding = relative - self.normal * relative.dot(self.normal);
        let old = self.tangent_impulse;
        let mut total = old - sliding / total_inverse_mass;
        let limit = self.friction * self.impulse;
        let squared = total.length_squared();
        if squared > limit * limit {
            total *= limit / squared.sqrt();
        }
        self.tangent_impulse = total;
        total - old
    }

    /// Corrects the (linearised) penetration after particle `a` moved by `move_a` and
    /// particle `b` by `move_b`; does nothing to a contact that involves neither.
    fn shift_penetration(&mut self, a: usize, b: Option<usize>, move_a: Vec3, move_b: Vec3) {
        for (moved, shift) in [(Some(a), move_a), (b, move_b)] {
            if moved == Some(self.a) {
                self.penetration -= shift.dot(self.normal);
            }
            if moved.is_some() && moved == self.b {
                self.penetration += shift.dot(self.normal);
            }
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
    /// interpenetration. `scratch` holds buffers reused from step to step.
    pub fn resolve(
        &self,
        contacts: &mut [Contact],
        particles: &mut Particles,
        dt: f32,
        scratch: &mut ResolverScratch,
    ) -> ResolveReport {
        let mut report = ResolveReport {
            velocity_iterations: self.resolve_velocities(contacts, particles, dt, scratch),
            ..ResolveReport::default()
        };
        let (iterations, max_penetration) = self.resolve_positions(contacts, particles, scratch);
        report.position_iterations = iterations;
        report.max_penetration = max_penetration;
        report
    }

    /// The velocity phase: repeatedly handles the contact furthest from its target
    /// separating velocity (at first, the one closing fastest). Impulses accumulate per
    /// contact and may be partly taken back when a later one overshoots, but a contact
    /// never pulls; that is what lets chains of links come to rest instead of jittering.
    /// Returns the number of contacts handled.
    pub fn resolve_velocities(
        &self,
        contacts: &mut [Contact],
        particles: &mut Particles,
        dt: f32,
        scratch: &mut ResolverScratch,
    ) -> usize {
        for contact in contacts.iter_mut() {
            contact.target = contact.target_velocity(particles, dt, self.restitution_threshold);
            contact.impulse = 0.0;
            contact.tangent_impulse = Vec3::ZERO;
        }
        // The worst is the largest error above epsilon, the first of equals.
        let epsilon = self.velocity_epsilon;
        let urgency = |contact: &Contact, particles: &Particles| {
            let error = contact.velocity_error(particles).abs();
            if error > epsilon && contact.total_inverse_mass(particles) > 0.0 { error } else { IDLE }
        };
        scratch.prepare(contacts, particles, urgency);
        let ResolverScratch { lists, worst, changed } = scratch;
        let mut iterations = 0;
        while iterations < self.max_iterations {
            let Some(i) = worst.best() else { break };
            contacts[i].resolve_velocity(particles);
            iterations += 1;
            // Only the contacts sharing a particle with it have a new error.
            let (a, b) = (contacts[i].a, contacts[i].b);
            lists.sharing(a, b, changed);
            for &k in changed.iter() {
                worst.keys[k as usize] = urgency(&contacts[k as usize], particles);
            }
            worst.refresh(changed);
        }
        Self::move_with_friction(contacts, particles, dt, lists, changed);
        iterations
    }

    /// Moves each particle a friction impulse acted on by the change of velocity it
    /// made, times `dt`, as if friction had acted inside the step: the integration
    /// already moved it with the velocity before friction. Without this a sphere held
    /// on a slope creeps down by `g sinθ dt²` every step, and a sliding one goes a step's
    /// worth of friction too far each step. The penetrations of the contacts that share
    /// a moved particle are corrected (linearised), as the position phase does.
    fn move_with_friction(
        contacts: &mut [Contact],
        particles: &mut Particles,
        dt: f32,
        lists: &ContactLists,
        changed: &mut Vec<u32>,
    ) {
        for i in 0..contacts.len() {
            let Contact { a, b, tangent_impulse, .. } = contacts[i];
            if tangent_impulse == Vec3::ZERO {
                continue;
            }
            let move_a = tangent_impulse * (particles.inverse_mass[a] * dt);
            particles.position[a] += move_a;
            let move_b = match b {
                Some(b) => {
                    let m = -tangent_impulse * (particles.inverse_mass[b] * dt);
                    particles.position[b] += m;
                    m
                }
                None => Vec3::ZERO,
            };
            lists.sharing(a, b, changed);
            for &k in changed.iter() {
                contacts[k as usize].shift_penetration(a, b, move_a, move_b);
            }
        }
        changed.clear();
    }

    /// The position phase: repeatedly removes the deepest penetration, updating the
    /// (linearised) penetration of every contact that shares a moved particle. Returns
    /// the contacts handled and the largest penetration left (m).
    pub fn resolve_positions(
        &self,
        contacts: &mut [Contact],
        particles: &mut Particles,
        scratch: &mut ResolverScratch,
    ) -> (usize, f32) {
        // The worst is the deepest a little past the slop (so round-off does not keep
        // picking the same one), the first of equals.
        let deepest = self.slop * 1.01 + 1e-7;
        let urgency = |contact: &Contact, particles: &Particles| {
            let depth = contact.penetration;
            if depth > deepest && contact.total_inverse_mass(particles) > 0.0 { depth } else { IDLE }
        };
        scratch.prepare(contacts, particles, urgency);
        let ResolverScratch { lists, worst, changed } = scratch;
        let mut iterations = 0;
        while iterations < self.max_iterations {
            let Some(i) = worst.best() else { break };
            let (a, b) = (contacts[i].a, contacts[i].b);
            let (move_a, move_b) = contacts[i].resolve_penetration(particles, self.slop);
            // Every contact sharing a moved particle now overlaps by a different amount
            // (each corrected once, as the scan over all of them did).
            lists.sharing(a, b, changed);
            for &k in changed.iter() {
                let contact = &mut contacts[k as usize];
                contact.shift_penetration(a, b, move_a, move_b);
                worst.keys[k as usize] = urgency(contact, particles);
            }
            worst.refresh(changed);
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

/// The urgency of a contact that needs nothing: never the worst.
const IDLE: f32 = f32::NEG_INFINITY;

/// Buffers the paper's resolver reuses from step to step: the contacts of each
/// particle, and the tree that finds the worst contact.
#[derive(Clone, Debug, Default)]
pub struct ResolverScratch {
    lists: ContactLists,
    worst: Tournament,
    /// Contacts whose urgency changed in an iteration, ascending.
    changed: Vec<u32>,
}

impl ResolverScratch {
    /// Lists the contacts of each particle, and ranks `contacts` by `urgency`.
    fn prepare(
        &mut self,
        contacts: &[Contact],
        particles: &Particles,
        urgency: impl Fn(&Contact, &Particles) -> f32,
    ) {
        self.lists.build(contacts, particles.len());
        self.worst.build(contacts.iter().map(|c| urgency(c, particles)));
    }
}

/// The contacts of each particle: a counting sort of the contacts by particle.
#[derive(Clone, Debug, Default)]
struct ContactLists {
    /// Per particle + 1: start of its contacts in `contacts` (prefix sums).
    starts: Vec<u32>,
    /// Fill cursors.
    cursors: Vec<u32>,
    /// Contact indices by particle, in contact order; a contact is listed under each
    /// of its particles once.
    contacts: Vec<u32>,
}

impl ContactLists {
    fn build(&mut self, contacts: &[Contact], particles: usize) {
        let ends = |c: &Contact| [Some(c.a), c.b.filter(|&b| b != c.a)];
        self.starts.clear();
        self.starts.resize(particles + 1, 0);
        for contact in contacts {
            for end in ends(contact).into_iter().flatten() {
                self.starts[end + 1] += 1;
            }
        }
        for i in 0..particles {
            self.starts[i + 1] += self.starts[i];
        }
        self.cursors.clear();
        self.cursors.extend_from_slice(&self.starts[..particles]);
        self.contacts.clear();
        self.contacts.resize(self.starts[particles] as usize, 0);
        for (k, contact) in contacts.iter().enumerate() {
            for end in ends(contact).into_iter().flatten() {
                let slot = &mut self.cursors[end];
                self.contacts[*slot as usize] = k as u32;
                *slot += 1;
            }
        }
    }

    /// Indices of the contacts of particle `i`, ascending.
    fn of(&self, i: usize) -> &[u32] {
        &self.contacts[self.starts[i] as usize..self.starts[i + 1] as usize]
    }

    /// Writes into `out` the contacts of `a` or `b`, ascending, each once.
    fn sharing(&self, a: usize, b: Option<usize>, out: &mut Vec<u32>) {
        out.clear();
        let (mut x, mut y) = (self.of(a), b.map_or(&[][..], |b| self.of(b)));
        while let (Some(&i), Some(&j)) = (x.first(), y.first()) {
            out.push(i.min(j));
            if i <= j {
                x = &x[1..];
            }
            if j <= i {
                y = &y[1..];
            }
        }
        out.extend_from_slice(x);
        out.extend_from_slice(y);
    }
}

/// A tournament tree over the contacts' urgencies: finds the most urgent (the first
/// of equals, as a scan from the front would) in O(1), and takes a changed urgency in
/// O(log contacts).
#[derive(Clone, Debug, Default)]
struct Tournament {
    /// Urgency per contact; [`IDLE`] (or NaN) never wins.
    keys: Vec<f32>,
    /// Leaves in the second half (contact indices, `u32::MAX` past the end), each
    /// inner node the winner of its two children; the root at 1.
    nodes: Vec<u32>,
    leaves: usize,
}

impl Tournament {
    const EMPTY: u32 = u32::MAX;

    fn build(&mut self, keys: impl Iterator<Item = f32>) {
        self.keys.clear();
        // NaN compares false with everything: it can never be the worst.
        self.keys.extend(keys.map(|k| if k.is_nan() { IDLE } else { k }));
        let n = self.keys.len();
        self.leaves = n.next_power_of_two().max(1);
        self.nodes.clear();
        self.nodes.resize(2 * self.leaves, Self::EMPTY);
        for (i, node) in self.nodes[self.leaves..self.leaves + n].iter_mut().enumerate() {
            *node = i as u32;
        }
        for node in (1..self.leaves).rev() {
            self.nodes[node] = self.winner(self.nodes[2 * node], self.nodes[2 * node + 1]);
        }
    }

    /// The better of two contacts: the more urgent, the left (lower index) if equal.
    #[inline]
    fn winner(&self, left: u32, right: u32) -> u32 {
        if right == Self::EMPTY {
            left
        } else if left == Self::EMPTY || self.keys[right as usize] > self.keys[left as usize] {
            right
        } else {
            left
        }
    }

    /// The most urgent contact, if any is more than idle.
    fn best(&self) -> Option<usize> {
        let best = *self.nodes.get(1)?;
        (best != Self::EMPTY && self.keys[best as usize] > IDLE).then_some(best as usize)
    }

    /// Replays the matches above the contacts in `changed` (ascending; emptied) after
    /// their keys were set, level by level, each node once: changing a run of `k`
    /// neighbouring contacts costs about `k + log n`, not `k log n`.
    fn refresh(&mut self, changed: &mut Vec<u32>) {
        for k in changed.iter_mut() {
            let key = &mut self.keys[*k as usize];
            if key.is_nan() {
                *key = IDLE;
            }
            *k = (self.leaves as u32 + *k) / 2;
        }
        changed.dedup();
        while changed.first().is_some_and(|&node| node >= 1) {
            for &node in changed.iter() {
                let node = node as usize;
                self.nodes[node] = self.winner(self.nodes[2 * node], self.nodes[2 * node + 1]);
            }
            for node in changed.iter_mut() {
                *node /= 2;
            }
            changed.dedup();
        }
        changed.clear();
    }
}

//! The world: particles, the generators acting on them, and the step.

use glam::Vec3;

use super::PhysicsError;
use super::contacts::{Contact, ContactResolver, NO_SOURCE, ResolveReport};
use super::forces::{ForceGenerator, ForceId, ForceRegistry};
use super::links::{ContactGenerator, LinkState, link_geometry};
use super::particles::{ParticleDesc, ParticleId, Particles};

/// Handle to a registered contact generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ContactGeneratorId(pub u32);

/// Kinetic and potential energy of a world (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// `Σ ½ m v²` over movable particles.
    pub kinetic: f32,
    /// Gravitational (from each particle's constant acceleration and from gravity
    /// generators) plus elastic energy stored in springs.
    pub potential: f32,
}

/// A mass-aggregate world.
#[derive(Default)]
pub struct World {
    /// The particles.
    pub particles: Particles,
    /// Force generators, applied every step in order.
    pub forces: ForceRegistry,
    /// Settings of the contact resolver.
    pub resolver: ContactResolver,
    contact_generators: Vec<(ContactGeneratorId, Box<dyn ContactGenerator>)>,
    next_contact_generator: u32,
    contacts: Vec<Contact>,
    /// Contacts regenerated for the extra position passes.
    pass_contacts: Vec<Contact>,
    /// Extra rounds of "regenerate contacts from the corrected positions, then remove
    /// interpenetration" after the main resolution. The resolver's position phase is
    /// linearised; these passes see the true geometry, so chains of rods and cables
    /// hold their lengths. 0 gives the paper's single pass.
    pub position_passes: usize,
    /// Tension from the last step's contact impulses, per contact generator (N).
    link_tension: Vec<f32>,
    last_report: ResolveReport,
    time: f64,
    steps: u64,
}

impl World {
    /// An empty world with the default resolver and 4 extra position passes.
    #[must_use]
    pub fn new() -> Self {
        Self { position_passes: 4, ..Self::default() }
    }

    /// Adds a particle.
    pub fn add_particle(&mut self, desc: ParticleDesc) -> Result<ParticleId, PhysicsError> {
        self.particles.add(desc)
    }

    /// Removes a particle with every generator and link that refers to it.
    pub fn remove_particle(&mut self, id: ParticleId) -> bool {
        if !self.particles.remove(id) {
            return false;
        }
        self.forces.remove_involving(id);
        self.contact_generators.retain(|(_, g)| !g.involves(id));
        // Contact indices refer to the old dense order; drop them until the next step.
        self.contacts.clear();
        self.link_tension.clear();
        true
    }

    /// Registers a force generator.
    pub fn add_force(&mut self, generator: impl ForceGenerator + 'static) -> ForceId {
        self.forces.add(Box::new(generator))
    }

    /// Registers a contact generator (ground, collisions, rod, cable, ...).
    pub fn add_contact_generator(
        &mut self,
        generator: impl ContactGenerator + 'static,
    ) -> ContactGeneratorId {
        let id = ContactGeneratorId(self.next_contact_generator);
        self.next_contact_generator += 1;
        self.contact_generators.push((id, Box::new(generator)));
        self.link_tension.clear();
        id
    }

    /// Unregisters a contact generator; false if it was not registered.
    pub fn remove_contact_generator(&mut self, id: ContactGeneratorId) -> bool {
        let before = self.contact_generators.len();
        self.contact_generators.retain(|(entry, _)| *entry != id);
        self.link_tension.clear();
        self.contacts.clear();
        before != self.contact_generators.len()
    }

    /// Advances the world by `dt` seconds: clear forces, apply force generators,
    /// integrate, generate contacts, resolve them.
    pub fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(PhysicsError::InvalidTimeStep(dt));
        }
        // Before the generators: the stiff spring reads this step's damping factor.
        self.particles.prepare_damping(dt);
        self.particles.clear_forces();
        self.forces.apply(&mut self.particles, dt);
        self.particles.integrate(dt);

        self.contacts.clear();
        for (source, (_, generator)) in self.contact_generators.iter().enumerate() {
            generator.generate(&self.particles, source as u32, &mut self.contacts);
        }
        self.last_report = self.resolver.resolve(&mut self.contacts, &mut self.particles, dt);
        for _ in 0..self.position_passes {
            self.pass_contacts.clear();
            for (source, (_, generator)) in self.contact_generators.iter().enumerate() {
                generator.generate(&self.particles, source as u32, &mut self.pass_contacts);
            }
            let (iterations, left) =
                self.resolver.resolve_positions(&mut self.pass_contacts, &mut self.particles);
            self.last_report.position_iterations += iterations;
            self.last_report.max_penetration = left;
            if iterations == 0 {
                break;
            }
        }

        self.link_tension.clear();
        self.link_tension.resize(self.contact_generators.len(), 0.0);
        for contact in &self.contacts {
            if contact.source != NO_SOURCE {
                let sign = if contact.pulls { 1.0 } else { -1.0 };
                self.link_tension[contact.source as usize] += sign * contact.impulse / dt;
            }
        }
        self.time += f64::from(dt);
        self.steps += 1;
        Ok(self.last_report)
    }

    /// Simulated time so far (s).
    #[must_use]
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken so far.
    #[must_use]
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Contacts found and resolved in the last step.
    #[must_use]
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// What the resolver did in the last step.
    #[must_use]
    pub fn last_report(&self) -> ResolveReport {
        self.last_report
    }

    /// Kinetic and potential energy now.
    #[must_use]
    pub fn energy(&self) -> Energy {
        let p = &self.particles;
        let mut energy = Energy::default();
        for i in 0..p.len() {
            let inverse_mass = p.inverse_mass[i];
            if inverse_mass > 0.0 {
                let mass = 1.0 / inverse_mass;
                energy.kinetic += 0.5 * mass * p.velocity[i].length_squared();
                energy.potential -= mass * p.acceleration[i].dot(p.position[i]);
            }
        }
        energy.potential += self.forces.iter().map(|g| g.potential_energy(p)).sum::<f32>();
        energy
    }

    /// Writes every link (springs, rods, cables, supports) in its current state into
    /// `out`, replacing what was there. Reuses `out`'s storage.
    pub fn links_into(&self, out: &mut Vec<LinkState>) {
        out.clear();
        let p = &self.particles;
        for generator in self.forces.iter() {
            if let Some(spec) = generator.link() {
                if let Some((from, to, length)) = link_geometry(p, &spec) {
                    out.push(LinkState { spec, from, to, length, tension: generator.tension(p) });
                }
            }
        }
        for (source, (_, generator)) in self.contact_generators.iter().enumerate() {
            if let Some(spec) = generator.link() {
                if let Some((from, to, length)) = link_geometry(p, &spec) {
                    let tension = self.link_tension.get(source).copied().unwrap_or(0.0);
                    out.push(LinkState { spec, from, to, length, tension });
                }
            }
        }
    }

    /// Every link in its current state.
    #[must_use]
    pub fn links(&self) -> Vec<LinkState> {
        let mut out = Vec::new();
        self.links_into(&mut out);
        out
    }

    /// Sets the constant acceleration of every particle (typically gravity).
    pub fn set_acceleration_all(&mut self, acceleration: Vec3) -> Result<(), PhysicsError> {
        if !acceleration.is_finite() {
            return Err(PhysicsError::InvalidParticle(format!(
                "acceleration must be finite, got {acceleration}"
            )));
        }
        self.particles.acceleration.fill(acceleration);
        Ok(())
    }

    /// True if every position and velocity is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        let p = &self.particles;
        p.position.iter().chain(&p.velocity).all(|v| v.is_finite())
    }
}

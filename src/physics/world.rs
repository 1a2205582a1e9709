//! The world: particles, the generators acting on them, and the step.

use glam::Vec3;

use std::time::Instant;

use super::broad_phase::BroadPhase;
use super::collisions::{ContactGenerator, Scratch};
use super::contacts::{Contact, ContactResolver, NO_SOURCE, ResolveReport};
use super::forces::{ForceGenerator, ForceId, ForceRegistry};
use super::integrator::{Integration, Integrator};
use super::links::{LinkEnd, LinkState, link_geometry};
use super::particles::{ParticleDesc, ParticleId, Particles};
use super::soft_step::SoftStep;
use super::solver::{SolverKind, SolverSettings};
use super::state::{StateHasher, WorldState};
use super::{PhysicsError, check};

/// Handle to a registered contact generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct ContactGeneratorId(pub u32);

/// The energy budget of a world (J).
///
/// `kinetic + potential + dissipated + removed - work` would stay at its value before
/// the first step if the integrator were exact; `error` is how far it is from that,
/// which is the integrator's (and the solver's numerical) error, shown as such.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// `Σ ½ m v²` over movable particles.
    pub kinetic: f32,
    /// Gravitational (from each particle's constant acceleration and from gravity
    /// generators) plus elastic energy stored in springs.
    pub potential: f32,
    /// The gravitational part of `potential`; the rest is elastic (springs, bungees,
    /// stiff springs) and buoyancy's.
    pub gravitational: f32,
    /// Taken out since the first step, cumulative: by damping, drag, a damped stiff
    /// spring, contacts and links (inelastic bounces, friction, the solver's pushes),
    /// and what was left when particles fell asleep.
    pub dissipated: f32,
    /// Put in from outside the step since the first step, cumulative: anything that
    /// changed the energy between steps (dragging with the mouse, changing g or a mass).
    pub work: f32,
    /// Carried out of the world by particles removed since the first step, cumulative:
    /// the kinetic and potential energy each had (with the springs that went with it)
    /// when it was removed. A round of the projectile that lands and goes takes its
    /// energy with it; it is neither lost nor an error.
    pub removed: f32,
    /// `kinetic + potential + dissipated + removed - work` minus its value before the
    /// first step.
    pub error: f32,
}

/// Running totals of the energy budget, in f64.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Ledger {
    /// `kinetic + potential` before the first step, once stepped.
    start: Option<f64>,
    /// `kinetic + potential` at the end of the last step.
    last: f64,
    dissipated: f64,
    work: f64,
    /// See [`Energy::removed`].
    #[serde(default)]
    removed: f64,
}

/// Wall time of the stages of the last step (ms), for the panel and the benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Profile {
    /// Finding candidate sphere pairs (the grid).
    pub broad_phase_ms: f32,
    /// Turning pairs, planes and links into contacts.
    pub narrow_phase_ms: f32,
    /// Solving contacts and links (with the paper's resolver: resolving them).
    pub solve_ms: f32,
    /// The whole step.
    pub total_ms: f32,
}

/// Most extra position passes of the paper's resolver.
pub const MAX_POSITION_PASSES: usize = 64;

/// Longest step [`World::step`] accepts (s). A longer step is a mistake (a pause
/// measured in wall time, seconds typed as milliseconds): nothing stays stable over it.
pub const MAX_TIME_STEP: f32 = 1.0;

/// A mass-aggregate world.
#[derive(Default)]
pub struct World {
    /// The particles.
    pub particles: Particles,
    /// Force generators, applied every step in order.
    pub forces: ForceRegistry,
    /// Settings of the paper's resolver (used when the solver is [`SolverKind::Paper`]).
    resolver: ContactResolver,
    solver: SolverSettings,
    contact_generators: Vec<(ContactGeneratorId, ContactGenerator)>,
    broad_phase: BroadPhase,
    scratch: Scratch,
    soft: SoftStep,
    /// Buffers of the integrators other than semi-implicit Euler (paper's solver).
    integration: Integration,
    /// How far each particle moved in an integration (scratch).
    moved: Vec<Vec3>,
    /// How far each particle moved in the last step with the paper's resolver.
    paper_motion: Vec<Vec3>,
    /// Positions at the start of a paper step (scratch).
    paper_start: Vec<Vec3>,
    /// Velocities at the start of a paper step (scratch, semi-implicit Euler only).
    paper_velocity: Vec<Vec3>,
    profile: Profile,
    next_contact_generator: u32,
    contacts: Vec<Contact>,
    /// Contacts regenerated for the extra position passes.
    pass_contacts: Vec<Contact>,
    /// Extra rounds of "regenerate contacts from the corrected positions, then remove
    /// interpenetration" after the main resolution. The resolver's position phase is
    /// linearised; these passes see the true geometry, so chains of rods and cables
    /// hold their lengths. 0 gives the paper's single pass.
    position_passes: usize,
    /// Tension from the last step's contact impulses, per contact generator (N).
    link_tension: Vec<f32>,
    last_report: ResolveReport,
    ledger: Ledger,
    time: f64,
    steps: u64,
    /// The last step's length (s).
    last_dt: f32,
}

/// A contact as the view's debug drawing shows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// Where the surfaces meet (m): midway across the overlap, or the gap.
    pub point: Vec3,
    /// Unit normal, pointing the way the first particle is pushed.
    pub normal: Vec3,
    /// Overlap now (m); negative is a gap: a contact the soft solver keeps in case the
    /// two meet within the step (speculative).
    pub depth: f32,
    /// How hard it pushed in the last step (N): its impulse over the time it acted.
    pub force: f32,
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
        let before = self.ledger.start.map(|_| self.mechanical_energy());
        if !self.particles.remove(id) {
            return false;
        }
        self.forces.remove_involving(id);
        self.contact_generators.retain(|(_, g)| !g.involves(id));
        if let Some(before) = before {
            // The energy leaves with the particle: neither work nor loss, its own line.
            let change = self.mechanical_energy() - before;
            self.ledger.removed -= change;
            self.ledger.last += change;
        }
        // Contact indices refer to the old dense order; drop them until the next step.
        self.contacts.clear();
        self.soft.forget();
        // Island labels are dense indices, which just shifted.
        self.particles.wake_all();
        self.link_tension.clear();
        true
    }

    /// Registers a force generator after checking its settings
    /// ([`ForceGenerator::validate`]); on an error nothing is added.
    pub fn add_force(&mut self, generator: impl ForceGenerator + 'static) -> Result<ForceId, PhysicsError> {
        self.forces.add(Box::new(generator))
    }

    /// Registers a contact generator (plane, sphere collisions, rod, cable, ...) after
    /// checking its settings ([`ContactGenerator::validate`]); on an error nothing is
    /// added.
    pub fn add_contact_generator(
        &mut self,
        generator: impl Into<ContactGenerator>,
    ) -> Result<ContactGeneratorId, PhysicsError> {
        let generator = generator.into();
        generator.validate()?;
        let id = ContactGeneratorId(self.next_contact_generator);
        self.next_contact_generator += 1;
        self.contact_generators.push((id, generator));
        self.link_tension.clear();
        Ok(id)
    }

    /// Unregisters a contact generator; false if it was not registered.
    pub fn remove_contact_generator(&mut self, id: ContactGeneratorId) -> bool {
        let before = self.contact_generators.len();
        self.contact_generators.retain(|(entry, _)| *entry != id);
        self.link_tension.clear();
        self.contacts.clear();
        self.soft.forget();
        before != self.contact_generators.len()
    }

    /// The solver and its settings.
    #[must_use]
    pub fn solver(&self) -> &SolverSettings {
        &self.solver
    }

    /// Changes the solver or its settings; refused (world unchanged) if a setting is
    /// out of range.
    pub fn set_solver(&mut self, settings: SolverSettings) -> Result<(), PhysicsError> {
        settings.validate()?;
        if settings.kind != self.solver.kind {
            self.soft.forget();
            self.contacts.clear();
        }
        if settings.kind == SolverKind::Paper || !settings.sleep {
            self.particles.wake_all();
        }
        self.solver = settings;
        Ok(())
    }

    /// Settings of the paper's resolver.
    #[must_use]
    pub fn resolver(&self) -> &ContactResolver {
        &self.resolver
    }

    /// Replaces the paper resolver's settings after checking them; on an error the
    /// world keeps the old ones.
    pub fn set_resolver(&mut self, resolver: ContactResolver) -> Result<(), PhysicsError> {
        resolver.validate()?;
        self.resolver = resolver;
        Ok(())
    }

    /// Extra position passes of the paper's resolver (see the field).
    #[must_use]
    pub fn position_passes(&self) -> usize {
        self.position_passes
    }

    /// Sets the paper resolver's extra position passes, 0 to [`MAX_POSITION_PASSES`].
    pub fn set_position_passes(&mut self, passes: usize) -> Result<(), PhysicsError> {
        check(passes <= MAX_POSITION_PASSES, "position_passes", passes, "0 to 64")?;
        self.position_passes = passes;
        Ok(())
    }

    /// Advances the world by `dt` seconds with the chosen solver.
    pub fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        if !(dt > 0.0 && dt <= MAX_TIME_STEP) {
            return Err(PhysicsError::InvalidTimeStep(dt));
        }
        self.link_tension.clear();
        self.link_tension.resize(self.contact_generators.len(), 0.0);
        // Whatever changed the energy since the last step came from outside.
        let now = self.mechanical_energy();
        match self.ledger.start {
            None => self.ledger.start = Some(now),
            Some(_) => self.ledger.work += now - self.ledger.last,
        }
        self.particles.dissipated = 0.0;
        self.last_report = match self.solver.kind {
            SolverKind::Soft => self.step_soft(dt),
            SolverKind::Paper => self.step_paper(dt),
        };
        self.ledger.dissipated += self.particles.dissipated;
        self.ledger.last = self.mechanical_energy();
        self.time += f64::from(dt);
        self.steps += 1;
        self.last_dt = dt;
        Ok(self.last_report)
    }

    /// The soft step: see [`super::soft_step`].
    fn step_soft(&mut self, dt: f32) -> ResolveReport {
        self.contacts.clear();
        let report = self.soft.step(
            &self.solver,
            &mut self.particles,
            &mut self.forces,
            &self.contact_generators,
            &mut self.broad_phase,
            &mut self.scratch,
            dt,
            &mut self.link_tension,
            &mut self.profile,
        );
        ResolveReport {
            velocity_iterations: 2 * self.solver.substeps as usize,
            position_iterations: 0,
            max_penetration: report.max_penetration,
            contacts: report.contacts,
            asleep: report.asleep,
            pair_budget_hit: report.pair_budget_hit,
        }
    }

    /// The paper's step: clear forces, apply force generators, integrate, generate
    /// contacts, resolve them worst first, then a few position passes on fresh contacts.
    fn step_paper(&mut self, dt: f32) -> ResolveReport {
        let started = Instant::now();
        self.paper_start.clone_from(&self.particles.position);
        // Before the generators: the stiff spring reads this step's damping factor.
        self.particles.prepare_damping(dt);
        let integrator = self.solver.integrator;
        // Closed-form generators need the integrator's separate moving and end velocities.
        let fast = integrator == Integrator::SemiImplicitEuler && !self.forces.has_closed_form();
        if fast {
            self.paper_velocity.clone_from(&self.particles.velocity);
            self.particles.clear_forces();
            self.forces.apply(&mut self.particles, dt);
            self.particles.integrate(dt);
        } else {
            // No constraints inside the paper's integration: move, then take the end
            // velocity; the resolver works on that afterwards.
            self.integration.predict(integrator, &mut self.particles, &mut self.forces, dt);
            let mut moved = std::mem::take(&mut self.moved);
            moved.clear();
            moved.resize(self.particles.len(), Vec3::ZERO);
            self.particles.integrate_positions(dt, &mut moved, false);
            self.moved = moved;
            self.integration.finish(&mut self.particles);
        }

        if self.particles.any_damping() && fast {
            self.particles.count_damping_loss();
        }

        let collide = Instant::now();
        let before = self.mechanical_energy();
        self.scratch.pair_budget_hit = false;
        self.generate_paper_contacts(false);
        let solve = Instant::now();
        let mut report =
            self.resolver.resolve(&mut self.contacts, &mut self.particles, dt, &mut self.scratch.resolver);
        for _ in 0..self.position_passes {
            self.generate_paper_contacts(true);
            let (iterations, left) = self.resolver.resolve_positions(
                &mut self.pass_contacts,
                &mut self.particles,
                &mut self.scratch.resolver,
            );
            report.position_iterations += iterations;
            report.max_penetration = left;
            if iterations == 0 {
                break;
            }
        }
        report.contacts = self.contacts.len();
        report.pair_budget_hit = self.scratch.pair_budget_hit;
        self.paper_motion.clear();
        let moves = self.particles.position.iter().zip(&self.paper_start);
        self.paper_motion.extend(moves.map(|(&now, &start)| now - start));
        // What the resolver's impulses and position corrections added (or took out).
        self.particles.dissipated -= self.mechanical_energy() - before;
        if fast {
            self.particles.dissipated -= self.integration_error_of_constrained(dt);
        }

        for contact in &self.contacts {
            if contact.source != NO_SOURCE {
                let sign = if contact.pulls { 1.0 } else { -1.0 };
                self.link_tension[contact.source as usize] += sign * contact.impulse / dt;
            }
        }
        let done = Instant::now();
        let ms = |d: std::time::Duration| d.as_secs_f32() * 1000.0;
        self.profile = Profile {
            broad_phase_ms: 0.0,
            narrow_phase_ms: ms(solve - collide),
            solve_ms: ms(done - solve),
            total_ms: ms(done - started),
        };
        report
    }

    /// The integrator's energy error in this paper step (semi-implicit Euler) on the
    /// particles the resolver changed (J): for each, its change of kinetic energy over
    /// the integration plus what damping took, less the work of its weight and forces
    /// along the move the integration made. A particle resting on the ground falls
    /// `g dt²` in the integration, which loses `½ m g² dt²` (semi-implicit Euler's own
    /// error in free fall), and the resolver puts it back; measured across the resolver
    /// alone, the contact would book that as energy it added, and the budget as an
    /// error, both growing while nothing moves. The constrained motion is the step's
    /// motion, so this error is the contact's work and is booked with it, as the soft
    /// solver books each constrained particle's change of energy over its substep. A
    /// particle nothing touched keeps its error as error.
    fn integration_error_of_constrained(&self, dt: f32) -> f64 {
        if self.contacts.is_empty() {
            return 0.0; // nothing touched (the passes only find what the first found)
        }
        let p = &self.particles;
        let mut error = 0.0;
        for (i, (&x0, &v0)) in self.paper_start.iter().zip(&self.paper_velocity).enumerate() {
            let (w, d) = (p.inverse_mass[i], p.damping_per_step[i]);
            if w <= 0.0 || d <= 0.0 {
                continue;
            }
            // The integration's end, as `Particles::integrate` computed it (same bits).
            let kicked = (v0 + (p.acceleration[i] + p.force[i] * w) * dt) * d;
            let moved_to = x0 + kicked * dt;
            if p.velocity[i] == kicked && p.position[i] == moved_to {
                continue; // nothing touched it
            }
            let (m, d) = (1.0 / f64::from(w), f64::from(d));
            let (v0, kicked) = (v0.as_dvec3(), kicked.as_dvec3());
            let push = p.acceleration[i].as_dvec3() * m + p.force[i].as_dvec3();
            let kinetic = 0.5 * m * (kicked.length_squared() - v0.length_squared());
            let damping = 0.5 * m * kicked.length_squared() * (1.0 / (d * d) - 1.0);
            error += kinetic + damping - push.dot((moved_to - x0).as_dvec3());
        }
        error
    }

    /// Fills `contacts` (or, for a position pass, `pass_contacts`) from every generator.
    fn generate_paper_contacts(&mut self, pass: bool) {
        let out = if pass { &mut self.pass_contacts } else { &mut self.contacts };
        out.clear();
        for (source, (_, generator)) in self.contact_generators.iter().enumerate() {
            generator.generate(&self.particles, source as u32, &mut self.broad_phase, &mut self.scratch, out);
        }
    }

    /// How far each particle moved in the last step (m), by dense index: what a
    /// continuous collision test has to cover, and what the view draws as swept paths.
    /// Empty before the first step, and after particles were added or removed since.
    #[must_use]
    pub fn last_motion(&self) -> &[Vec3] {
        let motion = match self.solver.kind {
            SolverKind::Soft => self.soft.motion(),
            SolverKind::Paper => &self.paper_motion,
        };
        if motion.len() == self.particles.len() { motion } else { &[] }
    }

    /// Wall time of the last step's stages.
    #[must_use]
    pub fn profile(&self) -> Profile {
        self.profile
    }

    /// Contacts the last step solved (with the soft solver, speculative ones too).
    #[must_use]
    pub fn contact_count(&self) -> usize {
        self.last_report.contacts
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

    /// Writes the last step's contacts with particles and planes (not links) into `out`
    /// for drawing, replacing what was there, with their overlap at the end of the step.
    pub fn contact_points_into(&self, out: &mut Vec<ContactPoint>) {
        out.clear();
        let p = &self.particles;
        let motion = self.last_motion();
        let moved = |i: usize| motion.get(i).copied().unwrap_or(Vec3::ZERO);
        // Where the surfaces meet, given the first particle, the normal and the overlap.
        let point = |a: usize, normal: Vec3, depth: f32, pair: bool| {
            let across = if pair { p.radius[a] - depth * 0.5 } else { p.radius[a] - depth };
            p.position[a] - normal * across
        };
        match self.solver.kind {
            SolverKind::Soft => {
                let substep = self.last_dt / self.solver.substeps as f32;
                for c in self.soft.contacts() {
                    let (a, pair) = (c.a as usize, c.b != super::soft_step::NONE);
                    let relative = moved(a) - if pair { moved(c.b as usize) } else { Vec3::ZERO };
                    let depth = -(c.separation + relative.dot(c.normal));
                    out.push(ContactPoint {
                        point: point(a, c.normal, depth, pair),
                        normal: c.normal,
                        depth,
                        force: c.normal_impulse / substep.max(1e-9),
                    });
                }
            }
            SolverKind::Paper => {
                let from_link = |c: &Contact| {
                    self.contact_generators.get(c.source as usize).is_some_and(|(_, g)| g.link().is_some())
                };
                for c in self.contacts.iter().filter(|c| !from_link(c)) {
                    out.push(ContactPoint {
                        point: point(c.a, c.normal, c.penetration, c.b.is_some()),
                        normal: c.normal,
                        depth: c.penetration,
                        force: c.impulse / self.last_dt.max(1e-9),
                    });
                }
            }
        }
    }

    /// Each force generator's force on a particle now (N), by the generator's name, in
    /// registration order: the free-body diagram's forces, without weight (the
    /// particle's constant acceleration), damping, contacts and links. Empty for an
    /// unknown particle.
    #[must_use]
    pub fn forces_on(&self, id: ParticleId) -> Vec<(&'static str, Vec3)> {
        let Some(i) = self.particles.index(id) else { return Vec::new() };
        self.forces.iter().filter_map(|g| Some((g.name(), g.force_on(&self.particles, i)?))).collect()
    }

    /// The forces on a particle computed from its current state, one by one (N): its
    /// weight (mass times its own constant acceleration), each force generator's (by
    /// name, as [`World::forces_on`]) and damping's. Damping keeps a fraction `d` of the
    /// velocity per second, `v(t) = v d^t`: the force `m ln(d) v`. Contacts and links
    /// are not here: they have no force in a state, only an impulse over a step (see
    /// [`ConstraintMeter`](super::inspect::ConstraintMeter)). Empty for an immovable or
    /// unknown particle.
    #[must_use]
    pub fn free_body(&self, id: ParticleId) -> Vec<(&'static str, Vec3)> {
        let particles = &self.particles;
        let Some(i) = particles.index(id) else { return Vec::new() };
        if particles.inverse_mass[i] == 0.0 {
            return Vec::new();
        }
        let mass = particles.mass(i);
        let mut forces = vec![("weight", particles.acceleration[i] * mass)];
        forces.extend(self.forces_on(id));
        let v = particles.velocity[i];
        forces.push(("damping", v * (mass * particles.damping(i).max(1e-6).ln())));
        forces
    }

    /// Whether a contact pushed the particle or a rod or cable held it in the last
    /// step: whether the inspector has a "contacts and links" force to show for it.
    #[must_use]
    pub fn constrained(&self, id: ParticleId) -> bool {
        let Some(i) = self.particles.index(id) else { return false };
        let mut found = false;
        self.mark_constrained(|j| found |= j == i);
        found
    }

    /// [`World::constrained`] for every particle at once, by dense index, into `out`
    /// (replacing what was there): one pass over the links and contacts.
    pub fn constrained_into(&self, out: &mut Vec<bool>) {
        out.clear();
        out.resize(self.particles.len(), false);
        self.mark_constrained(|j| out[j] = true);
    }

    /// Calls `mark` with the dense index of each particle a link holds or a contact
    /// pushed in the last step (a particle may come more than once).
    fn mark_constrained(&self, mut mark: impl FnMut(usize)) {
        let index = |id: ParticleId| self.particles.index(id);
        for spec in self.contact_generators.iter().filter_map(|(_, g)| g.link()) {
            index(spec.a).into_iter().for_each(&mut mark);
            if let LinkEnd::Particle(b) = spec.b {
                index(b).into_iter().for_each(&mut mark);
            }
        }
        match self.solver.kind {
            SolverKind::Soft => {
                for c in self.soft.contacts().iter().filter(|c| c.normal_impulse > 0.0) {
                    mark(c.a as usize);
                    if c.b != super::soft_step::NONE {
                        mark(c.b as usize);
                    }
                }
            }
            SolverKind::Paper => {
                for c in self.contacts.iter().filter(|c| c.impulse != 0.0 || c.penetration > 0.0) {
                    mark(c.a);
                    c.b.into_iter().for_each(&mut mark);
                }
            }
        }
    }

    /// Contacts the paper's resolver handled in the last step (empty with the soft
    /// solver; see [`World::contact_count`]).
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
        let (kinetic, gravitational, stored) = self.energies();
        let potential = gravitational + stored;
        let ledger = &self.ledger;
        let start = ledger.start.unwrap_or(kinetic + potential);
        let error = kinetic + potential + ledger.dissipated + ledger.removed - ledger.work - start;
        // `+ 0.0` turns a negative zero (an empty sum) into zero: no figure reads "-0".
        Energy {
            kinetic: kinetic as f32 + 0.0,
            potential: potential as f32 + 0.0,
            gravitational: gravitational as f32 + 0.0,
            dissipated: ledger.dissipated as f32 + 0.0,
            work: ledger.work as f32 + 0.0,
            removed: ledger.removed as f32 + 0.0,
            error: error as f32 + 0.0,
        }
    }

    /// What measuring gravitational energy from the height `height` (m) instead of
    /// y = 0 adds to it (J): `Σ m a_y height` over the movable particles, with `a` each
    /// one's constant acceleration (so `-m g height` each under gravity `g`).
    #[must_use]
    pub fn gravity_reference_shift(&self, height: f32) -> f32 {
        let p = &self.particles;
        let bodies = p.acceleration.iter().zip(&p.inverse_mass).filter(|(_, w)| **w > 0.0);
        let sum: f64 = bodies.map(|(a, &w)| f64::from(a.y) / f64::from(w)).sum();
        (sum * f64::from(height)) as f32 + 0.0
    }

    /// One particle's kinetic, gravitational and stored (elastic, buoyancy) energy (J):
    /// the stored energy of every force generator acting on it, whole (a spring between
    /// two particles counts for both). `None` for an unknown or immovable particle.
    #[must_use]
    pub fn particle_energy(&self, id: ParticleId) -> Option<(f32, f32, f32)> {
        let p = &self.particles;
        let i = p.index(id)?;
        let w = p.inverse_mass[i];
        if w <= 0.0 {
            return None;
        }
        let kinetic = 0.5 * p.velocity[i].length_squared() / w;
        let mut gravitational = -p.acceleration[i].dot(p.position[i]) / w;
        let mut stored = 0.0;
        for generator in self.forces.iter().filter(|g| g.involves(id)) {
            if generator.name() == "gravity" {
                // Only this particle's share of a field acting on many.
                gravitational -= generator.force_on(p, i).map_or(0.0, |f| f.dot(p.position[i]));
            } else {
                stored += generator.potential_energy(p);
            }
        }
        Some((kinetic, gravitational, stored))
    }

    /// Kinetic and potential energy (J), summed in f64.
    fn kinetic_and_potential(&self) -> (f64, f64) {
        let (kinetic, gravitational, stored) = self.energies();
        (kinetic, gravitational + stored)
    }

    /// Kinetic, gravitational and other stored (elastic, buoyancy) energy (J), in f64.
    fn energies(&self) -> (f64, f64, f64) {
        let p = &self.particles;
        let mut gravitational = 0.0;
        for i in 0..p.len() {
            let inverse_mass = p.inverse_mass[i];
            if inverse_mass > 0.0 {
                let mass = 1.0 / f64::from(inverse_mass);
                gravitational -= mass * p.acceleration[i].as_dvec3().dot(p.position[i].as_dvec3());
            }
        }
        let mut stored = 0.0;
        for generator in self.forces.iter() {
            let energy = f64::from(generator.potential_energy(p));
            if generator.name() == "gravity" {
                gravitational += energy;
            } else {
                stored += energy;
            }
        }
        (p.kinetic_energy(), gravitational, stored)
    }

    /// Kinetic plus potential energy (J).
    fn mechanical_energy(&self) -> f64 {
        let (kinetic, potential) = self.kinetic_and_potential();
        kinetic + potential
    }

    /// Writes every link (springs, rods, cables, supports) in its current state into
    /// `out`, replacing what was there. Reuses `out`'s storage.
    pub fn links_into(&self, out: &mut Vec<LinkState>) {
        out.clear();
        let p = &self.particles;
        for generator in self.forces.iter() {
            if let Some(spec) = generator.link()
                && let Some((from, to, length)) = link_geometry(p, &spec)
            {
                // `+ 0.0`: a slack link's tension is 0, not "-0".
                out.push(LinkState { spec, from, to, length, tension: generator.tension(p) + 0.0 });
            }
        }
        for (source, (_, generator)) in self.contact_generators.iter().enumerate() {
            if let Some(spec) = generator.link()
                && let Some((from, to, length)) = link_geometry(p, &spec)
            {
                let tension = self.link_tension.get(source).copied().unwrap_or(0.0) + 0.0;
                out.push(LinkState { spec, from, to, length, tension });
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
        // A pile at rest under the old gravity is not at rest under the new one.
        self.particles.wake_all();
        Ok(())
    }

    /// The world's state apart from its scratch, as a snapshot saves it; refused if a
    /// force generator is of a kind the snapshot format does not know.
    pub fn state(&self) -> Result<WorldState, PhysicsError> {
        let (forces, next_force) = self.forces.saved()?;
        Ok(WorldState {
            particles: self.particles.clone(),
            forces,
            next_force,
            contact_generators: self.contact_generators.clone(),
            next_contact_generator: self.next_contact_generator,
            solver: self.solver,
            resolver: self.resolver,
            position_passes: self.position_passes,
            soft: self.soft.memory(),
            link_tension: self.link_tension.clone(),
            ledger: self.ledger,
            time: self.time,
            steps: self.steps,
            last_dt: self.last_dt,
        })
    }

    /// A world from a saved state, after checking every part as the setters and `add`
    /// calls would (and that the parts agree with each other): a state read from a file
    /// that passes cannot make a step panic. Steps on with the same bits as the world
    /// the state came from.
    pub fn from_state(state: WorldState) -> Result<Self, PhysicsError> {
        let invalid = PhysicsError::InvalidSetting;
        state.particles.check_loaded()?;
        state.check_references().map_err(invalid)?;
        state.solver.validate()?;
        state.resolver.validate()?;
        check(
            state.position_passes <= MAX_POSITION_PASSES,
            "position_passes",
            state.position_passes,
            "0 to 64",
        )?;
        for (_, generator) in &state.contact_generators {
            generator.validate()?;
        }
        let ledger = state.ledger;
        let totals = [ledger.start.unwrap_or(0.0), ledger.last, ledger.dissipated, ledger.work];
        if !totals.iter().all(|x| x.is_finite()) {
            return Err(invalid("the energy ledger holds a number that is not finite".into()));
        }
        let mut world = Self {
            particles: state.particles,
            forces: ForceRegistry::from_saved(state.forces, state.next_force)?,
            resolver: state.resolver,
            solver: state.solver,
            contact_generators: state.contact_generators,
            position_passes: state.position_passes,
            link_tension: state.link_tension,
            ledger,
            time: state.time,
            steps: state.steps,
            last_dt: state.last_dt,
            next_contact_generator: state.next_contact_generator,
            ..Self::default()
        };
        let generators = world.contact_generators.len();
        world.soft.restore(state.soft, generators).map_err(invalid)?;
        Ok(world)
    }

    /// A 64-bit hash of the state the next step reads: step count, time, every
    /// particle's arrays (ids, position, velocity, acceleration, inverse mass, radius,
    /// damping, sleep) and the soft solver's warm-start impulses, each number by its
    /// bits. Two runs that agree here are the same run; `simulate` prints it and the
    /// panel shows it.
    #[must_use]
    pub fn state_hash(&self) -> u64 {
        let mut hasher = StateHasher::default();
        hasher.u64(self.steps);
        hasher.f64(self.time);
        self.particles.hash_into(&mut hasher);
        self.soft.memory_hash_into(&mut hasher);
        hasher.finish()
    }

    /// True if every position and velocity is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        let p = &self.particles;
        p.position.iter().chain(&p.velocity).all(|v| v.is_finite())
    }
}

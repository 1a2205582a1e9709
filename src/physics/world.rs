//! The world: owns the parts (particles, generators, solver settings and scratch) and
//! runs the stages of a step. The top of the engine: nothing in it imports this file
//! (the inspector, above, reads a world).

use glam::Vec3;

use super::collision::{BroadPhase, ContactGenerator, Plane, Plate, Scratch};
use super::contact::Contact;
use super::energy::{self, Energy, Ledger};
pub use super::error::MAX_TIME_STEP;
use super::error::{PhysicsError, check};
use super::forces::{Force, ForceId, ForceRegistry};
use super::hash::StateHasher;
use super::ids::ContactGeneratorId;
use super::links::{LinkEnd, LinkState, link_geometry};
use super::particles::{ParticleDesc, ParticleId, Particles};
pub use super::solver::paper::MAX_POSITION_PASSES;
use super::solver::paper::resolver::ContactResolver;
use super::solver::paper::{PaperStep, PaperWorld};
use super::solver::report::{Profile, ResolveReport};
use super::solver::soft::{NONE, PARALLEL_PARTICLES, SoftStep, keep_pool_awake};
use super::solver::{SolverKind, SolverSettings};
use super::state::{self, WorldState};

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
    /// The soft solver's scratch and warm start.
    soft: SoftStep,
    /// The paper solver's scratch.
    paper: PaperStep,
    profile: Profile,
    next_contact_generator: u32,
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
        self.paper.forget();
        self.soft.forget();
        // Island labels are dense indices, which just shifted.
        self.particles.wake_all();
        self.link_tension.clear();
        true
    }

    /// Registers a force generator (gravity, drag, spring, buoyancy, stiff spring)
    /// after checking its settings
    /// ([`ForceGenerator::validate`](super::forces::ForceGenerator::validate)); on an
    /// error nothing is added.
    pub fn add_force(&mut self, generator: impl Into<Force>) -> Result<ForceId, PhysicsError> {
        self.forces.add(generator)
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

    /// The planes particles rest on or bounce off (the ground and walls), in the order
    /// they were added: what a view draws of them.
    pub fn planes(&self) -> impl Iterator<Item = &Plane> + '_ {
        self.contact_generators.iter().filter_map(|(_, generator)| match generator {
            ContactGenerator::Plane(plane) => Some(plane),
            _ => None,
        })
    }

    /// The plates with an opening (an hourglass's floor), in the order they were added.
    pub fn plates(&self) -> impl Iterator<Item = &Plate> + '_ {
        self.contact_generators.iter().filter_map(|(_, generator)| match generator {
            ContactGenerator::Plate(plate) => Some(plate),
            _ => None,
        })
    }

    /// Unregisters a contact generator; false if it was not registered.
    pub fn remove_contact_generator(&mut self, id: ContactGeneratorId) -> bool {
        let before = self.contact_generators.len();
        self.contact_generators.retain(|(entry, _)| *entry != id);
        self.link_tension.clear();
        self.paper.forget();
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
            self.paper.forget();
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
        if !super::error::time_step_in_range(dt) {
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
        self.particles.constraint = 0.0;
        self.last_report = match self.solver.kind {
            SolverKind::Soft => self.step_soft(dt),
            SolverKind::Paper => self.step_paper(dt),
        };
        self.ledger.dissipated += self.particles.dissipated;
        self.ledger.constraint += self.particles.constraint;
        self.particles.turn(dt);
        self.ledger.last = self.mechanical_energy();
        self.time += f64::from(dt);
        self.steps += 1;
        self.last_dt = dt;
        Ok(self.last_report)
    }

    /// The soft step: see [`SoftStep`].
    fn step_soft(&mut self, dt: f32) -> ResolveReport {
        self.paper.forget();
        let shared = self.particles.len() >= PARALLEL_PARTICLES;
        let mut step = || {
            self.soft.step(
                &self.solver,
                &mut self.particles,
                &mut self.forces,
                &self.contact_generators,
                &mut self.broad_phase,
                &mut self.scratch,
                dt,
                &mut self.link_tension,
                &mut self.profile,
            )
        };
        // Enough particles for the stages to be shared out: keep the pool's other
        // threads ready between them (see `solver/soft/awake.rs`).
        let report = if shared { keep_pool_awake(step) } else { step() };
        ResolveReport {
            velocity_iterations: 2 * self.solver.substeps as usize,
            position_iterations: 0,
            max_penetration: report.max_penetration,
            contacts: report.contacts,
            asleep: report.asleep,
            pair_budget_hit: report.pair_budget_hit,
        }
    }

    /// The paper's step: see [`PaperStep`].
    fn step_paper(&mut self, dt: f32) -> ResolveReport {
        let world = PaperWorld {
            particles: &mut self.particles,
            forces: &mut self.forces,
            generators: &self.contact_generators,
            broad_phase: &mut self.broad_phase,
            scratch: &mut self.scratch,
            link_tension: &mut self.link_tension,
            profile: &mut self.profile,
        };
        self.paper.step(&self.resolver, self.position_passes, self.solver.integrator, world, dt)
    }

    /// How far each particle moved in the last step (m), by dense index: what a
    /// continuous collision test has to cover, and what the view draws as swept paths.
    /// Empty before the first step, and after particles were added or removed since.
    #[must_use]
    pub fn last_motion(&self) -> &[Vec3] {
        let motion = match self.solver.kind {
            SolverKind::Soft => self.soft.motion(),
            SolverKind::Paper => self.paper.motion(),
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
                    let (a, pair) = (c.a as usize, c.b != NONE);
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
                for c in self.paper.contacts().iter().filter(|c| !from_link(c)) {
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
                    if c.b != NONE {
                        mark(c.b as usize);
                    }
                }
            }
            SolverKind::Paper => {
                for c in self.paper.contacts().iter().filter(|c| c.impulse != 0.0 || c.penetration > 0.0) {
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
        self.paper.contacts()
    }

    /// What the resolver did in the last step.
    #[must_use]
    pub fn last_report(&self) -> ResolveReport {
        self.last_report
    }

    /// Kinetic and potential energy now.
    #[must_use]
    pub fn energy(&self) -> Energy {
        let energy = self.ledger.energy(energy::energies(&self.particles, &self.forces));
        Energy { rotational: self.particles.rotational_energy() as f32 + 0.0, ..energy }
    }

    /// What measuring gravitational energy from the height `height` (m) instead of
    /// y = 0 adds to it (J): `Σ m a_y height` over the movable particles, with `a` each
    /// one's constant acceleration (so `-m g height` each under gravity `g`).
    #[must_use]
    pub fn gravity_reference_shift(&self, height: f32) -> f32 {
        energy::gravity_reference_shift(&self.particles, height)
    }

    /// One particle's kinetic, gravitational and stored (elastic, buoyancy) energy (J):
    /// the stored energy of every force generator acting on it, whole (a spring between
    /// two particles counts for both). `None` for an unknown or immovable particle.
    #[must_use]
    pub fn particle_energy(&self, id: ParticleId) -> Option<(f32, f32, f32)> {
        energy::particle_energy(&self.particles, &self.forces, id)
    }

    /// Kinetic plus potential energy (J).
    fn mechanical_energy(&self) -> f64 {
        energy::mechanical_energy(&self.particles, &self.forces)
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
        super::particles::check_acceleration(acceleration)?;
        self.particles.acceleration.fill(acceleration);
        // A pile at rest under the old gravity is not at rest under the new one.
        self.particles.wake_all();
        Ok(())
    }

    /// The world's state apart from its scratch, as a snapshot saves it. Every kind of
    /// generator can be saved; the `Result` is kept for callers written when some could
    /// not.
    pub fn state(&self) -> Result<WorldState, PhysicsError> {
        let (forces, next_force) = state::saved_forces(&self.forces);
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
    pub fn from_state(mut state: WorldState) -> Result<Self, PhysicsError> {
        let invalid = PhysicsError::InvalidSetting;
        state.particles.fill_missing_rotation();
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
        if !ledger.is_finite() {
            return Err(invalid("the energy ledger holds a number that is not finite".into()));
        }
        let mut world = Self {
            particles: state.particles,
            forces: state::forces_from_saved(state.forces, state.next_force)?,
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

    /// The first figure of the world that is no longer a finite number, named for a
    /// message ("particle 3's velocity", "the kinetic energy", "link 2's tension"), or
    /// `None` when every one is finite: every number `simulate` prints of a world and a
    /// snapshot saves. Slower than [`World::is_finite`] (it sums the energy and walks
    /// the links, into `links`), so it is for the steps that are shown or saved.
    #[must_use]
    pub fn first_non_finite(&self, links: &mut Vec<LinkState>) -> Option<String> {
        let p = &self.particles;
        let arrays: [(&str, &[Vec3]); 4] = [
            ("position", &p.position),
            ("velocity", &p.velocity),
            ("angular velocity", &p.angular_velocity),
            ("acceleration", &p.acceleration),
        ];
        for (what, values) in arrays {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Some(format!("particle {}'s {what}", p.ids()[i].0));
            }
        }
        if let Some(i) = p.inverse_inertia.iter().position(|x| !x.is_finite()) {
            return Some(format!("particle {}'s inverse moment of inertia", p.ids()[i].0));
        }
        let e = self.energy();
        let terms = [
            ("kinetic energy", e.kinetic),
            ("rotational energy", e.rotational),
            ("potential energy", e.potential),
            ("dissipated energy", e.dissipated),
            ("constraint solve's error", e.constraint),
            ("work done", e.work),
            ("energy removed", e.removed),
            ("integrator's error", e.error),
        ];
        if let Some((what, _)) = terms.iter().find(|(_, x)| !x.is_finite()) {
            return Some(format!("the {what}"));
        }
        if !self.last_report().max_penetration.is_finite() {
            return Some("the deepest overlap".into());
        }
        self.links_into(links);
        links.iter().enumerate().find_map(|(k, link)| {
            let bad = !(link.tension.is_finite() && link.length.is_finite());
            bad.then(|| format!("link {k}'s {}", if link.tension.is_finite() { "length" } else { "tension" }))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::collision::SphereCollisions;

    /// Two layers of 3 × 3 rolling spheres, each pressed a little into its neighbours,
    /// on a floor between four walls: from its first step 39 contacts of several
    /// colours. Two substeps a step (the solver's default is four) keep it quick to
    /// interpret.
    fn small_pile() -> World {
        let mut world = World::new();
        world
            .set_solver(SolverSettings { substeps: 2, ..SolverSettings::default() })
            .expect("valid settings");
        let walls = [
            (Vec3::Y, Vec3::ZERO),
            (Vec3::X, Vec3::new(-1.0, 0.0, 0.0)),
            (Vec3::NEG_X, Vec3::new(1.0, 0.0, 0.0)),
            (Vec3::Z, Vec3::new(0.0, 0.0, -1.0)),
            (Vec3::NEG_Z, Vec3::new(0.0, 0.0, 1.0)),
        ];
        for (normal, point) in walls {
            let plane =
                Plane::new(normal, point, 0.2, 0.5).expect("a valid plane").with_rolling_resistance(0.05);
            world.add_contact_generator(plane).expect("a valid plane");
        }
        let spheres = SphereCollisions { rolling_resistance: 0.05, ..SphereCollisions::new(0.2, 0.5) };
        world.add_contact_generator(spheres).expect("valid collisions");
        let (radius, spacing) = (0.2, 0.39);
        for i in 0..18 {
            let (x, y, z) = ((i % 3) as f32, (i / 3 % 3) as f32, (i / 9) as f32);
            let wobble = 0.01 * ((i * 7 % 5) as f32 - 2.0);
            let id = world
                .add_particle(ParticleDesc {
                    position: Vec3::new(
                        (x - 1.0) * spacing + wobble,
                        radius * 0.98 + y * spacing,
                        (z - 1.0) * spacing,
                    ),
                    velocity: Vec3::new(0.1 * wobble, 0.0, -0.2 * wobble),
                    acceleration: Vec3::new(0.0, -9.81, 0.0),
                    mass: 1.0 + 0.1 * (i % 4) as f32,
                    radius,
                    ..ParticleDesc::default()
                })
                .expect("a valid sphere");
            world.particles.set_rolling(id, true).expect("a sphere with a radius");
        }
        world
    }

    /// A small pile stepped once on two threads gives the bits one thread gives (its
    /// positions, velocities, spins and orientations). Under Miri the sizes from which a
    /// step shares its work out are a few contacts, so there the two-thread run takes
    /// every threaded path of the soft solver: the counting sort, batching and
    /// unbatching (`Disjoint::run`), the passes over the colours on both threads at once
    /// (`SharedVelocities` on two threads), the sphere contacts in chunks and their
    /// `append`, and the broad phase's `keep_where`. With AVX on it takes the AVX warm
    /// start, the solve two batches at a time in eight lanes and the turn four spheres
    /// at a time; with AVX-512 on, the AVX-512 solve, whose colours here are too small
    /// for sixteen lanes (which Miri cannot run: it has no AVX-512 compare). Miri stops
    /// at a data race, were two threads ever to touch one element.
    #[test]
    fn a_small_pile_steps_alike_on_one_and_two_threads() {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            pool.install(|| {
                let mut world = small_pile();
                world.step(1.0 / 60.0).expect("a valid step");
                let contacts = world.contact_count();
                let p = &world.particles;
                let bits =
                    |v: &[Vec3]| v.iter().flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>();
                let turns =
                    p.orientations().iter().flat_map(|q| q.to_array().map(f32::to_bits)).collect::<Vec<_>>();
                (bits(p.positions()), bits(p.velocities()), bits(p.angular_velocities()), turns, contacts)
            })
        };
        let one = run(1);
        // At least the 32 contacts from which a step shares all its work out under Miri.
        assert!(one.4 >= 32, "the pile is in contact: {} contacts", one.4);
        assert!(one.2.iter().any(|&b| f32::from_bits(b) != 0.0), "the spheres roll");
        let two = run(2);
        assert!(one == two, "1 thread and 2 threads differ");
    }

    /// The deepest overlap a step reports, which the soft step finds on the batches as
    /// it empties them, is the one found on its contacts, to the bit, step after step
    /// of a small pile settling (on one thread and two).
    #[test]
    #[cfg_attr(
        miri,
        ignore = "3,000 spheres: too slow to interpret; the step's debug check covers Miri's runs"
    )]
    fn the_reported_overlap_is_the_contacts() {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            pool.install(|| {
                let mut world = small_pile();
                let mut deepest = 0.0f32;
                for step in 0..40 {
                    let report = world.step(1.0 / 60.0).expect("a valid step");
                    let contacts = world.soft.deepest_overlap();
                    assert_eq!(
                        report.max_penetration.to_bits(),
                        contacts.to_bits(),
                        "step {step} on {threads} threads"
                    );
                    deepest = deepest.max(contacts);
                }
                assert!(deepest > 0.0, "the pile overlaps somewhere");
            });
        }
        // And on 2 threads with contacts enough to empty the batches on both (8,192).
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
        pool.install(|| {
            // 3,000 rolling spheres (r 0.5 m) dropped from a 15 × 15 grid into a 16 m box.
            let mut world = World::new();
            for (normal, offset) in
                [(Vec3::Y, 0.0), (Vec3::X, 8.0), (Vec3::NEG_X, 8.0), (Vec3::Z, 8.0), (Vec3::NEG_Z, 8.0)]
            {
                let plane = Plane::new(normal, -normal * offset, 0.0, 0.5).expect("a valid plane");
                world.add_contact_generator(plane).expect("a valid plane");
            }
            world.add_contact_generator(SphereCollisions::new(0.0, 0.5)).expect("valid collisions");
            for i in 0..3000 {
                let (x, z, y) = ((i % 15) as f32, (i / 15 % 15) as f32, (i / 225) as f32);
                let wobble = 0.01 * ((i * 7 % 5) as f32 - 2.0);
                let id = world
                    .add_particle(ParticleDesc {
                        position: Vec3::new(x - 7.0 + wobble, 0.5 + 1.02 * y, z - 7.0 - wobble),
                        acceleration: Vec3::new(0.0, -9.81, 0.0),
                        radius: 0.5,
                        ..ParticleDesc::default()
                    })
                    .expect("a valid sphere");
                world.particles.set_rolling(id, true).expect("a sphere with a radius");
            }
            for step in 0..150 {
                let report = world.step(1.0 / 60.0).expect("a valid step");
                let contacts = world.soft.deepest_overlap();
                assert_eq!(report.max_penetration.to_bits(), contacts.to_bits(), "step {step} of the pile");
            }
            assert!(world.contact_count() >= 8192, "{} contacts", world.contact_count());
        });
    }

    /// The contacts' forces the view draws are what holds a stack up: two spheres of 2
    /// and 1 kg stacked on the ground, at rest, press on it with the weight of both
    /// (29.43 N) and on each other with the top one's (9.81 N), to 1%.
    #[test]
    fn a_resting_stack_presses_with_its_weight() {
        let mut world = World::new();
        // Awake: a sleeping stack makes no contacts.
        world
            .set_solver(SolverSettings { sleep: false, ..SolverSettings::default() })
            .expect("valid settings");
        let ground = Plane::new(Vec3::Y, Vec3::ZERO, 0.0, 0.5).expect("a valid plane");
        world.add_contact_generator(ground).expect("a valid plane");
        world.add_contact_generator(SphereCollisions::new(0.0, 0.5)).expect("valid collisions");
        for (mass, y) in [(2.0, 0.5), (1.0, 1.5)] {
            let desc = ParticleDesc {
                position: Vec3::new(0.0, y, 0.0),
                acceleration: Vec3::new(0.0, -9.81, 0.0),
                mass,
                radius: 0.5,
                ..ParticleDesc::default()
            };
            world.add_particle(desc).expect("a valid sphere");
        }
        for _ in 0..120 {
            world.step(1.0 / 60.0).expect("a valid step");
        }
        let mut points = Vec::new();
        world.contact_points_into(&mut points);
        let force_at = |height: f32| {
            let near = points.iter().filter(|c| (c.point.y - height).abs() < 0.05);
            near.map(|c| c.force).sum::<f32>()
        };
        let (on_ground, between) = (force_at(0.0), force_at(1.0));
        assert!((on_ground - 3.0 * 9.81).abs() < 0.01 * 3.0 * 9.81, "on the ground: {on_ground} N");
        assert!((between - 9.81).abs() < 0.01 * 9.81, "between the spheres: {between} N");
    }

    /// The soft step's profile: its stages (the solve being its five parts' sum) lie
    /// within the step, the step within its time measured from outside, and a pile in
    /// contact spends time in every part. The paper's resolver has no such parts.
    #[test]
    #[cfg_attr(miri, ignore = "timing: nothing unsafe")]
    fn the_profile_parts_the_step() {
        let mut world = small_pile();
        for _ in 0..3 {
            let outside = web_time::Instant::now();
            world.step(1.0 / 60.0).expect("a valid step");
            let outside_ms = outside.elapsed().as_secs_f32() * 1000.0;
            let p = world.profile();
            let parts = [p.color_ms, p.batch_ms, p.contact_passes_ms, p.particle_sweeps_ms, p.store_ms];
            assert!(parts.iter().all(|&t| t > 0.0), "every part takes time: {p:?}");
            let stages = p.broad_phase_ms + p.narrow_phase_ms + p.solve_ms;
            assert!(stages <= p.total_ms * (1.0 + 1e-5), "the stages fit in the step: {p:?}");
            assert!(p.total_ms <= outside_ms * (1.0 + 1e-5), "{p:?} within {outside_ms} ms");
        }
        world
            .set_solver(SolverSettings {
                kind: crate::physics::solver::settings::SolverKind::Paper,
                ..*world.solver()
            })
            .expect("valid settings");
        world.step(1.0 / 60.0).expect("a valid step");
        let p = world.profile();
        assert!(p.solve_ms > 0.0 && p.total_ms <= 1e6, "{p:?}");
        let parts = [p.color_ms, p.batch_ms, p.contact_passes_ms, p.particle_sweeps_ms, p.store_ms];
        assert_eq!(parts, [0.0; 5], "the paper's resolver has no soft parts");
    }
}

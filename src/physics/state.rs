//! A world's state apart from its scratch: what a snapshot saves.
//!
//! [`WorldState`] holds everything the next step reads: the particles (with their sleep
//! state), every force generator (with the state a stiff spring carries between steps),
//! every contact generator, the solver settings, the soft solver's warm-start impulses,
//! the energy ledger, time and step count. Grids, contact lists and integrator buffers
//! are rebuilt each step and never saved. A world made from a state steps on with the
//! same bits as the world it came from (`tests/snapshots.rs`).

//!
//! The codec sits above the parts it saves and reads them: a generator knows nothing of
//! snapshots; [`SavedForce`] is made from a [`Force`] here, by one match.

use super::collision::ContactGenerator;
use super::energy::Ledger;
use super::error::{MAX_TIME_STEP, PhysicsError};
use super::forces::{Buoyancy, Drag, Force, ForceId, ForceRegistry, Gravity, Spring, StiffSpring};
use super::ids::{ContactGeneratorId, ParticleId};
use super::links::LinkEnd;
use super::particles::{AWAKE, Particles};
use super::solver::paper::resolver::ContactResolver;
use super::solver::soft::SoftMemory;
use super::solver::{SolverKind, SolverSettings};

/// A force generator as a snapshot stores it: one of the kinds the lab knows.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SavedForce {
    /// [`Gravity`] on a list of particles.
    Gravity(Gravity),
    /// [`Drag`] on a list of particles.
    Drag(Drag),
    /// A [`Spring`] or bungee.
    Spring(Spring),
    /// [`Buoyancy`] on one particle.
    Buoyancy(Buoyancy),
    /// A closed-form [`StiffSpring`].
    StiffSpring(StiffSpring),
}

impl SavedForce {
    /// The generator this describes.
    #[must_use]
    pub fn into_force(self) -> Force {
        match self {
            Self::Gravity(g) => Force::Gravity(g),
            Self::Drag(g) => Force::Drag(g),
            Self::Spring(g) => Force::Spring(g),
            Self::Buoyancy(g) => Force::Buoyancy(g),
            Self::StiffSpring(g) => Force::StiffSpring(g),
        }
    }

    /// The particles it names, to check that each exists.
    fn particles(&self) -> Vec<ParticleId> {
        match self {
            Self::Gravity(g) => g.targets.clone(),
            Self::Drag(g) => g.targets.clone(),
            Self::Spring(g) => match g.b {
                LinkEnd::Particle(b) => vec![g.a, b],
                LinkEnd::Anchor(_) => vec![g.a],
            },
            Self::Buoyancy(g) => vec![g.target],
            Self::StiffSpring(g) => vec![g.target],
        }
    }
}

impl From<&Force> for SavedForce {
    /// The generator as a snapshot stores it, with any state it carries between steps.
    fn from(force: &Force) -> Self {
        match force {
            Force::Gravity(g) => Self::Gravity(g.clone()),
            Force::Drag(g) => Self::Drag(g.clone()),
            Force::Spring(g) => Self::Spring(g.clone()),
            Force::Buoyancy(g) => Self::Buoyancy(g.clone()),
            Force::StiffSpring(g) => Self::StiffSpring(g.clone()),
        }
    }
}

/// Every generator of `forces` as a snapshot stores it, with its handle, and the next
/// handle.
pub(crate) fn saved_forces(forces: &ForceRegistry) -> (Vec<(ForceId, SavedForce)>, u32) {
    let saved = forces.entries().iter().map(|(id, force)| (*id, SavedForce::from(force))).collect();
    (saved, forces.next_id())
}

/// A registry from saved generators, each checked as [`ForceRegistry::add`] checks.
pub(crate) fn forces_from_saved(
    saved: Vec<(ForceId, SavedForce)>,
    next: u32,
) -> Result<ForceRegistry, PhysicsError> {
    ForceRegistry::from_entries(saved.into_iter().map(|(id, force)| (id, force.into_force())).collect(), next)
}

/// Everything a world's next step depends on (see the module comment).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct WorldState {
    /// The particles, in dense order, with ids, sleep state and damping cache.
    pub(crate) particles: Particles,
    /// Force generators in the order they apply, with their handles.
    pub(crate) forces: Vec<(ForceId, SavedForce)>,
    /// The handle the next force generator gets.
    pub(crate) next_force: u32,
    /// Contact generators in the order they generate, with their handles.
    pub(crate) contact_generators: Vec<(ContactGeneratorId, ContactGenerator)>,
    /// The handle the next contact generator gets.
    pub(crate) next_contact_generator: u32,
    /// Solver, integrator and their settings.
    pub(crate) solver: SolverSettings,
    /// The paper resolver's settings.
    pub(crate) resolver: ContactResolver,
    /// The paper resolver's extra position passes.
    pub(crate) position_passes: usize,
    /// The soft solver's warm start and links' last tensions.
    pub(crate) soft: SoftMemory,
    /// Tension of each link in the last step (N), by contact generator.
    pub(crate) link_tension: Vec<f32>,
    /// The energy budget's running totals.
    pub(crate) ledger: Ledger,
    /// Simulated time (s).
    pub(crate) time: f64,
    /// Steps taken.
    pub(crate) steps: u64,
    /// The last step's length (s).
    pub(crate) last_dt: f32,
}

impl WorldState {
    /// The solver settings the world was saved with.
    #[must_use]
    pub fn solver(&self) -> SolverSettings {
        self.solver
    }

    /// Checks that the generators name only live particles and that the handles are
    /// unique and below the next handle. The parts check their own values.
    pub(crate) fn check_references(&self) -> Result<(), String> {
        let live = |id: ParticleId| self.particles.index(id).is_some();
        for (id, force) in &self.forces {
            if let Some(missing) = force.particles().into_iter().find(|&p| !live(p)) {
                return Err(format!(
                    "force generator {} names particle {}, which does not exist",
                    id.0, missing.0
                ));
            }
        }
        let mut last = None;
        for (id, generator) in &self.contact_generators {
            // Handles are handed out in increasing order and kept in it.
            if id.0 >= self.next_contact_generator || last.is_some_and(|last| last >= id.0) {
                return Err(format!(
                    "contact generator id {} is out of order or not below next_contact_generator = {}",
                    id.0, self.next_contact_generator
                ));
            }
            last = Some(id.0);
            if let Some(spec) = generator.link() {
                let b = match spec.b {
                    LinkEnd::Particle(b) => Some(b),
                    LinkEnd::Anchor(_) => None,
                };
                if let Some(missing) = std::iter::once(spec.a).chain(b).find(|&p| !live(p)) {
                    return Err(format!("link {} names particle {}, which does not exist", id.0, missing.0));
                }
            }
        }
        if !(self.time.is_finite() && self.time >= 0.0 && self.last_dt.is_finite() && self.last_dt >= 0.0) {
            return Err("time and last step must be finite and >= 0".into());
        }
        // Each step adds its dt, at most MAX_TIME_STEP: no run of these steps ends later.
        let max_step = MAX_TIME_STEP;
        let latest = self.steps as f64 * f64::from(max_step) * (1.0 + 1e-9);
        if self.time > latest || self.last_dt > max_step {
            let time = if self.time < 1e9 { self.time.to_string() } else { format!("{:e}", self.time) };
            return Err(format!(
                "time = {time} s (last step {} s) is more than {} steps of at most {max_step} s reach",
                self.last_dt, self.steps
            ));
        }
        if let Some(timer) = self.particles.sleep.iter().map(|s| s.timer).find(|t| *t < 0.0) {
            return Err(format!("a sleep timer of {timer} s is below zero"));
        }
        let generators = &self.contact_generators;
        for generator in self.soft.link_generators() {
            if generators.get(generator as usize).is_none_or(|(_, g)| g.link().is_none()) {
                return Err(format!(
                    "a warm-start impulse for contact generator {generator}, which is not a link (of {} \
                     generators)",
                    generators.len()
                ));
            }
        }
        if !self.link_tension.iter().all(|t| t.is_finite()) {
            return Err("a link tension is not finite".into());
        }
        // Room to go on counting: a step count or handle near its type's end would wrap.
        let room = 1u32 << 30;
        if self.steps > 1 << 53
            || self.next_force > u32::MAX - room
            || self.next_contact_generator > u32::MAX - room
        {
            return Err("the step count or a handle counter is too large".into());
        }
        let sleeping = self.particles.sleep.iter().any(|s| s.island != AWAKE);
        if sleeping && (self.solver.kind == SolverKind::Paper || !self.solver.sleep) {
            return Err("particles are asleep although the solver does not let them sleep".into());
        }
        Ok(())
    }
}

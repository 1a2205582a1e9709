//! A world's state apart from its scratch: what a snapshot saves, and its hash.
//!
//! [`WorldState`] holds everything the next step reads: the particles (with their sleep
//! state), every force generator (with the state a stiff spring carries between steps),
//! every contact generator, the solver settings, the soft solver's warm-start impulses,
//! the energy ledger, time and step count. Grids, contact lists and integrator buffers
//! are rebuilt each step and never saved. A world made from a state steps on with the
//! same bits as the world it came from (`tests/snapshots.rs`).

use glam::Vec3;

use super::collisions::ContactGenerator;
use super::contacts::ContactResolver;
use super::forces::{Buoyancy, Drag, ForceGenerator, ForceId, Gravity, Spring};
use super::links::LinkEnd;
use super::particles::{ParticleId, Particles};
use super::soft_step::SoftMemory;
use super::solver::SolverSettings;
use super::stiff_spring::StiffSpring;
use super::world::{ContactGeneratorId, Ledger};

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
    pub fn into_generator(self) -> Box<dyn ForceGenerator> {
        match self {
            Self::Gravity(g) => Box::new(g),
            Self::Drag(g) => Box::new(g),
            Self::Spring(g) => Box::new(g),
            Self::Buoyancy(g) => Box::new(g),
            Self::StiffSpring(g) => Box::new(g),
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
        let max_step = super::world::MAX_TIME_STEP;
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
        let sleeping = self.particles.sleep.iter().any(|s| s.island != super::particles::AWAKE);
        if sleeping && (self.solver.kind == super::solver::SolverKind::Paper || !self.solver.sleep) {
            return Err("particles are asleep although the solver does not let them sleep".into());
        }
        Ok(())
    }
}

/// A 64-bit hash of a state's numbers, fed word by word: each f32 by its bits, so two
/// states hash alike only if they are the same bits (up to collisions). Cheap enough
/// to run after every step: one multiply per word (the mix of `FxHash`, finished with
/// `splitmix64`'s so that nearby states give unlike hashes).
#[derive(Clone, Copy, Debug)]
pub struct StateHasher(u64);

impl Default for StateHasher {
    fn default() -> Self {
        Self(0x243F_6A88_85A3_08D3)
    }
}

impl StateHasher {
    /// Feeds a 64-bit word.
    #[inline]
    pub fn u64(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x517C_C1B7_2722_0A95);
    }

    /// Feeds an f32 by its bits.
    #[inline]
    pub fn f32(&mut self, x: f32) {
        self.u64(u64::from(x.to_bits()));
    }

    /// Feeds an f64 by its bits.
    #[inline]
    pub fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }

    /// Feeds a vector's three components.
    #[inline]
    pub fn vec3(&mut self, v: Vec3) {
        self.u64(u64::from(v.x.to_bits()) | (u64::from(v.y.to_bits()) << 32));
        self.f32(v.z);
    }

    /// The hash.
    #[must_use]
    pub fn finish(self) -> u64 {
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

//! What a force generator does: the behaviour every kind shares ([`ForceGenerator`]).
//!
//! The kinds themselves are listed in [`Force`](super::Force) (`kind.rs`); the trait is
//! the contract each fulfils, and what code that handles any kind calls.

use glam::Vec3;

use crate::physics::error::PhysicsError;
use crate::physics::ids::ParticleId;
use crate::physics::links::LinkSpec;
use crate::physics::particles::Particles;

/// Something that adds forces to particles every step. `Send` so that a world can be
/// handed to another thread (a benchmark's pool, a background simulation).
pub trait ForceGenerator: Send {
    /// Adds this step's force to the particles' accumulators, for a step that moves
    /// the particles with what this one evaluation gives (semi-implicit Euler): a
    /// generator may choose the force that lands that step on its own exact solution
    /// (drag does). `dt` is the step (s).
    fn apply(&mut self, particles: &mut Particles, dt: f32);

    /// Adds the force as the physics defines it at the particles' current state, for
    /// an integrator that evaluates forces at trial states and weighs them itself
    /// (explicit Euler, Verlet, RK4). What it books as dissipated is the power at this
    /// state times `dt`; the integrator weighs the evaluations' bookings as it weighs
    /// their forces, so a step books its loss once. By default the same as `apply`.
    fn apply_instantaneous(&mut self, particles: &mut Particles, dt: f32) {
        self.apply(particles, dt);
    }

    /// For a generator that moves its particle over the step in closed form, whatever
    /// the integrator (the stiff spring): the step from the particle's current state
    /// under its other accelerations `other` (m/s², by dense index), held constant over
    /// the step. Such a generator adds no force at an evaluation; the integrator takes
    /// this step for its particle instead. `None` for every other generator.
    fn closed_step(&self, _particles: &Particles, _other: &[Vec3], _h: f32) -> Option<ClosedStep> {
        None
    }

    /// Whether [`ForceGenerator::closed_step`] moves a particle.
    fn moves_in_closed_form(&self) -> bool {
        false
    }

    /// Checks every setting; the error names the field and its valid range. The
    /// registry calls it before accepting the generator.
    fn validate(&self) -> Result<(), PhysicsError> {
        Ok(())
    }

    /// Whether this generator refers to the particle.
    fn involves(&self, id: ParticleId) -> bool;

    /// The particle is being removed: forget it. Returns true if the generator has
    /// nothing left to act on and must go too. A link goes with either end; a field
    /// acting on many particles only drops that one from its list.
    fn release(&mut self, id: ParticleId) -> bool {
        self.involves(id)
    }

    /// Stored elastic or field energy (J) in the current state; 0 if not meaningful.
    fn potential_energy(&self, _particles: &Particles) -> f32 {
        0.0
    }

    /// The generator seen as a link between two points, if it is one (springs are).
    fn link(&self) -> Option<LinkSpec> {
        None
    }

    /// Tension (N) along the link in the current state; positive pulls the ends together.
    fn tension(&self, _particles: &Particles) -> f32 {
        0.0
    }

    /// A short name for the force, as the inspector and the free-body arrows show it.
    fn name(&self) -> &'static str {
        "force"
    }

    /// The force this generator puts on particle `i` (dense index) in the current state
    /// (N), as the physics defines it (not the step's integrated form), or `None` where
    /// it does not act on that particle.
    fn force_on(&self, _particles: &Particles, _i: usize) -> Option<Vec3> {
        None
    }
}

/// One particle's step taken in closed form ([`ForceGenerator::closed_step`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosedStep {
    /// The particle (dense index).
    pub index: usize,
    /// The velocity that carries it from its start to its end position over the step
    /// (m/s): the step's average velocity.
    pub moving: Vec3,
    /// Its exact velocity at the end of the step, before damping (m/s).
    pub end: Vec3,
    /// Energy the generator's own damping took over the step (J).
    pub dissipated: f64,
}

/// Which of a generator's two forms an evaluation asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Evaluation {
    /// [`ForceGenerator::apply`]: the one evaluation of a semi-implicit Euler step.
    Step,
    /// [`ForceGenerator::apply_instantaneous`]: one of an integrator's trial states.
    Instantaneous,
}

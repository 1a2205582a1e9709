//! The physics core: a mass-aggregate particle engine.
//!
//! It knows nothing of windows, GPUs or user interfaces: the renderer and the panel
//! read a [`World`]; only scenes and the command line step it.
//!
//! Units everywhere: metres, seconds, kilograms, newtons; y is up.
//!
//! The engine is layered rooms; a room imports only rooms on the floors below it (see
//! ARCHITECTURE.md, "The engine", and `scripts/imports.py`, which checks it):
//! 1. [`ids`], [`hash`], [`error`]: handles, the state hash, errors and range checks;
//!    `wide`: four lanes of `f32` at once (SSE, or arrays), for the contact solve;
//! 2. [`particles`]: the struct-of-arrays store;
//! 3. [`links`], [`contact`]: what a link and a contact are;
//! 4. [`forces`]: force generators; [`collision`]: broad and narrow phase;
//! 5. [`integrator`], [`energy`], [`exact`]: stepping a particle, the energy budget,
//!    closed forms;
//! 6. [`solver`]: settings, reports, the paper's resolver and the soft solver;
//! 7. [`state`]: the snapshot codec;
//! 8. [`world`]: owns the parts and runs the stages; [`inspect`] reads a world.
//!
//! This file only names the rooms and re-exports what outside code uses.

pub mod collision;
pub mod contact;
pub mod energy;
pub mod error;
pub mod exact;
pub mod forces;
pub mod hash;
pub mod ids;
pub mod inspect;
pub mod integrator;
pub mod links;
pub mod particles;
pub mod solver;
pub mod state;
pub(crate) mod wide;
pub mod world;

/// The broad phase, under the path it had before `collision/` (`physics::broad_phase`).
pub use collision::broad_phase;
/// The stiff spring, under the path it had before `forces/` (`physics::stiff_spring`).
pub use forces::stiff_spring;

pub use collision::{
    BroadPhase, ContactGenerator, DEFAULT_ROLLING_RESISTANCE, Extent, GroundPlane, Plane, Plate,
    SphereCollisions,
};
pub use contact::Contact;
pub use energy::Energy;
pub use error::PhysicsError;
pub use forces::{
    Buoyancy, ClosedStep, Drag, Force, ForceGenerator, ForceId, ForceRegistry, Gravity, Spring, StiffSpring,
};
pub use hash::StateHasher;
pub use ids::{ContactGeneratorId, ParticleId};
pub use integrator::Integrator;
pub use links::{Constraint, LinkEnd, LinkKind, LinkSpec, LinkState, direction_or_zero};
pub use particles::{ParticleDesc, Particles};
pub use solver::paper::resolver::ContactResolver;
pub use solver::report::{Profile, ResolveReport};
pub use solver::{LinkSolver, SolverChoice, SolverKind, SolverSettings};
pub use state::{SavedForce, WorldState};
pub use world::{ContactPoint, World};

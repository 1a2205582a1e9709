//! The physics core: a mass-aggregate particle engine.
//!
//! It knows nothing of windows, GPUs or user interfaces: the renderer and the panel
//! read a [`World`]; only scenes and the command line step it.
//!
//! Units everywhere: metres, seconds, kilograms, newtons; y is up.

pub mod broad_phase;
pub mod collisions;
pub mod contacts;
pub mod forces;
pub mod links;
pub mod particles;
pub mod soft_step;
pub mod solver;
pub mod stiff_spring;
pub mod world;

pub use broad_phase::BroadPhase;
pub use collisions::{ContactGenerator, GroundPlane, Plane, SphereCollisions};
pub use contacts::{Contact, ContactResolver, ResolveReport};
pub use forces::{Buoyancy, Drag, ForceGenerator, ForceId, ForceRegistry, Gravity, Spring};
pub use links::{Constraint, LinkEnd, LinkKind, LinkSpec, LinkState, direction_or_zero};
pub use particles::{ParticleDesc, ParticleId, Particles};
pub use solver::{SolverKind, SolverSettings};
pub use stiff_spring::StiffSpring;
pub use world::{ContactGeneratorId, Energy, Profile, World};

/// What can go wrong when building or stepping a world.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    /// A particle description was rejected.
    #[error("invalid particle: {0}")]
    InvalidParticle(String),
    /// A step was asked for with a non-positive or non-finite duration.
    #[error("time step must be a positive finite number of seconds, got {0}")]
    InvalidTimeStep(f32),
    /// A solver or generator setting out of its range; the message names the field.
    #[error("{0}")]
    InvalidSetting(String),
    /// An id that names no live particle.
    #[error("no particle with id {}", .0.0)]
    UnknownParticle(ParticleId),
}

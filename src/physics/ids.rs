//! Handles: the stable names outside code holds for particles and generators.
//!
//! The ground floor of the engine: every other room may import these, and this file
//! imports nothing of the engine.

/// A stable handle to a particle. Ids are never reused within one
/// [`Particles`](super::Particles) store.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub struct ParticleId(pub u32);

/// Handle to a registered force generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct ForceId(pub u32);

/// Handle to a registered contact generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct ContactGeneratorId(pub u32);

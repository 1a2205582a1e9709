//! Particle storage: struct-of-arrays with stable ids.
//!
//! Hot loops (integration, force clearing) walk the arrays in order with zipped
//! iterators; everything that refers to a particle from outside (force generators,
//! links, the renderer's trails) holds a [`ParticleId`], which stays valid until that
//! particle is removed, even when other particles are removed and the arrays are
//! compacted.
//!
//! The rooms, by what their parts do (this file only names them and re-exports):
//! - `store.rs`: [`Particles`], the arrays, adding and removing particles, the
//!   read-only views;
//! - `desc.rs`: what a particle is made from ([`ParticleDesc`]), the checks every
//!   value passes on its way in, and the stored values that follow from it;
//! - `sleep.rs`: a particle's sleep state;
//! - `setters.rs`: the one door that changes a particle's state, checking the value and
//!   waking it;
//! - `integrate.rs`: the step's kick and drift, damping, and the energy sums;
//! - `turning.rs`: rolling spheres turned by their spin, the same bits on every target.
//!
//! `desc.rs` and `sleep.rs` are leaves; `store.rs` reads them; the rest add methods to
//! the store. None imports this file.

mod desc;
mod integrate;
mod parts;
mod setters;
mod sleep;
mod store;
mod turning;

pub use super::ids::ParticleId;
pub(crate) use desc::check_acceleration;
pub use desc::{MAX_MASS, MIN_MASS, ParticleDesc, inverse_mass};
pub(crate) use integrate::kicked;
pub(crate) use parts::{Disjoint, in_lanes, on_threads, tree_sum};
pub(crate) use sleep::{AWAKE, Sleep};
pub use store::Particles;

//! Force generators: anything that adds a force to particles each step.
//!
//! Each generator names the particles it acts on by [`ParticleId`]; the
//! [`ForceRegistry`] owns the generators and applies them in the order they were added.
//!
//! - [`generator`]: the [`ForceGenerator`] behaviour every kind shares;
//! - [`kind`]: [`Force`], the closed set of kinds, which the registry holds;
//! - [`fields`]: [`Gravity`], [`Drag`], [`Buoyancy`];
//! - [`spring`]: [`Spring`] (and bungees);
//! - [`stiff_spring`]: the closed-form [`StiffSpring`].
//!
//! Imports the ground floor, particles and links; nothing above.

pub mod fields;
pub mod generator;
pub mod kind;
pub mod spring;
pub mod stiff_spring;

use glam::Vec3;

pub use fields::{Buoyancy, Drag, Gravity};
pub(crate) use generator::Evaluation;
pub use generator::{ClosedStep, ForceGenerator};
pub use kind::Force;
pub use spring::Spring;
pub use stiff_spring::StiffSpring;

use crate::physics::error::PhysicsError;
pub use crate::physics::ids::ForceId;
use crate::physics::ids::ParticleId;
use crate::physics::particles::Particles;

/// Owns the force generators of a world; supports add, remove and clear.
#[derive(Default)]
pub struct ForceRegistry {
    entries: Vec<(ForceId, Force)>,
    next: u32,
}

impl ForceRegistry {
    /// Registers a generator and returns its handle, after checking its settings
    /// ([`ForceGenerator::validate`]); on an error nothing is added.
    pub fn add(&mut self, generator: impl Into<Force>) -> Result<ForceId, PhysicsError> {
        let generator = generator.into();
        generator.generator().validate()?;
        let id = ForceId(self.next);
        self.next += 1;
        self.entries.push((id, generator));
        Ok(id)
    }

    /// Unregisters a generator; false if it was not registered.
    pub fn remove(&mut self, id: ForceId) -> bool {
        let before = self.entries.len();
        self.entries.retain(|(entry, _)| *entry != id);
        self.entries.len() != before
    }

    /// Swaps the generator behind `id` for another, keeping its place in the order;
    /// `Ok(false)` if `id` is not registered. A generator whose settings are invalid
    /// is refused and the old one kept.
    pub fn replace(&mut self, id: ForceId, generator: impl Into<Force>) -> Result<bool, PhysicsError> {
        let generator = generator.into();
        generator.generator().validate()?;
        Ok(match self.entries.iter_mut().find(|(entry, _)| *entry == id) {
            Some(entry) => {
                entry.1 = generator;
                true
            }
            None => false,
        })
    }

    /// Tells every generator the particle is gone, dropping those left with nothing.
    pub fn remove_involving(&mut self, particle: ParticleId) {
        self.entries.retain_mut(|(_, g)| !g.generator_mut().release(particle));
    }

    /// Unregisters everything.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Number of registered generators.
    #[must_use]
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when nothing is registered.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Applies every generator, in registration order.
    pub fn apply(&mut self, particles: &mut Particles, dt: f32) {
        for (_, generator) in &mut self.entries {
            generator.generator_mut().apply(particles, dt);
        }
    }

    /// Applies every generator but those that move their particle in closed form, in
    /// the form `evaluation` asks for: what an integrator that takes closed-form steps
    /// evaluates ([`crate::physics::integrator`]).
    pub(crate) fn apply_for(&mut self, particles: &mut Particles, dt: f32, evaluation: Evaluation) {
        let open =
            self.entries.iter_mut().map(|(_, g)| g.generator_mut()).filter(|g| !g.moves_in_closed_form());
        for generator in open {
            match evaluation {
                Evaluation::Step => generator.apply(particles, dt),
                Evaluation::Instantaneous => generator.apply_instantaneous(particles, dt),
            }
        }
    }

    /// Whether a generator moves its particle in closed form: such a world is stepped
    /// by the general integrator ([`crate::physics::integrator`]) whatever the integrator.
    #[must_use]
    pub fn has_closed_form(&self) -> bool {
        self.iter().any(|g| g.moves_in_closed_form())
    }

    /// The closed-form steps of the generators that take them, from the particles'
    /// current state, into `out` (cleared first).
    pub(crate) fn closed_steps(
        &self,
        particles: &Particles,
        other: &[Vec3],
        h: f32,
        out: &mut Vec<ClosedStep>,
    ) {
        out.clear();
        out.extend(self.iter().filter_map(|g| g.closed_step(particles, other, h)));
    }

    /// Iterates over the generators' behaviour, in registration order.
    pub fn iter(&self) -> impl Iterator<Item = &dyn ForceGenerator> {
        self.entries.iter().map(|(_, g)| g.generator())
    }

    /// Iterates over the generators by kind, in registration order.
    pub fn kinds(&self) -> impl Iterator<Item = &Force> {
        self.entries.iter().map(|(_, g)| g)
    }

    /// Every generator with its handle, in registration order.
    #[must_use]
    pub fn entries(&self) -> &[(ForceId, Force)] {
        &self.entries
    }

    /// The handle the next generator gets.
    #[must_use]
    pub fn next_id(&self) -> u32 {
        self.next
    }

    /// A registry from generators with their handles (as a snapshot holds them), each
    /// checked as [`ForceRegistry::add`] checks; handles must increase and stay below
    /// `next`.
    pub fn from_entries(saved: Vec<(ForceId, Force)>, next: u32) -> Result<Self, PhysicsError> {
        let mut entries = Vec::with_capacity(saved.len());
        for (id, generator) in saved {
            // Handles are handed out in increasing order and kept in it.
            let increasing = entries.last().is_none_or(|(last, _): &(ForceId, _)| last.0 < id.0);
            if id.0 >= next || !increasing {
                return Err(PhysicsError::InvalidSetting(format!(
                    "force id {} is out of order or not below next_force = {next}",
                    id.0
                )));
            }
            generator.generator().validate()?;
            entries.push((id, generator));
        }
        Ok(Self { entries, next })
    }
}

//! What an inspector shows of a particle's forces, measured the way a student would:
//! the forces of the current state from their laws ([`World::free_body`]), and what
//! contacts and links did over the last step, which has no law to evaluate, from the
//! step's change of momentum.

use glam::Vec3;

use super::particles::ParticleId;
use super::world::World;

/// The name of what contacts and links did over the last step, as the inspector and
/// `simulate --forces` show it.
pub const CONSTRAINT_FORCE: &str = "contacts and links (last step)";

/// The forces on a particle, one by one (N): [`World::free_body`] from the current
/// state and, while a contact or link acts on it, what they did over the last step
/// (`measured`, from a [`ConstraintMeter`]); for a particle asleep, which is at rest,
/// what they hold: the opposite of the rest. Their sum is the net force.
#[must_use]
pub fn forces_on(world: &World, id: ParticleId, measured: Option<Vec3>) -> Vec<(&'static str, Vec3)> {
    forces_given(world, id, measured, world.constrained(id))
}

/// [`forces_on`] when it is already known whether a contact or link acts on the
/// particle ([`World::constrained_into`], for many particles at once).
#[must_use]
pub fn forces_given(
    world: &World,
    id: ParticleId,
    measured: Option<Vec3>,
    constrained: bool,
) -> Vec<(&'static str, Vec3)> {
    let mut forces = world.free_body(id);
    if forces.is_empty() {
        return forces;
    }
    let asleep = world.particles.index(id).is_some_and(|i| world.particles.is_asleep(i));
    if asleep {
        let others: Vec3 = forces.iter().map(|(_, f)| *f).sum();
        forces.push((CONSTRAINT_FORCE, -others));
    } else if constrained && let Some(force) = measured {
        forces.push((CONSTRAINT_FORCE, force));
    }
    forces
}

/// Measures the force contacts and links put on particles over a step: the change of
/// momentum the step made, `m (v₁ − v₀) / dt`, less what the particle's other forces
/// (weight, generators, damping) gave at the start of the step. With semi-implicit
/// Euler that leaves only the constraints' impulse over `dt`, plus an `O(dt)` rest from
/// damping's and drag's curvature over the step.
#[derive(Clone, Debug, Default)]
pub struct ConstraintMeter {
    /// Each watched particle's velocity and summed other forces before the step.
    before: Vec<(ParticleId, Vec3, Vec3)>,
}

impl ConstraintMeter {
    /// Records the watched particles' state before a step (replacing what was kept).
    pub fn before_step(&mut self, world: &World, ids: impl IntoIterator<Item = ParticleId>) {
        self.before.clear();
        for id in ids {
            let Some(i) = world.particles.index(id) else { continue };
            if world.particles.inverse_masses()[i] > 0.0 {
                let other: Vec3 = world.free_body(id).iter().map(|(_, f)| *f).sum();
                self.before.push((id, world.particles.velocities()[i], other));
            }
        }
    }

    /// The constraint force on each watched particle that is still there over the step
    /// of `dt` just taken (N), by id.
    pub fn after_step<'a>(
        &'a self,
        world: &'a World,
        dt: f32,
    ) -> impl Iterator<Item = (ParticleId, Vec3)> + 'a {
        let particles = &world.particles;
        self.before.iter().filter_map(move |&(id, v0, other)| {
            let i = particles.index(id)?;
            let m = particles.mass(i);
            Some((id, (particles.velocities()[i] - v0) * (m / dt) - other))
        })
    }
}

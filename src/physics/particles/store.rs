//! The store: every particle's state in parallel arrays, one per quantity, indexed by
//! a dense index, with stable ids; adding and removing particles, and the read-only
//! views outside code reads.

use glam::{Quat, Vec3};

use super::desc::{MAX_MASS, MIN_MASS, ParticleDesc, damping_factor, sphere_inverse_inertia};
use super::sleep::{AWAKE, Sleep};
use crate::physics::error::{MAX_RADIUS, MIN_ROLLING_RADIUS, PhysicsError, Shown};
use crate::physics::hash::StateHasher;
use crate::physics::ids::ParticleId;

const DEAD: u32 = u32::MAX;

/// All particles of a world, stored as parallel arrays indexed by a dense index.
///
/// The dense index of a particle changes when another particle is removed; use
/// [`Particles::index`] to turn a [`ParticleId`] into the current index.
///
/// Outside the physics module the arrays are read-only slices (`positions()` and the
/// like): particles come and go through [`Particles::add`] and [`Particles::remove`],
/// so the arrays always have one length, and a state is changed through the setters,
/// which check the value and wake a sleeping particle.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Particles {
    /// Positions (m).
    pub(crate) position: Vec<Vec3>,
    /// Velocities (m/s).
    pub(crate) velocity: Vec<Vec3>,
    /// Constant accelerations (m/s²), usually gravity.
    pub(crate) acceleration: Vec<Vec3>,
    /// Force accumulated this step (N); cleared at the start of every step.
    pub(crate) force: Vec<Vec3>,
    /// Inverse masses (1/kg); 0 means immovable.
    pub(crate) inverse_mass: Vec<f32>,
    /// Collision radii (m).
    pub(crate) radius: Vec<f32>,
    /// Inverse moments of inertia (1/(kg·m²)): `1 / (2/5 m r²)` for a sphere that
    /// rolls (a solid sphere), 0 for a point mass, which never turns (the paper's
    /// particles, and every particle unless [`Particles::set_rolling`] says otherwise).
    #[serde(default)]
    pub(crate) inverse_inertia: Vec<f32>,
    /// Whether each particle was made a sphere that rolls ([`Particles::set_rolling`]);
    /// an immovable one has inverse inertia 0 all the same, and rolls once set free.
    #[serde(default)]
    pub(super) rolling: Vec<bool>,
    /// Angular velocities (rad/s); zero for particles that do not roll.
    #[serde(default)]
    pub(crate) angular_velocity: Vec<Vec3>,
    /// Orientations (unit quaternions), turned by the angular velocity each step; what
    /// the renderer shows of a sphere's spin.
    #[serde(default)]
    pub(crate) orientation: Vec<Quat>,
    /// Fraction of velocity kept per second.
    pub(super) damping: Vec<f32>,
    /// `damping.powf(damping_dt)`, cached so the step does not call `powf` per particle.
    pub(crate) damping_per_step: Vec<f32>,
    pub(super) damping_dt: f32,
    /// Sleep state, per particle: see [`Sleep`].
    pub(crate) sleep: Vec<Sleep>,
    /// Energy taken out by drag, damped springs, damping and the solvers' losses since
    /// the world last read it (J); see
    /// [`Energy::dissipated`](crate::physics::energy::Energy::dissipated).
    pub(crate) dissipated: f64,
    /// Energy taken out (negative: put in) by the solvers' corrections since the world
    /// last read it (J); see [`Energy::constraint`](crate::physics::energy::Energy::constraint).
    #[serde(default)]
    pub(crate) constraint: f64,
    /// Dense index -> id.
    pub(super) ids: Vec<ParticleId>,
    /// Id -> dense index, or `DEAD`.
    pub(super) slots: Vec<u32>,
}

impl Particles {
    /// An empty store.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty store with room for `n` particles without reallocating.
    #[must_use]
    pub fn with_capacity(n: usize) -> Self {
        Self {
            position: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
            acceleration: Vec::with_capacity(n),
            force: Vec::with_capacity(n),
            inverse_mass: Vec::with_capacity(n),
            radius: Vec::with_capacity(n),
            inverse_inertia: Vec::with_capacity(n),
            rolling: Vec::with_capacity(n),
            angular_velocity: Vec::with_capacity(n),
            orientation: Vec::with_capacity(n),
            damping: Vec::with_capacity(n),
            damping_per_step: Vec::with_capacity(n),
            damping_dt: 0.0,
            sleep: Vec::with_capacity(n),
            dissipated: 0.0,
            constraint: 0.0,
            ids: Vec::with_capacity(n),
            slots: Vec::with_capacity(n),
        }
    }

    /// Checks a store read from a snapshot: one length for every array, ids and slots
    /// that agree, finite values in range. A store that passes cannot make a step index
    /// out of bounds or divide by a bad mass.
    pub(crate) fn check_loaded(&self) -> Result<(), PhysicsError> {
        let n = self.ids.len();
        let lengths = [
            self.position.len(),
            self.velocity.len(),
            self.acceleration.len(),
            self.force.len(),
            self.inverse_mass.len(),
            self.radius.len(),
            self.inverse_inertia.len(),
            self.rolling.len(),
            self.angular_velocity.len(),
            self.orientation.len(),
            self.damping.len(),
            self.damping_per_step.len(),
            self.sleep.len(),
        ];
        if lengths.iter().any(|&len| len != n) {
            return Err(PhysicsError::InvalidParticle(format!(
                "the particle arrays have different lengths ({n} ids, arrays of {lengths:?})"
            )));
        }
        let live = self.slots.iter().filter(|&&slot| slot != DEAD).count();
        let agree =
            self.ids.iter().enumerate().all(|(i, id)| self.slots.get(id.0 as usize) == Some(&(i as u32)));
        if live != n || !agree {
            return Err(PhysicsError::InvalidParticle("particle ids and slots do not agree".into()));
        }
        let vectors = self.position.iter().chain(&self.velocity).chain(&self.acceleration).chain(&self.force);
        if !vectors.chain(&self.angular_velocity).copied().all(Vec3::is_finite) {
            return Err(PhysicsError::InvalidParticle(
                "a position, velocity, angular velocity, acceleration or force is not finite".into(),
            ));
        }
        for i in 0..n {
            let id = self.ids[i].0;
            let fail = |what: &str| Err(PhysicsError::InvalidParticle(format!("particle {id}: {what}")));
            let w = self.inverse_mass[i];
            if !(w == 0.0 || (1.0 / MAX_MASS..=1.0 / MIN_MASS).contains(&w)) {
                return fail("inverse mass must be 0 (immovable) or that of a mass in range");
            }
            if w == 0.0 && self.velocity[i] != Vec3::ZERO {
                return fail("an immovable particle cannot have a velocity");
            }
            if self.damping_per_step[i] != damping_factor(self.damping[i], self.damping_dt) {
                return fail("its damping per step does not follow from its damping");
            }
            if !(self.radius[i].is_finite() && (0.0..=MAX_RADIUS).contains(&self.radius[i])) {
                return fail(&format!("radius must be 0 to {MAX_RADIUS:e} m"));
            }
            if self.rolling[i] && w > 0.0 && self.radius[i] > 0.0 && self.radius[i] < MIN_ROLLING_RADIUS {
                return fail(&format!(
                    "a sphere that rolls needs a radius of at least {} m",
                    MIN_ROLLING_RADIUS.shown()
                ));
            }
            let rolls = self.inverse_inertia[i] != 0.0;
            if rolls != (self.rolling[i] && w > 0.0 && self.radius[i] > 0.0) {
                return fail("its inverse inertia does not follow from whether it rolls");
            }
            if rolls && self.inverse_inertia[i] != sphere_inverse_inertia(w, self.radius[i]) {
                return fail(
                    "its inverse inertia must be that of a solid sphere of its mass and radius, or 0",
                );
            }
            if !rolls && self.angular_velocity[i] != Vec3::ZERO {
                return fail("a particle that does not roll cannot have an angular velocity");
            }
            let q = self.orientation[i];
            if !(q.is_finite() && (q.length() - 1.0).abs() < 1e-3) {
                return fail("orientation must be a unit quaternion");
            }
            if !(0.0..=1.0).contains(&self.damping[i]) || !(0.0..=1.0).contains(&self.damping_per_step[i]) {
                return fail("damping must be between 0 and 1");
            }
            let sleep = &self.sleep[i];
            let rest = sleep.rest.is_finite() || sleep.rest.is_nan();
            if !(sleep.timer.is_finite() && rest) || (sleep.island != AWAKE && sleep.island as usize >= n) {
                return fail("sleep state out of range");
            }
            // Asleep: movable, and at rest unless moved from outside since (a NaN rest).
            let moving = self.velocity[i] != Vec3::ZERO || self.angular_velocity[i] != Vec3::ZERO;
            if sleep.island != AWAKE && (w == 0.0 || (moving && !sleep.rest.is_nan())) {
                return fail("only a movable particle at rest can be asleep");
            }
        }
        let tallies = self.dissipated.is_finite() && self.constraint.is_finite();
        if !(self.damping_dt.is_finite() && self.damping_dt >= 0.0 && tallies) {
            return Err(PhysicsError::InvalidParticle(
                "damping step, dissipated or constraint energy is not finite".into(),
            ));
        }
        Ok(())
    }

    /// Feeds every array a step reads to a state hash, in dense order.
    pub(crate) fn hash_into(&self, hasher: &mut StateHasher) {
        for id in &self.ids {
            hasher.u64(u64::from(id.0));
        }
        for (p, v) in self.position.iter().zip(&self.velocity) {
            hasher.vec3(*p);
            hasher.vec3(*v);
        }
        for ((a, w), (r, d)) in
            self.acceleration.iter().zip(&self.inverse_mass).zip(self.radius.iter().zip(&self.damping))
        {
            hasher.vec3(*a);
            hasher.f32(*w);
            hasher.f32(*r);
            hasher.f32(*d);
        }
        for sleep in &self.sleep {
            hasher.f32(sleep.timer);
            hasher.u64(u64::from(sleep.island));
        }
        // Only spheres that roll have rotation to hash, so a world of point masses
        // hashes as it did before spheres could roll.
        let turning = self.inverse_inertia.iter().zip(&self.angular_velocity).zip(&self.orientation);
        for (i, ((&inverse_inertia, &w), &q)) in turning.enumerate() {
            if inverse_inertia != 0.0 {
                hasher.u64(i as u64);
                hasher.f32(inverse_inertia);
                hasher.vec3(w);
                hasher.vec3(q.xyz());
                hasher.f32(q.w);
            }
        }
    }

    /// Number of live particles.
    #[inline]
    #[must_use]
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True when there are no particles.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Adds a particle, or explains why the description is invalid.
    pub fn add(&mut self, desc: ParticleDesc) -> Result<ParticleId, PhysicsError> {
        let inverse_mass = desc.validate()?;
        let id = ParticleId(self.slots.len() as u32);
        self.slots.push(self.ids.len() as u32);
        self.ids.push(id);
        self.position.push(desc.position);
        // An immovable particle never moves, so it has no velocity for contacts to see.
        self.velocity.push(if inverse_mass > 0.0 { desc.velocity } else { Vec3::ZERO });
        self.acceleration.push(desc.acceleration);
        self.force.push(Vec3::ZERO);
        self.inverse_mass.push(inverse_mass);
        self.radius.push(desc.radius);
        self.inverse_inertia.push(0.0);
        self.rolling.push(false);
        self.angular_velocity.push(Vec3::ZERO);
        self.orientation.push(Quat::IDENTITY);
        self.damping.push(desc.damping);
        self.damping_per_step.push(damping_factor(desc.damping, self.damping_dt));
        self.sleep.push(Sleep::default());
        Ok(id)
    }

    /// Removes a particle; returns false if it was already gone. Other ids stay valid.
    pub fn remove(&mut self, id: ParticleId) -> bool {
        let Some(index) = self.index(id) else {
            return false;
        };
        let last = self.ids.len() - 1;
        self.position.swap_remove(index);
        self.velocity.swap_remove(index);
        self.acceleration.swap_remove(index);
        self.force.swap_remove(index);
        self.inverse_mass.swap_remove(index);
        self.radius.swap_remove(index);
        self.inverse_inertia.swap_remove(index);
        self.rolling.swap_remove(index);
        self.angular_velocity.swap_remove(index);
        self.orientation.swap_remove(index);
        self.damping.swap_remove(index);
        self.damping_per_step.swap_remove(index);
        self.sleep.swap_remove(index);
        self.ids.swap_remove(index);
        if index != last {
            let moved = self.ids[index];
            self.slots[moved.0 as usize] = index as u32;
        }
        self.slots[id.0 as usize] = DEAD;
        true
    }

    /// Removes every particle. Ids handed out before stay dead.
    pub fn clear(&mut self) {
        for id in self.ids.drain(..) {
            self.slots[id.0 as usize] = DEAD;
        }
        self.position.clear();
        self.velocity.clear();
        self.acceleration.clear();
        self.force.clear();
        self.inverse_mass.clear();
        self.radius.clear();
        self.inverse_inertia.clear();
        self.rolling.clear();
        self.angular_velocity.clear();
        self.orientation.clear();
        self.damping.clear();
        self.damping_per_step.clear();
        self.sleep.clear();
    }

    /// Positions (m), by dense index.
    #[inline]
    #[must_use]
    pub fn positions(&self) -> &[Vec3] {
        &self.position
    }

    /// Velocities (m/s), by dense index.
    #[inline]
    #[must_use]
    pub fn velocities(&self) -> &[Vec3] {
        &self.velocity
    }

    /// Constant accelerations (m/s²), by dense index.
    #[inline]
    #[must_use]
    pub fn accelerations(&self) -> &[Vec3] {
        &self.acceleration
    }

    /// Forces accumulated in the last step's last substep (N), by dense index.
    #[inline]
    #[must_use]
    pub fn forces(&self) -> &[Vec3] {
        &self.force
    }

    /// Inverse masses (1/kg; 0 is immovable), by dense index.
    #[inline]
    #[must_use]
    pub fn inverse_masses(&self) -> &[f32] {
        &self.inverse_mass
    }

    /// Collision radii (m), by dense index.
    #[inline]
    #[must_use]
    pub fn radii(&self) -> &[f32] {
        &self.radius
    }

    /// Angular velocities (rad/s), by dense index: zero for particles that do not roll.
    #[inline]
    #[must_use]
    pub fn angular_velocities(&self) -> &[Vec3] {
        &self.angular_velocity
    }

    /// Orientations (unit quaternions), by dense index: the identity for particles
    /// that do not roll.
    #[inline]
    #[must_use]
    pub fn orientations(&self) -> &[Quat] {
        &self.orientation
    }

    /// Inverse moments of inertia (1/(kg·m²)), by dense index: 0 for point masses.
    #[inline]
    #[must_use]
    pub fn inverse_inertias(&self) -> &[f32] {
        &self.inverse_inertia
    }

    /// The current dense index of a live particle.
    #[inline]
    #[must_use]
    pub fn index(&self, id: ParticleId) -> Option<usize> {
        match self.slots.get(id.0 as usize) {
            Some(&slot) if slot != DEAD => Some(slot as usize),
            _ => None,
        }
    }

    /// The id of the particle at a dense index, or `None` past the last one.
    #[inline]
    #[must_use]
    pub fn id(&self, index: usize) -> Option<ParticleId> {
        self.ids.get(index).copied()
    }

    /// Ids of all live particles, in dense order.
    #[inline]
    #[must_use]
    pub fn ids(&self) -> &[ParticleId] {
        &self.ids
    }

    /// Whether the particle at `index` is asleep: at rest with its island, not
    /// simulated until something touches or moves it (soft solver only).
    #[inline]
    #[must_use]
    pub fn is_asleep(&self, index: usize) -> bool {
        self.sleep[index].island != AWAKE
    }

    /// How many particles are asleep.
    #[must_use]
    pub fn asleep_count(&self) -> usize {
        self.sleep.iter().filter(|s| s.island != AWAKE).count()
    }
}

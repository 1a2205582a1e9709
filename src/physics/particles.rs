//! Particle storage: struct-of-arrays with stable ids.
//!
//! Hot loops (integration, force clearing) walk the arrays in order with zipped
//! iterators; everything that refers to a particle from outside (force generators,
//! links, the renderer's trails) holds a [`ParticleId`], which stays valid until that
//! particle is removed, even when other particles are removed and the arrays are
//! compacted.

use glam::{Quat, Vec3};

use super::error::{
    MAX_ACCELERATION, MAX_COORDINATE, MAX_RADIUS, MAX_SPEED, MIN_ROLLING_RADIUS, PhysicsError, Shown,
};
use super::hash::StateHasher;
pub use super::ids::ParticleId;

/// Everything needed to create a particle. Units: metres, seconds, kilograms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParticleDesc {
    /// Position (m).
    pub position: Vec3,
    /// Velocity (m/s).
    pub velocity: Vec3,
    /// Constant acceleration applied every step, usually gravity (m/s²).
    pub acceleration: Vec3,
    /// Mass (kg): finite and > 0. Ignored when `immovable`.
    pub mass: f32,
    /// An immovable particle has inverse mass 0: nothing moves it.
    pub immovable: bool,
    /// Fraction of velocity kept per second, in [0, 1]; 1 means no damping.
    pub damping: f32,
    /// Collision radius (m), >= 0.
    pub radius: f32,
}

impl Default for ParticleDesc {
    fn default() -> Self {
        Self {
            position: Vec3::ZERO,
            velocity: Vec3::ZERO,
            acceleration: Vec3::ZERO,
            mass: 1.0,
            immovable: false,
            damping: 1.0,
            radius: 0.2,
        }
    }
}

impl ParticleDesc {
    /// Checks the description, returning the inverse mass to store.
    fn validate(&self) -> Result<f32, PhysicsError> {
        let finite = |v: Vec3| v.is_finite();
        if !(finite(self.position) && finite(self.velocity) && finite(self.acceleration)) {
            return Err(PhysicsError::InvalidParticle(
                "position, velocity and acceleration must be finite".into(),
            ));
        }
        check_position(self.position)?;
        check_speed(self.velocity)?;
        check_acceleration(self.acceleration)?;
        let inverse_mass = if self.immovable { 0.0 } else { inverse_mass(self.mass)? };
        if !(0.0..=1.0).contains(&self.damping) {
            return Err(PhysicsError::InvalidParticle(format!(
                "damping must be in [0, 1], got {}",
                self.damping
            )));
        }
        if !(self.radius.is_finite() && (0.0..=MAX_RADIUS).contains(&self.radius)) {
            return Err(PhysicsError::InvalidParticle(format!(
                "radius = {} m is out of range; valid range: 0 to {MAX_RADIUS:e} m",
                self.radius.shown()
            )));
        }
        Ok(inverse_mass)
    }
}

/// A position within [`MAX_COORDINATE`] of the origin on every axis.
fn check_position(position: Vec3) -> Result<(), PhysicsError> {
    if position.abs().max_element() <= MAX_COORDINATE {
        return Ok(());
    }
    Err(PhysicsError::InvalidParticle(format!(
        "position {} m is out of range; valid range: each coordinate within ±{MAX_COORDINATE:e} m",
        position.shown()
    )))
}

/// A velocity no faster than [`MAX_SPEED`].
fn check_speed(velocity: Vec3) -> Result<(), PhysicsError> {
    if velocity.length() <= MAX_SPEED {
        return Ok(());
    }
    Err(PhysicsError::InvalidParticle(format!(
        "velocity {} m/s is out of range; valid range: a speed of at most {MAX_SPEED:e} m/s",
        velocity.shown()
    )))
}

/// An acceleration no larger than [`MAX_ACCELERATION`].
pub(crate) fn check_acceleration(acceleration: Vec3) -> Result<(), PhysicsError> {
    if acceleration.length() <= MAX_ACCELERATION {
        return Ok(());
    }
    Err(PhysicsError::InvalidParticle(format!(
        "acceleration {} m/s² is out of range; valid range: at most {MAX_ACCELERATION:e} m/s² in size",
        acceleration.shown()
    )))
}

/// Why a particle of radius `radius` (m) cannot roll, if it cannot: it needs a surface
/// to turn, and an inverse inertia that single precision holds.
fn cannot_roll(id: ParticleId, radius: f32) -> Option<String> {
    if radius <= 0.0 {
        return Some(format!(
            "particle {} has no radius, so it cannot roll (a point mass has no surface to turn)",
            id.0
        ));
    }
    (radius < MIN_ROLLING_RADIUS).then(|| {
        format!(
            "particle {} has radius {} m; a sphere that rolls needs a radius of at least {} m",
            id.0,
            radius.shown(),
            MIN_ROLLING_RADIUS.shown()
        )
    })
}

/// Lightest mass a particle may have (kg): a microgram. Much lighter and `1/m` times an
/// ordinary impulse overflows single precision.
pub const MIN_MASS: f32 = 1e-9;
/// Heaviest mass a particle may have (kg). Anything that should not move at all is
/// asked for with [`ParticleDesc::immovable`] instead.
pub const MAX_MASS: f32 = 1e12;

/// Converts a mass to an inverse mass. A mass outside `[MIN_MASS, MAX_MASS]` (zero,
/// negative, infinite, NaN, or so small its inverse overflows) is an error: an
/// immovable particle is asked for with [`ParticleDesc::immovable`].
pub fn inverse_mass(mass: f32) -> Result<f32, PhysicsError> {
    if (MIN_MASS..=MAX_MASS).contains(&mass) {
        Ok(1.0 / mass)
    } else {
        Err(PhysicsError::InvalidParticle(format!(
            "mass = {} kg is out of range; valid range: {} to {} kg",
            mass.shown(),
            MIN_MASS.shown(),
            MAX_MASS.shown()
        )))
    }
}

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
    rolling: Vec<bool>,
    /// Angular velocities (rad/s); zero for particles that do not roll.
    #[serde(default)]
    pub(crate) angular_velocity: Vec<Vec3>,
    /// Orientations (unit quaternions), turned by the angular velocity each step; what
    /// the renderer shows of a sphere's spin.
    #[serde(default)]
    pub(crate) orientation: Vec<Quat>,
    /// Fraction of velocity kept per second.
    damping: Vec<f32>,
    /// `damping.powf(damping_dt)`, cached so the step does not call `powf` per particle.
    pub(crate) damping_per_step: Vec<f32>,
    damping_dt: f32,
    /// Sleep state, per particle: see [`Sleep`].
    pub(crate) sleep: Vec<Sleep>,
    /// Energy taken out by drag, damped springs and damping since the world last read
    /// it (J); see [`Energy::dissipated`](super::energy::Energy::dissipated).
    pub(crate) dissipated: f64,
    /// Dense index -> id.
    ids: Vec<ParticleId>,
    /// Id -> dense index, or `DEAD`.
    slots: Vec<u32>,
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
        if !(self.damping_dt.is_finite() && self.damping_dt >= 0.0 && self.dissipated.is_finite()) {
            return Err(PhysicsError::InvalidParticle(
                "damping step or dissipated energy is not finite".into(),
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

    /// Whether the particle at `index` rolls: a movable solid sphere with a radius.
    #[inline]
    #[must_use]
    pub fn rolls(&self, index: usize) -> bool {
        self.inverse_inertia[index] != 0.0
    }

    /// Whether any particle rolls.
    #[must_use]
    pub fn any_rolling(&self) -> bool {
        self.inverse_inertia.iter().any(|&i| i != 0.0)
    }

    /// Makes a particle a solid sphere that rolls (`true`: it gets the moment of
    /// inertia `2/5 m r²`, and friction at its surface turns it), or a point mass that
    /// never turns (`false`, the paper's particles: its spin and orientation are
    /// reset). A sphere needs a radius > 0; an immovable particle is accepted and
    /// stays still (it has no inertia to turn).
    pub fn set_rolling(&mut self, id: ParticleId, rolls: bool) -> Result<(), PhysicsError> {
        let index = self.index(id).ok_or(PhysicsError::UnknownParticle(id))?;
        if let Some(reason) = cannot_roll(id, self.radius[index]).filter(|_| rolls) {
            return Err(PhysicsError::InvalidParticle(reason));
        }
        self.rolling[index] = rolls;
        self.refresh_inertia(index);
        self.disturb(index);
        Ok(())
    }

    /// Sets the angular velocity of a particle that rolls (rad/s, finite). A particle
    /// that does not roll keeps 0: a non-zero value is refused.
    pub fn set_angular_velocity(&mut self, id: ParticleId, spin: Vec3) -> Result<(), PhysicsError> {
        let index = self.index(id).ok_or(PhysicsError::UnknownParticle(id))?;
        if !spin.is_finite() {
            return Err(PhysicsError::InvalidParticle(format!(
                "angular velocity must be finite, got {spin}"
            )));
        }
        if self.inverse_inertia[index] == 0.0 && spin != Vec3::ZERO {
            return Err(PhysicsError::InvalidParticle(format!(
                "particle {} does not roll, so its angular velocity stays 0",
                id.0
            )));
        }
        self.angular_velocity[index] = spin;
        self.disturb(index);
        Ok(())
    }

    /// Recomputes the inverse inertia of the particle at `index` from its mass, radius
    /// and whether it rolls; a particle that stops rolling loses its spin.
    fn refresh_inertia(&mut self, index: usize) {
        let w = self.inverse_mass[index];
        let rolls = self.rolling[index] && w > 0.0 && self.radius[index] > 0.0;
        self.inverse_inertia[index] = if rolls { sphere_inverse_inertia(w, self.radius[index]) } else { 0.0 };
        if !rolls {
            self.angular_velocity[index] = Vec3::ZERO;
            self.orientation[index] = Quat::IDENTITY;
        }
    }

    /// Gives a store read from an old snapshot (made before spheres could roll) its
    /// rotation arrays: every particle a point mass at rest.
    pub(crate) fn fill_missing_rotation(&mut self) {
        let n = self.ids.len();
        if self.inverse_inertia.is_empty() && self.angular_velocity.is_empty() && self.orientation.is_empty()
        {
            self.inverse_inertia.resize(n, 0.0);
            self.angular_velocity.resize(n, Vec3::ZERO);
            self.orientation.resize(n, Quat::IDENTITY);
        }
        if self.rolling.is_empty() {
            self.rolling.extend(self.inverse_inertia.iter().map(|&i| i != 0.0));
        }
    }

    /// Turns every rolling, awake sphere by its angular velocity over `dt` (the exact
    /// rotation for a constant spin; the step's contacts change the spin, not this).
    ///
    /// The arithmetic is spelled out in scalars (see [`turned`]) so that the same step gives
    /// the same bits on every target: glam's `Quat` product is SIMD on x86-64 and scalar on
    /// wasm, and `sin`/`cos` come from different libraries there, and orientation is part
    /// of the state hash that the browser build is checked against.
    pub(crate) fn turn(&mut self, dt: f32) {
        // Each sphere turns on its own: threads change nothing but the time.
        if self.len() >= PARALLEL_TURN {
            use rayon::prelude::*;
            let spins =
                self.angular_velocity.par_chunks(TURN_CHUNK).zip(self.inverse_inertia.par_chunks(TURN_CHUNK));
            self.orientation
                .par_chunks_mut(TURN_CHUNK)
                .zip(spins)
                .for_each(|(q, (w, inertia))| turn_run(q, w, inertia, dt));
        } else {
            turn_run(&mut self.orientation, &self.angular_velocity, &self.inverse_inertia, dt);
        }
    }

    /// Moves a particle (a teleport: its velocity is kept). The position must be finite.
    pub fn set_position(&mut self, id: ParticleId, position: Vec3) -> Result<(), PhysicsError> {
        let index = self.index(id).ok_or(PhysicsError::UnknownParticle(id))?;
        if !position.is_finite() {
            return Err(PhysicsError::InvalidParticle(format!("position must be finite, got {position}")));
        }
        check_position(position)?;
        self.position[index] = position;
        self.disturb(index);
        Ok(())
    }

    /// Sets a particle's velocity (m/s), which must be finite. An immovable particle
    /// keeps velocity 0: it is refused.
    pub fn set_velocity(&mut self, id: ParticleId, velocity: Vec3) -> Result<(), PhysicsError> {
        let index = self.index(id).ok_or(PhysicsError::UnknownParticle(id))?;
        if !velocity.is_finite() {
            return Err(PhysicsError::InvalidParticle(format!("velocity must be finite, got {velocity}")));
        }
        check_speed(velocity)?;
        if self.inverse_mass[index] == 0.0 && velocity != Vec3::ZERO {
            return Err(PhysicsError::InvalidParticle(
                "velocity of an immovable particle must stay 0".into(),
            ));
        }
        self.velocity[index] = velocity;
        self.disturb(index);
        Ok(())
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

    /// Marks a sleeping particle as disturbed: its island wakes at the next step.
    fn disturb(&mut self, index: usize) {
        if self.sleep[index].island != AWAKE {
            // No position equals NaN, so the next step sees it as moved.
            self.sleep[index].rest = Vec3::NAN;
        }
    }

    /// Wakes every particle.
    pub fn wake_all(&mut self) {
        for sleep in &mut self.sleep {
            *sleep = Sleep::default();
        }
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

    /// Mass of the particle at `index` (kg); infinite for immovable ones.
    #[inline]
    #[must_use]
    pub fn mass(&self, index: usize) -> f32 {
        let inverse = self.inverse_mass[index];
        if inverse > 0.0 { 1.0 / inverse } else { f32::INFINITY }
    }

    /// Sets the mass of a movable particle (kg); see [`inverse_mass`] for what is
    /// accepted. An immovable particle is refused: giving it a mass would set it free,
    /// which is [`Particles::set_movable`]'s job.
    pub fn set_mass(&mut self, id: ParticleId, mass: f32) -> Result<(), PhysicsError> {
        let index = self.index(id).ok_or(PhysicsError::UnknownParticle(id))?;
        if self.inverse_mass[index] == 0.0 {
            return Err(PhysicsError::InvalidParticle(format!(
                "particle {} is immovable, so it has no mass to set (use set_movable to free it)",
                id.0
            )));
        }
        self.inverse_mass[index] = inverse_mass(mass)?;
        self.refresh_inertia(index);
        self.disturb(index);
        Ok(())
    }

    /// Makes a particle movable with the given mass, or (with `None`) immovable, which
    /// also stops it. The explicit call for what `set_mass` refuses.
    pub fn set_movable(&mut self, id: ParticleId, mass: Option<f32>) -> Result<(), PhysicsError> {
        let index = self.index(id).ok_or(PhysicsError::UnknownParticle(id))?;
        self.inverse_mass[index] = match mass {
            Some(mass) => inverse_mass(mass)?,
            None => {
                self.velocity[index] = Vec3::ZERO;
                0.0
            }
        };
        self.refresh_inertia(index);
        self.disturb(index);
        Ok(())
    }

    /// Damping of the particle at `index`: fraction of velocity kept per second.
    #[inline]
    #[must_use]
    pub fn damping(&self, index: usize) -> f32 {
        self.damping[index]
    }

    /// Sets a particle's damping, in [0, 1].
    pub fn set_damping(&mut self, id: ParticleId, damping: f32) -> Result<(), PhysicsError> {
        let index = self.index(id).ok_or(PhysicsError::UnknownParticle(id))?;
        if !(0.0..=1.0).contains(&damping) {
            return Err(PhysicsError::InvalidParticle(format!("damping must be in [0, 1], got {damping}")));
        }
        self.damping[index] = damping;
        self.damping_per_step[index] = damping_factor(damping, self.damping_dt);
        self.disturb(index);
        Ok(())
    }

    /// The factor velocities are multiplied by over one step of the last integrated dt.
    #[inline]
    #[must_use]
    pub fn damping_per_step(&self, index: usize) -> f32 {
        self.damping_per_step[index]
    }

    /// Recomputes `damping^dt` for every particle if `dt` changed since the last step.
    /// With a fixed time step this runs once, not once per step.
    pub(crate) fn prepare_damping(&mut self, dt: f32) {
        if dt != self.damping_dt {
            self.damping_dt = dt;
            for (factor, &damping) in self.damping_per_step.iter_mut().zip(&self.damping) {
                *factor = damping_factor(damping, dt);
            }
        }
    }

    /// Kinetic energy of the movable particles (J), in f64 and in index order: of
    /// their motion, `Σ ½ m v²`, plus of the rolling spheres' rotation (see
    /// [`Particles::rotational_energy`]).
    pub(crate) fn kinetic_energy(&self) -> f64 {
        let [moving, turning] = tree_sum(0..self.len(), &|range| self.kinetic_parts(range));
        0.5 * (moving + turning)
    }

    /// Twice the kinetic energy of motion and of spin of the particles `range` (J).
    pub(crate) fn kinetic_parts(&self, range: std::ops::Range<usize>) -> [f64; 2] {
        let bodies = self.velocity[range.clone()].iter().zip(&self.inverse_mass[range.clone()]);
        let moving = bodies
            .filter(|(_, w)| **w > 0.0)
            .map(|(v, &w)| f64::from(v.length_squared()) / f64::from(w))
            .sum();
        let spins = self.angular_velocity[range.clone()].iter().zip(&self.inverse_inertia[range]);
        let turning = spins
            .filter(|(_, i)| **i != 0.0)
            .map(|(w, &i)| f64::from(w.length_squared()) / f64::from(i))
            .sum();
        [moving, turning]
    }

    /// Kinetic energy of rotation (J), `Σ ½ I ω²` over the rolling spheres, in f64.
    pub(crate) fn rotational_energy(&self) -> f64 {
        let [_, turning] = tree_sum(0..self.len(), &|range| self.kinetic_parts(range));
        0.5 * turning
    }

    /// Adds to `dissipated` what damping took this step: each damped particle's end
    /// velocity is `d` times what it would have been, so it lost `½ m v² (1/d² - 1)`.
    pub(crate) fn count_damping_loss(&mut self) {
        let [lost] = tree_sum(0..self.len(), &|range: std::ops::Range<usize>| {
            let bodies = self.velocity[range.clone()].iter().zip(&self.inverse_mass[range.clone()]);
            let mut lost = 0.0;
            for ((v, &w), &d) in bodies.zip(&self.damping_per_step[range]) {
                if w > 0.0 && d < 1.0 && d > 0.0 {
                    let undamp = 1.0 / f64::from(d);
                    lost += 0.5 * f64::from(v.length_squared()) / f64::from(w) * (undamp * undamp - 1.0);
                }
            }
            [lost]
        });
        self.dissipated += lost;
    }

    /// Whether any movable particle is damped (damping below 1).
    pub(crate) fn any_damping(&self) -> bool {
        self.damping.iter().zip(&self.inverse_mass).any(|(&d, &w)| w > 0.0 && d < 1.0)
    }

    /// Zeroes every force accumulator.
    #[inline]
    pub fn clear_forces(&mut self) {
        self.force.fill(Vec3::ZERO);
    }

    /// [`Particles::integrate_velocities`], keeping copies on the way: each velocity
    /// before the kick into `before`, each spin into `spins` (when given) and each
    /// velocity after it into `after`. The same numbers as the copies and the kick made
    /// one after the other, in one sweep over the particles (on several threads when
    /// `parallel`) instead of four: on 2 threads, an 8,000-sphere pile's kicks took
    /// 0.066 ms a step this way against 0.076 ms, and 0.12 against 0.20 ms when the
    /// two cores were far apart.
    pub(crate) fn integrate_velocities_keeping(
        &mut self,
        h: f32,
        parallel: bool,
        before: &mut Vec<Vec3>,
        mut spins: Option<&mut Vec<Vec3>>,
        after: &mut Vec<Vec3>,
    ) {
        let n = self.len();
        for out in [Some(&mut *before), spins.as_deref_mut(), Some(&mut *after)].into_iter().flatten() {
            out.resize(n, Vec3::ZERO);
        }
        let (velocity, inputs, spin) = self.kick_parts();
        // The run of particles from `first`: their velocities and their parts of the copies.
        let sweep = |first: usize,
                     v: &mut [Vec3],
                     before: &mut [Vec3],
                     spins: Option<&mut [Vec3]>,
                     after: &mut [Vec3]| {
            before.copy_from_slice(v);
            if let Some(spins) = spins {
                spins.copy_from_slice(&spin[first..first + v.len()]);
            }
            inputs.kick(first, v, h);
            after.copy_from_slice(v);
        };
        if parallel {
            use rayon::prelude::*;
            let runs = velocity.par_chunks_mut(KICK_RUN).zip(before.par_chunks_mut(KICK_RUN));
            let runs = runs.zip(after.par_chunks_mut(KICK_RUN)).enumerate();
            match spins {
                Some(spins) => runs
                    .zip(spins.par_chunks_mut(KICK_RUN))
                    .for_each(|((k, ((v, b), a)), s)| sweep(k * KICK_RUN, v, b, Some(s), a)),
                None => runs.for_each(|(k, ((v, b), a))| sweep(k * KICK_RUN, v, b, None, a)),
            }
        } else {
            sweep(0, velocity, before, spins.map(Vec::as_mut_slice), after);
        }
    }

    /// The velocity half of a semi-implicit Euler (sub)step: `v = (v + (a + F/m) h)
    /// damping^h` for every movable, awake particle ([`kicked`]).
    /// [`Particles::prepare_damping`] must have been called with `h`; the position half
    /// is [`Particles::integrate_positions`].
    pub(crate) fn integrate_velocities(&mut self, h: f32, parallel: bool) {
        let (velocity, inputs, _) = self.kick_parts();
        if parallel {
            use rayon::prelude::*;
            velocity.par_chunks_mut(KICK_RUN).enumerate().for_each(|(k, v)| inputs.kick(k * KICK_RUN, v, h));
        } else {
            inputs.kick(0, velocity, h);
        }
    }

    /// The velocities, what the kick reads, and the spins, borrowed apart.
    fn kick_parts(&mut self) -> (&mut [Vec3], KickInputs<'_>, &[Vec3]) {
        let Self {
            velocity,
            acceleration,
            force,
            inverse_mass,
            damping_per_step,
            sleep,
            angular_velocity,
            ..
        } = self;
        let inputs = KickInputs { acceleration, force, inverse_mass, damping: damping_per_step, sleep };
        (velocity, inputs, angular_velocity)
    }

    /// The position half of a substep: `p += v h` for every movable particle, adding the
    /// move to `delta` too.
    pub(crate) fn integrate_positions(&mut self, h: f32, delta: &mut [Vec3], parallel: bool) {
        // Sleeping particles have zero velocity: moving them by it changes nothing.
        let drift = |((p, d), (&v, &inverse_mass)): ((&mut Vec3, &mut Vec3), (&Vec3, &f32))| {
            if inverse_mass > 0.0 {
                *p += v * h;
                *d += v * h;
            }
        };
        if parallel {
            use rayon::prelude::*;
            let inputs = self.velocity.par_iter().zip(&self.inverse_mass);
            self.position.par_iter_mut().zip(delta).zip(inputs).with_min_len(2048).for_each(drift);
        } else {
            self.position
                .iter_mut()
                .zip(delta)
                .zip(self.velocity.iter().zip(&self.inverse_mass))
                .for_each(drift);
        }
    }

    /// Acceleration the particle at `index` received this step: constant part plus
    /// accumulated force over mass (m/s²). Zero for immovable particles.
    #[inline]
    #[must_use]
    pub fn step_acceleration(&self, index: usize) -> Vec3 {
        let inverse_mass = self.inverse_mass[index];
        if inverse_mass > 0.0 {
            self.acceleration[index] + self.force[index] * inverse_mass
        } else {
            Vec3::ZERO
        }
    }
}

/// Semi-implicit Euler's kick, the one place it is written: the velocity `v` (m/s)
/// after `h` seconds of the acceleration `acceleration` (m/s², constant plus force over
/// mass), times the step's damping factor `damping^h`. Positions then move with it.
#[inline]
#[must_use]
pub(crate) fn kicked(v: Vec3, acceleration: Vec3, h: f32, damping_per_step: f32) -> Vec3 {
    (v + acceleration * h) * damping_per_step
}

/// Particles per task of the kick.
const KICK_RUN: usize = 2048;

/// What the velocity kick reads of every particle.
#[derive(Clone, Copy)]
struct KickInputs<'a> {
    acceleration: &'a [Vec3],
    force: &'a [Vec3],
    inverse_mass: &'a [f32],
    damping: &'a [f32],
    sleep: &'a [Sleep],
}

impl KickInputs<'_> {
    /// Kicks the velocities `v` of the particles from `first` on: [`kicked`] for every
    /// movable, awake one.
    fn kick(&self, first: usize, v: &mut [Vec3], h: f32) {
        let run = first..first + v.len();
        let bodies = self.inverse_mass[run.clone()]
            .iter()
            .zip(&self.damping[run.clone()])
            .zip(&self.sleep[run.clone()]);
        let inputs = self.acceleration[run.clone()].iter().zip(&self.force[run]).zip(bodies);
        for (v, ((&a, &f), ((&inverse_mass, &damp), sleep))) in v.iter_mut().zip(inputs) {
            if inverse_mass > 0.0 && sleep.island == AWAKE {
                *v = kicked(*v, a + f * inverse_mass, h, damp);
            }
        }
    }
}

/// Inverse moment of inertia of a solid sphere of inverse mass `w` and radius `r`:
/// `1 / (2/5 m r²)` (1/(kg·m²)).
#[inline]
#[must_use]
pub(crate) fn sphere_inverse_inertia(w: f32, r: f32) -> f32 {
    2.5 * w / (r * r)
}

/// Particles per leaf of [`tree_sum`]: fixed, so that the order of a sum, and its bits,
/// are the same on any number of threads.
const SUM_LEAF: usize = 2048;
/// Particles from which [`tree_sum`] splits across threads.
const PARALLEL_SUM: usize = 4096;

/// `K` sums over `0..len`: each leaf of [`SUM_LEAF`] indices summed by `f`, the leaves
/// added up a binary tree whose shape depends on `len` alone (split at the middle leaf),
/// its halves on two threads (`rayon::join`) once there are enough particles. So the
/// bits of the result are the same on any number of threads, and nothing is allocated.
pub(crate) fn tree_sum<const K: usize>(
    range: std::ops::Range<usize>,
    f: &(impl Fn(std::ops::Range<usize>) -> [f64; K] + Sync),
) -> [f64; K] {
    let leaves = (range.end - range.start).div_ceil(SUM_LEAF);
    if leaves <= 1 {
        return f(range);
    }
    let middle = range.start + leaves / 2 * SUM_LEAF;
    let (left, right) = (range.start..middle, middle..range.end);
    let (a, b) = if range.end - range.start >= PARALLEL_SUM {
        rayon::join(|| tree_sum(left, f), || tree_sum(right, f))
    } else {
        (tree_sum(left, f), tree_sum(right, f))
    };
    std::array::from_fn(|k| a[k] + b[k])
}

/// Particles from which [`Particles::turn`] runs on several threads.
const PARALLEL_TURN: usize = 4096;
/// Particles a task of [`Particles::turn`] takes at a time.
const TURN_CHUNK: usize = 2048;

/// `Sleep::island` of a particle that is awake.
pub(crate) const AWAKE: u32 = u32::MAX;

/// A particle's sleep state.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Sleep {
    /// How long the particle has been slower than the sleep speed (s).
    pub timer: f32,
    /// [`AWAKE`], or the label of the sleeping island it belongs to.
    pub island: u32,
    /// Where it fell asleep: moving it from outside wakes it. NaN (written `null` in a
    /// snapshot) once something outside moved it, so the next step wakes it.
    #[serde(with = "nan_as_null")]
    pub rest: Vec3,
}

impl Default for Sleep {
    fn default() -> Self {
        Self { timer: 0.0, island: AWAKE, rest: Vec3::ZERO }
    }
}

#[inline]
fn damping_factor(damping: f32, dt: f32) -> f32 {
    if dt == 0.0 { 1.0 } else { damping.powf(dt) }
}

/// A sleeping particle's rest position in a snapshot: JSON has no NaN, so the "moved
/// from outside" mark is written as `null` and read back as NaN.
mod nan_as_null {
    use glam::Vec3;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(rest: &Vec3, serializer: S) -> Result<S::Ok, S::Error> {
        if rest.is_nan() { None::<Vec3>.serialize(serializer) } else { Some(*rest).serialize(serializer) }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec3, D::Error> {
        Ok(Option::<Vec3>::deserialize(deserializer)?.unwrap_or(Vec3::NAN))
    }
}

/// Turns each rolling sphere of a run (orientations `q`, spins `w`, inverse inertias)
/// by its spin over `dt`: [`turned`], with the sines and cosines of four spheres at a
/// time in AVX's four `f64` lanes where the processor has it (the same operations on
/// each, so the same bits: its 22 divisions a sphere were most of the time).
fn turn_run(q: &mut [Quat], w: &[Vec3], inverse_inertia: &[f32], dt: f32) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: `turn_run_avx` needs AVX, and the processor has it (checked just above).
        unsafe { turn_run_avx(q, w, inverse_inertia, dt) };
        return;
    }
    for ((q, &w), &inverse_inertia) in q.iter_mut().zip(w).zip(inverse_inertia) {
        if inverse_inertia != 0.0 && w != Vec3::ZERO {
            *q = turned(*q, w * dt);
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn turn_run_avx(q: &mut [Quat], w: &[Vec3], inverse_inertia: &[f32], dt: f32) {
    // Up to four spheres waiting for their sines: index, turn, angle, reduced half angle.
    let mut waiting = [(0usize, Vec3::ZERO, 0.0f32, 0.0f64); 4];
    let mut count = 0;
    for (i, (&w, &inverse_inertia)) in w.iter().zip(inverse_inertia).enumerate() {
        if inverse_inertia == 0.0 || w == Vec3::ZERO {
            continue;
        }
        let turn = w * dt;
        let angle = turn.length();
        if angle == 0.0 {
            continue; // see `turned`
        }
        waiting[count] = (i, turn, angle, reduced_half_angle(angle));
        count += 1;
        if count == 4 {
            let (sin, cos) = half_angle_sin_cos_avx(waiting.map(|(.., x)| x));
            for (k, &(i, turn, angle, _)) in waiting.iter().enumerate() {
                q[i] = rotated(q[i], turn, angle, sin[k], cos[k]);
            }
            count = 0;
        }
    }
    for &(i, turn, angle, x) in &waiting[..count] {
        let (sin, cos) = sin_cos_series(x);
        q[i] = rotated(q[i], turn, angle, sin, cos);
    }
}

/// [`sin_cos_series`] of four reduced half angles at once, in AVX's `f64` lanes: each
/// lane the same operations in the same order, so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn half_angle_sin_cos_avx(x: [f64; 4]) -> ([f32; 4], [f32; 4]) {
    use std::arch::x86_64::*;
    // Four f64, lane 0 first, are what `__m256d` holds: a plain cast, no pointer.
    let x: __m256d = bytemuck::cast(x);
    let x2 = _mm256_mul_pd(x, x);
    let one = _mm256_set1_pd(1.0);
    let (mut sin, mut cos) = (one, one);
    for k in (1..=11).rev() {
        let k = f64::from(k);
        let (sin_divisor, cos_divisor) = ((2.0 * k) * (2.0 * k + 1.0), (2.0 * k - 1.0) * (2.0 * k));
        sin = _mm256_sub_pd(one, _mm256_mul_pd(_mm256_div_pd(x2, _mm256_set1_pd(sin_divisor)), sin));
        cos = _mm256_sub_pd(one, _mm256_mul_pd(_mm256_div_pd(x2, _mm256_set1_pd(cos_divisor)), cos));
    }
    let (sin_out, cos_out): ([f64; 4], [f64; 4]) =
        (bytemuck::cast(_mm256_mul_pd(x, sin)), bytemuck::cast(cos));
    (sin_out.map(|s| s as f32), cos_out.map(|c| c as f32))
}

/// `q` turned by the rotation vector `turn` (axis × angle, rad), renormalised: the
/// product (cos ½θ, sin ½θ · axis) · q written out component by component in a fixed
/// order, with [`half_angle_sin_cos`] in place of the platform's `sin_cos`, so every
/// target rounds it alike.
fn turned(q: Quat, turn: Vec3) -> Quat {
    let angle = turn.length();
    if angle == 0.0 {
        // A spin so slow that its step's turn squares to nothing (|ω dt| < 1e-19 rad).
        return q;
    }
    let (sin, cos) = half_angle_sin_cos(angle);
    rotated(q, turn, angle, sin, cos)
}

/// The product of [`turned`], given the sine and cosine of half of `angle = |turn|`.
#[inline(always)]
fn rotated(q: Quat, turn: Vec3, angle: f32, sin: f32, cos: f32) -> Quat {
    let s = sin / angle;
    let (ax, ay, az, aw) = (turn.x * s, turn.y * s, turn.z * s, cos);
    let (bx, by, bz, bw) = (q.x, q.y, q.z, q.w);
    let x = aw * bx + ax * bw + (ay * bz - az * by);
    let y = aw * by + ay * bw + (az * bx - ax * bz);
    let z = aw * bz + az * bw + (ax * by - ay * bx);
    let w = aw * bw - (ax * bx + ay * by + az * bz);
    let length = (((x * x + y * y) + z * z) + w * w).sqrt();
    Quat::from_xyzw(x / length, y / length, z / length, w / length)
}

/// sin and cos of half of `angle` (rad), from a reduction to [−π, π] and Taylor
/// series in f64 (terms to the 22nd/23rd power: under 1e-10 at π, far below f32's
/// resolution). Only IEEE basic operations, so the bits are the same everywhere.
fn half_angle_sin_cos(angle: f32) -> (f32, f32) {
    sin_cos_series(reduced_half_angle(angle))
}

/// Half of `angle`, brought into [−π, π] (f64).
#[inline(always)]
fn reduced_half_angle(angle: f32) -> f64 {
    let tau = std::f64::consts::TAU;
    let half = f64::from(angle) * 0.5;
    half - tau * (half / tau).round()
}

/// sin and cos of `x` in [−π, π], from their Taylor series by Horner's rule.
#[inline(always)]
fn sin_cos_series(x: f64) -> (f32, f32) {
    let x2 = x * x;
    let (mut sin, mut cos) = (1.0f64, 1.0f64);
    // Horner from the highest term down: sin x = x(1 − x²/(2·3)(1 − x²/(4·5)(…))).
    for k in (1..=11).rev() {
        let k = f64::from(k);
        sin = 1.0 - x2 / ((2.0 * k) * (2.0 * k + 1.0)) * sin;
        cos = 1.0 - x2 / ((2.0 * k - 1.0) * (2.0 * k)) * cos;
    }
    ((x * sin) as f32, cos as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    /// The kick that keeps copies gives, bit for bit, the velocities of the plain kick
    /// and copies of the velocities before and after it and of the spins, on one thread
    /// and on several, for a mix of movable, immovable, damped and sleeping particles
    /// with forces on them, in more particles than one task takes.
    #[test]
    fn the_kick_that_keeps_copies_is_the_kick_and_the_copies() {
        let mut particles = Particles::new();
        for i in 0..5000 {
            let f = i as f32;
            let desc = ParticleDesc {
                velocity: Vec3::new((f * 0.37).sin(), (f * 0.11).cos(), -f * 1e-3),
                acceleration: Vec3::new(0.0, -9.81, 0.1 * (f * 0.7).sin()),
                mass: 1.0 + (i % 7) as f32,
                immovable: i % 17 == 3,
                damping: if i % 5 == 0 { 0.9 } else { 1.0 },
                radius: 0.5,
                ..ParticleDesc::default()
            };
            particles.add(desc).expect("a valid particle");
            particles.force[i] = Vec3::new(f.cos(), 0.5, f * 1e-2);
            particles.angular_velocity[i] = Vec3::new(f * 1e-3, -1.0, (f * 0.3).cos());
        }
        particles.sleep[11].island = 0;
        let h = 1.0 / 240.0;
        particles.prepare_damping(h);
        let mut expected = particles.clone();
        let start = expected.velocity.clone();
        expected.integrate_velocities(h, false);
        let bits = |v: &[Vec3]| v.iter().flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        for parallel in [false, true] {
            for with_spins in [false, true] {
                let mut p = particles.clone();
                let (mut before, mut spins, mut after) =
                    (Vec::new(), vec![Vec3::NAN; 3], vec![Vec3::NAN; 9000]);
                let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
                pool.install(|| {
                    p.integrate_velocities_keeping(
                        h,
                        parallel,
                        &mut before,
                        with_spins.then_some(&mut spins),
                        &mut after,
                    )
                });
                assert_eq!(bits(&p.velocity), bits(&expected.velocity), "parallel {parallel}");
                assert_eq!(bits(&before), bits(&start));
                assert_eq!(bits(&after), bits(&expected.velocity));
                if with_spins {
                    assert_eq!(bits(&spins), bits(&particles.angular_velocity));
                }
            }
        }
        assert_ne!(bits(&expected.velocity), bits(&start), "the kick changed the velocities");
    }

    /// A run of spheres turned four at a time (AVX's f64 lanes, where the processor
    /// has them) comes out bit for bit as each turned alone, including the spheres
    /// left over after the last four and those that do not turn.
    #[test]
    fn turning_a_run_equals_turning_each_alone() {
        let n = 1003;
        let q0: Vec<Quat> = (0..n)
            .map(|i| Quat::from_xyzw(0.3 + i as f32 * 1e-3, -0.5, 0.1, 0.8 - i as f32 * 2e-4).normalize())
            .collect();
        let w: Vec<Vec3> = (0..n)
            .map(|i| {
                let f = i as f32;
                if i % 11 == 0 {
                    Vec3::ZERO
                } else {
                    Vec3::new((f * 0.37).sin(), (f * 0.11).cos(), (f * 0.05).sin()) * (1e-6 + f * f * 0.01)
                }
            })
            .collect();
        let inertia: Vec<f32> = (0..n).map(|i| if i % 13 == 5 { 0.0 } else { 2.5 }).collect();
        let dt = 1.0 / 60.0;
        let mut q = q0.clone();
        turn_run(&mut q, &w, &inertia, dt);
        for i in 0..n {
            let expected =
                if inertia[i] != 0.0 && w[i] != Vec3::ZERO { turned(q0[i], w[i] * dt) } else { q0[i] };
            assert_eq!(
                q[i].to_array().map(f32::to_bits),
                expected.to_array().map(f32::to_bits),
                "sphere {i}"
            );
        }
        assert!((0..n).filter(|&i| q[i] != q0[i]).count() > n * 3 / 4, "most spheres turned");
    }

    /// The portable sin/cos and quaternion turn agree with the platform's (std and
    /// glam) to f32 resolution, over small, large and wrapped-around angles.
    #[test]
    fn the_portable_turn_agrees_with_glam() {
        let q = Quat::from_xyzw(0.3, -0.5, 0.1, 0.8).normalize();
        // A turn too small to square (the spin of a sphere all but at rest) leaves q.
        assert_eq!(turned(q, Vec3::new(1e-25, 0.0, 0.0)), q);
        assert!(turned(q, Vec3::new(1e-18, 1e-30, 0.0)).is_finite());
        for i in 0..2000 {
            let angle = (i as f32) * 0.013 - 5.0 + if i % 7 == 0 { 1000.0 } else { 0.0 };
            let (sin, cos) = half_angle_sin_cos(angle);
            let (s, c) = (f64::from(angle) * 0.5).sin_cos();
            assert!((f64::from(sin) - s).abs() < 2e-7 && (f64::from(cos) - c).abs() < 2e-7, "{angle}");
            if angle != 0.0 {
                let turn = Vec3::new(0.6, 0.0, -0.8) * angle;
                let ours = turned(q, turn);
                let glam = (Quat::from_scaled_axis(turn) * q).normalize();
                let apart = (Vec4::from(ours) - Vec4::from(glam))
                    .length()
                    .min((Vec4::from(ours) + Vec4::from(glam)).length());
                assert!(apart < 1e-5, "{angle}: {ours} vs {glam}");
            }
        }
    }
}

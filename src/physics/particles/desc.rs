//! What a particle is made from, the checks every value passes on its way in (a
//! description when the particle is added, a setter's value when it changes), and the
//! stored values that follow from them (inverse mass and inertia, damping per step).

use glam::Vec3;

use crate::physics::error::{
    MAX_ACCELERATION, MAX_COORDINATE, MAX_RADIUS, MAX_SPEED, MIN_ROLLING_RADIUS, PhysicsError, Shown,
};
use crate::physics::ids::ParticleId;

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
    pub(super) fn validate(&self) -> Result<f32, PhysicsError> {
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
pub(super) fn check_position(position: Vec3) -> Result<(), PhysicsError> {
    if position.abs().max_element() <= MAX_COORDINATE {
        return Ok(());
    }
    Err(PhysicsError::InvalidParticle(format!(
        "position {} m is out of range; valid range: each coordinate within ±{MAX_COORDINATE:e} m",
        position.shown()
    )))
}

/// A velocity no faster than [`MAX_SPEED`].
pub(super) fn check_speed(velocity: Vec3) -> Result<(), PhysicsError> {
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
pub(super) fn cannot_roll(id: ParticleId, radius: f32) -> Option<String> {
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

/// Inverse moment of inertia of a solid sphere of inverse mass `w` and radius `r`:
/// `1 / (2/5 m r²)` (1/(kg·m²)).
#[inline]
#[must_use]
pub(crate) fn sphere_inverse_inertia(w: f32, r: f32) -> f32 {
    2.5 * w / (r * r)
}

/// The factor a velocity is multiplied by over a step of `dt` seconds for `damping`,
/// the fraction kept per second: `damping^dt` (1 for a zero step).
#[inline]
pub(super) fn damping_factor(damping: f32, dt: f32) -> f32 {
    if dt == 0.0 { 1.0 } else { damping.powf(dt) }
}

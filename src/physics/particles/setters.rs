//! The one door that changes a particle's state from outside the step: each setter
//! checks its value (the error names the field and its valid range) and wakes the
//! particle if it sleeps.

use glam::{Quat, Vec3};

use super::desc::{
    cannot_roll, check_position, check_speed, damping_factor, inverse_mass, sphere_inverse_inertia,
};
use super::sleep::{AWAKE, Sleep};
use super::store::Particles;
use crate::physics::error::PhysicsError;
use crate::physics::ids::ParticleId;

impl Particles {
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
}

//! Fields: forces that act on a list of particles (gravity, drag) or on one body by
//! where it is (buoyancy).

use glam::Vec3;

use super::generator::ForceGenerator;
use crate::physics::error::{
    ACCELERATION, COEFFICIENT, LENGTH, MAX_ACCELERATION, MAX_COORDINATE, PhysicsError, acceleration, check,
    coefficient, length, non_negative,
};
use crate::physics::ids::ParticleId;
use crate::physics::particles::Particles;

/// Uniform gravity as a force, `F = m g`, on a list of particles.
///
/// Scenes usually put gravity in each particle's constant acceleration instead (as the
/// paper does); this generator exists for particles that need their own field.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Gravity {
    /// Acceleration of the field (m/s²), e.g. `(0, -9.81, 0)`.
    pub gravity: Vec3,
    /// Particles it acts on.
    pub targets: Vec<ParticleId>,
}

impl ForceGenerator for Gravity {
    fn validate(&self) -> Result<(), PhysicsError> {
        check(acceleration(self.gravity), "gravity", self.gravity, ACCELERATION)
    }

    fn apply(&mut self, particles: &mut Particles, _dt: f32) {
        for &id in &self.targets {
            if let Some(i) = particles.index(id) {
                let inverse_mass = particles.inverse_mass[i];
                if inverse_mass > 0.0 {
                    particles.force[i] += self.gravity / inverse_mass;
                }
            }
        }
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.targets.contains(&id)
    }

    fn release(&mut self, id: ParticleId) -> bool {
        self.targets.retain(|&target| target != id);
        self.targets.is_empty()
    }

    fn name(&self) -> &'static str {
        "gravity"
    }

    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        let w = particles.inverse_mass[i];
        (w > 0.0 && self.targets.contains(&particles.ids()[i])).then(|| self.gravity / w)
    }

    fn potential_energy(&self, particles: &Particles) -> f32 {
        self.targets
            .iter()
            .filter_map(|&id| particles.index(id))
            .filter(|&i| particles.inverse_mass[i] > 0.0)
            .map(|i| -self.gravity.dot(particles.position[i]) / particles.inverse_mass[i])
            .sum()
    }
}

/// Simplified aerodynamic drag, `F = -v̂ (k1 |v| + k2 |v|²)`.
///
/// Applied explicitly, drag overshoots (reverses the velocity, then grows without
/// bound) once `k1·dt/m > 2` or `k2·|v|·dt/m > 2`. So the generator solves the step's
/// velocity update itself, with the particle's other accelerations `g` (its constant
/// one and the forces registered before this generator) held over the step, and
/// applies the constant force that lands the integrator there:
/// - linear drag only (`k2 = 0`): the exact solution of `v' = g - (k1/m) v`,
///   `v(t) = v∞ + (v0 - v∞) e^{-k1 t/m}` with `v∞ = m g / k1`;
/// - with quadratic drag: backward Euler, `v1 = v0 + dt (g - (k1 + k2|v1|) v1 / m)`,
///   solved in closed form (a quadratic in `|v1|`).
///
/// Both are stable for any `k1, k2 >= 0`, never reverse the velocity, and reach the
/// exact terminal velocity (`k1 v + k2 v² = m g`). Register drag after the particle's
/// other force generators.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Drag {
    /// Linear coefficient (N·s/m).
    pub k1: f32,
    /// Quadratic coefficient (N·s²/m²).
    pub k2: f32,
    /// Particles it acts on.
    pub targets: Vec<ParticleId>,
}

impl Drag {
    /// The drag force on a particle moving at `velocity` (N), at this instant.
    #[inline]
    #[must_use]
    pub fn force(&self, velocity: Vec3) -> Vec3 {
        let speed = velocity.length();
        // -v̂ (k1|v| + k2|v|²) = -v (k1 + k2|v|); zero velocity gives zero force.
        -velocity * (self.k1 + self.k2 * speed)
    }

    /// Velocity after `dt` seconds (m/s) of a particle of inverse mass `inverse_mass`
    /// starting at `velocity` under drag and a constant other acceleration `other`.
    #[must_use]
    pub fn velocity_after(&self, velocity: Vec3, other: Vec3, inverse_mass: f32, dt: f32) -> Vec3 {
        let (v0, g, t) = (velocity.as_dvec3(), other.as_dvec3(), f64::from(dt));
        let (a, b) = (f64::from(self.k1 * inverse_mass), f64::from(self.k2 * inverse_mass));
        if b == 0.0 {
            if a == 0.0 {
                return (v0 + g * t).as_vec3();
            }
            let terminal = g / a;
            return (terminal + (v0 - terminal) * (-a * t).exp()).as_vec3();
        }
        // (1 + a t + b t s) v1 = v0 + g t, with s = |v1|: v1 points along u = v0 + g t and
        // b t s² + (1 + a t) s - |u| = 0.
        let u = v0 + g * t;
        let (c1, c2, length) = (1.0 + a * t, b * t, u.length());
        // The positive root, written so it does not cancel when c2 is small.
        let s = 2.0 * length / (c1 + (c1 * c1 + 4.0 * c2 * length).sqrt());
        if length > 0.0 { (u * (s / length)).as_vec3() } else { Vec3::ZERO }
    }
}

impl ForceGenerator for Drag {
    fn validate(&self) -> Result<(), PhysicsError> {
        check(coefficient(self.k1), "drag k1", self.k1, COEFFICIENT)?;
        check(coefficient(self.k2), "drag k2", self.k2, COEFFICIENT)
    }

    fn apply(&mut self, particles: &mut Particles, dt: f32) {
        for &id in &self.targets {
            let Some(i) = particles.index(id) else { continue };
            let (v, w) = (particles.velocity[i], particles.inverse_mass[i]);
            if !(w > 0.0 && dt > 0.0) {
                particles.force[i] += self.force(v);
                continue;
            }
            let other = particles.acceleration[i] + particles.force[i] * w;
            let landed = self.velocity_after(v, other, w, dt);
            // The integrator adds (a + F/m) dt: choose the drag force that makes it `landed`.
            let drag = ((landed - v) / dt - other) / w;
            particles.force[i] += drag;
            // Its share of the step's change of kinetic energy, F·(v + v')/2 dt, is lost.
            particles.dissipated -= f64::from(drag.dot(v + landed) * 0.5 * dt);
        }
    }

    /// The force `-v (k1 + k2 |v|)` at the current velocity, with its power booked.
    fn apply_instantaneous(&mut self, particles: &mut Particles, dt: f32) {
        for &id in &self.targets {
            let Some(i) = particles.index(id) else { continue };
            let v = particles.velocity[i];
            let drag = self.force(v);
            particles.force[i] += drag;
            if particles.inverse_mass[i] > 0.0 {
                particles.dissipated -= f64::from(drag.dot(v)) * f64::from(dt);
            }
        }
    }

    fn name(&self) -> &'static str {
        "drag"
    }

    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        self.targets.contains(&particles.ids()[i]).then(|| self.force(particles.velocity[i]))
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.targets.contains(&id)
    }

    fn release(&mut self, id: ParticleId) -> bool {
        self.targets.retain(|&target| target != id);
        self.targets.is_empty()
    }
}

/// Buoyancy of a body treated as a vertical column of height `2 * half_height` in a
/// liquid whose surface is the plane `y = surface`.
///
/// Submerged fraction `f = clamp((surface + half_height - y) / (2 half_height), 0, 1)`,
/// force `density * volume * g * f` upwards (Archimedes). This corrects the sign of the
/// partial-submersion term in the paper and in Cyclone.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Buoyancy {
    /// The floating particle.
    pub target: ParticleId,
    /// Height of the liquid surface (m).
    pub surface: f32,
    /// Half the body's height (m); the body is fully submerged at `y <= surface - half_height`.
    pub half_height: f32,
    /// Body volume (m³).
    pub volume: f32,
    /// Liquid density (kg/m³); water is 1000.
    pub density: f32,
    /// Gravitational acceleration (m/s², positive).
    pub g: f32,
}

impl Buoyancy {
    /// Fraction of the body below the surface when its centre is at height `y`.
    #[inline]
    #[must_use]
    pub fn submerged_fraction(&self, y: f32) -> f32 {
        if self.half_height <= 0.0 {
            return if y <= self.surface { 1.0 } else { 0.0 };
        }
        ((self.surface + self.half_height - y) / (2.0 * self.half_height)).clamp(0.0, 1.0)
    }

    /// Upward force (N) on the body when its centre is at height `y`.
    #[inline]
    #[must_use]
    pub fn force(&self, y: f32) -> Vec3 {
        Vec3::Y * (self.density * self.volume * self.g * self.submerged_fraction(y))
    }
}

impl ForceGenerator for Buoyancy {
    fn validate(&self) -> Result<(), PhysicsError> {
        let height = self.surface.is_finite() && self.surface.abs() <= MAX_COORDINATE;
        check(height, "buoyancy surface", self.surface, "a height within ±1e9 m")?;
        check(length(self.half_height), "buoyancy half_height", self.half_height, LENGTH)?;
        check(coefficient(self.volume), "buoyancy volume", self.volume, COEFFICIENT)?;
        check(coefficient(self.density), "buoyancy density", self.density, COEFFICIENT)?;
        let g = non_negative(self.g) && self.g <= MAX_ACCELERATION;
        check(g, "buoyancy g", self.g, "0 to 1e6 m/s²")
    }

    fn apply(&mut self, particles: &mut Particles, _dt: f32) {
        if let Some(i) = particles.index(self.target) {
            particles.force[i] += self.force(particles.position[i].y);
        }
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.target == id
    }

    fn name(&self) -> &'static str {
        "buoyancy"
    }

    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        (particles.ids()[i] == self.target).then(|| self.force(particles.position[i].y))
    }

    /// Work done against buoyancy to push the body down from the surface (J):
    /// `ρ V g s u²` while partly submerged (`u` the submerged fraction), growing
    /// linearly once fully under. Zero when clear of the liquid.
    fn potential_energy(&self, particles: &Particles) -> f32 {
        let Some(i) = particles.index(self.target) else { return 0.0 };
        // A fixed particle is held where it is: the liquid does no work on it.
        if particles.inverse_mass[i] == 0.0 {
            return 0.0;
        }
        let weight = self.density * self.volume * self.g;
        let s = self.half_height;
        if s <= 0.0 {
            return (weight * (self.surface - particles.position[i].y)).max(0.0);
        }
        let u = (self.surface + s - particles.position[i].y) / (2.0 * s);
        if u <= 0.0 {
            0.0
        } else if u <= 1.0 {
            weight * s * u * u
        } else {
            weight * s * (2.0 * u - 1.0)
        }
    }
}

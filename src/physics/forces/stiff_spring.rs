//! A stiff spring solved in closed form, stable at any stiffness.
//!
//! The paper leaves stiff springs out because an explicit spring force overshoots once
//! `ω·dt` grows past 2 and the motion explodes. Here the particle's motion about the
//! anchor is solved exactly as damped harmonic motion over the step,
//! `x'' + 2ζω x' + ω² x = a`, with the particle's other accelerations `a` held constant
//! over the step, and the generator applies exactly the force that makes the
//! integrator land on that solution.
//!
//! The step is the generator's, whatever the integrator: it adds no force at the
//! integrator's evaluations, and the integrator takes its closed-form step for the
//! particle instead ([`ForceGenerator::closed_step`]): the particle moves along the
//! exact solution with its average velocity over the step and ends it with the exact
//! velocity. So its energy is kept (undamped) or booked (damped, the exact loss of the
//! oscillator) under every integrator. An earlier form chose the force that landed
//! semi-implicit Euler on the closed form and remembered the exact velocity between
//! steps; under Verlet and RK4, which evaluate at trial states, that memory was
//! overwritten at each evaluation and the spring lost most of its energy unbooked.

use glam::{DVec3, Vec3};

use super::generator::{ClosedStep, ForceGenerator};
use crate::physics::error::{
    NON_NEGATIVE, POINT, PhysicsError, check, coefficient, non_negative, point, positive,
};
use crate::physics::ids::ParticleId;
use crate::physics::links::{LinkEnd, LinkKind, LinkSpec};
use crate::physics::particles::Particles;

/// An anchored spring of zero rest length whose motion is integrated analytically.
/// Register it after the particle's other force generators: their forces this step are
/// part of the constant acceleration it solves with.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct StiffSpring {
    /// The particle on the spring.
    pub target: ParticleId,
    /// The fixed end, where the spring is at rest (m).
    pub anchor: Vec3,
    /// Spring constant (N/m); any positive value.
    pub k: f32,
    /// Damping ratio ζ (dimensionless): 0 undamped, 1 critically damped.
    pub damping_ratio: f32,
}

impl StiffSpring {
    /// A stiff spring from `target` to `anchor`.
    #[must_use]
    pub fn new(target: ParticleId, anchor: Vec3, k: f32, damping_ratio: f32) -> Self {
        Self { target, anchor, k, damping_ratio }
    }
}

/// Exact solution of `y'' + 2ζω y' + ω² y = 0` after `t`: returns `(y, y')`.
#[must_use]
pub fn damped_oscillator(y0: DVec3, v0: DVec3, omega: f64, zeta: f64, t: f64) -> (DVec3, DVec3) {
    if zeta < 1.0 {
        let omega_d = omega * (1.0 - zeta * zeta).sqrt();
        let decay = (-zeta * omega * t).exp();
        let (sin, cos) = (omega_d * t).sin_cos();
        let y = decay * (y0 * cos + (v0 + zeta * omega * y0) * (sin / omega_d));
        let v = decay * (v0 * cos - (zeta * omega * v0 + omega * omega * y0) * (sin / omega_d));
        (y, v)
    } else if zeta == 1.0 {
        let decay = (-omega * t).exp();
        let c = v0 + omega * y0;
        (decay * (y0 + c * t), decay * (v0 - omega * t * c))
    } else {
        let root = (zeta * zeta - 1.0).sqrt();
        let r1 = -omega * (zeta - root);
        let r2 = -omega * (zeta + root);
        let a = (v0 - r2 * y0) / (r1 - r2);
        let b = y0 - a;
        let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
        (a * e1 + b * e2, a * r1 * e1 + b * r2 * e2)
    }
}

impl ForceGenerator for StiffSpring {
    fn validate(&self) -> Result<(), PhysicsError> {
        check(positive(self.k) && coefficient(self.k), "stiff spring k", self.k, "more than 0, at most 1e9")?;
        check(
            non_negative(self.damping_ratio),
            "stiff spring damping_ratio",
            self.damping_ratio,
            NON_NEGATIVE,
        )?;
        check(point(self.anchor), "stiff spring anchor", self.anchor, POINT)
    }

    /// The spring and its damper as forces, `-k x - c v`, for a caller that applies the
    /// generators itself; a world's step takes [`ForceGenerator::closed_step`] instead.
    fn apply(&mut self, particles: &mut Particles, _dt: f32) {
        if let Some(i) = particles.index(self.target)
            && let Some(force) = self.force_on(particles, i)
        {
            particles.force[i] += force;
        }
    }

    fn moves_in_closed_form(&self) -> bool {
        true
    }

    fn closed_step(&self, particles: &Particles, other: &[Vec3], h: f32) -> Option<ClosedStep> {
        let i = particles.index(self.target)?;
        let inverse_mass = particles.inverse_mass[i];
        if inverse_mass <= 0.0 || !(self.k > 0.0 && self.k.is_finite()) || h <= 0.0 {
            return None;
        }
        let mass = 1.0 / f64::from(inverse_mass);
        let omega = (f64::from(self.k) / mass).sqrt();
        let zeta = f64::from(self.damping_ratio.max(0.0));
        // Other accelerations, held constant over the step, shift the rest point.
        let rest = self.anchor.as_dvec3() + other[i].as_dvec3() / (omega * omega);
        let (position, velocity) = (particles.position[i].as_dvec3(), particles.velocity[i].as_dvec3());
        let y0 = position - rest;
        let (y1, v1) = damped_oscillator(y0, velocity, omega, zeta, f64::from(h));
        // The oscillator's energy the damping took this step (exact; 0 when undamped).
        let energy =
            |y: DVec3, v: DVec3| 0.5 * mass * (v.length_squared() + omega * omega * y.length_squared());
        let dissipated = if zeta > 0.0 { energy(y0, velocity) - energy(y1, v1) } else { 0.0 };
        let moving = ((rest + y1 - position) / f64::from(h)).as_vec3();
        Some(ClosedStep { index: i, moving, end: v1.as_vec3(), dissipated })
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.target == id
    }

    fn name(&self) -> &'static str {
        "stiff spring"
    }

    /// The spring and its damper as the physics defines them, `-k x - c v` with
    /// `c = 2 ζ √(k m)`; the step itself lands on the closed form instead.
    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        let w = particles.inverse_mass[i];
        if particles.ids()[i] != self.target || w <= 0.0 {
            return None;
        }
        let c = 2.0 * self.damping_ratio * (self.k / w).sqrt();
        Some(-(particles.position[i] - self.anchor) * self.k - particles.velocity[i] * c)
    }

    fn potential_energy(&self, particles: &Particles) -> f32 {
        particles
            .index(self.target)
            .map_or(0.0, |i| 0.5 * self.k * (particles.position[i] - self.anchor).length_squared())
    }

    fn link(&self) -> Option<LinkSpec> {
        Some(LinkSpec {
            kind: LinkKind::StiffSpring,
            a: self.target,
            b: LinkEnd::Anchor(self.anchor),
            rest: 0.0,
        })
    }

    fn tension(&self, particles: &Particles) -> f32 {
        particles.index(self.target).map_or(0.0, |i| self.k * (particles.position[i] - self.anchor).length())
    }
}

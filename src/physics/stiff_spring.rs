//! A stiff spring solved in closed form, stable at any stiffness.
//!
//! The paper leaves stiff springs out because an explicit spring force overshoots once
//! `ω·dt` grows past 2 and the motion explodes. Here the particle's motion about the
//! anchor is solved exactly as damped harmonic motion over the step,
//! `x'' + 2ζω x' + ω² x = a`, with the particle's other accelerations `a` held constant
//! over the step, and the generator applies exactly the force that makes the
//! integrator land on that solution.
//!
//! The integrator's stored velocity is then the step's average velocity, not the exact
//! end velocity; feeding the average back in is only marginally stable, so the
//! generator remembers the exact velocity and uses it when nothing else has moved the
//! particle since. A consequence: the particle's reported velocity (and so the world's
//! kinetic energy) is the step's average, which at ω·dt near 1 or more differs visibly
//! from the instantaneous velocity; positions follow the closed form exactly.

use glam::{DVec3, Vec3};

use super::forces::ForceGenerator;
use super::links::{LinkEnd, LinkKind, LinkSpec};
use super::particles::{ParticleId, Particles};
use super::{NON_NEGATIVE, POSITIVE, PhysicsError, check, non_negative, positive};

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
    /// Position and stored velocity we expect to find next step, with the exact velocity.
    expected: Option<(Vec3, Vec3, Vec3)>,
}

impl StiffSpring {
    /// A stiff spring from `target` to `anchor`.
    #[must_use]
    pub fn new(target: ParticleId, anchor: Vec3, k: f32, damping_ratio: f32) -> Self {
        Self { target, anchor, k, damping_ratio, expected: None }
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
    fn saved(&self) -> Option<super::state::SavedForce> {
        Some(super::state::SavedForce::StiffSpring(self.clone()))
    }

    fn validate(&self) -> Result<(), PhysicsError> {
        check(positive(self.k), "stiff spring k", self.k, POSITIVE)?;
        check(
            non_negative(self.damping_ratio),
            "stiff spring damping_ratio",
            self.damping_ratio,
            NON_NEGATIVE,
        )?;
        check(self.anchor.is_finite(), "stiff spring anchor", self.anchor, "a point of finite numbers")?;
        // What it carries between steps (read from a snapshot) must be finite too.
        let carried = self.expected.is_none_or(|(p, v, w)| p.is_finite() && v.is_finite() && w.is_finite());
        check(carried, "stiff spring state", self.anchor, "finite numbers")
    }

    fn apply(&mut self, particles: &mut Particles, dt: f32) {
        let Some(i) = particles.index(self.target) else { return };
        let inverse_mass = particles.inverse_mass[i];
        if inverse_mass <= 0.0 || !(self.k > 0.0 && self.k.is_finite()) || dt <= 0.0 {
            return;
        }
        let position = particles.position[i];
        let stored_velocity = particles.velocity[i];
        let velocity = match self.expected {
            Some((p, v, exact)) if p == position && v == stored_velocity => exact,
            _ => stored_velocity,
        };
        let mass = 1.0 / f64::from(inverse_mass);
        let omega = (f64::from(self.k) / mass).sqrt();
        let zeta = f64::from(self.damping_ratio.max(0.0));
        // Other accelerations, held constant over the step, shift the rest point.
        let other = (particles.acceleration[i] + particles.force[i] * inverse_mass).as_dvec3();
        let rest = self.anchor.as_dvec3() + other / (omega * omega);
        let h = f64::from(dt);
        let y0 = position.as_dvec3() - rest;
        let (y1, v1) = damped_oscillator(y0, velocity.as_dvec3(), omega, zeta, h);
        if zeta > 0.0 {
            // The oscillator's energy the damping took this step (exact; 0 when undamped).
            let energy =
                |y: DVec3, v: DVec3| 0.5 * mass * (v.length_squared() + omega * omega * y.length_squared());
            particles.dissipated += energy(y0, velocity.as_dvec3()) - energy(y1, v1);
        }
        let target = rest + y1;
        // The integrator does v' = (v + a h) d, p' = p + v' h, with d the damping factor.
        let damp = f64::from(particles.damping_per_step(i)).max(1e-6);
        let needed_velocity = (target - position.as_dvec3()) / h;
        let needed_acceleration = (needed_velocity / damp - stored_velocity.as_dvec3()) / h;
        let spring_acceleration = needed_acceleration - other;
        particles.force[i] += (spring_acceleration * mass).as_vec3();
        // Predict the integrator's f32 result exactly, to recognise it next step.
        let v_f32 = (stored_velocity + (particles.acceleration[i] + particles.force[i] * inverse_mass) * dt)
            * particles.damping_per_step(i);
        let p_f32 = position + v_f32 * dt;
        self.expected = Some((p_f32, v_f32, (v1 * damp).as_vec3()));
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

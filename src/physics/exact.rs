//! Exact answers to compare the integrators with: the closed forms of the motions the
//! scenes show, in f64. The lab draws them as ghosts beside the simulated particles and
//! plots the distance between the two.
//!
//! Particle damping `d` (the fraction of velocity kept per second) is, in the limit of
//! small steps, linear drag with rate `λ = -ln d` per second: every closed form here
//! takes it that way.

use glam::DVec3;

/// Position and velocity after `t` seconds of a particle starting at `(p0, v0)` under
/// a constant acceleration `g` and a velocity decay rate `lambda` (1/s, `>= 0`): linear
/// drag `k1 / m`, plus `-ln(damping)`.
///
/// With `lambda = 0` this is the drag-free parabola `p0 + v0 t + g t²/2`; otherwise
/// `v(t) = v∞ + (v0 - v∞) e^{-λt}` with terminal velocity `v∞ = g / λ`, and
/// `p(t) = p0 + v∞ t + (v0 - v∞)(1 - e^{-λt}) / λ`.
#[must_use]
pub fn projectile(p0: DVec3, v0: DVec3, g: DVec3, lambda: f64, t: f64) -> (DVec3, DVec3) {
    if lambda * t < 1e-9 {
        return (p0 + v0 * t + g * (0.5 * t * t), v0 + g * t);
    }
    let terminal = g / lambda;
    let decay = (-lambda * t).exp();
    // (1 - e^{-λt}) / λ, written so it stays accurate when λt is small.
    let spent = -(-lambda * t).exp_m1() / lambda;
    (p0 + terminal * t + (v0 - terminal) * spent, terminal + (v0 - terminal) * decay)
}

/// The decay rate (1/s) of particle damping `d`, the fraction of velocity kept per
/// second: `-ln d`; infinite for `d = 0`.
#[must_use]
pub fn damping_rate(damping: f32) -> f64 {
    -f64::from(damping).ln()
}

/// A particle of mass `m` on an anchored spring of stiffness `k` and zero rest length
/// (the stiff spring), or any rest length along a straight line through the anchor,
/// under gravity `g` and velocity decay `lambda`: the damped harmonic oscillator about
/// the point where the spring holds the weight, `anchor + rest_offset + g m / k`, with
/// `ω = √(k/m)` and damping ratio `ζ = λ / (2ω)`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SpringMotion {
    /// The spring's fixed end (m).
    pub anchor: DVec3,
    /// Where the rest length puts the particle relative to the anchor, along the line
    /// of motion: zero for the stiff spring; `(0, -L, 0)` for a spring of rest length
    /// `L` hanging below its anchor. The motion must stay on that side of the anchor.
    pub rest_offset: DVec3,
    /// Stiffness (N/m).
    pub k: f64,
    /// Mass (kg).
    pub m: f64,
    /// Gravity (m/s²).
    pub g: DVec3,
    /// Velocity decay rate (1/s): linear drag `k1 / m` plus `-ln(damping)`.
    pub lambda: f64,
}

impl SpringMotion {
    /// Where the spring holds the weight at rest (m).
    #[must_use]
    pub fn equilibrium(&self) -> DVec3 {
        self.anchor + self.rest_offset + self.g * (self.m / self.k)
    }

    /// Position and velocity `t` seconds after starting at `(p0, v0)`.
    #[must_use]
    pub fn at(&self, p0: DVec3, v0: DVec3, t: f64) -> (DVec3, DVec3) {
        let omega = (self.k / self.m).sqrt();
        let zeta = self.lambda / (2.0 * omega);
        let equilibrium = self.equilibrium();
        let (y, v) = super::forces::stiff_spring::damped_oscillator(p0 - equilibrium, v0, omega, zeta, t);
        (equilibrium + y, v)
    }
}

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

/// The complete elliptic integral of the first kind, K(k) = ∫₀^{π/2} dφ / √(1 − k²
/// sin²φ), for a modulus 0 ≤ k < 1, by the arithmetic–geometric mean: K = π / (2
/// AGM(1, √(1 − k²))). Infinite at k = 1.
#[must_use]
pub fn elliptic_k(k: f64) -> f64 {
    if k.abs() >= 1.0 {
        return f64::INFINITY;
    }
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    // The AGM converges quadratically: a handful of rounds reach f64's precision.
    for _ in 0..40 {
        if (a - b).abs() <= 1e-15 * a {
            break;
        }
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// The period (s) of a pendulum of length `length` (m) under gravity `g` (m/s²)
/// released from rest at `amplitude` (rad) from straight down, at any amplitude
/// below π: T = 4 √(L/g) K(sin(θ₀/2)). It is 2π√(L/g) for small swings, and grows
/// without bound towards a release straight up.
#[must_use]
pub fn pendulum_period(length: f64, g: f64, amplitude: f64) -> f64 {
    4.0 * (length / g).sqrt() * elliptic_k((0.5 * amplitude).sin().abs())
}

#[cfg(test)]
mod pendulum_tests {
    use super::{elliptic_k, pendulum_period};

    /// K against its series K(k) = π/2 Σ ((2n−1)!!/(2n)!!)² k²ⁿ (1 + k²/4 + 9k⁴/64 + …, six
    /// terms: the rest is below 1e-13 at k = 0.1) for a small
    /// modulus, and against a midpoint-rule quadrature of its integral for large ones.
    #[test]
    #[cfg_attr(miri, ignore = "hundreds of thousands of steps, no unsafe code: too slow to interpret")]
    fn elliptic_k_matches_its_series_and_its_integral() {
        let k: f64 = 0.1;
        let series = std::f64::consts::FRAC_PI_2
            * (1.0
                + k.powi(2) / 4.0
                + 9.0 * k.powi(4) / 64.0
                + 25.0 * k.powi(6) / 256.0
                + 1225.0 * k.powi(8) / 16384.0
                + 3969.0 * k.powi(10) / 65536.0);
        assert!((elliptic_k(k) - series).abs() < 1e-12);
        for k in [0.3, std::f64::consts::FRAC_1_SQRT_2, 0.95, 0.999] {
            let n = 200_000;
            let h = std::f64::consts::FRAC_PI_2 / f64::from(n);
            let integral: f64 = (0..n)
                .map(|i| {
                    let phi = (f64::from(i) + 0.5) * h;
                    h / (1.0 - k * k * phi.sin().powi(2)).sqrt()
                })
                .sum();
            assert!(
                (elliptic_k(k) - integral).abs() < 1e-7 * integral,
                "K({k}) = {} against {integral}",
                elliptic_k(k)
            );
        }
        assert!(elliptic_k(1.0).is_infinite());
    }

    /// The period from the closed form against the pendulum's equation of motion,
    /// θ'' = −(g/L) sin θ, integrated with RK4 from rest at θ₀ until θ first crosses 0
    /// (a quarter period).
    #[test]
    #[cfg_attr(miri, ignore = "hundreds of thousands of steps, no unsafe code: too slow to interpret")]
    fn the_period_matches_the_equation_of_motion() {
        let (length, g) = (1.0, 9.81);
        for degrees in [5.0_f64, 45.0, 90.0, 170.0] {
            let (mut theta, mut omega, mut t) = (degrees.to_radians(), 0.0_f64, 0.0);
            let h = 1e-5;
            let accel = |theta: f64| -(g / length) * theta.sin();
            while theta > 0.0 {
                let (k1t, k1w) = (omega, accel(theta));
                let (k2t, k2w) = (omega + 0.5 * h * k1w, accel(theta + 0.5 * h * k1t));
                let (k3t, k3w) = (omega + 0.5 * h * k2w, accel(theta + 0.5 * h * k2t));
                let (k4t, k4w) = (omega + h * k3w, accel(theta + h * k3t));
                let next = theta + h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t);
                if next <= 0.0 {
                    // The crossing, placed on the line between the two steps.
                    t += h * theta / (theta - next);
                    break;
                }
                omega += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
                theta = next;
                t += h;
            }
            let period = pendulum_period(length, g, degrees.to_radians());
            assert!((4.0 * t - period).abs() < 1e-6 * period, "{degrees}°: {} against {period}", 4.0 * t);
        }
        // Small swings: 2π√(L/g).
        let small = 2.0 * std::f64::consts::PI * (length / g).sqrt();
        assert!((pendulum_period(length, g, 1e-5) - small).abs() < 1e-9);
    }
}

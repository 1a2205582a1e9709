//! One contact's solve: the normal impulse with soft position feedback, then Coulomb
//! friction clamped to the normal impulse.

use glam::Vec3;

use super::color::SharedVelocities;
use super::{Context, NONE, SoftContact};

/// Bias velocity, mass scale and impulse scale of a one-sided constraint with gap `s`:
/// a positive gap may close by `s` this substep (speculative), an overlap is pushed out
/// softly (no faster than `max_push`) when feedback is on.
#[inline]
pub(super) fn contact_terms(s: f32, context: Context) -> (f32, f32, f32) {
    if s > 0.0 {
        (s * context.inv_h, 1.0, 0.0)
    } else if context.use_bias {
        let soft = context.soft;
        ((soft.bias_rate * s).max(-context.max_push), soft.mass_scale, soft.impulse_scale)
    } else {
        (0.0, 1.0, 0.0)
    }
}

/// Adds `impulse` to `a` and its opposite to `b`, each divided by its mass.
#[inline]
pub(super) fn apply(velocities: SharedVelocities<'_>, w: &[f32], a: u32, b: u32, impulse: Vec3) {
    let (a, wa) = (a as usize, w[a as usize]);
    if wa > 0.0 {
        velocities.set(a, velocities.get(a) + impulse * wa);
    }
    if b != NONE {
        let (b, wb) = (b as usize, w[b as usize]);
        if wb > 0.0 {
            velocities.set(b, velocities.get(b) - impulse * wb);
        }
    }
}

/// One contact: the normal impulse with soft feedback, then Coulomb friction clamped to
/// `μ` times it (a disc, since a particle's tangent plane has two directions). Both
/// velocities are read once and written once.
#[inline]
pub(super) fn solve_contact(
    c: &mut SoftContact,
    velocities: SharedVelocities<'_>,
    w: &[f32],
    delta: &[Vec3],
    context: Context,
) {
    let (a, b) = (c.a as usize, c.b as usize);
    let has_b = c.b != NONE;
    let wa = w[a];
    let wb = if has_b { w[b] } else { 0.0 };
    let mut va = velocities.get(a);
    let mut vb = if has_b { velocities.get(b) } else { Vec3::ZERO };
    let moved = if has_b { delta[a] - delta[b] } else { delta[a] };
    let s = c.separation + moved.dot(c.normal);
    if !context.use_bias && s > 0.0 && c.normal_impulse == 0.0 {
        // Relaxing a contact that has not touched: leave its closing speed alone. The
        // next substep's solve still stops it at the surface, and the impact stage
        // needs the speed it really arrives with to bounce it.
        return;
    }
    let (bias, mass_scale, impulse_scale) = contact_terms(s, context);
    let vn = (va - vb).dot(c.normal);
    let impulse = -c.mass * mass_scale * (vn + bias) - impulse_scale * c.normal_impulse;
    let total = (c.normal_impulse + impulse).max(0.0);
    let applied = total - c.normal_impulse;
    c.normal_impulse = total;
    let mut p = c.normal * applied;

    if c.friction > 0.0 {
        // Velocities after the normal impulse, in registers.
        let v = (va + p * wa) - (vb - p * wb);
        let tangential = v - c.normal * v.dot(c.normal);
        let old = c.tangent_impulse;
        let mut total = old - tangential * c.mass;
        let limit = c.friction * c.normal_impulse;
        let squared = total.length_squared();
        if squared > limit * limit {
            total *= limit / squared.sqrt();
        }
        c.tangent_impulse = total;
        p += total - old;
    }
    if wa > 0.0 {
        va += p * wa;
        velocities.set(a, va);
    }
    if has_b && wb > 0.0 {
        vb -= p * wb;
        velocities.set(b, vb);
    }
}

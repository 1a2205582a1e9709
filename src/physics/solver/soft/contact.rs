//! One contact's solve: the normal impulse with soft position feedback, then Coulomb
//! friction clamped to the normal impulse (at the contact point, turning spheres that
//! roll), then rolling resistance clamped to it.

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

/// What the solve reads of the particles besides velocities: inverse masses, inverse
/// inertias, how far each moved this step, and the spins (shared like the velocities,
/// under the same colouring invariant: only a movable sphere that rolls is written).
#[derive(Clone, Copy)]
pub(super) struct Bodies<'a> {
    pub(super) w: &'a [f32],
    pub(super) inertia: &'a [f32],
    pub(super) delta: &'a [Vec3],
    pub(super) spins: SharedVelocities<'a>,
}

/// Turns `a` and `b` by a contact's tangential impulse `p` (applied to `a` at `-lever_a
/// n` from its centre, its opposite to `b` at `+lever_b n`) and its rolling impulse
/// `rolling` (to `a`, its opposite to `b`).
#[inline]
pub(super) fn turn(c: &SoftContact, bodies: Bodies<'_>, p: Vec3, rolling: Vec3) {
    let torque = c.normal.cross(p);
    let (a, ia) = (c.a as usize, bodies.inertia[c.a as usize]);
    if ia > 0.0 {
        bodies.spins.set(a, bodies.spins.get(a) + (rolling - torque * c.lever_a) * ia);
    }
    if c.b != NONE {
        let (b, ib) = (c.b as usize, bodies.inertia[c.b as usize]);
        if ib > 0.0 {
            bodies.spins.set(b, bodies.spins.get(b) - (rolling + torque * c.lever_b) * ib);
        }
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
/// `μ` times it (a disc, since a particle's tangent plane has two directions), then
/// rolling resistance. Both velocities are read once and written once.
///
/// For spheres that roll, friction acts on the velocity of the contact point, `v_a +
/// ω_a × (-r_a n) - v_b - ω_b × (r_b n)`, and its impulse `P` turns each sphere by
/// `I⁻¹ (lever × ±P)`. Rolling resistance drives the relative spin `ω_a - ω_b` to
/// zero with an angular impulse clamped to `rolling` times the normal impulse: a
/// torque that at most balances `μ_r r N` (static while it holds, like friction).
#[inline]
pub(super) fn solve_contact(
    c: &mut SoftContact,
    velocities: SharedVelocities<'_>,
    bodies: Bodies<'_>,
    context: Context,
) {
    let (w, delta) = (bodies.w, bodies.delta);
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
    let rolls = c.lever_a > 0.0 || c.lever_b > 0.0;

    if c.friction > 0.0 {
        // Velocities after the normal impulse, in registers.
        let mut v = (va + p * wa) - (vb - p * wb);
        if rolls {
            let spin_a = bodies.spins.get(a) * c.lever_a;
            let spin_b = if has_b { bodies.spins.get(b) * c.lever_b } else { Vec3::ZERO };
            v -= (spin_a + spin_b).cross(c.normal);
        }
        let tangential = v - c.normal * v.dot(c.normal);
        let old = c.tangent_impulse;
        let mut total = old - tangential * c.tangent_mass;
        let limit = c.friction * c.normal_impulse;
        let squared = total.length_squared();
        if squared > limit * limit {
            total *= limit / squared.sqrt();
        }
        c.tangent_impulse = total;
        let friction = total - old;
        if rolls {
            turn(c, bodies, friction, Vec3::ZERO);
        }
        p += friction;
    }
    if c.rolling > 0.0 {
        let spin_b = if has_b { bodies.spins.get(b) } else { Vec3::ZERO };
        let relative = bodies.spins.get(a) - spin_b;
        let old = c.rolling_impulse;
        let mut total = old - relative * c.rolling_mass;
        let limit = c.rolling * c.normal_impulse;
        let squared = total.length_squared();
        if squared > limit * limit {
            total *= limit / squared.sqrt();
        }
        c.rolling_impulse = total;
        turn(c, bodies, Vec3::ZERO, total - old);
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

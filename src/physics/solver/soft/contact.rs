//! Four contacts' solve at once (a [`ContactBatch`]): the normal impulse with soft
//! position feedback, then Coulomb friction clamped to the normal impulse (at the
//! contact point, turning spheres that roll), then rolling resistance clamped to it.
//!
//! Each lane computes, operation for operation, what the solve of its one contact
//! computes alone (the formulas below, in glam's order): where a contact would skip a
//! part (no friction, a sphere that does not roll, a relax pass over a contact not
//! touching) its lane computes the part anyway and keeps its old values by a bit-exact
//! select. So the result does not depend on which contacts share a batch, and equals
//! the one-contact-at-a-time solve to the bit (`tests/state_hashes.rs` pins it).

use glam::Vec3;

use super::Context;
use super::batch::{ContactBatch, LANES};
use super::color::SharedVelocities;
use crate::physics::wide::{F4, M4, V4};

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

/// [`contact_terms`] in four lanes.
#[inline(always)]
fn contact_terms_wide(s: F4, context: Context) -> (F4, F4, F4) {
    let gap = s.gt(F4::ZERO);
    let (one, zero) = (F4::splat(1.0), F4::ZERO);
    let speculative = (s * F4::splat(context.inv_h), one, zero);
    let touching = if context.use_bias {
        let soft = context.soft;
        let bias = (F4::splat(soft.bias_rate) * s).max(F4::splat(-context.max_push));
        (bias, F4::splat(soft.mass_scale), F4::splat(soft.impulse_scale))
    } else {
        (zero, one, zero)
    };
    (
        gap.select(speculative.0, touching.0),
        gap.select(speculative.1, touching.1),
        gap.select(speculative.2, touching.2),
    )
}

/// What a solve reads and writes of the particles: velocities and spins (shared by
/// the tasks solving one colour, see [`SharedVelocities`]), and how far each particle
/// moved this step.
#[derive(Clone, Copy)]
pub(super) struct Bodies<'a> {
    pub(super) velocities: SharedVelocities<'a>,
    pub(super) spins: SharedVelocities<'a>,
    pub(super) delta: &'a [Vec3],
}

/// The vectors of the lanes' particles `indices` from `shared`.
#[inline(always)]
fn gather(shared: SharedVelocities<'_>, indices: &[u32; LANES]) -> V4 {
    shared.gather(*indices)
}

/// Writes lane `i`'s vector of `value` to particle `indices[i]` for each lane set in
/// `lanes`. Those particles are movable and distinct: a colour holds each movable
/// particle once.
#[inline(always)]
fn scatter(shared: SharedVelocities<'_>, indices: &[u32; LANES], lanes: u32, value: V4) {
    shared.scatter(*indices, lanes, value);
}

/// How far the lanes' particles `indices` moved this step (m).
#[inline(always)]
fn motion(delta: &[Vec3], indices: &[u32; LANES]) -> V4 {
    assert!(indices.iter().all(|&i| (i as usize) < delta.len()));
    // SAFETY: every index is in bounds (checked above); `delta` is only read.
    unsafe { V4::gather(delta.as_ptr(), *indices) }
}

/// Lanes where `x > 0`, as bits.
#[inline(always)]
fn positive(x: F4) -> u32 {
    x.gt(F4::ZERO).bits()
}

/// The torque impulse of a contact's tangential impulse `p`, turning `a` by
/// `(rolling - torque · lever_a) · I_a⁻¹` and `b` by `-(rolling + torque · lever_b) ·
/// I_b⁻¹`: the new spins of both.
#[inline(always)]
fn turned(batch: &ContactBatch, spin_a: V4, spin_b: V4, p: V4, rolling: V4) -> (V4, V4) {
    let torque = batch.normal.cross(p);
    let a = spin_a + (rolling - torque.scale(batch.lever_a)).scale(batch.ia);
    let b = spin_b - (rolling + torque.scale(batch.lever_b)).scale(batch.ib);
    (a, b)
}

/// `new` where `mask` is set, else `old`; just `new` when `ALL` says every lane is set.
#[inline(always)]
fn pick<const ALL: bool>(mask: M4, new: V4, old: V4) -> V4 {
    if ALL { new } else { V4::select(mask, new, old) }
}

/// Warm-starts a run of batches (see [`warm_start_batch`]), with AVX's three-operand
/// instructions where the processor has them (the same operations, the same bits).
pub(super) fn warm_start_batches(batches: &mut [ContactBatch], bodies: Bodies<'_>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (checked just above).
        unsafe { warm_start_avx(batches, bodies) };
        return;
    }
    batches.iter().for_each(|batch| warm_start_batch(batch, bodies));
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn warm_start_avx(batches: &mut [ContactBatch], bodies: Bodies<'_>) {
    batches.iter().for_each(|batch| warm_start_batch(batch, bodies));
}

/// Solves a run of batches (see [`solve_batch`]), with AVX's three-operand instructions
/// where the processor has them (the same operations, the same bits).
pub(super) fn solve_batches(batches: &mut [ContactBatch], bodies: Bodies<'_>, context: Context) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (checked just above).
        unsafe { solve_avx(batches, bodies, context) };
        return;
    }
    solve_run(batches, bodies, context);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn solve_avx(batches: &mut [ContactBatch], bodies: Bodies<'_>, context: Context) {
    solve_run(batches, bodies, context);
}

#[inline(always)]
fn solve_run(batches: &mut [ContactBatch], bodies: Bodies<'_>, context: Context) {
    for batch in batches {
        if batch.full {
            solve_batch::<true>(batch, bodies, context);
        } else {
            solve_batch::<false>(batch, bodies, context);
        }
    }
}

/// Applies last step's impulses of a batch's contacts (warm start).
#[inline(always)]
fn warm_start_batch(batch: &ContactBatch, bodies: Bodies<'_>) {
    let has_b = batch.has_b_mask();
    let impulse = batch.normal.scale(batch.normal_impulse) + batch.tangent_impulse;
    let va = gather(bodies.velocities, &batch.a);
    let vb = gather(bodies.velocities, &batch.b);
    scatter(bodies.velocities, &batch.a, batch.active & positive(batch.wa), va + impulse.scale(batch.wa));
    let b_lanes = batch.active & batch.has_b & positive(batch.wb);
    scatter(bodies.velocities, &batch.b, b_lanes, vb - impulse.scale(batch.wb));
    // Only spheres that roll turn (a positive inverse inertia means a movable sphere
    // that rolls, so its contact rolls).
    let (turn_a, turn_b) =
        (batch.active & positive(batch.ia), batch.active & batch.has_b & positive(batch.ib));
    if turn_a | turn_b != 0 {
        let spin_a = gather(bodies.spins, &batch.a);
        let spin_b = V4::select(has_b, gather(bodies.spins, &batch.b), V4::ZERO);
        let (a, b) = turned(batch, spin_a, spin_b, batch.tangent_impulse, batch.rolling_impulse);
        scatter(bodies.spins, &batch.a, turn_a, a);
        scatter(bodies.spins, &batch.b, turn_b, b);
    }
}

/// Solves a batch of four contacts: the normal impulse with soft feedback, then Coulomb
/// friction clamped to `μ` times it (a disc, since a particle's tangent plane has two
/// directions), then rolling resistance. Every velocity and spin is read once and
/// written once.
///
/// For spheres that roll, friction acts on the velocity of the contact point, `v_a +
/// ω_a × (-r_a n) - v_b - ω_b × (r_b n)`, and its impulse `P` turns each sphere by
/// `I⁻¹ (lever × ±P)`. Rolling resistance drives the relative spin `ω_a - ω_b` to
/// zero with an angular impulse clamped to `rolling` times the normal impulse: a
/// torque that at most balances `μ_r r N` (static while it holds, like friction).
/// `FULL`: every lane is a pair of rolling spheres with friction and rolling
/// resistance ([`ContactBatch::full`]), so no part of the solve is skipped in any lane
/// and the selects that would keep old values are left out.
#[inline(always)]
fn solve_batch<const FULL: bool>(batch: &mut ContactBatch, bodies: Bodies<'_>, context: Context) {
    let has_b = batch.has_b_mask();
    let n = batch.normal;
    let va = gather(bodies.velocities, &batch.a);
    let vb = pick::<FULL>(has_b, gather(bodies.velocities, &batch.b), V4::ZERO);
    let da = motion(bodies.delta, &batch.a);
    let db = pick::<FULL>(has_b, motion(bodies.delta, &batch.b), V4::ZERO);
    let s = batch.separation + (da - db).dot(n);
    // Relaxing a contact that has not touched: leave its closing speed alone. The next
    // substep's solve still stops it at the surface, and the impact stage needs the
    // speed it really arrives with to bounce it.
    let skip = if context.use_bias {
        M4::new([false; LANES])
    } else {
        s.gt(F4::ZERO).and(batch.normal_impulse.eq(F4::ZERO))
    };
    let (bias, mass_scale, impulse_scale) = contact_terms_wide(s, context);
    let vn = (va - vb).dot(n);
    let old_normal = batch.normal_impulse;
    let impulse = -batch.mass * mass_scale * (vn + bias) - impulse_scale * old_normal;
    let total = (old_normal + impulse).max(F4::ZERO);
    let applied = total - old_normal;
    let normal_impulse = total;
    let mut p = n.scale(applied);

    let rolls = batch.lever_a.gt(F4::ZERO).or(batch.lever_b.gt(F4::ZERO));
    let (turns_a, turns_b) = (batch.ia.gt(F4::ZERO), batch.ib.gt(F4::ZERO).and(has_b));
    let any_spin = FULL || (rolls.bits() & batch.active) != 0;
    let (mut spin_a, mut spin_b) = if any_spin {
        (gather(bodies.spins, &batch.a), pick::<FULL>(has_b, gather(bodies.spins, &batch.b), V4::ZERO))
    } else {
        (V4::ZERO, V4::ZERO)
    };

    let with_friction = batch.friction.gt(F4::ZERO);
    let mut tangent_impulse = batch.tangent_impulse;
    if FULL || (with_friction.bits() & batch.active) != 0 {
        // Velocities after the normal impulse, in registers.
        let mut v = (va + p.scale(batch.wa)) - (vb - p.scale(batch.wb));
        if any_spin {
            let spinning = spin_a.scale(batch.lever_a) + spin_b.scale(batch.lever_b);
            v = pick::<FULL>(rolls, v - spinning.cross(n), v);
        }
        let tangential = v - n.scale(v.dot(n));
        let old = batch.tangent_impulse;
        let mut total = old - tangential.scale(batch.tangent_mass);
        let limit = batch.friction * normal_impulse;
        let squared = total.dot(total);
        let over = squared.gt(limit * limit);
        total = V4::select(over, total.scale(limit / squared.sqrt()), total);
        tangent_impulse = pick::<FULL>(with_friction, total, old);
        let friction = total - old;
        if any_spin {
            let (a, b) = turned(batch, spin_a, spin_b, friction, V4::ZERO);
            let turning = with_friction.and(rolls);
            spin_a = pick::<FULL>(turning.and(turns_a), a, spin_a);
            spin_b = pick::<FULL>(turning.and(turns_b), b, spin_b);
        }
        p = pick::<FULL>(with_friction, p + friction, p);
    }

    let resisting = batch.rolling.gt(F4::ZERO);
    let mut rolling_impulse = batch.rolling_impulse;
    if FULL || (resisting.bits() & batch.active) != 0 {
        let relative = spin_a - spin_b;
        let old = batch.rolling_impulse;
        let mut total = old - relative.scale(batch.rolling_mass);
        let limit = batch.rolling * normal_impulse;
        let squared = total.dot(total);
        let over = squared.gt(limit * limit);
        total = V4::select(over, total.scale(limit / squared.sqrt()), total);
        rolling_impulse = pick::<FULL>(resisting, total, old);
        let (a, b) = turned(batch, spin_a, spin_b, V4::ZERO, total - old);
        spin_a = pick::<FULL>(resisting.and(turns_a), a, spin_a);
        spin_b = pick::<FULL>(resisting.and(turns_b), b, spin_b);
    }

    let solved = if context.use_bias {
        batch.normal_impulse = normal_impulse;
        batch.tangent_impulse = tangent_impulse;
        batch.rolling_impulse = rolling_impulse;
        batch.active
    } else {
        batch.normal_impulse = skip.select(old_normal, normal_impulse);
        batch.tangent_impulse = V4::select(skip, batch.tangent_impulse, tangent_impulse);
        batch.rolling_impulse = V4::select(skip, batch.rolling_impulse, rolling_impulse);
        batch.active & !skip.bits()
    };
    scatter(bodies.velocities, &batch.a, solved & positive(batch.wa), va + p.scale(batch.wa));
    scatter(bodies.velocities, &batch.b, solved & batch.has_b & positive(batch.wb), vb - p.scale(batch.wb));
    if any_spin {
        scatter(bodies.spins, &batch.a, solved & turns_a.bits(), spin_a);
        scatter(bodies.spins, &batch.b, solved & turns_b.bits(), spin_b);
    }
}

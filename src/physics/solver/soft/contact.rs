//! Four contacts' solve at once (a [`ContactBatch`]; eight, two batches joined, where
//! the processor has AVX; sixteen, four joined, where it has AVX-512): the normal
//! impulse with soft position feedback, then Coulomb friction clamped to the normal
//! impulse (at the contact point, turning spheres that roll), then rolling resistance
//! clamped to it.
//!
//! Each lane computes, operation for operation, what the solve of its one contact
//! computes alone (the formulas below, in glam's order): where a contact would skip a
//! part (no friction, a sphere that does not roll, a relax pass over a contact not
//! touching, a contact that stays without impulse) its lane computes the part anyway
//! and keeps its old values by a bit-exact select. So the result does not depend on
//! which contacts share a batch, and equals the one-contact-at-a-time solve to the bit
//! (`tests/state_hashes.rs` pins it).

use glam::Vec3;

use super::Context;
#[cfg(target_arch = "x86_64")]
use super::batch::split;
use super::batch::{ContactBatch, Material};
use super::shared::SharedVelocities;
#[cfg(target_arch = "x86_64")]
use crate::physics::wide::avx::F8;
#[cfg(target_arch = "x86_64")]
use crate::physics::wide::avx512::F16;
use crate::physics::wide::{Lane, Mask, V};

/// Largest twisting torque of a contact as a share of its largest rolling-resistance
/// torque: a tenth, the torsional friction `μ a N` of a contact patch of radius `a`
/// about 2% of the rolling radius with the lab's `μ` 0.5 and `μ_r` 0.1.
pub(super) const TWIST_SHARE: f32 = 0.1;

/// Time in which a contact's twist damping takes a relative spin about the normal down
/// by a factor e, where [`TWIST_SHARE`] does not bound it (s): a physical time, so
/// the same at every step.
pub(super) const TWIST_TIME: f32 = 0.1;

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

/// [`contact_terms`] in lanes.
#[inline(always)]
fn contact_terms_wide<L: Lane>(s: L, context: Context) -> (L, L, L) {
    let gap = s.gt(L::ZERO);
    let (one, zero) = (L::splat(1.0), L::ZERO);
    let speculative = (s * L::splat(context.inv_h), one, zero);
    let touching = if context.use_bias {
        let soft = context.soft;
        let bias = (L::splat(soft.bias_rate) * s).max(L::splat(-context.max_push));
        (bias, L::splat(soft.mass_scale), L::splat(soft.impulse_scale))
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
fn gather<L: Lane>(shared: SharedVelocities<'_>, indices: &L::Index) -> V<L> {
    shared.gather::<L>(*indices)
}

/// Writes lane `i`'s vector of `value` to particle `indices[i]` for each lane set in
/// `lanes`. Those particles are movable and distinct: a colour holds each movable
/// particle once.
#[inline(always)]
fn scatter<L: Lane>(shared: SharedVelocities<'_>, indices: &L::Index, lanes: u32, value: V<L>) {
    shared.scatter(*indices, lanes, value);
}

/// How far the lanes' particles `indices` moved this step (m).
#[inline(always)]
fn motion<L: Lane>(delta: &[Vec3], indices: &L::Index) -> V<L> {
    assert!(indices.as_ref().iter().all(|&i| (i as usize) < delta.len()));
    // SAFETY: every index is in bounds (checked above); `delta` is only read.
    unsafe { L::gather(delta.as_ptr(), delta.len(), *indices) }
}

/// Lanes where `x > 0`, as bits.
#[inline(always)]
fn positive<L: Lane>(x: L) -> u32 {
    x.gt(L::ZERO).bits()
}

/// The torque impulse of a contact's tangential impulse `p`, turning `a` by
/// `(rolling - torque · lever_a) · I_a⁻¹` and `b` by `-(rolling + torque · lever_b) ·
/// I_b⁻¹`: the new spins of both.
#[inline(always)]
fn turned<L: Lane>(
    batch: &ContactBatch<L>,
    m: &Material<L>,
    spin_a: V<L>,
    spin_b: V<L>,
    p: V<L>,
    rolling: V<L>,
) -> (V<L>, V<L>) {
    let torque = batch.normal.cross(p);
    let a = spin_a + (rolling - torque.scale(m.lever_a)).scale(m.ia);
    let b = spin_b - (rolling + torque.scale(m.lever_b)).scale(m.ib);
    (a, b)
}

/// `total` cut back to length `limit` in the lanes where it is longer (`squared` is
/// its squared length; `limit` is never negative): `total · limit / |total|` there.
///
/// The square root and division are the slowest operations of the solve, and most
/// batches need them in no lane: where a lane over its limit has `limit = 0` (a
/// contact that carries no load) the cut is `total · 0`, computed as that (the same
/// bits, signed zeros included, since `0 / |total|` is `+0`). Only a batch with a lane
/// over a positive limit takes the root.
#[inline(always)]
fn clamped<L: Lane>(total: V<L>, squared: L, limit: L) -> V<L> {
    let over = squared.gt(limit * limit);
    if over.bits() == 0 {
        total
    } else if over.and(limit.gt(L::ZERO)).bits() == 0 {
        V::select(over, total.scale(L::ZERO), total)
    } else {
        V::select(over, total.scale(limit / squared.sqrt()), total)
    }
}

/// `new` where `mask` is set, else `old`; just `new` when `ALL` says every lane is set.
#[inline(always)]
fn pick<L: Lane, const ALL: bool>(mask: L::Mask, new: V<L>, old: V<L>) -> V<L> {
    if ALL { new } else { V::select(mask, new, old) }
}

/// Warm-starts a run of batches (see [`warm_start_batch`]), with AVX's three-operand
/// instructions where the processor has them (the same operations, the same bits). Its
/// few operations per contact are not worth joining two batches into eight lanes as the
/// solve does: the joins cost more than they save (measured on a pile).
pub(super) fn warm_start_batches(batches: &mut [ContactBatch], materials: &[Material], bodies: Bodies<'_>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (checked just above).
        unsafe { warm_start_avx(batches, materials, bodies) };
        return;
    }
    warm_start_run(batches, materials, bodies);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn warm_start_avx(batches: &mut [ContactBatch], materials: &[Material], bodies: Bodies<'_>) {
    warm_start_run(batches, materials, bodies);
}

#[inline(always)]
fn warm_start_run(batches: &[ContactBatch], materials: &[Material], bodies: Bodies<'_>) {
    for batch in batches {
        warm_start_batch(batch, &materials[batch.material as usize], bodies);
    }
}

/// Solves a run of batches (see [`solve_batch`]), as wide as the processor allows:
/// with AVX a run of one colour is solved two batches at a time, joined into eight
/// lanes ([`ContactBatch::join`]; their eight contacts share no movable particle), with
/// AVX-512 four at a time in sixteen lanes (the rest in eights), and the overflow's
/// one batch at a time in four. Each lane computes the same operations whatever the
/// width, so the width changes the time, not the bits.
pub(super) fn solve_batches(
    batches: &mut [ContactBatch],
    materials: &[Material],
    one_colour: bool,
    bodies: Bodies<'_>,
    context: Context,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx512vl") {
        // SAFETY: the processor has AVX-512F and VL, and so AVX (checked just above).
        unsafe { solve_avx512(batches, materials, one_colour, bodies, context) };
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (checked just above).
        unsafe { solve_avx(batches, materials, one_colour, bodies, context) };
        return;
    }
    let _ = one_colour;
    solve_run(batches, materials, bodies, context);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn solve_avx(
    batches: &mut [ContactBatch],
    materials: &[Material],
    one_colour: bool,
    bodies: Bodies<'_>,
    context: Context,
) {
    if one_colour {
        solve_in_eights(batches, materials, bodies, context);
    } else {
        solve_run(batches, materials, bodies, context);
    }
}

/// Sixteen lanes: four batches of one colour joined (two eights joined). Measured on
/// an 8,000-sphere pile on AMD Zen 5, whose AVX-512 units are a full 512 bits wide: the
/// step about 10% faster than with eight lanes, the bits the same. The eight-lane
/// parts are compiled with AVX-512 too, which gives them 32 registers instead of 16.
///
/// Four batches of the same four materials as the four before (most of a pile's) reuse
/// their joined material instead of joining it again.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx512f,avx512vl")]
fn solve_avx512(
    batches: &mut [ContactBatch],
    materials: &[Material],
    one_colour: bool,
    bodies: Bodies<'_>,
    context: Context,
) {
    if !one_colour {
        solve_run(batches, materials, bodies, context);
        return;
    }
    let (fours, rest) = batches.as_chunks_mut::<4>();
    // The names of the four materials joined last, and their join.
    let mut joined: Option<([u32; 4], Material<F16>)> = None;
    for four in fours {
        let [b0, b1, b2, b3] = &*four;
        let names = [b0.material, b1.material, b2.material, b3.material];
        let material = match joined {
            Some((last, material)) if last == names => material,
            _ => {
                let [m0, m1, m2, m3] = names.map(|k| &materials[k as usize]);
                let both = (Material::<F8>::join(m0, m1), Material::<F8>::join(m2, m3));
                let material = Material::<F16>::join(&both.0, &both.1);
                joined = Some((names, material));
                material
            }
        };
        let (low, high) = (ContactBatch::<F8>::join(b0, b1), ContactBatch::<F8>::join(b2, b3));
        let mut wide = ContactBatch::<F16>::join(&low, &high);
        solve_one(&mut wide, &material, bodies, context);
        for (half, pair) in split(wide.impulses()).into_iter().zip(four.chunks_exact_mut(2)) {
            for (impulses, batch) in split::<F8>(half).into_iter().zip(pair) {
                batch.set_impulses(impulses);
            }
        }
    }
    solve_in_eights(rest, materials, bodies, context);
}

/// A run of one colour two batches at a time in eight lanes, the last one alone in four
/// (a pair of the same two materials as the pair before reuses their joined material).
/// Only called from functions compiled for AVX.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn solve_in_eights(
    batches: &mut [ContactBatch],
    materials: &[Material],
    bodies: Bodies<'_>,
    context: Context,
) {
    let mut pairs = batches.chunks_exact_mut(2);
    let mut joined: Option<([u32; 2], Material<F8>)> = None;
    for pair in &mut pairs {
        let [low, high] = pair else { unreachable!("chunks of two") };
        let names = [low.material, high.material];
        let material = match joined {
            Some((last, material)) if last == names => material,
            _ => {
                let material =
                    Material::<F8>::join(&materials[names[0] as usize], &materials[names[1] as usize]);
                joined = Some((names, material));
                material
            }
        };
        let mut wide = ContactBatch::<F8>::join(low, high);
        solve_one(&mut wide, &material, bodies, context);
        let [first, second] = split(wide.impulses());
        low.set_impulses(first);
        high.set_impulses(second);
    }
    solve_run(pairs.into_remainder(), materials, bodies, context);
}

#[inline(always)]
fn solve_run(batches: &mut [ContactBatch], materials: &[Material], bodies: Bodies<'_>, context: Context) {
    for batch in batches {
        let material = &materials[batch.material as usize];
        solve_one(batch, material, bodies, context);
    }
}

/// [`solve_batch`], without the selects where the batch is [`full`](ContactBatch::full).
#[inline(always)]
fn solve_one<L: Lane>(batch: &mut ContactBatch<L>, m: &Material<L>, bodies: Bodies<'_>, context: Context) {
    if batch.full {
        solve_batch::<L, true>(batch, m, bodies, context);
    } else {
        solve_batch::<L, false>(batch, m, bodies, context);
    }
}

/// Lanes whose normal, tangent and rolling impulses are all zero (either sign).
#[inline(always)]
fn without_impulse<L: Lane>(batch: &ContactBatch<L>) -> u32 {
    let zero = |x: L| x.eq(L::ZERO);
    let (t, r) = (batch.tangent_impulse, batch.rolling_impulse);
    let tangent = zero(t.x).and(zero(t.y)).and(zero(t.z));
    let rolling = zero(r.x).and(zero(r.y)).and(zero(r.z));
    zero(batch.normal_impulse).and(tangent).and(rolling).bits()
}

/// Applies last step's impulses of a batch's contacts (warm start). A contact without
/// any impulse has nothing to apply and writes nothing (adding zero would change only
/// a velocity of -0 to +0): a batch of such contacts, most of a pile's speculative
/// ones, which the colouring gathers into batches of their own, is passed over.
#[inline(always)]
fn warm_start_batch<L: Lane>(batch: &ContactBatch<L>, m: &Material<L>, bodies: Bodies<'_>) {
    let pushing = batch.active & !without_impulse(batch);
    if pushing == 0 {
        return;
    }
    let has_b = batch.has_b_mask();
    let impulse = batch.normal.scale(batch.normal_impulse) + batch.tangent_impulse;
    let va = gather::<L>(bodies.velocities, &batch.a);
    let vb = gather::<L>(bodies.velocities, &batch.b);
    scatter::<L>(bodies.velocities, &batch.a, pushing & positive(m.wa), va + impulse.scale(m.wa));
    let b_lanes = pushing & batch.has_b & positive(m.wb);
    scatter::<L>(bodies.velocities, &batch.b, b_lanes, vb - impulse.scale(m.wb));
    // Only spheres that roll turn (a positive inverse inertia means a movable sphere
    // that rolls, so its contact rolls).
    let (turn_a, turn_b) = (pushing & positive(m.ia), pushing & batch.has_b & positive(m.ib));
    if turn_a | turn_b != 0 {
        let spin_a = gather::<L>(bodies.spins, &batch.a);
        let spin_b = V::select(has_b, gather::<L>(bodies.spins, &batch.b), V::ZERO);
        let (a, b) = turned(batch, m, spin_a, spin_b, batch.tangent_impulse, batch.rolling_impulse);
        scatter::<L>(bodies.spins, &batch.a, turn_a, a);
        scatter::<L>(bodies.spins, &batch.b, turn_b, b);
    }
}

/// Solves a batch of four contacts: the normal impulse with soft feedback, then Coulomb
/// friction clamped to `μ` times it (a disc, since a particle's tangent plane has two
/// directions), then rolling resistance. Every velocity and spin is read once and
/// written once (neither, in a relax pass over a batch whose every contact skips; in a
/// solve over a batch whose every contact stays without impulse, the velocities are
/// read but not written, and the spins neither read nor written).
///
/// For spheres that roll, friction acts on the velocity of the contact point, `v_a +
/// ω_a × (-r_a n) - v_b - ω_b × (r_b n)`, and its impulse `P` turns each sphere by
/// `I⁻¹ (lever × ±P)`. Rolling resistance drives the relative spin `ω_a - ω_b` about
/// axes in the contact plane to zero with an angular impulse clamped to `rolling` times
/// the normal impulse: a torque that at most balances `μ_r r N` (static while it holds,
/// like friction). The twist, the relative spin about the normal, is damped (in
/// [`TWIST_TIME`], with a torque of at most [`TWIST_SHARE`] of that), never held.
/// `FULL`: every lane is a pair of rolling spheres with friction and rolling
/// resistance ([`ContactBatch::full`]), so no part of the solve is skipped in any lane
/// and the selects that would keep old values are left out.
#[inline(always)]
fn solve_batch<L: Lane, const FULL: bool>(
    batch: &mut ContactBatch<L>,
    m: &Material<L>,
    bodies: Bodies<'_>,
    context: Context,
) {
    let has_b = batch.has_b_mask();
    let n = batch.normal;
    let da = motion::<L>(bodies.delta, &batch.a);
    let db = pick::<L, FULL>(has_b, motion::<L>(bodies.delta, &batch.b), V::ZERO);
    let s = batch.separation + (da - db).dot(n);
    // Relaxing a contact that has not touched: leave its closing speed alone. The next
    // substep's solve still stops it at the surface, and the impact stage needs the
    // speed it really arrives with to bounce it.
    let skip = if context.use_bias {
        L::Mask::from_bits(0)
    } else {
        s.gt(L::ZERO).and(batch.normal_impulse.eq(L::ZERO))
    };
    // A skipped lane writes back what it read (below): a batch whose every contact is
    // skipped changes nothing, so it is left at that. Most of a pile's speculative
    // contacts, which the colouring gathers into batches of their own, are such.
    if skip.bits() & batch.active == batch.active {
        return;
    }
    let va = gather::<L>(bodies.velocities, &batch.a);
    let vb = pick::<L, FULL>(has_b, gather::<L>(bodies.velocities, &batch.b), V::ZERO);
    let (bias, mass_scale, impulse_scale) = contact_terms_wide(s, context);
    let vn = (va - vb).dot(n);
    let old_normal = batch.normal_impulse;
    let impulse = -m.mass * mass_scale * (vn + bias) - impulse_scale * old_normal;
    let total = (old_normal + impulse).max(L::ZERO);
    let applied = total - old_normal;
    let normal_impulse = total;
    // A contact that had no impulse and still gets no push (say a speculative one
    // whose gap this substep's motion does not close) changes nothing: it writes back
    // what it read (below), and a batch of such contacts is left at that. Most of a
    // pile's speculative contacts are such. Solving it would have clamped its friction
    // and rolling resistance to zero, changing only the signs of zeros (and, where the
    // sliding speed is below about 1e-22 m/s so that its square underflows, letting a
    // friction impulse of that order through).
    let idle =
        if context.use_bias { total.eq(L::ZERO).bits() & without_impulse(batch) & batch.active } else { 0 };
    if idle == batch.active {
        return;
    }
    let mut p = n.scale(applied);

    let rolls = m.lever_a.gt(L::ZERO).or(m.lever_b.gt(L::ZERO));
    let (turns_a, turns_b) = (m.ia.gt(L::ZERO), m.ib.gt(L::ZERO).and(has_b));
    let any_spin = FULL || (rolls.bits() & batch.active) != 0;
    let (mut spin_a, mut spin_b) = if any_spin {
        (
            gather::<L>(bodies.spins, &batch.a),
            pick::<L, FULL>(has_b, gather::<L>(bodies.spins, &batch.b), V::ZERO),
        )
    } else {
        (V::ZERO, V::ZERO)
    };
    let (spin_a_read, spin_b_read) = (spin_a, spin_b);

    let with_friction = m.friction.gt(L::ZERO);
    let mut tangent_impulse = batch.tangent_impulse;
    if FULL || (with_friction.bits() & batch.active) != 0 {
        // Velocities after the normal impulse, in registers.
        let mut v = (va + p.scale(m.wa)) - (vb - p.scale(m.wb));
        if any_spin {
            let spinning = spin_a.scale(m.lever_a) + spin_b.scale(m.lever_b);
            v = pick::<L, FULL>(rolls, v - spinning.cross(n), v);
        }
        let tangential = v - n.scale(v.dot(n));
        let old = batch.tangent_impulse;
        let mut total = old - tangential.scale(m.tangent_mass);
        let limit = m.friction * normal_impulse;
        let squared = total.dot(total);
        total = clamped(total, squared, limit);
        tangent_impulse = pick::<L, FULL>(with_friction, total, old);
        let friction = total - old;
        if any_spin {
            let (a, b) = turned(batch, m, spin_a, spin_b, friction, V::ZERO);
            let turning = with_friction.and(rolls);
            spin_a = pick::<L, FULL>(turning.and(turns_a), a, spin_a);
            spin_b = pick::<L, FULL>(turning.and(turns_b), b, spin_b);
        }
        p = pick::<L, FULL>(with_friction, p + friction, p);
    }

    let resisting = m.rolling.gt(L::ZERO);
    let mut rolling_impulse = batch.rolling_impulse;
    if FULL || (resisting.bits() & batch.active) != 0 {
        // Rolling resistance resists rolling, the relative spin about axes in the
        // contact plane, up to `μ_r r N`, static while it holds. Twist about the normal
        // is only damped ([`TWIST_TIME`]), up to a tenth of that torque
        // ([`TWIST_SHARE`]), and never held: DEM codes take the twist out of the
        // rolling torque. Holding the twist with the rolling limit held a grain in an
        // arch by three torques instead of two: an opening of 5 grains jammed in 2 of 5
        // random starts at any step (issue 39); held at a tenth of the limit, in 3 of
        // 15. Without any, a sphere spinning about the normal never stopped.
        let relative = spin_a - spin_b;
        let twist = relative.dot(n);
        let old = batch.rolling_impulse;
        let total = (old - n.scale(old.dot(n))) - (relative - n.scale(twist)).scale(m.rolling_mass);
        let limit = m.rolling * normal_impulse;
        let squared = total.dot(total);
        let total = clamped(total, squared, limit);
        // The twist's damping: implicit over the substep, fresh each substep (not
        // kept for the warm start, so it holds nothing), in the solve with feedback
        // only (the relax pass would damp twice).
        let twist_impulse = if context.use_bias {
            let twist_limit = L::splat(TWIST_SHARE) * limit;
            let damped = L::ZERO - twist * m.rolling_mass * L::splat(context.h / (TWIST_TIME + context.h));
            -((-damped.max(-twist_limit)).max(-twist_limit))
        } else {
            L::ZERO
        };
        rolling_impulse = pick::<L, FULL>(resisting, total, old);
        let (a, b) = turned(batch, m, spin_a, spin_b, V::ZERO, total - old + n.scale(twist_impulse));
        spin_a = pick::<L, FULL>(resisting.and(turns_a), a, spin_a);
        spin_b = pick::<L, FULL>(resisting.and(turns_b), b, spin_b);
    }

    let (mut va_new, mut vb_new) = (va + p.scale(m.wa), vb - p.scale(m.wb));
    if context.use_bias && idle == 0 {
        batch.normal_impulse = normal_impulse;
        batch.tangent_impulse = tangent_impulse;
        batch.rolling_impulse = rolling_impulse;
    } else {
        // The lanes that change nothing: skipped by the relax pass, idle in the solve.
        let keep = if context.use_bias { L::Mask::from_bits(idle) } else { skip };
        batch.normal_impulse = keep.select(old_normal, normal_impulse);
        batch.tangent_impulse = V::select(keep, batch.tangent_impulse, tangent_impulse);
        batch.rolling_impulse = V::select(keep, batch.rolling_impulse, rolling_impulse);
        // Such a lane writes back what it read (the same bits; no other contact of the
        // colour touches its particles): cheaper than leaving it out, since which
        // lanes keep changes from batch to batch and each left-out lane is a branch.
        (va_new, vb_new) = (V::select(keep, va, va_new), V::select(keep, vb, vb_new));
        (spin_a, spin_b) = (V::select(keep, spin_a_read, spin_a), V::select(keep, spin_b_read, spin_b));
    }
    let active = batch.active;
    scatter::<L>(bodies.velocities, &batch.a, active & positive(m.wa), va_new);
    scatter::<L>(bodies.velocities, &batch.b, active & batch.has_b & positive(m.wb), vb_new);
    if any_spin {
        scatter::<L>(bodies.spins, &batch.a, active & turns_a.bits(), spin_a);
        scatter::<L>(bodies.spins, &batch.b, active & turns_b.bits(), spin_b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::wide::{F4, V4};

    /// The warm start applies a contact's impulses to both its particles, and a
    /// contact without any impulse writes nothing: its particles keep their
    /// velocities and spins bit for bit, a -0 included (adding zero would make it +0),
    /// in a batch beside contacts that push and in a batch of such contacts alone.
    #[test]
    fn a_contact_without_impulse_leaves_its_particles_alone_in_the_warm_start() {
        let still = Vec3::new(-0.0, 1.0, -0.0);
        let mut velocities = vec![still; 16];
        let mut spins = vec![Vec3::new(-0.0, 0.0, -0.0); 16];
        let delta = vec![Vec3::ZERO; 16];
        // Four contacts between particles 0-1, 2-3, 4-5 and 6-7; those of lanes 1 and
        // 3 carry no impulse (zeros of either sign).
        let batch = ContactBatch {
            active: 0b1111,
            has_b: 0b1111,
            full: true,
            a: [0, 2, 4, 6],
            b: [1, 3, 5, 7],
            normal: V4::new([Vec3::Y; 4]),
            normal_impulse: F4::new([1.0, 0.0, 0.5, -0.0]),
            tangent_impulse: V4::new([Vec3::X * 0.25, Vec3::ZERO, Vec3::ZERO, Vec3::new(-0.0, 0.0, -0.0)]),
            ..ContactBatch::default()
        };
        let material = Material {
            lever_a: F4::splat(0.5),
            lever_b: F4::splat(0.5),
            wa: F4::splat(1.0),
            wb: F4::splat(0.5),
            ia: F4::splat(2.0),
            ib: F4::splat(4.0),
            ..Material::default()
        };
        {
            let bodies = Bodies {
                velocities: SharedVelocities::new(&mut velocities),
                spins: SharedVelocities::new(&mut spins),
                delta: &delta,
            };
            // The same four contacts on particles 8 to 15, none with an impulse.
            let idle = ContactBatch {
                a: batch.a.map(|i| i + 8),
                b: batch.b.map(|i| i + 8),
                normal_impulse: F4::new([0.0, -0.0, 0.0, -0.0]),
                tangent_impulse: V4::new([Vec3::ZERO; 4]),
                ..batch
            };
            warm_start_batches(&mut [batch, idle], &[material], bodies);
        }
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        for i in [2, 3, 6, 7].into_iter().chain(8..16) {
            assert_eq!(bits(velocities[i]), bits(still), "particle {i}'s velocity");
            assert_eq!(bits(spins[i]), bits(Vec3::new(-0.0, 0.0, -0.0)), "particle {i}'s spin");
        }
        // Lane 0: the impulse (0.25, 1, 0) pushes `a` by 1/kg and `b` back by 0.5/kg;
        // the friction part turns both, by the lever times n × P, over the inertia.
        assert_eq!(velocities[0], Vec3::new(0.25, 2.0, 0.0));
        assert_eq!(velocities[1], Vec3::new(-0.125, 0.5, 0.0));
        assert_eq!(spins[0], Vec3::new(0.0, 0.0, 0.25));
        assert_eq!(spins[1], Vec3::new(0.0, 0.0, 0.5));
        // Lane 2: the normal impulse alone.
        assert_eq!(velocities[4], Vec3::new(0.0, 1.5, 0.0));
        assert_eq!(velocities[5], Vec3::new(0.0, 0.75, 0.0));
    }

    /// In the solve, a contact that had no impulse and gets none (a gap that this
    /// substep's motion does not close) writes nothing: its particles keep their
    /// velocities and spins and it keeps its impulses, bit for bit (zeros of either
    /// sign included), whether it shares its batch with a contact that pushes or not,
    /// and however many batches are joined (five batches: four joined into sixteen
    /// lanes with AVX-512, or two pairs of eight with AVX, and one alone, half full).
    /// A contact with no normal impulse but a friction impulse left over (a hand-made
    /// snapshot can hold one) is not idle: its friction is taken back.
    #[test]
    fn a_contact_that_stays_without_impulse_changes_nothing_in_the_solve() {
        let h = 1.0 / 240.0;
        let context = Context {
            h,
            inv_h: 1.0 / h,
            max_push: 3.0,
            soft: crate::physics::solver::settings::Softness::new(30.0, 10.0, h),
            use_bias: true,
        };
        let apart = Vec3::new(-0.0, 0.5, -0.0);
        let resting = Vec3::new(-0.0, -0.0, -0.0);
        let spin = Vec3::new(-0.0, 0.0, -0.0);
        let zero = Vec3::new(-0.0, 0.0, -0.0);
        let left_over = Vec3::X * 0.3;
        // Batch `k` joins particles 8k + 2i and 8k + 2i + 1 in lane i. Lane 0 of batch
        // 0 overlaps and closes when `first_pushes`; every other lane is 0.5 m apart
        // and opening. Lane 2 holds a friction impulse with no normal one; lane 3 a
        // normal impulse of -0. Batch 4 holds two contacts only.
        let batch = |k: u32, first_pushes: bool| ContactBatch {
            active: if k == 4 { 0b0011 } else { 0b1111 },
            has_b: 0b1111,
            full: true,
            a: [0, 2, 4, 6].map(|i| 8 * k + i),
            b: [1, 3, 5, 7].map(|i| 8 * k + i),
            normal: V4::new([Vec3::Y; 4]),
            separation: F4::new([if first_pushes && k == 0 { -0.01 } else { 0.5 }, 0.5, 0.5, 0.5]),
            normal_impulse: F4::new([0.0, 0.0, 0.0, -0.0]),
            tangent_impulse: V4::new([zero, zero, left_over, zero]),
            rolling_impulse: V4::new([zero; 4]),
            // Batch 2 of its own material, equal to the rest's: the joined material of
            // the next four is made again.
            material: u32::from(k == 2),
        };
        let material = Material {
            friction: F4::splat(0.5),
            mass: F4::splat(0.5),
            tangent_mass: F4::splat(0.2),
            lever_a: F4::splat(0.5),
            lever_b: F4::splat(0.5),
            rolling: F4::splat(0.025),
            rolling_mass: F4::splat(0.05),
            wa: F4::splat(1.0),
            wb: F4::splat(1.0),
            ia: F4::splat(10.0),
            ib: F4::splat(10.0),
        };
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        for first_pushes in [true, false] {
            let mut velocities: Vec<Vec3> =
                (0..40).map(|i| if i % 2 == 0 { apart } else { resting }).collect();
            velocities[0] = Vec3::new(0.0, -1.0, 0.0);
            let mut spins = vec![spin; 40];
            let delta = vec![Vec3::ZERO; 40];
            let mut batches: Vec<ContactBatch> = (0..5).map(|k| batch(k, first_pushes)).collect();
            {
                let bodies = Bodies {
                    velocities: SharedVelocities::new(&mut velocities),
                    spins: SharedVelocities::new(&mut spins),
                    delta: &delta,
                };
                solve_batches(&mut batches, &[material, material], true, bodies, context);
            }
            for (k, solved) in batches.iter().enumerate() {
                let (normal, tangents) = (solved.normal_impulse.to_array(), solved.tangent_impulse.lanes());
                let rolling = solved.rolling_impulse.lanes();
                let lanes = if k == 4 { 2 } else { 4 };
                for lane in 0..lanes {
                    let (a, b) = (8 * k + 2 * lane, 8 * k + 2 * lane + 1);
                    let at = format!("batch {k} lane {lane}");
                    if k == 0 && lane == 0 {
                        if first_pushes {
                            // The overlapping pair is pushed apart: a up, b down.
                            assert!(normal[0] > 0.0, "{at} pushes: {}", normal[0]);
                            assert!(velocities[a].y > -1.0 && velocities[b].y < 0.0, "{velocities:?}");
                        } else {
                            // Closing 0.5 m at 1 m/s does not touch within the substep.
                            assert_eq!(bits(velocities[a]), bits(Vec3::new(0.0, -1.0, 0.0)), "{at}");
                            assert_eq!(normal[0].to_bits(), 0.0f32.to_bits(), "{at}");
                        }
                        continue;
                    }
                    if lane == 2 && k < 4 {
                        // The left-over friction is clamped to the zero normal impulse:
                        // taken back from both particles, which it turns too.
                        assert_eq!(tangents[lane].length(), 0.0, "{at}");
                        assert_eq!(velocities[a], Vec3::new(-0.3, 0.5, 0.0), "{at}");
                        assert_eq!(velocities[b], Vec3::new(0.3, 0.0, 0.0), "{at}");
                        assert!(spins[a].z != 0.0 && spins[b].z != 0.0, "{at}: {:?}", (spins[a], spins[b]));
                        continue;
                    }
                    assert_eq!(bits(velocities[a]), bits(apart), "{at}: a's velocity");
                    assert_eq!(bits(velocities[b]), bits(resting), "{at}: b's velocity");
                    assert_eq!(bits(spins[a]), bits(spin), "{at}: a's spin");
                    assert_eq!(bits(spins[b]), bits(spin), "{at}: b's spin");
                    let old_normal = if lane == 3 { -0.0f32 } else { 0.0 };
                    assert_eq!(normal[lane].to_bits(), old_normal.to_bits(), "{at}: normal impulse");
                    assert_eq!(bits(tangents[lane]), bits(zero), "{at}: friction impulse");
                    assert_eq!(bits(rolling[lane]), bits(zero), "{at}: rolling impulse");
                }
            }
        }
    }
}

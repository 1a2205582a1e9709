//! The contacts as the substeps solve them: four of one colour at a time, laid out lane
//! by lane (struct of arrays), the shape Box2D v3 gives its wide contact constraints.
//!
//! The four contacts of a batch share no movable particle (they are of one colour), so
//! their four solves are independent and run side by side in [`F4`] lanes; the overflow
//! colour, whose contacts may share particles, gets one contact per batch so that they
//! are still solved one after another. Everything a solve reads that does not change
//! within the step (indices, normals, masses, the particles' inverse masses and
//! inertias) is gathered here once a step; velocities, spins and motion are gathered
//! from the particles at every solve, since other contacts and the integrator move them.

use rayon::prelude::*;

use super::shared::Disjoint;
use super::{COLORS, NONE, OVERFLOW, SoftContact, SoftStep};
use crate::physics::particles::Particles;
#[cfg(target_arch = "x86_64")]
use crate::physics::wide::Joined;
use crate::physics::wide::{F4, Lane, Mask, V, V4};

/// Lanes of a batch.
pub(super) const LANES: usize = 4;
/// Contacts in all from which the batches are made, and their impulses copied back,
/// on several threads. Under Miri this and the run below are a few contacts, so that
/// its run of the tests reaches the threads (and `Disjoint::run`) at a size it can
/// interpret; which path runs changes no bit.
const PARALLEL_BATCHING: usize = if cfg!(miri) { 32 } else { 8192 };
/// Batches made (or copied back) one after another by one task.
const BATCH_RUN: usize = if cfg!(miri) { 4 } else { 256 };

/// The colour of batch `g` (the last colour whose first batch is at or before it),
/// stepping on from `color`, the colour of an earlier batch or 0.
#[inline]
fn color_of(batch_starts: &[usize; COLORS + 2], mut color: usize, g: usize) -> usize {
    while batch_starts[color + 1] <= g {
        color += 1;
    }
    color
}

/// Up to four contacts of one colour, lane by lane (`L` = [`F4`]); with AVX, two such
/// batches of one colour are joined into one of eight lanes ([`ContactBatch::join`]).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ContactBatch<L: Lane = F4> {
    /// Lanes holding a contact (bit `i`: lane `i`); the rest (inactive) repeat the last
    /// contact and are never written back.
    pub(super) active: u32,
    /// Lanes whose contact has a second particle (bit `i`: lane `i`).
    pub(super) has_b: u32,
    /// Every lane (the inactive ones repeat the last contact) is a pair of movable spheres
    /// that both roll, with friction and rolling resistance: the solve can skip the
    /// selects that keep a lane's old values where a part does not apply (most of a
    /// rolling pile's contacts).
    pub(super) full: bool,
    /// Dense index of each lane's particle `a`.
    pub(super) a: L::Index,
    /// Dense index of each lane's particle `b`, or `a`'s where it has none (read, then
    /// replaced by zero through `has_b`).
    pub(super) b: L::Index,
    pub(super) normal: V<L>,
    pub(super) separation: L,
    pub(super) friction: L,
    pub(super) mass: L,
    pub(super) tangent_mass: L,
    pub(super) lever_a: L,
    pub(super) lever_b: L,
    pub(super) rolling: L,
    pub(super) rolling_mass: L,
    /// Inverse masses of `a` and `b` (0 where there is no `b`) (1/kg).
    pub(super) wa: L,
    pub(super) wb: L,
    /// Inverse inertias of `a` and `b` (0 where there is no `b`) (1/(kg·m²)).
    pub(super) ia: L,
    pub(super) ib: L,
    pub(super) normal_impulse: L,
    pub(super) tangent_impulse: V<L>,
    pub(super) rolling_impulse: V<L>,
}

impl<L: Lane> ContactBatch<L> {
    /// `has_b` as a mask.
    #[inline(always)]
    pub(super) fn has_b_mask(&self) -> L::Mask {
        L::Mask::from_bits(self.has_b)
    }
}

/// A batch's impulses: normal, tangent and rolling.
#[cfg(target_arch = "x86_64")]
pub(super) type Impulses<L> = (L, V<L>, V<L>);

/// The impulses of the first half of the lanes, and of the second.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn split<W: Joined>((normal, tangent, rolling): Impulses<W>) -> [Impulses<W::Half>; 2] {
    let ((n0, n1), (t0, t1), (r0, r1)) = (normal.halves(), tangent.halves(), rolling.halves());
    [(n0, t0, r0), (n1, t1, r1)]
}

#[cfg(target_arch = "x86_64")]
impl<W: Joined> ContactBatch<W> {
    /// Two batches of one colour as one twice as wide: `low`'s lanes first, then
    /// `high`'s. Their contacts share no movable particle, so solving them side by side
    /// gives what solving the two in turn gives (eight lanes of two fours with AVX,
    /// sixteen of two eights with AVX-512).
    #[inline(always)]
    pub(super) fn join(low: &ContactBatch<W::Half>, high: &ContactBatch<W::Half>) -> Self {
        let (l, h) = (low, high);
        let shift = l.a.as_ref().len();
        Self {
            active: l.active | h.active << shift,
            has_b: l.has_b | h.has_b << shift,
            full: l.full && h.full,
            a: W::join_indices(l.a, h.a),
            b: W::join_indices(l.b, h.b),
            normal: V::join(l.normal, h.normal),
            separation: W::join(l.separation, h.separation),
            friction: W::join(l.friction, h.friction),
            mass: W::join(l.mass, h.mass),
            tangent_mass: W::join(l.tangent_mass, h.tangent_mass),
            lever_a: W::join(l.lever_a, h.lever_a),
            lever_b: W::join(l.lever_b, h.lever_b),
            rolling: W::join(l.rolling, h.rolling),
            rolling_mass: W::join(l.rolling_mass, h.rolling_mass),
            wa: W::join(l.wa, h.wa),
            wb: W::join(l.wb, h.wb),
            ia: W::join(l.ia, h.ia),
            ib: W::join(l.ib, h.ib),
            normal_impulse: W::join(l.normal_impulse, h.normal_impulse),
            tangent_impulse: V::join(l.tangent_impulse, h.tangent_impulse),
            rolling_impulse: V::join(l.rolling_impulse, h.rolling_impulse),
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl<L: Lane> ContactBatch<L> {
    /// The impulses, to be written back to the batches this one was joined from.
    #[inline(always)]
    pub(super) fn impulses(&self) -> Impulses<L> {
        (self.normal_impulse, self.tangent_impulse, self.rolling_impulse)
    }

    /// Sets the impulses (of a batch this one's wider copy was solved in).
    #[inline(always)]
    pub(super) fn set_impulses(&mut self, (normal, tangent, rolling): Impulses<L>) {
        (self.normal_impulse, self.tangent_impulse, self.rolling_impulse) = (normal, tangent, rolling);
    }
}

impl ContactBatch {
    /// A batch of `contacts` (1 to 4, lane by lane).
    fn new(contacts: &[SoftContact], particles: &Particles) -> Self {
        debug_assert!(!contacts.is_empty() && contacts.len() <= LANES);
        let last = contacts.len() - 1;
        let c: [&SoftContact; LANES] = [0, 1, 2, 3].map(|i| &contacts[i.min(last)]);
        let (w, inertia) = (&particles.inverse_mass, &particles.inverse_inertia);
        let column = |f: fn(&SoftContact) -> f32| F4::new(c.map(f));
        let of_b = |values: &[f32]| F4::new(c.map(|c| if c.b == NONE { 0.0 } else { values[c.b as usize] }));
        let has_b = (0..contacts.len()).filter(|&i| c[i].b != NONE).fold(0, |bits, i| bits | 1 << i);
        let full = c.iter().all(|c| {
            c.b != NONE
                && c.friction > 0.0
                && c.rolling > 0.0
                && [c.a, c.b].iter().all(|&p| w[p as usize] > 0.0 && inertia[p as usize] > 0.0)
        });
        Self {
            active: (1 << contacts.len()) - 1,
            has_b,
            full,
            a: c.map(|c| c.a),
            b: c.map(|c| if c.b == NONE { c.a } else { c.b }),
            normal: V4::new(c.map(|c| c.normal)),
            separation: column(|c| c.separation),
            friction: column(|c| c.friction),
            mass: column(|c| c.mass),
            tangent_mass: column(|c| c.tangent_mass),
            lever_a: column(|c| c.lever_a),
            lever_b: column(|c| c.lever_b),
            rolling: column(|c| c.rolling),
            rolling_mass: column(|c| c.rolling_mass),
            wa: F4::new(c.map(|c| w[c.a as usize])),
            wb: of_b(w),
            ia: F4::new(c.map(|c| inertia[c.a as usize])),
            ib: of_b(inertia),
            normal_impulse: column(|c| c.normal_impulse),
            tangent_impulse: V4::new(c.map(|c| c.tangent_impulse)),
            rolling_impulse: V4::new(c.map(|c| c.rolling_impulse)),
        }
    }
}

impl SoftStep {
    /// Lays the coloured contacts out in batches: each colour's contacts four at a
    /// time, the overflow's one at a time. `batch_starts[c]` is colour `c`'s first batch.
    pub(super) fn batch(&mut self, particles: &Particles) {
        let mut count = 0;
        for color in 0..=COLORS {
            self.batch_starts[color] = count;
            let contacts = self.color_starts[color + 1] - self.color_starts[color];
            count += if color == OVERFLOW { contacts } else { contacts.div_ceil(LANES) };
        }
        self.batch_starts[COLORS + 1] = count;
        // A batch that holds both pushing and waiting contacts counts as pushing.
        for color in 0..=COLORS {
            let pushing = self.waiting_contacts[color] - self.color_starts[color];
            let per_batch = if color == OVERFLOW { 1 } else { LANES };
            self.waiting_batches[color] = self.batch_starts[color] + pushing.div_ceil(per_batch);
        }
        // Every batch is written below: only growth needs filling.
        self.batches.resize(count, ContactBatch::default());
        // Each batch is made from its own contacts alone: threads change nothing but
        // the time.
        let (contacts, color_starts, batch_starts) = (&self.contacts, &self.color_starts, &self.batch_starts);
        let make = |color: usize, k: usize, (batch, origin): (&mut ContactBatch, &mut u32)| {
            let per_batch = if color == OVERFLOW { 1 } else { LANES };
            let first = color_starts[color] + k * per_batch;
            let last = (first + per_batch).min(color_starts[color + 1]);
            *batch = ContactBatch::new(&contacts[first..last], particles);
            *origin = contacts[first].origin;
        };
        // The solve reads and writes the lanes' particles without checking each index
        // again (`SharedVelocities::gather`): check them all once here.
        let n = particles.len() as u32;
        // One pass over every batch of every colour, a run of BATCH_RUN batches at a
        // time (on several threads for many contacts: a pile's colours are each too
        // small to share out alone), each batch's colour stepped on from the last.
        let make_run = |(k, (batches, origins)): (usize, (&mut [ContactBatch], &mut [u32]))| {
            let mut color = 0;
            for (g, (batch, origin)) in (k * BATCH_RUN..).zip(batches.iter_mut().zip(origins)) {
                color = color_of(batch_starts, color, g);
                make(color, g - batch_starts[color], (batch, origin));
                assert!(
                    batch.a.iter().chain(&batch.b).all(|&i| i < n),
                    "a contact names a particle beyond the {n} there are"
                );
            }
        };
        self.batch_origins.resize(count, 0);
        let origins = &mut self.batch_origins;
        if self.contacts.len() >= PARALLEL_BATCHING {
            let runs = self.batches.par_chunks_mut(BATCH_RUN).zip(origins.par_chunks_mut(BATCH_RUN));
            runs.enumerate().for_each(make_run);
        } else {
            let runs = self.batches.chunks_mut(BATCH_RUN).zip(origins.chunks_mut(BATCH_RUN));
            runs.enumerate().for_each(make_run);
        }
    }

    /// Copies the batches' impulses back into the contacts, for the warm start of the
    /// next step, sleeping and the debug view. Each batch writes its own contacts
    /// alone (a colour's contacts and its batches correspond in order), so large lists
    /// are copied on several threads, a run of [`BATCH_RUN`] batches per task: one
    /// fork for all the colours (a fork per colour cost a wake-up of the pool each).
    ///
    /// Returns the deepest overlap at the end of the step (m, +0 for none), from each
    /// contact's start separation and how far its particles moved, found while the
    /// batches are read anyway: a pass of its own over a falling pile's 390,000
    /// contacts took 5 ms of a 134 ms step on one thread.
    pub(super) fn unbatch(&mut self) -> f32 {
        let copy = |contacts: &mut [SoftContact], batch: &ContactBatch| {
            let normal = batch.normal_impulse.to_array();
            let (tangent, rolling) = (batch.tangent_impulse.lanes(), batch.rolling_impulse.lanes());
            for (i, c) in contacts.iter_mut().enumerate() {
                c.normal_impulse = normal[i];
                c.tangent_impulse = tangent[i];
                c.rolling_impulse = rolling[i];
            }
        };
        // The overlaps of a batch's contacts, as `SoftStep::deepest_overlap` computes
        // them from the contacts (the same operations, so the same bits).
        let delta = &self.delta;
        let deepest = |batch: &ContactBatch, lanes: usize| {
            let (normals, separations) = (batch.normal.lanes(), batch.separation.to_array());
            let mut deepest = 0.0f32;
            for lane in 0..lanes {
                let mut d = delta[batch.a[lane] as usize];
                if batch.has_b & 1 << lane != 0 {
                    d -= delta[batch.b[lane] as usize];
                }
                deepest = deepest.max(-(separations[lane] + d.dot(normals[lane])));
            }
            deepest
        };
        let parallel = self.contacts.len() >= PARALLEL_BATCHING;
        let (color_starts, batch_starts) = (&self.color_starts, &self.batch_starts);
        let contacts = Disjoint::new(&mut self.contacts);
        let unbatch_run = |(k, batches): (usize, &[ContactBatch])| {
            let mut color = 0;
            let mut deepest_of_run = 0.0f32;
            for (g, batch) in (k * BATCH_RUN..).zip(batches) {
                color = color_of(batch_starts, color, g);
                let per_batch = if color == OVERFLOW { 1 } else { LANES };
                let first = color_starts[color] + (g - batch_starts[color]) * per_batch;
                let last = (first + per_batch).min(color_starts[color + 1]);
                // SAFETY: batch `g`'s contacts are its own (no other batch's run), and
                // each batch is taken by one task.
                copy(unsafe { contacts.run(first..last) }, batch);
                deepest_of_run = deepest_of_run.max(deepest(batch, last - first));
            }
            deepest_of_run
        };
        // The largest of the same numbers in any order; a zero is reported as +0,
        // since `max` may give either of +0 and -0.
        let deepest = if parallel {
            self.batches.par_chunks(BATCH_RUN).enumerate().map(unbatch_run).reduce(|| 0.0, f32::max)
        } else {
            self.batches.chunks(BATCH_RUN).enumerate().map(unbatch_run).fold(0.0, f32::max)
        };
        if deepest == 0.0 { 0.0 } else { deepest }
    }
}

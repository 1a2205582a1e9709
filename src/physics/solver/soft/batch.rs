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

use super::collide::{Terms, terms};
use super::shared::Disjoint;
use super::{COLORS, NONE, OVERFLOW, SoftContact, SoftStep, Surface};
use crate::physics::particles::Particles;
#[cfg(target_arch = "x86_64")]
use crate::physics::wide::Joined;
use crate::physics::wide::{F4, Lane, Mask, V, V4};
use glam::Vec3;

/// What a run of batches is made into: its batches, their origins, its materials.
type RunOut<'a> = ((&'a mut [ContactBatch], &'a mut [u32]), &'a mut [Material]);

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
/// What its contacts are made of and weigh is its [`Material`], kept apart.
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
    /// The batch's [`Material`] in `SoftStep::materials` (unused in a joined batch).
    pub(super) material: u32,
    /// Dense index of each lane's particle `a`.
    pub(super) a: L::Index,
    /// Dense index of each lane's particle `b`, or `a`'s where it has none (read, then
    /// replaced by zero through `has_b`).
    pub(super) b: L::Index,
    pub(super) normal: V<L>,
    pub(super) separation: L,
    pub(super) normal_impulse: L,
    pub(super) tangent_impulse: V<L>,
    pub(super) rolling_impulse: V<L>,
}

/// What a batch's contacts are made of and how they weigh, lane by lane: the same for
/// most batches of a pile of like spheres, so a batch names one kept once per run of
/// batches (`SoftStep::batch`) instead of carrying its own. A pass over a 100,000-sphere
/// pile reads 56 bytes a contact instead of 100; the memory was what it waited for
/// (with 44 bytes a contact more, the passes took 29 to 39% longer).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub(super) struct Material<L: Lane = F4> {
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
}

impl Material {
    /// Whether every lane of every value has the same bits as `other`'s.
    #[inline]
    fn same(&self, other: &Material) -> bool {
        // SAFETY: a `Material` is eleven `F4`s, each 16 bytes of four f32 lanes with
        // no padding between or inside (`repr(C)`, the same size and alignment each),
        // so its bytes are all initialised, and are eleven u128s.
        let lanes = |m: &Material| unsafe { std::mem::transmute::<Material, [u128; 11]>(*m) };
        same_bits(&lanes(self), &lanes(other))
    }
}

#[cfg(target_arch = "x86_64")]
impl<W: Joined> Material<W> {
    /// Two materials as one twice as wide, `low`'s lanes first (see [`ContactBatch::join`]).
    #[inline(always)]
    pub(super) fn join(low: &Material<W::Half>, high: &Material<W::Half>) -> Self {
        let (l, h) = (low, high);
        Self {
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
        }
    }
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
            material: 0,
            a: W::join_indices(l.a, h.a),
            b: W::join_indices(l.b, h.b),
            normal: V::join(l.normal, h.normal),
            separation: W::join(l.separation, h.separation),
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

/// `[f(0), f(1), f(2), f(3)]`, in that order: one value per lane, written out so that
/// it is always inlined (an array's `map` with a closure was not, in the batch stage,
/// and cost a call per lane).
#[inline(always)]
fn lanes<T>(mut f: impl FnMut(usize) -> T) -> [T; LANES] {
    [f(0), f(1), f(2), f(3)]
}

impl ContactBatch {
    /// A batch of `contacts` (1 to 4, lane by lane), and its material: its generators'
    /// `surfaces`, and what follows from its particles ([`terms`]). A lane that does not
    /// roll carries no rolling impulse (it may have picked one up from last step, when
    /// it rolled).
    fn new(
        contacts: &[SoftContact],
        particles: &Particles,
        surfaces: &[Surface],
        known: &mut KnownTerms,
    ) -> (Self, Material) {
        debug_assert!(!contacts.is_empty() && contacts.len() <= LANES);
        let last = contacts.len() - 1;
        let c: [&SoftContact; LANES] = lanes(|i| &contacts[i.min(last)]);
        let surface = lanes(|i| surfaces[c[i].source as usize]);
        let t: [Terms; LANES] = lanes(|i| known.of(particles, c[i].a, c[i].b, surface[i].rolling_resistance));
        let (w, inertia) = (&particles.inverse_mass, &particles.inverse_inertia);
        let column = |f: fn(&SoftContact) -> f32| F4::new(lanes(|i| f(c[i])));
        let of_terms = |f: fn(&Terms) -> f32| F4::new(lanes(|i| f(&t[i])));
        let of_b =
            |values: &[f32]| F4::new(lanes(|i| if c[i].b == NONE { 0.0 } else { values[c[i].b as usize] }));
        let has_b = (0..contacts.len()).filter(|&i| c[i].b != NONE).fold(0, |bits, i| bits | 1 << i);
        let full = (0..LANES).all(|i| {
            c[i].b != NONE
                && surface[i].friction > 0.0
                && t[i].rolling > 0.0
                && [c[i].a, c[i].b].iter().all(|&p| w[p as usize] > 0.0 && inertia[p as usize] > 0.0)
        });
        let rolling_impulse = lanes(|i| if t[i].rolling > 0.0 { c[i].rolling_impulse } else { Vec3::ZERO });
        let batch = Self {
            active: (1 << contacts.len()) - 1,
            has_b,
            full,
            material: 0,
            a: lanes(|i| c[i].a),
            b: lanes(|i| if c[i].b == NONE { c[i].a } else { c[i].b }),
            normal: V4::new(lanes(|i| c[i].normal)),
            separation: column(|c| c.separation),
            normal_impulse: column(|c| c.normal_impulse),
            tangent_impulse: V4::new(lanes(|i| c[i].tangent_impulse)),
            rolling_impulse: V4::new(rolling_impulse),
        };
        let material = Material {
            friction: F4::new(lanes(|i| surface[i].friction)),
            mass: of_terms(|t| t.mass),
            tangent_mass: of_terms(|t| t.tangent_mass),
            lever_a: of_terms(|t| t.lever_a),
            lever_b: of_terms(|t| t.lever_b),
            rolling: of_terms(|t| t.rolling),
            rolling_mass: of_terms(|t| t.rolling_mass),
            wa: F4::new(lanes(|i| w[c[i].a as usize])),
            wb: of_b(w),
            ia: F4::new(lanes(|i| inertia[c[i].a as usize])),
            ib: of_b(inertia),
        };
        (batch, material)
    }
}

/// The [`terms`] of the last two different contacts a run of batches met, by what
/// they are made from: a pile of like spheres has two kinds of contact (two spheres, a
/// sphere and a wall), whose terms need working out once (five divisions a contact
/// made the batching 0.4 ms slower at 8,000 spheres, where they are most of its work).
#[derive(Clone, Copy, Default)]
struct KnownTerms {
    known: [Option<([u32; 7], Terms)>; 2],
    /// Which place the next new one takes.
    next: usize,
}

impl KnownTerms {
    /// [`terms`] of a contact of `a` and `b` with rolling resistance `coefficient`.
    #[inline]
    fn of(&mut self, particles: &Particles, a: u32, b: u32, coefficient: f32) -> Terms {
        let of_b = |values: &[f32]| if b == NONE { 0.0 } else { values[b as usize] };
        let (w, inertia, radius) = (&particles.inverse_mass, &particles.inverse_inertia, &particles.radius);
        // Everything `terms` reads, as bits.
        let from = [
            w[a as usize],
            of_b(w),
            inertia[a as usize],
            of_b(inertia),
            radius[a as usize],
            of_b(radius),
            coefficient,
        ]
        .map(f32::to_bits);
        for (known, terms) in self.known.iter().flatten() {
            if same_bits(known, &from) {
                return *terms;
            }
        }
        let new = terms(particles, a, b, coefficient);
        self.known[self.next] = Some((from, new));
        self.next = 1 - self.next;
        new
    }
}

/// Whether `a` and `b` hold the same bits: every bit that differs, or'ed together, which
/// compiles to a few instructions where `==` on arrays called the library to compare
/// memory (a call per batch made).
#[inline(always)]
fn same_bits<T, const N: usize>(a: &[T; N], b: &[T; N]) -> bool
where
    T: Copy + Default + PartialEq + std::ops::BitXor<Output = T> + std::ops::BitOr<Output = T>,
{
    a.iter().zip(b).fold(T::default(), |differ, (&x, &y)| differ | (x ^ y)) == T::default()
}

/// How many of the materials a run of batches has made are looked through, latest
/// first, for one equal to a new batch's before it gets its own.
const MATERIALS_SEARCHED: usize = 4;

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
        let surfaces = &self.surfaces;
        let make = |color: usize, k: usize, known: &mut KnownTerms| {
            let per_batch = if color == OVERFLOW { 1 } else { LANES };
            let first = color_starts[color] + k * per_batch;
            let last = (first + per_batch).min(color_starts[color + 1]);
            let (batch, material) = ContactBatch::new(&contacts[first..last], particles, surfaces, known);
            (batch, material, contacts[first].origin)
        };
        // The solve reads and writes the lanes' particles without checking each index
        // again (`SharedVelocities::gather`): check them all once here.
        let n = particles.len() as u32;
        // One pass over every batch of every colour, a run of BATCH_RUN batches at a
        // time (on several threads for many contacts: a pile's colours are each too
        // small to share out alone), each batch's colour stepped on from the last. Run
        // `k` keeps its materials in its own BATCH_RUN places from `k * BATCH_RUN`,
        // each once: a batch names an equal one made lately by its run (equal to the
        // bit), or a new one.
        let make_run = |(k, ((batches, origins), materials)): (usize, RunOut<'_>)| {
            let mut color = 0;
            let (mut made, mut last) = (0usize, 0usize);
            let mut known = KnownTerms::default();
            for (g, (batch, origin)) in (k * BATCH_RUN..).zip(batches.iter_mut().zip(origins)) {
                color = color_of(batch_starts, color, g);
                let (new, material, first) = make(color, g - batch_starts[color], &mut known);
                (*batch, *origin) = (new, first);
                assert!(
                    batch.a.iter().chain(&batch.b).all(|&i| i < n),
                    "a contact names a particle beyond the {n} there are"
                );
                // The material the batch before named first (most often the same), then
                // the latest made.
                // (Plain loops: `find` over a chain of candidates took a call per
                // candidate.)
                if !(last < made && materials[last].same(&material)) {
                    let mut found = None;
                    for j in (made.saturating_sub(MATERIALS_SEARCHED)..made).rev() {
                        if materials[j].same(&material) {
                            found = Some(j);
                            break;
                        }
                    }
                    last = found.unwrap_or_else(|| {
                        materials[made] = material;
                        made += 1;
                        made - 1
                    });
                }
                batch.material = (k * BATCH_RUN + last) as u32;
            }
        };
        self.batch_origins.resize(count, 0);
        self.materials.resize(count.div_ceil(BATCH_RUN) * BATCH_RUN, Material::default());
        let (origins, materials) = (&mut self.batch_origins, &mut self.materials);
        if self.contacts.len() >= PARALLEL_BATCHING {
            let runs = self.batches.par_chunks_mut(BATCH_RUN).zip(origins.par_chunks_mut(BATCH_RUN));
            runs.zip(materials.par_chunks_mut(BATCH_RUN)).enumerate().for_each(make_run);
        } else {
            let runs = self.batches.chunks_mut(BATCH_RUN).zip(origins.chunks_mut(BATCH_RUN));
            runs.zip(materials.chunks_mut(BATCH_RUN)).enumerate().for_each(make_run);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::particles::ParticleDesc;
    use crate::physics::solver::soft::FreshContact;

    /// Every batch names a material whose every lane is what its own contacts and
    /// particles give (read here from them, lane by lane), in its run's places. A pile
    /// of like spheres shares a few materials per run; contacts of mixed masses,
    /// inertias and friction get theirs. On one and two threads, above the size
    /// batched on several.
    #[test]
    #[cfg_attr(miri, ignore = "too slow to interpret; the state hashes cover the batches")]
    fn each_batch_names_the_material_of_its_contacts() {
        for alike in [true, false] {
            let (named, batches, runs) = batch_a_world(alike);
            if alike {
                assert!(named < batches / 10, "{named} materials for {batches} batches of like contacts");
            } else {
                assert!(named > batches / 2, "{named} materials for {batches} batches of mixed contacts");
            }
            assert!(named >= runs, "each run names its own");
        }
    }

    /// A contact picks up last step's rolling impulse whether or not it rolls now; its
    /// batch keeps it only where it rolls (rolling resistance turned off, or a sphere
    /// that stopped rolling, leaves none to warm-start with).
    #[test]
    fn a_contact_that_does_not_roll_carries_no_rolling_impulse() {
        let mut particles = Particles::new();
        for _ in 0..4 {
            particles.add(ParticleDesc { radius: 0.5, ..ParticleDesc::default() }).expect("a valid particle");
        }
        // Particles 0 and 1 roll; 2 and 3 do not.
        particles.inverse_inertia[..2].fill(10.0);
        let surfaces = [Surface { restitution: 0.0, friction: 0.5, rolling_resistance: 0.1 }];
        let spin = Vec3::new(0.0, 0.0, 0.25);
        let contact = |a, b| SoftContact { a, b, source: 0, rolling_impulse: spin, ..SoftContact::default() };
        let contacts = [contact(0, 1), contact(2, 3), contact(1, NONE), contact(3, NONE)];
        let (batch, material) =
            ContactBatch::new(&contacts, &particles, &surfaces, &mut KnownTerms::default());
        assert_eq!(batch.rolling_impulse.lanes(), [spin, Vec3::ZERO, spin, Vec3::ZERO]);
        assert_eq!(material.rolling.to_array().map(|r| r > 0.0), [true, false, true, false]);
    }

    /// Batches a world of contacts (all alike but for a few on the ground, or mixed) on
    /// one and two threads and checks each batch's material; the materials named, the
    /// batches and their runs.
    fn batch_a_world(alike: bool) -> (usize, usize, usize) {
        let mut particles = Particles::new();
        for i in 0..3000 {
            // Three masses, every seventh particle immovable, unless alike.
            let (mass, immovable) = if alike { (1.0, false) } else { ([1.0, 2.0, 5.0][i % 3], i % 7 == 0) };
            let radius = if alike { 0.5 } else { [0.5, 0.25][i % 2] };
            let desc = ParticleDesc { mass, immovable, radius, ..ParticleDesc::default() };
            particles.add(desc).expect("a valid particle");
        }
        // Spheres that roll, but not all alike.
        for (i, inertia) in particles.inverse_inertia.iter_mut().enumerate() {
            *inertia = if alike {
                10.0
            } else if i % 5 == 0 {
                0.0
            } else {
                10.0 + (i % 2) as f32
            };
        }
        let mut state = 7u64;
        let mut next = |n: u64| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 33) % n) as u32
        };
        let (w, inertia) = (particles.inverse_mass.clone(), particles.inverse_inertia.clone());
        let radius = particles.radius.clone();
        let mut step = SoftStep::default();
        // Generator 0 the common surface, 1 of another friction and rolling resistance.
        let surface =
            |friction, rolling_resistance| Surface { restitution: 0.0, friction, rolling_resistance };
        step.surfaces = vec![surface(0.5, 0.05), surface(0.3, 0.08)];
        while step.fresh.len() < 3 * PARALLEL_BATCHING {
            let (a, b) = (next(3000), next(3000));
            // One contact in fifty on the ground.
            let b = if next(50) == 0 { NONE } else { b };
            let movable = w[a as usize] > 0.0 || (b != NONE && w[b as usize] > 0.0);
            if b == a || !movable {
                continue;
            }
            // One in ten of another friction, unless alike.
            let source = u32::from(!alike && next(10) == 0);
            step.fresh.push(FreshContact { a, b, source, ..FreshContact::default() });
        }
        step.fresh_keys = step.fresh.iter().map(|c| super::super::warm::key(c.a, c.b)).collect();
        step.color(&particles);
        let mut named = std::collections::HashSet::new();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            pool.install(|| step.batch(&particles));
            named.clear();
            for color in 0..=COLORS {
                let per_batch = if color == OVERFLOW { 1 } else { LANES };
                for g in step.batch_starts[color]..step.batch_starts[color + 1] {
                    let batch = &step.batches[g];
                    let k = batch.material as usize;
                    assert_eq!(k / BATCH_RUN, g / BATCH_RUN, "batch {g} names a material of its own run");
                    named.insert(k);
                    let m = &step.materials[k];
                    let first = step.color_starts[color] + (g - step.batch_starts[color]) * per_batch;
                    let last = (first + per_batch).min(step.color_starts[color + 1]);
                    let contacts = &step.contacts[first..last];
                    for lane in 0..LANES {
                        // An empty lane repeats the last contact.
                        let c = &contacts[lane.min(contacts.len() - 1)];
                        let of_b = |values: &[f32]| if c.b == NONE { 0.0 } else { values[c.b as usize] };
                        // The contact's terms from its particles, as the narrow phase
                        // once stored them in each contact.
                        let (wa, wb, ia, ib) =
                            (w[c.a as usize], of_b(&w), inertia[c.a as usize], of_b(&inertia));
                        let mass = 1.0 / (wa + wb);
                        let la = if ia > 0.0 { radius[c.a as usize] } else { 0.0 };
                        let lb = if ib > 0.0 { of_b(&radius) } else { 0.0 };
                        let rolls = ia != 0.0 || ib != 0.0;
                        let tangent_mass =
                            if rolls { 1.0 / (1.0 / mass + ia * la * la + ib * lb * lb) } else { mass };
                        let rolling_radius =
                            if la > 0.0 && lb > 0.0 { la * lb / (la + lb) } else { la.max(lb) };
                        let (rolling, rolling_mass) = if rolls {
                            ([0.05, 0.08][c.source as usize] * rolling_radius, 1.0 / (ia + ib))
                        } else {
                            (0.0, 0.0)
                        };
                        let friction = [0.5, 0.3][c.source as usize];
                        let expected =
                            [friction, mass, tangent_mass, la, lb, rolling, rolling_mass, wa, wb, ia, ib];
                        let held = [
                            m.friction,
                            m.mass,
                            m.tangent_mass,
                            m.lever_a,
                            m.lever_b,
                            m.rolling,
                            m.rolling_mass,
                            m.wa,
                            m.wb,
                            m.ia,
                            m.ib,
                        ]
                        .map(|x| x.to_array()[lane]);
                        assert_eq!(
                            held.map(f32::to_bits),
                            expected.map(f32::to_bits),
                            "batch {g}, lane {lane}"
                        );
                    }
                }
            }
        }
        let batches = step.batches.len();
        (named.len(), batches, batches.div_ceil(BATCH_RUN))
    }
}

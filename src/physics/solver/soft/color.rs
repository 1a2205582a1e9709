//! Stage 2, colour: no two contacts of one colour share a movable particle, so a colour
//! is solved in parallel with the same result as in order. The colouring depends on the
//! contacts alone, never on the thread count.

use rayon::prelude::*;

use super::shared::Disjoint;
use super::{COLORS, FreshContact, NONE, OVERFLOW, SoftContact, SoftStep};
use crate::physics::particles::Particles;

/// Fresh contacts from which the greedy colouring runs beside the warm start's pick-up
/// (on two threads), rather than before it.
const PARALLEL_PICK_UP: usize = 4096;

impl SoftStep {
    /// Stage 2: greedy colouring in generation order, then a counting sort into
    /// `contacts`. Depends on the contacts alone, never on the thread count.
    ///
    /// The colouring reads each contact's particles from its key (8 bytes, see
    /// [`key`](super::warm::key)) rather than from the contact (88 bytes then, 60 now):
    /// this one serial pass then read a tenth of the memory (3 MB instead of 34 for a
    /// falling pile of 100,000 spheres, more than the processor's cache).
    ///
    /// The colouring is a function of the keys, in order, and of which particles are
    /// movable: when both are as they were for the last colouring (a pile at rest keeps
    /// its contacts from step to step), the last colours are used again, the same
    /// colours the greedy pass would give, and only the sort runs.
    ///
    /// The warm start's pick-up of last step's impulses
    /// ([`warm_start_from_last_step`](SoftStep::warm_start_from_last_step), for
    /// `generators` contact generators) comes first: the sort places the contacts that
    /// wait by what it finds. It reads the keys and the fresh contacts and writes where
    /// each one's impulses are, the greedy pass reads the keys alone, so with many
    /// contacts and several threads the serial greedy pass runs on one thread while the
    /// pick-up runs beside it (on the other, and on this one once the colours are
    /// done): the same colours and impulses, sooner.
    pub(super) fn pick_up_and_color(&mut self, particles: &Particles, generators: usize) {
        let w = &particles.inverse_mass;
        let recolor = !self.colors_still_hold(w);
        let keys = std::mem::take(&mut self.fresh_keys);
        if recolor && keys.len() >= PARALLEL_PICK_UP && rayon::current_num_threads() > 1 {
            let (mut masks, mut colors) = (std::mem::take(&mut self.masks), std::mem::take(&mut self.colors));
            let (starts, ()) = rayon::join(
                || color_greedily(&keys, w, &mut masks, &mut colors),
                || self.warm_start_from_last_step(&keys, generators),
            );
            (self.masks, self.colors, self.color_starts) = (masks, colors, starts);
        } else {
            self.warm_start_from_last_step(&keys, generators);
            if recolor {
                self.color_starts = color_greedily(&keys, w, &mut self.masks, &mut self.colors);
            }
        }
        self.fresh_keys = keys;
        self.finish_coloring(w, recolor);
    }

    /// [`pick_up_and_color`](SoftStep::pick_up_and_color) without a pick-up (the
    /// contacts keep the impulses they hold), for tests of the colouring.
    #[cfg(test)]
    pub(super) fn color(&mut self, particles: &Particles) {
        let w = &particles.inverse_mass;
        let recolor = !self.colors_still_hold(w);
        if recolor {
            self.color_starts = color_greedily(&self.fresh_keys, w, &mut self.masks, &mut self.colors);
        }
        self.finish_coloring(w, recolor);
    }

    /// Whether the last colouring holds for the fresh keys: they, and which particles
    /// are movable, are as they were then.
    fn colors_still_hold(&self, w: &[f32]) -> bool {
        self.fresh_keys == self.colored_keys
            && self.colored_movable.len() == w.len()
            && w.iter().zip(&self.colored_movable).all(|(&w, &movable)| (w > 0.0) == movable)
    }

    /// After the colours are known (`recolored`: made afresh for the fresh keys): note
    /// what they were made for, and sort the contacts by them.
    fn finish_coloring(&mut self, w: &[f32], recolored: bool) {
        debug_assert_eq!(self.colors.len(), self.fresh.len(), "a colour per fresh contact");
        if recolored {
            self.colored_keys.clone_from(&self.fresh_keys);
            self.colored_movable.clear();
            self.colored_movable.extend(w.iter().map(|&w| w > 0.0));
        }
        self.sort_by_color();
        debug_assert!(
            colours_are_disjoint(&self.contacts, &self.color_starts, w),
            "a colour holds two contacts of one movable particle"
        );
    }
}

/// The greedy colouring of the contacts of `keys`, in order: each contact's colour into
/// `colors` (`masks`: per particle, the colours it has taken), and where each colour's
/// run will start once sorted.
fn color_greedily(
    keys: &[u64],
    w: &[f32],
    masks: &mut Vec<u32>,
    colors: &mut Vec<u8>,
) -> [usize; COLORS + 2] {
    masks.clear();
    masks.resize(w.len(), 0);
    colors.clear();
    let mut counts = [0usize; COLORS + 1];
    for &key in keys {
        let (a, b) = ((key >> 32) as usize, key as u32);
        let movable_a = w[a] > 0.0;
        let movable_b = b != NONE && w[b as usize] > 0.0;
        let b = b as usize;
        let mut used = if movable_a { masks[a] } else { 0 };
        if movable_b {
            used |= masks[b];
        }
        let color = (!used).trailing_zeros() as usize;
        let color = if color < COLORS {
            let bit = 1u32 << color;
            if movable_a {
                masks[a] |= bit;
            }
            if movable_b {
                masks[b] |= bit;
            }
            color
        } else {
            OVERFLOW
        };
        colors.push(color as u8);
        counts[color] += 1;
    }
    let mut starts = [0; COLORS + 2];
    for (c, &count) in counts.iter().enumerate() {
        starts[c + 1] = starts[c] + count;
    }
    starts
}

/// Fresh contacts a counting-sort task places (see [`SoftStep::sort_by_color`]).
/// Under Miri this and the size below are a few contacts, so that its run of the tests
/// reaches the threads (and `Disjoint::run`) at a size it can interpret; which path
/// runs changes no bit.
const SORT_CHUNK: usize = if cfg!(miri) { 16 } else { 8192 };
/// Contacts from which the counting sort runs on several threads.
const PARALLEL_SORT: usize = if cfg!(miri) { 32 } else { 8192 };
/// The counting sort's buckets: two per colour, the contacts that push first, then
/// those that wait (see [`bucket`]).
const BUCKETS: usize = 2 * (COLORS + 1);

/// A fresh contact's bucket in the counting sort: `2 × colour`, plus one for a contact
/// of a colour (not the overflow) that starts the step apart and pushed nothing last
/// step. Such a contact is only speculative, and usually stays so through the step:
/// placed after the rest of its colour, it shares its batches with its like, and the
/// relax pass can pass over a batch whose every contact has not touched (see
/// `solve_batch`). A pile at rest holds about 40% of them. A colour's contacts share
/// no movable particle, so their order within it changes no result.
#[inline]
fn bucket(color: u8, waits: bool) -> usize {
    2 * color as usize + usize::from(waits && color as usize != OVERFLOW)
}

/// A chunk of the counting sort: its index, fresh contacts, where their impulses of
/// last step are, their colours, whether they wait, where they go (written), and the
/// chunk's first slot in each bucket.
type SortChunk<'a> = (
    usize,
    (((((&'a [FreshContact], &'a [u32]), &'a [u8]), &'a [bool]), &'a mut [u32]), &'a [usize; BUCKETS]),
);

impl SoftStep {
    /// The counting sort of stage 2: every fresh contact to its colour's run, in
    /// generation order within each of the colour's two [`bucket`]s, tagged with its
    /// origin and given the impulses the pick-up found for it
    /// ([`with_impulses`](SoftStep::with_impulses)); `slots` says where each went. The
    /// fresh list is cut into chunks of [`SORT_CHUNK`]; each chunk counts its buckets,
    /// the prefix sums give each chunk its slots in every bucket, and the chunks then
    /// place their contacts at once: the same list as placing them one by one.
    fn sort_by_color(&mut self) {
        let n = self.fresh.len();
        // Every slot is written below: only growth needs filling.
        self.contacts.resize(n, SoftContact::default());
        self.slots.resize(n, 0);
        // A step marks every fresh contact (`warm_start_from_last_step`); where they
        // were not marked (a test colouring contacts by hand), none waits.
        if self.waits.len() != n {
            self.waits.clear();
            self.waits.resize(n, false);
        }
        // Nor, then, were last step's impulses looked for.
        if self.picked.len() != n {
            self.picked.clear();
            self.picked.resize(n, NONE);
        }
        let chunks = n.div_ceil(SORT_CHUNK);
        self.chunk_starts.clear();
        self.chunk_starts.resize(chunks, [0; BUCKETS]);
        let parallel = n >= PARALLEL_SORT;
        let count = |((starts, colors), waits): ((&mut [usize; BUCKETS], &[u8]), &[bool])| {
            for (&color, &waits) in colors.iter().zip(waits) {
                starts[bucket(color, waits)] += 1;
            }
        };
        if parallel {
            let chunked = self.chunk_starts.par_iter_mut().zip(self.colors.par_chunks(SORT_CHUNK));
            chunked.zip(self.waits.par_chunks(SORT_CHUNK)).for_each(count);
        } else {
            let chunked = self.chunk_starts.iter_mut().zip(self.colors.chunks(SORT_CHUNK));
            chunked.zip(self.waits.chunks(SORT_CHUNK)).for_each(count);
        }
        // Each bucket's first slot: a colour's first bucket at the colour's start, its
        // second after all of the first.
        let mut cursor = [0; BUCKETS];
        for color in 0..=COLORS {
            let first: usize = self.chunk_starts.iter().map(|starts| starts[2 * color]).sum();
            cursor[2 * color] = self.color_starts[color];
            cursor[2 * color + 1] = self.color_starts[color] + first;
            self.waiting_contacts[color] = self.color_starts[color] + first;
        }
        // Counts to first slots: bucket by bucket, chunk after chunk.
        for starts in &mut self.chunk_starts {
            for (start, next) in starts.iter_mut().zip(&mut cursor) {
                let count = *start;
                *start = *next;
                *next += count;
            }
        }
        let out = Disjoint::new(&mut self.contacts);
        let warm = &self.warm;
        let place = |(k, (((((fresh, picked), colors), waits), slots), starts)): SortChunk<'_>| {
            let mut cursor = *starts;
            let tagged = fresh.iter().zip(picked).zip(colors).zip(waits);
            for (i, ((((contact, &picked), &color), &waits), slot)) in tagged.zip(slots).enumerate() {
                let next = &mut cursor[bucket(color, waits)];
                let origin = (k * SORT_CHUNK + i) as u32;
                // SAFETY: `next` lies in this chunk's run of slots of its bucket (see
                // `Disjoint`), and is used once.
                let placed = unsafe { out.run(*next..*next + 1) };
                placed[0] = SoftStep::with_impulses(warm, contact, picked, origin);
                *slot = *next as u32;
                *next += 1;
            }
        };
        let (fresh, colors, starts) = (&self.fresh, &self.colors, &self.chunk_starts);
        let (waits, picked) = (&self.waits, &self.picked);
        if parallel {
            fresh
                .par_chunks(SORT_CHUNK)
                .zip(picked.par_chunks(SORT_CHUNK))
                .zip(colors.par_chunks(SORT_CHUNK))
                .zip(waits.par_chunks(SORT_CHUNK))
                .zip(self.slots.par_chunks_mut(SORT_CHUNK))
                .zip(starts.par_iter())
                .enumerate()
                .for_each(place);
        } else {
            fresh
                .chunks(SORT_CHUNK)
                .zip(picked.chunks(SORT_CHUNK))
                .zip(colors.chunks(SORT_CHUNK))
                .zip(waits.chunks(SORT_CHUNK))
                .zip(self.slots.chunks_mut(SORT_CHUNK))
                .zip(starts.iter())
                .enumerate()
                .for_each(place);
        }
    }
}

/// Whether every colour but the overflow holds each movable particle at most once: the
/// invariant `shared::SharedVelocities` rests on. Allocates; debug builds and tests only.
fn colours_are_disjoint(contacts: &[SoftContact], starts: &[usize; COLORS + 2], w: &[f32]) -> bool {
    // Per particle, the last colour it was seen in plus one (0: not yet).
    let mut seen = vec![0usize; w.len()];
    for color in 0..COLORS {
        for contact in &contacts[starts[color]..starts[color + 1]] {
            let ends = if contact.b == NONE { [contact.a, NONE] } else { [contact.a, contact.b] };
            for i in ends.into_iter().filter(|&i| i != NONE && w[i as usize] > 0.0) {
                if seen[i as usize] == color + 1 {
                    return false;
                }
                seen[i as usize] = color + 1;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::particles::ParticleDesc;

    fn contact(a: u32, b: u32) -> FreshContact {
        FreshContact { a, b, ..FreshContact::default() }
    }

    /// The keys of a step's fresh contacts, as the collide stage makes them.
    fn keys_of(step: &mut SoftStep) {
        step.fresh_keys = step.fresh.iter().map(|c| super::super::warm::key(c.a, c.b)).collect();
    }

    /// A fan of contacts on particle 0 and a chain through the rest, with an immovable
    /// particle (1) in many: every colour keeps each movable particle once, and a
    /// colouring that breaks that is caught.
    #[test]
    fn each_movable_particle_appears_once_per_colour() {
        let mut particles = Particles::new();
        for i in 0..40 {
            let desc = ParticleDesc { immovable: i == 1, ..ParticleDesc::default() };
            particles.add(desc).expect("a valid particle");
        }
        let mut step = SoftStep::default();
        step.fresh.extend((2..40).map(|i| contact(0, i)));
        step.fresh.extend((2..39).map(|i| contact(i, i + 1)));
        step.fresh.extend((2..40).map(|i| contact(1, i)));
        step.fresh.extend((0..40).map(|i| contact(i, NONE)));
        keys_of(&mut step);
        step.color(&particles);
        let w = &particles.inverse_mass;
        assert!(colours_are_disjoint(&step.contacts, &step.color_starts, w));
        // Particle 0 has 38 contacts, more than the colours: the rest overflowed.
        assert!(step.color_starts[OVERFLOW + 1] > step.color_starts[OVERFLOW]);

        let mut starts = [0; COLORS + 2];
        starts[1..].fill(2);
        let sorted = |a: u32, b: u32| SoftContact { a, b, ..SoftContact::default() };
        let both_on_three = [sorted(3, 4), sorted(5, 3)];
        assert!(!colours_are_disjoint(&both_on_three, &starts, w));
        let both_on_the_immovable = [sorted(1, 4), sorted(5, 1)];
        assert!(colours_are_disjoint(&both_on_the_immovable, &starts, w));
    }

    /// Colouring the same keys again keeps the colours (and a fresh step's contacts
    /// are placed by them); a particle made immovable, or different keys, colour
    /// afresh: in every case the colours are those a new solver would give.
    #[test]
    fn colours_are_kept_only_while_keys_and_movable_particles_are() {
        let mut particles = Particles::new();
        let ids: Vec<_> =
            (0..12).map(|_| particles.add(ParticleDesc::default()).expect("a valid particle")).collect();
        let fan = |step: &mut SoftStep, last: u32| {
            step.fresh.clear();
            step.fresh.extend((1..last).map(|i| contact(0, i)));
            step.fresh.extend((1..last - 1).map(|i| contact(i, i + 1)));
            keys_of(step);
        };
        let afresh = |particles: &Particles, last: u32| {
            let mut step = SoftStep::default();
            fan(&mut step, last);
            step.color(particles);
            (step.colors, step.color_starts)
        };
        let mut step = SoftStep::default();
        fan(&mut step, 12);
        step.color(&particles);
        let first = (step.colors.clone(), step.color_starts);
        assert_eq!(first, afresh(&particles, 12));
        // The same keys: the same colours, and this step's contacts placed by them.
        fan(&mut step, 12);
        step.fresh[3].separation = 0.25;
        step.color(&particles);
        assert_eq!((step.colors.clone(), step.color_starts), first);
        assert_eq!(step.contacts[step.slots[3] as usize].separation, 0.25);
        // Particle 0 made immovable: its fan no longer needs a colour each.
        particles.set_movable(ids[0], None).expect("particle 0 exists");
        fan(&mut step, 12);
        step.color(&particles);
        let pinned = (step.colors.clone(), step.color_starts);
        assert_ne!(pinned, first, "the colouring depends on particle 0 being movable");
        assert_eq!(pinned, afresh(&particles, 12));
        // Fewer contacts: new keys, coloured afresh.
        fan(&mut step, 9);
        step.color(&particles);
        assert_eq!((step.colors.clone(), step.color_starts), afresh(&particles, 9));
    }

    /// The counting sort on several threads (above [`PARALLEL_SORT`], chunk by chunk)
    /// places every contact where placing them one by one in generation order does,
    /// tags it with its origin, and `slots` points back at it. (Under Miri, whose
    /// sizes are smaller, a hundred contacts on 60 particles.)
    #[test]
    fn the_parallel_counting_sort_is_the_one_by_one_sort() {
        let (n, contacts) = if cfg!(miri) { (60, 3 * PARALLEL_SORT + 5) } else { (3000, 45_000) };
        let mut particles = Particles::new();
        for _ in 0..n {
            particles.add(ParticleDesc::default()).expect("a valid particle");
        }
        let mut step = SoftStep::default();
        // 45,000 contacts over 3,000 particles, in a scrambled but fixed order, some of
        // them with a plane.
        let mut state = 12345u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 33) as u32
        };
        for _ in 0..contacts {
            let a = next() % n;
            let b = next() % n;
            step.fresh.push(if b == a || b % 17 == 0 { contact(a, NONE) } else { contact(a, b) });
        }
        assert!(step.fresh.len() >= PARALLEL_SORT + SORT_CHUNK);
        keys_of(&mut step);
        // About a third wait (as the step marks them: see `warm_start_from_last_step`).
        step.waits = (0..step.fresh.len()).map(|_| next() % 3 == 0).collect();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        pool.install(|| step.color(&particles));

        // One by one: each colour's contacts in generation order.
        let mut expected = Vec::new();
        // Those that wait after the rest of their colour (not in the overflow).
        for color in 0..=COLORS {
            for waiting in [false, true] {
                if color == OVERFLOW && waiting {
                    continue;
                }
                for (origin, fresh) in step.fresh.iter().enumerate() {
                    let waits = step.waits[origin] && color != OVERFLOW;
                    if step.colors[origin] as usize == color && waits == waiting {
                        expected.push((origin as u32, fresh.a, fresh.b));
                    }
                }
            }
            let pushing = (0..step.fresh.len())
                .filter(|&i| step.colors[i] as usize == color && !(step.waits[i] && color != OVERFLOW))
                .count();
            assert_eq!(step.waiting_contacts[color], step.color_starts[color] + pushing, "colour {color}");
        }
        let placed: Vec<_> = step.contacts.iter().map(|c| (c.origin, c.a, c.b)).collect();
        assert_eq!(placed, expected);
        let waiting = step.waits.iter().filter(|&&w| w).count();
        assert!(waiting * 9 > 2 * contacts && waiting * 9 < 5 * contacts, "{waiting} of the contacts wait");
        assert!(step.color_starts[OVERFLOW] > step.color_starts[1], "more than one colour used");
        for (origin, &slot) in step.slots.iter().enumerate() {
            assert_eq!(step.contacts[slot as usize].origin as usize, origin);
        }
        assert!(colours_are_disjoint(&step.contacts, &step.color_starts, &particles.inverse_mass));
    }
}

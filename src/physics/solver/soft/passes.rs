//! A pass over the batches, colour by colour, on every thread of the pool: each
//! thread's share of each colour (made once a step, after the batches), the pass
//! itself, and the wait between colours.

use super::batch::{ContactBatch, LANES};
use super::shared::Disjoint;
use super::{COLORS, OVERFLOW, SoftStep};

/// Contacts in all from which a pass over them runs on several threads (a few under
/// Miri, so that its run of the tests reaches [`run_on_all_threads`] at a size it can
/// interpret; which path runs changes no bit).
const PARALLEL_CONTACTS: usize = if cfg!(miri) { 16 } else { 2048 };

impl SoftStep {
    /// Each thread's share of each colour but the overflow, for the passes of this step
    /// (none on one thread): made from the batches just laid out (`SoftStep::batch`).
    pub(super) fn share_out(&mut self) {
        let threads = rayon::current_num_threads();
        self.shares.clear();
        if threads > 1 {
            for color in 0..OVERFLOW {
                let colour = self.batch_starts[color]..self.batch_starts[color + 1];
                let (wait, origins) = (self.waiting_batches[color], &self.batch_origins);
                debug_assert!(
                    [colour.start..wait, wait..colour.end]
                        .iter()
                        .all(|part| origins[part.clone()].is_sorted()),
                    "each part of a colour lists its batches in the order they were made"
                );
                self.shares.extend(share(colour, wait, origins, threads));
            }
            debug_assert!(self.shares_tile_the_colours(threads), "the threads' shares tile each colour");
        }
    }

    /// Whether the threads' shares of each colour are runs, in order, that together
    /// cover its pushing part and then its waiting part once (what
    /// `run_on_all_threads` hands out as disjoint). Debug builds check it every step.
    fn shares_tile_the_colours(&self, threads: usize) -> bool {
        (0..OVERFLOW).all(|color| {
            let shares = &self.shares[color * threads..(color + 1) * threads];
            let wait = self.waiting_batches[color];
            let mut at = (self.batch_starts[color], wait);
            for [push, waits] in shares {
                if push.start != at.0
                    || waits.start != at.1
                    || push.end < push.start
                    || waits.end < waits.start
                {
                    return false;
                }
                at = (push.end, waits.end);
            }
            at == (wait, self.batch_starts[color + 1])
        })
    }
}

/// Runs `f` on every batch of contacts, colour by colour, a run of batches at a time.
/// With several threads and enough contacts, every thread of the pool takes its own
/// share of the batches of a colour (up to two runs), and all wait for the colour to be
/// done before any starts on the next (see [`run_on_all_threads`]); the overflow colour's
/// batches, one contact each, run in order on one thread. A colour's contacts share no
/// movable particle, so which thread solves which does not change a bit. `f` is told
/// whether its run is of one colour (the contacts of all its batches share no movable
/// particle) or of the overflow.
///
/// `shares` gives, for the pool's threads, each thread's share of each colour but the
/// overflow (see [`share`]): `shares[c * threads + i]` for colour `c` and thread `i`.
/// Shares made for another number of threads (none are made for one) leave the pass
/// to the calling thread alone.
pub(super) fn for_each_batch(
    batches: &mut [ContactBatch],
    starts: &[usize; COLORS + 2],
    shares: &[Share],
    f: impl Fn(&mut [ContactBatch], bool) + Sync,
) {
    let threads = rayon::current_num_threads();
    if threads > 1 && batches.len() * LANES >= PARALLEL_CONTACTS && shares.len() == OVERFLOW * threads {
        run_on_all_threads(batches, starts, shares, &f);
        return;
    }
    for color in 0..=COLORS {
        let run = &mut batches[starts[color]..starts[color + 1]];
        if !run.is_empty() {
            f(run, color != OVERFLOW);
        }
    }
}

/// One pass over the colours on every thread of the current pool at once: one rayon
/// broadcast for the whole pass, not a fork and join per colour (a pass over a pile's
/// 15 colours then wakes the pool once, and threads hand over between colours through
/// an atomic counter per colour). The writes of a colour are published by the
/// `Release` add to its `done` counter and seen by the `Acquire` load that ends the
/// wait, before any thread starts on the next colour.
///
/// Thread `i` of `t` takes the `i`-th of `t` equal runs of every colour (in the order
/// the contacts were made, see the next paragraph). A colour
/// lists its contacts roughly in particle order, so each thread then writes the same
/// particles' velocities from colour to colour, and they stay in its core's cache.
/// Runs claimed from a shared counter instead went to whichever thread came first,
/// and every colour moved the velocities between the cores: on an 8,000-sphere pile
/// on 2 threads (three runs of 300 steps each), a step took 8.0–9.5 ms with claims
/// and 7.2–8.0 ms with fixed runs (the same bits).
///
/// A colour lists the contacts that push before those that wait (`color::bucket`), so a
/// thread's equal run would be made of the pushing contacts of all the particles, or
/// the waiting ones of all: a step of an 8,000-sphere pile on 2 threads went from 4.2
/// to 6.4 ms that way. Each thread takes its [`share`] instead: a run of each part, cut
/// where the contacts' order of generation reaches the thread's equal run of the
/// colour's batches.
fn run_on_all_threads(
    batches: &mut [ContactBatch],
    starts: &[usize; COLORS + 2],
    shares: &[Share],
    f: &(impl Fn(&mut [ContactBatch], bool) + Sync),
) {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let done: [AtomicUsize; COLORS + 1] = std::array::from_fn(|_| AtomicUsize::new(0));
    let shared = Disjoint::new(batches);
    rayon::broadcast(|context| {
        let (i, threads) = (context.index(), context.num_threads());
        for color in 0..=COLORS {
            let (start, end) = (starts[color], starts[color + 1]);
            let len = end - start;
            if len == 0 {
                continue;
            }
            if color == OVERFLOW {
                if i == 0 {
                    // SAFETY: only thread 0 takes the overflow colour.
                    f(unsafe { shared.run(start..end) }, false);
                    done[color].store(len, Ordering::Release);
                }
            } else {
                let mut mine = 0;
                for run in shares[color * threads + i].clone() {
                    if !run.is_empty() {
                        mine += run.len();
                        // SAFETY: the threads' shares are disjoint and lie within the
                        // colour's batches (`share`).
                        f(unsafe { shared.run(run) }, true);
                    }
                }
                if mine > 0 {
                    done[color].fetch_add(mine, Ordering::Release);
                }
            }
            wait_for(|| done[color].load(Ordering::Acquire) == len);
        }
    });
}

/// A thread's share of a colour: a run of its pushing batches and a run of its waiting
/// ones.
pub(super) type Share = [std::ops::Range<usize>; 2];

/// Each of `threads` threads' share of the colour of batches `colour`, whose waiting
/// part begins at batch `wait`: its run of the pushing part and its run of the waiting
/// part. `origins` gives each batch's first contact's place in the fresh list, rising
/// within each part. Thread `i` takes the batches ranked in the `i`-th of `threads`
/// equal runs of the colour's batches in origin order: about the contacts it took
/// before the colour was parted, so each thread keeps its particles from colour to
/// colour (measured on an 8,000-sphere pile: 4,463 particles changed threads from one
/// colour to the next in a pass, against 4,404 before the parting and 19,722 with
/// equal runs of the parted colour; equal runs of each part, cut apart, 5,321). The
/// shares cover the colour once, in order.
pub(super) fn share(
    colour: std::ops::Range<usize>,
    wait: usize,
    origins: &[u32],
    threads: usize,
) -> impl Iterator<Item = Share> {
    let (start, end) = (colour.start, colour.end);
    let (pushing, waiting) = (&origins[start..wait], &origins[wait..end]);
    // The batches of each part whose origin is below `x`.
    let below = |x: u32| (pushing.partition_point(|&o| o < x), waiting.partition_point(|&o| o < x));
    // Each part rises: its last origin is its largest.
    let past_all = pushing.last().max(waiting.last()).map_or(0, |&o| o + 1);
    // Where thread `k`'s runs begin in each part: at the least origin `x` with `k /
    // threads` of the colour's batches below it (origins are distinct, so the count
    // rises one batch at a time).
    let cut = move |k: usize| {
        let target = (end - start) * k / threads;
        let (mut low, mut high) = (0, past_all);
        while low < high {
            let middle = low + (high - low) / 2;
            let (p, w) = below(middle);
            if p + w >= target {
                high = middle;
            } else {
                low = middle + 1;
            }
        }
        let (p, w) = below(low);
        (start + p, wait + w)
    };
    let mut from = (start, wait);
    (1..=threads).map(move |k| {
        let to = if k == threads { (wait, end) } else { cut(k) };
        let runs = [from.0..to.0, from.1..to.1];
        from = to;
        runs
    })
}

/// Waits until `ready`: spinning briefly, then yielding the core (a thread it waits for
/// may need it, on a machine with more threads than cores).
fn wait_for(ready: impl Fn() -> bool) {
    let mut spins = 0u32;
    while !ready() {
        if spins < 128 {
            std::hint::spin_loop();
            spins += 1;
        } else {
            std::thread::yield_now();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The threads' shares of a parted colour cover it once, and thread `i`'s share
    /// holds the batches ranked `i`-th of `threads` runs by origin: merging both parts
    /// by origin and cutting the merged list into equal runs gives the same sets.
    #[test]
    #[cfg_attr(miri, ignore = "too slow to interpret, and no unsafe code")]
    fn shares_are_the_equal_runs_in_origin_order() {
        let mut state = 99u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 33) as usize
        };
        for case in 0..200 {
            // A colour of batches `start..end` after `start` others, parted at `wait`;
            // each part's origins rising, distinct over both.
            let (start, pushing, waiting) = (next() % 5, next() % 40, next() % 40);
            let (wait, end) = (start + pushing, start + pushing + waiting);
            let mut origins: Vec<u32> = (0..start).map(|k| k as u32).collect();
            let mut all: Vec<u32> = (0..(pushing + waiting) as u32).map(|k| 10 + 3 * k).collect();
            // Deal the sorted origins to the parts at random (each part stays sorted).
            let mut parts = (Vec::new(), Vec::new());
            for &o in &all {
                let to_pushing = parts.0.len() < pushing && (parts.1.len() == waiting || next() % 2 == 0);
                if to_pushing { parts.0.push(o) } else { parts.1.push(o) }
            }
            origins.extend(&parts.0);
            origins.extend(&parts.1);
            for threads in 1..=4 {
                let shares: Vec<Share> = share(start..end, wait, &origins, threads).collect();
                assert_eq!(shares.len(), threads);
                // Merged by origin: batch index of each origin, in origin order.
                all.sort_unstable();
                let index_of = |o: u32| (start..end).find(|&b| origins[b] == o).unwrap();
                let merged: Vec<usize> = all.iter().map(|&o| index_of(o)).collect();
                let len = end - start;
                for (i, [push, waits]) in shares.iter().enumerate() {
                    assert!(start <= push.start && push.end <= wait, "case {case}: {push:?}");
                    assert!(wait <= waits.start && waits.end <= end, "case {case}: {waits:?}");
                    let mut mine: Vec<usize> = push.clone().chain(waits.clone()).collect();
                    let mut expected = merged[len * i / threads..len * (i + 1) / threads].to_vec();
                    mine.sort_unstable();
                    expected.sort_unstable();
                    assert_eq!(mine, expected, "case {case}, thread {i} of {threads}");
                }
            }
        }
    }
}

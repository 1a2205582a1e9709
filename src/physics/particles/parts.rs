//! The particles shared out among the pool's threads in fixed runs, the same runs at
//! every sweep of a step: thread `i` always takes the same particles, so their
//! velocities, positions and copies stay in its core's cache from the kick to the drift
//! to the energy sums, as they do in the contact passes, where thread `i` takes the
//! contacts of about the same particles (`solver/soft/passes.rs`). Work split by
//! rayon's stealing went to whichever thread came first, and the data followed it from
//! core to core: on a 100,000-sphere pile on 2 threads the four drifts of a step took
//! 1.8 to 2.8 ms (6.5 ms when all of it ran on the calling thread, 0.66 ms on one
//! thread alone), and 0.57 ms in fixed runs.
//!
//! The runs are the nodes of [`tree_sum`]'s tree at the depth that gives each thread
//! at least one, so a sum split this way adds up in the same order, to the same bits,
//! as on one thread.

use std::marker::PhantomData;
use std::ops::Range;
use std::sync::OnceLock;

/// Particles per leaf of [`tree_sum`]: fixed, so that the order of a sum, and its bits,
/// are the same on any number of threads.
const SUM_LEAF: usize = 2048;
/// Particles from which sweeps and sums are shared out among the threads (a few under
/// Miri, so that its run of the tests reaches the threads at a size it can interpret;
/// which path runs changes no bit).
const PARALLEL_SWEEP: usize = if cfg!(miri) { 16 } else { 4096 };
/// Most runs a sweep is cut into (threads beyond this share runs).
const MOST: usize = 64;

/// `range` cut at its middle leaf, or `None` when it is one leaf or less: the shape of
/// [`tree_sum`]'s tree, which depends on the range alone.
fn halves(range: &Range<usize>) -> Option<(Range<usize>, Range<usize>)> {
    let leaves = (range.end - range.start).div_ceil(SUM_LEAF);
    if leaves <= 1 {
        return None;
    }
    let middle = range.start + leaves / 2 * SUM_LEAF;
    Some((range.start..middle, middle..range.end))
}

/// The runs of a sweep over a range on `threads` threads: the nodes of the sum's tree
/// `depth` levels down, the first depth with a node for each thread (a node of one
/// leaf is not cut further), in order.
struct Runs {
    runs: [Range<usize>; MOST],
    count: usize,
    threads: usize,
    depth: u32,
}

impl Runs {
    fn new(range: Range<usize>, threads: usize) -> Self {
        let depth = threads.min(MOST).next_power_of_two().trailing_zeros();
        let mut runs = Self { runs: std::array::from_fn(|_| 0..0), count: 0, threads, depth };
        runs.cut(range, depth);
        runs
    }

    fn cut(&mut self, range: Range<usize>, depth: u32) {
        match halves(&range) {
            Some((left, right)) if depth > 0 => {
                self.cut(left, depth - 1);
                self.cut(right, depth - 1);
            }
            _ => {
                self.runs[self.count] = range;
                self.count += 1;
            }
        }
    }

    /// The runs thread `thread` takes, with their places: runs in order, dealt out in
    /// equal numbers.
    fn of_thread(&self, thread: usize) -> impl Iterator<Item = (usize, Range<usize>)> + '_ {
        let runs = self.runs[..self.count].iter().cloned().enumerate();
        runs.filter(move |(j, _)| j * self.threads / self.count == thread)
    }
}

/// Runs `f` on every run of particles `0..len`, each on its own thread of the pool
/// (the same thread for the same particles at every call), or on this thread alone
/// below [`PARALLEL_SWEEP`] particles or on one thread.
pub(crate) fn on_threads(len: usize, f: impl Fn(Range<usize>) + Sync) {
    let threads = rayon::current_num_threads();
    if threads == 1 || len < PARALLEL_SWEEP {
        f(0..len);
        return;
    }
    let runs = Runs::new(0..len, threads);
    rayon::broadcast(|context| {
        for (_, run) in runs.of_thread(context.index()) {
            f(run);
        }
    });
}

/// `K` sums over `range`: each leaf of [`SUM_LEAF`] indices summed by `f`, the leaves
/// added up a binary tree whose shape depends on the range alone (split at the middle
/// leaf), its nodes shared out among the threads as [`on_threads`] shares the
/// particles. So the bits of the result are the same on any number of threads, and
/// nothing is allocated.
pub(crate) fn tree_sum<const K: usize>(
    range: Range<usize>,
    f: &(impl Fn(Range<usize>) -> [f64; K] + Sync),
) -> [f64; K] {
    let threads = rayon::current_num_threads();
    if threads == 1 || range.end - range.start < PARALLEL_SWEEP {
        return serial_sum(range, f);
    }
    let runs = Runs::new(range.clone(), threads);
    let sums: [OnceLock<[f64; K]>; MOST] = std::array::from_fn(|_| OnceLock::new());
    rayon::broadcast(|context| {
        for (j, run) in runs.of_thread(context.index()) {
            let _ = sums[j].set(serial_sum(run, f));
        }
    });
    let mut next = 0;
    combine(range, runs.depth, &sums, &mut next)
}

/// The sum of the tree's node `range`, `depth` levels above the runs, from the runs'
/// sums `sums` (taken in order from `next`).
fn combine<const K: usize>(
    range: Range<usize>,
    depth: u32,
    sums: &[OnceLock<[f64; K]>],
    next: &mut usize,
) -> [f64; K] {
    match halves(&range) {
        Some((left, right)) if depth > 0 => {
            let a = combine(left, depth - 1, sums, next);
            let b = combine(right, depth - 1, sums, next);
            std::array::from_fn(|k| a[k] + b[k])
        }
        _ => {
            let sum = *sums[*next].get().expect("every run was summed");
            *next += 1;
            sum
        }
    }
}

/// [`tree_sum`] on this thread.
fn serial_sum<const K: usize>(range: Range<usize>, f: &impl Fn(Range<usize>) -> [f64; K]) -> [f64; K] {
    match halves(&range) {
        None => f(range),
        Some((left, right)) => {
            let (a, b) = (serial_sum(left, f), serial_sum(right, f));
            std::array::from_fn(|k| a[k] + b[k])
        }
    }
}

/// `K` sums of `term(j)` over `j` in `0..len`, taken in four lanes: term `j` is added
/// to lane `j % 4`, and the lanes are added up as `(0 + 1) + (2 + 3)`: four chains of
/// additions that the processor can run side by side, where one chain waits for each
/// term's addition before the next can start. The order depends on `len` alone, so the
/// bits do too, on any number of threads and any target. `term` is called from one
/// place, so that it is inlined (called from four, the compiler left the energy sums'
/// terms as a call each).
#[inline(always)]
pub(crate) fn in_lanes<const K: usize>(len: usize, term: impl Fn(usize) -> [f64; K]) -> [f64; K] {
    let mut lanes = [[0.0; K]; 4];
    for j in 0..len {
        let t = term(j);
        let lane = &mut lanes[j % 4];
        for k in 0..K {
            lane[k] += t[k];
        }
    }
    std::array::from_fn(|k| (lanes[0][k] + lanes[1][k]) + (lanes[2][k] + lanes[3][k]))
}

/// A slice shared by tasks that each touch their own disjoint runs of it: the runs of
/// particles [`on_threads`] hands out, the batches
/// of a pass (`run_on_all_threads` hands out each run to exactly one thread: thread `i`
/// takes its `share` of a colour (`solver/soft/passes.rs`), the overflow colour only thread 0), the coloured
/// contacts as `unbatch` writes them back (each batch its own contacts)
/// and the coloured contact list of the counting sort (`sort_by_color` gives each
/// chunk of fresh contacts, in each bucket, its own slots: the prefix sums of the
/// chunks' counts). It holds the slice's exclusive borrow for as long as it lives, and
/// nothing reads the slice through it outside the tasks' own runs.
pub(crate) struct Disjoint<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

// SAFETY: the tasks sharing a `Disjoint` touch disjoint runs of it (the promise of
// `Disjoint::run`'s callers, kept as the type's note says), within the exclusive
// borrow `'a`; the elements may move between threads (`T: Send`).
unsafe impl<T: Send> Send for Disjoint<'_, T> {}
// SAFETY: as for `Send` above: through a shared reference each task still reaches
// only its own runs, so no element is reached from two threads.
unsafe impl<T: Send> Sync for Disjoint<'_, T> {}

impl<'a, T> Disjoint<'a, T> {
    pub(crate) fn new(slice: &'a mut [T]) -> Self {
        Self { ptr: slice.as_mut_ptr(), len: slice.len(), _borrow: PhantomData }
    }

    /// Length of the whole slice.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// The elements `range`, which must be in bounds and given to no other task.
    ///
    /// # Safety
    /// `range` must be this task's alone while the run is used.
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn run(&self, range: std::ops::Range<usize>) -> &mut [T] {
        assert!(range.start <= range.end && range.end <= self.len);
        // SAFETY: in bounds (checked above); exclusive to this task (the caller's
        // promise), within the borrow `'a`.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(range.start), range.end - range.start) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Numbers whose sum depends on the order it is taken in: large ones of both signs
    /// beside small ones (plain arithmetic, which Miri rounds as the processor does; it
    /// does not promise that of `sin`).
    fn term(i: usize) -> f64 {
        let x = i as f64;
        let sign = if i.is_multiple_of(3) { 1.0 } else { -0.7 };
        sign * 1e8 * (1.0 + x * 1e-3) + 1.0 / (x + 1.0)
    }

    /// A sum over the particles has the same bits on any number of threads, and is the
    /// sum of its terms (taken left to right, to a relative 1e-12).
    #[test]
    fn a_sum_has_the_same_bits_on_any_number_of_threads() {
        let lengths: &[usize] =
            if cfg!(miri) { &[0, 1, 40] } else { &[0, 1, 2047, 2048, 2049, 4096, 10_000, 70_001] };
        let leaf = |range: Range<usize>| [range.clone().map(term).sum::<f64>(), range.len() as f64];
        for &len in lengths {
            let alone = serial_sum(0..len, &leaf);
            let plain: f64 = (0..len).map(term).sum();
            assert!((alone[0] - plain).abs() <= 1e-12 * (0..len).map(|i| term(i).abs()).sum::<f64>());
            assert_eq!(alone[1], len as f64);
            let counts: &[usize] = if cfg!(miri) { &[1, 2, 3] } else { &[1, 2, 3, 4, 8] };
            for &threads in counts {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
                let shared = pool.install(|| tree_sum(0..len, &leaf));
                assert_eq!(shared.map(f64::to_bits), alone.map(f64::to_bits), "{len} on {threads} threads");
                // A range that starts further on is cut by its own leaves.
                let later = pool.install(|| tree_sum(3..len + 3, &leaf));
                assert_eq!(later.map(f64::to_bits), serial_sum(3..len + 3, &leaf).map(f64::to_bits));
            }
        }
    }

    /// A sum in lanes is the sum of its terms (to a relative 1e-12 of the terms' sizes),
    /// and is, bit for bit, term `j` added into lane `j % 4` and the lanes added as
    /// `(0 + 1) + (2 + 3)`, for every length around a multiple of four.
    #[test]
    fn a_sum_in_lanes_is_the_sum_of_its_lanes() {
        for len in [0, 1, 2, 3, 4, 5, 7, 8, 9, 2047, 2048] {
            let got = in_lanes(len, |j| [term(j), -2.0 * term(j)]);
            let mut lanes = [[0.0f64; 2]; 4];
            for j in 0..len {
                lanes[j % 4][0] += term(j);
                lanes[j % 4][1] += -2.0 * term(j);
            }
            for k in 0..2 {
                let by_hand = (lanes[0][k] + lanes[1][k]) + (lanes[2][k] + lanes[3][k]);
                assert_eq!(got[k].to_bits(), by_hand.to_bits(), "{len} terms, sum {k}");
            }
            let plain: f64 = (0..len).map(term).sum();
            let size: f64 = (0..len).map(|j| term(j).abs()).sum();
            assert!((got[0] - plain).abs() <= 1e-12 * size, "{len} terms: {} vs {plain}", got[0]);
        }
    }

    /// A sweep reaches every particle once, and each particle on the same thread at
    /// every call; with two threads, the first takes the lower half and the second the
    /// upper (about: the cut is at a leaf of the sum's tree).
    #[test]
    fn each_thread_sweeps_the_same_particles_every_time() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let len = if cfg!(miri) { 40 } else { 10_000 };
        let counts: &[usize] = if cfg!(miri) { &[1, 2, 3] } else { &[1, 2, 3, 4] };
        for &threads in counts {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            let sweep = || {
                let seen: Vec<AtomicUsize> = (0..len).map(|_| AtomicUsize::new(0)).collect();
                let by: Vec<AtomicUsize> = (0..len).map(|_| AtomicUsize::new(usize::MAX)).collect();
                pool.install(|| {
                    on_threads(len, |run| {
                        let me = rayon::current_thread_index().expect("on a thread of the pool");
                        for i in run {
                            seen[i].fetch_add(1, Ordering::Relaxed);
                            by[i].store(me, Ordering::Relaxed);
                        }
                    })
                });
                assert!(seen.iter().all(|s| s.load(Ordering::Relaxed) == 1), "{threads} threads");
                by.iter().map(|b| b.load(Ordering::Relaxed)).collect::<Vec<_>>()
            };
            let first = sweep();
            assert_eq!(first, sweep(), "{threads} threads: the same particles on the same threads");
            if threads == 2 && !cfg!(miri) {
                // 10,000 particles are 5 leaves: the cut is after the second, at 4,096.
                assert!(first[..4096].iter().all(|&t| t == 0) && first[4096..].iter().all(|&t| t == 1));
            }
        }
    }
}

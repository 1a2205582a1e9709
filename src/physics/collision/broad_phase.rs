//! Broad phase: which pairs of spheres are close enough to need a closer look.
//!
//! A uniform grid, rebuilt when spheres have moved (see *kept pairs* below). Each
//! sphere goes into the one cell that holds its centre. When the spheres' bounding box holds at most four cells per sphere the
//! grid is dense: cells are numbered row by row, so the three neighbouring cells along
//! x are one contiguous run and a query is 9 range look-ups. Otherwise (a few spheres
//! far apart, an unbounded world) cells are hashed into a table twice the size of the
//! particle count and a query is 27 look-ups that skip other cells sharing a bucket.
//! Either way the buckets are filled with a counting sort (count per bucket, prefix
//! sum, scatter) into buffers kept between steps: once warm, a step allocates nothing.
//!
//! The cell edge is the largest reach diameter among ordinary spheres, so a pair that
//! touches always lies in neighbouring cells (the 3x3x3 block around a centre). A
//! sphere much larger than the rest would make every cell huge; such "oversized"
//! spheres (diameter more than [`OVERSIZED_FACTOR`] times the mean) stay out of the
//! grid and are tested against every sphere instead, so mixed radii are always found.
//!
//! Pairs come out as `(a, b)` with `a < b`, sorted by `a` then `b`, whatever the thread
//! count: the work is split into chunks of particles whose size depends only on the
//! input, and the chunks' results are joined in order. That order is what the solver
//! colours contacts by, so 1 thread and N threads give the same bits.
//!
//! **The pair budget.** Spheres that do not overlap make few pairs: a sphere touches
//! at most about a dozen spheres as large as itself, so even with speculative margins
//! a pile makes fewer than 10 pairs per sphere. Spheres piled onto one point make a
//! pair of every two: 10,000 of them made 50 million pairs, and their contacts asked
//! for 2 to 3 GB. So one search makes at most [`pair_budget`] pairs:
//! [`PAIRS_PER_SPHERE`] (32) per sphere with a usable reach, and never fewer than
//! [`MIN_PAIR_BUDGET`] (65,536). Past it, the pairs kept are the first ones in the
//! usual order (those of the lowest-numbered first particles), exactly the list
//! without a budget cut short, and [`BroadPhase::budget_hit`] says so, for the world's
//! report. The search stops there too, so its time stays linear: a query of a sphere
//! in a crowded cell still visits every sphere of the cell, but only until the budget
//! runs out, and in a crowded cell that is after a few queries. Memory is then at most
//! the budget's pairs (each becomes a contact of about 160 bytes in the soft solver):
//! about 5 KB per sphere at worst.

//!
//! **Kept pairs.** A pile lying still would rebuild the same grid and find the same
//! pairs step after step. So the search grows every reach by a skin (0.3 of the mean
//! reach, `SKIN_FRACTION`) and keeps the pairs it finds, with the positions and
//! reaches it saw. While no sphere has moved by more than the skin (less what its
//! reach grew) since, every pair that touches now is among the kept ones, and a
//! search only tests those again, with the grid's own arithmetic and in its order:
//! the same pairs, the same bits. A few spheres past their skin (one rolling down a pile's flank) have their
//! own pairs found again, around them in the grid as it was built, and merged into
//! the kept ones; past one sphere in 32 the grid is built again. When spheres move
//! too fast for the skin (a falling pile) the kept pairs serve one search only, and
//! the grid waits a while before keeping pairs again. Worlds with sleeping spheres
//! use the plain search, which skips pairs of two sleepers.

use glam::Vec3;
use rayon::prelude::*;

/// A sphere whose reach diameter is more than this times the mean is kept out of the
/// grid and tested against every other sphere.
pub const OVERSIZED_FACTOR: f32 = 4.0;

/// Particles per chunk of the pair search (one rayon task each).
const CHUNK: usize = 2048;

/// Particles below which the search runs on the calling thread (threads cost more than
/// they save).
const PARALLEL_FROM: usize = 4096;

/// Pairs one search makes at most, per sphere with a usable reach (see the module's
/// doc: ordinary piles make fewer than 10).
pub const PAIRS_PER_SPHERE: usize = 32;

/// The pair budget is never below this (about 10 MB of contacts), so small worlds
/// are never cut short however they overlap.
pub const MIN_PAIR_BUDGET: usize = 65_536;

/// What a user is told when a step hit the pair budget (the window's status line,
/// `simulate`'s stderr).
pub const BUDGET_HIT_MESSAGE: &str = "so many spheres overlap that the broad phase stopped at its budget of 32 \
     pairs a sphere: contacts past it were left out this step (spheres piled onto one point?)";

/// Chunks searched together (in parallel) before the budget left is counted again. A
/// constant, not the thread count, so the pairs kept do not depend on the threads.
const BATCH: usize = 16;

/// Most pairs one search makes among `spheres` spheres with a usable reach.
#[must_use]
pub fn pair_budget(spheres: usize) -> usize {
    spheres.saturating_mul(PAIRS_PER_SPHERE).max(MIN_PAIR_BUDGET)
}

/// Grid coordinates are clamped to this many cells either side of the origin so that
/// they pack into 21 bits each; far-away spheres share a border cell, which costs time
/// but never misses a pair.
const COORD_LIMIT: i32 = (1 << 20) - 1;

const NOT_IN_GRID: u64 = u64::MAX;

/// Scratch for the grid, reused every step.
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    /// Edge of a grid cell (m), from the last build.
    cell_size: f32,
    /// The dense grid's corner and cells per axis, or `None` when hashed.
    dense: Option<(Vec3, [i32; 3])>,
    /// Per particle: packed cell coordinates, or `NOT_IN_GRID`.
    cell_keys: Vec<u64>,
    /// Per bucket + 1: start of the bucket in `entries` (prefix sums).
    starts: Vec<u32>,
    /// Fill cursors for the scatter.
    cursors: Vec<u32>,
    /// Particle indices sorted by bucket.
    entries: Vec<u32>,
    /// The packed cell of each entry, to skip other cells that share a bucket.
    entry_keys: Vec<u64>,
    /// Position and reach of each entry, in entry order, so a query reads runs of
    /// contiguous memory instead of jumping through the particle arrays.
    entry_spheres: Vec<glam::Vec4>,
    /// Spheres kept out of the grid.
    oversized: Vec<u32>,
    /// Pairs found per chunk, joined in chunk order.
    chunk_pairs: Vec<Vec<(u32, u32)>>,
    /// Candidate partners of one particle, per chunk.
    chunk_scratch: Vec<Vec<u32>>,
    /// Spheres with a usable reach in the last build.
    spheres: usize,
    /// Whether the last search left out pairs because of the budget.
    budget_hit: bool,
    /// The pairs within a skin of reach (see [`BroadPhase::find_pairs_awake`]).
    kept: KeptPairs,
}

/// Pairs found with every reach grown by a skin, kept between searches: while no
/// sphere has moved (or grown its reach) by more than the skin since, every pair that
/// touches is among them, and a search only tests those again.
#[derive(Clone, Debug, Default)]
struct KeptPairs {
    /// Whether `pairs` may be used: found in the last search that built them, and no
    /// search since found a sphere past its skin.
    valid: bool,
    /// Every pair `(a, b)`, `a < b`, closer than the grown reaches, in search order.
    pairs: Vec<(u32, u32)>,
    /// Positions and reaches when the pairs were found.
    positions: Vec<Vec3>,
    reach: Vec<f32>,
    /// The skin (m): how far a sphere may move and grow before the pairs are found again.
    skin: f32,
    /// The grown reaches, scratch for the search that keeps pairs.
    grown: Vec<f32>,
    /// Searches the current pairs served, and searches left before keeping pairs is
    /// tried again after it did not pay (pairs that served a single search).
    served: u32,
    wait: u32,
    /// Whether the last search used kept pairs (for tests and profiles).
    reused: bool,
    /// Spheres past their skin in this search, to be brought up to date.
    movers: Vec<u32>,
    /// The movers each chunk of [`MOVER_CHUNK`] spheres holds (scratch).
    mover_chunks: Vec<Vec<u32>>,
    /// Spheres brought up to date since the grid was built (their grid entries are
    /// stale), and per sphere the flags [`MOVER`] and [`REFRESHED`].
    refreshed: Vec<u32>,
    flags: Vec<u8>,
    /// The movers' new pairs, and the merged list (scratch).
    fresh: Vec<(u32, u32)>,
    merged: Vec<(u32, u32)>,
    /// The pairs each chunk of [`SERVE_CHUNK`] kept pairs serves (scratch).
    served_chunks: Vec<Vec<(u32, u32)>>,
}

/// Kept pairs tested by one task when they are served on several threads (a few
/// under Miri, so that its run of the tests reaches the threads at a size it can
/// interpret; which path serves the pairs changes nothing in the list).
const SERVE_CHUNK: usize = if cfg!(miri) { 16 } else { 8192 };
/// Kept pairs from which they are served on several threads.
const PARALLEL_SERVE: usize = 2 * SERVE_CHUNK;
/// Spheres one task looks through for movers, when it is done on several threads
/// (from two chunks; a few under Miri, as [`SERVE_CHUNK`]).
const MOVER_CHUNK: usize = if cfg!(miri) { 16 } else { 8192 };

/// A sphere past its skin in this search.
const MOVER: u8 = 1;
/// A sphere whose kept position is no longer the grid's.
const REFRESHED: u8 = 2;

/// At most one sphere in this many (and 16 more) is brought up to date between two
/// builds of the grid; past it the grid is built again.
const REFRESH_SHARE: usize = 32;

/// The skin, as a fraction of the mean reach: 0.3 (cells 0.6 mean reaches wider, so
/// more candidates when the pairs are kept, but a settling pile keeps them far more
/// often, and a pile at rest keeps them for good). Measured on the pile (the same
/// pairs, so the same bits, whatever the skin): the broad phase of a falling 100,000-sphere pile
/// (mean of its first 150 steps, 2 threads) took 8.9–9.3 ms a step with a tenth, 7.0–7.4
/// with 0.2, 6.0–6.4 with 0.3 and 5.8 with 0.4; that of a settled 8,000-sphere pile
/// (1 thread) 0.168–0.170, 0.143–0.146, 0.147–0.151 and 0.164 ms.
const SKIN_FRACTION: f32 = 0.3;

/// Searches without keeping pairs after kept pairs served only one search (things
/// move too fast for the skin: a falling pile), before trying again.
const KEEP_BACKOFF: u32 = 16;

impl BroadPhase {
    /// Empty scratch.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Writes into `out` (cleared first) every pair `(a, b)`, `a < b`, whose centres are
    /// closer than `reach[a] + reach[b]`, sorted by `a` then `b`. A particle with a reach
    /// of 0 or less (or not finite) takes part in no pair. At most [`pair_budget`] pairs
    /// are written: past it, the list is cut short and [`BroadPhase::budget_hit`] is true.
    ///
    /// # Panics
    /// If `positions` and `reach` differ in length.
    pub fn find_pairs(&mut self, positions: &[Vec3], reach: &[f32], out: &mut Vec<(u32, u32)>) {
        self.find_pairs_awake(positions, reach, None, out);
    }

    /// Like [`BroadPhase::find_pairs`], but particles with `asleep[i]` true only take
    /// part as the second of a pair: pairs of two sleeping particles are skipped, a
    /// pair of two awake ones comes as `(a, b)` with `a < b`, and a pair of an awake and
    /// a sleeping one comes as `(awake, asleep)`. Sorted by first, then second, and
    /// cut short at the same budget.
    ///
    /// # Panics
    /// If the slices differ in length.
    pub fn find_pairs_awake(
        &mut self,
        positions: &[Vec3],
        reach: &[f32],
        asleep: Option<&[bool]>,
        out: &mut Vec<(u32, u32)>,
    ) {
        assert_eq!(positions.len(), reach.len(), "one reach per position");
        assert!(asleep.is_none_or(|a| a.len() == positions.len()), "one flag per position");
        out.clear();
        self.budget_hit = false;
        self.kept.reused = false;
        // Kept pairs, for worlds with nothing asleep (with sleepers, the plain search
        // skips pairs of two of them, which the kept pairs would hold).
        if asleep.is_none() {
            if self.kept.find_movers(positions, reach) && self.refresh(positions, reach) {
                self.kept.serve(positions, reach, out);
                self.kept.reused = true;
                return;
            }
            if self.keep_pairs(positions, reach) {
                self.kept.serve(positions, reach, out);
                return;
            }
        } else {
            self.kept.valid = false;
        }
        self.search(positions, reach, asleep, out);
    }

    /// Whether the last search only tested kept pairs again (nothing moved by more
    /// than the skin since they were found).
    #[must_use]
    pub fn reused_pairs(&self) -> bool {
        self.kept.reused
    }

    /// Finds and keeps the pairs within the skin, unless waiting after kept pairs did
    /// not pay or the grown search hit the budget (then nothing is kept, and it waits
    /// [`KEEP_BACKOFF`] searches before trying again). True when pairs were kept.
    fn keep_pairs(&mut self, positions: &[Vec3], reach: &[f32]) -> bool {
        let kept = &mut self.kept;
        if kept.valid && kept.served <= 1 {
            kept.wait = KEEP_BACKOFF;
        }
        kept.valid = false;
        if kept.wait > 0 {
            kept.wait -= 1;
            return false;
        }
        let usable = |r: f32| r > 0.0 && r.is_finite();
        let (count, sum) = reach
            .iter()
            .filter(|&&r| usable(r))
            .fold((0usize, 0.0f64), |(count, sum), &r| (count + 1, sum + f64::from(r)));
        if count == 0 {
            return false;
        }
        let skin = SKIN_FRACTION * (sum / count as f64) as f32;
        let mut grown = std::mem::take(&mut self.kept.grown);
        grown.clear();
        grown.extend(reach.iter().map(|&r| if usable(r) { r + skin } else { r }));
        let mut pairs = std::mem::take(&mut self.kept.pairs);
        self.search(positions, &grown, None, &mut pairs);
        let hit = self.budget_hit;
        self.budget_hit = false;
        let kept = &mut self.kept;
        (kept.grown, kept.pairs) = (grown, pairs);
        if hit || !skin.is_finite() {
            // Spheres packed so close that their grown reaches pass the budget: wait
            // before searching with them again, as after pairs that did not pay.
            kept.wait = KEEP_BACKOFF;
            return false;
        }
        kept.positions.clear();
        kept.positions.extend_from_slice(positions);
        kept.reach.clear();
        kept.reach.extend_from_slice(reach);
        kept.skin = skin;
        kept.served = 0;
        kept.valid = true;
        kept.refreshed.clear();
        kept.flags.clear();
        kept.flags.resize(positions.len(), 0);
        true
    }

    /// Brings the kept pairs up to date for the spheres that moved past their skin
    /// (`kept.movers`), without building the grid again: each mover's kept position
    /// and reach become its present ones, its old pairs go, and its pairs within the
    /// skin now come in, in order. The grid built with the kept pairs still holds every
    /// other sphere where its pairs were found, except those already brought up to
    /// date since (`refreshed`), which are tested one by one. False (nothing to trust:
    /// search anew) when there are too many movers or refreshed spheres, a mover is
    /// oversized or its reach outgrew the grid's cells, or the pairs pass the budget.
    fn refresh(&mut self, positions: &[Vec3], reach: &[f32]) -> bool {
        let mut kept = std::mem::take(&mut self.kept);
        let fresh = self.refresh_kept(&mut kept, positions, reach);
        self.kept = kept;
        fresh
    }

    /// [`BroadPhase::refresh`] with the kept pairs apart from the grid they were found in.
    fn refresh_kept(&self, kept: &mut KeptPairs, positions: &[Vec3], reach: &[f32]) -> bool {
        if kept.movers.is_empty() {
            return true;
        }
        let limit = positions.len() / REFRESH_SHARE + 16;
        if kept.refreshed.len() + kept.movers.len() > limit {
            return false;
        }
        let skin = kept.skin;
        let half_cell = 0.5 * self.cell_size;
        for &m in &kept.movers {
            let m = m as usize;
            // (Reaches here are usable, so finite: the sum compares.)
            if self.cell_keys[m] == NOT_IN_GRID || reach[m] + skin > half_cell {
                return false;
            }
        }
        for &m in &kept.movers {
            let m = m as usize;
            kept.positions[m] = positions[m];
            kept.reach[m] = reach[m];
            kept.flags[m] |= MOVER;
            if kept.flags[m] & REFRESHED == 0 {
                kept.flags[m] |= REFRESHED;
                kept.refreshed.push(m as u32);
            }
        }
        // The movers' pairs within the skin now.
        kept.fresh.clear();
        let grid = self.view(positions, reach, None);
        let (flags, fresh) = (&kept.flags, &mut kept.fresh);
        let (then, then_reach) = (&kept.positions, &kept.reach);
        for &m in &kept.movers {
            let (pm, rm) = (then[m as usize], then_reach[m as usize] + skin);
            let mut near = |b: u32, pb: Vec3, rb: f32| {
                let reach = rm + rb;
                if b != m && (pm - pb).length_squared() < reach * reach {
                    fresh.push((m.min(b), m.max(b)));
                }
            };
            // Spheres the grid holds where they still are kept (the grid's own copy
            // of the grown reach), then the refreshed and the oversized ones.
            grid.around(pm, |b, sphere| {
                if flags[b as usize] & REFRESHED == 0 {
                    near(b, sphere.truncate(), sphere.w);
                }
            });
            for &b in kept.refreshed.iter().chain(self.oversized.iter()) {
                near(b, then[b as usize], then_reach[b as usize] + skin);
            }
        }
        fresh.sort_unstable();
        fresh.dedup();
        // The kept pairs without the movers' old ones, merged with their new ones (no
        // pair is in both: each new one has a mover). Between two new pairs, the kept
        // ones are copied without a branch per pair (`keep_where`): with a branch, which
        // pairs have a mover follows no pattern. (Measured on a forming pile of 100,000
        // spheres on 2 threads: bringing movers up to date took 2.5 ms a search with a
        // branch per pair, 0.7 to 1.9 this way, in two runs.)
        let flags = &kept.flags;
        let stays = |&(a, b): &(u32, u32)| (flags[a as usize] | flags[b as usize]) & MOVER == 0;
        kept.merged.clear();
        kept.merged.reserve(kept.pairs.len() + kept.fresh.len());
        let mut from = 0;
        for &next in &kept.fresh {
            let until = from + kept.pairs[from..].partition_point(|&pair| pair < next);
            keep_where(&kept.pairs[from..until], stays, &mut kept.merged);
            kept.merged.push(next);
            from = until;
        }
        keep_where(&kept.pairs[from..], stays, &mut kept.merged);
        std::mem::swap(&mut kept.pairs, &mut kept.merged);
        for &m in &kept.movers {
            kept.flags[m as usize] &= !MOVER;
        }
        kept.pairs.len() <= pair_budget(self.spheres)
    }

    /// The built grid, to be searched for the spheres `positions` with `reach`.
    fn view<'a>(
        &'a self,
        positions: &'a [Vec3],
        reach: &'a [f32],
        asleep: Option<&'a [bool]>,
    ) -> GridView<'a> {
        GridView {
            cell_size: self.cell_size,
            dense: self.dense,
            cell_keys: &self.cell_keys,
            starts: &self.starts,
            entries: &self.entries,
            entry_keys: &self.entry_keys,
            entry_spheres: &self.entry_spheres,
            oversized: &self.oversized,
            positions,
            reach,
            asleep,
        }
    }

    /// The plain search (see [`BroadPhase::find_pairs_awake`]).
    fn search(
        &mut self,
        positions: &[Vec3],
        reach: &[f32],
        asleep: Option<&[bool]>,
        out: &mut Vec<(u32, u32)>,
    ) {
        out.clear();
        self.budget_hit = false;
        let n = positions.len();
        self.build(positions, reach);
        if n == 0 {
            return;
        }
        let chunks = n.div_ceil(CHUNK);
        if self.chunk_pairs.len() < chunks {
            self.chunk_pairs.resize_with(chunks, Vec::new);
            self.chunk_scratch.resize_with(chunks, Vec::new);
        }
        // The chunks' buffers are taken out while the grid is read.
        let (mut chunk_pairs, mut chunk_scratch) =
            (std::mem::take(&mut self.chunk_pairs), std::mem::take(&mut self.chunk_scratch));
        self.budget_hit =
            self.search_chunks(positions, reach, asleep, &mut chunk_pairs, &mut chunk_scratch, out);
        (self.chunk_pairs, self.chunk_scratch) = (chunk_pairs, chunk_scratch);
    }

    /// The search of [`BroadPhase::search`] over the built grid, chunk by chunk into
    /// `chunk_pairs` (one buffer per chunk) and then `out`. True when the budget was hit.
    fn search_chunks(
        &self,
        positions: &[Vec3],
        reach: &[f32],
        asleep: Option<&[bool]>,
        chunk_pairs: &mut [Vec<(u32, u32)>],
        chunk_scratch: &mut [Vec<u32>],
        out: &mut Vec<(u32, u32)>,
    ) -> bool {
        let n = positions.len();
        let chunks = n.div_ceil(CHUNK);
        let grid = self.view(positions, reach, asleep);
        // Batch by batch, each chunk allowed what is left of the budget when its batch
        // starts: what a chunk finds depends on the input alone, never on the threads.
        let mut left = pair_budget(self.spheres);
        for first in (0..chunks).step_by(BATCH) {
            let batch = first..(first + BATCH).min(chunks);
            let pairs = &mut chunk_pairs[batch.clone()];
            let scratch = &mut chunk_scratch[batch.clone()];
            if n >= PARALLEL_FROM {
                pairs.par_iter_mut().zip(scratch.par_iter_mut()).zip(batch.clone()).for_each(
                    |((pairs, scratch), chunk)| {
                        grid.search_chunk(chunk, left, pairs, scratch);
                    },
                );
            } else {
                for ((pairs, scratch), chunk) in pairs.iter_mut().zip(scratch.iter_mut()).zip(batch.clone()) {
                    grid.search_chunk(chunk, left, pairs, scratch);
                }
            }
            let mut hit = false;
            for pairs in &chunk_pairs[batch] {
                let kept = pairs.len().min(left);
                out.extend_from_slice(&pairs[..kept]);
                left -= kept;
                hit |= kept < pairs.len();
            }
            if hit {
                return true;
            }
        }
        false
    }

    /// Whether the last search found more pairs than [`pair_budget`] allows and left
    /// the rest out (spheres piled onto each other). Never true for spheres that only
    /// touch.
    #[must_use]
    pub fn budget_hit(&self) -> bool {
        self.budget_hit
    }

    /// Sizes the cells and sorts particles into buckets.
    fn build(&mut self, positions: &[Vec3], reach: &[f32]) {
        let n = positions.len();
        let usable = |r: f32| r > 0.0 && r.is_finite();
        let (mut count, mut sum, mut largest) = (0usize, 0.0f64, 0.0f32);
        for &r in reach {
            if usable(r) {
                count += 1;
                sum += f64::from(r);
                largest = largest.max(r);
            }
        }
        self.spheres = count;
        let mean = if count > 0 { (sum / count as f64) as f32 } else { 0.0 };
        let limit = mean * OVERSIZED_FACTOR;
        // The cell edge is the largest diameter that is not oversized.
        let cell_radius = if largest <= limit {
            largest
        } else {
            reach.iter().copied().filter(|&r| usable(r) && r <= limit).fold(0.0, f32::max)
        };
        self.cell_size = (2.0 * cell_radius).max(f32::MIN_POSITIVE);
        let inverse_cell = 1.0 / self.cell_size;

        let in_grid = |r: f32| usable(r) && r <= cell_radius;
        self.oversized.clear();
        for (i, &r) in reach.iter().enumerate() {
            if usable(r) && r > cell_radius {
                self.oversized.push(i as u32);
            }
        }

        // Dense when the bounding box of the grid's spheres needs few enough cells.
        let (mut low, mut high) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for (p, &r) in positions.iter().zip(reach) {
            if in_grid(r) {
                low = low.min(*p);
                high = high.max(*p);
            }
        }
        let cells = ((high - low) * inverse_cell).floor() + Vec3::ONE; // once per build
        let dense_cells = f64::from(cells.x) * f64::from(cells.y) * f64::from(cells.z);
        self.dense = (cells.is_finite() && dense_cells <= (4 * n).max(64) as f64)
            .then_some((low, [cells.x as i32, cells.y as i32, cells.z as i32]));

        self.cell_keys.clear();
        let buckets =
            match self.dense {
                Some((origin, dims)) => {
                    self.cell_keys.extend(positions.iter().zip(reach).map(|(p, &r)| {
                        if in_grid(r) {
                            dense_index(dense_cell(*p, origin, inverse_cell, dims), dims)
                        } else {
                            NOT_IN_GRID
                        }
                    }));
                    (dims[0] * dims[1] * dims[2]) as usize
                }
                None => {
                    self.cell_keys.extend(positions.iter().zip(reach).map(|(p, &r)| {
                        if in_grid(r) { pack(cell_of(*p, inverse_cell)) } else { NOT_IN_GRID }
                    }));
                    (2 * n).next_power_of_two().max(64)
                }
            };
        // The bucket of a key: the cell index itself when dense, its hash otherwise.
        let bits = if self.dense.is_some() { 0 } else { buckets.trailing_zeros() };
        let bucket = |key: u64| if bits == 0 { key as usize } else { bucket(key, bits) };
        self.starts.clear();
        self.starts.resize(buckets + 1, 0);
        for &key in &self.cell_keys {
            if key != NOT_IN_GRID {
                self.starts[bucket(key) + 1] += 1;
            }
        }
        for b in 0..buckets {
            self.starts[b + 1] += self.starts[b];
        }
        let total = self.starts[buckets] as usize;
        self.cursors.clear();
        self.cursors.extend_from_slice(&self.starts[..buckets]);
        self.entries.clear();
        self.entries.resize(total, 0);
        self.entry_keys.clear();
        self.entry_keys.resize(total, 0);
        self.entry_spheres.clear();
        self.entry_spheres.resize(total, glam::Vec4::ZERO);
        for (i, &key) in self.cell_keys.iter().enumerate() {
            if key != NOT_IN_GRID {
                let slot = &mut self.cursors[bucket(key)];
                self.entries[*slot as usize] = i as u32;
                self.entry_keys[*slot as usize] = key;
                self.entry_spheres[*slot as usize] = positions[i].extend(reach[i]);
                *slot += 1;
            }
        }
    }
}

impl KeptPairs {
    /// Whether the kept pairs can serve, and which spheres must be brought up to date
    /// first (`movers`). Every pair touching now is among the kept pairs when the same
    /// spheres have a usable reach and none has moved by more than its skin less what
    /// its reach grew: for a pair closer than `r_a + r_b` now, its distance when kept
    /// was less than `r_a + r_b + d_a + d_b`, at most the grown reaches' sum. A tenth
    /// of the skin is kept back for rounding. The spheres past it are the movers
    /// (given up, false, when there are more than [`REFRESH_SHARE`] allows).
    fn find_movers(&mut self, positions: &[Vec3], reach: &[f32]) -> bool {
        self.movers.clear();
        if !self.valid || positions.len() != self.positions.len() {
            return false;
        }
        let n = positions.len();
        let limit = n / REFRESH_SHARE + 16;
        let (then, then_reach, allowed) = (&self.positions[..], &self.reach[..], 0.9 * self.skin);
        // The movers among spheres `range`, onto `movers`: false as soon as the pairs
        // cannot serve (a sphere gained or lost its reach, or left the numbers, or more
        // than `limit` are on the list).
        let look = |range: std::ops::Range<usize>, movers: &mut Vec<u32>| {
            let now = positions[range.clone()].iter().zip(&reach[range.clone()]);
            let kept = then[range.clone()].iter().zip(&then_reach[range.clone()]);
            for (i, ((&p, &r), (&p0, &r0))) in range.zip(now.zip(kept)) {
                let usable = |r: f32| r > 0.0 && r.is_finite();
                if usable(r0) != usable(r) {
                    return false;
                }
                // NaN fails every comparison, so a sphere that left the numbers moved.
                let within = p.distance(p0) + (r - r0) <= allowed;
                if usable(r) && !within {
                    if !(p.is_finite() && r.is_finite()) || movers.len() == limit {
                        return false;
                    }
                    movers.push(i as u32);
                }
            }
            true
        };
        let chunks = n.div_ceil(MOVER_CHUNK);
        if chunks < 2 || rayon::current_num_threads() == 1 {
            return look(0..n, &mut self.movers);
        }
        // In chunks on several threads, then the chunks' movers in order: the same list.
        // (Serial, it took 0.26 ms of every step of a forming 100,000-sphere pile.)
        if self.mover_chunks.len() < chunks {
            self.mover_chunks.resize_with(chunks, Vec::new);
        }
        let found = &mut self.mover_chunks[..chunks];
        let fine = found.par_iter_mut().enumerate().all(|(k, movers)| {
            movers.clear();
            look(k * MOVER_CHUNK..((k + 1) * MOVER_CHUNK).min(n), movers)
        });
        if !fine || found.iter().map(Vec::len).sum::<usize>() > limit {
            return false;
        }
        found.iter().for_each(|movers| self.movers.extend_from_slice(movers));
        true
    }

    /// The kept pairs that touch now, tested as the grid tests them, in their order
    /// (the grid's).
    fn serve(&mut self, positions: &[Vec3], reach: &[f32], out: &mut Vec<(u32, u32)>) {
        out.clear();
        let touching = |&(a, b): &(u32, u32)| {
            let (a, b) = (a as usize, b as usize);
            let (ra, rb) = (reach[a], reach[b]);
            let reach = ra + rb;
            (positions[a] - positions[b]).length_squared() < reach * reach
        };
        if self.pairs.len() >= PARALLEL_SERVE && rayon::current_num_threads() > 1 {
            // Chunk by chunk on several threads, then the chunks' pairs in order: the
            // same list as the plain filter. (A pile at rest keeps its pairs for good,
            // so this runs every step: serial, it took 0.17 ms of a 2.4 ms 2-thread
            // step of an 8,000-sphere pile.)
            let chunks = self.pairs.len().div_ceil(SERVE_CHUNK);
            if self.served_chunks.len() < chunks {
                self.served_chunks.resize_with(chunks, Vec::new);
            }
            let served = &mut self.served_chunks[..chunks];
            served.par_iter_mut().zip(self.pairs.par_chunks(SERVE_CHUNK)).for_each(|(served, pairs)| {
                served.clear();
                keep_where(pairs, touching, served);
            });
            out.reserve(served.iter().map(Vec::len).sum());
            served.iter().for_each(|served| out.extend_from_slice(served));
        } else {
            keep_where(&self.pairs, touching, out);
        }
        self.served += 1;
    }
}

/// Appends to `out` the pairs for which `keep` holds, in order: as a filter would, but
/// without a branch per pair. Each pair is written at the end of the list and counted
/// only if kept, so the next overwrites a pair left out. Which of a pile's kept pairs
/// are in reach follows no pattern a branch predictor could learn: serving an
/// 8,000-sphere pile's pairs took 0.11 ms a step with a filter, 0.055 ms this way.
fn keep_where(pairs: &[(u32, u32)], keep: impl Fn(&(u32, u32)) -> bool, out: &mut Vec<(u32, u32)>) {
    out.reserve(pairs.len());
    let spare = &mut out.spare_capacity_mut()[..pairs.len()];
    let mut kept = 0;
    for (&pair, i) in pairs.iter().zip(0..) {
        // `kept <= i < pairs.len()`: in bounds.
        spare[kept].write(pair);
        debug_assert!(kept <= i);
        kept += usize::from(keep(&pair));
    }
    let len = out.len() + kept;
    // SAFETY: the first `kept` spare elements were written (each index below `kept`
    // was the write target of the pair counted at it), and `kept <= pairs.len()`, the
    // reserved room.
    unsafe { out.set_len(len) };
}

/// The built grid, shared read-only by the search tasks.
#[derive(Clone, Copy)]
struct GridView<'a> {
    cell_size: f32,
    dense: Option<(Vec3, [i32; 3])>,
    cell_keys: &'a [u64],
    starts: &'a [u32],
    entries: &'a [u32],
    entry_keys: &'a [u64],
    entry_spheres: &'a [glam::Vec4],
    oversized: &'a [u32],
    positions: &'a [Vec3],
    reach: &'a [f32],
    asleep: Option<&'a [bool]>,
}

impl GridView<'_> {
    /// Calls `visit` with every grid entry (particle, position and reach as built) in
    /// the 3x3x3 block of cells around `p`.
    fn around(&self, p: Vec3, mut visit: impl FnMut(u32, &glam::Vec4)) {
        let inverse_cell = 1.0 / self.cell_size;
        if let Some((origin, dims)) = self.dense {
            let [x, y, z] = dense_cell(p, origin, inverse_cell, dims);
            let (x0, x1) = ((x - 1).max(0), (x + 1).min(dims[0] - 1));
            for cz in (z - 1).max(0)..=(z + 1).min(dims[2] - 1) {
                for cy in (y - 1).max(0)..=(y + 1).min(dims[1] - 1) {
                    let row = (cy + dims[1] * cz) * dims[0];
                    let run = self.starts[(row + x0) as usize] as usize
                        ..self.starts[(row + x1 + 1) as usize] as usize;
                    for (&b, sphere) in self.entries[run.clone()].iter().zip(&self.entry_spheres[run]) {
                        visit(b, sphere);
                    }
                }
            }
        } else {
            let bits = (self.starts.len() - 1).trailing_zeros();
            let [x, y, z] = cell_of(p, inverse_cell);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let key = pack([x + dx, y + dy, z + dz]);
                        let bucket = bucket(key, bits);
                        let range = self.starts[bucket] as usize..self.starts[bucket + 1] as usize;
                        let entries =
                            self.entries[range.clone()].iter().zip(&self.entry_spheres[range.clone()]);
                        for ((&b, sphere), &entry_key) in entries.zip(&self.entry_keys[range]) {
                            if entry_key == key {
                                visit(b, sphere);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Finds the pairs whose first particle lies in chunk `chunk`, in order, stopping
    /// after the first particle whose pairs take the count past `cap`: then more than
    /// `cap` pairs are left in `pairs`, so the caller knows the budget was hit.
    fn search_chunk(&self, chunk: usize, cap: usize, pairs: &mut Vec<(u32, u32)>, partners: &mut Vec<u32>) {
        pairs.clear();
        let n = self.positions.len();
        let asleep = |i: usize| self.asleep.is_some_and(|flags| flags[i]);
        // Whether b is found from a: every sleeping partner, awake ones only once.
        let second = |a: usize, b: usize| if asleep(b) { b != a } else { b > a };
        for a in chunk * CHUNK..((chunk + 1) * CHUNK).min(n) {
            let ra = self.reach[a];
            if !(ra > 0.0 && ra.is_finite()) || asleep(a) {
                continue;
            }
            partners.clear();
            let pa = self.positions[a];
            let touches = |b: usize| {
                let rb = self.reach[b];
                let reach = ra + rb;
                rb > 0.0 && rb.is_finite() && (pa - self.positions[b]).length_squared() < reach * reach
            };
            let consider = |b: usize, partners: &mut Vec<u32>| {
                if second(a, b) && touches(b) {
                    partners.push(b as u32);
                }
            };
            if self.cell_keys[a] == NOT_IN_GRID {
                // Oversized: against everything.
                (0..n).for_each(|b| consider(b, partners));
            } else {
                // Which of the two finds the pair first (an index compare, so half the
                // candidates cost no distance); every grid entry has a usable reach:
                // test it from the grid's copy.
                self.around(pa, |b, sphere| {
                    let reach = ra + sphere.w;
                    if second(a, b as usize) && (pa - sphere.truncate()).length_squared() < reach * reach {
                        partners.push(b);
                    }
                });
                self.oversized.iter().for_each(|&b| consider(b as usize, partners));
            }
            partners.sort_unstable();
            // Cells clamped at the coordinate limit can be visited twice.
            partners.dedup();
            pairs.extend(partners.iter().map(|&b| (a as u32, b)));
            if pairs.len() > cap {
                return;
            }
        }
    }
}

/// Integer cell coordinates of a point, clamped so they pack; a non-finite point lands
/// in some cell rather than panicking.
#[inline]
fn cell_of(p: Vec3, inverse_cell: f32) -> [i32; 3] {
    let c = p * inverse_cell;
    [c.x, c.y, c.z].map(|v| floor(v).clamp(-COORD_LIMIT, COORD_LIMIT))
}

/// Cell of a point in a dense grid, clamped into it (a non-finite point lands in some
/// cell rather than panicking).
#[inline]
fn dense_cell(p: Vec3, origin: Vec3, inverse_cell: f32, dims: [i32; 3]) -> [i32; 3] {
    let c = (p - origin) * inverse_cell;
    [floor(c.x).clamp(0, dims[0] - 1), floor(c.y).clamp(0, dims[1] - 1), floor(c.z).clamp(0, dims[2] - 1)]
}

/// `x.floor() as i32` without the library call `f32::floor` becomes on baseline x86-64
/// (it has no rounding instruction before SSE4.1): truncate, then step down for
/// negative non-integers. Saturates like `as` (NaN gives 0).
#[inline]
fn floor(x: f32) -> i32 {
    let t = x as i32;
    if (t as f32) > x { t - 1 } else { t }
}

/// Row-by-row number of a dense cell: x fastest, so neighbours along x are adjacent.
#[inline]
fn dense_index([x, y, z]: [i32; 3], dims: [i32; 3]) -> u64 {
    (x + dims[0] * (y + dims[1] * z)) as u64
}

/// Packs clamped cell coordinates into 63 bits (21 each, offset to be non-negative).
#[inline]
fn pack([x, y, z]: [i32; 3]) -> u64 {
    let field = |v: i32| (v.clamp(-COORD_LIMIT - 1, COORD_LIMIT) + (1 << 20)) as u64;
    (field(x) << 42) | (field(y) << 21) | field(z)
}

/// Fibonacci hashing: the top `bits` bits of the key times 2^64/φ.
#[inline]
fn bucket(key: u64, bits: u32) -> usize {
    (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
}

/// The reference the grid is tested against: every pair `(a, b)`, `a < b`, closer than
/// `reach[a] + reach[b]`, by testing all of them. O(n²); for tests and tiny worlds.
pub fn all_pairs(positions: &[Vec3], reach: &[f32], out: &mut Vec<(u32, u32)>) {
    out.clear();
    let usable = |r: f32| r > 0.0 && r.is_finite();
    for a in 0..positions.len() {
        if !usable(reach[a]) {
            continue;
        }
        for b in a + 1..positions.len() {
            let r = reach[a] + reach[b];
            if usable(reach[b]) && (positions[a] - positions[b]).length_squared() < r * r {
                out.push((a as u32, b as u32));
            }
        }
    }
}

/// Buffers the contact generators reuse between steps: what they ask the grid and
/// what it answers.
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    /// Reach of each particle for the broad phase (m).
    pub reach: Vec<f32>,
    /// Pairs from the broad phase.
    pub pairs: Vec<(u32, u32)>,
    /// Set when a search of the broad phase hit its pair budget (spheres piled onto
    /// each other: see [`pair_budget`]); the world clears it at the start of a step
    /// and reports it.
    pub pair_budget_hit: bool,
}

#[cfg(test)]
mod tests {
    use super::keep_where;
    use super::{BroadPhase, KEEP_BACKOFF, pair_budget};
    use glam::Vec3;

    /// Spheres so closely packed that their pairs fit the budget but their pairs
    /// grown by the skin do not: the plain search serves, nothing is kept, and the
    /// grown search waits before it is tried again (it is not run, to be cut short,
    /// every step).
    #[test]
    #[cfg_attr(miri, ignore = "8,000 spheres: too slow to interpret, and no unsafe code")]
    fn a_grown_search_past_the_budget_waits_before_it_is_tried_again() {
        let side = 20;
        let positions: Vec<Vec3> = (0..side * side * side)
            .map(|i| Vec3::new((i % side) as f32, (i / side % side) as f32, (i / (side * side)) as f32))
            .collect();
        let reach = vec![1.1; positions.len()];
        let mut broad_phase = BroadPhase::new();
        let mut pairs = Vec::new();
        broad_phase.find_pairs(&positions, &reach, &mut pairs);
        assert!(!broad_phase.budget_hit(), "the spheres' own pairs fit the budget");
        assert_eq!(broad_phase.kept.pairs.len(), pair_budget(positions.len()), "the grown ones did not");
        assert!(!broad_phase.kept.valid);
        assert_eq!(broad_phase.kept.wait, KEEP_BACKOFF);
        broad_phase.find_pairs(&positions, &reach, &mut pairs);
        assert_eq!(broad_phase.kept.wait, KEEP_BACKOFF - 1, "the next search only counts down");
    }

    /// Which pairs to keep.
    type Rule = dyn Fn(&(u32, u32)) -> bool;

    /// Keeping without a branch gives what a filter gives, appended after what the
    /// list held, for every pattern of kept and dropped pairs (none, all, runs, lone).
    #[test]
    fn keeping_without_a_branch_is_filtering() {
        let pairs: Vec<(u32, u32)> = (0..200).map(|i| (i, 1000 - i)).collect();
        let rules: [&Rule; 5] =
            [&|_| false, &|_| true, &|p| p.0 % 3 == 1, &|p| (p.0 / 10) % 2 == 0, &|p| p.0 == 199 || p.0 == 0];
        for (k, rule) in rules.iter().enumerate() {
            let mut kept = vec![(7, 7), (8, 8)];
            keep_where(&pairs, rule, &mut kept);
            let mut expected = vec![(7, 7), (8, 8)];
            expected.extend(pairs.iter().copied().filter(|p| rule(p)));
            assert_eq!(kept, expected, "rule {k}");
        }
    }
}

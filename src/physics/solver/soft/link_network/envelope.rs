//! A direct solver for the links' equations: a symmetric positive definite matrix
//! stored by its envelope (each row from its first nonzero to the diagonal) and
//! factored as `L D Lᵀ`, in `f64`, with the reverse Cuthill–McKee ordering that keeps
//! the envelope narrow (George & Liu, "Computer Solution of Large Sparse Positive
//! Definite Systems", 1981, chapter 4).
//!
//! Why an envelope: the matrix of a link network couples two links when they share a
//! particle. A chain orders into a tridiagonal matrix (width 1: the factorization is
//! linear in the number of links, a 200,000-rod chain included); a `k × k` net of rods
//! orders into a band about `2k` wide. Fill-in stays inside the envelope, so its size
//! is known before factoring, and the cost, `Σ width²`, can be checked against a budget
//! before any work is done (see [`Envelope::cost`]).
//!
//! Everything here is `+ - * /` on `f64` in a fixed order: the same bits on every
//! machine and thread count.

/// A symmetric matrix by its envelope, and its `L D Lᵀ` factors in place.
#[derive(Clone, Debug, Default)]
pub(super) struct Envelope {
    /// First column of each row's envelope.
    first: Vec<u32>,
    /// Where each row's entries start in `values`; one more entry for the end.
    start: Vec<usize>,
    /// Row `i`'s entries from column `first[i]` to `i - 1` (strictly lower part):
    /// the matrix before [`factor`](Self::factor), `L` after.
    values: Vec<f64>,
    /// The diagonal: the matrix's, then `D`'s.
    diagonal: Vec<f64>,
}

impl Envelope {
    /// Sets the shape: row `i` holds columns `first[i]..=i`. Entries become zero.
    pub(super) fn shape(&mut self, first: impl Iterator<Item = u32>) {
        self.first.clear();
        self.first.extend(first);
        self.start.clear();
        let mut at = 0;
        for (i, &f) in self.first.iter().enumerate() {
            self.start.push(at);
            at += i - f as usize;
        }
        self.start.push(at);
        self.values.clear();
        self.values.resize(at, 0.0);
        self.diagonal.clear();
        self.diagonal.resize(self.first.len(), 0.0);
    }

    /// Multiply-adds a factorization takes, `Σ width²` over the rows.
    pub(super) fn cost(first: &[u32]) -> f64 {
        first
            .iter()
            .enumerate()
            .map(|(i, &f)| {
                let width = (i - f as usize) as f64;
                width * width
            })
            .sum()
    }

    /// Sets every entry to zero, keeping the shape.
    pub(super) fn clear(&mut self) {
        self.values.iter_mut().for_each(|v| *v = 0.0);
        self.diagonal.iter_mut().for_each(|v| *v = 0.0);
    }

    /// Row `i`'s entry in column `j < i`, which must lie in the envelope.
    #[inline]
    pub(super) fn lower(&mut self, i: usize, j: usize) -> &mut f64 {
        let first = self.first[i] as usize;
        debug_assert!(first <= j && j < i, "({i}, {j}) is outside the envelope");
        &mut self.values[self.start[i] + j - first]
    }

    /// Row `i`'s diagonal entry.
    #[inline]
    pub(super) fn diagonal(&mut self, i: usize) -> &mut f64 {
        &mut self.diagonal[i]
    }

    /// Factors the matrix as `L D Lᵀ` in place, row by row (the bordering method).
    /// Returns false if a pivot is not positive (the matrix was not positive
    /// definite): the factors are then not to be used.
    ///
    /// Row `i` is first solved for `tⱼ = Lᵢⱼ Dⱼ = Aᵢⱼ - Σₘ tₘ Lⱼₘ` (left to right, in
    /// place), then `Dᵢ = Aᵢᵢ - Σ tⱼ² / Dⱼ` and `Lᵢⱼ = tⱼ / Dⱼ`: every inner loop is a
    /// dot product of two rows.
    #[must_use]
    pub(super) fn factor(&mut self) -> bool {
        let n = self.first.len();
        for i in 0..n {
            let (fi, si) = (self.first[i] as usize, self.start[i]);
            for j in fi..i {
                let (fj, sj) = (self.first[j] as usize, self.start[j]);
                let from = fi.max(fj);
                let (done, rest) = self.values.split_at_mut(si + j - fi);
                // Row j lies wholly before row i.
                let t = &done[si + from - fi..];
                let row_j = &done[sj + from - fj..sj + j - fj];
                rest[0] -= dot(t, row_j);
            }
            let mut pivot = self.diagonal[i];
            for (t, &d) in self.values[si..si + i - fi].iter_mut().zip(&self.diagonal[fi..i]) {
                let l = *t / d;
                pivot -= *t * l;
                *t = l;
            }
            if !(pivot > 0.0 && pivot.is_finite()) {
                return false;
            }
            self.diagonal[i] = pivot;
        }
        true
    }

    /// Solves `L D Lᵀ x = b` in place with the factors of [`factor`](Self::factor).
    pub(super) fn solve(&self, b: &mut [f64]) {
        let n = self.first.len();
        for i in 0..n {
            let (fi, si) = (self.first[i] as usize, self.start[i]);
            let (before, after) = b.split_at_mut(i);
            after[0] -= dot(&self.values[si..si + i - fi], &before[fi..]);
        }
        for (x, &d) in b.iter_mut().zip(&self.diagonal) {
            *x /= d;
        }
        for i in (0..n).rev() {
            let (fi, si) = (self.first[i] as usize, self.start[i]);
            let xi = b[i];
            let row = &self.values[si..si + i - fi];
            for (x, &l) in b[fi..i].iter_mut().zip(row) {
                *x -= l * xi;
            }
        }
    }
}

/// `Σ aₖ bₖ` over the shorter length, in four running sums added at the end: a fixed
/// order (the same bits everywhere) that does not wait on one sum.
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut sums = [0.0f64; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ta, tb) = (a4.remainder(), b4.remainder());
    for (x, y) in a4.zip(b4) {
        sums[0] += x[0] * y[0];
        sums[1] += x[1] * y[1];
        sums[2] += x[2] * y[2];
        sums[3] += x[3] * y[3];
    }
    let mut tail = 0.0;
    for (x, y) in ta.iter().zip(tb) {
        tail += x * y;
    }
    ((sums[0] + sums[1]) + (sums[2] + sums[3])) + tail
}

/// The reverse Cuthill–McKee ordering of a graph given by `neighbours(node)`, written
/// into `order` (position → node). Each connected part is numbered in turn from a
/// node of least degree, breadth first, neighbours by rising degree (ties by index),
/// and the whole is reversed. A path graph comes out in path order.
///
/// `degree`, `placed` and `queue` are scratch.
pub(super) fn reverse_cuthill_mckee<'a, N>(
    nodes: usize,
    neighbours: N,
    order: &mut Vec<u32>,
    degree: &mut Vec<u32>,
    placed: &mut Vec<bool>,
    queue: &mut Vec<u32>,
) where
    N: Fn(usize) -> &'a [u32],
{
    degree.clear();
    degree.extend((0..nodes).map(|i| neighbours(i).len() as u32));
    placed.clear();
    placed.resize(nodes, false);
    order.clear();
    // Starting nodes by rising degree; a part already numbered is skipped.
    queue.clear();
    queue.extend(0..nodes as u32);
    queue.sort_by_key(|&i| (degree[i as usize], i));
    let starts = std::mem::take(queue);
    for &start in &starts {
        if placed[start as usize] {
            continue;
        }
        placed[start as usize] = true;
        let mut head = order.len();
        order.push(start);
        while head < order.len() {
            let node = order[head] as usize;
            head += 1;
            let from = order.len();
            for &next in neighbours(node) {
                if !placed[next as usize] {
                    placed[next as usize] = true;
                    order.push(next);
                }
            }
            order[from..].sort_by_key(|&i| (degree[i as usize], i));
        }
    }
    *queue = starts;
    order.reverse();
}

#[cfg(test)]
// Dense test matrices read best by their indices.
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    /// A dense symmetric positive definite test matrix with a given sparsity.
    fn matrix(n: usize, pattern: impl Fn(usize, usize) -> bool) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in 0..i {
                if pattern(i, j) {
                    let v = 0.3 + 0.1 * ((i * 7 + j * 3) % 5) as f64;
                    a[i][j] = -v;
                    a[j][i] = -v;
                }
            }
        }
        for i in 0..n {
            a[i][i] = 1.0 + a[i].iter().map(|v| v.abs()).sum::<f64>();
        }
        a
    }

    fn envelope_of(a: &[Vec<f64>]) -> Envelope {
        let n = a.len();
        let first: Vec<u32> = (0..n).map(|i| (0..=i).find(|&j| a[i][j] != 0.0).unwrap() as u32).collect();
        let mut e = Envelope::default();
        e.shape(first.iter().copied());
        for i in 0..n {
            *e.diagonal(i) = a[i][i];
            for j in first[i] as usize..i {
                *e.lower(i, j) = a[i][j];
            }
        }
        e
    }

    #[test]
    #[cfg_attr(miri, ignore = "slow to interpret, and no unsafe code")]
    fn solves_a_banded_and_a_scattered_system() {
        for pattern in [
            |i: usize, j: usize| i - j <= 3,
            |i: usize, j: usize| (i + 2 * j).is_multiple_of(7) || i - j == 1,
        ] {
            let n = 40;
            let a = matrix(n, pattern);
            let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).fract() - 0.5).collect();
            let mut b: Vec<f64> = (0..n).map(|i| (0..n).map(|j| a[i][j] * x[j]).sum()).collect();
            let mut e = envelope_of(&a);
            assert!(e.factor());
            e.solve(&mut b);
            for (found, want) in b.iter().zip(&x) {
                assert!((found - want).abs() < 1e-12, "{found} against {want}");
            }
        }
    }

    #[test]
    fn a_matrix_that_is_not_positive_definite_is_refused() {
        let mut e = Envelope::default();
        e.shape([0, 0].into_iter());
        *e.diagonal(0) = 1.0;
        *e.diagonal(1) = 1.0;
        *e.lower(1, 0) = 2.0;
        assert!(!e.factor());
    }

    #[test]
    #[cfg_attr(miri, ignore = "slow to interpret, and no unsafe code")]
    fn a_path_orders_along_the_path_and_a_grid_into_a_narrow_band() {
        // A path given in scrambled order comes out as a path: width 1.
        let n = 50;
        let label = |k: usize| (k * 17) % n;
        let mut neighbours = vec![Vec::new(); n];
        for k in 0..n - 1 {
            neighbours[label(k)].push(label(k + 1) as u32);
            neighbours[label(k + 1)].push(label(k) as u32);
        }
        let (mut order, mut degree, mut placed, mut queue) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        reverse_cuthill_mckee(n, |i| &neighbours[i], &mut order, &mut degree, &mut placed, &mut queue);
        let mut position = vec![0; n];
        for (p, &node) in order.iter().enumerate() {
            position[node as usize] = p as i64;
        }
        for k in 0..n - 1 {
            assert_eq!((position[label(k)] - position[label(k + 1)]).abs(), 1);
        }
        // A 20 × 20 grid: the band is about the side, far below the 400 it could be.
        let side = 20;
        let mut neighbours = vec![Vec::new(); side * side];
        for r in 0..side {
            for c in 0..side {
                let i = r * side + c;
                for (dr, dc) in [(0, 1), (1, 0)] {
                    if r + dr < side && c + dc < side {
                        let j = (r + dr) * side + c + dc;
                        neighbours[i].push(j as u32);
                        neighbours[j].push(i as u32);
                    }
                }
            }
        }
        reverse_cuthill_mckee(
            side * side,
            |i| &neighbours[i],
            &mut order,
            &mut degree,
            &mut placed,
            &mut queue,
        );
        let mut position = vec![0i64; side * side];
        for (p, &node) in order.iter().enumerate() {
            position[node as usize] = p as i64;
        }
        let band = (0..side * side)
            .flat_map(|i| neighbours[i].iter().map(move |&j| (i, j as usize)))
            .map(|(i, j)| (position[i] - position[j]).abs())
            .max()
            .unwrap();
        assert!(band <= 2 * side as i64, "band {band}");
    }
}

//! Particles held by a taut straight path of links between two fixed points.
//!
//! Rods and cables never grow longer than their length. If a path of them joins two
//! fixed points `A` and `B` (immovable particles or anchors) and the lengths along it
//! add up to `|AB|`, then by the triangle inequality every particle `P` on it obeys
//! `|AB| ≤ |AP| + |PB| ≤ d(A, P) + d(P, B) = |AB|`: it lies on the segment, at
//! distance `d(A, P)` from `A`, and cannot move at all. The shipped cloth is such a
//! case: its pinned edge is a straight row of rods exactly as long as the pins are
//! apart. Solved as links, that row is singular (its rods' directions are dependent:
//! they can carry a tension in equilibrium with nothing, a self-stress), the equations
//! have no solution once the cloth pulls the row down, and any give let into the solve
//! turns the row into a stiff string whose vibrations drain the cloth's energy (a 10 ×
//! 10 cloth kept 34% of its swing energy over 20 s that way; held still, as ideal rods
//! hold it, 97%, measured with a scratch model of the exact solve).
//!
//! So such particles are found here and held still by the link solve, as ideal links
//! would hold them; their links to each other drop out of the solve (they carry the
//! self-stress, whose size no rigid model can tell: their tension reads 0), and links
//! from them to free particles act as links to a fixed point.
//!
//! A particle is held only if it is where the path puts it (within a ten-thousandth of
//! the span): a network built off its lengths is left to the solve. The search runs
//! only when the links or the fixed points change (the caller keeps a signature), and
//! is bounded: with more than [`MAX_FIXED`] fixed points, or more than [`MAX_WORK`]
//! fixed points times particles, nothing is held.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec3;

use crate::physics::particles::Particles;
use crate::physics::solver::soft::{NONE, SoftLink};

/// Most fixed points (immovable linked particles and anchors) searched from.
pub(super) const MAX_FIXED: usize = 64;
/// Most fixed points times linked particles the search may cover.
pub(super) const MAX_WORK: usize = 8_000_000;
/// A path counts as taut when it is at most this much longer than the span (relative).
const TAUT: f64 = 1e-5;
/// A particle is held only within this share of the span of where the path puts it.
const IN_PLACE: f64 = 1e-4;

/// Scratch of the search, kept between steps so that it allocates nothing once warm.
#[derive(Clone, Debug, Default)]
pub(super) struct TautPaths {
    /// Links at each particle (CSR: `start[i]..start[i + 1]` of `incident`).
    start: Vec<u32>,
    incident: Vec<u32>,
    /// Fixed points: position, and the particle it is (or [`NONE`] for an anchor,
    /// whose link is `link`).
    fixed: Vec<(DVec3, u32, u32)>,
    /// Which fixed point a fixed particle is, by particle.
    fixed_of: Vec<u32>,
    /// Path distance from each fixed point to each particle (`fixed × particles`).
    distance: Vec<f64>,
    /// Shortest path found between each pair of fixed points (`fixed × fixed`).
    between: Vec<f64>,
    heap: BinaryHeap<Reverse<(u64, u32)>>,
}

impl TautPaths {
    /// Marks in `held` (by particle) every movable particle on a taut path between two
    /// fixed points; returns whether any is.
    pub(super) fn find(&mut self, links: &[SoftLink], particles: &Particles, held: &mut Vec<bool>) -> bool {
        let n = particles.len();
        held.clear();
        held.resize(n, false);
        let w = &particles.inverse_mass;
        let position = |i: u32| particles.position[i as usize].as_dvec3();
        // Fixed points, in link order (deterministic).
        self.fixed.clear();
        self.fixed_of.clear();
        self.fixed_of.resize(n, NONE);
        for (k, link) in links.iter().enumerate() {
            if link.b == NONE {
                self.fixed.push((link.anchor.as_dvec3(), NONE, k as u32));
            }
            for end in [link.a, link.b] {
                if end != NONE && w[end as usize] <= 0.0 && self.fixed_of[end as usize] == NONE {
                    self.fixed_of[end as usize] = self.fixed.len() as u32;
                    self.fixed.push((position(end), end, NONE));
                }
            }
        }
        let k = self.fixed.len();
        if !(2..=MAX_FIXED).contains(&k) || k.saturating_mul(n) > MAX_WORK {
            return false;
        }
        // Links at each particle.
        self.start.clear();
        self.start.resize(n + 1, 0);
        for link in links {
            self.start[link.a as usize + 1] += 1;
            if link.b != NONE {
                self.start[link.b as usize + 1] += 1;
            }
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        self.incident.clear();
        self.incident.resize(self.start[n] as usize, 0);
        let mut fill = self.start.clone();
        for (index, link) in links.iter().enumerate() {
            for end in [link.a, link.b] {
                if end != NONE {
                    self.incident[fill[end as usize] as usize] = index as u32;
                    fill[end as usize] += 1;
                }
            }
        }
        self.distance.clear();
        self.distance.resize(k * n, f64::INFINITY);
        self.between.clear();
        self.between.resize(k * k, f64::INFINITY);
        for from in 0..k {
            self.search(from, links, w);
        }
        let mut any = false;
        for f in 0..k {
            for g in f + 1..k {
                let (pf, pg) = (self.fixed[f].0, self.fixed[g].0);
                let span = pf.distance(pg);
                let slack = span * TAUT;
                if span <= 0.0 || self.between[f * k + g].min(self.between[g * k + f]) > span + slack {
                    continue;
                }
                let (df, dg) = (&self.distance[f * n..(f + 1) * n], &self.distance[g * n..(g + 1) * n]);
                for i in 0..n {
                    if w[i] <= 0.0 || df[i] + dg[i] > span + slack {
                        continue;
                    }
                    let place = pf + (pg - pf) * (df[i] / span);
                    if position(i as u32).distance(place) <= span * IN_PLACE {
                        held[i] = true;
                        any = true;
                    }
                }
            }
        }
        any
    }

    /// Dijkstra from fixed point `from` through movable particles only, out to the
    /// farthest other fixed point (a path longer than the span cannot be taut).
    fn search(&mut self, from: usize, links: &[SoftLink], w: &[f32]) {
        let n = w.len();
        let k = self.fixed.len();
        let origin = self.fixed[from].0;
        let reach = self.fixed.iter().map(|f| f.0.distance(origin)).fold(0.0, f64::max) * (1.0 + TAUT);
        let mut walk = Walk {
            from,
            reach,
            w,
            fixed_of: &self.fixed_of,
            distance: &mut self.distance[from * n..(from + 1) * n],
            between: &mut self.between[from * k..(from + 1) * k],
            heap: &mut self.heap,
        };
        walk.heap.clear();
        // The first links: those at the fixed particle, or the anchor's own link.
        let (_, particle, anchor_link) = self.fixed[from];
        if particle != NONE {
            let range = self.start[particle as usize] as usize..self.start[particle as usize + 1] as usize;
            for &l in &self.incident[range] {
                let link = &links[l as usize];
                let other = if link.a == particle { link.b } else { link.a };
                walk.arrive(other, false, f64::from(link.length));
            }
        } else {
            let link = &links[anchor_link as usize];
            walk.arrive(link.a, false, f64::from(link.length));
        }
        while let Some(Reverse((bits, node))) = walk.heap.pop() {
            // Non-negative f64s order as their bits do.
            let d = f64::from_bits(bits);
            if d > walk.distance[node as usize] {
                continue; // an older, longer entry
            }
            let range = self.start[node as usize] as usize..self.start[node as usize + 1] as usize;
            for &l in &self.incident[range] {
                let link = &links[l as usize];
                let next = d + f64::from(link.length);
                if link.b == NONE {
                    // A path that ends at an anchor.
                    let g =
                        self.fixed.iter().position(|f| f.2 == l).expect("every anchor link is a fixed point");
                    if g != from {
                        walk.between[g] = walk.between[g].min(next);
                    }
                    continue;
                }
                let other = if link.a == node { link.b } else { link.a };
                walk.arrive(other, true, next);
            }
        }
    }
}

/// One search's view of the scratch.
struct Walk<'a> {
    from: usize,
    reach: f64,
    w: &'a [f32],
    fixed_of: &'a [u32],
    distance: &'a mut [f64],
    between: &'a mut [f64],
    heap: &'a mut BinaryHeap<Reverse<(u64, u32)>>,
}

impl Walk<'_> {
    /// The path reaches particle `end` at length `d`; `through` says whether it passed
    /// a movable particle on the way (a link from fixed point to fixed point holds
    /// nothing).
    fn arrive(&mut self, end: u32, through: bool, d: f64) {
        if self.w[end as usize] > 0.0 {
            if d < self.distance[end as usize] && d <= self.reach {
                self.distance[end as usize] = d;
                self.heap.push(Reverse((d.to_bits(), end)));
            }
        } else {
            let g = self.fixed_of[end as usize] as usize;
            if g != self.from && through {
                self.between[g] = self.between[g].min(d);
            }
        }
    }
}

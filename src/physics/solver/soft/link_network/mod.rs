//! Rods and cables solved exactly ([`LinkSolver::Exact`]): the links of a step form a
//! network whose impulses are found together, to convergence, with a direct solve.
//!
//! # Why
//!
//! Ideal rods do no work, so an undamped chain or cloth of them keeps its energy
//! (issue 18, item 7). Solved as soft constraints one at a time (Box2D v3's soft step,
//! [`LinkSolver::Soft`]), rods stretch (a cloth's by 2.5%), and the stretch is damped
//! and relaxed away: an undamped 20-rod chain kept 27% of its swing energy over 20 s at
//! 240 Hz, a 10 × 10 cloth 18% (`tests/joint_energy.rs` lists what was tried).
//!
//! # What
//!
//! Semi-implicit Euler with constraints, as SHAKE and RATTLE do it (Ryckaert, Ciccotti
//! & Berendsen 1977; Andersen 1983; Hairer, Lubich & Wanner, "Geometric Numerical
//! Integration", VII.1): in each substep, after the kick,
//! 1. **shake**: impulses `λ` along each link's direction at the *start* of the
//!    substep, such that after the drift (`x + h v`) every rod and taut cable has its
//!    length: `|d'ₖ(λ)| - Lₖ + αₖ λₖ / h = 0`;
//! 2. **project** (in the relax pass, after the drift): velocities made to agree with
//!    the links at their new directions (`J v = 0`, again solved together).
//!
//! That map is symplectic (the constraint force along the start-of-substep gradient is
//! what makes it so): its energy error stays bounded instead of draining. Measured on
//! a scratch model: a chain keeps 100% (the same run with the force along the *end*
//! gradient, i.e. a converged position projection as XPBD does, kept 7%). It only holds
//! if the equations are solved: Gauss-Seidel with 16 passes kept a 10 × 10 cloth's 33%,
//! whose matrix's condition grows with the square of its size.
//!
//! The equations are nonlinear; they are solved by Newton's method with the matrix
//! `J M⁻¹ Jᵀ + α / h²` at the start directions (so one factorization serves every
//! iteration: a quasi-Newton method that converges in 2 to 4 iterations at 240 Hz), and
//! a backtracking line search on the residual. `αₖ` is a small give, the compliance of
//! a spring of natural frequency [`link_hertz`](SolverSettings::link_hertz): rigid in
//! all but name, it keeps the matrix regular where links line up (a row of rods pulled
//! straight) and the equations would have no solution. Where they still have none
//! nearby (fast motion through such a moment, at large steps) the line search stalls;
//! the substep then takes the backward Euler step of the same springs (the force along
//! the *end* directions, Gauss-Newton on the implicit step's objective with a line
//! search: it always has a solution), which damps that moment a little.
//!
//! Cables are one-sided: a cable is in the equations while it would end the substep
//! stretched, and leaves them if its impulse would push (an active set, a few rounds).
//! Particles that a taut straight path of links holds still are found first (see
//! `taut.rs`) and held: their links to each other drop out.
//!
//! The matrix couples two links that share a particle. It is ordered by reverse
//! Cuthill–McKee and factored in its envelope (`envelope.rs`): linear in the number of
//! links for a chain (a 200,000-rod chain included), `n k²` for a `k`-wide net. A
//! network whose factorization would cost more than [`BUDGET`] is solved soft instead.
//!
//! The solve runs in `f64`, one network at a time in a fixed order, with `+ - * /` and
//! `sqrt` only: the same bits on every thread count and machine.

mod envelope;
mod shake;
mod taut;

use glam::{DVec3, Vec3};

use envelope::{Envelope, reverse_cuthill_mckee};
use taut::TautPaths;

use super::{Changes, NONE, SoftLink, note};
use crate::physics::particles::Particles;
use crate::physics::solver::settings::SolverSettings;

/// Most multiply-adds one factorization of a step's network may take before its links
/// are solved soft instead: about a millisecond and a half. A 30 × 30 cloth of rods
/// takes 3.1 million (a step of it 3.6 ms, 1,740 links), a 40 × 40 one 9.9 million
/// (9.6 ms: solved soft, 1.1 ms); a chain of 200,000 rods 0 (tridiagonal).
pub(super) const BUDGET: f64 = 4.0e6;
/// The solve stops when no link is off its length by more than this share of it.
const TOLERANCE: f64 = 1e-7;
/// A solve that stalls with every link within this share of its length is kept.
const NEARLY: f64 = 1e-4;
/// Old factors are replaced once an iteration shrinks the error by less than this.
const SLOW: f64 = 0.8;
/// Most Newton iterations of one solve.
const MAX_ITERATIONS: usize = 24;
/// Most halvings of a Newton step in the line search.
const MAX_HALVINGS: usize = 8;
/// Most rounds of the cables' active set.
const MAX_ROUNDS: usize = 4;
/// Most Gauss-Newton iterations of the backward Euler step.
const MAX_DAMPED: usize = 8;

/// A link as the network solves it. An end that does not move (an anchor, an immovable
/// or held particle) is [`NONE`] with its position in `fixed_*`.
#[derive(Clone, Copy, Debug, Default)]
struct Slot {
    /// Index in the step's links.
    link: u32,
    /// Local index of end `a` (pushed along the direction from `b` to `a`), or NONE.
    a: u32,
    b: u32,
    fixed_a: DVec3,
    fixed_b: DVec3,
    length: f64,
    rigid: bool,
}

/// The exact link solve's scratch: the network (rebuilt when the links change) and
/// the buffers of a substep. Nothing here carries between steps but a cache.
#[derive(Clone, Debug, Default)]
pub(super) struct LinkNetwork {
    /// What the network was built from (see [`signature`]); 0: never built.
    signature: u64,
    /// The step's links are solved here (false: no links, the soft solver chosen, or
    /// over [`BUDGET`]).
    exact: bool,
    /// Particles held still by a taut path (by dense index), and their list.
    held: Vec<bool>,
    held_list: Vec<u32>,
    taut: TautPaths,
    /// Links in solve order.
    slots: Vec<Slot>,
    /// Local index of each particle (NONE if it is not moved by the network).
    local_of: Vec<u32>,
    /// The particle of each local index, and its inverse mass.
    particle_of: Vec<u32>,
    w: Vec<f64>,
    /// For slot `i`, the slots `j < i` sharing a particle with it: (j, local particle,
    /// product of the two links' signs at it). CSR by `coupling_start`.
    coupling_start: Vec<u32>,
    coupling: Vec<(u32, u32, f64)>,
    matrix: Envelope,
    /// Ordering scratch: slots at each local particle, slot neighbours, RCM buffers.
    at_particle_start: Vec<u32>,
    at_particle: Vec<u32>,
    neighbour_start: Vec<u32>,
    neighbours: Vec<u32>,
    order: Vec<u32>,
    degree: Vec<u32>,
    placed: Vec<bool>,
    queue: Vec<u32>,
    unordered: Vec<Slot>,
    /// Substep state, by local index: positions, velocities, velocities after the kick
    /// (and contacts), a saved copy for the line search.
    x: Vec<DVec3>,
    v: Vec<DVec3>,
    kicked: Vec<DVec3>,
    saved: Vec<DVec3>,
    target: Vec<DVec3>,
    /// By slot: direction the impulse acts along, compliance, impulse, residual,
    /// Newton step, and whether it is in the equations.
    u: Vec<DVec3>,
    alpha: Vec<f64>,
    lambda: Vec<f64>,
    saved_lambda: Vec<f64>,
    /// Length each link is brought to by the end of the substep: its own, or, for a
    /// link that starts the substep off its length by more than `max_push_speed · h`,
    /// that much nearer to it (a network built stretched, or a particle moved by hand,
    /// is pulled back at that speed rather than in one substep).
    goal: Vec<f64>,
    residual: Vec<f64>,
    step: Vec<f64>,
    active: Vec<bool>,
    /// Cables the projection holds at no impulse over the substep (it would push).
    clamped: Vec<bool>,
    /// `1 / (2π link_hertz)²` (s²): a link's compliance per unit of inverse mass.
    compliance: f64,
    /// `matrix` holds factors made earlier in this step, for the links in
    /// `factored_active` (see [`factor`](Self::factor)); `fresh` if they are of the
    /// directions now in `u`.
    factored: bool,
    fresh: bool,
    factored_active: Vec<bool>,
    /// Substeps of this step, and how many have been shaken.
    substeps: u32,
    shaken: u32,
    /// [`SolverSettings::max_push_speed`] (m/s).
    max_push: f64,
    /// This substep's shake brought some link only part of the way to its length.
    correcting: bool,
}

impl LinkNetwork {
    /// Builds the network for this step's `links`, unless they are what it was built
    /// for. Afterwards [`exact`](Self::exact) says whether the links are solved here.
    pub(super) fn prepare(&mut self, links: &[SoftLink], particles: &Particles, settings: &SolverSettings) {
        use crate::physics::solver::settings::LinkSolver;
        if settings.link_solver != LinkSolver::Exact || links.is_empty() {
            self.exact = false;
            self.held_list.clear();
            self.signature = 0;
            return;
        }
        let omega = std::f64::consts::TAU * f64::from(settings.link_hertz);
        self.compliance = 1.0 / (omega * omega);
        // Each step factors anew: the solve then depends on nothing from an earlier
        // step, so a snapshot replays to the bit.
        self.factored = false;
        self.substeps = settings.substeps.max(1);
        self.shaken = 0;
        self.max_push = f64::from(settings.max_push_speed);
        let signature = signature(links, particles);
        if signature == self.signature {
            return;
        }
        self.signature = signature;
        self.build(links, particles);
    }

    /// Whether this step's links are solved by the network.
    pub(super) fn exact(&self) -> bool {
        self.exact
    }

    /// Whether the network moves (or holds still) the particle at dense index `i`.
    #[inline]
    pub(super) fn moves(&self, i: usize) -> bool {
        self.exact
            && (self.local_of.get(i).is_some_and(|&l| l != NONE)
                || self.held.get(i).copied().unwrap_or(false))
    }

    fn build(&mut self, links: &[SoftLink], particles: &Particles) {
        let n = particles.len();
        let any_held = self.taut.find(links, particles, &mut self.held);
        let w = &particles.inverse_mass;
        let moves = |i: u32| i != NONE && w[i as usize] > 0.0 && !(any_held && self.held[i as usize]);
        let fixed = |i: u32, anchor: Vec3| if i == NONE { anchor } else { particles.position[i as usize] };
        // Local indices, and the links that move something.
        self.local_of.clear();
        self.local_of.resize(n, NONE);
        self.particle_of.clear();
        self.unordered.clear();
        for (k, link) in links.iter().enumerate() {
            let (ma, mb) = (moves(link.a), moves(link.b));
            if !ma && !mb {
                continue;
            }
            let mut local = |i: u32, m: bool| {
                if !m {
                    return NONE;
                }
                if self.local_of[i as usize] == NONE {
                    self.local_of[i as usize] = self.particle_of.len() as u32;
                    self.particle_of.push(i);
                }
                self.local_of[i as usize]
            };
            let (a, b) = (local(link.a, ma), local(link.b, mb));
            self.unordered.push(Slot {
                link: k as u32,
                a,
                b,
                fixed_a: if ma { DVec3::ZERO } else { fixed(link.a, link.anchor).as_dvec3() },
                fixed_b: if mb { DVec3::ZERO } else { fixed(link.b, link.anchor).as_dvec3() },
                length: f64::from(link.length),
                rigid: link.rigid,
            });
        }
        self.held_list.clear();
        if any_held {
            self.held_list.extend((0..n as u32).filter(|&i| self.held[i as usize]));
        }
        let locals = self.particle_of.len();
        self.w.clear();
        self.w.extend(self.particle_of.iter().map(|&i| f64::from(w[i as usize])));
        // Slots at each local particle.
        let count = self.unordered.len();
        self.at_particle_start.clear();
        self.at_particle_start.resize(locals + 1, 0);
        for slot in &self.unordered {
            for end in [slot.a, slot.b] {
                if end != NONE {
                    self.at_particle_start[end as usize + 1] += 1;
                }
            }
        }
        for i in 0..locals {
            self.at_particle_start[i + 1] += self.at_particle_start[i];
        }
        // Pairs of links at one particle: a hub of many links makes a dense matrix, as
        // good as over budget; say so before building it.
        let pairs: f64 = (0..locals)
            .map(|i| f64::from(self.at_particle_start[i + 1] - self.at_particle_start[i]))
            .map(|d| d * d)
            .sum();
        if pairs > BUDGET {
            self.exact = false;
            self.held_list.clear();
            return;
        }
        self.at_particle.clear();
        self.at_particle.resize(self.at_particle_start[locals] as usize, 0);
        let mut fill: Vec<u32> = self.at_particle_start[..locals].to_vec();
        for (s, slot) in self.unordered.iter().enumerate() {
            for end in [slot.a, slot.b] {
                if end != NONE {
                    self.at_particle[fill[end as usize] as usize] = s as u32;
                    fill[end as usize] += 1;
                }
            }
        }
        // Neighbouring slots (sharing a particle), for the ordering.
        self.neighbour_start.clear();
        self.neighbours.clear();
        for slot in &self.unordered {
            self.neighbour_start.push(self.neighbours.len() as u32);
            for end in [slot.a, slot.b] {
                if end == NONE {
                    continue;
                }
                let range = self.at_particle_start[end as usize] as usize
                    ..self.at_particle_start[end as usize + 1] as usize;
                let mine = self.neighbour_start.len() as u32 - 1;
                self.neighbours.extend(self.at_particle[range].iter().copied().filter(|&o| o != mine));
            }
        }
        self.neighbour_start.push(self.neighbours.len() as u32);
        let (starts, list) = (&self.neighbour_start, &self.neighbours);
        reverse_cuthill_mckee(
            count,
            |i| &list[starts[i] as usize..starts[i + 1] as usize],
            &mut self.order,
            &mut self.degree,
            &mut self.placed,
            &mut self.queue,
        );
        self.slots.clear();
        self.slots.extend(self.order.iter().map(|&s| self.unordered[s as usize]));
        // Where each old slot went, then the couplings in the new order.
        self.degree.clear();
        self.degree.resize(count, 0);
        for (new, &old) in self.order.iter().enumerate() {
            self.degree[old as usize] = new as u32;
        }
        let position = &self.degree;
        self.coupling_start.clear();
        self.coupling.clear();
        self.queue.clear(); // first column of each row
        for (i, slot) in self.slots.iter().enumerate() {
            self.coupling_start.push(self.coupling.len() as u32);
            let mut first = i as u32;
            for (end, sign) in [(slot.a, 1.0), (slot.b, -1.0)] {
                if end == NONE {
                    continue;
                }
                let range = self.at_particle_start[end as usize] as usize
                    ..self.at_particle_start[end as usize + 1] as usize;
                for &old in &self.at_particle[range] {
                    let j = position[old as usize];
                    if j >= i as u32 {
                        continue;
                    }
                    let other = &self.slots[j as usize];
                    let other_sign = if other.a == end { 1.0 } else { -1.0 };
                    self.coupling.push((j, end, sign * other_sign));
                    first = first.min(j);
                }
            }
            self.queue.push(first);
        }
        self.coupling_start.push(self.coupling.len() as u32);
        if Envelope::cost(&self.queue) > BUDGET {
            self.exact = false;
            self.held_list.clear();
            return;
        }
        self.matrix.shape(self.queue.iter().copied());
        self.exact = true;
        for buffer in [&mut self.x, &mut self.v, &mut self.kicked, &mut self.saved, &mut self.target] {
            buffer.clear();
            buffer.resize(locals, DVec3::ZERO);
        }
        self.u.clear();
        self.u.resize(count, DVec3::Y);
        for buffer in [
            &mut self.alpha,
            &mut self.lambda,
            &mut self.saved_lambda,
            &mut self.goal,
            &mut self.residual,
            &mut self.step,
        ] {
            buffer.clear();
            buffer.resize(count, 0.0);
        }
        self.active.clear();
        self.active.resize(count, true);
        self.clamped.clear();
        self.clamped.resize(count, false);
    }

    /// Stops the particles a taut path holds (see `taut.rs`).
    pub(super) fn hold(&self, particles: &mut Particles, mut changes: Changes<'_>) {
        for &i in &self.held_list {
            let v = &mut particles.velocity[i as usize];
            note(&mut changes, i, -*v);
            *v = Vec3::ZERO;
        }
    }

    /// Reads the network's particles into `x` and `v`.
    fn load(&mut self, particles: &Particles) {
        for ((x, v), &i) in self.x.iter_mut().zip(&mut self.v).zip(&self.particle_of) {
            *x = particles.position[i as usize].as_dvec3();
            *v = particles.velocity[i as usize].as_dvec3();
        }
    }

    /// Writes `v` back to the particles, and what that changes of their velocities to
    /// `changes`.
    fn store(&self, particles: &mut Particles, mut changes: Changes<'_>) {
        for (v, &i) in self.v.iter().zip(&self.particle_of) {
            let (new, old) = (v.as_vec3(), &mut particles.velocity[i as usize]);
            note(&mut changes, i, new - *old);
            *old = new;
        }
    }

    /// Where slot `s`'s ends are after moving for `h` seconds (0: now).
    #[inline]
    fn ends(&self, s: &Slot, h: f64) -> (DVec3, DVec3) {
        let at = |end: u32, fixed: DVec3| {
            if end == NONE { fixed } else { self.x[end as usize] + self.v[end as usize] * h }
        };
        (at(s.a, s.fixed_a), at(s.b, s.fixed_b))
    }

    /// Directions of every slot's link (from `b` to `a`) after moving for `h` seconds.
    fn directions(&mut self, h: f64) {
        self.fresh = false;
        for i in 0..self.slots.len() {
            let (pa, pb) = self.ends(&self.slots[i], h);
            // Coincident ends: any fixed axis will do (as the soft solve's).
            self.u[i] = (pa - pb).try_normalize().unwrap_or(DVec3::Y);
        }
    }

    /// Makes sure `matrix` holds factors for the links now in the equations: made
    /// earlier in the step (stale: a quasi-Newton matrix) if `stale_ok`, else of the
    /// directions now in `u`. False if the matrix is not positive definite.
    fn ensure_factors(&mut self, h: f64, stale_ok: bool) -> bool {
        if self.factored && self.active == self.factored_active && (stale_ok || self.fresh) {
            return true;
        }
        self.factor(h)
    }

    /// Fills the matrix `J M⁻¹ Jᵀ + diag(α) / h²` at the directions `u`, rows of
    /// links outside the equations replaced by the identity, and factors it.
    ///
    /// Factors are reused through the step: the directions change little from one
    /// substep to the next, so the matrix of an earlier substep still makes a good
    /// Newton matrix, and a solve with its factors costs `2 × envelope` where a
    /// factorization costs `Σ width²` (a 40 × 40 cloth: 0.5 million against 30). The
    /// solves refactor when the old factors converge slowly.
    fn factor(&mut self, h: f64) -> bool {
        self.factored = false;
        self.matrix.clear();
        let inverse_h2 = 1.0 / (h * h);
        for (i, slot) in self.slots.iter().enumerate() {
            if !self.active[i] {
                *self.matrix.diagonal(i) = 1.0;
                continue;
            }
            let mass = |end: u32| if end == NONE { 0.0 } else { self.w[end as usize] };
            *self.matrix.diagonal(i) = mass(slot.a) + mass(slot.b) + self.alpha[i] * inverse_h2;
            let range = self.coupling_start[i] as usize..self.coupling_start[i + 1] as usize;
            for &(j, particle, sign) in &self.coupling[range] {
                if self.active[j as usize] {
                    *self.matrix.lower(i, j as usize) +=
                        sign * self.w[particle as usize] * self.u[i].dot(self.u[j as usize]);
                }
            }
        }
        self.factored = self.matrix.factor();
        self.fresh = self.factored;
        self.factored_active.clone_from(&self.active);
        self.factored
    }

    /// Adds impulses `scale · step` along `u` to the velocities.
    fn apply(&mut self, scale: f64) {
        for (i, slot) in self.slots.iter().enumerate() {
            let p = self.u[i] * (self.step[i] * scale);
            if slot.a != NONE {
                self.v[slot.a as usize] += p * self.w[slot.a as usize];
            }
            if slot.b != NONE {
                self.v[slot.b as usize] -= p * self.w[slot.b as usize];
            }
        }
    }

    /// The shake's residuals after the drift, as `-r / h` in `residual`; returns the
    /// sum of squared relative errors and the largest relative error.
    fn residuals(&mut self, h: f64) -> (f64, f64) {
        let (mut sum, mut worst) = (0.0, 0.0f64);
        for i in 0..self.slots.len() {
            let slot = self.slots[i];
            if !self.active[i] {
                self.residual[i] = 0.0;
                continue;
            }
            let (pa, pb) = self.ends(&slot, h);
            let r = pa.distance(pb) - self.goal[i] + self.alpha[i] * self.lambda[i] / h;
            self.residual[i] = -r / h;
            let relative = r / slot.length;
            sum += relative * relative;
            worst = worst.max(relative.abs());
        }
        (sum, worst)
    }
}

/// What a network is built from: each link's ends, length and kind, and where its
/// fixed ends are. Equal signatures, same network (a 64-bit mix; a collision would
/// only reuse an ordering that the solve checks as it goes).
fn signature(links: &[SoftLink], particles: &Particles) -> u64 {
    let mut hash = 0x9e37_79b9_7f4a_7c15_u64 ^ links.len() as u64 ^ ((particles.len() as u64) << 32);
    let mut mix = |value: u64| {
        hash = (hash ^ value).wrapping_mul(0x0100_0000_01b3).rotate_left(29);
    };
    for link in links {
        mix(u64::from(link.a) | (u64::from(link.b) << 32));
        mix(u64::from(link.length.to_bits()) | (u64::from(link.rigid) << 32));
        for end in [link.a, link.b] {
            let at = if end == NONE {
                link.anchor
            } else if particles.inverse_mass[end as usize] <= 0.0 {
                particles.position[end as usize]
            } else {
                continue;
            };
            mix(u64::from(at.x.to_bits()) | (u64::from(at.y.to_bits()) << 32));
            mix(u64::from(at.z.to_bits()) | 1 << 40);
        }
    }
    hash.max(1)
}

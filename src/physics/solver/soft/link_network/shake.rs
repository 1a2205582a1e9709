//! The two solves of a substep on the network (see `mod.rs`): the shake before the
//! drift, the projection after it, and the backward Euler step the shake falls back
//! to where its equations have no solution.

use super::{LinkNetwork, MAX_DAMPED, MAX_HALVINGS, MAX_ITERATIONS, MAX_ROUNDS, NEARLY, SLOW, TOLERANCE};
use crate::physics::particles::Particles;
use crate::physics::solver::soft::{Changes, NONE, SoftLink};

impl LinkNetwork {
    /// Before the drift: impulses along the links' start directions such that after
    /// moving for `h` seconds every rod and taut cable has its length (with its give).
    /// Each link's `impulse` becomes the one found (rods: negative pulls; cables:
    /// positive pulls), or 0 for a link the network leaves out.
    pub(in crate::physics::solver::soft) fn shake(
        &mut self,
        links: &mut [SoftLink],
        particles: &mut Particles,
        h: f32,
        mut changes: Changes<'_>,
    ) {
        self.hold(particles, changes.as_deref_mut());
        if !self.exact {
            return;
        }
        self.shaken += 1;
        let h = f64::from(h);
        self.load(particles);
        self.kicked.copy_from_slice(&self.v);
        self.directions(0.0);
        self.correcting = false;
        for i in 0..self.slots.len() {
            let slot = self.slots[i];
            let mass = |end: u32| if end == NONE { 0.0 } else { self.w[end as usize] };
            self.alpha[i] = (mass(slot.a) + mass(slot.b)) * self.compliance;
            let (pa, pb) = self.ends(&slot, 0.0);
            let error = pa.distance(pb) - slot.length;
            let reach = self.max_push * h;
            // A slack cable is no error: its target is its length.
            let excess = if slot.rigid { error } else { error.max(0.0) };
            self.goal[i] = slot.length + (excess - excess.clamp(-reach, reach));
            self.correcting |= self.goal[i] != slot.length;
            // A cable is in the equations if the drift would stretch it.
            let (pa, pb) = self.ends(&slot, h);
            self.active[i] = slot.rigid || pa.distance(pb) > self.goal[i];
        }
        for round in 0..MAX_ROUNDS {
            if round > 0 {
                self.v.copy_from_slice(&self.kicked);
            }
            self.lambda.iter_mut().for_each(|l| *l = 0.0);
            if round == 0 {
                // Start from the impulses of the substep before (saved with the links,
                // so a snapshot starts from the same): the solve then has only their
                // change to find, in fewer iterations.
                for (i, slot) in self.slots.iter().enumerate() {
                    let last = f64::from(links[slot.link as usize].impulse);
                    self.lambda[i] = match (self.active[i], slot.rigid) {
                        (false, _) => 0.0,
                        (true, true) => last,
                        (true, false) => (-last).min(0.0),
                    };
                }
                self.step.copy_from_slice(&self.lambda);
                self.apply(1.0);
            }
            if !(self.ensure_factors(h, true) && self.newton(h)) {
                self.damped(h);
            }
            // Cables: out if pushing, in if left stretched; solve again if any changed.
            let mut changed = false;
            for i in 0..self.slots.len() {
                let slot = self.slots[i];
                if slot.rigid {
                    continue;
                }
                let (pa, pb) = self.ends(&slot, h);
                let pushing = self.active[i] && self.lambda[i] > 0.0;
                let stretched = !self.active[i] && pa.distance(pb) > self.goal[i] * (1.0 + TOLERANCE);
                changed |= pushing || stretched;
            }
            if !changed || round + 1 == MAX_ROUNDS {
                break;
            }
            for i in 0..self.slots.len() {
                let slot = self.slots[i];
                if !slot.rigid {
                    let (pa, pb) = self.ends(&slot, h);
                    self.active[i] = if self.active[i] {
                        self.lambda[i] <= 0.0
                    } else {
                        pa.distance(pb) > self.goal[i] * (1.0 + TOLERANCE)
                    };
                }
            }
        }
        self.store(particles, changes);
        for link in links.iter_mut() {
            link.impulse = 0.0;
        }
        for (slot, &lambda) in self.slots.iter().zip(&self.lambda) {
            links[slot.link as usize].impulse = (if slot.rigid { lambda } else { -lambda }) as f32;
        }
    }

    /// After the drift of the step's last substep: velocities made to agree with the
    /// links at their new directions (no rod or taut cable lengthening or shortening),
    /// the cables that the shake kept in the equations staying in unless they would
    /// push. Adds the impulses to each link's `impulse`.
    ///
    /// Only the last substep projects. The next shake finds the impulses that put the
    /// links' ends where they must be after the drift, whatever velocities it starts
    /// from, so projecting in between changes no position (RATTLE's projection and
    /// the next shake's impulse act along the same directions and add up); it makes
    /// the velocities the step ends with agree with the links. A substep whose shake
    /// pulled a link back from far off its length projects too: the speed that
    /// moved it back is taken out again (as Box2D's relax pass takes out the push of
    /// its soft constraints), not kept for the next substep.
    pub(in crate::physics::solver::soft) fn project(
        &mut self,
        links: &mut [SoftLink],
        particles: &mut Particles,
        h: f32,
        mut changes: Changes<'_>,
    ) {
        self.hold(particles, changes.as_deref_mut());
        if !self.exact || (self.shaken < self.substeps && !self.correcting) {
            return;
        }
        let h = f64::from(h);
        self.load(particles);
        self.directions(0.0);
        self.saved.copy_from_slice(&self.v);
        // The shake's impulses: a cable may push back by as much as it pulled in the
        // substep (taking out the speed it gave), no more.
        self.saved_lambda.copy_from_slice(&self.lambda);
        self.clamped.iter_mut().for_each(|c| *c = false);
        for round in 0..MAX_ROUNDS {
            self.v.copy_from_slice(&self.saved);
            for i in 0..self.slots.len() {
                self.step[i] = if self.clamped[i] { -self.saved_lambda[i] } else { 0.0 };
            }
            self.apply(1.0);
            self.lambda.copy_from_slice(&self.step);
            if !self.refine(h) {
                // Not positive definite (it is, with any give): leave the velocities.
                self.v.copy_from_slice(&self.saved);
                self.lambda.iter_mut().for_each(|l| *l = 0.0);
                break;
            }
            let mut changed = false;
            for i in 0..self.slots.len() {
                if !self.slots[i].rigid && self.active[i] && self.saved_lambda[i] + self.lambda[i] > 0.0 {
                    changed = true;
                    if round + 1 < MAX_ROUNDS {
                        self.active[i] = false;
                        self.clamped[i] = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
        self.store(particles, changes);
        for (slot, &mu) in self.slots.iter().zip(&self.lambda) {
            links[slot.link as usize].impulse += (if slot.rigid { mu } else { -mu }) as f32;
        }
    }

    /// The projection's linear equations `(J M⁻¹ Jᵀ + α/h²) μ = -J v` at the directions
    /// in `u`, by iterative refinement on the factors at hand (one step if they are
    /// fresh), refactoring if they converge slowly. The impulses are added to `v` and
    /// to `lambda`. False if no factors could be made.
    fn refine(&mut self, h: f64) -> bool {
        if !self.ensure_factors(h, true) {
            return false;
        }
        let mut last = f64::INFINITY;
        for _ in 0..MAX_ITERATIONS {
            // Residual: the velocity along each link, with the give's share.
            let mut worst = 0.0f64;
            for i in 0..self.slots.len() {
                let slot = self.slots[i];
                if !self.active[i] {
                    self.step[i] = 0.0;
                    continue;
                }
                let velocity = |end: u32| if end == NONE { glam::DVec3::ZERO } else { self.v[end as usize] };
                let r = -self.u[i].dot(velocity(slot.a) - velocity(slot.b))
                    - self.alpha[i] * self.lambda[i] / (h * h);
                self.step[i] = r;
                worst = worst.max((r * h / slot.length).abs());
            }
            if worst <= TOLERANCE {
                break;
            }
            if worst > SLOW * last && !self.fresh && !self.factor(h) {
                return false;
            }
            last = worst;
            self.matrix.solve(&mut self.step);
            self.apply(1.0);
            for (l, &s) in self.lambda.iter_mut().zip(&self.step) {
                *l += s;
            }
        }
        true
    }

    /// Newton's method on the shake's equations, with the factors at hand (refactored
    /// at the start directions if they converge slowly) and a backtracking line
    /// search on the sum of squared residuals. True if it converged, or stalled with
    /// every link within [`NEARLY`] of its length.
    fn newton(&mut self, h: f64) -> bool {
        let (mut sum, mut worst) = self.residuals(h);
        for _ in 0..MAX_ITERATIONS {
            if worst <= TOLERANCE {
                return true;
            }
            self.step.copy_from_slice(&self.residual);
            self.matrix.solve(&mut self.step);
            self.saved.copy_from_slice(&self.v);
            self.saved_lambda.copy_from_slice(&self.lambda);
            let mut scale = 1.0;
            let mut accepted = false;
            for _ in 0..=MAX_HALVINGS {
                self.apply(scale);
                for (l, &s) in self.lambda.iter_mut().zip(&self.step) {
                    *l += s * scale;
                }
                let (trial_sum, trial_worst) = self.residuals(h);
                if trial_sum < sum * (1.0 - 1e-4 * scale) {
                    accepted = true;
                    let slow = trial_worst > SLOW * worst;
                    (sum, worst) = (trial_sum, trial_worst);
                    if slow && !self.fresh && !self.factor(h) {
                        return false;
                    }
                    break;
                }
                self.v.copy_from_slice(&self.saved);
                self.lambda.copy_from_slice(&self.saved_lambda);
                scale *= 0.5;
            }
            if !accepted {
                if self.fresh {
                    break;
                }
                // Old factors that find no descent: make fresh ones and go on.
                if !self.factor(h) {
                    return false;
                }
                self.residuals(h);
            }
        }
        worst <= NEARLY
    }

    /// The backward Euler step of the links taken as springs of compliance `α`, for
    /// a substep whose shake has no solution: Gauss-Newton on
    /// `Φ(v) = Σ ½ m h² |v - v_kicked|² + Σ ½ (h² / α) g(x + h v)²` (`g` a link's
    /// stretch), each iterate the kicked velocities plus impulses along the links'
    /// directions at the iterate, with a line search on `Φ`. It always has a solution;
    /// it damps what it corrects. `lambda` ends as the last impulses solved for.
    fn damped(&mut self, h: f64) {
        self.v.copy_from_slice(&self.kicked);
        let mut objective = self.objective(h);
        for _ in 0..MAX_DAMPED {
            self.directions(h);
            let mut worst = 0.0f64;
            for i in 0..self.slots.len() {
                let slot = self.slots[i];
                if !self.active[i] {
                    self.step[i] = 0.0;
                    continue;
                }
                let (pa, pb) = self.ends(&slot, h);
                let stretch = pa.distance(pb) - self.goal[i];
                worst = worst.max((stretch / slot.length).abs());
                let moved = |end: u32| {
                    if end == NONE {
                        glam::DVec3::ZERO
                    } else {
                        (self.v[end as usize] - self.kicked[end as usize]) * h
                    }
                };
                self.step[i] = (self.u[i].dot(moved(slot.a) - moved(slot.b)) - stretch) / h;
            }
            if worst <= TOLERANCE || !self.factor(h) {
                break;
            }
            self.matrix.solve(&mut self.step);
            // The Gauss-Newton iterate, then a line search from the current velocities.
            self.saved.copy_from_slice(&self.v);
            self.v.copy_from_slice(&self.kicked);
            self.apply(1.0);
            self.target.copy_from_slice(&self.v);
            self.lambda.copy_from_slice(&self.step);
            let mut scale = 1.0;
            let mut accepted = false;
            for _ in 0..=MAX_HALVINGS {
                for ((v, &from), &to) in self.v.iter_mut().zip(&self.saved).zip(&self.target) {
                    *v = from + (to - from) * scale;
                }
                let trial = self.objective(h);
                if trial <= objective {
                    objective = trial;
                    accepted = true;
                    break;
                }
                scale *= 0.5;
            }
            if !accepted {
                self.v.copy_from_slice(&self.saved);
                break;
            }
        }
    }

    /// `Φ` of [`damped`](Self::damped) at the current velocities.
    fn objective(&self, h: f64) -> f64 {
        let h2 = h * h;
        let mut sum = 0.0;
        for ((v, kicked), &w) in self.v.iter().zip(&self.kicked).zip(&self.w) {
            sum += 0.5 * h2 * (*v - *kicked).length_squared() / w;
        }
        for (i, slot) in self.slots.iter().enumerate() {
            if self.active[i] {
                let (pa, pb) = self.ends(slot, h);
                let stretch = pa.distance(pb) - self.goal[i];
                sum += 0.5 * h2 * stretch * stretch / self.alpha[i];
            }
        }
        sum
    }
}

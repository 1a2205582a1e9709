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

use glam::Vec3;

use super::{COLORS, NONE, OVERFLOW, SoftContact, SoftStep};
use crate::physics::particles::Particles;
use crate::physics::wide::{F4, M4, V4};

/// Lanes of a batch.
pub(super) const LANES: usize = 4;

/// Up to four contacts of one colour, lane by lane.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ContactBatch {
    /// Index in `SoftStep::contacts` of lane 0's contact; the lanes follow it.
    pub(super) first: u32,
    /// Lanes holding a contact (bit `i`: lane `i`); the rest repeat lane 0's particle
    /// indices and are never written back.
    pub(super) active: u32,
    /// Lanes whose contact has a second particle (bit `i`: lane `i`).
    pub(super) has_b: u32,
    /// Every lane (the idle ones repeat the last contact) is a pair of movable spheres
    /// that both roll, with friction and rolling resistance: the solve can skip the
    /// selects that keep a lane's old values where a part does not apply (most of a
    /// rolling pile's contacts).
    pub(super) full: bool,
    /// Dense index of each lane's particle `a`.
    pub(super) a: [u32; LANES],
    /// Dense index of each lane's particle `b`, or `a`'s where it has none (read, then
    /// replaced by zero through `has_b`).
    pub(super) b: [u32; LANES],
    pub(super) normal: V4,
    pub(super) separation: F4,
    pub(super) friction: F4,
    pub(super) mass: F4,
    pub(super) tangent_mass: F4,
    pub(super) lever_a: F4,
    pub(super) lever_b: F4,
    pub(super) rolling: F4,
    pub(super) rolling_mass: F4,
    /// Inverse masses of `a` and `b` (0 where there is no `b`) (1/kg).
    pub(super) wa: F4,
    pub(super) wb: F4,
    /// Inverse inertias of `a` and `b` (0 where there is no `b`) (1/(kg·m²)).
    pub(super) ia: F4,
    pub(super) ib: F4,
    pub(super) normal_impulse: F4,
    pub(super) tangent_impulse: V4,
    pub(super) rolling_impulse: V4,
}

impl ContactBatch {
    /// A batch of `contacts` (1 to 4, lane 0 at index `first` of the coloured list).
    fn new(first: usize, contacts: &[SoftContact], particles: &Particles) -> Self {
        debug_assert!(!contacts.is_empty() && contacts.len() <= LANES);
        let lane = |i: usize| &contacts[i.min(contacts.len() - 1)];
        let (w, inertia) = (&particles.inverse_mass, &particles.inverse_inertia);
        let mut batch = Self { first: first as u32, active: (1 << contacts.len()) - 1, ..Self::default() };
        let mut columns = [[0.0f32; LANES]; 14];
        let mut normals = [Vec3::ZERO; LANES];
        let (mut tangents, mut rollings) = ([Vec3::ZERO; LANES], [Vec3::ZERO; LANES]);
        for i in 0..LANES {
            let c = lane(i);
            let (a, has_b) = (c.a as usize, c.b != NONE);
            batch.a[i] = c.a;
            batch.b[i] = if has_b { c.b } else { c.a };
            if has_b && i < contacts.len() {
                batch.has_b |= 1 << i;
            }
            let (wb, ib) = if has_b { (w[c.b as usize], inertia[c.b as usize]) } else { (0.0, 0.0) };
            let values = [
                c.separation,
                c.friction,
                c.mass,
                c.tangent_mass,
                c.lever_a,
                c.lever_b,
                c.rolling,
                c.rolling_mass,
                w[a],
                wb,
                inertia[a],
                ib,
                c.normal_impulse,
                0.0,
            ];
            for (column, value) in columns.iter_mut().zip(values) {
                column[i] = value;
            }
            normals[i] = c.normal;
            tangents[i] = c.tangent_impulse;
            rollings[i] = c.rolling_impulse;
        }
        let full = (0..LANES).all(|i| {
            let c = lane(i);
            c.b != NONE
                && c.friction > 0.0
                && c.rolling > 0.0
                && [c.a, c.b].iter().all(|&p| w[p as usize] > 0.0 && inertia[p as usize] > 0.0)
        });
        let [separation, friction, mass, tangent_mass, lever_a, lever_b, rolling, rolling_mass, wa, wb, ia, ib, normal_impulse, _] =
            columns.map(F4::new);
        Self {
            normal: V4::new(normals),
            separation,
            friction,
            mass,
            tangent_mass,
            lever_a,
            lever_b,
            rolling,
            rolling_mass,
            wa,
            wb,
            ia,
            ib,
            normal_impulse,
            tangent_impulse: V4::new(tangents),
            rolling_impulse: V4::new(rollings),
            full,
            ..batch
        }
    }

    /// Lanes holding a contact.
    #[inline(always)]
    pub(super) fn lanes(&self) -> usize {
        self.active.count_ones() as usize
    }

    /// `has_b` as a mask.
    #[inline(always)]
    pub(super) fn has_b_mask(&self) -> M4 {
        M4::new([0, 1, 2, 3].map(|i| self.has_b & (1 << i) != 0))
    }
}

impl SoftStep {
    /// Lays the coloured contacts out in batches: each colour's contacts four at a
    /// time, the overflow's one at a time. `batch_starts[c]` is colour `c`'s first batch.
    pub(super) fn batch(&mut self, particles: &Particles) {
        self.batches.clear();
        for color in 0..=COLORS {
            self.batch_starts[color] = self.batches.len();
            let (start, end) = (self.color_starts[color], self.color_starts[color + 1]);
            let per_batch = if color == OVERFLOW { 1 } else { LANES };
            let mut first = start;
            while first < end {
                let last = (first + per_batch).min(end);
                self.batches.push(ContactBatch::new(first, &self.contacts[first..last], particles));
                first = last;
            }
        }
        self.batch_starts[COLORS + 1] = self.batches.len();
        // The solve reads and writes the lanes' particles without checking each index
        // again (`SharedVelocities::gather`): check them all once here.
        let n = particles.len() as u32;
        assert!(
            self.batches.iter().all(|batch| batch.a.iter().chain(&batch.b).all(|&i| i < n)),
            "a contact names a particle beyond the {n} there are"
        );
    }

    /// Copies the batches' impulses back into the contacts, for the warm start of the
    /// next step, sleeping and the debug view.
    pub(super) fn unbatch(&mut self) {
        for batch in &self.batches {
            let normal = batch.normal_impulse.to_array();
            let (tangent, rolling) = (batch.tangent_impulse.lanes(), batch.rolling_impulse.lanes());
            let first = batch.first as usize;
            for i in 0..batch.lanes() {
                let c = &mut self.contacts[first + i];
                c.normal_impulse = normal[i];
                c.tangent_impulse = tangent[i];
                c.rolling_impulse = rolling[i];
            }
        }
    }
}

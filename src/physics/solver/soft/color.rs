//! Stage 2, colour: no two contacts of one colour share a movable particle, so a colour
//! is solved in parallel with the same result as in order. The colouring depends on the
//! contacts alone, never on the thread count.

use glam::Vec3;
use rayon::prelude::*;

use super::{COLORS, NONE, OVERFLOW, SoftContact, SoftStep};
use crate::physics::particles::Particles;

/// A colour with at least this many contacts is split across threads.
const PARALLEL_CONTACTS: usize = 2048;
/// Contacts per parallel task.
const TASK: usize = 512;

/// Velocities shared by the tasks solving one colour.
#[derive(Clone, Copy)]
pub(super) struct SharedVelocities {
    ptr: *mut Vec3,
    len: usize,
}

// SAFETY: the pointer is only used while the solver holds the `&mut` to the velocity
// array it came from; see `get` and `set` for why tasks never touch the same element.
unsafe impl Send for SharedVelocities {}
unsafe impl Sync for SharedVelocities {}

impl SharedVelocities {
    pub(super) fn new(velocities: &mut [Vec3]) -> Self {
        Self { ptr: velocities.as_mut_ptr(), len: velocities.len() }
    }

    #[inline]
    pub(super) fn get(&self, i: usize) -> Vec3 {
        assert!(i < self.len);
        // SAFETY: in bounds (checked above). Within one colour, an element is written
        // only by the one contact of that colour that involves its (movable) particle,
        // so no other task writes it while this one reads; immovable particles' velocities
        // are never written during the solve.
        unsafe { *self.ptr.add(i) }
    }

    #[inline]
    pub(super) fn set(&self, i: usize, v: Vec3) {
        assert!(i < self.len);
        // SAFETY: in bounds; only called for movable particles, and the colouring gives
        // each movable particle at most one contact per colour (see `get`).
        unsafe { *self.ptr.add(i) = v }
    }
}

impl SoftStep {
    /// Stage 2: greedy colouring in generation order, then a counting sort into
    /// `contacts`. Depends on the contacts alone, never on the thread count.
    pub(super) fn color(&mut self, particles: &Particles) {
        let w = &particles.inverse_mass;
        self.masks.clear();
        self.masks.resize(particles.len(), 0);
        self.colors.clear();
        let mut counts = [0usize; COLORS + 1];
        for contact in &self.fresh {
            let (a, b) = (contact.a as usize, contact.b as usize);
            let movable_a = w[a] > 0.0;
            let movable_b = contact.b != NONE && w[b] > 0.0;
            let mut used = if movable_a { self.masks[a] } else { 0 };
            if movable_b {
                used |= self.masks[b];
            }
            let color = (!used).trailing_zeros() as usize;
            let color = if color < COLORS {
                let bit = 1u32 << color;
                if movable_a {
                    self.masks[a] |= bit;
                }
                if movable_b {
                    self.masks[b] |= bit;
                }
                color
            } else {
                OVERFLOW
            };
            self.colors.push(color as u8);
            counts[color] += 1;
        }
        self.color_starts[0] = 0;
        for (c, &count) in counts.iter().enumerate() {
            self.color_starts[c + 1] = self.color_starts[c] + count;
        }
        let mut cursor = self.color_starts;
        self.contacts.clear();
        self.contacts.resize(self.fresh.len(), SoftContact::default());
        for (origin, (contact, &color)) in self.fresh.iter().zip(&self.colors).enumerate() {
            let slot = &mut cursor[color as usize];
            self.contacts[*slot] = SoftContact { origin: origin as u32, ..*contact };
            *slot += 1;
        }
    }

    /// Runs `f` on every contact, colour by colour; large colours across threads.
    pub(super) fn for_each_contact(&mut self, f: impl Fn(&mut SoftContact) + Sync) {
        for_each_contact(&mut self.contacts, &self.color_starts, f);
    }
}

/// Runs `f` on every contact, colour by colour; a large colour is split across threads
/// (its contacts share no movable particle, so the order within it does not matter).
pub(super) fn for_each_contact(
    contacts: &mut [SoftContact],
    starts: &[usize; COLORS + 2],
    f: impl Fn(&mut SoftContact) + Sync,
) {
    for color in 0..=COLORS {
        let slice = &mut contacts[starts[color]..starts[color + 1]];
        if color != OVERFLOW && slice.len() >= PARALLEL_CONTACTS {
            slice.par_chunks_mut(TASK).for_each(|chunk| chunk.iter_mut().for_each(&f));
        } else {
            slice.iter_mut().for_each(&f);
        }
    }
}

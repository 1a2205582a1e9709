//! What the parallel tasks of a pass share, each task touching its own elements: the
//! velocity array a colour's solves read and write ([`SharedVelocities`]), and a list
//! handed out in disjoint runs ([`Disjoint`], kept with the particles' own runs in
//! `particles/parts.rs`). The soft solver's threads share memory here and there and
//! nowhere else; each `unsafe` states the invariant it rests on, and debug
//! builds check what can be checked of it (indices in bounds, the colours disjoint,
//! the threads' shares tiling each colour).

use std::marker::PhantomData;

use glam::Vec3;

pub(super) use crate::physics::particles::Disjoint;
use crate::physics::wide::{Lane, V};

/// The velocity array, shared by the tasks solving one colour at once: each task reads
/// and writes the velocities of its own contacts' particles through this handle.
///
/// It holds the array's exclusive borrow (`'a`) for as long as it lives, so nothing
/// else touches the array meanwhile; the tasks' accesses never overlap because of the
/// colouring, as the `SAFETY` note below states.
#[derive(Clone, Copy)]
pub(super) struct SharedVelocities<'a> {
    ptr: *mut Vec3,
    len: usize,
    /// The exclusive borrow of the array the pointer came from.
    _borrow: PhantomData<&'a mut [Vec3]>,
}

// SAFETY: the tasks that use one `SharedVelocities` at the same time solve the
// contacts of one colour (`for_each_batch`), and the invariant is: *within one
// colour, each movable particle belongs to at most one contact* (`color_greedily`
// builds it; debug builds check it after every colouring, `colours_are_disjoint`). A
// task writes only the velocities of its contacts' movable particles (the warm start
// and the solve scatter only to lanes whose particle has a positive inverse mass), so
// no element is written by two tasks or written by one while another reads it;
// immovable particles' velocities are only read. The overflow colour, which may
// repeat a particle, is solved in order on one thread. Sending the handle to the
// tasks is then sound for as long as `'a`, the exclusive borrow of the array, lasts.
unsafe impl Send for SharedVelocities<'_> {}
// SAFETY: as for `Send` above: shared by reference, the tasks still touch disjoint
// elements (or only read the immovable ones).
unsafe impl Sync for SharedVelocities<'_> {}

impl<'a> SharedVelocities<'a> {
    /// Shares `velocities` for the duration of its borrow.
    pub(super) fn new(velocities: &'a mut [Vec3]) -> Self {
        Self { ptr: velocities.as_mut_ptr(), len: velocities.len(), _borrow: PhantomData }
    }

    /// The velocities of the particles of a batch's lanes (four or eight). The batch's indices
    /// were checked against the particle count when it was made (`SoftStep::batch`).
    #[inline(always)]
    pub(super) fn gather<L: Lane>(&self, indices: L::Index) -> V<L> {
        debug_assert!(indices.as_ref().iter().all(|&i| (i as usize) < self.len));
        // SAFETY: every index is in bounds (checked when the batch was made), within
        // the borrow `'a`; no other task writes these elements meanwhile (the
        // invariant above: a lane's particle is written only by its own contact).
        unsafe { L::gather(self.ptr, self.len, indices) }
    }

    /// Sets the velocities of the lanes set in `lanes` (bit `i`: lane `i`), whose
    /// particles must be movable; the batch's indices were checked when it was made.
    #[inline(always)]
    pub(super) fn scatter<L: Lane>(&self, indices: L::Index, lanes: u32, value: V<L>) {
        debug_assert!(indices.as_ref().iter().all(|&i| (i as usize) < self.len));
        // SAFETY: in bounds (checked when the batch was made), within the borrow `'a`;
        // the lanes written are movable particles of one colour's contacts, distinct,
        // and by the invariant above read or written by no other task meanwhile.
        unsafe { L::scatter(value, self.ptr, self.len, indices, lanes) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::wide::{F4, V4};
    use rayon::prelude::*;

    /// Lanes read through the shared handle are the vectors plain indexing reads, and
    /// lanes written are the ones asked for; the others stay as they were.
    #[test]
    fn shared_velocities_read_and_write_what_indexing_does() {
        let mut velocities: Vec<Vec3> =
            (0..9).map(|i| Vec3::new(i as f32, 0.5 * i as f32, -(i as f32))).collect();
        let before = velocities.clone();
        let shared = SharedVelocities::new(&mut velocities);
        let read = shared.gather::<F4>([8, 0, 3, 3]).lanes();
        assert_eq!(read, [before[8], before[0], before[3], before[3]]);
        let value = V4::new([Vec3::ONE, Vec3::NAN, Vec3::X, Vec3::NAN]);
        shared.scatter::<F4>([1, 5, 7, 5], 0b0101, value);
        for (i, (now, was)) in velocities.iter().zip(&before).enumerate() {
            let expected = match i {
                1 => Vec3::ONE,
                7 => Vec3::X,
                _ => *was,
            };
            assert_eq!(*now, expected, "velocity {i}");
        }
    }

    /// Runs of a `Disjoint` list handed to tasks on several threads each write their
    /// own elements: the list ends as written one run after another.
    #[test]
    fn disjoint_runs_on_threads_write_their_own_elements() {
        let mut list = vec![0u32; 1000];
        let shared = Disjoint::new(&mut list);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool of two");
        pool.install(|| {
            (0..10).into_par_iter().for_each(|k| {
                // SAFETY: run `k` is `k*100..(k+1)*100`, given to task `k` alone.
                let run = unsafe { shared.run(k * 100..(k + 1) * 100) };
                for (i, x) in run.iter_mut().enumerate() {
                    *x = (k * 100 + i) as u32;
                }
            });
        });
        assert!(list.iter().enumerate().all(|(i, &x)| x == i as u32));
    }
}

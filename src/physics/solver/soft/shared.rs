//! What the parallel tasks of a pass share, each task touching its own elements: the
//! velocity array a colour's solves read and write ([`SharedVelocities`]), and a list
//! handed out in disjoint runs ([`Disjoint`]). The soft solver's threads share memory
//! here and nowhere else; each `unsafe` states the invariant it rests on.

use std::marker::PhantomData;

use glam::Vec3;

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
        unsafe { L::gather(self.ptr, indices) }
    }

    /// Sets the velocities of the lanes set in `lanes` (bit `i`: lane `i`), whose
    /// particles must be movable; the batch's indices were checked when it was made.
    #[inline(always)]
    pub(super) fn scatter<L: Lane>(&self, indices: L::Index, lanes: u32, value: V<L>) {
        debug_assert!(indices.as_ref().iter().all(|&i| (i as usize) < self.len));
        // SAFETY: in bounds (checked when the batch was made), within the borrow `'a`;
        // the lanes written are movable particles of one colour's contacts, distinct,
        // and by the invariant above read or written by no other task meanwhile.
        unsafe { L::scatter(value, self.ptr, indices, lanes) }
    }
}

/// A slice shared by tasks that each touch their own disjoint runs of it: the batches
/// of a pass (`run_on_all_threads` hands out each run to exactly one thread: thread `i`
/// takes its [`share`] of a colour, the overflow colour only thread 0), the coloured
/// contacts as `unbatch` writes them back (each batch its own contacts)
/// and the coloured contact list of the counting sort (`sort_by_color` gives each
/// chunk of fresh contacts, in each bucket, its own slots: the prefix sums of the
/// chunks' counts). It holds the slice's exclusive borrow for as long as it lives, and
/// nothing reads the slice through it outside the tasks' own runs.
pub(super) struct Disjoint<'a, T> {
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
    pub(super) fn new(slice: &'a mut [T]) -> Self {
        Self { ptr: slice.as_mut_ptr(), len: slice.len(), _borrow: PhantomData }
    }

    /// The elements `range`, which must be in bounds and given to no other task.
    ///
    /// # Safety
    /// `range` must be this task's alone while the run is used.
    #[allow(clippy::mut_from_ref)]
    pub(super) unsafe fn run(&self, range: std::ops::Range<usize>) -> &mut [T] {
        assert!(range.start <= range.end && range.end <= self.len);
        // SAFETY: in bounds (checked above); exclusive to this task (the caller's
        // promise), within the borrow `'a`.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(range.start), range.end - range.start) }
    }
}


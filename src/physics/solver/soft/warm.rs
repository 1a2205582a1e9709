//! Warm starting: what the solver keeps of a step for the next (impulses by contact key
//! and by link), how it picks it up again, and how a snapshot saves it.

use rayon::prelude::*;

use super::{FreshContact, NONE, SoftContact, SoftMemory, SoftStep, Warm};
use crate::physics::hash::StateHasher;

/// Contacts from which their impulses are stored, and picked up, on several threads.
const PARALLEL_STORE: usize = 8192;
/// Contacts per piece of the parallel pick-up.
const PIECE: usize = 4096;

impl SoftStep {
    /// What the next step reads of this one: the warm-start impulses and each link's
    /// last tension. A snapshot holds it, so a loaded world steps on with the same bits.
    pub(crate) fn memory(&self) -> SoftMemory {
        SoftMemory {
            warm: self.warm.clone(),
            warm_groups: self.warm_groups.clone(),
            warm_links: self.warm_links.clone(),
            last_tension: self.last_tension.clone(),
        }
    }

    /// Takes back what [`SoftStep::memory`] gave, after checking that its ranges fit
    /// (a hand-edited snapshot must not make the next step index out of bounds).
    pub(crate) fn restore(&mut self, memory: SoftMemory, generators: usize) -> Result<(), String> {
        // One group and one link impulse per generator at most: the step looks them up.
        if memory.warm_groups.len() > generators || memory.warm_links.len() > generators {
            return Err("more warm-start groups or link impulses than contact generators".into());
        }
        for (id, range) in &memory.warm_groups {
            if range.start > range.end || range.end > memory.warm.len() {
                return Err(format!(
                    "warm-start group of contact generator {} covers {}..{} of {} contacts",
                    id.0,
                    range.start,
                    range.end,
                    memory.warm.len()
                ));
            }
        }
        let impulses = memory.warm.iter().all(|w| {
            w.normal_impulse.is_finite() && w.tangent_impulse.is_finite() && w.rolling_impulse.is_finite()
        });
        let links = memory
            .warm_links
            .iter()
            .map(|l| l.1)
            .chain(memory.last_tension.iter().copied())
            .all(f32::is_finite);
        if !(impulses && links) {
            return Err("a warm-start impulse or a link's last tension is not finite".into());
        }
        self.warm = memory.warm;
        self.warm_groups = memory.warm_groups;
        self.warm_links = memory.warm_links;
        self.last_tension = memory.last_tension;
        Ok(())
    }

    /// Feeds the warm-start impulses to a state hash, without copying them.
    pub(crate) fn memory_hash_into(&self, hasher: &mut StateHasher) {
        for warm in &self.warm {
            hasher.u64(warm.key);
            hasher.f32(warm.normal_impulse);
            hasher.vec3(warm.tangent_impulse);
            // Only contacts of spheres that roll resist rolling: a world of point
            // masses hashes as it did before spheres could roll.
            if warm.rolling_impulse != glam::Vec3::ZERO {
                hasher.vec3(warm.rolling_impulse);
            }
        }
        for &(generator, impulse) in &self.warm_links {
            hasher.u64(u64::from(generator));
            hasher.f32(impulse);
        }
    }

    /// Finds last step's impulses of this step's contacts (`picked`: their places in
    /// `warm`, for the colour stage's sort to copy) and gives the links theirs; `keys`
    /// are the fresh contacts' keys (taken out of `fresh_keys` while the colouring
    /// reads them too), `generators` is how many contact generators the world has.
    ///
    /// It also marks the contacts that wait (`waits`): apart at the start of the step
    /// and without a normal impulse to start from (see `color::bucket`).
    pub(super) fn warm_start_from_last_step(&mut self, keys: &[u64], generators: usize) {
        let n = self.fresh.len();
        self.waits.clear();
        self.waits.resize(n, false);
        self.picked.clear();
        self.picked.resize(n, NONE);
        let (fresh, warm) = (&self.fresh, &self.warm);
        for (id, range) in &self.fresh_groups {
            let contacts = &fresh[range.clone()];
            let (picked, waits) = (&mut self.picked[range.clone()], &mut self.waits[range.clone()]);
            let Some((_, old)) = self.warm_groups.iter().find(|(old_id, _)| old_id == id) else {
                for (contact, waits) in contacts.iter().zip(waits) {
                    *waits = waiting(contact, 0.0);
                }
                continue;
            };
            let (old_keys, new_keys, base) = (&warm[old.clone()], &keys[range.clone()], old.start);
            // Both runs are sorted by key: walk them together, from where the old run
            // reaches a piece's first key (pieces on several threads for long runs).
            let pick_up = |(((contacts, new_keys), picked), waits): Piece<'_>| {
                let Some(&first) = new_keys.first() else { return };
                let mut j = old_keys.partition_point(|warm| warm.key < first);
                for (((contact, &k), picked), waits) in contacts.iter().zip(new_keys).zip(picked).zip(waits) {
                    while j < old_keys.len() && old_keys[j].key < k {
                        j += 1;
                    }
                    let mut normal_impulse = 0.0;
                    if j < old_keys.len() && old_keys[j].key == k {
                        *picked = (base + j) as u32;
                        normal_impulse = old_keys[j].normal_impulse;
                    }
                    *waits = waiting(contact, normal_impulse);
                }
            };
            if contacts.len() >= PARALLEL_STORE {
                let pieces = contacts.par_chunks(PIECE).zip(new_keys.par_chunks(PIECE));
                pieces.zip(picked.par_chunks_mut(PIECE)).zip(waits.par_chunks_mut(PIECE)).for_each(pick_up);
            } else {
                pick_up((((contacts, new_keys), picked), waits));
            }
        }
        // Last step's impulses by generator index, so each link finds its own at once
        // (searching the list per link made a chain of 200,000 rods cost 7 s a step).
        // Filled from the back so that, as a search from the front would, the first
        // entry for a generator wins (a restored snapshot may hold one twice).
        let by_generator = &mut self.warm_link_by_generator;
        by_generator.clear();
        by_generator.resize(generators, None);
        for &(generator, impulse) in self.warm_links.iter().rev() {
            if let Some(slot) = by_generator.get_mut(generator as usize) {
                *slot = Some(impulse);
            }
        }
        for link in &mut self.links {
            if let Some(Some(impulse)) = by_generator.get(link.generator as usize) {
                link.impulse = *impulse;
            }
        }
    }

    /// Stage 4: keep impulses for the next step; report link tensions.
    pub(super) fn store(&mut self, h: f32, link_tension: &mut [f32]) {
        // Every entry is written below: only growth needs filling.
        self.warm.resize(self.fresh.len(), Warm::default());
        // In generation order: each entry reads the contact its fresh one became.
        let (contacts, slots, keys) = (&self.contacts, &self.slots, &self.fresh_keys);
        let keep = |(origin, warm): (usize, &mut Warm)| {
            let contact = &contacts[slots[origin] as usize];
            *warm = Warm {
                key: keys[origin],
                normal_impulse: contact.normal_impulse,
                tangent_impulse: contact.tangent_impulse,
                rolling_impulse: contact.rolling_impulse,
            };
        };
        if self.warm.len() >= PARALLEL_STORE {
            self.warm.par_iter_mut().enumerate().with_min_len(1024).for_each(keep);
        } else {
            self.warm.iter_mut().enumerate().for_each(keep);
        }
        std::mem::swap(&mut self.warm_groups, &mut self.fresh_groups);
        self.warm_links.clear();
        for link in &self.links {
            self.warm_links.push((link.generator, link.impulse));
            // Rods pull with a negative impulse, cables with a positive one.
            let tension = if link.rigid { -link.impulse } else { link.impulse } / h;
            if let Some(slot) = link_tension.get_mut(link.generator as usize) {
                *slot = tension;
            }
        }
        // A sleeping link carries what it carried when it fell asleep: a bridge at rest
        // still holds its load.
        self.last_tension.resize(link_tension.len(), 0.0);
        for &generator in &self.sleeping_links {
            if let Some(slot) = link_tension.get_mut(generator as usize) {
                *slot = self.last_tension[generator as usize];
            }
        }
        self.last_tension.copy_from_slice(link_tension);
    }
}

/// Sort key of a contact within its generator's run.
#[inline]
pub(super) fn key(a: u32, b: u32) -> u64 {
    (u64::from(a) << 32) | u64::from(b)
}

/// Whether a contact waits: apart at the start of the step and without a normal
/// impulse to start from (`normal_impulse`, last step's; see `color::bucket`).
fn waiting(contact: &FreshContact, normal_impulse: f32) -> bool {
    contact.separation > 0.0 && normal_impulse == 0.0
}

/// A piece of the pick-up: fresh contacts, their keys, and what it writes of each
/// (where its impulses are in `warm`, whether it waits).
type Piece<'a> = (((&'a [FreshContact], &'a [u64]), &'a mut [u32]), &'a mut [bool]);

impl SoftStep {
    /// The contact `contact` (fresh contact number `origin`) with the impulses the
    /// pick-up found for it (`picked`, see
    /// [`warm_start_from_last_step`](SoftStep::warm_start_from_last_step)), or none.
    #[inline]
    pub(super) fn with_impulses(
        warm: &[Warm],
        contact: &FreshContact,
        picked: u32,
        origin: u32,
    ) -> SoftContact {
        let FreshContact { a, b, normal, separation, source } = *contact;
        let mut out = SoftContact { a, b, normal, separation, source, origin, ..SoftContact::default() };
        if let Some(warm) = warm.get(picked as usize) {
            out.normal_impulse = warm.normal_impulse;
            // The normal turned a little since: keep the tangential part.
            let t = warm.tangent_impulse;
            out.tangent_impulse = t - normal * t.dot(normal);
            // Kept whether or not the contact rolls now: one that does not gets none
            // where its batch is made (`ContactBatch::new`).
            out.rolling_impulse = warm.rolling_impulse;
        }
        out
    }
}

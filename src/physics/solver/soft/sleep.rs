//! Islands and sleep: particles joined by contacts and links that have all been slow
//! for a while stop being simulated until something disturbs them.

use glam::Vec3;

use super::{NONE, SoftStep};
use crate::physics::particles::{AWAKE, Disjoint, Particles, Sleep, on_threads};
use crate::physics::solver::settings::SolverSettings;

impl SoftStep {
    /// Wakes the islands of sleeping particles that were moved or pushed from outside
    /// (dragged, teleported, given a velocity) since the last step.
    pub(super) fn wake_disturbed(&mut self, particles: &mut Particles) {
        self.to_wake.clear();
        let bodies = particles.sleep.iter().zip(&particles.position).zip(&particles.velocity);
        for (((sleep, &p), &v), &spin) in bodies.zip(&particles.angular_velocity) {
            if sleep.island != AWAKE && (v != Vec3::ZERO || spin != Vec3::ZERO || p != sleep.rest) {
                self.to_wake.push(sleep.island);
            }
        }
        wake(particles, &mut self.to_wake);
    }

    /// Stage 5: islands whose every particle has been slow for `sleep_time` fall
    /// asleep. An island is the particles joined by contacts (speculative ones too) and links
    /// (immovable particles and planes join nothing).
    pub(super) fn fall_asleep(&mut self, particles: &mut Particles, settings: &SolverSettings, dt: f32) {
        self.to_wake.clear();
        let ready = self.time_the_slow(particles, settings, dt);
        wake(particles, &mut self.to_wake);
        if !ready {
            return;
        }
        // An island (particles joined by contacts, speculative ones too, and links;
        // immovable particles and planes join nothing) falls asleep when every particle
        // in it is ready: slow for `sleep_time`. So only the ready particles are joined
        // into islands, and a ready island joined to a movable particle that is not
        // ready is blocked: the islands left are whole islands of ready particles, the
        // ones that fall asleep. (Joining every contact into islands took 0.27 ms of a
        // forming 8,000-sphere pile's step. While the pile forms, more of its spheres
        // become ready, up to half of them by step 180 with 12,000 of its 29,000
        // contacts joining two ready ones, and the spheres still moving block every
        // island.) Every contact joins, speculative ones too: a pair close enough to
        // have a contact is close enough that the next step's contact would wake one
        // from the other, so two islands split by a near miss would wake each other in
        // turn.
        let n = particles.len();
        let w = &particles.inverse_mass;
        self.parent.clear();
        self.parent.extend(0..n as u32);
        self.blocked.clear();
        self.blocked.resize(n, false);
        self.join_contacts(w);
        let (parent, blocked, ready) = (&mut self.parent, &mut self.blocked, &self.ready);
        for link in &self.links {
            match joining(ready, w, link.a, link.b) {
                Joining::Both => union(parent, link.a, link.b),
                Joining::Blocks(i) => blocked[i as usize] = true,
                Joining::Neither => {}
            }
        }
        // A block holds for the whole island: note it at the island's root.
        for i in 0..n {
            if blocked[i] {
                let root = find(parent, i as u32) as usize;
                blocked[root] = true;
            }
        }
        for (i, &ready) in ready.iter().enumerate() {
            if !ready {
                continue;
            }
            // The root is the island's lowest index (see `union`): its label.
            let root = find(parent, i as u32);
            if !blocked[root as usize] {
                // Falling asleep stops what little motion was left: count it as lost.
                let v = particles.velocity[i];
                particles.dissipated +=
                    0.5 * f64::from(v.length_squared()) / f64::from(particles.inverse_mass[i]);
                particles.velocity[i] = Vec3::ZERO;
                let (spin, inverse_inertia) = (particles.angular_velocity[i], particles.inverse_inertia[i]);
                if inverse_inertia != 0.0 {
                    particles.dissipated +=
                        0.5 * f64::from(spin.length_squared()) / f64::from(inverse_inertia);
                    particles.angular_velocity[i] = Vec3::ZERO;
                }
                particles.sleep[i] = Sleep { timer: 0.0, island: root, rest: particles.position[i] };
            }
        }
    }
}

impl SoftStep {
    /// Each awake particle's time at rest brought up to date (reset when it is not slow),
    /// and each sleeping island that a force now acts on (a new spring, a float reaching
    /// water) noted in `to_wake`; which particles are ready to sleep (`ready`: movable
    /// and slow for `sleep_time`, noted before any falls asleep, which resets its
    /// timer), and whether any is. On the pool's threads, each its own run of
    /// particles, for many particles: each particle's timer is its own, so the same bits
    /// on any number of threads. (On one thread it took 92 µs of an 8,000-sphere step,
    /// 59 µs on two.)
    fn time_the_slow(&mut self, particles: &mut Particles, settings: &SolverSettings, dt: f32) -> bool {
        use std::sync::Mutex;
        use std::sync::atomic::{AtomicBool, Ordering};
        let Particles { sleep, velocity, force, inverse_mass, angular_velocity, radius, .. } = particles;
        let (velocity, force, inverse_mass) = (&*velocity, &*force, &*inverse_mass);
        let (angular_velocity, radius, delta) = (&*angular_velocity, &*radius, &self.delta);
        // Rare (a force reaching a sleeping island), so one list behind a lock will do.
        let to_wake = Mutex::new(&mut self.to_wake);
        let any_ready = AtomicBool::new(false);
        // Every flag is written below.
        self.ready.resize(sleep.len(), false);
        let (sleeps, ready) = (Disjoint::new(sleep), Disjoint::new(&mut self.ready));
        on_threads(sleeps.len(), |run| {
            let first = run.start;
            // SAFETY: `on_threads` gives each run to one thread; the runs are disjoint.
            let (sleeps, ready) = unsafe { (sleeps.run(run.clone()), ready.run(run)) };
            let mut any = false;
            for (k, (sleep, ready)) in sleeps.iter_mut().zip(ready).enumerate() {
                let i = first + k;
                if sleep.island != AWAKE {
                    if force[i] != Vec3::ZERO {
                        to_wake.lock().expect("no thread panics holding it").push(sleep.island);
                    }
                } else {
                    // Slow by its velocity and by how far it moved: the relax pass leaves
                    // a particle still being pushed out of an overlap with almost no
                    // velocity. Particles that forces keep holding never sleep: the
                    // force may change. A sphere that spins in place is not at rest: its
                    // surface moves at |ω| r.
                    let speed = velocity[i]
                        .length()
                        .max(delta[i].length() / dt)
                        .max(angular_velocity[i].length() * radius[i]);
                    let slow =
                        inverse_mass[i] > 0.0 && speed < settings.sleep_speed && force[i] == Vec3::ZERO;
                    sleep.timer = if slow { sleep.timer + dt } else { 0.0 };
                }
                *ready = inverse_mass[i] > 0.0 && sleep.timer >= settings.sleep_time;
                any |= *ready;
            }
            if any {
                any_ready.store(true, Ordering::Relaxed);
            }
        });
        any_ready.into_inner()
    }

    /// Joins the contacts' ready particles into islands (`parent`, set apart before)
    /// and marks each ready particle a contact joins to a movable one that is not ready
    /// (`blocked`, all false before), given the particles' inverse masses `w`. The keys
    /// are read on the pool's threads, each its own run of them: each run marks its
    /// blocks (flags only ever set, so the same flags whichever thread sets one) and
    /// lists its pairs of ready particles, which are then joined on this thread. The
    /// islands do not depend on the order of the joins (each is labelled by its lowest
    /// index, see [`union`]). (A forming 8,000-sphere pile has 29,000 contacts, of
    /// which up to 12,000 join two ready spheres.)
    fn join_contacts(&mut self, w: &[f32]) {
        use std::sync::Mutex;
        use std::sync::atomic::{AtomicBool, Ordering};
        let (keys, ready) = (&self.fresh_keys, &self.ready);
        // SAFETY: `AtomicBool` has the size, alignment and bit validity of `bool`; the
        // exclusive borrow of `blocked` is held while `blocked` is used, and only
        // through it.
        let blocked: &[AtomicBool] =
            unsafe { &*(std::ptr::from_mut::<[bool]>(&mut self.blocked[..]) as *const [AtomicBool]) };
        // Each run writes its pairs from where it begins, so only lengths matter here.
        self.joins.resize(keys.len(), 0);
        self.join_runs.clear();
        let joins = Disjoint::new(&mut self.joins);
        let runs = Mutex::new(&mut self.join_runs);
        on_threads(keys.len(), |run| {
            // SAFETY: `on_threads` gives each run to one thread; the runs are disjoint.
            let pairs = unsafe { joins.run(run.clone()) };
            let mut count = 0;
            for &key in &keys[run.clone()] {
                match joining(ready, w, (key >> 32) as u32, key as u32) {
                    Joining::Both => {
                        pairs[count] = key;
                        count += 1;
                    }
                    Joining::Blocks(i) => blocked[i as usize].store(true, Ordering::Relaxed),
                    Joining::Neither => {}
                }
            }
            runs.lock().expect("no thread panics holding it").push((run.start, count));
        });
        for &(start, count) in &self.join_runs {
            for &key in &self.joins[start..start + count] {
                union(&mut self.parent, (key >> 32) as u32, key as u32);
            }
        }
    }
}

/// What a contact or link between particles `a` and `b` ([`NONE`]: a plane or an
/// anchor) does to the islands that can sleep, given which particles are `ready` and
/// their inverse masses `w`.
enum Joining {
    /// Both are ready: one island.
    Both,
    /// This ready particle touches a movable one that is not: its island stays awake.
    Blocks(u32),
    /// Neither is ready, or one is joined only to something that does not move.
    Neither,
}

#[inline]
fn joining(ready: &[bool], w: &[f32], a: u32, b: u32) -> Joining {
    // A ready particle is movable, so a pair of which neither is ready (most contacts
    // of a forming pile) is passed over on the `ready` list alone, without reading
    // the particles' masses.
    let is_ready = |i: u32| i != NONE && ready[i as usize];
    let movable = |i: u32| i != NONE && w[i as usize] > 0.0;
    match (is_ready(a), is_ready(b)) {
        (true, true) => Joining::Both,
        (true, false) if movable(b) => Joining::Blocks(a),
        (false, true) if movable(a) => Joining::Blocks(b),
        _ => Joining::Neither,
    }
}

/// Wakes every island whose label is in `labels` (emptied).
pub(super) fn wake(particles: &mut Particles, labels: &mut Vec<u32>) {
    if labels.is_empty() {
        return;
    }
    labels.sort_unstable();
    labels.dedup();
    for sleep in &mut particles.sleep {
        if sleep.island != AWAKE && labels.binary_search(&sleep.island).is_ok() {
            *sleep = Sleep::default();
        }
    }
    labels.clear();
}

/// Union-find root with path halving.
fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let grand = parent[parent[i as usize] as usize];
        parent[i as usize] = grand;
        i = grand;
    }
    i
}

/// Joins two sets; the smaller root becomes the root, so labels depend on the
/// particles alone.
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (low, high) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[high as usize] = low;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::particles::ParticleDesc;

    /// Which particles fall asleep, and with what labels, is what joining every contact
    /// into islands gives (the way the step once found them, written again here): an
    /// island sleeps when every movable particle in it is ready, labelled by its lowest
    /// index. On random contact graphs of ready, moving and immovable particles, on two
    /// threads (which share out the timing and the contacts only under Miri, where runs
    /// are short: the next test shares out large ones).
    #[test]
    fn the_islands_that_sleep_are_those_of_all_the_contacts() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
        let cases = if cfg!(miri) { 12 } else { 300 };
        let settings = SolverSettings::default();
        let dt = 1.0 / 60.0;
        let mut state = 7u64;
        let mut next = |below: u64| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 33) % below
        };
        let mut sleepers = 0;
        for case in 0..cases {
            let n = 2 + next(40) as usize;
            let mut particles = Particles::new();
            // Kinds: 0 ready (at rest long enough), 1 moving, 2 immovable.
            let kinds: Vec<u64> = (0..n).map(|_| [0, 0, 0, 0, 1, 2][next(6) as usize]).collect();
            for &kind in &kinds {
                let desc = ParticleDesc {
                    velocity: if kind == 1 { Vec3::X } else { Vec3::ZERO },
                    immovable: kind == 2,
                    radius: 0.5,
                    ..ParticleDesc::default()
                };
                particles.add(desc).expect("a valid particle");
            }
            for (sleep, &kind) in particles.sleep.iter_mut().zip(&kinds) {
                sleep.timer = if kind == 0 { settings.sleep_time } else { 0.0 };
            }
            let mut step = SoftStep { delta: vec![Vec3::ZERO; n], ..SoftStep::default() };
            let contacts = next(2 * n as u64) as usize;
            for _ in 0..contacts {
                let a = next(n as u64) as u32;
                let b = if next(5) == 0 { NONE } else { next(n as u64) as u32 };
                if a != b {
                    step.fresh_keys.push(u64::from(a) << 32 | u64::from(b));
                }
            }
            // The reference: every contact between movable particles joined.
            let movable = |i: u32| i != NONE && kinds[i as usize] != 2;
            let mut parent: Vec<u32> = (0..n as u32).collect();
            for &key in &step.fresh_keys {
                let (a, b) = ((key >> 32) as u32, key as u32);
                if movable(a) && movable(b) {
                    union(&mut parent, a, b);
                }
            }
            let mut all_ready = vec![true; n];
            for (i, &kind) in kinds.iter().enumerate() {
                if movable(i as u32) {
                    let root = find(&mut parent, i as u32) as usize;
                    all_ready[root] &= kind == 0;
                }
            }
            let expected: Vec<u32> = (0..n)
                .map(|i| {
                    let root = find(&mut parent, i as u32);
                    if movable(i as u32) && all_ready[root as usize] { root } else { AWAKE }
                })
                .collect();
            pool.install(|| step.fall_asleep(&mut particles, &settings, dt));
            let islands: Vec<u32> = particles.sleep.iter().map(|s| s.island).collect();
            assert_eq!(islands, expected, "case {case}: kinds {kinds:?}, keys {:?}", step.fresh_keys);
            sleepers += islands.iter().filter(|&&island| island != AWAKE).count();
        }
        assert!(sleepers > cases, "some islands fall asleep: {sleepers}");
    }

    /// On two threads (each timing its own run of particles) the timers, the islands
    /// that fall asleep and those a force wakes are, to the bit, those of one thread: a
    /// world of particles that are slow, moving, spinning, pushed or asleep under a new
    /// force, in a chain of contacts.
    #[test]
    #[cfg_attr(miri, ignore = "10,000 particles: too slow to interpret (`parts.rs` tests its threads)")]
    fn timing_the_slow_on_two_threads_is_timing_them_on_one() {
        let settings = SolverSettings::default();
        let dt = 1.0 / 60.0;
        let n = 10_000;
        let mut particles = Particles::new();
        for i in 0..n {
            let f = i as f32;
            let moving = i % 97 == 0;
            let desc = ParticleDesc {
                velocity: if moving {
                    Vec3::new(0.3 * f.sin(), 0.0, 0.0)
                } else {
                    Vec3::splat(1e-4 * (f * 0.1).cos())
                },
                immovable: i % 31 == 2,
                radius: 0.5,
                ..ParticleDesc::default()
            };
            particles.add(desc).expect("a valid particle");
            particles.sleep[i].timer = if i % 50 == 0 { 0.0 } else { settings.sleep_time };
            if i % 11 == 0 {
                particles.angular_velocity[i] = Vec3::Y * (f * 0.01);
            }
        }
        // An island asleep with a force on one of its particles, and one asleep without.
        for i in 100..110 {
            particles.sleep[i] = Sleep { timer: 0.0, island: 100, rest: Vec3::ZERO };
            particles.velocity[i] = Vec3::ZERO;
        }
        for i in 5000..5004 {
            particles.sleep[i] = Sleep { timer: 0.0, island: 5000, rest: Vec3::ZERO };
            particles.velocity[i] = Vec3::ZERO;
        }
        particles.force[103] = Vec3::Y;
        particles.force[17] = Vec3::X;
        let keys: Vec<u64> = (0..n as u64 - 1).filter(|i| i % 13 != 0).map(|i| i << 32 | (i + 1)).collect();
        let run = |threads: usize| {
            let mut p = particles.clone();
            let mut delta = vec![Vec3::ZERO; n];
            delta[40] = Vec3::X * 0.1;
            let mut step = SoftStep { delta, fresh_keys: keys.clone(), ..SoftStep::default() };
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            pool.install(|| step.fall_asleep(&mut p, &settings, dt));
            p.sleep.iter().map(|s| (s.timer.to_bits(), s.island)).collect::<Vec<_>>()
        };
        let (one, two) = (run(1), run(2));
        assert_eq!(one, two);
        assert!(one[100..110].iter().all(|&(_, island)| island == AWAKE), "the force woke its island");
        let asleep = one.iter().filter(|&&(_, island)| island != AWAKE).count();
        assert!(asleep > 100 && asleep < n - 1000, "some islands fall asleep, not all: {asleep}");
        assert!(one.iter().any(|&(t, _)| t == 0) && one.iter().any(|&(t, _)| f32::from_bits(t) > 0.0));
    }
}

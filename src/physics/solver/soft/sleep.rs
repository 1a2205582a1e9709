//! Islands and sleep: particles joined by contacts and links that have all been slow
//! for a while stop being simulated until something disturbs them.

use glam::Vec3;

use super::{NONE, SoftStep};
use crate::physics::particles::{AWAKE, Particles, Sleep};
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
        let mut ready = false;
        self.to_wake.clear();
        let bodies = particles.velocity.iter().zip(&particles.force).zip(&particles.inverse_mass);
        let turning = particles.angular_velocity.iter().zip(&particles.radius);
        let states = particles.sleep.iter_mut().zip(bodies).zip(&self.delta).zip(turning);
        for (((sleep, ((v, f), &w)), moved), (spin, &r)) in states {
            if sleep.island != AWAKE {
                // A force started acting on it (a new spring, a float reaching water).
                if *f != Vec3::ZERO {
                    self.to_wake.push(sleep.island);
                }
                continue;
            }
            // Slow by its velocity and by how far it moved: the relax pass leaves a
            // particle still being pushed out of an overlap with almost no velocity.
            // Particles that forces keep holding never sleep: the force may change.
            // A sphere that spins in place is not at rest: its surface moves at |ω| r.
            let speed = v.length().max(moved.length() / dt).max(spin.length() * r);
            let slow = w > 0.0 && speed < settings.sleep_speed && *f == Vec3::ZERO;
            sleep.timer = if slow { sleep.timer + dt } else { 0.0 };
            ready |= sleep.timer >= settings.sleep_time;
        }
        wake(particles, &mut self.to_wake);
        if !ready {
            return;
        }
        // An island (particles joined by contacts, speculative ones too, and links;
        // immovable particles and planes join nothing) falls asleep when every particle
        // in it is ready: slow for `sleep_time`. So only the ready particles are joined
        // into islands, and a ready island joined to a movable particle that is not
        // ready is blocked: the islands left are whole islands of ready particles, the
        // ones that fall asleep. While a pile forms a few of its spheres are ready and
        // almost all contacts join none, where joining every contact into islands took
        // 0.27 ms of an 8,000-sphere step. Every contact joins, speculative ones too: a
        // pair close enough to have a contact is close enough that the next step's
        // contact would wake one from the other, so two islands split by a near miss
        // would wake each other in turn.
        let n = particles.len();
        let (w, sleep_time) = (&particles.inverse_mass, settings.sleep_time);
        let movable = |i: u32| i != NONE && w[i as usize] > 0.0;
        // Noted before any falls asleep (which resets its timer).
        self.ready.clear();
        self.ready.extend(particles.sleep.iter().zip(w).map(|(s, &w)| w > 0.0 && s.timer >= sleep_time));
        self.parent.clear();
        self.parent.extend(0..n as u32);
        self.blocked.clear();
        self.blocked.resize(n, false);
        let (parent, blocked, ready) = (&mut self.parent, &mut self.blocked, &self.ready);
        let mut join = |a: u32, b: u32| {
            if movable(a) && movable(b) {
                match (ready[a as usize], ready[b as usize]) {
                    (true, true) => union(parent, a, b),
                    (true, false) => blocked[a as usize] = true,
                    (false, true) => blocked[b as usize] = true,
                    (false, false) => {}
                }
            }
        };
        // The contacts' particles, read from their keys (8 bytes, not the contact's 60).
        for &key in &self.fresh_keys {
            join((key >> 32) as u32, key as u32);
        }
        for link in &self.links {
            join(link.a, link.b);
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
    /// index. On random contact graphs of ready, moving and immovable particles.
    #[test]
    #[cfg_attr(miri, ignore = "many random worlds: too slow to interpret, and no unsafe code")]
    fn the_islands_that_sleep_are_those_of_all_the_contacts() {
        let settings = SolverSettings::default();
        let dt = 1.0 / 60.0;
        let mut state = 7u64;
        let mut next = |below: u64| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 33) % below
        };
        let mut sleepers = 0;
        for case in 0..300 {
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
            step.fall_asleep(&mut particles, &settings, dt);
            let islands: Vec<u32> = particles.sleep.iter().map(|s| s.island).collect();
            assert_eq!(islands, expected, "case {case}: kinds {kinds:?}, keys {:?}", step.fresh_keys);
            sleepers += islands.iter().filter(|&&island| island != AWAKE).count();
        }
        assert!(sleepers > 300, "some islands fall asleep: {sleepers}");
    }
}

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
        let n = particles.len();
        self.parent.clear();
        self.parent.extend(0..n as u32);
        let movable = |i: u32| i != NONE && particles.inverse_mass[i as usize] > 0.0;
        // Every contact joins, speculative ones too: a pair close enough to have a
        // contact is close enough that the next step's contact would wake one from the
        // other, so two islands split by a near miss would wake each other in turn.
        for c in &self.contacts {
            if movable(c.a) && movable(c.b) {
                union(&mut self.parent, c.a, c.b);
            }
        }
        for link in &self.links {
            if movable(link.a) && movable(link.b) {
                union(&mut self.parent, link.a, link.b);
            }
        }
        self.island_timer.clear();
        self.island_timer.resize(n, f32::INFINITY);
        for i in 0..n {
            let root = find(&mut self.parent, i as u32) as usize;
            let sleep = particles.sleep[i];
            // Immovable particles are never in an island; they never keep one awake.
            if particles.inverse_mass[i] > 0.0 {
                self.island_timer[root] = self.island_timer[root].min(sleep.timer);
            }
        }
        for i in 0..n {
            let root = find(&mut self.parent, i as u32);
            if particles.inverse_mass[i] > 0.0 && self.island_timer[root as usize] >= settings.sleep_time {
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

//! The solve of a substep: warm start, then every contact (colour by colour) and every
//! rod and cable on its exact geometry: all links together as a network (`link_network/`),
//! or each as a soft constraint.

use super::contact::{Bodies, contact_terms, solve_batches, warm_start_batches};
use super::passes::for_each_batch;
use super::shared::SharedVelocities;
use super::{Changes, Context, NONE, SoftLink, SoftStep, note};
use crate::physics::links::direction_or_zero;
use crate::physics::particles::Particles;
use glam::Vec3;

impl SoftStep {
    pub(super) fn warm_start(&mut self, particles: &mut Particles) {
        let bodies = Bodies {
            velocities: SharedVelocities::new(&mut particles.velocity),
            spins: SharedVelocities::new(&mut particles.angular_velocity),
            delta: &self.delta,
        };
        let materials = &self.materials;
        for_each_batch(&mut self.batches, &self.batch_starts, &self.shares, |run, _| {
            warm_start_batches(run, materials, bodies)
        });
        if self.network.exact() {
            return; // the network solves its links whole each substep: no warm start
        }
        let w = &particles.inverse_mass;
        let velocities = &mut particles.velocity;
        let mut changes = self.noting.then_some(&mut self.changes[..]);
        for link in &self.links {
            // Warm start along the link's start-of-step direction is close enough; the
            // solve corrects it on the exact geometry.
            let (u, _, _) = link.geometry(&particles.position, |i| velocities[i]);
            let p = u * link.impulse * if link.rigid { 1.0 } else { -1.0 };
            let change = p * w[link.a as usize];
            velocities[link.a as usize] += change;
            note(&mut changes, link.a, change);
            if link.b != NONE {
                let change = p * w[link.b as usize];
                velocities[link.b as usize] -= change;
                note(&mut changes, link.b, -change);
            }
        }
    }

    pub(super) fn solve(&mut self, particles: &mut Particles, contacts: Context, joints: Context) {
        let bodies = Bodies {
            velocities: SharedVelocities::new(&mut particles.velocity),
            spins: SharedVelocities::new(&mut particles.angular_velocity),
            delta: &self.delta,
        };
        let materials = &self.materials;
        for_each_batch(&mut self.batches, &self.batch_starts, &self.shares, |run, one_colour| {
            solve_batches(run, materials, one_colour, bodies, contacts);
        });
        let mut changes = self.noting.then_some(&mut self.changes[..]);
        if self.network.exact() {
            // The shake with position feedback, the projection in the relax pass.
            if joints.use_bias {
                self.network.shake(&mut self.links, particles, joints.h, changes);
            } else {
                self.network.project(&mut self.links, particles, joints.h, changes);
            }
            return;
        }
        let w = &particles.inverse_mass;
        for link in &mut self.links {
            link.solve(&particles.position, &mut particles.velocity, w, joints, changes.as_deref_mut());
        }
    }
}

impl SoftLink {
    /// Direction from the far end to `a` (unit), length, and the rate the length grows.
    pub(super) fn geometry(&self, positions: &[Vec3], velocity: impl Fn(usize) -> Vec3) -> (Vec3, f32, f32) {
        let (pb, vb) = if self.b == NONE {
            (self.anchor, Vec3::ZERO)
        } else {
            (positions[self.b as usize], velocity(self.b as usize))
        };
        let (u, length) = direction_or_zero(positions[self.a as usize] - pb);
        // Coincident ends: any fixed axis will do to push them apart.
        let u = if u == Vec3::ZERO { Vec3::Y } else { u };
        (u, length, (velocity(self.a as usize) - vb).dot(u))
    }

    fn solve(
        &mut self,
        positions: &[Vec3],
        velocities: &mut [Vec3],
        w: &[f32],
        context: Context,
        mut changes: Changes<'_>,
    ) {
        let (u, length, vrel) = self.geometry(positions, |i| velocities[i]);
        let applied = if self.rigid {
            // Bilateral: drive C = length - rest to zero; a negative impulse pulls.
            let error = length - self.length;
            let (bias, mass_scale, impulse_scale) = if context.use_bias {
                (context.soft.bias_rate * error, context.soft.mass_scale, context.soft.impulse_scale)
            } else {
                (0.0, 1.0, 0.0)
            };
            let impulse = -self.mass * mass_scale * (vrel + bias) - impulse_scale * self.impulse;
            self.impulse += impulse;
            impulse
        } else {
            // A cable is a contact whose normal is -u and whose gap is the slack.
            let slack = self.length - length;
            if !context.use_bias && slack > 0.0 && self.impulse == 0.0 {
                return; // slack and not pulling: as for a contact, see `solve_contact`
            }
            let (bias, mass_scale, impulse_scale) = contact_terms(slack, context);
            let impulse = -self.mass * mass_scale * (-vrel + bias) - impulse_scale * self.impulse;
            let total = (self.impulse + impulse).max(0.0);
            let applied = total - self.impulse;
            self.impulse = total;
            -applied
        };
        let change = u * (applied * w[self.a as usize]);
        velocities[self.a as usize] += change;
        note(&mut changes, self.a, change);
        if self.b != NONE {
            let change = u * (applied * w[self.b as usize]);
            velocities[self.b as usize] -= change;
            note(&mut changes, self.b, -change);
        }
    }
}

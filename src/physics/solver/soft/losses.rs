//! The contacts' share of the energy budget: how much of what the constraints change in a
//! substep the contacts' impulses took (an inelastic stop, friction, rolling resistance),
//! and so is dissipated, rather than the solver's own correction.
//!
//! # Why
//!
//! The step measures what the contacts and links change of the mechanical energy, exactly
//! (`step.rs`, `kick_and_solve_work`). Booked whole as dissipated, that total went negative
//! on a frictionless, undamped pendulum: a rod moved back to its length and stopped from
//! stretching swings the energy by a few millijoules either way, which is the solver's
//! error, not a loss. So the budget splits it: the losses are dissipated; the rest, of
//! either sign, is the constraint term.
//!
//! # What
//!
//! The work of impulses `P` on velocities that go from `v` to `v'` is exactly
//! `Σ P · (v + v') / 2`, summed over what they act on; for a contact it is its normal
//! and friction impulse times its relative velocity at the contact point, and rolling
//! resistance's angular impulse times the relative spin. Summed over the particles
//! instead, it is each particle's share of all its contacts' impulses, `m Δv_c`, times
//! its mean velocity over the substep, plus the change of its spin's energy (only
//! contacts turn a sphere). `Δv_c` is the change of velocity over the substep that
//! neither the forces' kick nor a link nor the impact stage made (those note theirs,
//! see [`Changes`](super::Changes)). So one pass over the particles, beside the kinetic
//! energy the step sums anyway, measures it.
//!
//! The mean is taken from the velocity the substep began with, before the kick (for
//! integrators other than semi-implicit Euler, the moving velocity less a whole kick,
//! see [`Integration::kick_free_velocities`](crate::physics::integrator::Integration)),
//! with the impact stage's bounces added (the stage books those itself). A resting
//! contact then starts and ends at rest and does no work, where measured from the kicked
//! velocity it would take the kick's `½ m g² h²` every substep. Measured so, the
//! contacts' work is what their impulses took: an inelastic stop's `½ m v²`, friction's
//! `μ N |v_slip| h`. It leaves out what the contacts do through positions (pushing an
//! overlap apart, which changes potential energy), which is the solver's correction; and
//! rods and cables, whose impulses are the links' (a cable jerked taut has its loss
//! booked where it happens, `impact.rs`).
//!
//! Summed over a step, the work taken out is dissipated, and the step's constraint term
//! is the rest of the constraints' work. A total that comes out positive (the contacts
//! put energy in, which only their correction can do) is no loss: nothing is dissipated
//! then.
//!
//! A contact against a particle that rods hold sees only that particle's mass (the
//! solve is one constraint at a time): it stops the pair as if the particle were free,
//! and the rods then take the rest of the blow out of it. That part is the links' work,
//! so it shows as the constraint term: the solver's way of meeting the blow, not the
//! physics'. (The platform scene's 3 kg ball on rails of 0.05 kg spheres: 23 J so in its
//! first 5 s, beside 66 J dissipated.)

use super::SoftStep;
use crate::physics::particles::{Particles, in_lanes, tree_sum};

impl SoftStep {
    /// After the relax pass: the particles' kinetic energy (J, as
    /// [`Particles::kinetic_energy`]) and the work of the contacts' impulses this substep
    /// (J; negative: taken out), see the module's notes. `semi_implicit`: the kick was
    /// semi-implicit Euler's own (the velocities it made are in `kicked`); `rolling`:
    /// spheres roll (their spins at the start are in `substep_spin`). Summed up a fixed
    /// tree, the same on any number of threads.
    pub(super) fn relaxed(&self, p: &Particles, semi_implicit: bool, rolling: bool) -> (f64, f64) {
        let entering = if semi_implicit { &self.kicked } else { &self.moving };
        let start = if self.own_reference { &self.reference } else { &self.substep_velocity };
        let changes = self.noting.then_some(&self.changes[..]);
        let masses = &self.masses;
        let [moving, turning, work] = tree_sum(0..p.len(), &|range: std::ops::Range<usize>| {
            let first = range.start;
            let (v, masses) = (&p.velocity[range.clone()], &masses[range.clone()]);
            let (entering, start) = (&entering[range.clone()], &start[range.clone()]);
            let [moving, moving_work] = in_lanes(range.len(), |j| {
                let [mass, _] = masses[j];
                if mass == 0.0 {
                    return [0.0; 2]; // immovable
                }
                let v = v[j];
                // What the contacts changed of the velocity: all but the kick and the
                // changes noted.
                let by_contacts = match changes {
                    Some(changes) => v - entering[j] - changes[first + j],
                    None => v - entering[j],
                };
                [f64::from(v.length_squared()) * mass, f64::from(by_contacts.dot(start[j] + v)) * mass]
            });
            let spin = &p.angular_velocity[range.clone()];
            let spin_start = if rolling { &self.substep_spin[range] } else { &[][..] };
            let [turning, turning_work] = in_lanes(spin.len(), |j| {
                let [_, inertia] = masses[j];
                if inertia == 0.0 {
                    return [0.0; 2];
                }
                let spin = f64::from(spin[j].length_squared());
                let work =
                    if rolling { (spin - f64::from(spin_start[j].length_squared())) * inertia } else { 0.0 };
                [spin * inertia, work]
            });
            [moving, turning, moving_work + turning_work]
        });
        (0.5 * (moving + turning), 0.5 * work)
    }
}

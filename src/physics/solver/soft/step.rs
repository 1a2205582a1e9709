//! The step's order: collide, pick up last step's impulses and colour (side by side:
//! they read the contacts' keys and write different things), batch, then the substeps
//! (kick, impacts, warm start, solve, drift, relax), store, sleep. Each stage is
//! finished before the next begins.

use std::time::Duration;

use web_time::Instant;

use glam::Vec3;

use super::sleep::wake;
use super::{Context, NONE, PARALLEL_PARTICLES, SoftStep, ms};
use rayon::prelude::*;

/// Particles from which the per-substep copies of velocities run on several threads.
const PARALLEL_COPY: usize = 4096;

/// Contacts from which the deepest overlap is found on several threads.
const PARALLEL_OVERLAP: usize = 8192;

/// `to = from`, in parallel chunks for large arrays.
fn copy(to: &mut Vec<Vec3>, from: &[Vec3], parallel: bool) {
    if parallel {
        to.resize(from.len(), Vec3::ZERO);
        to.par_chunks_mut(2048).zip(from.par_chunks(2048)).for_each(|(to, from)| to.copy_from_slice(from));
    } else {
        to.clear();
        to.extend_from_slice(from);
    }
}
use crate::physics::collision::{BroadPhase, ContactGenerator, Scratch};
use crate::physics::forces::ForceRegistry;
use crate::physics::ids::ContactGeneratorId;
use crate::physics::integrator::Integrator;
use crate::physics::particles::{Particles, in_lanes, tree_sum};
use crate::physics::solver::report::{Profile, SoftReport};
use crate::physics::solver::settings::{CONTACT_HERTZ_LIMIT, Softness, SolverSettings};

impl SoftStep {
    /// Advances the particles by `dt`: the whole soft step. `link_tension` receives the
    /// tension of every link by generator index (N).
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        settings: &SolverSettings,
        particles: &mut Particles,
        forces: &mut ForceRegistry,
        generators: &[(ContactGeneratorId, ContactGenerator)],
        broad_phase: &mut BroadPhase,
        scratch: &mut Scratch,
        dt: f32,
        link_tension: &mut [f32],
        profile: &mut Profile,
    ) -> SoftReport {
        let substeps = settings.substeps.max(1);
        let h = dt / substeps as f32;
        let started = Instant::now();
        if settings.sleep {
            self.wake_disturbed(particles);
        }
        // Contacts with sleeping particles wake their islands; their own contacts are
        // then found by colliding again (rare: only when something wakes).
        loop {
            self.collide(settings, particles, generators, broad_phase, scratch, dt, profile);
            if self.to_wake.is_empty() {
                break;
            }
            wake(particles, &mut self.to_wake);
        }
        let collided = Instant::now();
        self.pick_up_and_color(particles, generators.len());
        let colored = Instant::now();
        self.batch(particles);
        self.share_out();
        self.network.prepare(&self.links, particles, settings);
        let batched = Instant::now();

        let contact_hertz = settings.contact_hertz.min(CONTACT_HERTZ_LIMIT / h);
        let joint_hertz = settings.joint_hertz.min(0.25 / h);
        let bias =
            |soft| Context { h, inv_h: 1.0 / h, max_push: settings.max_push_speed, soft, use_bias: true };
        let contact_context = bias(Softness::new(contact_hertz, settings.contact_damping_ratio, h));
        let joint_context = bias(Softness::new(joint_hertz, settings.joint_damping_ratio, h));
        let relax = Context { soft: Softness::RIGID, use_bias: false, ..contact_context };

        self.delta.clear();
        self.delta.resize(particles.len(), Vec3::ZERO);
        particles.prepare_damping(h);
        let parallel = particles.len() >= PARALLEL_PARTICLES;
        let copying = particles.len() >= PARALLEL_COPY;
        debug_assert_eq!(
            self.bouncy_contacts,
            self.contacts.iter().any(|c| self.surfaces[c.source as usize].restitution > 0.0),
            "collide notes whether a contact has restitution"
        );
        let bouncy = self.bouncy_contacts || self.links.iter().any(|l| !l.rigid && l.restitution > 0.0);
        let integrator = settings.integrator;
        let damped = particles.any_damping();
        // The energy the contacts and links add (negative: take out), for the budget.
        // Nothing to measure without constraints.
        let constrained = !self.contacts.is_empty() || !self.links.is_empty();
        // Semi-implicit Euler's own fast path, unless a closed-form generator needs the
        // integrator's separate moving and end velocities.
        let semi_implicit = integrator == Integrator::SemiImplicitEuler && !forces.has_closed_form();
        let mut constraint_work = 0.0;
        // Of that work, what the physics loses (bounces, cables jerked taut: >= 0) and
        // the work of the contacts' impulses, summed over the substeps (see `losses.rs`).
        let (mut lost, mut contact_work) = (0.0, 0.0);
        let touching = !self.batches.is_empty();
        // The changes of velocity the contacts do not make are noted while anything else
        // can make them (bounces, links).
        self.noting = touching && (bouncy || !self.links.is_empty());
        let jerky = self.links.iter().any(|l| !l.rigid && l.restitution == 0.0);
        // Spheres that roll: the contacts change their spin as well (nothing else does).
        let rolling = constrained && particles.any_rolling();
        // The time of the passes over the contacts and links, summed over the substeps.
        let mut passes = Duration::ZERO;
        if constrained {
            particles.masses_into(&mut self.masses, parallel);
        }
        for _ in 0..substeps {
            if self.noting {
                self.changes.clear();
                self.changes.resize(particles.len(), Vec3::ZERO);
            }
            if semi_implicit {
                particles.clear_forces();
                forces.apply(particles, h);
                if constrained {
                    // The velocities and spins at the start of the substep, and the
                    // velocities kicked, copied in the kick's own sweep (the forces
                    // change neither). Restitution needs contacts: `bouncy` implies
                    // `constrained`.
                    let (start, spins) =
                        (&mut self.substep_velocity, rolling.then_some(&mut self.substep_spin));
                    particles.integrate_velocities_keeping(h, copying, start, spins, &mut self.kicked);
                } else {
                    particles.integrate_velocities(h, parallel);
                }
                if damped {
                    particles.count_damping_loss();
                }
            } else {
                if bouncy || constrained {
                    copy(&mut self.substep_velocity, &particles.velocity, copying);
                }
                if rolling {
                    copy(&mut self.substep_spin, &particles.angular_velocity, copying);
                }
                self.integration.predict(integrator, particles, forces, h);
                if touching {
                    copy(&mut self.moving, &particles.velocity, copying);
                    self.integration.kick_free_velocities(particles, &mut self.reference);
                }
            }
            let before = if constrained && !semi_implicit { particles.kinetic_energy() } else { 0.0 };
            self.bounced.clear();
            if bouncy {
                lost += self.impacts(particles, h, settings.restitution_threshold);
            }
            if jerky {
                lost += self.jerked_cables(particles, h, settings.restitution_threshold);
            }
            if touching {
                self.prepare_reference(semi_implicit);
            }
            let pass = Instant::now();
            self.warm_start(particles);
            self.solve(particles, contact_context, joint_context);
            passes += pass.elapsed();
            // The kinetic energy before the relax pass: velocities do not change as
            // positions move, so it is measured now, with the solve's work.
            let mut before_relax = 0.0;
            if constrained {
                constraint_work += if semi_implicit {
                    let (work, kinetic) = self.kick_and_solve_work(particles, rolling);
                    before_relax = kinetic;
                    work
                } else {
                    before_relax = particles.kinetic_energy();
                    before_relax - before
                };
            }
            particles.integrate_positions(h, &mut self.delta, parallel);
            let pass = Instant::now();
            self.solve(particles, relax, relax);
            passes += pass.elapsed();
            if touching {
                let (kinetic, work) = self.relaxed(particles, semi_implicit, rolling);
                constraint_work += kinetic - before_relax;
                contact_work += work;
            } else if constrained {
                constraint_work += particles.kinetic_energy() - before_relax;
            }
            if !semi_implicit {
                self.integration.finish(particles);
            }
        }
        // The losses are dissipated; the rest of the constraints' work is their error.
        let dissipated = lost + (-contact_work).max(0.0);
        particles.dissipated += dissipated;
        particles.constraint -= constraint_work + dissipated;
        let substepped = Instant::now();
        let max_penetration = self.unbatch();
        debug_assert_eq!(
            max_penetration.to_bits(),
            self.deepest_overlap().to_bits(),
            "the batches' deepest overlap is the contacts'"
        );
        let unbatched = Instant::now();
        self.store(h, link_tension);
        if settings.sleep {
            self.fall_asleep(particles, settings, dt);
        }
        let solved = Instant::now();
        // The parts tile the solve: each span runs from the end of the one before.
        profile.color_ms = ms(colored - collided);
        profile.batch_ms = ms(batched - colored) + ms(unbatched - substepped);
        profile.contact_passes_ms = ms(passes);
        profile.particle_sweeps_ms = ms((substepped - batched).saturating_sub(passes));
        profile.store_ms = ms(solved - unbatched);
        profile.solve_ms = profile.color_ms
            + profile.batch_ms
            + profile.contact_passes_ms
            + profile.particle_sweeps_ms
            + profile.store_ms;
        profile.total_ms = ms(solved - started);
        let asleep = if settings.sleep { particles.asleep_count() } else { 0 };
        let pair_budget_hit = scratch.pair_budget_hit;
        SoftReport { contacts: self.contacts.len(), max_penetration, asleep, pair_budget_hit }
    }

    /// The velocities the contacts' work is measured from this substep, after the relax
    /// pass (see `losses.rs`): those it began with (semi-implicit Euler's start velocities, the
    /// other integrators' kick-free velocities, see
    /// [`Integration::kick_free_velocities`](crate::physics::integrator::Integration)),
    /// with the impact stage's bounces added, since the stage books those itself.
    /// The bounces are noted among the changes the contacts did not make.
    fn prepare_reference(&mut self, semi_implicit: bool) {
        if !self.bounced.is_empty() {
            if semi_implicit {
                self.reference.clone_from(&self.substep_velocity);
            }
            for &(i, change) in &self.bounced {
                self.reference[i as usize] += change;
                self.changes[i as usize] += change;
            }
        }
        self.own_reference = !semi_implicit || !self.bounced.is_empty();
    }

    /// Work done by the contacts and links in a substep's impact stage and solve (J),
    /// and the particles' kinetic energy after it (J).
    ///
    /// For each particle a contact or link changed: the change of its kinetic energy
    /// from the start of the substep to after the solve, less the forces' work along
    /// the step it is about to take (`m a·v h`, with `a h` read off the kick, which is
    /// exactly minus the change of gravitational energy), plus what damping took
    /// (counted on its own). So a constrained particle's change of mechanical energy is
    /// the constraint's: a pendulum's rod does almost no work (0.007 J in 10 s), an
    /// inelastic bounce takes the kinetic energy it stops. Measuring across the solve
    /// alone would charge a rod with the part of gravity's kick along it, which the rod
    /// only takes out again. A particle nothing touched keeps its integrator's error
    /// (free fall's `g²h²/2` per substep) as error. With `rolling`, the contacts' work
    /// on the spheres' spin is added: the change of `½ I ω²` since the substep began
    /// (no force generator turns a sphere, so all of it is the contacts').
    ///
    /// Summed up a fixed tree ([`tree_sum`]), the same on any number of threads.
    fn kick_and_solve_work(&self, particles: &Particles, rolling: bool) -> (f64, f64) {
        let (start, kicked) = (&self.substep_velocity, &self.kicked);
        let (spin_start, p, masses) = (&self.substep_spin, particles, &self.masses);
        let network = &self.network;
        let linear = |range: std::ops::Range<usize>| {
            let first = range.start;
            let (v, kicked, v0) = (&p.velocity[range.clone()], &kicked[range.clone()], &start[range.clone()]);
            let (masses, damping) = (&masses[range.clone()], &p.damping_per_step[range.clone()]);
            let [work, kinetic] = in_lanes(range.len(), |j| {
                let [mass, _] = masses[j];
                if mass == 0.0 {
                    return [0.0; 2]; // immovable
                }
                let (v, d) = (v[j].as_dvec3(), damping[j]);
                let kinetic = v.length_squared() * mass;
                // A link of the exact solve holds its particles even when they need no
                // impulse this substep (a rod whose end moves across it).
                if d <= 0.0 || (v == kicked[j].as_dvec3() && !network.moves(first + j)) {
                    return [0.0, kinetic]; // fully damped, or no contact or link touched it
                }
                let (kicked, v0, d) = (kicked[j].as_dvec3(), v0[j].as_dvec3(), f64::from(d));
                // v0 kicked (and damped by d) gives `kicked`: the kick is kicked/d - v0.
                let (kick, damping_loss) = if d == 1.0 {
                    (kicked - v0, 0.0)
                } else {
                    let undamp = 1.0 / d;
                    (kicked * undamp - v0, 0.5 * kicked.length_squared() * (undamp * undamp - 1.0))
                };
                let work =
                    (0.5 * (v.length_squared() - v0.length_squared()) - kick.dot(v) + damping_loss) * mass;
                [work, kinetic]
            });
            (work, 0.5 * kinetic)
        };
        let turning = |range: std::ops::Range<usize>| {
            let (w, w0, masses) =
                (&p.angular_velocity[range.clone()], &spin_start[range.clone()], &masses[range]);
            let [work, kinetic] = in_lanes(masses.len(), |j| {
                let [_, inertia] = masses[j];
                if inertia == 0.0 {
                    return [0.0; 2];
                }
                let spin = f64::from(w[j].length_squared());
                let work = if w[j] != w0[j] {
                    0.5 * (spin - f64::from(w0[j].length_squared())) * inertia
                } else {
                    0.0
                };
                [work, 0.5 * spin * inertia]
            });
            (work, kinetic)
        };
        let [work, kinetic] = tree_sum(0..p.len(), &|range: std::ops::Range<usize>| {
            let (work, kinetic) = linear(range.clone());
            if rolling {
                let (turn_work, spin_energy) = turning(range);
                [work + turn_work, kinetic + spin_energy]
            } else {
                [work, kinetic]
            }
        });
        (work, kinetic)
    }

    /// Deepest overlap at the end of the step, from the contacts' start separations and
    /// how far their particles moved (m): what [`unbatch`](SoftStep::unbatch) finds on
    /// the batches as it empties them, found again on the contacts to check it.
    pub(crate) fn deepest_overlap(&self) -> f32 {
        let delta = &self.delta;
        let overlap = |c: &super::SoftContact| {
            let mut d = delta[c.a as usize];
            if c.b != NONE {
                d -= delta[c.b as usize];
            }
            -(c.separation + d.dot(c.normal))
        };
        // The largest of the same numbers, in any order (on several threads for many);
        // a zero is reported as +0, since `max` may give either of +0 and -0.
        let deepest = if self.contacts.len() >= PARALLEL_OVERLAP {
            self.contacts.par_iter().with_min_len(4096).map(overlap).reduce(|| 0.0, f32::max)
        } else {
            self.contacts.iter().map(overlap).fold(0.0, f32::max)
        };
        if deepest == 0.0 { 0.0 } else { deepest }
    }
}

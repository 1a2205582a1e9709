//! The paper's solver: Cyclone's pipeline, kept so the lab can show why the soft step
//! exists. Integrate, generate contacts, resolve them one at a time worst first
//! ([`resolver`]), then a few position passes on contacts regenerated from the
//! corrected positions.
//!
//! [`PaperStep`] is the pipeline's scratch, rebuilt every step; its settings (the
//! resolver's and the number of position passes) belong to the world's state.

pub mod resolver;

use web_time::Instant;

use glam::Vec3;

use crate::physics::collision::{BroadPhase, ContactGenerator, Scratch};
use crate::physics::contact::{Contact, NO_SOURCE};
use crate::physics::energy::mechanical_energy;
use crate::physics::forces::ForceRegistry;
use crate::physics::ids::ContactGeneratorId;
use crate::physics::integrator::{Integration, Integrator};
use crate::physics::particles::{Particles, kicked};
use crate::physics::solver::report::{Profile, ResolveReport};
use resolver::{ContactResolver, ResolverScratch};

/// Most extra position passes of the paper's resolver.
pub const MAX_POSITION_PASSES: usize = 64;

/// What one paper step works on, apart from the world's parts.
pub(crate) struct PaperWorld<'a> {
    /// The particles, moved by the step.
    pub particles: &'a mut Particles,
    /// The force generators.
    pub forces: &'a mut ForceRegistry,
    /// The contact generators, in order (their index is a contact's `source`).
    pub generators: &'a [(ContactGeneratorId, ContactGenerator)],
    /// The grid the sphere collisions query.
    pub broad_phase: &'a mut BroadPhase,
    /// The contact generators' buffers.
    pub scratch: &'a mut Scratch,
    /// Receives each link's tension by generator index (N).
    pub link_tension: &'a mut [f32],
    /// Receives the stages' wall time.
    pub profile: &'a mut Profile,
}

/// Scratch of the paper's pipeline: the integrator's buffers, the contacts and where
/// each particle started. Nothing here needs saving.
#[derive(Clone, Debug, Default)]
pub struct PaperStep {
    /// Buffers of the integrators other than semi-implicit Euler.
    integration: Integration,
    /// How far each particle moved in an integration (scratch).
    moved: Vec<Vec3>,
    /// How far each particle moved in the last step.
    motion: Vec<Vec3>,
    /// Positions at the start of a step.
    start: Vec<Vec3>,
    /// Velocities at the start of a step, before the kick.
    start_velocity: Vec<Vec3>,
    /// The contacts the resolver handled in the last step.
    contacts: Vec<Contact>,
    /// Contacts regenerated for the extra position passes.
    pass_contacts: Vec<Contact>,
    /// The resolver's buffers.
    resolver: ResolverScratch,
}

impl PaperStep {
    /// The contacts the resolver handled in the last step.
    pub(crate) fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// How far each particle moved in the last step (m), by dense index.
    pub(crate) fn motion(&self) -> &[Vec3] {
        &self.motion
    }

    /// Drops the last step's contacts (their indices no longer mean what they did).
    pub(crate) fn forget(&mut self) {
        self.contacts.clear();
    }

    /// The paper's step: clear forces, apply force generators, integrate, generate
    /// contacts, resolve them worst first, then up to `position_passes` passes on fresh
    /// contacts.
    pub(crate) fn step(
        &mut self,
        resolver: &ContactResolver,
        position_passes: usize,
        integrator: Integrator,
        world: PaperWorld<'_>,
        dt: f32,
    ) -> ResolveReport {
        let PaperWorld { particles, forces, generators, broad_phase, scratch, link_tension, profile } = world;
        let started = Instant::now();
        self.start.clone_from(&particles.position);
        // Before the generators: the stiff spring reads this step's damping factor.
        particles.prepare_damping(dt);
        // Closed-form generators need the integrator's separate moving and end velocities.
        let fast = integrator == Integrator::SemiImplicitEuler && !forces.has_closed_form();
        // The velocities before the kick: what the contacts' work is measured from.
        self.start_velocity.clone_from(&particles.velocity);
        if fast {
            particles.clear_forces();
            forces.apply(particles, dt);
            // Semi-implicit Euler, the soft solver's kick and drift in one step (no
            // particle sleeps under this solver).
            particles.integrate_velocities(dt, false);
            self.moved.clear();
            self.moved.resize(particles.len(), Vec3::ZERO);
            particles.integrate_positions(dt, &mut self.moved, false);
        } else {
            // No constraints inside the paper's integration: move, then take the end
            // velocity; the resolver works on that afterwards.
            self.integration.predict(integrator, particles, forces, dt);
            let mut moved = std::mem::take(&mut self.moved);
            moved.clear();
            moved.resize(particles.len(), Vec3::ZERO);
            particles.integrate_positions(dt, &mut moved, false);
            self.moved = moved;
            self.integration.finish(particles);
        }

        if particles.any_damping() && fast {
            particles.count_damping_loss();
        }

        let collide = Instant::now();
        let before = mechanical_energy(particles, forces);
        scratch.pair_budget_hit = false;
        generate(generators, particles, broad_phase, scratch, &mut self.contacts);
        let solve = Instant::now();
        let mut report = resolver.resolve(&mut self.contacts, particles, dt, &mut self.resolver);
        for _ in 0..position_passes {
            generate(generators, particles, broad_phase, scratch, &mut self.pass_contacts);
            let (iterations, left) =
                resolver.resolve_positions(&mut self.pass_contacts, particles, &mut self.resolver);
            report.position_iterations += iterations;
            report.max_penetration = left;
            if iterations == 0 {
                break;
            }
        }
        report.contacts = self.contacts.len();
        report.pair_budget_hit = scratch.pair_budget_hit;
        self.motion.clear();
        let moves = particles.position.iter().zip(&self.start);
        self.motion.extend(moves.map(|(&now, &start)| now - start));
        // What the resolver's impulses and position corrections added (or took out): of
        // it, what the collisions' impulses took is lost (see `collision_work`), the rest
        // is the resolver's error.
        let mut constraint_work = mechanical_energy(particles, forces) - before;
        if fast {
            constraint_work += self.integration_error_of_constrained(particles, dt);
        }
        let dissipated = (-self.collision_work(particles)).max(0.0);
        particles.dissipated += dissipated;
        particles.constraint -= constraint_work + dissipated;

        for contact in &self.contacts {
            if contact.source != NO_SOURCE {
                let sign = if contact.pulls { 1.0 } else { -1.0 };
                link_tension[contact.source as usize] += sign * contact.impulse / dt;
            }
        }
        let done = Instant::now();
        let ms = |d: std::time::Duration| d.as_secs_f32() * 1000.0;
        *profile = Profile {
            broad_phase_ms: 0.0,
            narrow_phase_ms: ms(solve - collide),
            solve_ms: ms(done - solve),
            total_ms: ms(done - started),
            ..Profile::default()
        };
        report
    }

    /// Work of the collisions' impulses in this step (J; negative: taken out): for each
    /// contact with the ground, a wall or another sphere, its normal and friction impulse
    /// times its relative velocity halfway between the step's start (before the kick: a
    /// resting contact then does no work) and the end of the velocity phase. The
    /// velocity phase's impulses are all this work, exactly, and the position phase
    /// moves no velocity. Taken out, it is what an inelastic bounce (`½ m v² (1 - e²)`)
    /// and friction lose, and is booked as dissipated. Rods and cables are left out: the
    /// paper's resolver corrects them by stopping the velocity along them and moving
    /// positions, which takes energy out of a swinging chain, and that is its error.
    fn collision_work(&self, p: &Particles) -> f64 {
        let (before, after) = (&self.start_velocity, &p.velocity);
        let relative = |c: &Contact, v: &[Vec3]| v[c.a] - c.b.map_or(Vec3::ZERO, |b| v[b]);
        let collisions = self.contacts.iter().filter(|c| c.source == NO_SOURCE);
        collisions
            .map(|c| {
                let impulse = c.normal * c.impulse + c.tangent_impulse;
                0.5 * f64::from(impulse.dot(relative(c, before) + relative(c, after)))
            })
            .sum()
    }

    /// The integrator's energy error in this paper step (semi-implicit Euler) on the
    /// particles the resolver changed (J): for each, its change of kinetic energy over
    /// the integration plus what damping took, less the work of its weight and forces
    /// along the move the integration made. A particle resting on the ground falls
    /// `g dt²` in the integration, which loses `½ m g² dt²` (semi-implicit Euler's own
    /// error in free fall), and the resolver puts it back; measured across the resolver
    /// alone, the contact would book that as energy it added, and the budget as an
    /// error, both growing while nothing moves. The constrained motion is the step's
    /// motion, so this error is the contact's work and is booked with it, as the soft
    /// solver books each constrained particle's change of energy over its substep. A
    /// particle nothing touched keeps its error as error.
    fn integration_error_of_constrained(&self, p: &Particles, dt: f32) -> f64 {
        if self.contacts.is_empty() {
            return 0.0; // nothing touched (the passes only find what the first found)
        }
        let mut error = 0.0;
        for (i, (&x0, &v0)) in self.start.iter().zip(&self.start_velocity).enumerate() {
            let (w, d) = (p.inverse_mass[i], p.damping_per_step[i]);
            if w <= 0.0 || d <= 0.0 {
                continue;
            }
            // The integration's end, as the kick and drift computed it (same bits).
            let kicked = kicked(v0, p.acceleration[i] + p.force[i] * w, dt, d);
            let moved_to = x0 + kicked * dt;
            if p.velocity[i] == kicked && p.position[i] == moved_to {
                continue; // nothing touched it
            }
            let (m, d) = (1.0 / f64::from(w), f64::from(d));
            let (v0, kicked) = (v0.as_dvec3(), kicked.as_dvec3());
            let push = p.acceleration[i].as_dvec3() * m + p.force[i].as_dvec3();
            let kinetic = 0.5 * m * (kicked.length_squared() - v0.length_squared());
            let damping = 0.5 * m * kicked.length_squared() * (1.0 / (d * d) - 1.0);
            error += kinetic + damping - push.dot((moved_to - x0).as_dvec3());
        }
        error
    }
}

/// Fills `out` with the contacts of every generator, in order.
fn generate(
    generators: &[(ContactGeneratorId, ContactGenerator)],
    particles: &Particles,
    broad_phase: &mut BroadPhase,
    scratch: &mut Scratch,
    out: &mut Vec<Contact>,
) {
    out.clear();
    for (source, (_, generator)) in generators.iter().enumerate() {
        generator.generate(particles, source as u32, broad_phase, scratch, out);
    }
}

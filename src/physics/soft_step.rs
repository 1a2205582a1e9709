//! The soft step: a substepped solver with soft contacts, friction and restitution.
//!
//! The shape is Box2D v3's "soft step" (Erin Catto, "Solver2D", 2024) applied to
//! particles, with the substepping argument of Macklin et al. 2019 ("Small Steps in
//! Physics Simulation"): many small steps of one iteration beat one big step of many.
//!
//! Stages, each finished before the next begins:
//! 1. **Collide** once per step: the broad phase's pairs and the planes give contacts
//!    whose gap is below a speculative margin (a pair that may touch within the step
//!    gets its contact now). A sphere pair's contact is swept: it is made only if the
//!    pair's straight relative path comes near touching within the step, along the
//!    line of centres at the time of impact (see `swept_contact`), so spheres passing
//!    each other are never stopped by a ghost. Each contact stores its separation at
//!    the start of the step, and picks up last step's impulses (warm starting).
//! 2. **Colour** the contacts so that no two of one colour share a movable particle;
//!    a colour is then solved in parallel with the same result as in order.
//! 3. **Substeps**, `n` of them, each of `h = dt / n`: apply force generators (springs
//!    too) and integrate velocities; bounce the pairs that meet within the substep
//!    (the impact stage, one pair at a time, so a blow passes down a row of balls);
//!    warm start; solve every contact and link with soft position feedback; integrate
//!    positions; relax (solve again without feedback, so pushing overlaps apart adds
//!    no energy).
//! 4. **Store** impulses for the next step's warm start.
//!
//! A contact's separation during the substeps is its start separation plus how far its
//! two particles have moved along the normal since, so contacts are found once a step.
//! Rods and cables are few and are solved on their exact geometry every substep.

use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;

use super::broad_phase::BroadPhase;
use super::collisions::{ContactGenerator, Plane, Scratch, SphereCollisions};
use super::forces::ForceRegistry;
use super::integrator::{Integration, Integrator};
use super::links::{Constraint, LinkEnd, direction_or_zero};
use super::particles::{AWAKE, Particles, Sleep};
use super::solver::{Softness, SolverSettings};
use super::world::{ContactGeneratorId, Profile};

/// "No second particle" (a plane contact, or a link to an anchor).
pub const NONE: u32 = u32::MAX;

/// Colours solved in parallel; contacts that find no free colour go to one more,
/// solved in order.
const COLORS: usize = 24;
const OVERFLOW: usize = COLORS;

/// Most passes of the impact stage over its pairs in one substep; a row of `n` touching
/// balls with `k` arriving needs about `k + 1`.
const MAX_IMPACT_SWEEPS: usize = 32;

/// A colour with at least this many contacts is split across threads.
const PARALLEL_CONTACTS: usize = 2048;
/// Contacts per parallel task.
const TASK: usize = 512;
/// Particles from which the integration loops run on several threads.
pub(crate) const PARALLEL_PARTICLES: usize = 16_384;

/// A contact between a particle and another particle or a plane, as the soft solver
/// keeps it over one step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftContact {
    /// Dense index of the particle pushed along `normal`.
    pub a: u32,
    /// Dense index of the other particle, or [`NONE`] for a plane.
    pub b: u32,
    /// Unit normal, pointing the way `a` is pushed.
    pub normal: Vec3,
    /// Gap at the start of the step (m); negative is overlap.
    pub separation: f32,
    /// Coefficient of restitution.
    pub restitution: f32,
    /// Coulomb friction coefficient.
    pub friction: f32,
    /// Effective mass along any direction, `1 / (1/m_a + 1/m_b)` (kg).
    pub mass: f32,
    /// Normal impulse of the current substep (N·s), >= 0.
    pub normal_impulse: f32,
    /// Friction impulse of the current substep (N·s), in the tangent plane.
    pub tangent_impulse: Vec3,
    /// Index in generation order, for storing the warm start.
    origin: u32,
}

/// A rod or cable as the soft solver keeps it over one step.
#[derive(Clone, Copy, Debug, PartialEq)]
struct SoftLink {
    a: u32,
    b: u32,
    anchor: Vec3,
    length: f32,
    rigid: bool,
    restitution: f32,
    mass: f32,
    impulse: f32,
    generator: u32,
}

/// A contact or cable that may bounce within the current substep, as the impact stage
/// sees it. Positions do not move during the stage, so the normal and gap are fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Impact {
    a: u32,
    b: u32,
    /// Unit normal, pointing the way `a` is pushed.
    normal: Vec3,
    /// Gap at the start of the substep (m); negative is overlap.
    gap: f32,
    restitution: f32,
    mass: f32,
    /// How fast forces alone made the closing speed grow this substep (m/s²).
    closing_acceleration: f32,
}

/// What the soft solver keeps of a contact for the next step.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
struct Warm {
    key: u64,
    normal_impulse: f32,
    tangent_impulse: Vec3,
}

/// The part of the soft solver that carries from one step to the next (see
/// [`SoftStep::memory`]); everything else in [`SoftStep`] is scratch.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SoftMemory {
    warm: Vec<Warm>,
    warm_groups: Vec<(ContactGeneratorId, std::ops::Range<usize>)>,
    warm_links: Vec<(u32, f32)>,
    last_tension: Vec<f32>,
}

impl SoftMemory {
    /// The contact generator (by index) each kept link impulse belongs to, for a
    /// loaded state to check against its generators.
    pub(crate) fn link_generators(&self) -> impl Iterator<Item = u32> + '_ {
        self.warm_links.iter().map(|&(generator, _)| generator)
    }
}

/// Scratch and warm-start memory of the soft solver. Only [`SoftMemory`] needs saving:
/// without it a new one starts cold, which changes the next step's bits.
#[derive(Clone, Debug, Default)]
pub struct SoftStep {
    /// Contacts in generation order (per generator, sorted by particle pair).
    fresh: Vec<SoftContact>,
    /// Keys of `fresh`, for warm starting.
    fresh_keys: Vec<u64>,
    /// Generator id and range of `fresh` each generator made.
    fresh_groups: Vec<(ContactGeneratorId, std::ops::Range<usize>)>,
    /// Contacts in colour order: what the substeps solve.
    contacts: Vec<SoftContact>,
    /// Start of each colour in `contacts`, and the end.
    color_starts: [usize; COLORS + 2],
    colors: Vec<u8>,
    masks: Vec<u32>,
    links: Vec<SoftLink>,
    /// Last step's contacts, in generation order, with their groups.
    warm: Vec<Warm>,
    warm_groups: Vec<(ContactGeneratorId, std::ops::Range<usize>)>,
    /// Last step's link impulses by generator index (cleared by [`SoftStep::forget`]
    /// whenever indices shift).
    warm_links: Vec<(u32, f32)>,
    /// `warm_links` looked up by generator index (scratch).
    warm_link_by_generator: Vec<Option<f32>>,
    /// Links skipped this step because their particles sleep (by generator index).
    sleeping_links: Vec<u32>,
    /// Each link's tension as last reported (N), by generator index.
    last_tension: Vec<f32>,
    /// Movement of each particle since the start of the step (m).
    delta: Vec<Vec3>,
    /// Speculative margin of each particle (m).
    margin: Vec<f32>,
    /// Contacts and cables with restitution this step, refreshed every substep.
    impacts: Vec<Impact>,
    /// Buffers of the integrators other than semi-implicit Euler.
    integration: Integration,
    /// Velocities after the substep's kick, before the solve (energy budget).
    kicked: Vec<Vec3>,
    /// Velocities at the start of the substep, kept while anything can bounce.
    substep_velocity: Vec<Vec3>,
    /// Per particle: asleep at the start of this collide pass.
    asleep: Vec<bool>,
    /// Labels of sleeping islands to wake.
    to_wake: Vec<u32>,
    /// Union-find parents and each island's shortest rest time, for sleeping.
    parent: Vec<u32>,
    island_timer: Vec<f32>,
}

/// What a soft step did, for reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftReport {
    /// Contacts solved (speculative ones included).
    pub contacts: usize,
    /// Largest overlap left at the end of the step (m), from the contacts.
    pub max_penetration: f32,
    /// Particles asleep after the step.
    pub asleep: usize,
    /// The broad phase hit its pair budget (see [`super::broad_phase::pair_budget`]).
    pub pair_budget_hit: bool,
}

/// Velocities shared by the tasks solving one colour.
#[derive(Clone, Copy)]
struct SharedVelocities {
    ptr: *mut Vec3,
    len: usize,
}

// SAFETY: the pointer is only used while the solver holds the `&mut` to the velocity
// array it came from; see `get` and `set` for why tasks never touch the same element.
unsafe impl Send for SharedVelocities {}
unsafe impl Sync for SharedVelocities {}

impl SharedVelocities {
    fn new(velocities: &mut [Vec3]) -> Self {
        Self { ptr: velocities.as_mut_ptr(), len: velocities.len() }
    }

    #[inline]
    fn get(&self, i: usize) -> Vec3 {
        assert!(i < self.len);
        // SAFETY: in bounds (checked above). Within one colour, an element is written
        // only by the one contact of that colour that involves its (movable) particle,
        // so no other task writes it while this one reads; immovable particles' velocities
        // are never written during the solve.
        unsafe { *self.ptr.add(i) }
    }

    #[inline]
    fn set(&self, i: usize, v: Vec3) {
        assert!(i < self.len);
        // SAFETY: in bounds; only called for movable particles, and the colouring gives
        // each movable particle at most one contact per colour (see `get`).
        unsafe { *self.ptr.add(i) = v }
    }
}

/// Per-substep constants handed to every contact (Box2D's step context).
#[derive(Clone, Copy)]
struct Context {
    inv_h: f32,
    max_push: f32,
    soft: Softness,
    use_bias: bool,
}

impl SoftStep {
    /// The contacts of the last step, as solved (speculative ones too).
    pub(crate) fn contacts(&self) -> &[SoftContact] {
        &self.contacts
    }

    /// How far each particle moved in the last step (m), by dense index.
    pub(crate) fn motion(&self) -> &[Vec3] {
        &self.delta
    }

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
        let impulses =
            memory.warm.iter().all(|w| w.normal_impulse.is_finite() && w.tangent_impulse.is_finite());
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
    pub(crate) fn memory_hash_into(&self, hasher: &mut super::state::StateHasher) {
        for warm in &self.warm {
            hasher.u64(warm.key);
            hasher.f32(warm.normal_impulse);
            hasher.vec3(warm.tangent_impulse);
        }
        for &(generator, impulse) in &self.warm_links {
            hasher.u64(u64::from(generator));
            hasher.f32(impulse);
        }
    }

    /// Forgets warm-start memory (after particles or generators were removed, when
    /// dense indices no longer mean what they did).
    pub fn forget(&mut self) {
        self.warm.clear();
        self.warm_groups.clear();
        self.warm_links.clear();
    }

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
        self.warm_start_from_last_step(generators.len());
        self.color(particles);

        let contact_hertz = settings.contact_hertz.min(0.25 / h);
        let joint_hertz = settings.joint_hertz.min(0.25 / h);
        let bias = |soft| Context { inv_h: 1.0 / h, max_push: settings.max_push_speed, soft, use_bias: true };
        let contact_context = bias(Softness::new(contact_hertz, settings.contact_damping_ratio, h));
        let joint_context = bias(Softness::new(joint_hertz, settings.joint_damping_ratio, h));
        let relax = Context { soft: Softness::RIGID, use_bias: false, ..contact_context };

        self.delta.clear();
        self.delta.resize(particles.len(), Vec3::ZERO);
        particles.prepare_damping(h);
        let parallel = particles.len() >= PARALLEL_PARTICLES;
        let bouncy = self.contacts.iter().any(|c| c.restitution > 0.0)
            || self.links.iter().any(|l| !l.rigid && l.restitution > 0.0);
        let integrator = settings.integrator;
        let damped = particles.any_damping();
        // The energy the contacts and links add (negative: take out), for the budget.
        // Nothing to measure without constraints.
        let constrained = !self.contacts.is_empty() || !self.links.is_empty();
        // Semi-implicit Euler's own fast path, unless a closed-form generator needs the
        // integrator's separate moving and end velocities.
        let semi_implicit = integrator == Integrator::SemiImplicitEuler && !forces.has_closed_form();
        let mut constraint_work = 0.0;
        for _ in 0..substeps {
            if bouncy || constrained {
                self.substep_velocity.clone_from(&particles.velocity);
            }
            if semi_implicit {
                particles.clear_forces();
                forces.apply(particles, h);
                particles.integrate_velocities(h, parallel);
                if damped {
                    particles.count_damping_loss();
                }
                if constrained {
                    self.kicked.clone_from(&particles.velocity);
                }
            } else {
                self.integration.predict(integrator, particles, forces, h);
            }
            let before = if constrained && !semi_implicit { particles.kinetic_energy() } else { 0.0 };
            if bouncy {
                self.impacts(particles, h, settings.restitution_threshold);
            }
            self.warm_start(particles);
            self.solve(particles, contact_context, joint_context);
            if constrained {
                constraint_work += if semi_implicit {
                    self.kick_and_solve_work(particles)
                } else {
                    particles.kinetic_energy() - before
                };
            }
            particles.integrate_positions(h, &mut self.delta, parallel);
            let before = if constrained { particles.kinetic_energy() } else { 0.0 };
            self.solve(particles, relax, relax);
            if constrained {
                constraint_work += particles.kinetic_energy() - before;
            }
            if !semi_implicit {
                self.integration.finish(particles);
            }
        }
        particles.dissipated -= constraint_work;
        self.store(h, link_tension);
        let max_penetration = self.deepest_overlap();
        if settings.sleep {
            self.fall_asleep(particles, settings, dt);
        }
        let solved = Instant::now();
        profile.solve_ms = ms(solved - collided);
        profile.total_ms = ms(solved - started);
        let asleep = if settings.sleep { particles.asleep_count() } else { 0 };
        let pair_budget_hit = scratch.pair_budget_hit;
        SoftReport { contacts: self.contacts.len(), max_penetration, asleep, pair_budget_hit }
    }

    /// Wakes the islands of sleeping particles that were moved or pushed from outside
    /// (dragged, teleported, given a velocity) since the last step.
    fn wake_disturbed(&mut self, particles: &mut Particles) {
        self.to_wake.clear();
        let bodies = particles.sleep.iter().zip(&particles.position).zip(&particles.velocity);
        for ((sleep, &p), &v) in bodies {
            if sleep.island != AWAKE && (v != Vec3::ZERO || p != sleep.rest) {
                self.to_wake.push(sleep.island);
            }
        }
        wake(particles, &mut self.to_wake);
    }

    /// Work done by the contacts and links in a substep's impact stage and solve (J).
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
    /// (free fall's `g²h²/2` per substep) as error.
    fn kick_and_solve_work(&self, particles: &Particles) -> f64 {
        let start = &self.substep_velocity;
        let bodies = particles.velocity.iter().zip(&self.kicked).zip(start);
        let masses = particles.inverse_mass.iter().zip(&particles.damping_per_step);
        let mut work = 0.0;
        for (((&v, &kicked), &v0), (&w, &d)) in bodies.zip(masses) {
            if w <= 0.0 || d <= 0.0 {
                continue;
            }
            let (v, kicked, v0) = (v.as_dvec3(), kicked.as_dvec3(), v0.as_dvec3());
            let d = f64::from(d);
            if v == kicked {
                continue; // no contact or link touched it
            }
            let kick = kicked / d - v0;
            let damping_loss = 0.5 * kicked.length_squared() * (1.0 / (d * d) - 1.0);
            work += (0.5 * (v.length_squared() - v0.length_squared()) - kick.dot(v) + damping_loss)
                / f64::from(w);
        }
        work
    }

    /// Stage 5: islands whose every particle has been slow for `sleep_time` fall
    /// asleep. An island is the particles joined by contacts (speculative ones too) and links
    /// (immovable particles and planes join nothing).
    fn fall_asleep(&mut self, particles: &mut Particles, settings: &SolverSettings, dt: f32) {
        let mut ready = false;
        self.to_wake.clear();
        let bodies = particles.velocity.iter().zip(&particles.force).zip(&particles.inverse_mass);
        for ((sleep, ((v, f), &w)), moved) in particles.sleep.iter_mut().zip(bodies).zip(&self.delta) {
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
            let speed = v.length().max(moved.length() / dt);
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
                particles.sleep[i] = Sleep { timer: 0.0, island: root, rest: particles.position[i] };
            }
        }
    }

    /// Stage 1: contacts from every generator, with speculative margins.
    #[allow(clippy::too_many_arguments)]
    fn collide(
        &mut self,
        settings: &SolverSettings,
        particles: &Particles,
        generators: &[(ContactGeneratorId, ContactGenerator)],
        broad_phase: &mut BroadPhase,
        scratch: &mut Scratch,
        dt: f32,
        profile: &mut Profile,
    ) {
        // How far each particle can move this step, plus the fixed margin.
        self.margin.clear();
        self.margin.extend(
            particles
                .velocity
                .iter()
                .zip(&particles.acceleration)
                .map(|(v, a)| settings.speculative_distance + (v.length() + a.length() * dt) * dt),
        );
        self.fresh.clear();
        self.fresh_keys.clear();
        self.fresh_groups.clear();
        self.links.clear();
        self.sleeping_links.clear();
        self.to_wake.clear();
        self.asleep.clear();
        self.asleep.extend(particles.sleep.iter().map(|s| s.island != AWAKE));
        let any_asleep = self.asleep.contains(&true);
        // With every sphere asleep there is nobody to query the grid: skip building it.
        let any_awake_sphere =
            particles.radius.iter().zip(&self.asleep).any(|(&r, &asleep)| r > 0.0 && !asleep);
        profile.broad_phase_ms = 0.0;
        scratch.pair_budget_hit = false;
        let started = Instant::now();
        for (source, (id, generator)) in generators.iter().enumerate() {
            let start = self.fresh.len();
            match generator {
                ContactGenerator::Plane(plane) => self.collide_plane(plane, particles),
                ContactGenerator::Spheres(_) if !any_awake_sphere => {}
                ContactGenerator::Spheres(spheres) => {
                    let broad = Instant::now();
                    scratch.reach.clear();
                    scratch.reach.extend(
                        particles.radius.iter().zip(&self.margin).map(
                            |(&r, &m)| {
                                if r > 0.0 { r + m } else { 0.0 }
                            },
                        ),
                    );
                    let asleep = any_asleep.then_some(self.asleep.as_slice());
                    broad_phase.find_pairs_awake(
                        &particles.position,
                        &scratch.reach,
                        asleep,
                        &mut scratch.pairs,
                    );
                    scratch.pair_budget_hit |= broad_phase.budget_hit();
                    profile.broad_phase_ms += ms(broad.elapsed());
                    let slack = 2.0 * settings.speculative_distance;
                    self.collide_spheres(spheres, particles, &scratch.pairs, slack, dt);
                }
                ContactGenerator::Link(link) => self.add_link(link, particles, source as u32),
            }
            if self.fresh.len() > start {
                self.fresh_groups.push((*id, start..self.fresh.len()));
            }
        }
        profile.narrow_phase_ms = ms(started.elapsed()) - profile.broad_phase_ms;
    }

    fn collide_plane(&mut self, plane: &Plane, particles: &Particles) {
        let positions = particles.position.iter().zip(&particles.radius);
        let bodies = particles.inverse_mass.iter().zip(&self.margin);
        for (i, (((&p, &r), (&w, &margin)), &asleep)) in positions.zip(bodies).zip(&self.asleep).enumerate() {
            let separation = plane.distance(p) - r;
            if w > 0.0 && !asleep && separation < margin {
                self.fresh_keys.push(key(i as u32, NONE));
                self.fresh.push(SoftContact {
                    a: i as u32,
                    b: NONE,
                    normal: plane.normal,
                    separation,
                    restitution: plane.restitution,
                    friction: plane.friction,
                    mass: 1.0 / w,
                    ..SoftContact::default()
                });
            }
        }
    }

    /// Contacts of the broad phase's pairs that can come within `slack` of touching in
    /// the step `dt` (see [`swept_contact`]: a pair that only passes by gets none).
    fn collide_spheres(
        &mut self,
        spheres: &SphereCollisions,
        particles: &Particles,
        pairs: &[(u32, u32)],
        slack: f32,
        dt: f32,
    ) {
        let (p, w, r) = (&particles.position, &particles.inverse_mass, &particles.radius);
        let (v, acceleration) = (&particles.velocity, &particles.acceleration);
        for &(a, b) in pairs {
            let (i, j) = (a as usize, b as usize);
            let total = w[i] + w[j];
            if total <= 0.0 {
                continue;
            }
            if self.asleep[j] {
                // An awake particle reached a sleeping one: wake its island.
                if w[j] > 0.0 {
                    self.to_wake.push(particles.sleep[j].island);
                }
                continue;
            }
            // Gravity moves both alike; any difference in constant acceleration may
            // close the gap by up to |a_i - a_j| dt² / 2 (counted twice, as the margins do).
            let slack = slack + (acceleration[i].length() + acceleration[j].length()) * dt * dt;
            let swept = swept_contact(p[i] - p[j], v[i] - v[j], r[i] + r[j], dt, slack);
            let Some((normal, separation)) = swept else { continue };
            self.fresh_keys.push(key(a, b));
            self.fresh.push(SoftContact {
                a,
                b,
                normal,
                separation,
                restitution: spheres.restitution,
                friction: spheres.friction,
                mass: 1.0 / total,
                ..SoftContact::default()
            });
        }
    }

    fn add_link(&mut self, link: &Constraint, particles: &Particles, generator: u32) {
        let Some(a) = particles.index(link.a) else { return };
        let (b, anchor) = match link.b {
            LinkEnd::Particle(id) => match particles.index(id) {
                Some(b) if b != a => (b as u32, Vec3::ZERO),
                _ => return, // gone, or a link to itself, which constrains nothing
            },
            LinkEnd::Anchor(point) => (NONE, point),
        };
        let w = particles.inverse_mass[a] + if b == NONE { 0.0 } else { particles.inverse_mass[b as usize] };
        if w <= 0.0 {
            return;
        }
        let asleep_b = b != NONE && self.asleep[b as usize];
        match (self.asleep[a], asleep_b) {
            (true, true) => {
                self.sleeping_links.push(generator);
                return;
            }
            (true, false) if b != NONE && particles.inverse_mass[b as usize] > 0.0 => {
                self.to_wake.push(particles.sleep[a].island);
            }
            (false, true) if particles.inverse_mass[a] > 0.0 => {
                self.to_wake.push(particles.sleep[b as usize].island)
            }
            (true, false) => {
                // Asleep on an anchor or an immovable particle.
                self.sleeping_links.push(generator);
                return;
            }
            _ => {}
        }
        self.links.push(SoftLink {
            a: a as u32,
            b,
            anchor,
            length: link.length,
            rigid: link.rigid,
            restitution: link.restitution,
            mass: 1.0 / w,
            impulse: 0.0,
            generator,
        });
    }

    /// Copies last step's impulses into this step's matching contacts and links;
    /// `generators` is how many contact generators the world has.
    fn warm_start_from_last_step(&mut self, generators: usize) {
        for (id, range) in &self.fresh_groups {
            let Some((_, old)) = self.warm_groups.iter().find(|(old_id, _)| old_id == id) else { continue };
            let (old_keys, new_keys) = (&self.warm[old.clone()], &self.fresh_keys[range.clone()]);
            let contacts = &mut self.fresh[range.clone()];
            // Both runs are sorted by key: walk them together.
            let mut j = 0;
            for (contact, &k) in contacts.iter_mut().zip(new_keys) {
                while j < old_keys.len() && old_keys[j].key < k {
                    j += 1;
                }
                if j < old_keys.len() && old_keys[j].key == k {
                    let warm = old_keys[j];
                    contact.normal_impulse = warm.normal_impulse;
                    // The normal turned a little since: keep the tangential part.
                    let t = warm.tangent_impulse;
                    contact.tangent_impulse = t - contact.normal * t.dot(contact.normal);
                }
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

    /// Stage 2: greedy colouring in generation order, then a counting sort into
    /// `contacts`. Depends on the contacts alone, never on the thread count.
    fn color(&mut self, particles: &Particles) {
        let w = &particles.inverse_mass;
        self.masks.clear();
        self.masks.resize(particles.len(), 0);
        self.colors.clear();
        let mut counts = [0usize; COLORS + 1];
        for contact in &self.fresh {
            let (a, b) = (contact.a as usize, contact.b as usize);
            let movable_a = w[a] > 0.0;
            let movable_b = contact.b != NONE && w[b] > 0.0;
            let mut used = if movable_a { self.masks[a] } else { 0 };
            if movable_b {
                used |= self.masks[b];
            }
            let color = (!used).trailing_zeros() as usize;
            let color = if color < COLORS {
                let bit = 1u32 << color;
                if movable_a {
                    self.masks[a] |= bit;
                }
                if movable_b {
                    self.masks[b] |= bit;
                }
                color
            } else {
                OVERFLOW
            };
            self.colors.push(color as u8);
            counts[color] += 1;
        }
        self.color_starts[0] = 0;
        for (c, &count) in counts.iter().enumerate() {
            self.color_starts[c + 1] = self.color_starts[c] + count;
        }
        let mut cursor = self.color_starts;
        self.contacts.clear();
        self.contacts.resize(self.fresh.len(), SoftContact::default());
        for (origin, (contact, &color)) in self.fresh.iter().zip(&self.colors).enumerate() {
            let slot = &mut cursor[color as usize];
            self.contacts[*slot] = SoftContact { origin: origin as u32, ..*contact };
            *slot += 1;
        }
    }

    /// Runs `f` on every contact, colour by colour; large colours across threads.
    fn for_each_contact(&mut self, f: impl Fn(&mut SoftContact) + Sync) {
        for_each_contact(&mut self.contacts, &self.color_starts, f);
    }

    fn warm_start(&mut self, particles: &mut Particles) {
        let velocities = SharedVelocities::new(&mut particles.velocity);
        let w = &particles.inverse_mass;
        self.for_each_contact(|c| {
            let impulse = c.normal * c.normal_impulse + c.tangent_impulse;
            apply(velocities, w, c.a, c.b, impulse);
        });
        let velocities = &mut particles.velocity;
        for link in &self.links {
            // Warm start along the link's start-of-step direction is close enough; the
            // solve corrects it on the exact geometry.
            let (u, _, _) = link.geometry(&particles.position, |i| velocities[i]);
            let p = u * link.impulse * if link.rigid { 1.0 } else { -1.0 };
            velocities[link.a as usize] += p * w[link.a as usize];
            if link.b != NONE {
                velocities[link.b as usize] -= p * w[link.b as usize];
            }
        }
    }

    fn solve(&mut self, particles: &mut Particles, contacts: Context, joints: Context) {
        let velocities = SharedVelocities::new(&mut particles.velocity);
        let (w, delta) = (&particles.inverse_mass, &self.delta);
        for_each_contact(&mut self.contacts, &self.color_starts, |c| {
            solve_contact(c, velocities, w, delta, contacts)
        });
        for link in &mut self.links {
            link.solve(&particles.position, &mut particles.velocity, w, joints);
        }
    }

    /// The impact stage of a substep, between integrating velocities and the solve:
    /// every contact and cable with restitution that closes faster than `threshold` and
    /// would meet within the substep bounces, one pair at a time, in generation order,
    /// sweeping until none is left closing. One pair at a time is what passes a blow
    /// down a row of touching balls (Newton's cradle) instead of sharing it out.
    ///
    /// The bounce is exact for the integrator. Semi-implicit Euler in steps of `h`
    /// under a constant closing acceleration `a` keeps `a·gap + c²/2 - a·h·c/2` for the
    /// closing speed `c` it moved with: its "shadow" energy, conserved exactly where
    /// `a·gap + c²/2` drifts by `a²h²/2` every substep, and at the top of a flight
    /// (`c` = 0) simply `a` times the height. The bounce leaves with the speed whose
    /// shadow energy is `e²` times the one it came with, so a ball dropped on the
    /// ground returns to `e²` of its height at any step (tests/truth.rs).
    fn impacts(&mut self, particles: &mut Particles, h: f32, threshold: f32) {
        let (v, v0, w) = (&particles.velocity, &self.substep_velocity, &particles.inverse_mass);
        let closing = |a: u32, b: u32, n: Vec3, v: &[Vec3]| {
            let vb = if b == NONE { Vec3::ZERO } else { v[b as usize] };
            -(v[a as usize] - vb).dot(n)
        };
        self.impacts.clear();
        // Generation order (by generator, then by pair), so the result is the same
        // however the contacts were coloured.
        for c in &self.fresh {
            if c.restitution == 0.0 {
                continue;
            }
            let moved = if c.b == NONE {
                self.delta[c.a as usize]
            } else {
                self.delta[c.a as usize] - self.delta[c.b as usize]
            };
            let acceleration = (closing(c.a, c.b, c.normal, v) - closing(c.a, c.b, c.normal, v0)) / h;
            self.impacts.push(Impact {
                a: c.a,
                b: c.b,
                normal: c.normal,
                gap: c.separation + moved.dot(c.normal),
                restitution: c.restitution,
                mass: c.mass,
                closing_acceleration: acceleration,
            });
        }
        for link in &self.links {
            if link.rigid || link.restitution == 0.0 {
                continue;
            }
            // A cable is a contact whose normal is -u and whose gap is the slack.
            let (u, length, _) = link.geometry(&particles.position, |i| v[i]);
            let acceleration = (closing(link.a, link.b, -u, v) - closing(link.a, link.b, -u, v0)) / h;
            self.impacts.push(Impact {
                a: link.a,
                b: link.b,
                normal: -u,
                gap: link.length - length,
                restitution: link.restitution,
                mass: link.mass,
                closing_acceleration: acceleration,
            });
        }
        if self.impacts.is_empty() {
            return;
        }
        let v = &mut particles.velocity;
        for _ in 0..MAX_IMPACT_SWEEPS {
            let mut bounced = false;
            for impact in &self.impacts {
                let c = closing(impact.a, impact.b, impact.normal, v);
                if c <= threshold || impact.gap >= c * h {
                    continue;
                }
                let leaving = impact.leaving_speed(c, h);
                let p = impact.normal * (impact.mass * (leaving + c));
                v[impact.a as usize] += p * w[impact.a as usize];
                if impact.b != NONE {
                    v[impact.b as usize] -= p * w[impact.b as usize];
                }
                bounced = true;
            }
            if !bounced {
                break;
            }
        }
    }

    /// Stage 4: keep impulses for the next step; report link tensions.
    fn store(&mut self, h: f32, link_tension: &mut [f32]) {
        self.warm.clear();
        self.warm.resize(self.fresh.len(), Warm::default());
        for contact in &self.contacts {
            let origin = contact.origin as usize;
            self.warm[origin] = Warm {
                key: self.fresh_keys[origin],
                normal_impulse: contact.normal_impulse,
                tangent_impulse: contact.tangent_impulse,
            };
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

    /// Deepest overlap at the end of the step, from the contacts' start separations and
    /// how far their particles moved (m).
    fn deepest_overlap(&self) -> f32 {
        let delta = &self.delta;
        self.contacts
            .iter()
            .map(|c| {
                let mut d = delta[c.a as usize];
                if c.b != NONE {
                    d -= delta[c.b as usize];
                }
                -(c.separation + d.dot(c.normal))
            })
            .fold(0.0, f32::max)
    }
}

impl Impact {
    /// Separating speed after the bounce of a pair closing at `c` (m/s); see
    /// [`SoftStep::impacts`]. The pair then moves off from `gap` this substep.
    fn leaving_speed(&self, c: f32, h: f32) -> f32 {
        let (a, e, gap) = (self.closing_acceleration, self.restitution, self.gap.max(0.0));
        // Shadow energy per unit effective mass on the way in, measured from contact.
        let arriving = a * gap + 0.5 * c * c - 0.5 * a * h * c;
        // On the way out the pair starts at `gap` and moves with the new speed `u` this
        // substep: its shadow energy is a·gap + u²/2 + a·h·u/2.
        let kinetic = (e * e * arriving - a * gap).max(0.0);
        let half = 0.5 * a * h;
        -half + (half * half + 2.0 * kinetic).sqrt()
    }
}

impl SoftLink {
    /// Direction from the far end to `a` (unit), length, and the rate the length grows.
    fn geometry(&self, positions: &[Vec3], velocity: impl Fn(usize) -> Vec3) -> (Vec3, f32, f32) {
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

    fn solve(&mut self, positions: &[Vec3], velocities: &mut [Vec3], w: &[f32], context: Context) {
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
        velocities[self.a as usize] += u * (applied * w[self.a as usize]);
        if self.b != NONE {
            velocities[self.b as usize] -= u * (applied * w[self.b as usize]);
        }
    }
}

/// Runs `f` on every contact, colour by colour; a large colour is split across threads
/// (its contacts share no movable particle, so the order within it does not matter).
fn for_each_contact(
    contacts: &mut [SoftContact],
    starts: &[usize; COLORS + 2],
    f: impl Fn(&mut SoftContact) + Sync,
) {
    for color in 0..=COLORS {
        let slice = &mut contacts[starts[color]..starts[color + 1]];
        if color != OVERFLOW && slice.len() >= PARALLEL_CONTACTS {
            slice.par_chunks_mut(TASK).for_each(|chunk| chunk.iter_mut().for_each(&f));
        } else {
            slice.iter_mut().for_each(&f);
        }
    }
}

/// Bias velocity, mass scale and impulse scale of a one-sided constraint with gap `s`:
/// a positive gap may close by `s` this substep (speculative), an overlap is pushed out
/// softly (no faster than `max_push`) when feedback is on.
#[inline]
fn contact_terms(s: f32, context: Context) -> (f32, f32, f32) {
    if s > 0.0 {
        (s * context.inv_h, 1.0, 0.0)
    } else if context.use_bias {
        let soft = context.soft;
        ((soft.bias_rate * s).max(-context.max_push), soft.mass_scale, soft.impulse_scale)
    } else {
        (0.0, 1.0, 0.0)
    }
}

/// The contact of two spheres `offset = p_a - p_b` apart, closing with relative velocity
/// `velocity = v_a - v_b`, whose radii sum to `reach`: its unit normal (pointing the way
/// `a` is pushed) and its gap along that normal at the start of the step, or `None` when
/// the swept spheres come no closer than `slack` to touching within `dt`.
///
/// The relative path `d(t) = offset + velocity·t` is a straight line over the step.
/// The solver keeps a contact's gap along a fixed normal, `d(t)·n - reach`, from going
/// negative, so the normal decides what the contact does:
/// - overlapping at the start: the line of centres now (the overlap is pushed out);
/// - meeting within the step: the line of centres at the time of impact, the smallest
///   `t` in `[0, dt]` with `|d(t)| = reach` (the quadratic of PHYSICS.md). Along it the
///   gap is positive before `t` and zero at `t`, so the pair is stopped where it
///   touches and pushed the way it really touches (a glancing hit goes sideways);
/// - only passing near: the line of centres at the closest approach `t*`. As `t*`
///   minimises `|d|` over `[0, dt]`, `d(t*)·velocity·(t - t*) >= 0` for every `t` in the
///   step, so `d(t)·n >= |d(t*)| > reach`: the contact cannot act on the motion it was
///   made for. It is there for pushes from other contacts within the step (a pile).
///
/// A normal from the start separation alone would stop two spheres passing at a clear
/// gap as soon as their start-of-step line of centres closed: a ghost collision.
#[inline]
fn swept_contact(offset: Vec3, velocity: Vec3, reach: f32, dt: f32, slack: f32) -> Option<(Vec3, f32)> {
    let unit_or_up = |d: Vec3| {
        // Coincident centres have no direction: separate them vertically.
        let (n, length) = direction_or_zero(d);
        (if n == Vec3::ZERO { Vec3::Y } else { n }, length)
    };
    let squared = offset.length_squared();
    if squared <= reach * reach {
        let (normal, distance) = unit_or_up(offset);
        return Some((normal, distance - reach));
    }
    let closing = offset.dot(velocity);
    let speed_squared = velocity.length_squared();
    let closest_time = if speed_squared > 0.0 { (-closing / speed_squared).clamp(0.0, dt) } else { 0.0 };
    let closest = offset + velocity * closest_time;
    let closest_distance = closest.length();
    if closest_distance - reach >= slack {
        return None;
    }
    let at = if closest_distance < reach {
        // |offset + velocity t|² = reach²: the earlier root (the pair closes, so the
        // discriminant is positive and `closing` negative).
        let c = squared - reach * reach;
        let root = (closing * closing - speed_squared * c).max(0.0).sqrt();
        offset + velocity * (c / (-closing + root))
    } else {
        closest
    };
    let (normal, _) = unit_or_up(at);
    Some((normal, offset.dot(normal) - reach))
}

/// Adds `impulse` to `a` and its opposite to `b`, each divided by its mass.
#[inline]
fn apply(velocities: SharedVelocities, w: &[f32], a: u32, b: u32, impulse: Vec3) {
    let (a, wa) = (a as usize, w[a as usize]);
    if wa > 0.0 {
        velocities.set(a, velocities.get(a) + impulse * wa);
    }
    if b != NONE {
        let (b, wb) = (b as usize, w[b as usize]);
        if wb > 0.0 {
            velocities.set(b, velocities.get(b) - impulse * wb);
        }
    }
}

/// One contact: the normal impulse with soft feedback, then Coulomb friction clamped to
/// `μ` times it (a disc, since a particle's tangent plane has two directions). Both
/// velocities are read once and written once.
#[inline]
fn solve_contact(
    c: &mut SoftContact,
    velocities: SharedVelocities,
    w: &[f32],
    delta: &[Vec3],
    context: Context,
) {
    let (a, b) = (c.a as usize, c.b as usize);
    let has_b = c.b != NONE;
    let wa = w[a];
    let wb = if has_b { w[b] } else { 0.0 };
    let mut va = velocities.get(a);
    let mut vb = if has_b { velocities.get(b) } else { Vec3::ZERO };
    let moved = if has_b { delta[a] - delta[b] } else { delta[a] };
    let s = c.separation + moved.dot(c.normal);
    if !context.use_bias && s > 0.0 && c.normal_impulse == 0.0 {
        // Relaxing a contact that has not touched: leave its closing speed alone. The
        // next substep's solve still stops it at the surface, and the impact stage
        // needs the speed it really arrives with to bounce it.
        return;
    }
    let (bias, mass_scale, impulse_scale) = contact_terms(s, context);
    let vn = (va - vb).dot(c.normal);
    let impulse = -c.mass * mass_scale * (vn + bias) - impulse_scale * c.normal_impulse;
    let total = (c.normal_impulse + impulse).max(0.0);
    let applied = total - c.normal_impulse;
    c.normal_impulse = total;
    let mut p = c.normal * applied;

    if c.friction > 0.0 {
        // Velocities after the normal impulse, in registers.
        let v = (va + p * wa) - (vb - p * wb);
        let tangential = v - c.normal * v.dot(c.normal);
        let old = c.tangent_impulse;
        let mut total = old - tangential * c.mass;
        let limit = c.friction * c.normal_impulse;
        let squared = total.length_squared();
        if squared > limit * limit {
            total *= limit / squared.sqrt();
        }
        c.tangent_impulse = total;
        p += total - old;
    }
    if wa > 0.0 {
        va += p * wa;
        velocities.set(a, va);
    }
    if has_b && wb > 0.0 {
        vb -= p * wb;
        velocities.set(b, vb);
    }
}

/// Wakes every island whose label is in `labels` (emptied).
fn wake(particles: &mut Particles, labels: &mut Vec<u32>) {
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

/// Sort key of a contact within its generator's run.
#[inline]
fn key(a: u32, b: u32) -> u64 {
    (u64::from(a) << 32) | u64::from(b)
}

fn ms(duration: std::time::Duration) -> f32 {
    duration.as_secs_f32() * 1000.0
}

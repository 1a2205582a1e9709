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
//! Rods and cables are solved on their exact geometry every substep: by default all
//! together, to convergence, as a network (`link_network/`: the impulses that bring every
//! link to its length at the end of the substep, then velocities that agree with the
//! links; conservative), or one at a time as soft constraints.
//!
//! One file per stage, as Box2D v3 keeps them: `step.rs` (the order above, and the
//! energy the constraints add), `collide.rs` (1), `color.rs` (2), `batch.rs` (the
//! coloured contacts four by four, lane by lane), `passes.rs` (a pass over the colours
//! on every thread) and `shared.rs` (the memory those threads share), in each substep
//! `impact.rs` (the bounces, and what they lose), `solve.rs` (warm start, contacts and
//! links) and `contact.rs` (one contact's impulse), `losses.rs` (what of the
//! constraints' work the contacts' impulses took, dissipated; the rest is the
//! constraint term), `link_network/` (the exact link solve: `mod.rs` the network,
//! `shake.rs` its two solves, `envelope.rs` its direct solver, `taut.rs` particles a
//! taut path of links holds still), `warm.rs` (4, and the memory a snapshot saves),
//! `sleep.rs` (islands falling asleep and waking), `awake.rs` (the pool's threads kept
//! ready through a step).
//! This file holds the data every stage shares.

mod awake;
pub(crate) use awake::keep_pool_awake;
mod batch;
mod collide;
mod color;
mod contact;
mod impact;
mod link_network;
mod losses;
mod passes;
mod shared;
mod sleep;
mod solve;
mod step;
mod warm;

use glam::Vec3;

use crate::physics::ids::ContactGeneratorId;
use crate::physics::integrator::Integration;
use crate::physics::solver::settings::Softness;

/// "No second particle" (a plane contact, or a link to an anchor).
pub const NONE: u32 = u32::MAX;

/// Colours solved in parallel; contacts that find no free colour go to one more,
/// solved in order.
const COLORS: usize = 24;
const OVERFLOW: usize = COLORS;

/// Particles from which the integration loops run on several threads.
pub(crate) const PARALLEL_PARTICLES: usize = 4096;

/// A contact between a particle and another particle or a plane, as the soft solver
/// keeps it over one step from the colour stage on: which particles, along what
/// normal, how far apart, and the impulses (the narrow phase makes a [`FreshContact`],
/// without them). What it is made of is its generator's [`Surface`]; its effective
/// masses, levers and rolling resistance follow from its particles
/// ([`collide::terms`]) and are worked out where the batches are made. Kept out of the
/// contact, they spared 28 of its 88 bytes, which every stage from the narrow phase to
/// the store copies or reads (28 bytes more cost a forming 100,000-sphere pile 7 to 10%
/// of its step).
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
    /// Index of the contact generator that made it (its surface: `SoftStep::surfaces`).
    pub source: u32,
    /// Normal impulse of the current substep (N·s), >= 0.
    pub normal_impulse: f32,
    /// Friction impulse of the current substep (N·s), in the tangent plane.
    pub tangent_impulse: Vec3,
    /// Rolling-resistance angular impulse of the current substep (N·m·s), applied to
    /// `a` (and its opposite to `b`); zero for a contact that does not roll.
    pub rolling_impulse: Vec3,
    /// Index in generation order, for storing the warm start.
    origin: u32,
}

/// A contact as the narrow phase makes it: a [`SoftContact`] without the impulses,
/// which the colour stage's sort adds from last step's (see `warm.rs`). 28 bytes
/// instead of 60: the narrow phase writes it, copies it from its threads' chunks onto
/// one list, and the pick-up and the sort read it, each over every contact a step. At
/// 100,000 spheres on 2 threads this took about 1 ms a step off the narrow phase and
/// 0.3–0.9 ms off the colour stage (three runs each, the same bits).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct FreshContact {
    /// Dense index of the particle pushed along `normal`.
    pub(super) a: u32,
    /// Dense index of the other particle, or [`NONE`] for a plane.
    pub(super) b: u32,
    /// Unit normal, pointing the way `a` is pushed.
    pub(super) normal: Vec3,
    /// Gap at the start of the step (m); negative is overlap.
    pub(super) separation: f32,
    /// Index of the contact generator that made it (its surface: `SoftStep::surfaces`).
    pub(super) source: u32,
}

/// What a contact generator's contacts are made of.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Surface {
    /// Coefficient of restitution.
    pub(crate) restitution: f32,
    /// Coulomb friction coefficient.
    pub(crate) friction: f32,
    /// Rolling resistance coefficient (times the rolling radius: the largest torque
    /// per newton of normal force).
    pub(crate) rolling_resistance: f32,
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
    #[serde(default)]
    rolling_impulse: Vec3,
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
    fresh: Vec<FreshContact>,
    /// Per fresh contact: where its impulses of last step are in `warm`, or [`NONE`]
    /// (see `warm_start_from_last_step`).
    picked: Vec<u32>,
    /// Keys of `fresh`, for warm starting.
    fresh_keys: Vec<u64>,
    /// Generator id and range of `fresh` each generator made.
    fresh_groups: Vec<(ContactGeneratorId, std::ops::Range<usize>)>,
    /// Contacts in colour order: what the substeps solve.
    contacts: Vec<SoftContact>,
    /// Start of each colour in `contacts`, and the end.
    color_starts: [usize; COLORS + 2],
    /// The contacts in batches of four of a colour (one for the overflow colour), as
    /// the substeps solve them; their impulses go back to `contacts` after the step.
    batches: Vec<batch::ContactBatch>,
    /// The batches' materials (see `batch::Material`): `BATCH_RUN` places per run of
    /// batches, of which the run fills the first few.
    materials: Vec<batch::Material>,
    /// First batch of each colour, and the end.
    batch_starts: [usize; COLORS + 2],
    /// Each colour's first contact of those that wait (see `color::bucket`), and its
    /// first batch made of waiting contacts only (a batch holding both counts as
    /// pushing): the end of the colour where none waits.
    waiting_contacts: [usize; COLORS + 1],
    waiting_batches: [usize; COLORS + 1],
    /// Each batch's first contact's place in `fresh` (see `passes::share`).
    batch_origins: Vec<u32>,
    /// Each thread's share of each colour, for the pool the step runs on (see
    /// `passes::for_each_batch`).
    shares: Vec<passes::Share>,
    /// Per fresh contact: it waits (see `color::bucket`).
    waits: Vec<bool>,
    /// Colour of each fresh contact.
    colors: Vec<u8>,
    /// The keys `colors` and `color_starts` were made for, and which particles were
    /// movable then: while both are unchanged, so is the colouring (`pick_up_and_color`).
    colored_keys: Vec<u64>,
    colored_movable: Vec<bool>,
    /// Where each fresh contact went in `contacts` (by generation order).
    slots: Vec<u32>,
    /// Per chunk of fresh contacts, its first slot in each of the counting sort's
    /// buckets (two per colour, see `color::bucket`).
    chunk_starts: Vec<[usize; 2 * (COLORS + 1)]>,
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
    /// Length of each particle's acceleration at the start of the step (m/s²).
    acceleration: Vec<f32>,
    /// Contacts and cables with restitution this step, refreshed every substep.
    impacts: Vec<Impact>,
    /// Buffers of the integrators other than semi-implicit Euler.
    integration: Integration,
    /// Velocities after the substep's kick, before the solve (energy budget).
    kicked: Vec<Vec3>,
    /// Each particle's mass and moment of inertia in `f64`, noted once a step for the
    /// substeps' energy sums (`Particles::masses_into`).
    masses: Vec<[f64; 2]>,
    /// Velocities at the start of the substep, kept while anything can bounce.
    substep_velocity: Vec<Vec3>,
    /// Angular velocities at the start of the substep, kept while spheres roll
    /// (energy budget).
    substep_spin: Vec<Vec3>,
    /// Velocities the contacts' work is measured from, when they are not
    /// `substep_velocity` (energy budget, see `losses.rs`): an integrator's kick-free
    /// velocities, or the start velocities with the impact stage's bounces added.
    reference: Vec<Vec3>,
    /// Each change of velocity the impact stage made this substep: (particle, change).
    bounced: Vec<(u32, Vec3)>,
    /// The contacts' work is measured from `reference` this substep, not from
    /// `substep_velocity`.
    own_reference: bool,
    /// Velocities as the constraints got them this substep, for integrators other than
    /// semi-implicit Euler (whose are `kicked`): the moving velocities (energy budget).
    moving: Vec<Vec3>,
    /// Each particle's change of velocity this substep that no contact made (bounces,
    /// links), while `noting` (energy budget, see `losses.rs`).
    changes: Vec<Vec3>,
    noting: bool,
    /// Whether a contact of this step has restitution: a generator with restitution
    /// made one (noted by `collide`, so that the step need not look through them all).
    bouncy_contacts: bool,
    /// Each contact generator's surface, by its index (this step's).
    surfaces: Vec<Surface>,
    /// Per chunk of sphere pairs: its contacts (see `SoftStep::collide_spheres`).
    pair_chunks: Vec<collide::PairChunk>,
    /// Per particle: asleep at the start of this collide pass.
    asleep: Vec<bool>,
    /// Labels of sleeping islands to wake.
    to_wake: Vec<u32>,
    /// Union-find parents, which particles are ready to sleep, and which particles'
    /// islands hold one that is not, for sleeping (see `sleep.rs`).
    parent: Vec<u32>,
    ready: Vec<bool>,
    blocked: Vec<bool>,
    /// For sleeping (`sleep.rs`): the keys of contacts joining two ready particles, each
    /// run's written where that run's keys begin, and each run's start and count.
    joins: Vec<u64>,
    join_runs: Vec<(usize, usize)>,
    /// The exact solve of rods and cables (`link_network/`), with its cached network.
    network: link_network::LinkNetwork,
}

/// Where a stage that changes velocities, but is not a contact's solve, notes each
/// particle's change of velocity (by dense index) for the energy budget: the links and
/// the impact stage (see `losses.rs`). `None`: nothing needs them.
type Changes<'a> = Option<&'a mut [Vec3]>;

/// Adds `change` to particle `i`'s noted change of velocity, if changes are noted.
#[inline]
fn note(changes: &mut Changes<'_>, i: u32, change: Vec3) {
    if let Some(changes) = changes {
        changes[i as usize] += change;
    }
}

/// Per-substep constants handed to every contact (Box2D's step context).
#[derive(Clone, Copy)]
struct Context {
    /// The substep (s).
    h: f32,
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

    /// Forgets warm-start memory (after particles or generators were removed, when
    /// dense indices no longer mean what they did).
    pub fn forget(&mut self) {
        self.warm.clear();
        self.warm_groups.clear();
        self.warm_links.clear();
    }
}

fn ms(duration: std::time::Duration) -> f32 {
    duration.as_secs_f32() * 1000.0
}

//! What a step reports: what the solver did ([`ResolveReport`], [`SoftReport`]) and how
//! long each stage took ([`Profile`]), for the panel, the command line and the
//! benchmarks.

/// What one call of [`ContactResolver::resolve`](super::paper::resolver::ContactResolver::resolve) did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ResolveReport {
    /// Contacts handled in the velocity phase.
    pub velocity_iterations: usize,
    /// Contacts handled in the interpenetration phase.
    pub position_iterations: usize,
    /// Largest penetration left after resolution (m); 0 if none.
    pub max_penetration: f32,
    /// Contacts handled (with the soft solver, speculative ones included).
    pub contacts: usize,
    /// Particles asleep after the step (soft solver).
    pub asleep: usize,
    /// True when spheres overlapped so much that the broad phase made only its budget
    /// of pairs ([`pair_budget`](crate::physics::collision::broad_phase::pair_budget): 32 per sphere) and left the rest
    /// out: the step went on with those contacts alone, and the UI or command line
    /// should say so.
    pub pair_budget_hit: bool,
}

impl ResolveReport {
    /// Total iterations used, both phases.
    #[must_use]
    pub fn iterations(&self) -> usize {
        self.velocity_iterations + self.position_iterations
    }
}

/// Wall time of the stages of the last step (ms), for the panel and the benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Profile {
    /// Finding candidate sphere pairs (the grid).
    pub broad_phase_ms: f32,
    /// Turning pairs, planes and links into contacts.
    pub narrow_phase_ms: f32,
    /// Solving contacts and links (with the paper's resolver: resolving them). With the
    /// soft solver it is the sum of the five parts below.
    pub solve_ms: f32,
    /// The whole step.
    pub total_ms: f32,
    /// Soft solver: picking up last step's impulses, colouring the contacts and sorting
    /// them by colour.
    pub color_ms: f32,
    /// Soft solver: laying the contacts out in batches, and taking their impulses and
    /// the deepest overlap back out after the substeps.
    pub batch_ms: f32,
    /// Soft solver: the passes over the contacts and links in every substep (warm start,
    /// solve, relax).
    pub contact_passes_ms: f32,
    /// Soft solver: the rest of the substeps, sweeps over the particles (the kick, the
    /// drift, the impact stage, the energy ledger's sums).
    pub particle_sweeps_ms: f32,
    /// Soft solver: keeping the impulses for the next step, and sleep.
    pub store_ms: f32,
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
    /// The broad phase hit its pair budget (see [`pair_budget`](crate::physics::collision::broad_phase::pair_budget)).
    pub pair_budget_hit: bool,
}

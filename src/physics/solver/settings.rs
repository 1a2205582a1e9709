//! Which solver a world uses, and its settings: one struct, documented once, validated.

use crate::physics::error::PhysicsError;
use crate::physics::integrator::Integrator;

/// The constraint solvers a world can use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum SolverKind {
    /// Substepped soft-constraint solver (the default): contacts with friction and
    /// restitution, rods, cables and springs all inside substeps. See
    /// [`soft`](super::soft).
    #[default]
    Soft,
    /// The paper's resolver: one contact at a time, worst first (with Coulomb friction
    /// clamped by each contact's normal impulse), then interpenetration.
    /// Kept to show why the soft solver exists; see [`paper`](super::paper).
    Paper,
}

impl SolverKind {
    /// Every solver, in menu order.
    pub const ALL: [Self; 2] = [Self::Soft, Self::Paper];

    /// The name on the command line and in the panel.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Soft => "soft",
            Self::Paper => "paper",
        }
    }

    /// One line saying what it is.
    #[must_use]
    pub fn summary(self) -> &'static str {
        match self {
            Self::Soft => "substepped soft contacts with friction, warm started (Box2D v3's soft step)",
            Self::Paper => {
                "the paper's resolver: worst contact first (with Coulomb friction), then interpenetration"
            }
        }
    }

    /// Looks a solver up by name.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|kind| kind.name().eq_ignore_ascii_case(name.trim())).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|k| k.name()).collect();
            format!("unknown solver '{}'; valid solvers: {}", crate::messages::quote(name), names.join(", "))
        })
    }
}

/// How the soft solver solves rods and cables.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum LinkSolver {
    /// Ideal links (the default): each substep, the impulses that bring every rod and
    /// taut cable to its length at the end of the substep are solved for together, to
    /// convergence, along the links' directions at its start, and the velocities are
    /// then made to agree with the links (RATTLE, Andersen 1983, on semi-implicit
    /// Euler; see `solver/soft/link_network/`). Conservative: an undamped chain or cloth keeps
    /// its swing energy. A network too large for the direct solve is solved `Soft`.
    #[default]
    Exact,
    /// Soft links: each rod and cable is a soft constraint of
    /// [`joint_hertz`](SolverSettings::joint_hertz) and
    /// [`joint_damping_ratio`](SolverSettings::joint_damping_ratio), one pass per
    /// substep in turn (Box2D v3's soft step). Cheap, but the give it lets in is damped
    /// away: an undamped chain keeps a quarter of its swing energy over 20 s.
    Soft,
}

impl LinkSolver {
    /// Every link solver, in menu order.
    pub const ALL: [Self; 2] = [Self::Exact, Self::Soft];

    /// The name in files and messages.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::Soft => "soft",
        }
    }
}

/// The solver, substeps and integrator a scene file, a link or the command line names:
/// each `None` where it names none, so that choices can be laid over one another
/// (the defaults, then a scene file's own, then the flags typed).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolverChoice {
    /// The solver, if named.
    pub kind: Option<SolverKind>,
    /// The substeps, if named (checked against [`SUBSTEP_RANGE`] where it is read).
    pub substeps: Option<u32>,
    /// The integrator, if named.
    pub integrator: Option<Integrator>,
}

impl SolverChoice {
    /// `base` with what this choice names put over it.
    #[must_use]
    pub fn over(self, base: SolverSettings) -> SolverSettings {
        SolverSettings {
            kind: self.kind.unwrap_or(base.kind),
            substeps: self.substeps.unwrap_or(base.substeps),
            integrator: self.integrator.unwrap_or(base.integrator),
            ..base
        }
    }

    /// What `settings` names that the defaults do not: the choice that, laid over the
    /// defaults, gives `settings`' solver, substeps and integrator.
    #[must_use]
    pub fn differing(settings: &SolverSettings) -> Self {
        let default = SolverSettings::default();
        Self {
            kind: (settings.kind != default.kind).then_some(settings.kind),
            substeps: (settings.substeps != default.substeps).then_some(settings.substeps),
            integrator: (settings.integrator != default.integrator).then_some(settings.integrator),
        }
    }

    /// Whether it names nothing.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self == Self::default()
    }
}

/// Smallest and largest substep count.
pub const SUBSTEP_RANGE: std::ops::RangeInclusive<u32> = 1..=64;

/// Settings of a world's solver. Every field says its unit, default and valid range;
/// [`SolverSettings::validate`] checks them and names the field that is off.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SolverSettings {
    /// Which solver. Default [`SolverKind::Soft`].
    pub kind: SolverKind,
    /// How motion is advanced each (sub)step. Default [`Integrator::SemiImplicitEuler`],
    /// the paper's; see [`integrator`](crate::physics::integrator) for what the others do with contacts.
    pub integrator: Integrator,
    /// Substeps per step for the soft solver, 1 to 64. Default 4: each substep
    /// integrates, solves every contact and link once with position feedback, and once
    /// without ("relax"). More substeps make stiff links and tall piles converge better.
    pub substeps: u32,
    /// Stiffness of contacts (Hz), > 0. Default 100. A physical value, the same at
    /// every step: only a substep too coarse to resolve it (fewer than `1 /`
    /// [`CONTACT_HERTZ_LIMIT`] substeps per period, 200 substeps a second at 100 Hz) clamps
    /// it, where a soft constraint stays stable. A soft contact gives like a spring under
    /// load (overlap ≈ load / (m ω²)): Box2D's 30 Hz left 17 mm of overlap at the bottom
    /// of a 10-layer pile of 1 kg spheres, 60 Hz 7 mm; 100 Hz keeps a settled pile of
    /// 3,000 spheres of radius 0.5 m at 0.56% of the radius at its deepest (60 Hz: 1.2%,
    /// issue 39).
    pub contact_hertz: f32,
    /// Damping ratio of contacts, >= 0. Default 5: heavily damped, so a pushed-out
    /// overlap does not bounce. The damping (`2 ζ ω` per unit mass) is what an arch of
    /// grains leans on: with rolling resistance free of twist, an opening of 5 grains
    /// jammed at 60 Hz and 10 in 2 of 25 random starts, at 120 Hz and 10 in 4 of 10, at
    /// 120 Hz and 5 in none of 4 (issue 39, docs/convergence.md). At
    /// 100 Hz, 5 is the least that lets a pile settle at 4 substeps of 1/60 s (at 120 Hz
    /// and 5 a 3,000-sphere pile still stirred at 1 cm/s after 20 s).
    pub contact_damping_ratio: f32,
    /// How rods and cables are solved (soft solver). Default [`LinkSolver::Exact`].
    #[serde(default)]
    pub link_solver: LinkSolver,
    /// Give of rods and taut cables in the exact link solve, as the natural frequency
    /// (Hz) of a link and the particles it joins, > 0. Default 20,000: each link is
    /// solved as a spring of stiffness `m (2π f)²` (`m` its effective mass) taken
    /// implicitly, which a rod carrying its end's weight stretches by `g / (2π f)²`
    /// (0.6 nm), so links are rigid in all but name. The give only matters where links
    /// line up and the equations become singular (a row of rods pulled straight): it
    /// keeps the solve regular there. Measured on the shipped 10 × 10 cloth, undamped,
    /// 20 s at 240 Hz (swing energy kept, largest strain): 3,000 Hz 49% (0.08%), 10,000
    /// Hz 86% (0.02%), 20,000 Hz 95% (0.006%), 50,000 Hz 100.8%, 200,000 Hz 101.1%:
    /// softer links let energy into such moments and damp it; stiffer ones make the
    /// equations harder to solve there, and the energy drifts up. The 20-rod chain
    /// keeps 98.7% to 100.1% over that whole range. Not clamped to the substep: the
    /// solve is implicit.
    #[serde(default = "default_link_hertz")]
    pub link_hertz: f32,
    /// Stiffness of soft rods and cables (Hz), > 0: what [`LinkSolver::Soft`] uses.
    /// Default 240, clamped like contacts' to a
    /// quarter of the substep rate (so 240 Hz at 240 Hz with 4 substeps, 60 Hz at 60 Hz).
    /// Measured on a chain flung at 4 m/s at 240 Hz: largest rod strain 1.05e-3 at
    /// 60 Hz, 4.9e-4 at 120 Hz, 2.4e-4 at 240 Hz with damping ratio 1 (the paper's
    /// resolver: 3.4e-4).
    pub joint_hertz: f32,
    /// Damping ratio of soft rods and cables, >= 0 ([`LinkSolver::Soft`]). Default 1 (at
    /// 2 the rods above strained 3.4e-4).
    pub joint_damping_ratio: f32,
    /// Fastest speed at which an overlap is pushed out (m/s), > 0. Default 3: deep
    /// overlaps come apart without launching anything. The exact link solve brings a
    /// link that is off its length (a network built stretched, a particle moved by
    /// hand) back at this speed, too.
    pub max_push_speed: f32,
    /// Closing speeds below this do not bounce (m/s), >= 0. Default 0.1: resting
    /// contacts are not resting if gravity's step-by-step speed makes them bounce.
    pub restitution_threshold: f32,
    /// Gap below which a sphere and a plane get a contact before they touch (m), >= 0.
    /// Default 0.02. To it is added how far the particle can move in the step, so fast
    /// particles are caught before they pass through. Two spheres get one when their
    /// straight relative path over the step comes within twice this of touching (each
    /// sphere's share), at the closest approach: spheres that only pass by get none.
    pub speculative_distance: f32,
    /// Let islands of particles at rest fall asleep (soft solver). Default true. A
    /// sleeping particle is not integrated or solved (its velocity is zero) until an
    /// awake particle touches it, a force starts acting on it, or it is moved from
    /// outside; then its whole island wakes. What makes a settled pile cost little.
    pub sleep: bool,
    /// Speed below which a particle counts as at rest (m/s), >= 0. Default 0.05.
    pub sleep_speed: f32,
    /// How long every particle of an island must have been at rest before the island
    /// sleeps (s), > 0. Default 0.5.
    pub sleep_time: f32,
}

/// Largest contact stiffness per substep rate: a contact's hertz is clamped to this
/// over the substep (s), so that `h ω` stays at most π. Box2D v3 clamps at a quarter,
/// which made the default stiffness turn on the step: the default pile's 4 substeps of
/// 1/60 s would hold 100 Hz contacts at 60.
pub const CONTACT_HERTZ_LIMIT: f32 = 0.5;

/// Default of [`SolverSettings::link_hertz`] (Hz).
pub const DEFAULT_LINK_HERTZ: f32 = 20_000.0;

fn default_link_hertz() -> f32 {
    DEFAULT_LINK_HERTZ
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            kind: SolverKind::Soft,
            integrator: Integrator::SemiImplicitEuler,
            substeps: 4,
            contact_hertz: 100.0,
            contact_damping_ratio: 5.0,
            link_solver: LinkSolver::Exact,
            link_hertz: DEFAULT_LINK_HERTZ,
            joint_hertz: 240.0,
            joint_damping_ratio: 1.0,
            max_push_speed: 3.0,
            restitution_threshold: 0.1,
            speculative_distance: 0.02,
            sleep: true,
            sleep_speed: 0.05,
            sleep_time: 0.5,
        }
    }
}

impl SolverSettings {
    /// Checks every field; the error names the first that is out of range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let bad = |field: &str, value: f32, range: &str| {
            Err(PhysicsError::InvalidSetting(format!(
                "solver {field} = {value} is out of range; valid range: {range}"
            )))
        };
        if !SUBSTEP_RANGE.contains(&self.substeps) {
            return bad("substeps", self.substeps as f32, "1 to 64");
        }
        let positive = |v: f32| v > 0.0 && v.is_finite();
        let non_negative = |v: f32| v >= 0.0 && v.is_finite();
        for (field, value) in [
            ("contact_hertz", self.contact_hertz),
            ("link_hertz", self.link_hertz),
            ("joint_hertz", self.joint_hertz),
            ("max_push_speed", self.max_push_speed),
            ("sleep_time", self.sleep_time),
        ] {
            if !positive(value) {
                return bad(field, value, "a finite number > 0");
            }
        }
        for (field, value) in [
            ("contact_damping_ratio", self.contact_damping_ratio),
            ("joint_damping_ratio", self.joint_damping_ratio),
            ("restitution_threshold", self.restitution_threshold),
            ("speculative_distance", self.speculative_distance),
            ("sleep_speed", self.sleep_speed),
        ] {
            if !non_negative(value) {
                return bad(field, value, "a finite number >= 0");
            }
        }
        Ok(())
    }
}

/// The coefficients of a soft constraint for one substep.
///
/// A constraint error `C` is driven to zero like a damped spring of natural frequency
/// `ω = 2π hertz` and damping ratio `ζ`, solved implicitly over the substep `h`. Working
/// through the implicit Euler update of `m C'' = -k C - c C'` with `k = m ω²` and
/// `c = 2 m ζ ω` gives an impulse `λ = -m_eff (massScale (C' + biasRate C)) -
/// impulseScale λ_acc`, where
/// `biasRate = ω / (2ζ + hω)`, `massScale = hω(2ζ + hω) / (1 + hω(2ζ + hω))` and
/// `impulseScale = 1 / (1 + hω(2ζ + hω))`.
/// As `hω` grows, `massScale → 1` and `impulseScale → 0` (a rigid constraint) and
/// `biasRate → 1/h` (all the error removed in one substep): stable for any stiffness,
/// which is why stiffness is still clamped to keep the feedback gentle (Box2D v3 and
/// rapier derive the same three numbers).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Softness {
    /// Velocity bias per metre of error (1/s).
    pub bias_rate: f32,
    /// Fraction of the rigid impulse applied.
    pub mass_scale: f32,
    /// Fraction of the accumulated impulse taken back (the spring's give).
    pub impulse_scale: f32,
}

impl Softness {
    /// Coefficients for stiffness `hertz` (Hz), damping ratio `zeta` and substep `h` (s).
    #[must_use]
    pub fn new(hertz: f32, zeta: f32, h: f32) -> Self {
        if hertz <= 0.0 {
            return Self { bias_rate: 0.0, mass_scale: 1.0, impulse_scale: 0.0 };
        }
        let omega = std::f32::consts::TAU * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Self { bias_rate: omega / a1, mass_scale: a2 * a3, impulse_scale: a3 }
    }

    /// A rigid constraint with no position feedback (the relax pass).
    pub const RIGID: Self = Self { bias_rate: 0.0, mass_scale: 1.0, impulse_scale: 0.0 };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_passes_validation_and_matches_its_docs() {
        let s = SolverSettings::default();
        s.validate().unwrap();
        assert_eq!((s.kind, s.substeps), (SolverKind::Soft, 4));
        assert_eq!(s.integrator, Integrator::SemiImplicitEuler);
        assert_eq!((s.contact_hertz, s.contact_damping_ratio), (100.0, 5.0));
        assert_eq!((s.link_solver, s.link_hertz), (LinkSolver::Exact, 20_000.0));
        assert_eq!((s.joint_hertz, s.joint_damping_ratio), (240.0, 1.0));
        assert_eq!((s.max_push_speed, s.restitution_threshold, s.speculative_distance), (3.0, 0.1, 0.02));
        assert_eq!((s.sleep, s.sleep_speed, s.sleep_time), (true, 0.05, 0.5));
    }

    #[test]
    fn each_bad_field_is_named() {
        type Spoil = fn(&mut SolverSettings);
        let cases: [(&str, Spoil); 8] = [
            ("link_hertz", |s| s.link_hertz = 0.0),
            ("sleep_speed", |s| s.sleep_speed = -0.1),
            ("sleep_time", |s| s.sleep_time = 0.0),
            ("substeps", |s| s.substeps = 0),
            ("contact_hertz", |s| s.contact_hertz = f32::NAN),
            ("joint_damping_ratio", |s| s.joint_damping_ratio = -1.0),
            ("max_push_speed", |s| s.max_push_speed = 0.0),
            ("speculative_distance", |s| s.speculative_distance = f32::INFINITY),
        ];
        for (field, spoil) in cases {
            let mut s = SolverSettings::default();
            spoil(&mut s);
            let message = s.validate().unwrap_err().to_string();
            assert!(message.contains(field), "{message}");
        }
    }

    #[test]
    fn softness_tends_to_rigid_as_stiffness_grows() {
        let soft = Softness::new(1e6, 1.0, 1.0 / 240.0);
        assert!(soft.mass_scale > 0.999 && soft.impulse_scale < 1e-3);
        assert!((soft.bias_rate * (1.0 / 240.0) - 1.0).abs() < 1e-2);
        assert_eq!(Softness::new(0.0, 1.0, 0.01), Softness::RIGID);
    }

    #[test]
    fn solver_names_round_trip() {
        for kind in SolverKind::ALL {
            assert_eq!(SolverKind::parse(kind.name()), Ok(kind));
        }
        assert!(SolverKind::parse("pgs").unwrap_err().contains("soft, paper"));
    }
}

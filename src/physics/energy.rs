//! The energy budget: what a world holds now ([`Energy`]), the running totals since the
//! first step ([`Ledger`]), and the sums over particles and force generators they are
//! made of.
//!
//! Imports particles and forces; the world books each step here, the solvers book what
//! they take out on the particles' `dissipated` tally (losses, never negative) and what
//! their corrections change on its `constraint` tally (either sign).

use crate::physics::forces::ForceRegistry;
use crate::physics::ids::ParticleId;
use crate::physics::particles::{Particles, tree_sum};

/// The energy budget of a world (J).
///
/// `kinetic + potential + dissipated + constraint + removed - work` would stay at its
/// value before the first step if the integrator were exact; `error` is how far it is
/// from that, which is the integrator's error, shown as such. The solver's error has a
/// line of its own, [`constraint`](Self::constraint).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// `Σ ½ m v²` over movable particles, plus `Σ ½ I ω²` over the spheres that roll.
    pub kinetic: f32,
    /// The rotational part of `kinetic`, `Σ ½ I ω²` (0 when nothing rolls).
    pub rotational: f32,
    /// Gravitational (from each particle's constant acceleration and from gravity
    /// generators) plus elastic energy stored in springs.
    pub potential: f32,
    /// The gravitational part of `potential`; the rest is elastic (springs, bungees,
    /// stiff springs) and buoyancy's.
    pub gravitational: f32,
    /// Taken out since the first step, cumulative, by what loses energy in the physics:
    /// damping, drag, a damped stiff spring, inelastic bounces (restitution below 1, a
    /// cable jerked taut), friction and rolling resistance, and what was left when
    /// particles fell asleep. Each is a loss (>= 0), so this total never decreases.
    pub dissipated: f32,
    /// Taken out since the first step by the constraint solve's own corrections,
    /// cumulative (negative: put in): what moving rods, cables and contacts back to
    /// their geometry (position projection, the soft solver's pushes out of overlaps
    /// and its relax pass) and stopping the velocity gravity's kick builds up along them
    /// changed, beyond the losses booked as dissipated. Ideal links and contacts do no
    /// work, so this is the solver's error, as `error` is the integrator's: it swings
    /// about zero on a rigid pendulum and grows with the step.
    pub constraint: f32,
    /// Put in from outside the step since the first step, cumulative: anything that
    /// changed the energy between steps (dragging with the mouse, changing g or a mass).
    pub work: f32,
    /// Carried out of the world by particles removed since the first step, cumulative:
    /// the kinetic and potential energy each had (with the springs that went with it)
    /// when it was removed. A round of the projectile that lands and goes takes its
    /// energy with it; it is neither lost nor an error.
    pub removed: f32,
    /// `kinetic + potential + dissipated + constraint + removed - work` minus its value
    /// before the first step.
    pub error: f32,
}

/// Running totals of the energy budget, in f64.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Ledger {
    /// `kinetic + potential` before the first step, once stepped.
    pub(crate) start: Option<f64>,
    /// `kinetic + potential` at the end of the last step.
    pub(crate) last: f64,
    /// See [`Energy::dissipated`].
    pub(crate) dissipated: f64,
    /// See [`Energy::constraint`]. Absent from a snapshot saved before it had a line
    /// of its own (it was booked with `dissipated` then): 0.
    #[serde(default)]
    pub(crate) constraint: f64,
    /// See [`Energy::work`].
    pub(crate) work: f64,
    /// See [`Energy::removed`].
    #[serde(default)]
    pub(crate) removed: f64,
}

impl Ledger {
    /// The budget now, from the energies in the state (J, in f64: kinetic,
    /// gravitational, other stored) and the running totals.
    pub(crate) fn energy(&self, (kinetic, gravitational, stored): (f64, f64, f64)) -> Energy {
        let potential = gravitational + stored;
        let start = self.start.unwrap_or(kinetic + potential);
        let error =
            kinetic + potential + self.dissipated + self.constraint + self.removed - self.work - start;
        // `+ 0.0` turns a negative zero (an empty sum) into zero: no figure reads "-0".
        Energy {
            kinetic: kinetic as f32 + 0.0,
            rotational: 0.0,
            potential: potential as f32 + 0.0,
            gravitational: gravitational as f32 + 0.0,
            dissipated: self.dissipated as f32 + 0.0,
            constraint: self.constraint as f32 + 0.0,
            work: self.work as f32 + 0.0,
            removed: self.removed as f32 + 0.0,
            error: error as f32 + 0.0,
        }
    }

    /// Whether every running total is a finite number (a loaded ledger must be).
    pub(crate) fn is_finite(&self) -> bool {
        [self.start.unwrap_or(0.0), self.last, self.dissipated, self.constraint, self.work, self.removed]
            .iter()
            .all(|x| x.is_finite())
    }
}

/// Kinetic, gravitational and other stored (elastic, buoyancy) energy (J), in f64.
pub(crate) fn energies(p: &Particles, forces: &ForceRegistry) -> (f64, f64, f64) {
    // One pass over the particles, in leaves summed up a fixed tree (the same bits on
    // any number of threads): twice the kinetic energy of motion and of spin, and the
    // gravitational energy of the constant accelerations, -m a·p.
    let [moving, turning, mut gravitational] = tree_sum(0..p.len(), &|range: std::ops::Range<usize>| {
        let [moving, turning] = p.kinetic_parts(range.clone());
        let bodies = p.inverse_mass[range.clone()].iter().zip(&p.acceleration[range.clone()]);
        let mut gravitational = 0.0;
        for ((&inverse_mass, a), x) in bodies.zip(&p.position[range]) {
            if inverse_mass > 0.0 {
                gravitational -= a.as_dvec3().dot(x.as_dvec3()) / f64::from(inverse_mass);
            }
        }
        [moving, turning, gravitational]
    });
    let mut stored = 0.0;
    for force in forces.kinds() {
        let energy = f64::from(force.generator().potential_energy(p));
        if force.is_gravity() {
            gravitational += energy;
        } else {
            stored += energy;
        }
    }
    (0.5 * (moving + turning), gravitational, stored)
}

/// Kinetic plus potential energy (J), summed in f64.
pub(crate) fn mechanical_energy(particles: &Particles, forces: &ForceRegistry) -> f64 {
    let (kinetic, gravitational, stored) = energies(particles, forces);
    kinetic + (gravitational + stored)
}

/// One particle's kinetic, gravitational and stored (elastic, buoyancy) energy (J):
/// the stored energy of every force generator acting on it, whole (a spring between
/// two particles counts for both). `None` for an unknown or immovable particle.
pub(crate) fn particle_energy(
    p: &Particles,
    forces: &ForceRegistry,
    id: ParticleId,
) -> Option<(f32, f32, f32)> {
    let i = p.index(id)?;
    let w = p.inverse_mass[i];
    if w <= 0.0 {
        return None;
    }
    let mut kinetic = 0.5 * p.velocity[i].length_squared() / w;
    if p.inverse_inertia[i] != 0.0 {
        kinetic += 0.5 * p.angular_velocity[i].length_squared() / p.inverse_inertia[i];
    }
    let mut gravitational = -p.acceleration[i].dot(p.position[i]) / w;
    let mut stored = 0.0;
    for force in forces.kinds().filter(|g| g.generator().involves(id)) {
        let generator = force.generator();
        if force.is_gravity() {
            // Only this particle's share of a field acting on many.
            gravitational -= generator.force_on(p, i).map_or(0.0, |f| f.dot(p.position[i]));
        } else {
            stored += generator.potential_energy(p);
        }
    }
    Some((kinetic, gravitational, stored))
}

/// What measuring gravitational energy from the height `height` (m) instead of y = 0
/// adds to it (J): `Σ m a_y height` over the movable particles.
pub(crate) fn gravity_reference_shift(p: &Particles, height: f32) -> f32 {
    let bodies = p.acceleration.iter().zip(&p.inverse_mass).filter(|(_, w)| **w > 0.0);
    let sum: f64 = bodies.map(|(a, &w)| f64::from(a.y) / f64::from(w)).sum();
    (sum * f64::from(height)) as f32 + 0.0
}

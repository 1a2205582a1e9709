//! Force generators: anything that adds a force to particles each step.
//!
//! Each generator names the particles it acts on by [`ParticleId`]; the
//! [`ForceRegistry`] owns the generators and applies them in the order they were added.

use glam::Vec3;

use super::links::{LinkEnd, LinkKind, LinkSpec, direction_or_zero, end_position};
use super::particles::{ParticleId, Particles};
use super::state::SavedForce;
use super::{NON_NEGATIVE, PhysicsError, check, non_negative};

/// Something that adds forces to particles every step. `Send` so that a world can be
/// handed to another thread (a benchmark's pool, a background simulation).
pub trait ForceGenerator: Send {
    /// Adds this step's force to the particles' accumulators, for a step that moves
    /// the particles with what this one evaluation gives (semi-implicit Euler): a
    /// generator may choose the force that lands that step on its own exact solution
    /// (drag does). `dt` is the step (s).
    fn apply(&mut self, particles: &mut Particles, dt: f32);

    /// Adds the force as the physics defines it at the particles' current state, for
    /// an integrator that evaluates forces at trial states and weighs them itself
    /// (explicit Euler, Verlet, RK4). What it books as dissipated is the power at this
    /// state times `dt`; the integrator weighs the evaluations' bookings as it weighs
    /// their forces, so a step books its loss once. By default the same as `apply`.
    fn apply_instantaneous(&mut self, particles: &mut Particles, dt: f32) {
        self.apply(particles, dt);
    }

    /// For a generator that moves its particle over the step in closed form, whatever
    /// the integrator (the stiff spring): the step from the particle's current state
    /// under its other accelerations `other` (m/s², by dense index), held constant over
    /// the step. Such a generator adds no force at an evaluation; the integrator takes
    /// this step for its particle instead. `None` for every other generator.
    fn closed_step(&self, _particles: &Particles, _other: &[Vec3], _h: f32) -> Option<ClosedStep> {
        None
    }

    /// Whether [`ForceGenerator::closed_step`] moves a particle.
    fn moves_in_closed_form(&self) -> bool {
        false
    }

    /// Checks every setting; the error names the field and its valid range. The
    /// registry calls it before accepting the generator.
    fn validate(&self) -> Result<(), PhysicsError> {
        Ok(())
    }

    /// Whether this generator refers to the particle.
    fn involves(&self, id: ParticleId) -> bool;

    /// The particle is being removed: forget it. Returns true if the generator has
    /// nothing left to act on and must go too. A link goes with either end; a field
    /// acting on many particles only drops that one from its list.
    fn release(&mut self, id: ParticleId) -> bool {
        self.involves(id)
    }

    /// Stored elastic or field energy (J) in the current state; 0 if not meaningful.
    fn potential_energy(&self, _particles: &Particles) -> f32 {
        0.0
    }

    /// The generator seen as a link between two points, if it is one (springs are).
    fn link(&self) -> Option<LinkSpec> {
        None
    }

    /// Tension (N) along the link in the current state; positive pulls the ends together.
    fn tension(&self, _particles: &Particles) -> f32 {
        0.0
    }

    /// A short name for the force, as the inspector and the free-body arrows show it.
    fn name(&self) -> &'static str {
        "force"
    }

    /// The force this generator puts on particle `i` (dense index) in the current state
    /// (N), as the physics defines it (not the step's integrated form), or `None` where
    /// it does not act on that particle.
    fn force_on(&self, _particles: &Particles, _i: usize) -> Option<Vec3> {
        None
    }

    /// The generator as a snapshot stores it, with any state it carries between steps;
    /// `None` for a kind the snapshot format does not know (a world holding one cannot
    /// be saved).
    fn saved(&self) -> Option<SavedForce> {
        None
    }
}

/// One particle's step taken in closed form ([`ForceGenerator::closed_step`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosedStep {
    /// The particle (dense index).
    pub index: usize,
    /// The velocity that carries it from its start to its end position over the step
    /// (m/s): the step's average velocity.
    pub moving: Vec3,
    /// Its exact velocity at the end of the step, before damping (m/s).
    pub end: Vec3,
    /// Energy the generator's own damping took over the step (J).
    pub dissipated: f64,
}

/// Which of a generator's two forms an evaluation asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Evaluation {
    /// [`ForceGenerator::apply`]: the one evaluation of a semi-implicit Euler step.
    Step,
    /// [`ForceGenerator::apply_instantaneous`]: one of an integrator's trial states.
    Instantaneous,
}

/// Handle to a registered force generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct ForceId(pub u32);

/// Owns the force generators of a world; supports add, remove and clear.
#[derive(Default)]
pub struct ForceRegistry {
    entries: Vec<(ForceId, Box<dyn ForceGenerator>)>,
    next: u32,
}

impl ForceRegistry {
    /// Registers a generator and returns its handle, after checking its settings
    /// ([`ForceGenerator::validate`]); on an error nothing is added.
    pub fn add(&mut self, generator: Box<dyn ForceGenerator>) -> Result<ForceId, PhysicsError> {
        generator.validate()?;
        let id = ForceId(self.next);
        self.next += 1;
        self.entries.push((id, generator));
        Ok(id)
    }

    /// Unregisters a generator; false if it was not registered.
    pub fn remove(&mut self, id: ForceId) -> bool {
        let before = self.entries.len();
        self.entries.retain(|(entry, _)| *entry != id);
        self.entries.len() != before
    }

    /// Swaps the generator behind `id` for another, keeping its place in the order;
    /// `Ok(false)` if `id` is not registered. A generator whose settings are invalid
    /// is refused and the old one kept.
    pub fn replace(&mut self, id: ForceId, generator: Box<dyn ForceGenerator>) -> Result<bool, PhysicsError> {
        generator.validate()?;
        Ok(match self.entries.iter_mut().find(|(entry, _)| *entry == id) {
            Some(entry) => {
                entry.1 = generator;
                true
            }
            None => false,
        })
    }

    /// Tells every generator the particle is gone, dropping those left with nothing.
    pub fn remove_involving(&mut self, particle: ParticleId) {
        self.entries.retain_mut(|(_, g)| !g.release(particle));
    }

    /// Unregisters everything.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Number of registered generators.
    #[must_use]
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when nothing is registered.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Applies every generator, in registration order.
    pub fn apply(&mut self, particles: &mut Particles, dt: f32) {
        for (_, generator) in &mut self.entries {
            generator.apply(particles, dt);
        }
    }

    /// Applies every generator but those that move their particle in closed form, in
    /// the form `evaluation` asks for: what an integrator that takes closed-form steps
    /// evaluates ([`super::integrator`]).
    pub(crate) fn apply_for(&mut self, particles: &mut Particles, dt: f32, evaluation: Evaluation) {
        for (_, generator) in self.entries.iter_mut().filter(|(_, g)| !g.moves_in_closed_form()) {
            match evaluation {
                Evaluation::Step => generator.apply(particles, dt),
                Evaluation::Instantaneous => generator.apply_instantaneous(particles, dt),
            }
        }
    }

    /// Whether a generator moves its particle in closed form: such a world is stepped
    /// by [`super::integrator::Integration`] whatever the integrator.
    #[must_use]
    pub fn has_closed_form(&self) -> bool {
        self.entries.iter().any(|(_, g)| g.moves_in_closed_form())
    }

    /// The closed-form steps of the generators that take them, from the particles'
    /// current state, into `out` (cleared first).
    pub(crate) fn closed_steps(
        &self,
        particles: &Particles,
        other: &[Vec3],
        h: f32,
        out: &mut Vec<ClosedStep>,
    ) {
        out.clear();
        out.extend(self.entries.iter().filter_map(|(_, g)| g.closed_step(particles, other, h)));
    }

    /// Iterates over the generators.
    pub fn iter(&self) -> impl Iterator<Item = &dyn ForceGenerator> {
        self.entries.iter().map(|(_, g)| g.as_ref())
    }

    /// Every generator as a snapshot stores it, with its handle, and the next handle;
    /// the error names a generator whose kind cannot be saved.
    pub(crate) fn saved(&self) -> Result<(Vec<(ForceId, SavedForce)>, u32), PhysicsError> {
        let mut out = Vec::with_capacity(self.entries.len());
        for (id, generator) in &self.entries {
            let saved = generator.saved().ok_or_else(|| {
                PhysicsError::InvalidSetting(format!(
                    "force generator '{}' cannot be saved",
                    generator.name()
                ))
            })?;
            out.push((*id, saved));
        }
        Ok((out, self.next))
    }

    /// A registry from saved generators, each checked as [`ForceRegistry::add`] checks.
    pub(crate) fn from_saved(saved: Vec<(ForceId, SavedForce)>, next: u32) -> Result<Self, PhysicsError> {
        let mut entries = Vec::with_capacity(saved.len());
        for (id, force) in saved {
            // Handles are handed out in increasing order and kept in it.
            let increasing = entries.last().is_none_or(|(last, _): &(ForceId, _)| last.0 < id.0);
            if id.0 >= next || !increasing {
                return Err(PhysicsError::InvalidSetting(format!(
                    "force id {} is out of order or not below next_force = {next}",
                    id.0
                )));
            }
            let generator = force.into_generator();
            generator.validate()?;
            entries.push((id, generator));
        }
        Ok(Self { entries, next })
    }
}

/// Uniform gravity as a force, `F = m g`, on a list of particles.
///
/// Scenes usually put gravity in each particle's constant acceleration instead (as the
/// paper does); this generator exists for particles that need their own field.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Gravity {
    /// Acceleration of the field (m/s²), e.g. `(0, -9.81, 0)`.
    pub gravity: Vec3,
    /// Particles it acts on.
    pub targets: Vec<ParticleId>,
}

impl ForceGenerator for Gravity {
    fn saved(&self) -> Option<SavedForce> {
        Some(SavedForce::Gravity(self.clone()))
    }

    fn validate(&self) -> Result<(), PhysicsError> {
        check(self.gravity.is_finite(), "gravity", self.gravity, "a vector of finite numbers (m/s²)")
    }

    fn apply(&mut self, particles: &mut Particles, _dt: f32) {
        for &id in &self.targets {
            if let Some(i) = particles.index(id) {
                let inverse_mass = particles.inverse_mass[i];
                if inverse_mass > 0.0 {
                    particles.force[i] += self.gravity / inverse_mass;
                }
            }
        }
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.targets.contains(&id)
    }

    fn release(&mut self, id: ParticleId) -> bool {
        self.targets.retain(|&target| target != id);
        self.targets.is_empty()
    }

    fn name(&self) -> &'static str {
        "gravity"
    }

    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        let w = particles.inverse_mass[i];
        (w > 0.0 && self.targets.contains(&particles.ids()[i])).then(|| self.gravity / w)
    }

    fn potential_energy(&self, particles: &Particles) -> f32 {
        self.targets
            .iter()
            .filter_map(|&id| particles.index(id))
            .filter(|&i| particles.inverse_mass[i] > 0.0)
            .map(|i| -self.gravity.dot(particles.position[i]) / particles.inverse_mass[i])
            .sum()
    }
}

/// Simplified aerodynamic drag, `F = -v̂ (k1 |v| + k2 |v|²)`.
///
/// Applied explicitly, drag overshoots (reverses the velocity, then grows without
/// bound) once `k1·dt/m > 2` or `k2·|v|·dt/m > 2`. So the generator solves the step's
/// velocity update itself, with the particle's other accelerations `g` (its constant
/// one and the forces registered before this generator) held over the step, and
/// applies the constant force that lands the integrator there:
/// - linear drag only (`k2 = 0`): the exact solution of `v' = g - (k1/m) v`,
///   `v(t) = v∞ + (v0 - v∞) e^{-k1 t/m}` with `v∞ = m g / k1`;
/// - with quadratic drag: backward Euler, `v1 = v0 + dt (g - (k1 + k2|v1|) v1 / m)`,
///   solved in closed form (a quadratic in `|v1|`).
///
/// Both are stable for any `k1, k2 >= 0`, never reverse the velocity, and reach the
/// exact terminal velocity (`k1 v + k2 v² = m g`). Register drag after the particle's
/// other force generators.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Drag {
    /// Linear coefficient (N·s/m).
    pub k1: f32,
    /// Quadratic coefficient (N·s²/m²).
    pub k2: f32,
    /// Particles it acts on.
    pub targets: Vec<ParticleId>,
}

impl Drag {
    /// The drag force on a particle moving at `velocity` (N), at this instant.
    #[inline]
    #[must_use]
    pub fn force(&self, velocity: Vec3) -> Vec3 {
        let speed = velocity.length();
        // -v̂ (k1|v| + k2|v|²) = -v (k1 + k2|v|); zero velocity gives zero force.
        -velocity * (self.k1 + self.k2 * speed)
    }

    /// Velocity after `dt` seconds (m/s) of a particle of inverse mass `inverse_mass`
    /// starting at `velocity` under drag and a constant other acceleration `other`.
    #[must_use]
    pub fn velocity_after(&self, velocity: Vec3, other: Vec3, inverse_mass: f32, dt: f32) -> Vec3 {
        let (v0, g, t) = (velocity.as_dvec3(), other.as_dvec3(), f64::from(dt));
        let (a, b) = (f64::from(self.k1 * inverse_mass), f64::from(self.k2 * inverse_mass));
        if b == 0.0 {
            if a == 0.0 {
                return (v0 + g * t).as_vec3();
            }
            let terminal = g / a;
            return (terminal + (v0 - terminal) * (-a * t).exp()).as_vec3();
        }
        // (1 + a t + b t s) v1 = v0 + g t, with s = |v1|: v1 points along u = v0 + g t and
        // b t s² + (1 + a t) s - |u| = 0.
        let u = v0 + g * t;
        let (c1, c2, length) = (1.0 + a * t, b * t, u.length());
        // The positive root, written so it does not cancel when c2 is small.
        let s = 2.0 * length / (c1 + (c1 * c1 + 4.0 * c2 * length).sqrt());
        if length > 0.0 { (u * (s / length)).as_vec3() } else { Vec3::ZERO }
    }
}

impl ForceGenerator for Drag {
    fn saved(&self) -> Option<SavedForce> {
        Some(SavedForce::Drag(self.clone()))
    }

    fn validate(&self) -> Result<(), PhysicsError> {
        check(non_negative(self.k1), "drag k1", self.k1, NON_NEGATIVE)?;
        check(non_negative(self.k2), "drag k2", self.k2, NON_NEGATIVE)
    }

    fn apply(&mut self, particles: &mut Particles, dt: f32) {
        for &id in &self.targets {
            let Some(i) = particles.index(id) else { continue };
            let (v, w) = (particles.velocity[i], particles.inverse_mass[i]);
            if !(w > 0.0 && dt > 0.0) {
                particles.force[i] += self.force(v);
                continue;
            }
            let other = particles.acceleration[i] + particles.force[i] * w;
            let landed = self.velocity_after(v, other, w, dt);
            // The integrator adds (a + F/m) dt: choose the drag force that makes it `landed`.
            let drag = ((landed - v) / dt - other) / w;
            particles.force[i] += drag;
            // Its share of the step's change of kinetic energy, F·(v + v')/2 dt, is lost.
            particles.dissipated -= f64::from(drag.dot(v + landed) * 0.5 * dt);
        }
    }

    /// The force `-v (k1 + k2 |v|)` at the current velocity, with its power booked.
    fn apply_instantaneous(&mut self, particles: &mut Particles, dt: f32) {
        for &id in &self.targets {
            let Some(i) = particles.index(id) else { continue };
            let v = particles.velocity[i];
            let drag = self.force(v);
            particles.force[i] += drag;
            if particles.inverse_mass[i] > 0.0 {
                particles.dissipated -= f64::from(drag.dot(v)) * f64::from(dt);
            }
        }
    }

    fn name(&self) -> &'static str {
        "drag"
    }

    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        self.targets.contains(&particles.ids()[i]).then(|| self.force(particles.velocity[i]))
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.targets.contains(&id)
    }

    fn release(&mut self, id: ParticleId) -> bool {
        self.targets.retain(|&target| target != id);
        self.targets.is_empty()
    }
}

/// Hooke's law between a particle and the other end: a spring pushes when compressed
/// and pulls when stretched; a bungee only pulls, and only when stretched.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Spring {
    /// The particle the force acts on.
    pub a: ParticleId,
    /// The other end: a particle (which gets the opposite force) or a fixed anchor.
    pub b: LinkEnd,
    /// Spring constant (N/m).
    pub k: f32,
    /// Length at which the spring exerts no force (m).
    pub rest_length: f32,
    /// A bungee exerts no force when shorter than its rest length.
    pub bungee: bool,
}

impl Spring {
    /// A spring between two particles.
    #[must_use]
    pub fn between(a: ParticleId, b: ParticleId, k: f32, rest_length: f32) -> Self {
        Self { a, b: LinkEnd::Particle(b), k, rest_length, bungee: false }
    }

    /// A spring from a particle to a fixed anchor point.
    #[must_use]
    pub fn anchored(a: ParticleId, anchor: Vec3, k: f32, rest_length: f32) -> Self {
        Self { a, b: LinkEnd::Anchor(anchor), k, rest_length, bungee: false }
    }

    /// The same link, as a bungee.
    #[must_use]
    pub fn as_bungee(mut self) -> Self {
        self.bungee = true;
        self
    }

    /// Force on end `a` (N) given the two end positions; `b` gets the opposite.
    #[inline]
    #[must_use]
    pub fn force(&self, a: Vec3, b: Vec3) -> Vec3 {
        let (direction, length) = direction_or_zero(a - b);
        let extension = length - self.rest_length;
        if self.bungee && extension <= 0.0 {
            return Vec3::ZERO;
        }
        // Coincident ends have no direction; a compressed spring there still stores
        // k L²/2 and still pushes, so it pushes `a` up (+y), as contacts and links do.
        let direction = if direction == Vec3::ZERO { Vec3::Y } else { direction };
        -self.k * extension * direction
    }

    fn extension(&self, particles: &Particles) -> Option<f32> {
        let a = end_position(particles, LinkEnd::Particle(self.a))?;
        let b = end_position(particles, self.b)?;
        let extension = (a - b).length() - self.rest_length;
        Some(if self.bungee { extension.max(0.0) } else { extension })
    }
}

impl ForceGenerator for Spring {
    fn saved(&self) -> Option<SavedForce> {
        Some(SavedForce::Spring(self.clone()))
    }

    fn validate(&self) -> Result<(), PhysicsError> {
        let name = if self.bungee { "bungee" } else { "spring" };
        check(non_negative(self.k), &format!("{name} k"), self.k, NON_NEGATIVE)?;
        check(
            non_negative(self.rest_length),
            &format!("{name} rest_length"),
            self.rest_length,
            NON_NEGATIVE,
        )?;
        if let LinkEnd::Anchor(anchor) = self.b {
            check(anchor.is_finite(), &format!("{name} anchor"), anchor, "a point of finite numbers")?;
        }
        Ok(())
    }

    fn apply(&mut self, particles: &mut Particles, _dt: f32) {
        let Some(ia) = particles.index(self.a) else { return };
        let Some(b) = end_position(particles, self.b) else { return };
        let force = self.force(particles.position[ia], b);
        particles.force[ia] += force;
        if let LinkEnd::Particle(id) = self.b
            && let Some(ib) = particles.index(id)
        {
            particles.force[ib] -= force;
        }
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.a == id || self.b == LinkEnd::Particle(id)
    }

    fn name(&self) -> &'static str {
        if self.bungee { "bungee" } else { "spring" }
    }

    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        let id = particles.ids()[i];
        let force =
            self.force(end_position(particles, LinkEnd::Particle(self.a))?, end_position(particles, self.b)?);
        if id == self.a { Some(force) } else { (self.b == LinkEnd::Particle(id)).then_some(-force) }
    }

    fn potential_energy(&self, particles: &Particles) -> f32 {
        self.extension(particles).map_or(0.0, |x| 0.5 * self.k * x * x)
    }

    fn link(&self) -> Option<LinkSpec> {
        let kind = if self.bungee { LinkKind::Bungee } else { LinkKind::Spring };
        Some(LinkSpec { kind, a: self.a, b: self.b, rest: self.rest_length })
    }

    fn tension(&self, particles: &Particles) -> f32 {
        self.extension(particles).map_or(0.0, |x| self.k * x)
    }
}

/// Buoyancy of a body treated as a vertical column of height `2 * half_height` in a
/// liquid whose surface is the plane `y = surface`.
///
/// Submerged fraction `f = clamp((surface + half_height - y) / (2 half_height), 0, 1)`,
/// force `density * volume * g * f` upwards (Archimedes). This corrects the sign of the
/// partial-submersion term in the paper and in Cyclone.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Buoyancy {
    /// The floating particle.
    pub target: ParticleId,
    /// Height of the liquid surface (m).
    pub surface: f32,
    /// Half the body's height (m); the body is fully submerged at `y <= surface - half_height`.
    pub half_height: f32,
    /// Body volume (m³).
    pub volume: f32,
    /// Liquid density (kg/m³); water is 1000.
    pub density: f32,
    /// Gravitational acceleration (m/s², positive).
    pub g: f32,
}

impl Buoyancy {
    /// Fraction of the body below the surface when its centre is at height `y`.
    #[inline]
    #[must_use]
    pub fn submerged_fraction(&self, y: f32) -> f32 {
        if self.half_height <= 0.0 {
            return if y <= self.surface { 1.0 } else { 0.0 };
        }
        ((self.surface + self.half_height - y) / (2.0 * self.half_height)).clamp(0.0, 1.0)
    }

    /// Upward force (N) on the body when its centre is at height `y`.
    #[inline]
    #[must_use]
    pub fn force(&self, y: f32) -> Vec3 {
        Vec3::Y * (self.density * self.volume * self.g * self.submerged_fraction(y))
    }
}

impl ForceGenerator for Buoyancy {
    fn saved(&self) -> Option<SavedForce> {
        Some(SavedForce::Buoyancy(self.clone()))
    }

    fn validate(&self) -> Result<(), PhysicsError> {
        check(self.surface.is_finite(), "buoyancy surface", self.surface, "a finite height (m)")?;
        check(non_negative(self.half_height), "buoyancy half_height", self.half_height, NON_NEGATIVE)?;
        check(non_negative(self.volume), "buoyancy volume", self.volume, NON_NEGATIVE)?;
        check(non_negative(self.density), "buoyancy density", self.density, NON_NEGATIVE)?;
        check(non_negative(self.g), "buoyancy g", self.g, NON_NEGATIVE)
    }

    fn apply(&mut self, particles: &mut Particles, _dt: f32) {
        if let Some(i) = particles.index(self.target) {
            particles.force[i] += self.force(particles.position[i].y);
        }
    }

    fn involves(&self, id: ParticleId) -> bool {
        self.target == id
    }

    fn name(&self) -> &'static str {
        "buoyancy"
    }

    fn force_on(&self, particles: &Particles, i: usize) -> Option<Vec3> {
        (particles.ids()[i] == self.target).then(|| self.force(particles.position[i].y))
    }

    /// Work done against buoyancy to push the body down from the surface (J):
    /// `ρ V g s u²` while partly submerged (`u` the submerged fraction), growing
    /// linearly once fully under. Zero when clear of the liquid.
    fn potential_energy(&self, particles: &Particles) -> f32 {
        let Some(i) = particles.index(self.target) else { return 0.0 };
        let weight = self.density * self.volume * self.g;
        let s = self.half_height;
        if s <= 0.0 {
            return (weight * (self.surface - particles.position[i].y)).max(0.0);
        }
        let u = (self.surface + s - particles.position[i].y) / (2.0 * s);
        if u <= 0.0 {
            0.0
        } else if u <= 1.0 {
            weight * s * u * u
        } else {
            weight * s * (2.0 * u - 1.0)
        }
    }
}

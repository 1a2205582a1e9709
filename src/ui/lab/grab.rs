//! Dragging particles with the mouse (a soft spring to the pointer, Box2D's mouse
//! joint), picking the particle under the pointer, and the selection.

use glam::{Vec2, Vec3};

use super::limits::{
    MOUSE_DAMPING_RATIO, MOUSE_HERTZ, MOUSE_JOINED_ACCELERATION, MOUSE_MAX_ACCELERATION, MOUSE_TORN_SPEED,
};
use super::model::Lab;
use super::records::Grab;
use crate::physics::ParticleId;

/// The change of velocity the mouse spring gives in a step of `h` seconds to a particle
/// `offset` metres short of the pointer and moving at `v`: a damped spring integrated
/// implicitly (the soft step: stable for any `h`), then limited to
/// [`MOUSE_MAX_ACCELERATION`] over the step.
#[must_use]
pub fn mouse_pull(offset: Vec3, v: Vec3, h: f32) -> Vec3 {
    mouse_pull_joined(offset, v, h, 1.0)
}

/// [`mouse_pull`] for a particle joined by links to others, `ratio` times its own mass
/// in all (1 for a lone particle): the spring pulls as if on the whole joined mass,
/// `ratio` times harder, its damping the particle's own, and its force limit that of
/// [`MOUSE_MAX_ACCELERATION`] on the particle plus [`MOUSE_JOINED_ACCELERATION`] on
/// the rest, so a chain or a
/// cloth follows the pointer as a single particle does and a hard pull tears cloth.
/// The pull is the whole mass's 5 Hz spring, explicit in the offset (stable while
/// 2π·5 Hz times the step is well under 2: any physics rate the panel offers).
#[must_use]
pub fn mouse_pull_joined(offset: Vec3, v: Vec3, h: f32, ratio: f32) -> Vec3 {
    let ratio = ratio.max(1.0);
    let omega = std::f32::consts::TAU * MOUSE_HERTZ;
    let (k, c) = (omega * omega, 2.0 * MOUSE_DAMPING_RATIO * omega);
    // The spring's pull on the whole joined mass lands on the particle (its links pass
    // it on); the damping stays the particle's own, which an implicit step of `ratio`
    // times the damping would turn into a brake 40 times stronger than the pull.
    let dv = (offset * k * ratio - v * (c + k * h)) * h / (1.0 + c * h + k * h * h);
    // The particle's own share as for a lone one; the joined rest at a higher limit,
    // since the links, not the particle, carry it (and a hard pull should tear cloth).
    let limit = MOUSE_MAX_ACCELERATION + MOUSE_JOINED_ACCELERATION * (ratio - 1.0);
    dv.clamp_length_max(limit * h)
}

impl Lab {
    /// Selects a particle for the inspector (or none).
    pub fn select(&mut self, id: Option<ParticleId>) {
        if self.selected != id {
            self.selected = id;
            self.constraint_force = None;
        }
    }

    /// Pulls the dragged particle towards the pointer with a soft spring (Box2D's mouse
    /// joint): [`MOUSE_HERTZ`] and [`MOUSE_DAMPING_RATIO`], solved implicitly so it is
    /// stable at any step, and at most [`MOUSE_MAX_ACCELERATION`]. A whip of the mouse
    /// then throws a particle about as fast as the pointer moved, not hundreds of m/s.
    /// A particle joined by links pulls the whole joined mass along the same way
    /// ([`mouse_pull_joined`]): dragging a cloth's corner hard enough tears it. Its work goes into the energy budget as work put in from outside.
    pub(super) fn hold_grabbed(&mut self, dt: f32) {
        let Some(grab) = self.grab else { return };
        let world = self.scene.world_mut();
        let Some(i) = world.particles.index(grab.id) else {
            self.grab = None;
            return;
        };
        if world.particles.inverse_mass[i] == 0.0 {
            return;
        }
        // Links may have torn since the last step: what it pulls along is found again.
        let joined = self.joined.mass(world, i);
        let ratio = joined * world.particles.inverse_mass[i];
        let torn = joined < grab.pulled_mass * 0.999;
        if let Some(grab) = &mut self.grab {
            grab.pulled_mass = joined;
        }
        let world = self.scene.world_mut();
        if torn {
            // Torn from the rest: the piece in the hand moves at the hand's pace, not
            // with the pull the whole cloth was taking (which would fling it off).
            let v = &mut world.particles.velocity[i];
            *v = v.clamp_length_max(MOUSE_TORN_SPEED);
        }
        let (x, v) = (world.particles.position[i], world.particles.velocity[i]);
        world.particles.velocity[i] = v + mouse_pull_joined(grab.target - x, v, dt, ratio);
    }

    /// The particle whose sphere the ray through `pixel` hits first, if any.
    #[must_use]
    pub fn pick(&self, pixel: Vec2, viewport: Vec2) -> Option<ParticleId> {
        let (origin, direction) = self.camera.ray(pixel, viewport);
        let particles = &self.scene.world().particles;
        let mut best: Option<(f32, ParticleId)> = None;
        for (i, &id) in particles.ids().iter().enumerate() {
            if particles.inverse_mass[i] == 0.0 {
                continue; // nothing moves an immovable particle: a press there orbits
            }
            // A little larger than drawn, so small particles are easy to catch.
            let radius = particles.radius[i].max(0.05) * 1.3 + 0.05;
            let to_center = particles.position[i] - origin;
            let along = to_center.dot(direction);
            let miss = to_center.length_squared() - along * along;
            if along > 0.0 && miss <= radius * radius && best.is_none_or(|(d, _)| along < d) {
                best = Some((along, id));
            }
        }
        best.map(|(_, id)| id)
    }

    /// Starts dragging the particle under `pixel`; false if there is none.
    pub fn start_grab(&mut self, pixel: Vec2, viewport: Vec2) -> bool {
        let Some(id) = self.pick(pixel, viewport) else { return false };
        let particles = &self.scene.world().particles;
        let Some(i) = particles.index(id) else { return false };
        let point = particles.position[i];
        let normal = (self.camera.eye() - self.camera.target).normalize_or_zero();
        let pulled_mass = self.joined.mass(self.scene.world(), i);
        self.grab = Some(Grab { id, plane_point: point, plane_normal: normal, target: point, pulled_mass });
        self.select(Some(id));
        log::info!("grab: particle {}", id.0);
        true
    }

    /// Moves the drag target to where the ray through `pixel` meets the drag plane.
    /// While paused the particle goes straight there (at rest); running, the physics
    /// steps carry it.
    pub fn move_grab(&mut self, pixel: Vec2, viewport: Vec2) {
        let Some(grab) = &mut self.grab else { return };
        let (origin, direction) = self.camera.ray(pixel, viewport);
        let facing = direction.dot(grab.plane_normal);
        if facing.abs() > 1e-4 {
            let t = (grab.plane_point - origin).dot(grab.plane_normal) / facing;
            if t > 0.0 {
                grab.target = origin + direction * t;
            }
        }
        if self.paused {
            let (id, target) = (grab.id, grab.target);
            let particles = &mut self.scene.world_mut().particles;
            if let Some(i) = particles.index(id) {
                particles.position[i] = target;
                particles.velocity[i] = Vec3::ZERO;
            }
        }
    }

    /// Lets go of the dragged particle (it keeps the velocity it had).
    pub fn end_grab(&mut self) {
        self.grab = None;
    }
}

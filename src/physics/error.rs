//! Errors and the checks that make them: what a setter, `add` or a loaded file is told
//! when a value is out of its range.
//!
//! The ground floor: imports only [`ids`](super::ids).

use super::ids::ParticleId;

/// Longest step [`World::step`](super::World::step) accepts (s). A longer step is a
/// mistake (a pause measured in wall time, seconds typed as milliseconds): nothing stays
/// stable over it.
pub const MAX_TIME_STEP: f32 = 1.0;

/// Shortest step [`World::step`](super::World::step) accepts (s), a microsecond. What a
/// step measures per second (a link's tension is its impulse over `dt`) overflows
/// single precision for steps near the smallest floats: `--dt 1e-45` made every
/// tension infinite.
pub const MIN_TIME_STEP: f32 = 1e-6;

/// Whether `dt` (s) is a step the engine takes: from [`MIN_TIME_STEP`] to
/// [`MAX_TIME_STEP`].
#[must_use]
pub fn time_step_in_range(dt: f32) -> bool {
    (MIN_TIME_STEP..=MAX_TIME_STEP).contains(&dt)
}

/// Fastest a particle may be started or set moving (m/s), a third of the speed of
/// light, far past where Newton's mechanics holds: its kinetic energy, `m v² / 2` up
/// to [`MAX_MASS`](super::particles::MAX_MASS), stays finite in single precision with
/// room for sums over many particles (3e38 m/s made it infinite).
pub const MAX_SPEED: f32 = 1e8;

/// Largest constant acceleration a particle may be given (m/s²): a hundred thousand
/// times Earth's gravity, and small enough that `m a y`, its potential energy, stays
/// finite.
pub const MAX_ACCELERATION: f32 = 1e6;

/// Farthest from the origin a particle may be placed (m), on each axis; a million
/// kilometres. Its potential energy stays finite, and single precision still resolves
/// a metre there.
pub const MAX_COORDINATE: f32 = 1e9;

/// Largest radius a particle may have (m).
pub const MAX_RADIUS: f32 = 1e6;

/// Smallest radius of a sphere that rolls (m), a micrometre: its inverse moment of
/// inertia, `5 / (2 m r²)`, overflows single precision for radii near the smallest
/// floats (a sphere of radius 1e-30 saved its inertia as `null`).
pub const MIN_ROLLING_RADIUS: f32 = 1e-6;

/// A value as an error message shows it: numbers far from 1 in scientific notation
/// (`2e-39`, not thirty-eight zeros).
pub trait Shown {
    /// The value as a message shows it.
    fn shown(&self) -> String;
}

impl Shown for f32 {
    fn shown(&self) -> String {
        let x = self.abs();
        if x != 0.0 && x.is_finite() && !(1e-4..1e7).contains(&x) {
            format!("{self:e}")
        } else {
            format!("{self}")
        }
    }
}

impl Shown for usize {
    fn shown(&self) -> String {
        self.to_string()
    }
}

impl Shown for u32 {
    fn shown(&self) -> String {
        self.to_string()
    }
}

impl Shown for glam::Vec3 {
    fn shown(&self) -> String {
        format!("({}, {}, {})", self.x.shown(), self.y.shown(), self.z.shown())
    }
}

/// The error for a setting out of its range: names the field, the value and the range,
/// so a user knows what to type instead.
pub(crate) fn out_of_range(field: &str, value: impl Shown, range: &str) -> PhysicsError {
    PhysicsError::InvalidSetting(format!("{field} = {} is out of range; valid range: {range}", value.shown()))
}

/// `Ok` if `ok`, else [`out_of_range`].
pub(crate) fn check(ok: bool, field: &str, value: impl Shown, range: &str) -> Result<(), PhysicsError> {
    if ok { Ok(()) } else { Err(out_of_range(field, value, range)) }
}

/// Range text of a finite number >= 0.
pub(crate) const NON_NEGATIVE: &str = "a finite number >= 0";
/// Range text of a coefficient of restitution.
pub(crate) const UNIT: &str = "0 to 1";

/// Largest coefficient a force generator takes: a spring's or a stiff spring's k
/// (N/m), drag's k1 (N·s/m) and k2 (N·s²/m²), buoyancy's volume (m³) and density
/// (kg/m³). With every other quantity in its range, the forces and energies they make
/// stay finite in single precision (a stiff spring of k = 1e30 did not).
pub const MAX_COEFFICIENT: f32 = 1e9;
/// Range text of a force's coefficient.
pub(crate) const COEFFICIENT: &str = "0 to 1e9";
/// Range text of a length (m).
pub(crate) const LENGTH: &str = "0 to 1e9 m";
/// Range text of a point (m).
pub(crate) const POINT: &str = "a point within ±1e9 m of the origin on each axis";
/// Range text of an acceleration (m/s²).
pub(crate) const ACCELERATION: &str = "at most 1e6 m/s² (finite)";

/// A force's coefficient: finite, from 0 to [`MAX_COEFFICIENT`].
pub(crate) fn coefficient(x: f32) -> bool {
    non_negative(x) && x <= MAX_COEFFICIENT
}

/// A length: finite, from 0 to [`MAX_COORDINATE`] (m).
pub(crate) fn length(x: f32) -> bool {
    non_negative(x) && x <= MAX_COORDINATE
}

/// A point within [`MAX_COORDINATE`] of the origin on every axis (m).
pub(crate) fn point(p: glam::Vec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_COORDINATE
}

/// An acceleration no larger than [`MAX_ACCELERATION`] (m/s²).
pub(crate) fn acceleration(a: glam::Vec3) -> bool {
    a.is_finite() && a.length() <= MAX_ACCELERATION
}

/// A finite number >= 0.
pub(crate) fn non_negative(x: f32) -> bool {
    x.is_finite() && x >= 0.0
}

/// A finite number > 0.
pub(crate) fn positive(x: f32) -> bool {
    x.is_finite() && x > 0.0
}

/// What can go wrong when building or stepping a world.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    /// A particle description was rejected.
    #[error("invalid particle: {0}")]
    InvalidParticle(String),
    /// A step was asked for with a duration outside `(0, MAX_TIME_STEP]`.
    #[error("time step dt = {0} s is out of range; valid range: {min:e} to {max} s", min = MIN_TIME_STEP, max = MAX_TIME_STEP)]
    InvalidTimeStep(f32),
    /// A solver or generator setting out of its range; the message names the field.
    #[error("{0}")]
    InvalidSetting(String),
    /// An id that names no live particle.
    #[error("no particle with id {}", .0.0)]
    UnknownParticle(ParticleId),
}

//! Errors and the checks that make them: what a setter, `add` or a loaded file is told
//! when a value is out of its range.
//!
//! The ground floor: imports only [`ids`](super::ids).

use super::ids::ParticleId;

/// Longest step [`World::step`](super::World::step) accepts (s). A longer step is a
/// mistake (a pause measured in wall time, seconds typed as milliseconds): nothing stays
/// stable over it.
pub const MAX_TIME_STEP: f32 = 1.0;

/// A value as an error message shows it: numbers far from 1 in scientific notation
/// (`2e-39`, not thirty-eight zeros).
pub(crate) trait Shown {
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
/// Range text of a finite number > 0.
pub(crate) const POSITIVE: &str = "a finite number > 0";
/// Range text of a coefficient of restitution.
pub(crate) const UNIT: &str = "0 to 1";

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
    #[error("time step dt = {0} s is out of range; valid range: more than 0 and at most {max} s", max = MAX_TIME_STEP)]
    InvalidTimeStep(f32),
    /// A solver or generator setting out of its range; the message names the field.
    #[error("{0}")]
    InvalidSetting(String),
    /// An id that names no live particle.
    #[error("no particle with id {}", .0.0)]
    UnknownParticle(ParticleId),
}

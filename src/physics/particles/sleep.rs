//! A particle's sleep state: at rest with its island, not simulated until something
//! touches or moves it (the soft solver's islands put it to sleep and wake it).

use glam::Vec3;

/// `Sleep::island` of a particle that is awake.
pub(crate) const AWAKE: u32 = u32::MAX;

/// A particle's sleep state.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Sleep {
    /// How long the particle has been slower than the sleep speed (s).
    pub timer: f32,
    /// [`AWAKE`], or the label of the sleeping island it belongs to.
    pub island: u32,
    /// Where it fell asleep: moving it from outside wakes it. NaN (written `null` in a
    /// snapshot) once something outside moved it, so the next step wakes it.
    #[serde(with = "nan_as_null")]
    pub rest: Vec3,
}

impl Default for Sleep {
    fn default() -> Self {
        Self { timer: 0.0, island: AWAKE, rest: Vec3::ZERO }
    }
}

/// A sleeping particle's rest position in a snapshot: JSON has no NaN, so the "moved
/// from outside" mark is written as `null` and read back as NaN.
mod nan_as_null {
    use glam::Vec3;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(rest: &Vec3, serializer: S) -> Result<S::Ok, S::Error> {
        if rest.is_nan() { None::<Vec3>.serialize(serializer) } else { Some(*rest).serialize(serializer) }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec3, D::Error> {
        Ok(Option::<Vec3>::deserialize(deserializer)?.unwrap_or(Vec3::NAN))
    }
}

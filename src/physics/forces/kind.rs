//! The closed set of force generators the lab knows: [`Force`].
//!
//! A world holds [`Force`]s, not boxed trait objects: the snapshot codec, the energy
//! sums and the inspector tell the kinds apart by matching on the enum, never by a
//! name string. The [`ForceGenerator`] trait stays as the contract each kind fulfils
//! (and what a test calls on any of them); it is no plug-in point, since a world
//! stores only the kinds listed here.

use super::fields::{Buoyancy, Drag, Gravity};
use super::generator::ForceGenerator;
use super::spring::Spring;
use super::stiff_spring::StiffSpring;

/// A force generator of one of the kinds the lab knows.
#[derive(Clone, Debug)]
pub enum Force {
    /// [`Gravity`] on a list of particles.
    Gravity(Gravity),
    /// [`Drag`] on a list of particles.
    Drag(Drag),
    /// A [`Spring`] or bungee.
    Spring(Spring),
    /// [`Buoyancy`] on one particle.
    Buoyancy(Buoyancy),
    /// A closed-form [`StiffSpring`].
    StiffSpring(StiffSpring),
}

impl Force {
    /// The generator's behaviour, whatever its kind.
    #[must_use]
    pub fn generator(&self) -> &dyn ForceGenerator {
        match self {
            Self::Gravity(g) => g,
            Self::Drag(g) => g,
            Self::Spring(g) => g,
            Self::Buoyancy(g) => g,
            Self::StiffSpring(g) => g,
        }
    }

    /// The generator's behaviour, whatever its kind, to apply it.
    pub fn generator_mut(&mut self) -> &mut dyn ForceGenerator {
        match self {
            Self::Gravity(g) => g,
            Self::Drag(g) => g,
            Self::Spring(g) => g,
            Self::Buoyancy(g) => g,
            Self::StiffSpring(g) => g,
        }
    }

    /// Whether this is a gravity field, whose stored energy the budget counts as
    /// gravitational rather than elastic.
    #[must_use]
    pub fn is_gravity(&self) -> bool {
        matches!(self, Self::Gravity(_))
    }
}

impl From<Gravity> for Force {
    fn from(g: Gravity) -> Self {
        Self::Gravity(g)
    }
}

impl From<Drag> for Force {
    fn from(g: Drag) -> Self {
        Self::Drag(g)
    }
}

impl From<Spring> for Force {
    fn from(g: Spring) -> Self {
        Self::Spring(g)
    }
}

impl From<Buoyancy> for Force {
    fn from(g: Buoyancy) -> Self {
        Self::Buoyancy(g)
    }
}

impl From<StiffSpring> for Force {
    fn from(g: StiffSpring) -> Self {
        Self::StiffSpring(g)
    }
}

/// A boxed kind, as [`ForceRegistry::add`](super::ForceRegistry::add) and `replace`
/// took generators before the kinds became an enum: unboxed.
impl<T: Into<Force>> From<Box<T>> for Force {
    fn from(boxed: Box<T>) -> Self {
        (*boxed).into()
    }
}

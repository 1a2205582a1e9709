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

/// For each kind (the variant is named as its generator's type): the generator behind
/// a [`Force`], and a generator into its [`Force`].
macro_rules! force_kinds {
    ($($kind:ident),* $(,)?) => {
        impl Force {
            /// The generator's behaviour, whatever its kind.
            #[must_use]
            pub fn generator(&self) -> &dyn ForceGenerator {
                match self {
                    $(Self::$kind(g) => g,)*
                }
            }

            /// The generator's behaviour, whatever its kind, to apply it.
            pub fn generator_mut(&mut self) -> &mut dyn ForceGenerator {
                match self {
                    $(Self::$kind(g) => g,)*
                }
            }
        }

        $(
            impl From<$kind> for Force {
                fn from(g: $kind) -> Self {
                    Self::$kind(g)
                }
            }
        )*
    };
}

force_kinds!(Gravity, Drag, Spring, Buoyancy, StiffSpring);

impl Force {
    /// Whether this is a gravity field, whose stored energy the budget counts as
    /// gravitational rather than elastic.
    #[must_use]
    pub fn is_gravity(&self) -> bool {
        matches!(self, Self::Gravity(_))
    }
}

/// A boxed kind, as [`ForceRegistry::add`](super::ForceRegistry::add) and `replace`
/// took generators before the kinds became an enum: unboxed.
impl<T: Into<Force>> From<Box<T>> for Force {
    fn from(boxed: Box<T>) -> Self {
        (*boxed).into()
    }
}

//! Scene parameter tables and validated values.

use std::borrow::Cow;
use std::fmt;
use std::ops::Deref;
use std::sync::Arc;

use crate::messages::quote;

/// One tunable parameter of a scene. The same entry drives a slider, a `--set` flag
/// and validation. A compiled scene's texts are borrowed from the binary; a scene
/// file's are its own, freed with the file.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// Key, as typed after `--set` and shown on the slider.
    pub name: Cow<'static, str>,
    /// Unit shown next to the value ("" for dimensionless).
    pub unit: Cow<'static, str>,
    /// Value at start.
    pub default: f32,
    /// Smallest accepted value.
    pub min: f32,
    /// Largest accepted value.
    pub max: f32,
    /// One line saying what it means.
    pub help: Cow<'static, str>,
    /// True when a slider should move on a logarithmic scale.
    pub logarithmic: bool,
    /// True for a count (balls, links): the slider moves in whole numbers and shows
    /// no decimals; the scene rounds a value typed between them.
    pub integer: bool,
}

/// A named set of parameter values, such as an ammo type.
#[derive(Clone, Copy, Debug)]
pub struct Preset {
    /// Name shown on the button.
    pub name: &'static str,
    /// One line about it.
    pub help: &'static str,
    /// Values it sets; parameters not listed keep their value.
    pub values: &'static [(&'static str, f32)],
}

/// Why a parameter value was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamError {
    /// No parameter has that name.
    UnknownKey {
        /// What was typed.
        key: String,
        /// The valid names.
        valid: Vec<String>,
    },
    /// The value is not a finite number.
    NotANumber {
        /// The parameter.
        key: String,
        /// What was typed.
        text: String,
    },
    /// The value is outside the parameter's range.
    OutOfRange {
        /// The parameter.
        key: String,
        /// The value given.
        value: f32,
        /// Smallest accepted.
        min: f32,
        /// Largest accepted.
        max: f32,
        /// Unit of the range.
        unit: String,
    },
    /// A whole-number parameter (a count, a 0/1 switch) given a fraction.
    NotWhole {
        /// The parameter.
        key: String,
        /// The value given.
        value: f32,
    },
    /// Not of the form KEY=VALUE.
    Malformed(String),
    /// The value is in range, but the scene cannot be built with it (a scene file
    /// whose expressions give, say, a negative mass at that value).
    Rejected {
        /// The parameter.
        key: String,
        /// Why, naming the place in the file.
        reason: String,
    },
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownKey { key, valid } => {
                write!(f, "unknown parameter '{}'; valid parameters: {}", quote(key), valid.join(", "))
            }
            Self::NotANumber { key, text } => {
                write!(f, "value '{}' for '{}' is not a finite number", quote(text), quote(key))
            }
            Self::OutOfRange { key, value, min, max, unit } => {
                let unit = if unit.is_empty() { String::new() } else { format!(" {unit}") };
                write!(f, "'{key}' = {value} is out of range; valid range: {min} to {max}{unit}")
            }
            Self::NotWhole { key, value } => {
                write!(f, "'{key}' = {value} is not a whole number, and '{key}' takes only whole numbers")
            }
            Self::Malformed(text) => {
                write!(f, "'{}' is not of the form KEY=VALUE (for example g=9.81)", quote(text))
            }
            Self::Rejected { key, reason } => write!(f, "'{key}' cannot take that value: {reason}"),
        }
    }
}

impl std::error::Error for ParamError {}

/// A scene's parameter table: a compiled scene's, in the binary, or the one a scene
/// file declared, which its description and every set of values made from it share
/// (a clone is a pointer; the table goes with the last of them).
#[derive(Clone, Debug)]
pub enum ParamTable {
    /// A compiled scene's.
    Static(&'static [Param]),
    /// A scene file's.
    Shared(Arc<[Param]>),
}

impl Deref for ParamTable {
    type Target = [Param];

    fn deref(&self) -> &[Param] {
        match self {
            Self::Static(table) => table,
            Self::Shared(table) => table,
        }
    }
}

impl PartialEq for ParamTable {
    /// Tables are equal when their parameters are, wherever they are kept.
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

/// Values for every parameter of one table, always within range.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamValues {
    table: ParamTable,
    values: Vec<f32>,
}

impl ParamValues {
    /// Every parameter at its default.
    #[must_use]
    pub fn defaults(table: &ParamTable) -> Self {
        Self { table: table.clone(), values: table.iter().map(|p| p.default).collect() }
    }

    /// The table these values belong to.
    #[must_use]
    pub fn table(&self) -> &[Param] {
        &self.table
    }

    /// The value of a declared parameter.
    ///
    /// # Panics
    /// If `name` is not in the table: that is a bug in the scene, not user input.
    #[must_use]
    pub fn get(&self, name: &str) -> f32 {
        let index = self.position(name).unwrap_or_else(|| panic!("scene declares no parameter '{name}'"));
        self.values[index]
    }

    /// Sets a parameter after checking its name and range.
    pub fn set(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        let index = self.position(name).ok_or_else(|| self.unknown(name))?;
        let param = &self.table[index];
        if !value.is_finite() {
            return Err(ParamError::NotANumber { key: name.to_string(), text: value.to_string() });
        }
        if value < param.min || value > param.max {
            return Err(ParamError::OutOfRange {
                key: param.name.to_string(),
                value,
                min: param.min,
                max: param.max,
                unit: param.unit.to_string(),
            });
        }
        if param.integer && value.fract() != 0.0 {
            return Err(ParamError::NotWhole { key: param.name.to_string(), value });
        }
        self.values[index] = value;
        Ok(())
    }

    /// Parses and applies `KEY=VALUE`.
    pub fn assign(&mut self, assignment: &str) -> Result<(), ParamError> {
        let Some((key, text)) = assignment.split_once('=') else {
            return Err(ParamError::Malformed(assignment.to_string()));
        };
        let (key, text) = (key.trim(), text.trim());
        if self.position(key).is_none() {
            return Err(self.unknown(key));
        }
        let value: f32 = text
            .parse()
            .ok()
            .filter(|v: &f32| v.is_finite())
            .ok_or_else(|| ParamError::NotANumber { key: key.to_string(), text: text.to_string() })?;
        self.set(key, value)
    }

    /// Pairs of (parameter, value) in table order.
    pub fn iter(&self) -> impl Iterator<Item = (&Param, f32)> {
        self.table.iter().zip(self.values.iter().copied())
    }

    fn unknown(&self, key: &str) -> ParamError {
        ParamError::UnknownKey {
            key: key.to_string(),
            valid: self.table.iter().map(|p| p.name.to_string()).collect(),
        }
    }

    fn position(&self, name: &str) -> Option<usize> {
        self.table.iter().position(|p| p.name == name)
    }
}

//! Scene parameter tables and validated values.

use std::fmt;

use crate::messages::quote;

/// One tunable parameter of a scene. The same entry drives a slider, a `--set` flag
/// and validation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    /// Key, as typed after `--set` and shown on the slider.
    pub name: &'static str,
    /// Unit shown next to the value ("" for dimensionless).
    pub unit: &'static str,
    /// Value at start.
    pub default: f32,
    /// Smallest accepted value.
    pub min: f32,
    /// Largest accepted value.
    pub max: f32,
    /// One line saying what it means.
    pub help: &'static str,
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
        valid: Vec<&'static str>,
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
        key: &'static str,
        /// The value given.
        value: f32,
        /// Smallest accepted.
        min: f32,
        /// Largest accepted.
        max: f32,
        /// Unit of the range.
        unit: &'static str,
    },
    /// A whole-number parameter (a count, a 0/1 switch) given a fraction.
    NotWhole {
        /// The parameter.
        key: &'static str,
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

/// Values for every parameter of one table, always within range.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamValues {
    table: &'static [Param],
    values: Vec<f32>,
}

impl ParamValues {
    /// Every parameter at its default.
    #[must_use]
    pub fn defaults(table: &'static [Param]) -> Self {
        Self { table, values: table.iter().map(|p| p.default).collect() }
    }

    /// The table these values belong to.
    #[must_use]
    pub fn table(&self) -> &'static [Param] {
        self.table
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
                key: param.name,
                value,
                min: param.min,
                max: param.max,
                unit: param.unit,
            });
        }
        if param.integer && value.fract() != 0.0 {
            return Err(ParamError::NotWhole { key: param.name, value });
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
    pub fn iter(&self) -> impl Iterator<Item = (&'static Param, f32)> + '_ {
        self.table.iter().zip(self.values.iter().copied())
    }

    fn unknown(&self, key: &str) -> ParamError {
        ParamError::UnknownKey { key: key.to_string(), valid: self.table.iter().map(|p| p.name).collect() }
    }

    fn position(&self, name: &str) -> Option<usize> {
        self.table.iter().position(|p| p.name == name)
    }
}

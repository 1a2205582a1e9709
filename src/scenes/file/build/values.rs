//! Values: compiling a file's numbers and expressions, evaluating them against the
//! parameters and bounds, counts and names.

use glam::Vec3;

use super::{ANY, Bounds, Builder, Located, MAX_PARTICLES, Value};
use crate::messages::clip;
use crate::scenes::file::expr::Expr;
use crate::scenes::file::format::{Document, Num, SNum, SVec};
use crate::scenes::file::number;

impl Builder<'_> {
    pub(super) fn gravity(&mut self, doc: &Document) -> Result<f32, Located> {
        match &doc.scene.gravity {
            Some(field) => {
                let value = self.compile(field, &[])?;
                self.eval(&value, &[], "gravity", ANY)
            }
            None => Ok(self.g_index.map_or(0.0, |k| self.values[k] as f32)),
        }
    }

    /// Parses a value with the given locals (`i`, `j`) visible after the parameters.
    pub(super) fn compile(&mut self, field: &SNum, locals: &[&'static str]) -> Result<Value, Located> {
        let span = field.span();
        let expr = match field.get_ref() {
            Num::Value(x) => Expr::Number(*x),
            Num::Text(text) => {
                self.names.truncate(self.params);
                self.names.extend_from_slice(locals);
                Expr::parse(text, &self.names).map_err(|error| {
                    // Point inside the quotes when the text is written as it reads.
                    let written = self.source.get(span.clone()).unwrap_or("");
                    let inner = written.len() == text.len() + 2
                        && written.get(1..written.len() - 1) == Some(text.as_str());
                    let offset = if inner { span.start + 1 + error.offset } else { span.start };
                    let message = format!("in the expression \"{}\": {}", clip(text, 32), error.message);
                    Located { offset, message }
                })?
            }
        };
        if let Some(g) = self.g_index {
            self.g_elsewhere |= expr.uses(g);
        }
        Ok(Value { expr, span })
    }

    pub(super) fn compile_or(
        &mut self,
        field: Option<&SNum>,
        default: f64,
        locals: &[&'static str],
    ) -> Result<Value, Located> {
        match field {
            Some(field) => self.compile(field, locals),
            None => Ok(Value { expr: Expr::Number(default), span: 0..0 }),
        }
    }

    pub(super) fn compile_vec(
        &mut self,
        field: &SVec,
        locals: &[&'static str],
    ) -> Result<[Value; 3], Located> {
        let items = field.get_ref();
        if items.len() != 3 {
            return Err(Located::at(
                &field.span(),
                format!("expected three values [x, y, z], found {}", items.len()),
            ));
        }
        Ok([
            self.compile(&items[0], locals)?,
            self.compile(&items[1], locals)?,
            self.compile(&items[2], locals)?,
        ])
    }

    pub(super) fn compile_vec_or(
        &mut self,
        field: Option<&SVec>,
        default: Vec3,
        locals: &[&'static str],
    ) -> Result<[Value; 3], Located> {
        match field {
            Some(field) => self.compile_vec(field, locals),
            None => Ok(default.to_array().map(|x| Value { expr: Expr::Number(f64::from(x)), span: 0..0 })),
        }
    }

    /// Evaluates with the locals' values, checking the result against `bounds`.
    pub(super) fn eval(
        &mut self,
        value: &Value,
        locals: &[f64],
        what: &str,
        bounds: Bounds,
    ) -> Result<f32, Located> {
        self.values.truncate(self.params);
        self.values.extend_from_slice(locals);
        let x = value.expr.eval(&self.values);
        let single = x as f32;
        if !x.is_finite() {
            return Err(Located::at(&value.span, format!("{what} is {x}, not a finite number")));
        }
        if !single.is_finite() {
            return Err(Located::at(
                &value.span,
                format!(
                    "{what} = {} is too large: beyond ±3.4e38, the range of a single-precision number",
                    number(x)
                ),
            ));
        }
        if x < bounds.min || x > bounds.max {
            // The single-precision value where it reads the same, so 0.1 is not 0.100000001.
            let shown = if number(x).contains('e') { number(x) } else { single.to_string() };
            return Err(Located::at(
                &value.span,
                format!("{what} = {shown} is out of range; valid range: {}", bounds.text),
            ));
        }
        Ok(single)
    }

    pub(super) fn eval_vec(
        &mut self,
        value: &[Value; 3],
        locals: &[f64],
        what: &str,
    ) -> Result<Vec3, Located> {
        Ok(Vec3::new(
            self.eval(&value[0], locals, what, ANY)?,
            self.eval(&value[1], locals, what, ANY)?,
            self.eval(&value[2], locals, what, ANY)?,
        ))
    }

    /// A count: rounded, at least 1, and within what the scene may still add.
    pub(super) fn count(&mut self, field: &SNum, what: &str) -> Result<usize, Located> {
        let value = self.compile(field, &[])?;
        let x = self.eval(&value, &[], what, ANY)?;
        let x = whole(x, what, &value)?;
        let room = MAX_PARTICLES - self.ids.len();
        if x < 1.0 || x > room as f32 {
            return Err(Located::at(
                &value.span,
                format!(
                    "{what} = {} is out of range; valid range: 1 to {room} (a scene file makes at most \
                     {MAX_PARTICLES} particles)",
                    number(f64::from(x))
                ),
            ));
        }
        Ok(x as usize)
    }

    pub(super) fn name<'f>(
        &self,
        field: Option<&'f toml::Spanned<String>>,
    ) -> Result<Option<&'f str>, Located> {
        let Some(field) = field else { return Ok(None) };
        let name = field.get_ref().as_str();
        let valid = !name.is_empty()
            && name.chars().all(|c| c.is_alphanumeric() || c == '_')
            && !name.starts_with(|c: char| c.is_ascii_digit());
        if !valid {
            return Err(Located::at(
                &field.span(),
                format!("'{}' is not a name: use letters, digits and _", clip(name, 40)),
            ));
        }
        if self.named.contains_key(name) {
            return Err(Located::at(
                &field.span(),
                format!("the name '{}' is already taken", clip(name, 40)),
            ));
        }
        Ok(Some(name))
    }
}

/// Most a count or an index may miss a whole number by and still count as it: an
/// expression such as `"0.3 * 10"` lands a rounding error away from 3.
const WHOLE_TOLERANCE: f32 = 1e-3;

/// `x`, a count or an index, as the whole number it must be; `count = 2.5` is refused
/// rather than rounded, since neither 2 nor 3 is what the file said.
pub(super) fn whole(x: f32, what: &str, value: &Value) -> Result<f32, Located> {
    let rounded = x.round();
    if (x - rounded).abs() > WHOLE_TOLERANCE {
        return Err(Located::at(
            &value.span,
            format!("{what} = {} is not a whole number, and {what} must be one", number(f64::from(x))),
        ));
    }
    Ok(rounded)
}

//! Particles: single ones, rows and grids, each group findable by its name.

use std::ops::Range;

use glam::Vec3;

use super::{
    ANY, Builder, Group, KINDS, Kind, Located, MASS, MAX_PARTICLES, NON_NEGATIVE, Placement, UNIT, size,
};
use crate::messages::clip;
use crate::physics::ParticleDesc;
use crate::scenes::file::format::{Document, SNum};

impl<'a> Builder<'a> {
    /// Adds a group of particles, findable by its name from now on.
    pub(super) fn push_group(&mut self, group: Group<'a>) {
        if let Some(name) = group.name {
            self.named.insert(name, self.groups.len());
        }
        self.groups.push(group);
    }

    pub(super) fn add(
        &mut self,
        desc: ParticleDesc,
        rolls: bool,
        span: &Range<usize>,
    ) -> Result<(), Located> {
        let id = self.world.add_particle(desc).map_err(|e| Located::at(span, e.to_string()))?;
        if rolls {
            self.world.particles.set_rolling(id, true).map_err(|e| {
                let reason = match e {
                    crate::physics::PhysicsError::InvalidParticle(reason) => reason,
                    other => other.to_string(),
                };
                Located::at(span, format!("rolls = true cannot be: {reason}"))
            })?;
        }
        self.ids.push(id);
        Ok(())
    }

    pub(super) fn particles(&mut self, doc: &'a Document) -> Result<(), Located> {
        for table in &doc.particle {
            let span = table.span();
            let t = table.get_ref();
            let name = self.name(t.name.as_ref())?;
            if self.ids.len() >= MAX_PARTICLES {
                return Err(Located::at(
                    &span,
                    format!("a scene file makes at most {MAX_PARTICLES} particles"),
                ));
            }
            let position = self.compile_vec(&t.position, &[])?;
            let velocity = self.compile_vec_or(t.velocity.as_ref(), Vec3::ZERO, &[])?;
            let mass = self.compile_or(t.mass.as_ref(), 1.0, &[])?;
            let radius = self.compile_or(t.radius.as_ref(), 0.1, &[])?;
            let damping = self.compile_or(t.damping.as_ref(), 1.0, &[])?;
            let desc = ParticleDesc {
                position: self.eval_vec(&position, &[], "position")?,
                velocity: self.eval_vec(&velocity, &[], "velocity")?,
                acceleration: self.gravity,
                mass: self.eval(&mass, &[], "mass", MASS)?,
                immovable: t.fixed,
                damping: self.eval(&damping, &[], "damping", UNIT)?,
                radius: self.eval(&radius, &[], "radius", NON_NEGATIVE)?,
            };
            let color = t.color.as_ref().map(parse_color).transpose()?;
            self.push_group(Group { name, single: true, first: self.ids.len(), rows: 1, cols: 1 });
            self.add(desc, t.rolls, &span)?;
            if let (Some(color), Some(&id)) = (color, self.ids.last()) {
                self.colors.push((id, color));
            }
        }
        Ok(())
    }

    /// The kind a group's `link` names.
    pub(super) fn kind(field: &toml::Spanned<String>) -> Result<Kind, Located> {
        let text = field.get_ref().as_str();
        KINDS.iter().find(|(name, _)| *name == text).map(|&(_, kind)| kind).ok_or_else(|| {
            let valid: Vec<&str> = KINDS.iter().map(|(n, _)| *n).collect();
            Located::at(
                &field.span(),
                format!("unknown link kind '{}'; valid kinds: {}", clip(text, 40), valid.join(", ")),
            )
        })
    }

    /// An index into `0..len`, negative counting from the end.
    pub(super) fn index(&mut self, field: &SNum, len: usize, what: &str) -> Result<usize, Located> {
        let value = self.compile(field, &[])?;
        let x = super::values::whole(self.eval(&value, &[], what, ANY)?, what, &value)? as i64;
        let len_i = len as i64;
        let index = if x < 0 { x + len_i } else { x };
        if !(0..len_i).contains(&index) {
            return Err(Located::at(
                &value.span,
                format!("{what} {x} is out of range: there are {len} (0 to {}, or -1 for the last)", len - 1),
            ));
        }
        Ok(index as usize)
    }

    pub(super) fn rows(&mut self, doc: &'a Document) -> Result<(), Located> {
        const I: &[&str] = &["i"];
        for table in &doc.row {
            let span = table.span();
            let t = table.get_ref();
            let name = self.name(t.name.as_ref())?;
            let count = self.count(&t.count, "count")?;
            let place = match (&t.position, &t.start) {
                (Some(position), _) => Placement::Formula(self.compile_vec(position, I)?),
                (None, Some(start)) => Placement::Steps(
                    self.compile_vec(start, &[])?,
                    self.compile_vec_or(t.step.as_ref(), Vec3::X, &[])?,
                    None,
                ),
                (None, None) => {
                    return Err(Located::at(&span, "a row needs `start` (and `step`), or `position` with i"));
                }
            };
            let velocity = self.compile_vec_or(t.velocity.as_ref(), Vec3::ZERO, I)?;
            let mass = self.compile_or(t.mass.as_ref(), 1.0, I)?;
            let radius = self.compile_or(t.radius.as_ref(), 0.1, I)?;
            let damping = self.compile_or(t.damping.as_ref(), 1.0, I)?;
            let each =
                place.size() + size(&velocity) + mass.expr.size() + radius.expr.size() + damping.expr.size();
            self.spend_evaluations(each, count, "[[row]]", &span)?;
            let mut pinned = vec![t.fixed; count];
            for pin in &t.pin {
                let k = self.index(pin, count, "pin")?;
                pinned[k] = true;
            }
            let first = self.ids.len();
            let steps = place.evaluate(self)?;
            for (i, &fixed) in pinned.iter().enumerate() {
                let local = [i as f64];
                let position = place.at(self, &steps, &local, i as f32, 0.0)?;
                let desc = ParticleDesc {
                    position,
                    velocity: self.eval_vec(&velocity, &local, "velocity")?,
                    acceleration: self.gravity,
                    mass: self.eval(&mass, &local, "mass", MASS)?,
                    immovable: fixed,
                    damping: self.eval(&damping, &local, "damping", UNIT)?,
                    radius: self.eval(&radius, &local, "radius", NON_NEGATIVE)?,
                };
                self.add(desc, t.rolls, &span)?;
            }
            self.push_group(Group { name, single: false, first, rows: 1, cols: count });
            if let Some(kind) = &t.link {
                let kind = Self::kind(kind)?;
                let mut pairs: Vec<(usize, usize)> = (1..count).map(|k| (k - 1, k)).collect();
                if t.closed && count > 2 {
                    pairs.push((count - 1, 0));
                }
                self.group_links(kind, t.props(), first, &pairs, &span)?;
            }
        }
        Ok(())
    }

    pub(super) fn grids(&mut self, doc: &'a Document) -> Result<(), Located> {
        const IJ: &[&str] = &["i", "j"];
        for table in &doc.grid {
            let span = table.span();
            let t = table.get_ref();
            let name = self.name(t.name.as_ref())?;
            let rows = self.count(&t.rows, "rows")?;
            let cols = self.count(&t.cols, "cols")?;
            if rows * cols > MAX_PARTICLES - self.ids.len() {
                return Err(Located::at(
                    &t.cols.span(),
                    format!(
                        "{rows} rows of {cols} make {} particles; a scene file makes at most {MAX_PARTICLES}",
                        rows * cols
                    ),
                ));
            }
            let place = match &t.position {
                Some(position) => Placement::Formula(self.compile_vec(position, IJ)?),
                None => Placement::Steps(
                    self.compile_vec_or(t.origin.as_ref(), Vec3::ZERO, &[])?,
                    self.compile_vec_or(t.step_col.as_ref(), Vec3::X, &[])?,
                    Some(self.compile_vec_or(t.step_row.as_ref(), Vec3::Z, &[])?),
                ),
            };
            let velocity = self.compile_vec_or(t.velocity.as_ref(), Vec3::ZERO, IJ)?;
            let mass = self.compile_or(t.mass.as_ref(), 1.0, IJ)?;
            let radius = self.compile_or(t.radius.as_ref(), 0.1, IJ)?;
            let damping = self.compile_or(t.damping.as_ref(), 1.0, IJ)?;
            let each =
                place.size() + size(&velocity) + mass.expr.size() + radius.expr.size() + damping.expr.size();
            self.spend_evaluations(each, rows * cols, "[[grid]]", &span)?;
            let mut pinned = vec![t.fixed; rows * cols];
            for pin in &t.pin {
                let pair = pin.get_ref();
                if pair.len() != 2 {
                    return Err(Located::at(
                        &pin.span(),
                        format!("expected [row, col], found {} values", pair.len()),
                    ));
                }
                let i = self.index(&pair[0], rows, "pinned row")?;
                let j = self.index(&pair[1], cols, "pinned column")?;
                pinned[i * cols + j] = true;
            }
            let first = self.ids.len();
            let steps = place.evaluate(self)?;
            for i in 0..rows {
                for j in 0..cols {
                    let local = [i as f64, j as f64];
                    let position = place.at(self, &steps, &local, j as f32, i as f32)?;
                    let desc = ParticleDesc {
                        position,
                        velocity: self.eval_vec(&velocity, &local, "velocity")?,
                        acceleration: self.gravity,
                        mass: self.eval(&mass, &local, "mass", MASS)?,
                        immovable: pinned[i * cols + j],
                        damping: self.eval(&damping, &local, "damping", UNIT)?,
                        radius: self.eval(&radius, &local, "radius", NON_NEGATIVE)?,
                    };
                    self.add(desc, t.rolls, &span)?;
                }
            }
            self.push_group(Group { name, single: false, first, rows, cols });
            if let Some(kind) = &t.link {
                let kind = Self::kind(kind)?;
                let at = |i: usize, j: usize| i * cols + j;
                let mut pairs = Vec::new();
                for i in 0..rows {
                    for j in 0..cols {
                        if j + 1 < cols {
                            pairs.push((at(i, j), at(i, j + 1)));
                        }
                        if i + 1 < rows {
                            pairs.push((at(i, j), at(i + 1, j)));
                        }
                        if t.shear && i + 1 < rows && j + 1 < cols {
                            pairs.push((at(i, j), at(i + 1, j + 1)));
                            pairs.push((at(i, j + 1), at(i + 1, j)));
                        }
                    }
                }
                self.group_links(kind, t.props(), first, &pairs, &span)?;
            }
        }
        Ok(())
    }
}

/// A colour written `"#rrggbb"` (hexadecimal red, green, blue), as the view's 0–1
/// components.
fn parse_color(field: &toml::Spanned<String>) -> Result<[f32; 3], Located> {
    let text = field.get_ref().trim();
    let hex = text.strip_prefix('#').filter(|h| h.len() == 6 && h.chars().all(|c| c.is_ascii_hexdigit()));
    let Some(hex) = hex else {
        return Err(Located::at(
            &field.span(),
            format!("color '{}' is not a colour; write it \"#rrggbb\", e.g. \"#e07020\"", clip(text, 20)),
        ));
    };
    let channel =
        |k: usize| f32::from(u8::from_str_radix(&hex[k..k + 2], 16).expect("checked hexadecimal")) / 255.0;
    Ok([channel(0), channel(2), channel(4)])
}

//! Building a world from a parsed scene file and a set of parameter values.
//!
//! Every value is checked where it is read, so that an error points at the value in the
//! file (a byte span, turned into a line and column by the caller), not at whatever the
//! physics would later refuse.

use std::collections::HashMap;
use std::ops::Range;

use glam::{Vec2, Vec3, Vec3Swizzles};

use super::expr::Expr;
use super::format::{Document, LinkProps, Num, Ref, SNum, SVec};
use super::{clip, list, number};
use crate::physics::particles::{MAX_MASS, MIN_MASS};
use crate::physics::{
    Buoyancy, Constraint, ContactGeneratorId, Drag, ForceGenerator, ForceId, LinkEnd, LinkSpec, ParticleDesc,
    ParticleId, Plane, SphereCollisions, Spring, StiffSpring, World,
};
use crate::scenes::{CameraHint, ParamValues, Water};

/// Most particles one scene file may make.
pub const MAX_PARTICLES: usize = 200_000;
/// Most links one scene file may make.
pub const MAX_LINKS: usize = 1_000_000;
/// Most applications a step of the generators that act on many particles one scene file
/// may ask for: each drag and buoyancy counts one per particle it acts on (links have
/// their own limit, [`MAX_LINKS`]). The whole of a 200,000-particle row under five
/// drags. It bounds the memory of the targets and the work of a step: a drag
/// application costs about half a microsecond to one (its exact step), so this is up to
/// about a second a step on a busy two-core machine.
pub const MAX_APPLICATIONS: usize = 1_000_000;
/// Most terms of expressions one build may evaluate for the members of rows and grids
/// (an expression of a thousand terms for each of 200,000 particles would be 200
/// million, seconds of work from a few kilobytes): about a tenth of a second.
pub const MAX_EVALUATIONS: usize = 50_000_000;

/// An error at a byte range of the file.
#[derive(Clone, Debug, PartialEq)]
pub struct Located {
    /// Byte offset of the offending value in the file.
    pub offset: usize,
    /// What is wrong and what was expected.
    pub message: String,
}

impl Located {
    pub(super) fn at(span: &Range<usize>, message: impl Into<String>) -> Self {
        Self { offset: span.start, message: message.into() }
    }
}

/// How a link is held by the world, to remove it when it tears.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Handle {
    /// A spring, bungee or stiff spring in the force registry.
    Force(ForceId),
    /// A rod or cable among the contact generators.
    Contact(ContactGeneratorId),
}

/// A link the scene made, in the order [`World::links`] reports them.
#[derive(Clone, Copy, Debug)]
pub struct LinkRecord {
    /// Where the world holds it.
    pub handle: Handle,
    /// Its declaration, to check that a link state is this link.
    pub spec: LinkSpec,
    /// Tension at which it breaks (N), if it can.
    pub tear: Option<f32>,
}

/// A world built from a file, with what the scene needs to run it.
pub struct Built {
    /// The world.
    pub world: World,
    /// Every link, forces first, then rods and cables, as `World::links` lists them.
    pub links: Vec<LinkRecord>,
    /// Named particles and arrays, with the particle to write the name at.
    pub labels: Vec<(ParticleId, &'static str)>,
    /// The starting camera.
    pub camera: CameraHint,
    /// Buoyancy generators, to give them a new `g`.
    pub floats: Vec<(ForceId, Buoyancy)>,
    /// The liquid to draw, where there is buoyancy.
    pub water: Option<Water>,
    /// Whether `g` appears in an expression other than `[scene] gravity` (a change of `g`
    /// then needs a rebuild).
    pub g_elsewhere: bool,
}

/// A value ready to evaluate: its expression and where it is in the file.
struct Value {
    expr: Expr,
    span: Range<usize>,
}

/// A closed range a value must fall in, with the text the error shows.
#[derive(Clone, Copy)]
struct Bounds {
    min: f64,
    max: f64,
    text: &'static str,
}

const ANY: Bounds = Bounds { min: f64::MIN, max: f64::MAX, text: "a finite number" };
const NON_NEGATIVE: Bounds = Bounds { min: 0.0, max: f64::MAX, text: "a finite number >= 0" };
const POSITIVE: Bounds = Bounds { min: f64::MIN_POSITIVE, max: f64::MAX, text: "a finite number > 0" };
const UNIT: Bounds = Bounds { min: 0.0, max: 1.0, text: "0 to 1" };
const MASS: Bounds = Bounds { min: MIN_MASS as f64, max: MAX_MASS as f64, text: "1e-9 to 1e12 kg" };

/// The particles of one `[[particle]]`, `[[row]]` or `[[grid]]`.
struct Group {
    name: Option<&'static str>,
    /// A `[[particle]]`, not an array (even of one).
    single: bool,
    first: usize,
    rows: usize,
    cols: usize,
}

/// A link to make once every particle exists.
struct LinkPlan {
    kind: Kind,
    a: usize,
    b: End,
    length: Option<f32>,
    k: f32,
    restitution: f32,
    damping_ratio: f32,
    tear: Option<f32>,
    span: Range<usize>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Rod,
    Cable,
    Spring,
    Bungee,
    StiffSpring,
}

const KINDS: &[(&str, Kind)] = &[
    ("rod", Kind::Rod),
    ("cable", Kind::Cable),
    ("spring", Kind::Spring),
    ("bungee", Kind::Bungee),
    ("stiff_spring", Kind::StiffSpring),
];

#[derive(Clone, Copy)]
enum End {
    Particle(usize),
    Anchor(Vec3),
}

struct Builder<'a> {
    source: &'a str,
    /// Parameter names, then the locals of the value being read (`i`, `j`).
    names: Vec<&'a str>,
    /// Parameter values, then locals.
    values: Vec<f64>,
    params: usize,
    g_index: Option<usize>,
    g_elsewhere: bool,
    world: World,
    gravity: Vec3,
    ids: Vec<ParticleId>,
    groups: Vec<Group>,
    /// Each named group's index in `groups`.
    named: HashMap<&'static str, usize>,
    plans: Vec<LinkPlan>,
    /// Terms evaluated for the members of rows and grids so far, against
    /// [`MAX_EVALUATIONS`].
    evaluations: usize,
}

fn builder<'a>(source: &'a str, params: &'a ParamValues) -> Builder<'a> {
    let names: Vec<&str> = params.iter().map(|(p, _)| p.name).collect();
    let values: Vec<f64> = params.iter().map(|(_, v)| f64::from(v)).collect();
    let g_index = names.iter().position(|n| *n == "g");
    Builder {
        source,
        params: names.len(),
        names,
        values,
        g_index,
        g_elsewhere: false,
        world: World::new(),
        gravity: Vec3::ZERO,
        ids: Vec::new(),
        groups: Vec::new(),
        named: HashMap::new(),
        plans: Vec::new(),
        evaluations: 0,
    }
}

/// The downward acceleration `[scene] gravity` gives with these values (m/s²).
pub fn gravity(doc: &'static Document, source: &str, params: &ParamValues) -> Result<f32, Located> {
    builder(source, params).gravity(doc)
}

/// Builds the world the document describes with these parameter values.
pub fn build(doc: &'static Document, source: &str, params: &ParamValues) -> Result<Built, Located> {
    let mut b = builder(source, params);
    let g = b.gravity(doc)?;
    // The gravity expression is applied at once on a change of g: not a use elsewhere.
    b.g_elsewhere = false;
    b.gravity = Vec3::new(0.0, -g, 0.0);
    b.particles(doc)?;
    b.rows(doc)?;
    b.grids(doc)?;
    b.links(doc)?;
    // Springs first, then drag, buoyancy and stiff springs: drag and a stiff spring each
    // solve their step with the forces registered before them.
    let plans = std::mem::take(&mut b.plans);
    let (mut links, contacts) = b.make_links(plans.iter().filter(|p| p.kind != Kind::StiffSpring))?;
    let floats = b.forces(doc, g)?;
    let (stiff, _) = b.make_links(plans.iter().filter(|p| p.kind == Kind::StiffSpring))?;
    links.extend(stiff);
    links.extend(contacts);
    b.surfaces(doc)?;
    let camera = b.camera(doc)?;
    // Named single particles are labelled; an array's name at one member would be
    // ambiguous, and several arrays often start at the same corner.
    let labels = b
        .groups
        .iter()
        .filter(|group| group.single)
        .filter_map(|group| Some((b.ids[group.first], group.name?)))
        .collect();
    let water = water(&b.world, &floats);
    Ok(Built { world: b.world, links, labels, camera, floats, water, g_elsewhere: b.g_elsewhere })
}

/// A pool around the floating particles.
fn water(world: &World, floats: &[(ForceId, Buoyancy)]) -> Option<Water> {
    let (_, first) = floats.first()?;
    let p = &world.particles;
    let points: Vec<Vec2> = floats
        .iter()
        .filter_map(|(_, f)| p.index(f.target))
        .map(|i| p.positions()[i])
        .map(|v| v.xz())
        .collect();
    let (min, max) = points
        .iter()
        .fold((Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)), |(lo, hi), &q| (lo.min(q), hi.max(q)));
    Some(Water {
        height: first.surface,
        center: (min + max) * 0.5,
        half_extent: (max - min) * 0.5 + Vec2::splat(1.0),
    })
}

impl Builder<'_> {
    fn gravity(&mut self, doc: &'static Document) -> Result<f32, Located> {
        match &doc.scene.gravity {
            Some(field) => {
                let value = self.compile(field, &[])?;
                self.eval(&value, &[], "gravity", ANY)
            }
            None => Ok(self.g_index.map_or(0.0, |k| self.values[k] as f32)),
        }
    }

    /// Parses a value with the given locals (`i`, `j`) visible after the parameters.
    fn compile(&mut self, field: &SNum, locals: &[&'static str]) -> Result<Value, Located> {
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

    fn compile_or(
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

    fn compile_vec(&mut self, field: &SVec, locals: &[&'static str]) -> Result<[Value; 3], Located> {
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

    fn compile_vec_or(
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
    fn eval(&mut self, value: &Value, locals: &[f64], what: &str, bounds: Bounds) -> Result<f32, Located> {
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

    fn eval_vec(&mut self, value: &[Value; 3], locals: &[f64], what: &str) -> Result<Vec3, Located> {
        Ok(Vec3::new(
            self.eval(&value[0], locals, what, ANY)?,
            self.eval(&value[1], locals, what, ANY)?,
            self.eval(&value[2], locals, what, ANY)?,
        ))
    }

    /// A count: rounded, at least 1, and within what the scene may still add.
    fn count(&mut self, field: &SNum, what: &str) -> Result<usize, Located> {
        let value = self.compile(field, &[])?;
        let x = self.eval(&value, &[], what, ANY)?.round();
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

    fn name(&self, field: Option<&'static toml::Spanned<String>>) -> Result<Option<&'static str>, Located> {
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

    /// Adds a group of particles, findable by its name from now on.
    fn push_group(&mut self, group: Group) {
        if let Some(name) = group.name {
            self.named.insert(name, self.groups.len());
        }
        self.groups.push(group);
    }

    fn add(&mut self, desc: ParticleDesc, span: &Range<usize>) -> Result<(), Located> {
        let id = self.world.add_particle(desc).map_err(|e| Located::at(span, e.to_string()))?;
        self.ids.push(id);
        Ok(())
    }

    fn particles(&mut self, doc: &'static Document) -> Result<(), Located> {
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
            self.push_group(Group { name, single: true, first: self.ids.len(), rows: 1, cols: 1 });
            self.add(desc, &span)?;
        }
        Ok(())
    }

    /// The kind a group's `link` names.
    fn kind(field: &toml::Spanned<String>) -> Result<Kind, Located> {
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
    fn index(&mut self, field: &SNum, len: usize, what: &str) -> Result<usize, Located> {
        let value = self.compile(field, &[])?;
        let x = self.eval(&value, &[], what, ANY)?.round() as i64;
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

    fn rows(&mut self, doc: &'static Document) -> Result<(), Located> {
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
                self.add(desc, &span)?;
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

    fn grids(&mut self, doc: &'static Document) -> Result<(), Located> {
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
                    self.add(desc, &span)?;
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

    /// Plans links between members `first + a` and `first + b` of a group.
    fn group_links(
        &mut self,
        kind: Kind,
        props: LinkProps<'_>,
        first: usize,
        pairs: &[(usize, usize)],
        span: &Range<usize>,
    ) -> Result<(), Located> {
        if kind == Kind::StiffSpring {
            return Err(Located::at(
                span,
                "a stiff spring joins a particle to an anchor; use it in a [[link]]",
            ));
        }
        let shared = self.props(props, kind)?;
        if shared.k.is_nan() {
            return Err(Located::at(span, format!("a {} needs `k` (N/m)", kind_name(kind))));
        }
        self.check_link_room(pairs.len(), span)?;
        for &(a, b) in pairs {
            self.plans.push(LinkPlan {
                a: first + a,
                b: End::Particle(first + b),
                span: span.clone(),
                ..shared
            });
        }
        Ok(())
    }

    /// Counts `each` terms for every one of `members`, refusing the table that takes the
    /// file past [`MAX_EVALUATIONS`] with what it costs.
    fn spend_evaluations(
        &mut self,
        each: usize,
        members: usize,
        table: &str,
        span: &Range<usize>,
    ) -> Result<(), Located> {
        self.evaluations += each * members;
        if self.evaluations > MAX_EVALUATIONS {
            return Err(Located::at(
                span,
                format!(
                    "this {table} evaluates {each} expression terms for each of its {members} particles, \
                     which brings the file to {}; a scene file evaluates at most {MAX_EVALUATIONS} \
                     (shorten the expressions, or make fewer particles)",
                    self.evaluations
                ),
            ));
        }
        Ok(())
    }

    fn check_link_room(&self, more: usize, span: &Range<usize>) -> Result<(), Located> {
        if self.plans.len() + more > MAX_LINKS {
            return Err(Located::at(span, format!("a scene file makes at most {MAX_LINKS} links")));
        }
        Ok(())
    }

    /// The properties every link of a group shares, checked for its kind.
    fn props(&mut self, props: LinkProps<'_>, kind: Kind) -> Result<LinkPlan, Located> {
        let length = match props.length {
            Some(field) => {
                let value = self.compile(field, &[])?;
                let bounds =
                    if kind == Kind::Spring || kind == Kind::Bungee { NON_NEGATIVE } else { POSITIVE };
                Some(self.eval(&value, &[], "length", bounds)?)
            }
            None => None,
        };
        let springy = matches!(kind, Kind::Spring | Kind::Bungee | Kind::StiffSpring);
        let k = match (props.k, springy) {
            (Some(field), true) => {
                let value = self.compile(field, &[])?;
                let bounds = if kind == Kind::StiffSpring { POSITIVE } else { NON_NEGATIVE };
                self.eval(&value, &[], "k", bounds)?
            }
            // Missing: the caller says so at the table, where `k` belongs.
            (None, true) => f32::NAN,
            (Some(field), false) => {
                return Err(Located::at(&field.span(), "k is for springs, bungees and stiff springs"));
            }
            (None, false) => 0.0,
        };
        let restitution = self.compile_or(props.restitution, 0.0, &[])?;
        let restitution = self.eval(&restitution, &[], "restitution", UNIT)?;
        let damping_ratio = self.compile_or(props.damping_ratio, 0.0, &[])?;
        let damping_ratio = self.eval(&damping_ratio, &[], "damping_ratio", NON_NEGATIVE)?;
        let tear = match props.tear {
            Some(field) => {
                let value = self.compile(field, &[])?;
                Some(self.eval(&value, &[], "tear", POSITIVE)?)
            }
            None => None,
        };
        Ok(LinkPlan {
            kind,
            a: 0,
            b: End::Anchor(Vec3::ZERO),
            length,
            k,
            restitution,
            damping_ratio,
            tear,
            span: 0..0,
        })
    }

    /// The particles a reference names.
    fn resolve(&self, field: &toml::Spanned<Ref>) -> Result<Vec<usize>, Located> {
        let span = field.span();
        let total = self.ids.len();
        match field.get_ref() {
            Ref::Index(k) => {
                if (0..total as i64).contains(k) {
                    Ok(vec![*k as usize])
                } else {
                    Err(Located::at(
                        &span,
                        format!(
                            "particle {k} is out of range: the file makes {total} particles (0 to {})",
                            total.saturating_sub(1)
                        ),
                    ))
                }
            }
            Ref::Name(text) => {
                let mut parts = text.split('.');
                let base = parts.next().unwrap_or("");
                let Some(group) = self.named.get(base).map(|&k| &self.groups[k]) else {
                    let valid = if self.named.is_empty() {
                        "none (give particles a name)".into()
                    } else {
                        list(self.groups.iter().filter_map(|g| g.name))
                    };
                    return Err(Located::at(
                        &span,
                        format!("no particle or array named '{}'; names: {valid}", clip(base, 40)),
                    ));
                };
                let indices: Vec<&str> = parts.collect();
                let member = |part: &str, len: usize| -> Result<usize, Located> {
                    let k: i64 = part.parse().map_err(|_| {
                        Located::at(
                            &span,
                            format!("'{}' in '{}' is not a whole number", clip(part, 24), clip(text, 40)),
                        )
                    })?;
                    let index = if k < 0 { k + len as i64 } else { k };
                    if (0..len as i64).contains(&index) {
                        Ok(index as usize)
                    } else {
                        Err(Located::at(
                            &span,
                            format!(
                                "index {k} of '{}' is out of range: it has {len} (0 to {})",
                                clip(base, 40),
                                len - 1
                            ),
                        ))
                    }
                };
                let single = group.single && indices.is_empty();
                match (indices.as_slice(), group.rows) {
                    ([], _) if single => Ok(vec![group.first]),
                    ([], _) => Ok((group.first..group.first + group.rows * group.cols).collect()),
                    ([k], 1) => Ok(vec![group.first + member(k, group.cols)?]),
                    ([i, j], _) => {
                        Ok(vec![group.first + member(i, group.rows)? * group.cols + member(j, group.cols)?])
                    }
                    ([_], _) => Err(Located::at(
                        &span,
                        format!("'{0}' is a grid: name a member as '{0}.ROW.COL'", clip(base, 40)),
                    )),
                    _ => Err(Located::at(&span, format!("'{}' has too many indices", clip(text, 40)))),
                }
            }
        }
    }

    fn links(&mut self, doc: &'static Document) -> Result<(), Located> {
        for table in &doc.link {
            let span = table.span();
            let t = table.get_ref();
            let kind = Self::kind(&t.kind)?;
            let a = self.resolve(&t.a)?;
            let ends: Vec<End> = match (&t.b, &t.anchor) {
                (Some(b), None) => {
                    if kind == Kind::StiffSpring {
                        return Err(Located::at(
                            &b.span(),
                            "a stiff spring joins a particle to an `anchor`, not to `b`",
                        ));
                    }
                    self.resolve(b)?.into_iter().map(End::Particle).collect()
                }
                (None, Some(anchor)) => {
                    let anchor = self.compile_vec(anchor, &[])?;
                    vec![End::Anchor(self.eval_vec(&anchor, &[], "anchor")?)]
                }
                (Some(b), Some(_)) => return Err(Located::at(&b.span(), "give `b` or `anchor`, not both")),
                (None, None) => {
                    return Err(Located::at(&span, "a link needs `b` (a particle) or `anchor` ([x, y, z])"));
                }
            };
            let pairs: Vec<(usize, End)> = match (a.len(), ends.len()) {
                (_, 1) => a.iter().map(|&a| (a, ends[0])).collect(),
                (1, _) => ends.iter().map(|&b| (a[0], b)).collect(),
                (m, n) if m == n => a.iter().copied().zip(ends.iter().copied()).collect(),
                (m, n) => {
                    return Err(Located::at(
                        &span,
                        format!("`a` names {m} particles and `b` {n}: they must match"),
                    ));
                }
            };
            let mut shared = self.props(t.props(), kind)?;
            if shared.k.is_nan() {
                return Err(Located::at(&t.kind.span(), format!("a {} needs `k` (N/m)", t.kind.get_ref())));
            }
            shared.span = span.clone();
            self.check_link_room(pairs.len(), &span)?;
            for (a, b) in pairs {
                if let End::Particle(b) = b
                    && a == b
                {
                    return Err(Located::at(&span, format!("particle {a} is linked to itself")));
                }
                self.plans.push(LinkPlan { a, b, span: span.clone(), ..shared });
            }
        }
        Ok(())
    }

    fn forces(&mut self, doc: &'static Document, g: f32) -> Result<Vec<(ForceId, Buoyancy)>, Located> {
        let mut applications = 0;
        for table in &doc.drag {
            let span = table.span();
            let t = table.get_ref();
            let k1 = self.compile_or(t.k1.as_ref(), 0.0, &[])?;
            let k2 = self.compile_or(t.k2.as_ref(), 0.0, &[])?;
            let targets = match &t.targets {
                Some(list) => {
                    let mut out = Vec::new();
                    for field in list {
                        let members = self.resolve(field)?;
                        spend(&mut applications, members.len(), "[[drag]]", &span)?;
                        out.extend(members.into_iter().map(|k| self.ids[k]));
                    }
                    out
                }
                None => {
                    spend(&mut applications, self.ids.len(), "[[drag]]", &span)?;
                    self.ids.clone()
                }
            };
            let drag = Drag {
                k1: self.eval(&k1, &[], "k1", NON_NEGATIVE)?,
                k2: self.eval(&k2, &[], "k2", NON_NEGATIVE)?,
                targets,
            };
            self.world.add_force(drag).map_err(|e| Located::at(&span, e.to_string()))?;
        }
        let mut floats = Vec::new();
        for table in &doc.buoyancy {
            let span = table.span();
            let t = table.get_ref();
            let targets = self.resolve(&t.particle)?;
            spend(&mut applications, targets.len(), "[[buoyancy]]", &span)?;
            let surface = self.compile(&t.surface, &[])?;
            let half_height = self.compile(&t.half_height, &[])?;
            let volume = self.compile(&t.volume, &[])?;
            let density = self.compile_or(t.density.as_ref(), 1000.0, &[])?;
            let (surface, half_height, volume, density) = (
                self.eval(&surface, &[], "surface", ANY)?,
                self.eval(&half_height, &[], "half_height", NON_NEGATIVE)?,
                self.eval(&volume, &[], "volume", NON_NEGATIVE)?,
                self.eval(&density, &[], "density", NON_NEGATIVE)?,
            );
            for k in targets {
                let float =
                    Buoyancy { target: self.ids[k], surface, half_height, volume, density, g: g.max(0.0) };
                let id =
                    self.world.add_force(float.clone()).map_err(|e| Located::at(&span, e.to_string()))?;
                floats.push((id, float));
            }
        }
        Ok(floats)
    }

    /// Makes planned links: springs into the force registry, rods and cables as contact
    /// generators. Returns the records of both, each in the order made.
    fn make_links<'p>(
        &mut self,
        plans: impl Iterator<Item = &'p LinkPlan>,
    ) -> Result<(Vec<LinkRecord>, Vec<LinkRecord>), Located> {
        let mut forces = Vec::new();
        let mut contacts = Vec::new();
        for plan in plans {
            let a = self.ids[plan.a];
            let pa = self.world.particles.positions()[plan.a];
            let (b, pb) = match plan.b {
                End::Particle(k) => (LinkEnd::Particle(self.ids[k]), self.world.particles.positions()[k]),
                End::Anchor(p) => (LinkEnd::Anchor(p), p),
            };
            let distance = pa.distance(pb);
            let length = plan.length.unwrap_or(distance);
            let fail = |e: crate::physics::PhysicsError| Located::at(&plan.span, e.to_string());
            match plan.kind {
                Kind::Rod | Kind::Cable => {
                    if length <= 0.0 {
                        return Err(Located::at(
                            &plan.span,
                            format!(
                                "a {} needs a length > 0 (its ends start {distance} m apart)",
                                kind_name(plan.kind)
                            ),
                        ));
                    }
                    let rigid = plan.kind == Kind::Rod;
                    let link = match b {
                        LinkEnd::Particle(b) if rigid => Constraint::rod(a, b, length),
                        LinkEnd::Particle(b) => Constraint::cable(a, b, length, plan.restitution),
                        LinkEnd::Anchor(p) if rigid => Constraint::support_rod(a, p, length),
                        LinkEnd::Anchor(p) => Constraint::support_cable(a, p, length, plan.restitution),
                    };
                    let spec = link.spec();
                    let id = self.world.add_contact_generator(link).map_err(fail)?;
                    contacts.push(LinkRecord { handle: Handle::Contact(id), spec, tear: plan.tear });
                }
                Kind::Spring | Kind::Bungee => {
                    let mut spring = Spring { a, b, k: plan.k, rest_length: length, bungee: false };
                    if plan.kind == Kind::Bungee {
                        spring = spring.as_bungee();
                    }
                    let spec = spring.link().expect("a spring is a link");
                    let id = self.world.add_force(spring).map_err(fail)?;
                    forces.push(LinkRecord { handle: Handle::Force(id), spec, tear: plan.tear });
                }
                Kind::StiffSpring => {
                    let LinkEnd::Anchor(anchor) = b else {
                        return Err(Located::at(&plan.span, "a stiff spring needs an `anchor`"));
                    };
                    let spring = StiffSpring::new(a, anchor, plan.k, plan.damping_ratio);
                    let spec = spring.link().expect("a stiff spring is a link");
                    let id = self.world.add_force(spring).map_err(fail)?;
                    forces.push(LinkRecord { handle: Handle::Force(id), spec, tear: plan.tear });
                }
            }
        }
        Ok((forces, contacts))
    }

    fn surfaces(&mut self, doc: &'static Document) -> Result<(), Located> {
        if let Some(ground) = &doc.ground {
            let height = self.compile_or(ground.height.as_ref(), 0.0, &[])?;
            let restitution = self.compile_or(ground.restitution.as_ref(), 0.3, &[])?;
            let friction = self.compile_or(ground.friction.as_ref(), 0.5, &[])?;
            let plane = Plane::ground(
                self.eval(&height, &[], "height", ANY)?,
                self.eval(&restitution, &[], "restitution", UNIT)?,
                self.eval(&friction, &[], "friction", NON_NEGATIVE)?,
            );
            self.world.add_contact_generator(plane).map_err(|e| Located::at(&height.span, e.to_string()))?;
        }
        for wall in &doc.wall {
            let normal = self.compile_vec(&wall.normal, &[])?;
            let point = self.compile_vec(&wall.point, &[])?;
            let restitution = self.compile_or(wall.restitution.as_ref(), 0.3, &[])?;
            let friction = self.compile_or(wall.friction.as_ref(), 0.5, &[])?;
            let plane = Plane::new(
                self.eval_vec(&normal, &[], "normal")?,
                self.eval_vec(&point, &[], "point")?,
                self.eval(&restitution, &[], "restitution", UNIT)?,
                self.eval(&friction, &[], "friction", NON_NEGATIVE)?,
            )
            .map_err(|e| Located::at(&wall.normal.span(), e.to_string()))?;
            self.world
                .add_contact_generator(plane)
                .map_err(|e| Located::at(&wall.normal.span(), e.to_string()))?;
        }
        if let Some(collisions) = &doc.collisions {
            let restitution = self.compile_or(collisions.restitution.as_ref(), 0.5, &[])?;
            let friction = self.compile_or(collisions.friction.as_ref(), 0.3, &[])?;
            let spheres = SphereCollisions {
                restitution: self.eval(&restitution, &[], "restitution", UNIT)?,
                friction: self.eval(&friction, &[], "friction", NON_NEGATIVE)?,
            };
            self.world
                .add_contact_generator(spheres)
                .map_err(|e| Located::at(&restitution.span, e.to_string()))?;
        }
        Ok(())
    }

    /// The `[camera]` table, with what it leaves out framing every particle.
    fn camera(&mut self, doc: &'static Document) -> Result<CameraHint, Located> {
        let positions = self.world.particles.positions();
        let (lo, hi) = positions
            .iter()
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let (centre, size) =
            if positions.is_empty() { (Vec3::ZERO, 1.0) } else { ((lo + hi) * 0.5, (hi - lo).max_element()) };
        let framing =
            CameraHint { target: centre, distance: 1.8 * size.max(0.5) + 1.0, yaw: 0.0, pitch: 0.2 };
        let Some(camera) = &doc.camera else { return Ok(framing) };
        let target = match &camera.target {
            Some(field) => {
                let value = self.compile_vec(field, &[])?;
                self.eval_vec(&value, &[], "target")?
            }
            None => framing.target,
        };
        let distance = self.compile_or(camera.distance.as_ref(), f64::from(framing.distance), &[])?;
        let yaw = self.compile_or(camera.yaw.as_ref(), 0.0, &[])?;
        let pitch = self.compile_or(camera.pitch.as_ref(), f64::from(framing.pitch.to_degrees()), &[])?;
        Ok(CameraHint {
            target,
            distance: self.eval(&distance, &[], "distance", POSITIVE)?,
            yaw: self.eval(&yaw, &[], "yaw", ANY)?.to_radians(),
            pitch: self
                .eval(&pitch, &[], "pitch", Bounds { min: -89.0, max: 89.0, text: "-89 to 89 degrees" })?
                .to_radians(),
        })
    }
}

/// Adds `more` generator applications a step to the file's count, refusing the table
/// that takes it past [`MAX_APPLICATIONS`] with what the file then costs.
fn spend(applications: &mut usize, more: usize, table: &str, span: &Range<usize>) -> Result<(), Located> {
    *applications += more;
    if *applications > MAX_APPLICATIONS {
        return Err(Located::at(
            span,
            format!(
                "this {table} acts on {more} particles, which brings the file to {applications} drag \
                 and buoyancy applications a step (one per particle each acts on); a scene file makes \
                 at most {MAX_APPLICATIONS}"
            ),
        ));
    }
    Ok(())
}

fn kind_name(kind: Kind) -> &'static str {
    KINDS.iter().find(|(_, k)| *k == kind).map_or("link", |(n, _)| n)
}

/// Where a row's or grid's particles go: a formula of `i` (and `j`), or a start and
/// steps along columns (and rows).
// One lives for the building of one group: its size does not matter.
#[allow(clippy::large_enum_variant)]
enum Placement {
    Formula([Value; 3]),
    Steps([Value; 3], [Value; 3], Option<[Value; 3]>),
}

/// Terms in three values.
fn size(values: &[Value; 3]) -> usize {
    values.iter().map(|v| v.expr.size()).sum()
}

impl Placement {
    /// Terms evaluated for each member (a start and steps are evaluated once).
    fn size(&self) -> usize {
        match self {
            Self::Formula(position) => size(position),
            Self::Steps(..) => 0,
        }
    }

    /// The start and steps, evaluated once (they do not depend on the index).
    fn evaluate(&self, b: &mut Builder<'_>) -> Result<[Vec3; 3], Located> {
        match self {
            Self::Formula(_) => Ok([Vec3::ZERO; 3]),
            Self::Steps(start, col, row) => Ok([
                b.eval_vec(start, &[], "start")?,
                b.eval_vec(col, &[], "step")?,
                match row {
                    Some(row) => b.eval_vec(row, &[], "step_row")?,
                    None => Vec3::ZERO,
                },
            ]),
        }
    }

    fn at(
        &self,
        b: &mut Builder<'_>,
        steps: &[Vec3; 3],
        local: &[f64],
        col: f32,
        row: f32,
    ) -> Result<Vec3, Located> {
        match self {
            Self::Formula(position) => b.eval_vec(position, local, "position"),
            Self::Steps(..) => Ok(steps[0] + steps[1] * col + steps[2] * row),
        }
    }
}

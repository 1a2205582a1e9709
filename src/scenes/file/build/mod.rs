//! Building a world from a parsed scene file and a set of parameter values.
//!
//! Every value is checked where it is read, so that an error points at the value in the
//! file (a byte span, turned into a line and column by the caller), not at whatever the
//! physics would later refuse.
//!
//! The rooms: `values.rs` (numbers and expressions, checked against their bounds),
//! `particles.rs` (single ones, rows, grids), `links.rs` (planned from references, then
//! made), `surroundings.rs` (force fields, ground and walls, camera). This file holds
//! what they share: the builder, the results and the limits.

use std::collections::HashMap;
use std::ops::Range;

use glam::{Vec2, Vec3, Vec3Swizzles};

use super::expr::Expr;
use super::format::Document;
use crate::physics::particles::{MAX_MASS, MIN_MASS};
use crate::physics::solver::SUBSTEP_RANGE;
use crate::physics::{
    Buoyancy, ContactGeneratorId, ForceId, Integrator, LinkSpec, ParticleId, SolverChoice, SolverKind,
    SolverSettings, World,
};
use crate::scenes::{CameraHint, ParamValues, Water};

mod links;
mod particles;
mod surroundings;
mod values;

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
    pub labels: Vec<(ParticleId, String)>,
    /// The starting camera.
    pub camera: CameraHint,
    /// Buoyancy generators, to give them a new `g`.
    pub floats: Vec<(ForceId, Buoyancy)>,
    /// The liquid to draw, where there is buoyancy.
    pub water: Option<Water>,
    /// Whether `g` appears in an expression other than `[scene] gravity` (a change of `g`
    /// then needs a rebuild).
    pub g_elsewhere: bool,
    /// The `[launcher]`'s aim, and whether a headless run fires a round at step 0
    /// (`fire_at_start`).
    pub launcher: Option<(crate::scenes::launcher::Aim, bool)>,
    /// Particles a `color` was given, by id (ascending: made in order).
    pub colors: Vec<(ParticleId, [f32; 3])>,
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
struct Group<'a> {
    name: Option<&'a str>,
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
    groups: Vec<Group<'a>>,
    /// Each named group's index in `groups`.
    named: HashMap<&'a str, usize>,
    plans: Vec<LinkPlan>,
    /// Particles given a colour, in the order made.
    colors: Vec<(ParticleId, [f32; 3])>,
    /// Terms evaluated for the members of rows and grids so far, against
    /// [`MAX_EVALUATIONS`].
    evaluations: usize,
}

fn builder<'a>(source: &'a str, params: &'a ParamValues) -> Builder<'a> {
    let names: Vec<&str> = params.iter().map(|(p, _)| &*p.name).collect();
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
        colors: Vec::new(),
        evaluations: 0,
    }
}

/// The downward acceleration `[scene] gravity` gives with these values (m/s²).
pub fn gravity(doc: &Document, source: &str, params: &ParamValues) -> Result<f32, Located> {
    builder(source, params).gravity(doc)
}

/// `[scene] solver`, `substeps` and `integrator`: the solver the scene names as its
/// own, each part `None` where it names none.
pub fn solver_choice(doc: &Document) -> Result<SolverChoice, Located> {
    let scene = &doc.scene;
    let kind = scene
        .solver
        .as_ref()
        .map(|name| SolverKind::parse(name.get_ref()).map_err(|e| Located::at(&name.span(), e)))
        .transpose()?;
    let substeps = scene
        .substeps
        .as_ref()
        .map(|n| {
            u32::try_from(*n.get_ref()).ok().filter(|k| SUBSTEP_RANGE.contains(k)).ok_or_else(|| {
                Located::at(
                    &n.span(),
                    format!(
                        "substeps = {} is out of range; valid range: {} to {}",
                        n.get_ref(),
                        SUBSTEP_RANGE.start(),
                        SUBSTEP_RANGE.end()
                    ),
                )
            })
        })
        .transpose()?;
    let integrator = scene
        .integrator
        .as_ref()
        .map(|name| Integrator::parse(name.get_ref()).map_err(|e| Located::at(&name.span(), e)))
        .transpose()?;
    Ok(SolverChoice { kind, substeps, integrator })
}

/// Builds the world the document describes with these parameter values, with the
/// solver the scene names as its own (the lab lays the user's choice over it).
pub fn build(doc: &Document, source: &str, params: &ParamValues) -> Result<Built, Located> {
    let mut b = builder(source, params);
    let own = solver_choice(doc)?;
    if !own.is_empty() {
        b.world
            .set_solver(own.over(SolverSettings::default()))
            .expect("a solver choice read from a file is valid");
    }
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
    let launcher = b.launcher(doc, g)?;
    let camera = b.camera(doc)?;
    // Named single particles are labelled; an array's name at one member would be
    // ambiguous, and several arrays often start at the same corner.
    let labels = b
        .groups
        .iter()
        .filter(|group| group.single)
        .filter_map(|group| Some((b.ids[group.first], group.name?.to_string())))
        .collect();
    let water = water(&b.world, &floats);
    Ok(Built {
        world: b.world,
        links,
        labels,
        camera,
        floats,
        water,
        g_elsewhere: b.g_elsewhere,
        launcher,
        colors: b.colors,
    })
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

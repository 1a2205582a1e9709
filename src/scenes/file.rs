//! Scenes as files: a TOML file declares a scene's parameters and builds its particles,
//! links, force generators and contact generators from them, without recompiling.
//!
//! # The format
//!
//! ```toml
//! [scene]
//! name = "chain"                 # the Scene menu's name
//! summary = "A chain of rods hanging from a pivot"
//! dt = 0.004166667               # physics step (s), default 1/240
//! steps = 2400                   # steps `simulate` runs by default
//! trails = true                  # trails on at the start (default true)
//! gravity = "g"                  # downward acceleration of every particle (m/s²), default "g"
//!
//! [[param]]                      # one slider and one `--set` key each
//! name = "links"
//! unit = ""
//! default = 12
//! min = 2
//! max = 40
//! help = "Number of rods"
//! logarithmic = false
//!
//! [[particle]]                   # a single particle
//! name = "ball"
//! position = [0, "1 + r", 0]     # numbers or expressions of the parameters
//! velocity = [1, 0, 0]           # default 0
//! mass = "mass"                  # kg, default 1
//! radius = 0.2                   # m, default 0.1
//! damping = 1                    # fraction of velocity kept per second, default 1
//! fixed = false                  # immovable
//!
//! [[row]]                        # `count` particles at start + i * step,
//! name = "chain"                 #   or at `position = [.. "i" ..]`
//! count = "links + 1"
//! start = [0, 5, 0]
//! step = [0, "-length", 0]
//! pin = [0]                      # immovable members; -1 is the last
//! link = "rod"                   # link neighbours: rod, cable, spring, bungee
//! closed = false                 # also link the last to the first (a ring)
//! # length, k, restitution, tear: as for [[link]]
//!
//! [[grid]]                       # rows x cols at origin + j * step_col + i * step_row,
//! name = "cloth"                 #   or at `position = [.. "i" .. "j" ..]`
//! rows = 10
//! cols = 10
//! origin = [0, 3, 0]
//! step_col = [0.2, 0, 0]
//! step_row = [0, 0, 0.2]
//! pin = [[0, 0], [0, -1]]        # [row, col] pairs
//! link = "rod"                   # along rows and columns
//! shear = true                   # and along diagonals
//!
//! [[link]]
//! kind = "spring"                # rod, cable, spring, bungee, stiff_spring
//! a = "ball"                     # a particle: its number, name, "row.3", "grid.2.5",
//! b = "chain.-1"                 #   or a whole array (one link to each member)
//! # anchor = [0, 5, 0]           # instead of b: a fixed point (support rod, cable, ...)
//! length = 1.0                   # rest / rod / maximum length (m), default the start distance
//! k = 50                         # spring constant (N/m) for springs
//! restitution = 0                # a cable snapping taut
//! damping_ratio = 0              # a stiff spring's
//! tear = "tear"                  # tension (N) above which the link breaks
//!
//! [[drag]]                       # k1 |v| and k2 |v|² against the motion
//! k1 = 0.1
//! k2 = 0
//! targets = ["ball"]             # default every particle
//!
//! [[buoyancy]]
//! particle = "ball"
//! surface = 0
//! half_height = 0.2
//! volume = 0.03
//! density = 1000
//!
//! [ground]                       # the plane y = height
//! height = 0
//! restitution = 0.3
//! friction = 0.5
//!
//! [[wall]]
//! normal = [1, 0, 0]
//! point = [-5, 0, 0]
//!
//! [collisions]                   # spheres collide with each other
//! restitution = 0.5
//! friction = 0.3
//!
//! [camera]                       # default: frame every particle
//! target = [0, 2, 0]
//! distance = 8
//! yaw = 0                        # degrees
//! pitch = 10                     # degrees, positive looks down
//! ```
//!
//! Particles are numbered in the file's order within each kind: every `[[particle]]`,
//! then every `[[row]]`, then every `[[grid]]` (row by row). Values are numbers or
//! expressions in quotes (see [`expr`]): `+ - * / ^`, parentheses, parameter names,
//! `pi`, `sqrt sin cos tan abs exp ln rad round`; in a row's values `i` is the member's index,
//! in a grid's `i` is its row and `j` its column. Every file scene has a parameter `g`
//! (9.81 m/s², 0 to 30) unless it declares its own; changing `g` acts at once, any other
//! parameter rebuilds the scene with the solver kept. A scene makes at most
//! 200,000 particles and a million links. Its cost is bounded whatever the file's size:
//! an expression holds at most [`expr::MAX_NODES`] terms, drags and buoyancies act at
//! most `MAX_APPLICATIONS` (1,000,000) times a step (once per particle each acts on), the
//! members of rows and grids evaluate at most `MAX_EVALUATIONS` (50,000,000) terms a
//! build, and a file is at most 4 MB ([`load_path`] reads no more of a regular file and
//! refuses devices, FIFOs and directories).
//!
//! Errors name the file, line and column of the offending value and what was expected,
//! on one line: `chain.toml:12:9: unknown name 'lenght'; valid names here: links, ...`.
//!
//! # How a file scene joins the registry
//!
//! A load makes one [`Definition`]: the file's text, its parsed tables and its
//! [`SceneInfo`], whose name, summary and parameter table are the file's own (owned
//! strings, where a compiled scene's borrow from the binary). It comes back as a
//! [`SceneEntry::File`], which holds the definition behind an `Arc`. Every clone of the
//! entry (the lab's, a Compare copy's) and every scene built from it hold that same
//! `Arc`, and every set of parameter values shares the file's parameter table, so reset,
//! Compare, snapshots and the panel work on file scenes exactly as on compiled ones.
//! When the last of them is dropped (the file reloaded after an edit, a snapshot of
//! another scene loaded, another scene picked) the file and its tables are freed:
//! nothing keeps a list of loads, and a thousand reloads take no more memory than one
//! (`tests/scene_memory.rs`). Only the shipped scenes, loaded once for the Scene menu
//! ([`shipped`]), live as long as the program, as the compiled scenes do.

mod build;
pub mod expr;
mod format;
mod write;

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use glam::Vec3;

pub use self::build::MAX_PARTICLES;
use self::build::{Built, Handle, Located};
use self::format::Document;
pub use self::format::{ACCEPTED_KEYS, accepted_keys};
pub use self::write::{HEADER, float32, string as toml_string};
use super::launcher::Launcher;
use super::{
    CameraHint, GRAVITY_PRESETS, Param, ParamError, ParamTable, ParamValues, Scene, SceneAction, SceneEntry,
    SceneInfo, Water,
};
use crate::messages::{self, clip, quote};
use crate::physics::{LinkState, ParticleId, PhysicsError, ResolveReport, SolverChoice, World};
use crate::reading;

/// The scenes shipped in `assets/scenes/`, built into the binary so the Scene menu has
/// them wherever it runs; a copy on disk beside the working directory is used instead
/// when there is one, so that editing it reloads the scene.
pub static SHIPPED: &[(&str, &str)] = &[
    ("assets/scenes/chain.toml", include_str!("../../assets/scenes/chain.toml")),
    ("assets/scenes/cloth.toml", include_str!("../../assets/scenes/cloth.toml")),
    ("assets/scenes/platform.toml", include_str!("../../assets/scenes/platform.toml")),
    ("assets/scenes/blob.toml", include_str!("../../assets/scenes/blob.toml")),
];

/// Largest scene file read (bytes): far more than any hand-written scene.
pub const MAX_FILE_BYTES: u64 = 4 << 20;

/// A scene file that could not be read or built: where and why.
#[derive(Clone, Debug, PartialEq)]
pub struct FileError {
    /// The file, as the user named it.
    pub file: String,
    /// Line and column (from 1) of the offending value, when there is one.
    pub position: Option<(usize, usize)>,
    /// What is wrong and what was expected.
    pub message: String,
}

impl std::fmt::Display for FileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.position {
            Some((line, column)) => write!(f, "{}:{line}:{column}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for FileError {}

/// A loaded scene file: its text, where it came from, and its parsed tables. Its
/// entry ([`SceneEntry::File`]) and every scene built from it share it; it is freed
/// with the last of them.
pub struct Definition {
    doc: Document,
    /// The solver the file names as its own (`[scene] solver`, `substeps`, `integrator`).
    solver: SolverChoice,
    source: String,
    shown: String,
    path: Option<PathBuf>,
    info: SceneInfo,
}

impl std::fmt::Debug for Definition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Definition").field("name", &self.info.name).field("file", &self.shown).finish()
    }
}

impl Definition {
    /// The file's text, as loaded.
    #[must_use]
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The file on disk it was read from (`None` for a shipped scene built in).
    #[must_use]
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The file as the writer writes it ([`write`](self::write)): the same tables in the
    /// reference's order, with each parameter's default the value in `values` (a slider
    /// moved, a `--set`).
    #[must_use]
    pub fn written(&self, values: Option<&ParamValues>) -> String {
        write::write(&self.doc, values)
    }

    /// The scene's description, as the file declares it.
    #[must_use]
    pub fn info(&self) -> &SceneInfo {
        &self.info
    }

    /// Builds the scene with these values; an error names the line and column of the
    /// value that cannot be used with them. The scene holds this file while it lives.
    pub fn create(self: &Arc<Self>, params: ParamValues) -> Result<Box<dyn Scene>, FileError> {
        Ok(Box::new(FileScene::new(Arc::clone(self), params)?))
    }

    fn build(&self, params: &ParamValues) -> Result<Built, FileError> {
        build::build(&self.doc, &self.source, params).map_err(|e| self.locate(&e))
    }

    fn locate(&self, error: &Located) -> FileError {
        FileError {
            file: self.shown.clone(),
            position: Some(line_column(&self.source, error.offset)),
            message: error.message.clone(),
        }
    }
}

/// Line and column (from 1, the column in characters) of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// The file behind a registry entry, if it is a file scene.
#[must_use]
pub fn definition(entry: &SceneEntry) -> Option<&Definition> {
    match entry {
        SceneEntry::File(definition) => Some(definition),
        SceneEntry::Compiled { .. } => None,
    }
}

/// The solver a scene names as its own: a scene file's `[scene] solver`, `substeps`
/// and `integrator`; nothing for a scene built into the program.
#[must_use]
pub fn own_solver(entry: &SceneEntry) -> SolverChoice {
    definition(entry).map_or_else(SolverChoice::default, |d| d.solver)
}

/// The scene file of a scene as it stands: its tables with each parameter's default
/// the value in `values` ([`Definition::written`]); or why it cannot be written.
pub fn written(entry: &SceneEntry, values: &ParamValues) -> Result<String, String> {
    writable(entry).map(|definition| definition.written(Some(values)))
}

/// A scene file's text as the writer writes it (its tables and keys in the reference's
/// order, its header), or why it cannot be read.
pub fn canonical(text: &str) -> Result<String, String> {
    let doc: Document = toml::from_str(text).map_err(|e| toml_message(&e))?;
    Ok(write::write(&doc, None))
}

/// The file a scene can be written as, or why it cannot be.
pub fn writable(entry: &SceneEntry) -> Result<&Definition, String> {
    match definition(entry) {
        Some(definition) => Ok(definition),
        None => Err(format!(
            "'{}' is built into the program: Scene > Edit a copy of this scene (B) makes one of its particles \
             and links that saves as a scene file",
            entry.info().name
        )),
    }
}

/// Reads and loads a scene file from disk. A device, FIFO or directory is refused
/// before it is opened, and at most [`MAX_FILE_BYTES`] are read whatever the file
/// says its size is.
pub fn load_path(path: &Path) -> Result<SceneEntry, FileError> {
    let shown = messages::path(path);
    let fail = |message: String| FileError { file: shown.clone(), position: None, message };
    let bytes =
        reading::read_limited(path, MAX_FILE_BYTES).map_err(|e| fail(format!("cannot read it: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|_| fail("is not UTF-8 text".into()))?;
    load_shown(&text, shown, Some(path.to_path_buf()))
}

/// Loads a scene from its text; `shown` names it in messages (escaped and cut, as any
/// user text there), `path` is where it lives on disk, if anywhere.
pub fn load_text(text: &str, shown: &str, path: Option<PathBuf>) -> Result<SceneEntry, FileError> {
    load_shown(text, quote(shown), path)
}

/// A number for a message: as Rust writes it, but with an exponent where that would
/// take more than a few digits (1e39, not forty digits; 1e-300, not three hundred).
fn number(x: f64) -> String {
    if x.is_finite() && x != 0.0 && !(1e-6..1e16).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A TOML error's words on one line: the key or value it echoes in backquotes is
/// escaped and cut like any user text.
fn toml_message(error: &toml::de::Error) -> String {
    let pieces: Vec<String> = error
        .message()
        .trim()
        .split('`')
        .enumerate()
        .map(|(k, piece)| if k % 2 == 1 { clip(piece, 40) } else { clip(&piece.replace('\n', "; "), 200) })
        .collect();
    clip(&pieces.join("`"), 240)
}

/// [`load_text`] with `shown` already fit for a message.
fn load_shown(text: &str, shown: String, path: Option<PathBuf>) -> Result<SceneEntry, FileError> {
    let shown = shown.as_str();
    if text.len() as u64 > MAX_FILE_BYTES {
        let limit = reading::bytes(MAX_FILE_BYTES);
        let message = format!("it is larger than the limit of {limit} for a scene file");
        return Err(FileError { file: shown.to_string(), position: None, message });
    }
    let at = |offset: usize, message: String| FileError {
        file: shown.to_string(),
        position: Some(line_column(text, offset)),
        message,
    };
    let doc: Document = toml::from_str(text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        at(offset, toml_message(&e))
    })?;
    let params = param_table(&doc).map_err(|e| at(e.offset, e.message))?;
    let scene = &doc.scene;
    let name = scene.name.get_ref().trim();
    if name.is_empty() {
        return Err(at(scene.name.span().start, "the scene needs a name".into()));
    }
    let dt = match &scene.dt {
        Some(dt) if !(1e-5..=0.1).contains(dt.get_ref()) => {
            return Err(at(
                dt.span().start,
                format!("dt = {} is out of range; valid range: 1e-5 to 0.1 s", number(*dt.get_ref())),
            ));
        }
        Some(dt) => *dt.get_ref() as f32,
        None => 1.0 / 240.0,
    };
    let steps = match &scene.steps {
        Some(steps) if !(1..=10_000_000).contains(steps.get_ref()) => {
            return Err(at(
                steps.span().start,
                format!("steps = {} is out of range; valid range: 1 to 10000000", steps.get_ref()),
            ));
        }
        Some(steps) => *steps.get_ref() as u32,
        None => 2400,
    };
    let has_g = params.iter().any(|p| p.name == "g");
    let info = SceneInfo {
        name: Cow::Owned(name.to_string()),
        summary: Cow::Owned(scene.summary.clone()),
        dt,
        default_steps: steps,
        params: ParamTable::Shared(params.into()),
        presets: if has_g { GRAVITY_PRESETS } else { &[] },
        actions: if doc.launcher.is_some() { super::launcher::FIRE } else { &[] },
        trails: scene.trails.unwrap_or(true),
        color_by_speed: scene.color_by_speed.unwrap_or(false),
    };
    let solver = build::solver_choice(&doc).map_err(|e| at(e.offset, e.message))?;
    let definition =
        Definition { doc, solver, source: text.to_string(), shown: shown.to_string(), path, info };
    // Build once with the defaults: an error anywhere in the file shows now.
    definition.build(&ParamValues::defaults(&definition.info.params))?;
    Ok(SceneEntry::File(Arc::new(definition)))
}

/// The `[[param]]` tables as a parameter table, with `g` added unless declared.
fn param_table(doc: &Document) -> Result<Vec<Param>, Located> {
    const RESERVED: &[&str] =
        &["i", "j", "pi", "sqrt", "sin", "cos", "tan", "abs", "exp", "ln", "rad", "round"];
    let mut table: Vec<Param> = Vec::new();
    for spanned in &doc.param {
        let p = spanned.get_ref();
        let name = p.name.get_ref().as_str();
        let span = p.name.span();
        let identifier = name.starts_with(|c: char| c.is_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_alphanumeric() || c == '_');
        if !identifier {
            return Err(Located::at(
                &span,
                format!("'{}' is not a parameter name: use letters, digits and _", clip(name, 40)),
            ));
        }
        if RESERVED.contains(&name) {
            return Err(Located::at(
                &span,
                format!("'{name}' is reserved in expressions; pick another name"),
            ));
        }
        if table.iter().any(|q| q.name == name) {
            return Err(Located::at(&span, format!("the parameter '{}' is declared twice", clip(name, 40))));
        }
        let (min, max, default) = (*p.min.get_ref(), *p.max.get_ref(), *p.default.get_ref());
        let finite = |x: f64| x.is_finite() && (x as f32).is_finite();
        if !(finite(min) && finite(max)) || min > max {
            return Err(Located::at(
                &p.min.span(),
                format!("min = {} and max = {} are not a range", number(min), number(max)),
            ));
        }
        if !finite(default) || default < min || default > max {
            return Err(Located::at(
                &p.default.span(),
                format!(
                    "default = {} is out of range; valid range: {} to {}",
                    number(default),
                    number(min),
                    number(max)
                ),
            ));
        }
        if p.integer && [min, max, default].iter().any(|x| x.fract() != 0.0) {
            return Err(Located::at(
                &p.default.span(),
                "a whole-number parameter (integer = true) needs a whole default, min and max",
            ));
        }
        if p.logarithmic && min <= 0.0 {
            return Err(Located::at(&p.min.span(), "a logarithmic parameter needs min > 0"));
        }
        table.push(Param {
            name: Cow::Owned(name.to_string()),
            unit: Cow::Owned(p.unit.clone()),
            default: default as f32,
            min: min as f32,
            max: max as f32,
            help: Cow::Owned(p.help.clone()),
            logarithmic: p.logarithmic,
            integer: p.integer,
        });
    }
    if !table.iter().any(|p| p.name == "g") {
        table.push(super::GRAVITY);
    }
    Ok(table)
}

/// The shipped scenes, loaded once (from disk where the working directory has them)
/// and kept for the program's life, as the compiled scenes are.
#[must_use]
pub fn shipped() -> &'static [SceneEntry] {
    static ENTRIES: OnceLock<Vec<SceneEntry>> = OnceLock::new();
    ENTRIES.get_or_init(|| {
        SHIPPED
            .iter()
            .filter_map(|(shown, text)| {
                let on_disk = Path::new(shown);
                let loaded =
                    if on_disk.is_file() { load_path(on_disk) } else { load_text(text, shown, None) };
                loaded.map_err(|e| log::warn!("particle-lab: {e}")).ok()
            })
            .collect()
    })
}

/// The scene a command line asks for: exactly one of a name and a file.
pub fn choose(name: Option<&str>, file: Option<&Path>) -> Result<SceneEntry, String> {
    match (name, file) {
        (Some(name), None) => super::find(name).cloned(),
        (None, Some(path)) => load_path(path).map_err(|e| e.to_string()),
        (Some(_), Some(_)) => Err("give either --scene NAME or --scene-file PATH, not both".into()),
        (None, None) => Err("no scene given: name one with --scene NAME or --scene-file PATH".into()),
    }
}

/// A running scene built from a file, which it holds while it lives.
struct FileScene {
    definition: Arc<Definition>,
    params: ParamValues,
    built: Built,
    /// Links torn so far.
    torn: usize,
    /// Reused buffer of link states, for tearing.
    states: Vec<LinkState>,
    /// The walls' patches as drawn (see [`wall_outlines`]), made when the world is built.
    walls: Vec<(Vec3, Vec3)>,
    /// The `[launcher]`, with its rounds. It fires none when built (see
    /// [`super::fire_at_start`]), so every particle of the world as built is the file's.
    launcher: Option<Launcher>,
    /// The state hash of the world as built, before any round: a parameter change that
    /// builds the same world changes only the launcher's aim, and the motion goes on.
    built_hash: u64,
}

/// The launcher `built` asks for, no round fired yet.
fn arm(built: &Built) -> Option<Launcher> {
    built.launcher.map(|(aim, fire_at_start)| Launcher::new(aim, fire_at_start))
}

/// The lines that draw `built`'s walls: every plane but the ground the view draws (at
/// y = 0), and every plate with its opening, each a patch around the box its particles (by their radii) and link
/// anchors fill as built.
fn wall_outlines(built: &Built) -> Vec<(Vec3, Vec3)> {
    let world = &built.world;
    let (mut lo, mut hi) = particle_box(world);
    let mut links = Vec::new();
    world.links_into(&mut links);
    for link in &links {
        if let crate::physics::LinkEnd::Anchor(anchor) = link.spec.b {
            (lo, hi) = (lo.min(anchor), hi.max(anchor));
        }
    }
    let mut out = Vec::new();
    for plane in world.planes().filter(|plane| !(plane.normal == Vec3::Y && plane.offset == 0.0)) {
        super::walls::plane_patch(plane, lo, hi, &mut out);
    }
    for plate in world.plates() {
        super::walls::plate_patch(plate, lo, hi, &mut out);
    }
    out
}

/// The box `world`'s particles fill, by their radii (m): lowest and highest corner;
/// with no particles, `lo` is above `hi`.
fn particle_box(world: &World) -> (Vec3, Vec3) {
    let p = &world.particles;
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for (&x, &r) in p.positions().iter().zip(p.radii()) {
        (lo, hi) = (lo.min(x - r), hi.max(x + r));
    }
    (lo, hi)
}

impl FileScene {
    fn new(definition: Arc<Definition>, params: ParamValues) -> Result<Self, FileError> {
        let built = definition.build(&params)?;
        let walls = wall_outlines(&built);
        let built_hash = built.world.state_hash();
        let launcher = arm(&built);
        Ok(Self { definition, params, built, torn: 0, states: Vec::new(), walls, launcher, built_hash })
    }

    /// Breaks every link pulled harder than its `tear` tension in the last step.
    fn tear(&mut self) {
        let links = &mut self.built.links;
        if links.iter().all(|l| l.tear.is_none()) {
            return;
        }
        let world = &mut self.built.world;
        world.links_into(&mut self.states);
        if self.states.len() != links.len() {
            return;
        }
        let mut k = 0;
        let mut states = self.states.iter();
        links.retain(|record| {
            let state = states.next();
            let broken =
                record.tear.zip(state).is_some_and(|(limit, s)| s.spec == record.spec && s.tension > limit);
            if broken {
                match record.handle {
                    Handle::Force(id) => world.forces.remove(id),
                    Handle::Contact(id) => world.remove_contact_generator(id),
                };
                k += 1;
            }
            !broken
        });
        self.torn += k;
    }
}

impl Scene for FileScene {
    fn info(&self) -> &SceneInfo {
        &self.definition.info
    }

    fn world(&self) -> &World {
        &self.built.world
    }

    fn world_mut(&mut self) -> &mut World {
        &mut self.built.world
    }

    fn params(&self) -> &ParamValues {
        &self.params
    }

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        let mut params = self.params.clone();
        params.set(name, value)?;
        if name == "g" && !self.built.g_elsewhere {
            // Gravity acts at once: no rebuild, the motion goes on.
            let g = build::gravity(&self.definition.doc, &self.definition.source, &params).map_err(|e| {
                ParamError::Rejected { key: name.to_string(), reason: self.definition.locate(&e).to_string() }
            })?;
            self.built
                .world
                .set_acceleration_all(Vec3::new(0.0, -g, 0.0))
                .expect("gravity was checked finite");
            for (id, float) in &mut self.built.floats {
                float.g = g.max(0.0);
                // The same particle and settings with only g changed, which was checked.
                let _ = self.built.world.forces.replace(*id, Box::new(float.clone()));
            }
            if let Some(launcher) = &mut self.launcher {
                launcher.set_gravity(&self.built.world, g);
            }
            self.params = params;
            return Ok(());
        }
        let rejected = |reason: String| ParamError::Rejected { key: name.to_string(), reason };
        let built = self.definition.build(&params).map_err(|e| rejected(e.to_string()))?;
        let built_hash = built.world.state_hash();
        let same_world = built_hash == self.built_hash && built.links.iter().all(|l| l.tear.is_none());
        if let (true, Some(launcher), Some((aim, _))) = (same_world, &mut self.launcher, built.launcher) {
            // Only the launcher's aim changed: it applies to the next round fired.
            launcher.aim = aim;
            self.params = params;
            return Ok(());
        }
        self.walls = wall_outlines(&built);
        let launcher = arm(&built);
        let running = std::mem::replace(&mut self.built, built);
        super::keep_solver(&running.world, &mut self.built.world);
        (self.launcher, self.built_hash) = (launcher, built_hash);
        self.params = params;
        self.torn = 0;
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        if let Some(launcher) = &mut self.launcher {
            launcher.before_step(&self.built.world);
        }
        let report = self.built.world.step(dt)?;
        if let Some(launcher) = &mut self.launcher {
            launcher.after_step(&mut self.built.world);
        }
        self.tear();
        Ok(report)
    }

    fn act(&mut self, action: SceneAction) -> bool {
        match (action, &mut self.launcher) {
            (SceneAction::Fire, Some(launcher)) => launcher.fire(&mut self.built.world).is_ok(),
            _ => false,
        }
    }

    /// The links still whole (a torn one's generator is gone from the world) and how
    /// many tore.
    fn save_state(&self) -> serde_json::Value {
        let whole: Vec<Handle> = self.built.links.iter().map(|l| l.handle).collect();
        match &self.launcher {
            Some(launcher) => {
                serde_json::json!({ "torn": self.torn, "whole": whole, "launcher": launcher.save_state() })
            }
            None => serde_json::json!({ "torn": self.torn, "whole": whole }),
        }
    }

    fn restore_state(&mut self, state: &super::RawValue) -> Result<(), String> {
        #[derive(serde::Deserialize)]
        struct Saved {
            torn: usize,
            whole: Vec<Handle>,
            #[serde(default)]
            launcher: Option<Box<super::RawValue>>,
        }
        let saved: Saved = super::read_state(state)?;
        match (&mut self.launcher, &saved.launcher) {
            (Some(launcher), Some(state)) => launcher.restore_state(&self.built.world, state)?,
            (None, None) => {}
            (Some(_), None) => return Err("the scene has a launcher the snapshot does not hold".into()),
            (None, Some(_)) => {
                return Err("the snapshot holds a launcher this scene file does not make".into());
            }
        }
        self.built.links.retain(|link| saved.whole.contains(&link.handle));
        if self.built.links.len() != saved.whole.len() {
            return Err("a link the snapshot keeps is not one this scene file makes".into());
        }
        self.torn = saved.torn;
        Ok(())
    }

    fn water(&self) -> Option<Water> {
        self.built.water
    }

    fn outlines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        out.extend_from_slice(&self.walls);
        if let Some(launcher) = &self.launcher {
            launcher.outlines(out);
        }
    }

    fn markers(&self, out: &mut Vec<super::Marker>) {
        if let Some(launcher) = &self.launcher {
            launcher.markers(out);
        }
    }

    fn predictions(&self, out: &mut Vec<super::Marker>) {
        if let Some(launcher) = &self.launcher {
            launcher.predictions(&self.built.world, out);
        }
    }

    fn hover_points(&self, out: &mut Vec<(Vec3, String)>) {
        if let Some(launcher) = &self.launcher {
            launcher.hover_points(out);
        }
    }

    fn exact_error(&self) -> Option<f32> {
        self.launcher.as_ref().and_then(|launcher| launcher.exact_error(&self.built.world))
    }

    fn launcher(&self) -> Option<&Launcher> {
        self.launcher.as_ref()
    }

    fn particle_colors(&self) -> &[(ParticleId, [f32; 3])] {
        &self.built.colors
    }

    fn particle_labels(&self) -> &[(ParticleId, String)] {
        &self.built.labels
    }

    fn delete_runs(&mut self, which: Option<usize>) -> bool {
        self.launcher.as_mut().map(|launcher| launcher.delete_runs(which)).is_some()
    }

    /// With walls: their patches' corners and the corners of the box the particles
    /// fill now, so that framing shows the walls and what is on them.
    fn framing_points(&self, out: &mut Vec<Vec3>) {
        if let Some(launcher) = &self.launcher {
            launcher.framing_points(out);
        }
        if self.walls.is_empty() {
            return;
        }
        for &(a, b) in &self.walls {
            out.extend([a, b]);
        }
        let (lo, hi) = particle_box(&self.built.world);
        if lo.cmple(hi).all() {
            for k in 0..8 {
                out.push(Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                ));
            }
        }
    }

    fn camera(&self) -> CameraHint {
        self.built.camera
    }

    fn labels<'a>(&'a self, out: &mut Vec<(Vec3, &'a str)>) {
        let p = &self.built.world.particles;
        for (id, name) in &self.built.labels {
            if let Some(i) = p.index(*id) {
                out.push((p.positions()[i] + Vec3::Y * (p.radii()[i] + 0.15), name));
            }
        }
        if let Some(launcher) = &self.launcher {
            launcher.labels(&self.built.world, out);
        }
    }

    fn readout_rows(&self, _dt: f32) -> Vec<super::Readout> {
        use super::Readout;
        let world = &self.built.world;
        let (particles, links) = (world.particles.len(), self.built.links.len());
        let mut out = vec![
            Readout::new("file", self.definition.shown.clone())
                .help("The scene file this scene was read from"),
            Readout::new("particles, links", format!("{particles}, {links}"))
                .with("particles", particles as f32)
                .with("links", links as f32)
                .help("Particles in the world, and the links (rods, cables, springs) the file made"),
        ];
        if self.torn > 0 || self.built.links.iter().any(|l| l.tear.is_some()) {
            out.push(
                Readout::new("links torn", self.torn.to_string())
                    .with("links_torn", self.torn as f32)
                    .help("Links whose tension passed their `tear` force and broke"),
            );
        }
        if let Some(launcher) = &self.launcher {
            out.extend(launcher.readout_rows(world));
        }
        out
    }

    fn source(&self) -> Option<(&str, Option<&Path>)> {
        Some((self.definition.source(), self.definition.path()))
    }
}

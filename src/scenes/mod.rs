//! The demos as data. Each scene builds a [`World`], declares its parameters once (the
//! panel's sliders, the `--set` flags and their validation all come from that table),
//! and adds its own rules on top of the world's step (firing rounds, moving a load).

/// The four accessors every scene writes the same way, for a scene struct with `world`
/// and `params` fields and a `static INFO`: its description, world and parameters.
macro_rules! scene_basics {
    () => {
        fn info(&self) -> &SceneInfo {
            &INFO
        }

        fn world(&self) -> &World {
            &self.world
        }

        fn world_mut(&mut self) -> &mut World {
            &mut self.world
        }

        fn params(&self) -> &ParamValues {
            &self.params
        }
    };
}

pub mod about;
mod bridge;
mod cradle;
pub mod file;
pub mod ghost;
mod granular;
pub mod heap;
pub mod hourglass;
pub mod launcher;
mod params;
mod pendulum;
pub mod pile;
mod projectile;
pub mod readout;
pub mod runs;
pub mod sketch;
pub mod snapshot;
mod spring_forces;
pub mod walls;

use std::borrow::Cow;
use std::path::Path;
use std::sync::Arc;

use glam::{Vec2, Vec3};
pub use serde_json::value::RawValue;

use crate::physics::{PhysicsError, ResolveReport, World};

pub use params::{Param, ParamError, ParamTable, ParamValues, Preset};
pub use readout::Readout;

/// How far one key press moves the bridge's load, in load coordinates (m).
pub const LOAD_STEP: f32 = 0.1;

/// The `g` parameter most scenes share: gravity pulling straight down (m/s²), from
/// weightless to three Earths. Its presets are [`GRAVITY_PRESETS`].
pub(crate) const GRAVITY: Param = Param {
    name: Cow::Borrowed("g"),
    unit: Cow::Borrowed("m/s²"),
    default: 9.81,
    min: 0.0,
    max: 30.0,
    help: Cow::Borrowed("Gravitational acceleration, downwards"),
    logarithmic: false,
    integer: false,
};

/// How a scene of a few bodies whose paths are the point is shown, the part of its
/// [`SceneInfo`] the pendulum and the springs share: the gravity presets, no actions,
/// trails on, plain colours. Name, summary, step, steps and parameters are blank here:
/// each scene gives its own (`..super::TRACED`).
pub(crate) const TRACED: SceneInfo = SceneInfo {
    name: Cow::Borrowed(""),
    summary: Cow::Borrowed(""),
    dt: 0.0,
    default_steps: 0,
    params: ParamTable::Static(&[]),
    presets: GRAVITY_PRESETS,
    actions: &[],
    trails: true,
    color_by_speed: false,
};

/// Sets every particle's acceleration to gravity `g` (m/s²) pulling straight down: what
/// the `g` parameter does to a running scene, whose range keeps it finite.
pub(crate) fn pull_down(world: &mut World, g: f32) {
    world.set_acceleration_all(Vec3::new(0.0, -g, 0.0)).expect("g is range-checked");
}

/// Sets parameter `name` to `value` in `params` (an error if out of range); `g` pulls
/// every particle of `world` down at once ([`pull_down`]). Returns whether it was any
/// other parameter, one that shapes the scene: the caller then rebuilds or rearranges it.
pub(crate) fn set_param_or_gravity(
    params: &mut ParamValues,
    world: &mut World,
    name: &str,
    value: f32,
) -> Result<bool, ParamError> {
    params.set(name, value)?;
    if name == "g" {
        pull_down(world, value);
        return Ok(false);
    }
    Ok(true)
}

/// Sets the damping (fraction of velocity kept per second) of every particle of
/// `world`: what a scene's `damping` parameter does, whose range keeps it valid.
pub(crate) fn damp_all(world: &mut World, damping: f32) {
    for id in world.particles.ids().to_vec() {
        world.particles.set_damping(id, damping).expect("damping is range-checked");
    }
}

/// Gives `restarted`, a scene's world built again for new parameters, the solver
/// settings of `running`, the world it replaces: the solver the user picked outlives
/// a restart.
pub(crate) fn keep_solver(running: &World, restarted: &mut World) {
    restarted.set_solver(*running.solver()).expect("the running world's settings were valid");
}

/// Surface gravity of a few worlds (m/s²), as presets that set `g` alone.
#[rustfmt::skip]
pub static GRAVITY_PRESETS: &[Preset] = &[
    Preset { name: "Earth", help: "g = 9.81 m/s²", values: &[("g", 9.81)] },
    Preset { name: "Moon", help: "g = 1.62 m/s²", values: &[("g", 1.62)] },
    Preset { name: "Mars", help: "g = 3.71 m/s²", values: &[("g", 3.71)] },
    Preset { name: "Jupiter", help: "g = 24.79 m/s² (at the cloud tops)", values: &[("g", 24.79)] },
];

/// Description of a scene: a compiled scene's is a static, a scene file's is part of
/// the loaded file.
#[derive(Debug)]
pub struct SceneInfo {
    /// Name used on the command line and in the Scene menu (the paper's name).
    pub name: Cow<'static, str>,
    /// One line saying what it shows.
    pub summary: Cow<'static, str>,
    /// Physics time step used unless the user picks another (s).
    pub dt: f32,
    /// Steps `simulate` runs unless told otherwise.
    pub default_steps: u32,
    /// The parameter table.
    pub params: ParamTable,
    /// Named sets of parameter values (e.g. ammo types).
    pub presets: &'static [Preset],
    /// Actions the scene offers, with the key that triggers them in the window.
    pub actions: &'static [ActionInfo],
    /// Whether trails help here (they clutter a scene that barely moves).
    pub trails: bool,
    /// Whether particles are best coloured by speed (many alike particles, where what
    /// matters is which still move).
    pub color_by_speed: bool,
}

/// Something a user can do to a running scene besides changing parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SceneAction {
    /// Fire a new round with the current parameters (projectile).
    Fire,
    /// Move the load by this much in load coordinates (bridge).
    MoveLoad {
        /// Along the bridge.
        dx: f32,
        /// Across the bridge.
        dz: f32,
    },
}

/// A button the panel shows for a scene action.
#[derive(Clone, Copy, Debug)]
pub struct ActionInfo {
    /// Button label.
    pub label: &'static str,
    /// The key that does the same, as shown to the user.
    pub key: &'static str,
    /// The action.
    pub action: SceneAction,
}

/// A rectangle of liquid surface to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Water {
    /// Surface height (m).
    pub height: f32,
    /// Centre of the pool in x and z (m).
    pub center: Vec2,
    /// Half size of the pool in x and z (m).
    pub half_extent: Vec2,
}

/// An extra sphere to draw that is not a particle (e.g. the bridge's load).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marker {
    /// Centre (m).
    pub position: Vec3,
    /// Radius (m).
    pub radius: f32,
    /// Linear RGB colour.
    pub color: [f32; 3],
}

/// Where a camera should look to frame a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraHint {
    /// Point looked at (m).
    pub target: Vec3,
    /// Distance from the target (m).
    pub distance: f32,
    /// Rotation about the vertical axis (radians); 0 looks along -z.
    pub yaw: f32,
    /// Elevation (radians), positive looks down.
    pub pitch: f32,
}

/// A running scene: a world plus the scene's own rules and parameters.
pub trait Scene: Send {
    /// The scene's description.
    fn info(&self) -> &SceneInfo;

    /// The world, for reading.
    fn world(&self) -> &World;

    /// The world, for interaction such as dragging a particle.
    fn world_mut(&mut self) -> &mut World;

    /// Current parameter values.
    fn params(&self) -> &ParamValues;

    /// Changes one parameter; takes effect at once where it can (gravity, load) or on
    /// the next round (projectile launch settings), otherwise rebuilds the world.
    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError>;

    /// Advances the scene by `dt` seconds.
    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError>;

    /// Performs an action; false if this scene has no such action.
    fn act(&mut self, _action: SceneAction) -> bool {
        false
    }

    /// A liquid surface to draw, if the scene has one.
    fn water(&self) -> Option<Water> {
        None
    }

    /// Extra spheres to draw.
    fn markers(&self, _out: &mut Vec<Marker>) {}

    /// What the scene predicts, drawn over it: the ghost following the exact solution,
    /// the drag-free path of the next round. View → Predictions off (so a class
    /// predicts before it measures) leaves them out, as it does the predicted read-outs.
    fn predictions(&self, _out: &mut Vec<Marker>) {}

    /// Where to put the camera initially.
    fn camera(&self) -> CameraHint;

    /// Height of the ground the view draws under the scene (m): y = 0 but where the
    /// scene reaches below it (the hourglass's basin lies under its floor at y = 0).
    fn ground(&self) -> f32 {
        0.0
    }

    /// The read-outs at the integrator's step `dt` (s): each panel row with the numbers
    /// it shows, e.g. a spring's stability number ω·dt. `simulate` prints the numbers.
    fn readout_rows(&self, _dt: f32) -> Vec<Readout> {
        Vec::new()
    }

    /// The read-outs as the panel writes them: (label, text) per row.
    fn readouts(&self, dt: f32) -> Vec<(String, String)> {
        self.readout_rows(dt).into_iter().map(|row| (row.label.to_string(), row.text)).collect()
    }

    /// The read-outs' numbers by key, in the panel's order, as `simulate` prints them.
    fn readout_values(&self, dt: f32) -> Vec<(&'static str, f64)> {
        self.readout_rows(dt).into_iter().flat_map(|row| row.values).collect()
    }

    /// Edges to draw that are not links (m): the outline of a box's walls.
    fn outlines(&self, _out: &mut Vec<(Vec3, Vec3)>) {}

    /// A vertical ruler the 3D view draws beside the scene (springForces' beside its
    /// bob), ticked every half metre with a mark at each metre. The side view leaves it
    /// out: its own height scale measures the same thing, and two would disagree.
    fn ruler(&self) -> Option<Ruler> {
        None
    }

    /// Names of the scene's objects, at the points to write them (the view's labels):
    /// the bob, the launcher, the load. Links are labelled by kind without help.
    fn labels<'a>(&'a self, _out: &mut Vec<(Vec3, &'a str)>) {}

    /// A warning to show under a parameter's slider, given the integrator's step `h`
    /// (s): e.g. a spring's stability number approaching its limit, before it blows up.
    fn param_warning(&self, _name: &str, _h: f32) -> Option<String> {
        None
    }

    /// Points the pointer can hover for a tooltip, with its text: a projectile's path
    /// points and its launch, apex and landing, with time, range and height.
    fn hover_points(&self, _out: &mut Vec<(Vec3, String)>) {}

    /// Points (m) a camera framing the scene should keep in view besides its particles:
    /// the projectile's predicted path down to its landing, and its target.
    fn framing_points(&self, _out: &mut Vec<Vec3>) {}

    /// The height (m) the energy bars and plot measure gravitational energy from, and
    /// what stands there, where the ground (y = 0) would hide the exchange the scene
    /// shows: a cradle's balls swap a joule of height while hanging 0.6 m up, 30 J
    /// above the ground. `None`: the ground.
    fn gravity_reference(&self) -> Option<(f32, &'static str)> {
        None
    }

    /// The particle whose energy the bars show until the user picks another (or the
    /// scene), and its name: springForces' bob, whose joules its stiff spring's
    /// kilojoules would swamp. `None`: the whole scene.
    fn energy_focus(&self) -> Option<(crate::physics::ParticleId, &'static str)> {
        None
    }

    /// Distance from the exact answer (m) where the scene has a closed form: the newest
    /// round's or the bob's distance from its ghost. Plotted live beside the energy.
    fn exact_error(&self) -> Option<f32> {
        None
    }

    /// Whether a snapshot's world must still hold `id`, a particle of the scene as
    /// built, with the same movability: the scene's rules act on its own particles by
    /// id (the bob, the bridge's deck). A scene whose particles come and go (the
    /// projectile's rounds, removed as they land) says `false` for those; its
    /// [`Scene::restore_state`] checks what it names instead.
    fn keeps_particle(&self, _id: crate::physics::ParticleId) -> bool {
        true
    }

    /// What the scene keeps beside its world and parameters (rounds in flight and when
    /// they were fired, ghosts of the exact answer, a stopwatch), as a snapshot saves
    /// it; `null` for a scene that keeps nothing.
    fn save_state(&self) -> serde_json::Value {
        serde_json::Value::Null
    }

    /// Takes back what [`Scene::save_state`] gave, after the snapshot's world has
    /// replaced the built one. The error says which part is wrong. A scene that keeps
    /// nothing takes only `null`: anything else was not written by it.
    ///
    /// The state comes as its JSON text, unparsed: each scene reads it into its own
    /// types ([`read_state`]), so a huge array costs what its values do, not a tree of
    /// JSON values many times the file's size.
    fn restore_state(&mut self, state: &RawValue) -> Result<(), String> {
        if state.get() == "null" {
            Ok(())
        } else {
            Err(format!("{} keeps no state beside its world, so it must be null", self.info().name))
        }
    }

    /// The scene's launcher, if it fires rounds (the projectile, a file's
    /// `[launcher]`).
    fn launcher(&self) -> Option<&launcher::Launcher> {
        None
    }

    /// Colours the scene gives particles, by id in ascending order (a scene file's
    /// `color`); the others take the lab's palette.
    fn particle_colors(&self) -> &[(crate::physics::ParticleId, [f32; 3])] {
        &[]
    }

    /// The names the scene gives single particles (a scene file's `name`), by id.
    fn particle_labels(&self) -> &[(crate::physics::ParticleId, String)] {
        &[]
    }

    /// The scene's table of runs, if it keeps one: a row for each completed
    /// measurement.
    fn runs(&self) -> Option<runs::Table<'_>> {
        self.launcher().map(launcher::Launcher::runs)
    }

    /// Deletes run `k` of the table, or every run with `None`; false if the scene
    /// keeps no table.
    fn delete_runs(&mut self, _which: Option<usize>) -> bool {
        false
    }

    /// The text the scene was built from and the file it was read from, for a scene
    /// loaded from a file (the path is `None` for a shipped scene built in).
    fn source(&self) -> Option<(&str, Option<&Path>)> {
        None
    }
}

/// A vertical ruler standing on the ground (see [`Scene::ruler`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ruler {
    /// Its foot (m), on the ground.
    pub foot: Vec3,
    /// Its height (m).
    pub height: f32,
}

impl Ruler {
    /// Its line and ticks (m): a tick every half metre, longer at each metre.
    pub fn lines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        out.push((self.foot, self.foot + Vec3::Y * self.height));
        for half_metres in 0..=(self.height * 2.0).floor() as usize {
            let at = self.foot + Vec3::Y * (half_metres as f32 * 0.5);
            let tick = if half_metres % 2 == 0 { 0.3 } else { 0.15 };
            out.push((at, at + Vec3::X * tick));
        }
    }

    /// Its marks: each whole metre from the foot, the point of its tick and its text.
    #[must_use]
    pub fn marks(&self) -> Vec<(Vec3, String)> {
        (0..=self.height.floor() as u32).map(|m| (self.foot + Vec3::Y * m as f32, format!("{m} m"))).collect()
    }
}

/// A scene in the registry: its description and how to build it. A handle, cheap to
/// clone: a compiled scene's is two pointers into the binary; a scene file's shares the
/// loaded file with every clone and every scene built from it, and the file is freed
/// when the last of them is dropped (a reload or an edit keeps no old copy).
#[derive(Clone)]
pub enum SceneEntry {
    /// A scene compiled into the binary.
    Compiled {
        /// The description.
        info: &'static SceneInfo,
        /// Builds the scene with the given (already validated) parameter values.
        create: fn(ParamValues) -> Box<dyn Scene>,
    },
    /// A scene loaded from a file.
    File(Arc<file::Definition>),
}

impl SceneEntry {
    /// The description.
    #[must_use]
    pub fn info(&self) -> &SceneInfo {
        match self {
            Self::Compiled { info, .. } => info,
            Self::File(definition) => definition.info(),
        }
    }

    /// Builds the scene with the given (already validated) parameter values. A scene
    /// file that cannot be built with them (values reach here only once a build with
    /// them has worked) is built with its defaults, which were built when it loaded,
    /// with a warning; [`create_entry`] says why instead.
    #[must_use]
    pub fn create(&self, values: ParamValues) -> Box<dyn Scene> {
        match self {
            Self::Compiled { create, .. } => create(values),
            Self::File(definition) => definition.create(values).unwrap_or_else(|error| {
                log::warn!("{error}; using the defaults");
                let defaults = ParamValues::defaults(&definition.info().params);
                definition.create(defaults).expect("the defaults were built at load")
            }),
        }
    }

    /// Builds the scene with its default parameters.
    #[must_use]
    pub fn create_default(&self) -> Box<dyn Scene> {
        self.create(ParamValues::defaults(&self.info().params))
    }

    /// Whether `other` is this very entry or a clone of it: the same compiled scene, or
    /// the same load of a file (a file loaded twice makes two entries).
    #[must_use]
    pub fn same(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::Compiled { info: a, .. }, Self::Compiled { info: b, .. }) => std::ptr::eq(*a, *b),
            (Self::File(a), Self::File(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

impl std::fmt::Debug for SceneEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Compiled { info, .. } => f.debug_tuple("Compiled").field(&info.name).finish(),
            Self::File(definition) => f.debug_tuple("File").field(definition).finish(),
        }
    }
}

/// Every scene, in menu order.
pub static SCENES: &[SceneEntry] = &[
    projectile::ENTRY,
    spring_forces::ENTRY,
    bridge::ENTRY,
    pile::ENTRY,
    pendulum::ENTRY,
    cradle::ENTRY,
    hourglass::ENTRY,
    heap::ENTRY,
];

/// Looks a scene up by name, forgiving case, `-` and `_` (so `spring-forces` works):
/// the compiled scenes, then the shipped scene files.
pub fn find(name: &str) -> Result<&'static SceneEntry, String> {
    let simplify = |s: &str| s.chars().filter(|c| *c != '-' && *c != '_').collect::<String>().to_lowercase();
    let wanted = simplify(name);
    let found = SCENES.iter().chain(file::shipped()).find(|entry| simplify(&entry.info().name) == wanted);
    found.ok_or_else(|| {
        format!(
            "unknown scene '{}'; valid scenes: {}",
            crate::messages::quote(name),
            scene_names().join(", ")
        )
    })
}

/// Builds a registered scene with its defaults.
///
/// # Panics
/// If no scene has that name; for names a user typed, use [`build`].
#[must_use]
pub fn create_default(name: &str) -> Box<dyn Scene> {
    find(name).expect("scene is registered").create_default()
}

/// Names of every scene, in menu order: the compiled ones, then the shipped files.
#[must_use]
pub fn scene_names() -> Vec<&'static str> {
    SCENES.iter().chain(file::shipped()).map(|e| &*e.info().name).collect()
}

/// Builds a scene by name with `KEY=VALUE` assignments applied over its defaults.
pub fn build(name: &str, assignments: &[String]) -> Result<Box<dyn Scene>, String> {
    build_entry(find(name)?, assignments)
}

/// Builds a scene with `KEY=VALUE` assignments applied over its defaults. A file
/// scene that cannot be built with them says where in the file and why.
pub fn build_entry(entry: &SceneEntry, assignments: &[String]) -> Result<Box<dyn Scene>, String> {
    let mut values = ParamValues::defaults(&entry.info().params);
    for assignment in assignments {
        values.assign(assignment).map_err(|e| e.to_string())?;
    }
    create_entry(entry, values)
}

/// Builds a scene with (already validated) values; a scene file that cannot be built
/// with them says why ([`SceneEntry::create`] would fall back to the defaults).
pub fn create_entry(entry: &SceneEntry, values: ParamValues) -> Result<Box<dyn Scene>, String> {
    match entry {
        SceneEntry::Compiled { create, .. } => Ok(create(values)),
        SceneEntry::File(definition) => definition.create(values).map_err(|e| e.to_string()),
    }
}

/// Whether a headless run starting on `scene` fires a round first: the scene has a
/// launcher that fires at the start (the projectile's does; a file's `[launcher]` unless
/// `fire_at_start = false`), it has fired none, and the world is at step 0.
#[must_use]
pub fn fires_at_start(scene: &dyn Scene) -> bool {
    let ready = scene.launcher().is_some_and(|l| l.fire_at_start && l.fired_none());
    ready && scene.world().steps() == 0
}

/// The start of a headless run (`simulate`, `render`, a link with `steps`): fires one
/// round, as pressing F at step 0 would, when [`fires_at_start`] says so. The window
/// never calls it: there nothing flies until the user fires. Returns whether it fired.
pub fn fire_at_start(scene: &mut dyn Scene) -> bool {
    fires_at_start(scene) && scene.act(SceneAction::Fire)
}

/// A scene's saved state ([`Scene::restore_state`]) read straight from its JSON text
/// into the scene's own type `T`; the error is serde's, in one line.
pub(crate) fn read_state<T: serde::de::DeserializeOwned>(state: &RawValue) -> Result<T, String> {
    serde_json::from_str(state.get()).map_err(|e| crate::messages::one_line(&e.to_string()))
}

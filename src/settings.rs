//! Settings that persist: how the window was left (the scene and its parameters, the
//! solver, integrator and physics rate, the view toggles, the camera, the window's size
//! and the panel) is written to a versioned JSON file in the platform's config
//! directory (`$XDG_CONFIG_HOME/particle-lab/settings.json`, else
//! `~/.config/particle-lab/settings.json`, on Linux) and comes back at the next launch.
//!
//! Only the window reads and writes it; `simulate` and `render` never do. It is written
//! on exit and, when something changed, every [`AUTOSAVE_INTERVAL`], so a window that is
//! killed keeps nearly all of it.
//!
//! What comes back, and what wins:
//! - `--fresh` starts from the defaults and does not read the file (it is replaced on
//!   exit with what that session leaves).
//! - `--scene`, `--set`, `--solver`, `--substeps` and `--integrator`, when typed, win
//!   over the saved values, each on its own. The saved parameters, physics rate, camera,
//!   trails and colour by speed belong to the saved scene: they come back only when the
//!   window opens on that scene (with `--set` applied over them).
//! - A file that is not valid JSON, has a wrong type, an unknown field, an unknown
//!   scene or parameter, a value out of its range, or a newer (or no) version is moved
//!   aside to `settings.json.bad` with one warning line, and the window starts from the
//!   defaults: a file is used whole or not at all. A toggle or parameter missing from
//!   an otherwise valid file takes its default (a file from before it existed).
//! - A scene opened from a file of the user's (`--scene-file`, File → Open) is saved by
//!   its absolute path as well as its name, and that file is opened again at the next
//!   launch. The file is the user's to move or edit: if it is gone or no longer loads,
//!   one warning line says so and the window starts on [`DEFAULT_SCENE`] with the rest
//!   of the settings; if the saved values no longer fit it, it opens with its defaults
//!   and one warning line. The settings file is not set aside for either.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::cli::Cli;
use crate::physics::solver::SUBSTEP_RANGE;
use crate::physics::{Integrator, SolverKind, SolverSettings};
use crate::render::ViewOptions;
use crate::scenes::{self, ParamValues, SceneEntry};
use crate::ui::Lab;
use crate::ui::lab::{MSAA_LIMIT, PHYSICS_RATE_RANGE, TIME_SCALE_RANGE};

/// The file format's version; a file with a larger one is set aside, not guessed at.
pub const VERSION: u32 = 1;
/// The settings file's name inside the config directory.
pub const FILE_NAME: &str = "settings.json";
/// The scene the window opens on when nothing says otherwise.
pub const DEFAULT_SCENE: &str = "projectile";
/// The window's size at the first launch (logical pixels).
pub const DEFAULT_WINDOW: [u32; 2] = [1280, 720];
/// Smallest window the lab opens (logical pixels), as the window's minimum size.
pub const MIN_WINDOW: [u32; 2] = [320, 240];
/// Largest window side accepted from the file (logical pixels).
pub const MAX_WINDOW_SIDE: u32 = 16_384;
/// Largest settings file read (bytes): a real one is about 1 KB.
pub const MAX_FILE_BYTES: u64 = 1 << 20;
/// How often the window checks whether the settings changed and writes them if so.
pub const AUTOSAVE_INTERVAL: Duration = Duration::from_secs(2);
/// Largest camera distance or coordinate accepted from the file (m): far beyond any
/// scene, small enough that a typo like `1e30` is caught.
const MAX_CAMERA_EXTENT: f32 = 1e6;
/// Nearest camera distance accepted from the file (m); the wheel stops at 0.5 m.
const MIN_CAMERA_DISTANCE: f32 = 1e-3;

/// Everything that persists, as written to the file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// The format's version, [`VERSION`].
    pub version: u32,
    /// The last scene, by its registry name.
    pub scene: String,
    /// The file the last scene was opened from (absolute), when it was a file of the
    /// user's rather than a compiled or shipped scene, which the name finds. Absent from
    /// files written before it existed and for named scenes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_file: Option<String>,
    /// Its parameter values by name; a parameter missing here takes its default.
    pub params: BTreeMap<String, f32>,
    /// Solver, substeps and integrator.
    pub solver: SolverChoice,
    /// Physics steps per simulated second (Hz), 30 to 1000.
    pub physics_rate: f32,
    /// Simulated seconds per real second, 0.05 to 4.
    pub time_scale: f32,
    /// The View menu's toggles.
    pub view: ViewSettings,
    /// The camera.
    pub camera: CameraSettings,
    /// The window's inner size.
    pub window: WindowSize,
    /// The side panel.
    pub panel: PanelSettings,
}

/// The solver choice, by the names the command line takes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverChoice {
    /// `soft` or `paper`.
    pub kind: String,
    /// Substeps of the soft solver, 1 to 64.
    pub substeps: u32,
    /// `explicit-euler`, `semi-implicit-euler`, `verlet` or `rk4`.
    pub integrator: String,
}

/// The View menu's toggles; one missing from the file takes its default.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ViewSettings {
    /// Trails behind moving particles.
    pub trails: bool,
    /// Swept paths of the last step.
    pub swept_paths: bool,
    /// Links coloured by tension.
    pub tension_colors: bool,
    /// Particles coloured by speed.
    pub color_by_speed: bool,
    /// Grid on the ground.
    pub grid: bool,
    /// The stats block.
    pub stats: bool,
    /// 4x MSAA.
    pub msaa: bool,
    /// Names and metre ticks.
    pub labels: bool,
    /// Force arrows on the selected particle.
    pub forces: bool,
    /// Vectors on every particle.
    pub all_vectors: bool,
    /// Contacts and link limits.
    pub contacts: bool,
    /// The 2D side view.
    pub side_view: bool,
    /// The camera follows the selected (or newest) particle.
    pub follow: bool,
}

impl Default for ViewSettings {
    fn default() -> Self {
        Self::new(&ViewOptions::default(), false, false)
    }
}

impl ViewSettings {
    fn new(view: &ViewOptions, side_view: bool, follow: bool) -> Self {
        Self {
            trails: view.trails,
            swept_paths: view.swept,
            tension_colors: view.tension_colors,
            color_by_speed: view.color_by_speed,
            grid: view.grid,
            stats: view.stats,
            msaa: view.msaa,
            labels: view.labels,
            forces: view.forces,
            all_vectors: view.all_vectors,
            contacts: view.contacts,
            side_view,
            follow,
        }
    }

    /// The toggles as the renderer takes them, over `base` (so a toggle this file does
    /// not know keeps the base's value).
    fn options(&self, base: ViewOptions) -> ViewOptions {
        let mut view = base;
        view.trails = self.trails;
        view.swept = self.swept_paths;
        view.tension_colors = self.tension_colors;
        view.color_by_speed = self.color_by_speed;
        view.grid = self.grid;
        view.stats = self.stats;
        view.msaa = self.msaa;
        view.labels = self.labels;
        view.forces = self.forces;
        view.all_vectors = self.all_vectors;
        view.contacts = self.contacts;
        view
    }

    /// The names of the toggles that are on, for the log.
    fn on(&self) -> Vec<&'static str> {
        let toggles = [
            (self.trails, "trails"),
            (self.swept_paths, "swept"),
            (self.tension_colors, "tension"),
            (self.color_by_speed, "speed-colours"),
            (self.grid, "grid"),
            (self.stats, "stats"),
            (self.msaa, "msaa"),
            (self.labels, "labels"),
            (self.forces, "forces"),
            (self.all_vectors, "all-vectors"),
            (self.contacts, "contacts"),
            (self.side_view, "side"),
            (self.follow, "follow"),
        ];
        toggles.into_iter().filter(|(on, _)| *on).map(|(_, name)| name).collect()
    }
}

/// The orbit camera.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSettings {
    /// The user orbited, panned or zoomed: the camera comes back as it was. Otherwise
    /// the scene is framed afresh for the window it opens in.
    pub moved: bool,
    /// Point looked at (m).
    pub target: [f32; 3],
    /// Distance from the target (m).
    pub distance: f32,
    /// Rotation about the vertical axis (radians).
    pub yaw: f32,
    /// Elevation of the eye (radians), -π/2 to π/2.
    pub pitch: f32,
}

/// The window's inner size (logical pixels).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindowSize {
    /// Width, 320 to 16384.
    pub width: u32,
    /// Height, 240 to 16384.
    pub height: u32,
}

/// The side panel; a field missing from the file takes its default.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PanelSettings {
    /// The side panel is shown (P hides it).
    pub open: bool,
    /// The Controls window is open.
    pub help: bool,
    /// The Compare section is expanded.
    pub compare: bool,
}

impl Default for PanelSettings {
    fn default() -> Self {
        Self { open: true, help: false, compare: false }
    }
}

/// A settings file's values after validation: what [`Settings`] names, found.
struct Resolved {
    /// The saved scene when it is found by name; `None` for a scene file, which is
    /// opened (and its parameters checked) only when the window opens on it.
    entry: Option<&'static SceneEntry>,
    solver: SolverSettings,
}

impl Settings {
    /// What persists of `lab`, in a window `window` logical pixels large.
    #[must_use]
    pub fn of(lab: &Lab, window: [u32; 2]) -> Self {
        let solver = lab.solver();
        let camera = lab.camera;
        Self {
            version: VERSION,
            scene: lab.entry.info.name.to_string(),
            scene_file: scene_file_of(lab.entry),
            params: lab.scene.params().iter().map(|(param, value)| (param.name.to_string(), value)).collect(),
            solver: SolverChoice {
                kind: solver.kind.name().to_string(),
                substeps: solver.substeps,
                integrator: solver.integrator.name().to_string(),
            },
            physics_rate: lab.physics_rate,
            time_scale: lab.time_scale,
            view: ViewSettings::new(&lab.view, lab.side_view, lab.follow),
            camera: CameraSettings {
                moved: lab.camera_moved,
                target: camera.target.to_array(),
                distance: camera.distance,
                yaw: camera.yaw,
                pitch: camera.pitch,
            },
            window: WindowSize { width: window[0], height: window[1] },
            panel: PanelSettings { open: lab.panel_open, help: lab.show_help, compare: lab.compare_open },
        }
    }

    /// Reads settings from the text of a file, checking every value; the error is one
    /// line saying what is wrong and where.
    pub fn parse(text: &str) -> Result<Self, String> {
        // The version first: a newer file may be valid in a shape this build cannot read.
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| format!("not valid JSON: {e}"))?;
        let version = match value.get("version") {
            Some(serde_json::Value::Number(n)) => n.as_u64(),
            None => return Err("it has no version number".into()),
            Some(_) => None,
        };
        match version {
            Some(v) if v == u64::from(VERSION) => {}
            Some(v) if v > u64::from(VERSION) => {
                return Err(format!(
                    "it is version {v}, from a newer particle-lab (this one reads version {VERSION})"
                ));
            }
            _ => return Err(format!("its version is {}, not a version this build knows", value["version"])),
        }
        let settings: Self = serde_json::from_str(text).map_err(|e| e.to_string())?;
        settings.resolve()?;
        Ok(settings)
    }

    /// The settings as the file's text: pretty JSON, so a person can read and edit it.
    #[must_use]
    pub fn to_text(&self) -> String {
        let mut text = serde_json::to_string_pretty(self).expect("settings are plain data with string keys");
        text.push('\n');
        text
    }

    /// Checks every value and finds what the names name.
    fn resolve(&self) -> Result<Resolved, String> {
        let entry = match &self.scene_file {
            Some(path) if path.is_empty() => return Err("scene_file is empty".into()),
            Some(_) => None,
            None => {
                let entry = scenes::find(&self.scene).map_err(|e| format!("scene: {e}"))?;
                let mut params = ParamValues::defaults(entry.info.params);
                for (name, value) in &self.params {
                    params.set(name, *value).map_err(|e| format!("params of {}: {e}", entry.info.name))?;
                }
                Some(entry)
            }
        };
        let kind = SolverKind::parse(&self.solver.kind).map_err(|e| format!("solver.kind: {e}"))?;
        if !SUBSTEP_RANGE.contains(&self.solver.substeps) {
            return Err(format!(
                "solver.substeps = {} is out of range; valid range: {} to {}",
                self.solver.substeps,
                SUBSTEP_RANGE.start(),
                SUBSTEP_RANGE.end()
            ));
        }
        let integrator =
            Integrator::parse(&self.solver.integrator).map_err(|e| format!("solver.integrator: {e}"))?;
        in_range("physics_rate", self.physics_rate, *PHYSICS_RATE_RANGE.start(), *PHYSICS_RATE_RANGE.end())?;
        in_range("time_scale", self.time_scale, *TIME_SCALE_RANGE.start(), *TIME_SCALE_RANGE.end())?;
        let camera = &self.camera;
        for (axis, value) in ["x", "y", "z"].into_iter().zip(camera.target) {
            in_range(&format!("camera.target.{axis}"), value, -MAX_CAMERA_EXTENT, MAX_CAMERA_EXTENT)?;
        }
        in_range("camera.distance", camera.distance, MIN_CAMERA_DISTANCE, MAX_CAMERA_EXTENT)?;
        in_range("camera.yaw", camera.yaw, -MAX_CAMERA_EXTENT, MAX_CAMERA_EXTENT)?;
        let quarter = std::f32::consts::FRAC_PI_2;
        in_range("camera.pitch", camera.pitch, -quarter, quarter)?;
        for (name, value, min) in [
            ("window.width", self.window.width, MIN_WINDOW[0]),
            ("window.height", self.window.height, MIN_WINDOW[1]),
        ] {
            if !(min..=MAX_WINDOW_SIDE).contains(&value) {
                return Err(format!(
                    "{name} = {value} is out of range; valid range: {min} to {MAX_WINDOW_SIDE}"
                ));
            }
        }
        let solver =
            SolverSettings { kind, substeps: self.solver.substeps, integrator, ..SolverSettings::default() };
        solver.validate().map_err(|e| format!("solver: {e}"))?;
        Ok(Resolved { entry, solver })
    }

    /// One line saying what the settings hold, for the log.
    #[must_use]
    pub fn describe(&self) -> String {
        let params: Vec<String> = self.params.iter().map(|(name, value)| format!("{name}={value}")).collect();
        let solver = match self.solver.kind.as_str() {
            "soft" => format!("soft ({} substeps)", self.solver.substeps),
            other => other.to_string(),
        };
        let c = &self.camera;
        let camera = if c.moved {
            format!(
                "camera moved (target {:.2},{:.2},{:.2}, distance {:.2}, yaw {:.2}, pitch {:.2})",
                c.target[0], c.target[1], c.target[2], c.distance, c.yaw, c.pitch
            )
        } else {
            "camera framed".to_string()
        };
        let file = self.scene_file.as_ref().map_or_else(String::new, |path| format!(" (file {path})"));
        format!(
            "scene {}{file} [{}], solver {solver}, integrator {}, rate {} Hz, time scale {}, view [{}], {camera}, \
             window {}x{}, panel {}, help {}, compare {}",
            self.scene,
            params.join(" "),
            self.solver.integrator,
            // 1 / (1/240) in f32 is 239.99998: the log shows it as the panel does.
            (self.physics_rate * 1000.0).round() / 1000.0,
            self.time_scale,
            self.view.on().join(" "),
            self.window.width,
            self.window.height,
            if self.panel.open { "shown" } else { "hidden" },
            if self.panel.help { "open" } else { "closed" },
            if self.panel.compare { "open" } else { "closed" },
        )
    }
}

/// Where a scene opened from a file of the user's lives, absolute (so a launch from
/// another directory finds it), to open it again by; `None` for a compiled or shipped
/// scene, which its name finds.
fn scene_file_of(entry: &SceneEntry) -> Option<String> {
    if scenes::file::shipped().iter().any(|shipped| std::ptr::eq(*shipped, entry)) {
        return None;
    }
    let path = scenes::file::definition(entry)?.path()?;
    let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    Some(path.to_string_lossy().into_owned())
}

/// Why a scene file did not load, without its name (the warning names it already).
fn file_reason(error: &scenes::file::FileError) -> String {
    let message = crate::messages::one_line(&error.message);
    match error.position {
        Some((line, column)) => format!("line {line}, column {column}: {message}"),
        None => message,
    }
}

/// Refuses a value that is not finite or outside `min..=max`, naming the field.
fn in_range(name: &str, value: f32, min: f32, max: f32) -> Result<(), String> {
    if value.is_finite() && (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(format!("{name} = {value} is out of range; valid range: {min} to {max}"))
    }
}

/// What the command line asked the window for. A solver flag that was not typed is
/// `None`, so the saved choice is used rather than the flag's default.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Launch {
    /// `--scene`.
    pub scene: Option<String>,
    /// `--scene-file`.
    pub scene_file: Option<std::path::PathBuf>,
    /// `--set KEY=VALUE`, in order.
    pub set: Vec<String>,
    /// `--solver`.
    pub solver: Option<SolverKind>,
    /// `--substeps`.
    pub substeps: Option<u32>,
    /// `--integrator`.
    pub integrator: Option<Integrator>,
    /// `--fresh`: start from the defaults, without reading the settings file.
    pub fresh: bool,
    /// `--from FILE`: open on this snapshot (the saved view and window still apply).
    pub from: Option<std::path::PathBuf>,
}

impl Launch {
    /// The window's flags from the parsed command line. Which solver flags were typed
    /// is read from the process's arguments again, since clap fills in their defaults.
    pub fn from_cli(cli: &Cli) -> Result<Self, String> {
        let solver = cli.solver.settings()?;
        let typed = typed_solver_flags();
        Ok(Self {
            scene: cli.scene.clone(),
            scene_file: cli.scene_file.clone(),
            set: cli.set.clone(),
            solver: typed[0].then_some(solver.kind),
            substeps: typed[1].then_some(solver.substeps),
            integrator: typed[2].then_some(solver.integrator),
            fresh: cli.fresh,
            from: cli.from.clone(),
        })
    }

    /// The solver flags over `base`.
    fn solver_over(&self, base: SolverSettings) -> SolverSettings {
        SolverSettings {
            kind: self.solver.unwrap_or(base.kind),
            substeps: self.substeps.unwrap_or(base.substeps),
            integrator: self.integrator.unwrap_or(base.integrator),
            ..base
        }
    }

    /// The flags typed, for the log.
    fn typed(&self) -> Vec<&'static str> {
        let flags = [
            (self.scene.is_some(), "--scene"),
            (self.scene_file.is_some(), "--scene-file"),
            (!self.set.is_empty(), "--set"),
            (self.solver.is_some(), "--solver"),
            (self.substeps.is_some(), "--substeps"),
            (self.integrator.is_some(), "--integrator"),
        ];
        flags.into_iter().filter(|(typed, _)| *typed).map(|(_, flag)| flag).collect()
    }
}

/// Whether `--solver`, `--substeps` and `--integrator` were typed on this process's
/// command line (as opposed to filled in with their defaults).
fn typed_solver_flags() -> [bool; 3] {
    use clap::CommandFactory;
    use clap::parser::ValueSource;
    match Cli::command().try_get_matches_from(std::env::args_os()) {
        Ok(matches) => ["solver", "substeps", "integrator"]
            .map(|id| matches.value_source(id) == Some(ValueSource::CommandLine)),
        // Parsed once already, so this does not happen; if it did, the flags win.
        Err(_) => [true; 3],
    }
}

/// What reading the settings file found.
#[derive(Clone, Debug, PartialEq)]
pub enum Loaded {
    /// No file (a first launch), or no config directory to look in.
    Missing,
    /// A valid file.
    Restored(Settings),
    /// A file that could not be used: set aside, with the one warning line to print.
    Unusable {
        /// `particle-lab: ...`, saying what was wrong and where the file went.
        warning: String,
    },
}

/// The settings file: where it is, and what was last written to it.
#[derive(Debug)]
pub struct Store {
    path: Option<PathBuf>,
    written: Option<Settings>,
    checked: Instant,
    save_failed: bool,
}

impl Store {
    /// The file in the platform's config directory (on Linux `$XDG_CONFIG_HOME`, else
    /// `~/.config`, then `particle-lab/settings.json`); none if there is no home.
    #[must_use]
    pub fn from_platform() -> Self {
        let dirs = directories::ProjectDirs::from("", "", "particle-lab");
        Self::with_path(dirs.map(|dirs| dirs.config_dir().join(FILE_NAME)))
    }

    /// The file `FILE_NAME` in `directory` (for tests).
    #[must_use]
    pub fn in_dir(directory: &Path) -> Self {
        Self::with_path(Some(directory.join(FILE_NAME)))
    }

    fn with_path(path: Option<PathBuf>) -> Self {
        Self { path, written: None, checked: Instant::now(), save_failed: false }
    }

    /// Where the settings live, if anywhere.
    #[must_use]
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// Where an unusable file is moved: `settings.json.bad` beside it.
    #[must_use]
    pub fn aside_path(path: &Path) -> PathBuf {
        let mut name = path.file_name().unwrap_or_default().to_os_string();
        name.push(".bad");
        path.with_file_name(name)
    }

    /// Reads the file, at most [`MAX_FILE_BYTES`] of it, refusing a directory, device
    /// or FIFO without opening it (so nothing blocks or reads on forever). One that
    /// cannot be used is moved aside (replacing an older one there; a link is moved, not
    /// what it points to) and the warning says so; nothing here panics or exits.
    pub fn load(&mut self) -> Loaded {
        use crate::reading::{self, ReadError};
        let Some(path) = &self.path else { return Loaded::Missing };
        let shown = crate::messages::path(path);
        let parsed = match reading::read_limited(path, MAX_FILE_BYTES) {
            Ok(bytes) => std::str::from_utf8(&bytes)
                .map_err(|e| format!("not UTF-8 text: {e}"))
                .and_then(Settings::parse),
            Err(ReadError::Missing) => return Loaded::Missing,
            // The OS refused (permission): the file may be fine; it is left where it is.
            Err(ReadError::Io(reason)) => {
                return Loaded::Unusable {
                    warning: format!(
                        "particle-lab: cannot read the settings file {shown}: {reason}; starting from the defaults"
                    ),
                };
            }
            Err(error @ (ReadError::NotAFile(_) | ReadError::TooLarge { .. })) => Err(error.to_string()),
        };
        match parsed {
            Ok(settings) => {
                self.written = Some(settings.clone());
                Loaded::Restored(settings)
            }
            Err(reason) => {
                let aside = Self::aside_path(path);
                let whereto = match std::fs::rename(path, &aside) {
                    Ok(()) => format!("moved it to {}", crate::messages::path(&aside)),
                    Err(error) => format!("could not move it aside ({})", crate::messages::io_reason(&error)),
                };
                let reason = crate::messages::one_line(&reason);
                Loaded::Unusable {
                    warning: format!(
                        "particle-lab: the settings file {shown} is unusable ({reason}); {whereto} and started from \
                         the defaults"
                    ),
                }
            }
        }
    }

    /// Writes `settings` unless the file already holds them; true if it wrote. The file
    /// is written beside its place and renamed into it, so a crash mid-write leaves the
    /// old one.
    pub fn save(&mut self, settings: &Settings) -> Result<bool, String> {
        let Some(path) = &self.path else { return Ok(false) };
        if self.written.as_ref() == Some(settings) {
            return Ok(false);
        }
        let write = || -> std::io::Result<()> {
            if let Some(directory) = path.parent() {
                std::fs::create_dir_all(directory)?;
            }
            let mut name = path.file_name().unwrap_or_default().to_os_string();
            name.push(".tmp");
            let temporary = path.with_file_name(name);
            std::fs::write(&temporary, settings.to_text())?;
            std::fs::rename(&temporary, path)
        };
        write().map_err(|e| {
            format!(
                "cannot save the settings to {}: {}",
                crate::messages::path(path),
                crate::messages::io_reason(&e)
            )
        })?;
        self.written = Some(settings.clone());
        Ok(true)
    }

    /// Saves what `current` gives if [`AUTOSAVE_INTERVAL`] has passed since the last
    /// check and it changed. A failure is reported once, on stderr, then only logged.
    pub fn autosave(&mut self, current: impl FnOnce() -> Settings) {
        if self.path.is_none() || self.checked.elapsed() < AUTOSAVE_INTERVAL {
            return;
        }
        self.checked = Instant::now();
        self.save_reporting(&current());
    }

    /// Saves now (on exit), reporting a failure as [`Self::autosave`] does; true if
    /// the file holds `settings` afterwards.
    pub fn save_reporting(&mut self, settings: &Settings) -> bool {
        match self.save(settings) {
            Ok(wrote) => {
                if wrote {
                    log::debug!("settings saved");
                }
                self.path.is_some()
            }
            Err(message) => {
                if std::mem::replace(&mut self.save_failed, true) {
                    log::debug!("{message}");
                } else {
                    eprintln!("particle-lab: {message}");
                }
                false
            }
        }
    }
}

/// The lab the window opens on, and what it needs to keep the settings.
pub struct Opened {
    /// The lab, with the settings applied.
    pub lab: Lab,
    /// The window's inner size (logical pixels).
    pub window: [u32; 2],
    /// The file, for saving.
    pub store: Store,
    /// The one warning line for an unusable file, to print.
    pub warning: Option<String>,
    /// One line for the log saying where the settings came from and what they are.
    pub summary: String,
}

/// Builds the window's lab from the command line and the settings in `store`: the
/// saved settings (unless `--fresh`, or there are none or they are unusable), with
/// whatever the command line typed winning. An error is a bad command line.
pub fn open(launch: &Launch, mut store: Store) -> Result<Opened, String> {
    // A mistyped scene (or a bad scene file) is refused before the settings file is
    // touched.
    let typed_entry = match (launch.scene.as_deref(), launch.scene_file.as_deref()) {
        (None, None) => None,
        (scene, file) => Some(scenes::file::choose(scene, file)?),
    };
    let place =
        store.path().map_or_else(|| "nowhere (no config directory)".to_string(), crate::messages::path);
    let (saved, origin, mut warning) = if launch.fresh {
        (None, format!("--fresh: starting from the defaults; the settings at {place} are not read"), None)
    } else {
        match store.load() {
            Loaded::Missing => (None, format!("none saved yet at {place}; starting from the defaults"), None),
            Loaded::Restored(settings) => (Some(settings), format!("restored from {place}"), None),
            Loaded::Unusable { warning } => {
                (None, format!("the file at {place} was unusable; starting from the defaults"), Some(warning))
            }
        }
    };
    let resolved = saved.as_ref().map(Settings::resolve).transpose()?;
    // The saved scene: found by name, or its file opened again (unless the command line
    // chose another scene or a snapshot, when the file is not read at all).
    let saved_entry = match (&saved, &resolved) {
        (Some(saved), Some(resolved)) => match &saved.scene_file {
            None => resolved.entry,
            Some(path) => match typed_entry {
                Some(typed) => (scene_file_of(typed).as_ref() == Some(path)).then_some(typed),
                None if launch.from.is_some() => None,
                None => scenes::file::load_path(Path::new(path))
                    .map_err(|error| {
                        warning = Some(format!(
                            "particle-lab: the scene file {} saved in the settings cannot be opened ({}); \
                             starting on {DEFAULT_SCENE}",
                            crate::messages::path(Path::new(path)),
                            file_reason(&error)
                        ));
                    })
                    .ok(),
            },
        },
        _ => None,
    };
    let entry = match typed_entry.or(saved_entry) {
        Some(entry) => entry,
        None => scenes::find(DEFAULT_SCENE)?,
    };
    let same_scene = saved_entry.is_some_and(|saved| std::ptr::eq(saved, entry));
    // The saved values first, then `--set` over them: the later assignment wins.
    let mut assignments: Vec<String> = Vec::new();
    if let (true, Some(saved)) = (same_scene, &saved) {
        assignments.extend(saved.params.iter().map(|(name, value)| format!("{name}={value}")));
    }
    assignments.extend(launch.set.iter().cloned());
    let base = resolved.as_ref().map_or_else(SolverSettings::default, |r| r.solver);
    let solver = launch.solver_over(base);
    let mut lab = match Lab::from_entry(entry, &assignments, solver) {
        Ok(lab) => lab,
        // A scene file edited since: the saved values may no longer fit it. It opens
        // with its own (and `--set` still has to fit).
        Err(error) if same_scene && saved.as_ref().is_some_and(|s| s.scene_file.is_some()) => {
            let lab = Lab::from_entry(entry, &launch.set, solver)?;
            let path = saved.as_ref().and_then(|s| s.scene_file.as_deref()).unwrap_or_default();
            warning = Some(format!(
                "particle-lab: the values saved for the scene file {} no longer fit it ({}); opening it \
                 with its defaults",
                crate::messages::path(Path::new(path)),
                crate::messages::one_line(&error)
            ));
            lab
        }
        Err(error) => return Err(error),
    };
    let mut window = DEFAULT_WINDOW;
    if let Some(saved) = &saved {
        apply(saved, &mut lab, same_scene);
        window = [saved.window.width, saved.window.height];
    }
    let typed = launch.typed();
    let overrides = if typed.is_empty() {
        String::new()
    } else {
        format!("; from the command line: {}", typed.join(" "))
    };
    let summary = format!("settings {origin}{overrides}: {}", Settings::of(&lab, window).describe());
    Ok(Opened { lab, window, store, warning, summary })
}

/// Applies what the lab was built without: the view, panel and time scale always; the
/// physics rate, camera, trails and colour by speed only on the scene they were saved
/// with (another scene keeps its own).
fn apply(saved: &Settings, lab: &mut Lab, same_scene: bool) {
    let mut view = saved.view.options(lab.view);
    if !same_scene {
        view.trails = lab.view.trails;
        view.color_by_speed = lab.view.color_by_speed;
        // A crowd the command line asked for keeps the lab's choice of MSAA.
        if lab.scene.world().particles.len() > MSAA_LIMIT {
            view.msaa = lab.view.msaa;
        }
    }
    lab.view = view;
    lab.time_scale = saved.time_scale;
    lab.panel_open = saved.panel.open;
    lab.show_help = saved.panel.help;
    lab.compare_open = saved.panel.compare;
    if same_scene {
        lab.physics_rate = saved.physics_rate;
    }
    if saved.view.side_view {
        lab.set_side_view(true);
    }
    if same_scene && saved.camera.moved {
        let c = &saved.camera;
        lab.camera.target = Vec3::from_array(c.target);
        lab.camera.distance = c.distance;
        lab.camera.yaw = c.yaw;
        lab.camera.pitch = c.pitch;
        lab.camera.orthographic = lab.side_view;
        lab.camera_moved = true;
    }
    lab.follow = saved.view.follow;
    lab.follow_particle();
}

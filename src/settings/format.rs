//! The settings file's fields: what persists of the lab, read back with every value
//! checked, and described in one line for the log.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::physics::solver::SUBSTEP_RANGE;
use crate::physics::{Integrator, SolverKind, SolverSettings};
use crate::render::ViewOptions;
use crate::scenes::{self, ParamValues, SceneEntry};
use crate::ui::Lab;
use crate::ui::lab::{PHYSICS_RATE_RANGE, TIME_SCALE_RANGE};
use crate::ui::layout::PanelLayout;

/// The file format's version; a file with a larger one is set aside, not guessed at.
pub const VERSION: u32 = 1;
/// The scene the window opens on when nothing says otherwise.
pub const DEFAULT_SCENE: &str = "projectile";
/// The window's size at the first launch (logical pixels).
pub const DEFAULT_WINDOW: [u32; 2] = [1280, 720];
/// Smallest window the lab opens (logical pixels), as the window's minimum size.
pub const MIN_WINDOW: [u32; 2] = [320, 240];
/// Largest window side accepted from the file (logical pixels).
pub const MAX_WINDOW_SIDE: u32 = 16_384;
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
    pub solver: SavedSolver,
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
    pub panel: PanelLayout,
}

/// The solver choice, by the names the command line takes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SavedSolver {
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
    /// Predictions drawn and read out (off: a class predicts before it measures).
    pub predictions: bool,
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
            predictions: view.predictions,
        }
    }

    /// The toggles as the renderer takes them, over `base` (so a toggle this file does
    /// not know keeps the base's value).
    pub(super) fn options(&self, base: ViewOptions) -> ViewOptions {
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
        view.predictions = self.predictions;
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

/// A settings file's values after validation: what [`Settings`] names, found.
pub(super) struct Resolved {
    /// The saved scene when it is found by name; `None` for a scene file, which is
    /// opened (and its parameters checked) only when the window opens on it.
    pub(super) entry: Option<&'static SceneEntry>,
    pub(super) solver: SolverSettings,
}

impl Settings {
    /// What persists of `lab` and the panel `panel`, in a window `window` logical pixels
    /// large. A scene with no home to open again from (a scene file carried by a link,
    /// or picked in a web page: neither registered nor on disk) is not saved: the
    /// settings name the default scene with its defaults instead, and keep the rest.
    #[must_use]
    pub fn of(lab: &Lab, panel: &PanelLayout, window: [u32; 2]) -> Self {
        let mut settings = Self::of_any(lab, panel, window);
        let found = scenes::find(&settings.scene).is_ok_and(|entry| entry.same(&lab.entry));
        if settings.scene_file.is_none() && !found {
            let default = scenes::find(DEFAULT_SCENE).expect("the default scene is registered");
            settings.scene = DEFAULT_SCENE.to_string();
            settings.params.clear();
            settings.physics_rate = 1.0 / default.info().dt;
            settings.camera.moved = false;
        }
        settings
    }

    /// What `lab` is now, whatever its scene (for the log's summary); [`Self::of`] is
    /// what is saved.
    pub(super) fn of_any(lab: &Lab, panel: &PanelLayout, window: [u32; 2]) -> Self {
        let solver = lab.solver();
        let camera = lab.camera;
        Self {
            version: VERSION,
            scene: lab.entry.info().name.to_string(),
            scene_file: scene_file_of(&lab.entry),
            params: lab.scene.params().iter().map(|(param, value)| (param.name.to_string(), value)).collect(),
            solver: SavedSolver {
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
            panel: *panel,
        }
    }

    /// What the window saves: [`Self::of`], except that while the lab is still on the
    /// scene it opened on instead of a saved scene file that could not be opened
    /// (`kept`, the settings as read; see [`open`](super::open)), the saved scene file
    /// and what belongs to it (its name, path and parameter values, physics rate,
    /// camera, trails and colour by speed) are written back as they were read, so the
    /// next start tries the file again. Once the lab is on another scene (the user
    /// opened one, or loaded a snapshot of one) that is the choice, and `kept` is
    /// dropped for good.
    #[must_use]
    pub fn keeping(kept: &mut Option<Settings>, lab: &Lab, panel: &PanelLayout, window: [u32; 2]) -> Self {
        let mut now = Self::of(lab, panel, window);
        let Some(saved) = kept.as_ref() else { return now };
        let still_instead = scenes::find(DEFAULT_SCENE).is_ok_and(|instead| instead.same(&lab.entry));
        if !still_instead {
            *kept = None;
            return now;
        }
        now.scene.clone_from(&saved.scene);
        now.scene_file.clone_from(&saved.scene_file);
        now.params.clone_from(&saved.params);
        now.physics_rate = saved.physics_rate;
        now.camera = saved.camera;
        now.view.trails = saved.view.trails;
        now.view.color_by_speed = saved.view.color_by_speed;
        now
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
    pub(super) fn resolve(&self) -> Result<Resolved, String> {
        let entry = match &self.scene_file {
            Some(path) if path.is_empty() => return Err("scene_file is empty".into()),
            Some(_) => None,
            None => {
                let entry = scenes::find(&self.scene).map_err(|e| format!("scene: {e}"))?;
                let mut params = ParamValues::defaults(&entry.info().params);
                for (name, value) in &self.params {
                    params.set(name, *value).map_err(|e| format!("params of {}: {e}", entry.info().name))?;
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
pub(super) fn scene_file_of(entry: &SceneEntry) -> Option<String> {
    if scenes::file::shipped().iter().any(|shipped| shipped.same(entry)) {
        return None;
    }
    let path = scenes::file::definition(entry)?.path()?;
    let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    Some(path.to_string_lossy().into_owned())
}

/// Why a scene file did not load, without its name (the warning names it already).
pub(super) fn file_reason(error: &scenes::file::FileError) -> String {
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

//! The command line over the saved settings: which typed flags win, and the lab
//! (and panel layout) the window opens on.

use std::path::Path;

use glam::Vec3;

use crate::cli::Cli;
use crate::physics::{Integrator, SolverChoice, SolverKind, SolverSettings};
use crate::scenes::{self};
use crate::ui::Lab;
use crate::ui::layout::PanelLayout;

use super::format::{DEFAULT_SCENE, DEFAULT_WINDOW, Settings, file_reason, scene_file_of};
use super::store::{Loaded, Store};
use crate::ui::lab::MSAA_LIMIT;

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
    /// A scene file's text carried by a link (`#file=…`), opened instead of a named
    /// scene or a file on disk.
    pub scene_text: Option<String>,
    /// A link's `steps=N`: run N physics steps at once, then pause.
    pub steps: Option<u64>,
    /// Opened from a link: its physics rate (`rate=HZ`, else the scene's own) wins over
    /// a saved one.
    pub link: Option<LinkRate>,
    /// A link's `view=` and `camera=`, applied once the lab is open.
    pub view: crate::ui::lab::LinkView,
}

/// The physics rate a link opens at: its own `rate=HZ`, or (`None`) the scene's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LinkRate(pub Option<f32>);

impl Launch {
    /// The window's flags from the parsed command line.
    pub fn from_cli(cli: &Cli) -> Result<Self, String> {
        let solver = cli.choice.solver.choice()?;
        Ok(Self {
            scene: cli.choice.scene.clone(),
            scene_file: cli.choice.scene_file.clone(),
            set: cli.choice.set.clone(),
            solver: solver.kind,
            substeps: solver.substeps,
            integrator: solver.integrator,
            fresh: cli.fresh,
            from: cli.from.clone(),
            scene_text: None,
            steps: None,
            link: None,
            view: crate::ui::lab::LinkView::default(),
        })
    }

    /// What a link (`particle-lab open LINK`: a whole link as copied, its query and
    /// fragment) opens the window with: read as the window's command line, with the
    /// scene file it carries and the steps to run before pausing.
    pub fn from_link(text: &str) -> Result<Self, String> {
        let link = crate::ui::lab::Link::parse_text(text)?;
        let mut launch = Self::from_args(&link.args)?;
        launch.link = link.names_experiment().then_some(LinkRate(link.rate));
        launch.scene_text = link.scene_text;
        launch.steps = link.steps;
        launch.view = link.view;
        Ok(launch)
    }

    /// The window's flags from `args` (the program's name first) as a command line
    /// would give them: a link's query string in a browser. A bad one is the one line
    /// clap gives it.
    pub fn from_args(args: &[String]) -> Result<Self, String> {
        use clap::{CommandFactory, FromArgMatches};
        let first_line = |e: clap::Error| {
            let text = e.to_string();
            let line = text.lines().next().unwrap_or_default();
            line.strip_prefix("error: ").unwrap_or(line).to_string()
        };
        let matches = Cli::command().try_get_matches_from(args).map_err(first_line)?;
        let cli = Cli::from_arg_matches(&matches).map_err(first_line)?;
        if cli.command.is_some() {
            return Err("a link opens the lab; it runs no command".into());
        }
        Self::from_cli(&cli)
    }

    /// The solver flags typed, as a choice to lay over the others.
    fn solver_choice(&self) -> SolverChoice {
        SolverChoice { kind: self.solver, substeps: self.substeps, integrator: self.integrator }
    }

    /// The flags typed, for the log.
    fn typed(&self) -> Vec<&'static str> {
        let flags = [
            (self.scene.is_some(), "--scene"),
            (self.scene_file.is_some(), "--scene-file"),
            (self.scene_text.is_some(), "a link's scene file"),
            (!self.set.is_empty(), "--set"),
            (self.solver.is_some(), "--solver"),
            (self.substeps.is_some(), "--substeps"),
            (self.integrator.is_some(), "--integrator"),
        ];
        flags.into_iter().filter(|(typed, _)| *typed).map(|(_, flag)| flag).collect()
    }
}

/// The lab the window opens on, and what it needs to keep the settings.
pub struct Opened {
    /// The lab, with the settings applied.
    pub lab: Lab,
    /// The side panel's layout, as saved (or the default).
    pub layout: PanelLayout,
    /// The window's inner size (logical pixels).
    pub window: [u32; 2],
    /// The file, for saving.
    pub store: Store,
    /// The one warning line for an unusable file, to print.
    pub warning: Option<String>,
    /// One line for the log saying where the settings came from and what they are.
    pub summary: String,
    /// The settings as read, when they name a scene file that could not be opened:
    /// what [`Settings::keeping`] writes back while the lab is on the scene it opened
    /// on instead, so the next start tries the file again.
    pub kept: Option<Settings>,
}

/// Builds the window's lab from the command line and the settings in `store`: the
/// saved settings (unless `--fresh`, or there are none or they are unusable), with
/// whatever the command line typed winning. An error is a bad command line.
pub fn open(launch: &Launch, mut store: Store) -> Result<Opened, String> {
    // A mistyped scene (or a bad scene file) is refused before the settings file is
    // touched.
    let typed_entry = match (launch.scene.as_deref(), launch.scene_file.as_deref(), &launch.scene_text) {
        (None, None, None) => None,
        (None, None, Some(text)) => Some(
            scenes::file::load_text(text, crate::ui::lab::CARRIED_NAME, None).map_err(|e| e.to_string())?,
        ),
        (_, _, Some(_)) => {
            return Err("a link carries its own scene file: give no --scene or --scene-file".into());
        }
        (scene, file, None) => Some(scenes::file::choose(scene, file)?),
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
    // A saved scene file that cannot be opened: the settings as read, kept (see
    // `Settings::keeping`) so that saving does not drop the file the user chose.
    let mut kept = None;
    // The saved scene: found by name, or its file opened again (unless the command line
    // chose another scene or a snapshot, when the file is not read at all).
    let saved_entry = match (&saved, &resolved) {
        (Some(saved), Some(resolved)) => match &saved.scene_file {
            None => resolved.entry.cloned(),
            Some(path) => match &typed_entry {
                Some(typed) => (scene_file_of(typed).as_ref() == Some(path)).then(|| typed.clone()),
                None if launch.from.is_some() => None,
                None => scenes::file::load_path(Path::new(path))
                    .map_err(|error| {
                        warning = Some(format!(
                            "particle-lab: the scene file {} saved in the settings cannot be opened ({}); \
                             starting on {DEFAULT_SCENE}, and the settings keep it for the next start",
                            crate::messages::path(Path::new(path)),
                            file_reason(&error)
                        ));
                        kept = Some(saved.clone());
                    })
                    .ok(),
            },
        },
        _ => None,
    };
    let entry = match typed_entry.or_else(|| saved_entry.clone()) {
        Some(entry) => entry,
        None => scenes::find(DEFAULT_SCENE)?.clone(),
    };
    let same_scene = saved_entry.is_some_and(|saved| saved.same(&entry));
    // The saved values first, then `--set` over them: the later assignment wins.
    let mut assignments: Vec<String> = Vec::new();
    if let (true, Some(saved)) = (same_scene, &saved) {
        assignments.extend(saved.params.iter().map(|(name, value)| format!("{name}={value}")));
    }
    assignments.extend(launch.set.iter().cloned());
    // The saved solver, then the scene file's own, then the flags typed.
    let base = resolved.as_ref().map_or_else(SolverSettings::default, |r| r.solver);
    let solver = launch.solver_choice().over(scenes::file::own_solver(&entry).over(base));
    let mut layout = PanelLayout::default();
    let mut lab = match Lab::from_entry(&entry, &assignments, solver) {
        Ok(lab) => lab,
        // A scene file edited since: the saved values may no longer fit it. It opens
        // with its own (and `--set` still has to fit).
        Err(error) if same_scene && saved.as_ref().is_some_and(|s| s.scene_file.is_some()) => {
            let lab = Lab::from_entry(&entry, &launch.set, solver)?;
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
        layout = saved.panel;
        window = [saved.window.width, saved.window.height];
    }
    if let Some(LinkRate(rate)) = launch.link {
        lab.physics_rate = rate.unwrap_or(1.0 / lab.entry.info().dt);
    }
    let typed = launch.typed();
    let overrides = if typed.is_empty() {
        String::new()
    } else {
        format!("; from the command line: {}", typed.join(" "))
    };
    let summary =
        format!("settings {origin}{overrides}: {}", Settings::of_any(&lab, &layout, window).describe());
    // What went wrong with the saved scene file is in the status line too, once.
    if let Some(line) = warning.as_deref().filter(|_| saved.as_ref().is_some_and(|s| s.scene_file.is_some()))
    {
        lab.status = status_line(line);
    }
    Ok(Opened { lab, layout, window, store, warning, summary, kept })
}

/// A warning as the status line shows it: without the program's name, capitalised.
fn status_line(warning: &str) -> String {
    let text = warning.strip_prefix("particle-lab: ").unwrap_or(warning);
    let mut chars = text.chars();
    chars.next().map_or_else(String::new, |first| first.to_uppercase().chain(chars).collect())
}

/// Applies what the lab was built without: the view and time scale always (the panel
/// is the caller's); the
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

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

//!
//! Rooms: `format` (the file's fields, checked and described), `store` (reading,
//! writing and setting aside the file), `medium` (where its text lives: a file, or a
//! browser's local storage), `launch` (the command line over the saved
//! settings, and the lab the window opens on).

mod format;
mod launch;
mod medium;
mod store;

/// The side panel's saved layout (the settings file's `panel`).
pub use crate::ui::layout::PanelLayout as PanelSettings;
pub use format::{
    CameraSettings, DEFAULT_SCENE, DEFAULT_WINDOW, MAX_WINDOW_SIDE, MIN_WINDOW, SavedSolver, Settings,
    VERSION, ViewSettings, WindowSize,
};
pub use launch::{Launch, LinkRate, Opened, open};
pub use store::{AUTOSAVE_INTERVAL, FILE_NAME, Loaded, MAX_FILE_BYTES, Store};

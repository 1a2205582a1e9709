//! Scene files in the lab: open one (File → Open, the shipped files in the Scene
//! menu), and reload it when it changes on disk (the camera stays where it is; a bad
//! edit shows its error in the status line and the running scene goes on).

use std::path::Path;

use super::model::Lab;
use super::watch::Watch;
use crate::scenes::file::{self, FileError};
use crate::scenes::{self, ParamValues, SceneEntry};

impl Lab {
    /// Opens a scene file, replacing the running scene and watching the file for
    /// changes. A bad file leaves the running scene and goes to the status line (and
    /// the terminal) as `FILE:LINE:COL: message`. Returns whether it opened.
    pub fn open_scene_file(&mut self, path: &Path) -> bool {
        match file::load_path(path) {
            Ok(entry) => {
                log::info!("scene file opened: {}", path.display());
                self.switch_scene(&entry);
                self.watch_scene_file();
                true
            }
            Err(error) => {
                self.report(&error);
                false
            }
        }
    }

    /// Opens a scene file's text that came from elsewhere than a path (a browser's file
    /// input); `name` names it in messages. As [`Self::open_scene_file`], unwatched.
    pub fn open_scene_text(&mut self, name: &str, text: &str) -> bool {
        match file::load_text(text, name, None) {
            Ok(entry) => {
                log::info!("scene file opened: {name}");
                self.switch_scene(&entry);
                self.scene_file = None;
                self.status = format!("Opened {name}");
                true
            }
            Err(error) => {
                self.report(&error);
                false
            }
        }
    }

    /// Starts watching the running scene's file, if it was read from one.
    pub fn watch_scene_file(&mut self) {
        let Some(path) = file::definition(&self.entry).and_then(|d| d.path().map(Path::to_path_buf)) else {
            self.scene_file = None;
            return;
        };
        match Watch::new(&path) {
            Ok(watch) => self.scene_file = Some(watch),
            Err(error) => {
                log::warn!("{error}");
                self.scene_file = None;
            }
        }
    }

    /// Reloads the scene file if it changed on disk; called once a frame.
    pub fn poll_scene_file(&mut self) {
        let Some(watch) = &mut self.scene_file else { return };
        // Another scene was picked since: its file, if any, is not the one watched.
        let current = file::definition(&self.entry);
        if current.and_then(|d| d.path()) != Some(watch.path.as_path()) {
            self.scene_file = None;
            return;
        }
        if !watch.settled_change() {
            return;
        }
        let path = watch.path.clone();
        let unchanged =
            current.is_some_and(|d| std::fs::read_to_string(&path).is_ok_and(|text| text == d.source()));
        if !unchanged {
            self.reload_scene_file(&path);
        }
    }

    /// Loads the file again, keeping the camera and the parameter values the new file
    /// still accepts.
    fn reload_scene_file(&mut self, path: &Path) {
        let entry = match file::load_path(path) {
            Ok(entry) => entry,
            Err(error) => {
                self.report(&error);
                return;
            }
        };
        let (camera, moved) = (self.camera, self.camera_moved);
        let kept = kept_values(&entry, self.scene.params());
        let watch = self.scene_file.take();
        self.switch_scene(&entry);
        if let Some(values) = kept
            && let Ok(scene) = scenes::create_entry(&entry, values)
        {
            self.scene = scene;
            self.reset();
        }
        self.scene_file = watch;
        self.camera = camera;
        self.camera_moved = moved;
        self.status = format!("Reloaded {} (it changed on disk)", path.display());
        log::info!("scene file reloaded: {}", path.display());
    }

    /// The running scene as a scene file, with the sliders' values as its defaults:
    /// a name to save it under (the scene's, made safe for a file name) and the text.
    pub fn scene_file_text(&self) -> Result<(String, String), String> {
        let text = file::written(&self.entry, self.scene.params())?;
        let stem: String = self
            .entry
            .info()
            .name
            .chars()
            .map(|c| if c.is_alphanumeric() || c == '-' || c == '_' { c } else { '-' })
            .collect();
        Ok((format!("{stem}.toml"), text))
    }

    /// File → Save scene as…: writes the running scene as a scene file at `path`
    /// (replaced whole or not at all); true if it was written. The status line says
    /// what happened either way.
    pub fn save_scene_to(&mut self, path: &Path) -> bool {
        let shown = crate::messages::path(path);
        let written = self.scene_file_text().and_then(|(_, text)| {
            crate::writing::write_atomic(path, text.as_bytes())
                .map_err(|e| format!("cannot save to {shown}: {e}"))
        });
        match written {
            Ok(()) => {
                log::info!("scene file saved: {}", path.display());
                self.status = format!("Saved the scene as {shown}");
                true
            }
            Err(error) => {
                self.status = error;
                false
            }
        }
    }

    fn report(&mut self, error: &FileError) {
        eprintln!("particle-lab: {error}");
        self.status = error.to_string();
    }
}

/// The values a user moved away from the old file's defaults, where the new entry's
/// table accepts them, over its defaults (an edited default takes effect); `None` when
/// that is just the defaults.
fn kept_values(entry: &SceneEntry, old: &ParamValues) -> Option<ParamValues> {
    let mut values = ParamValues::defaults(&entry.info().params);
    for (param, value) in old.iter() {
        if value != param.default {
            // A parameter the new file dropped or narrowed falls back to its default.
            let _ = values.set(&param.name, value);
        }
    }
    (values != ParamValues::defaults(&entry.info().params)).then_some(values)
}

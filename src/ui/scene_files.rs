//! Scene files in the window: File → Open, the shipped files in the Scene menu, and
//! hot reload when the open file changes on disk (the camera stays where it is; a bad
//! edit shows its error in the status line and the running scene goes on).

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, channel};
use std::time::{Duration, Instant};

use egui::containers::menu::{MenuButton, MenuConfig};
use notify::{RecursiveMode, Watcher};

use super::Lab;
use crate::scenes::file::{self, FileError};
use crate::scenes::{ParamValues, SceneEntry};

/// How long the file must stay unchanged before it is read: editors save in several
/// writes (truncate, write, rename), and reading between them would see half a file.
const SETTLE: Duration = Duration::from_millis(150);

/// Watches the open scene file's folder for changes to it.
pub struct Watch {
    /// The file.
    path: PathBuf,
    /// Kept alive: dropping it stops the watching.
    _watcher: notify::RecommendedWatcher,
    events: Receiver<notify::Result<notify::Event>>,
    /// When the file last changed, if it has since the last reload.
    changed: Option<Instant>,
}

impl Watch {
    /// Starts watching `path`. The folder is watched rather than the file, since an
    /// editor that saves by renaming a new file over the old one would end a watch on
    /// the file itself.
    pub fn new(path: &Path) -> Result<Self, String> {
        let (sender, events) = channel();
        let mut watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            // The window may be gone; then nobody needs the event.
            let _ = sender.send(event);
        })
        .map_err(|e| format!("cannot watch {} for changes: {e}", path.display()))?;
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        watcher
            .watch(&folder, RecursiveMode::NonRecursive)
            .map_err(|e| format!("cannot watch {} for changes: {e}", path.display()))?;
        Ok(Self { path: path.to_path_buf(), _watcher: watcher, events, changed: None })
    }

    /// True once the file has changed and then stayed unchanged for [`SETTLE`].
    fn settled_change(&mut self) -> bool {
        let name = self.path.file_name();
        while let Ok(event) = self.events.try_recv() {
            let Ok(event) = event else { continue };
            let touches = event.paths.iter().any(|p| p.file_name() == name);
            if touches && !event.kind.is_access() {
                self.changed = Some(Instant::now());
            }
        }
        match self.changed {
            Some(at) if at.elapsed() >= SETTLE => {
                self.changed = None;
                true
            }
            _ => false,
        }
    }
}

impl Lab {
    /// Opens a scene file, replacing the running scene and watching the file for
    /// changes. A bad file leaves the running scene and goes to the status line (and
    /// the terminal) as `FILE:LINE:COL: message`. Returns whether it opened.
    pub fn open_scene_file(&mut self, path: &Path) -> bool {
        match file::load_path(path) {
            Ok(entry) => {
                log::info!("scene file opened: {}", path.display());
                self.switch_scene(entry);
                self.watch_scene_file();
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
        let Some(path) = file::definition(self.entry).and_then(|d| d.path().map(Path::to_path_buf)) else {
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
        let current = file::definition(self.entry);
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
        let kept = kept_values(entry, &self.scene.params().clone());
        let watch = self.scene_file.take();
        self.switch_scene(entry);
        if let Some(values) = kept
            && let Some(definition) = file::definition(entry)
            && let Ok(scene) = definition.create(values)
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

    fn report(&mut self, error: &FileError) {
        eprintln!("particle-lab: {error}");
        self.status = error.to_string();
    }
}

/// The values a user moved away from the old file's defaults, where the new entry's
/// table accepts them, over its defaults (an edited default takes effect); `None` when
/// that is just the defaults.
fn kept_values(entry: &'static SceneEntry, old: &ParamValues) -> Option<ParamValues> {
    let mut values = ParamValues::defaults(entry.info.params);
    for (param, value) in old.iter() {
        if value != param.default {
            // A parameter the new file dropped or narrowed falls back to its default.
            let _ = values.set(param.name, value);
        }
    }
    (values != ParamValues::defaults(entry.info.params)).then_some(values)
}

/// The File menu: open a scene file by its path. It stays open while the path is
/// typed (a menu closes on any click by default, the text field's too).
pub fn file_menu(ui: &mut egui::Ui, lab: &mut Lab) {
    let config = MenuConfig::new().close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside);
    MenuButton::new("File").config(config).ui(ui, |ui| {
        let id = egui::Id::unique("scene file path");
        let mut text = ui.data_mut(|d| d.get_temp::<String>(id)).unwrap_or_default();
        ui.label("Open a scene file (TOML):");
        let field = ui.add(
            egui::TextEdit::singleline(&mut text).hint_text("assets/scenes/cloth.toml").desired_width(260.0),
        );
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        let path = text.trim().to_string();
        if (ui.button("Open").clicked() || entered)
            && !path.is_empty()
            && lab.open_scene_file(Path::new(&path))
        {
            ui.close();
        }
        if let Some((_, Some(path))) = lab.scene.source() {
            ui.separator();
            ui.label(format!("Watching {} for changes", path.display()));
        }
        ui.data_mut(|d| d.insert_temp(id, text));
        ui.separator();
        super::snapshot_menu(ui, lab);
    });
}

/// The shipped scene files, under the compiled scenes in the Scene menu.
pub fn scene_menu(ui: &mut egui::Ui, lab: &mut Lab) {
    ui.separator();
    for &entry in file::shipped() {
        let path = |e: &SceneEntry| file::definition(e).map(|d| d.path().map(Path::to_path_buf));
        let current = lab.entry.info.name == entry.info.name && path(lab.entry) == path(entry);
        let label = format!("{} (file)", entry.info.name);
        if ui.selectable_label(current, label).on_hover_text(entry.info.summary).clicked() {
            match file::definition(entry).and_then(|d| d.path().map(Path::to_path_buf)) {
                // Read it again: it may have been edited since it was first loaded.
                Some(path) => {
                    lab.open_scene_file(&path);
                }
                None => lab.switch_scene(entry),
            }
            ui.close();
        }
    }
}

//! The File menu: open a scene file, save and load snapshots, quick save. Open and
//! Save go through the platform's file dialog (the `rfd` crate: the desktop portal,
//! else zenity); the typed paths stay below as the fallback where there is no dialog
//! (a bare X server, a remote session), and for those who prefer typing.

use std::path::{Path, PathBuf};

use egui::containers::menu::{MenuButton, MenuConfig};

use crate::ui::keys::{self, Command};
use crate::ui::lab::Lab;
use crate::ui::layout::PanelLayout;

/// Where the shipped scene files are, the dialog's first folder.
pub const SCENE_FOLDER: &str = "assets/scenes";

/// The File menu's drafts: the typed paths.
#[derive(Debug)]
pub struct FileMenu {
    /// The scene file path being typed.
    pub scene_path: String,
    /// Where Save and Load snapshot write and read.
    pub snapshot_path: String,
}

impl Default for FileMenu {
    fn default() -> Self {
        Self { scene_path: String::new(), snapshot_path: "snapshot.json".into() }
    }
}

/// What a file dialog gave.
enum Picked {
    /// A path the user chose (no dialog gives one in a browser yet).
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    Path(PathBuf),
    /// Cancelled, or no dialog could be shown.
    Nothing,
}

/// Asks the platform for a file to open (or, with `save`, a file to write), of the
/// given kind. `None` from the dialog means cancelled or no dialog at all; rfd does
/// not tell them apart, so the status line mentions the typed path.
#[cfg(not(target_arch = "wasm32"))]
fn dialog(kind: &str, extension: &str, folder: &Path, save: bool) -> Picked {
    let dialog = rfd::FileDialog::new().add_filter(kind, &[extension]).set_directory(folder);
    let chosen = if save { dialog.save_file() } else { dialog.pick_file() };
    match chosen {
        Some(path) => Picked::Path(path),
        None => Picked::Nothing,
    }
}

/// In a browser rfd has only its asynchronous dialog, which this synchronous menu cannot
/// wait for: no dialog opens there yet (issue 20 gives the page its own file input).
#[cfg(target_arch = "wasm32")]
fn dialog(_kind: &str, _extension: &str, _folder: &Path, _save: bool) -> Picked {
    Picked::Nothing
}

/// The status line's word when a dialog gave nothing.
pub const NO_DIALOG: &str =
    "No file chosen (where no file dialog can open, type the path in the File menu instead)";

impl FileMenu {
    /// Draws the menu. It stays open while a path is typed (a menu closes on any
    /// click by default, the text field's too).
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
        let config = MenuConfig::new().close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside);
        MenuButton::new("File").config(config).ui(ui, |ui| {
            if ui.button("Open scene file…").on_hover_text("A TOML scene file, in the file dialog").clicked()
            {
                ui.close();
                match dialog("scene file", "toml", Path::new(SCENE_FOLDER), false) {
                    Picked::Path(path) => {
                        lab.open_scene_file(&path);
                    }
                    Picked::Nothing => lab.status = NO_DIALOG.into(),
                }
            }
            ui.label("or type its path:");
            let field = ui.add(
                egui::TextEdit::singleline(&mut self.scene_path)
                    .hint_text("assets/scenes/cloth.toml")
                    .desired_width(260.0),
            );
            let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            let path = self.scene_path.trim().to_string();
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
            ui.separator();
            self.snapshot_items(ui, lab, layout);
        });
    }

    /// The snapshot items: Save as… and Open… through the dialog, the typed path
    /// with Save and Load, and the quick save keys.
    fn snapshot_items(&mut self, ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
        ui.horizontal(|ui| {
            if ui.button("Save snapshot as…").clicked() {
                ui.close();
                match dialog("snapshot", "json", Path::new("."), true) {
                    Picked::Path(path) => {
                        lab.save_snapshot_to(&path);
                        self.snapshot_path = path.display().to_string();
                    }
                    Picked::Nothing => lab.status = NO_DIALOG.into(),
                }
            }
            if ui.button("Open snapshot…").clicked() {
                ui.close();
                match dialog("snapshot", "json", Path::new("."), false) {
                    Picked::Path(path) => {
                        lab.load_snapshot_from(&path);
                        self.snapshot_path = path.display().to_string();
                    }
                    Picked::Nothing => lab.status = NO_DIALOG.into(),
                }
            }
        });
        ui.label("Snapshot file");
        ui.add(egui::TextEdit::singleline(&mut self.snapshot_path).desired_width(260.0)).on_hover_text(
            "A snapshot holds the whole state: scene, parameters, solver, every particle and link, time",
        );
        let path = PathBuf::from(self.snapshot_path.trim());
        ui.horizontal(|ui| {
            if ui.button("Save snapshot").clicked() {
                lab.save_snapshot_to(&path);
                ui.close();
            }
            if ui
                .button("Load snapshot")
                .on_hover_text("A bad file changes nothing; the status line says why")
                .clicked()
            {
                lab.load_snapshot_from(&path);
                ui.close();
            }
        });
        ui.separator();
        if ui.button("Quick save (F5)").clicked() {
            keys::run(Command::QuickSave, lab, layout);
            ui.close();
        }
        if ui.button("Back to quick save (F9)").clicked() {
            keys::run(Command::QuickLoad, lab, layout);
            ui.close();
        }
    }
}

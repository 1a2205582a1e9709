//! The File menu: open a scene file, save and load snapshots, quick save. Open and
//! Save go through the platform's file dialog (the `rfd` crate: the desktop portal,
//! else zenity); the typed paths stay below as the fallback where there is no dialog
//! (a bare X server, a remote session), and for those who prefer typing. In a browser
//! files come from the browser's file chooser and snapshots go out as downloads.
//! Copy link gives the link that opens the experiment on screen in the web lab.

#[cfg(not(target_arch = "wasm32"))]
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
#[cfg(not(target_arch = "wasm32"))]
enum Picked {
    /// A path the user chose.
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

/// The status line's word when a dialog gave nothing.
pub const NO_DIALOG: &str =
    "No file chosen (where no file dialog can open, type the path in the File menu instead)";

impl FileMenu {
    /// Draws the menu. It stays open while a path is typed (a menu closes on any
    /// click by default, the text field's too).
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
        let config = MenuConfig::new().close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside);
        MenuButton::new("File").config(config).ui(ui, |ui| {
            #[cfg(target_arch = "wasm32")]
            {
                Self::page_items(ui, lab);
                ui.separator();
                Self::quick_save_items(ui, lab, layout);
                ui.separator();
                Self::link_item(ui, lab);
            }
            #[cfg(not(target_arch = "wasm32"))]
            {
                self.scene_items(ui, lab);
                ui.separator();
                self.snapshot_items(ui, lab);
                ui.separator();
                Self::quick_save_items(ui, lab, layout);
                ui.separator();
                Self::link_item(ui, lab);
            }
        });
    }

    /// In a browser: files come from the visitor's disk through the browser's file
    /// chooser, and snapshots go back as downloads.
    #[cfg(target_arch = "wasm32")]
    fn page_items(ui: &mut egui::Ui, lab: &mut Lab) {
        if ui.button("Open scene file…").on_hover_text("A TOML scene file from your disk").clicked() {
            crate::ui::page::pick_file(crate::ui::page::FileKind::Scene);
            ui.close();
        }
        if ui.button("Download snapshot").on_hover_text("The whole state, as a JSON file").clicked() {
            lab.status = match lab.snapshot_download().and_then(|(name, text)| {
                crate::ui::page::download(&name, "application/json", text.as_bytes()).map(|()| name)
            }) {
                Ok(name) => format!("Downloaded {name}"),
                Err(error) => error,
            };
            ui.close();
        }
        if ui.button("Open snapshot…").on_hover_text("A snapshot JSON file from your disk").clicked() {
            crate::ui::page::pick_file(crate::ui::page::FileKind::Snapshot);
            ui.close();
        }
    }

    /// Copy link: the query string that opens this experiment as it is now.
    fn link_item(ui: &mut egui::Ui, lab: &mut Lab) {
        let hover = "A link that opens this scene with its parameters, solver and integrator in the web \
                     version of the lab";
        if ui.button("Copy link").on_hover_text(hover).clicked() {
            let query = crate::ui::lab::Link::of(lab, false);
            #[cfg(target_arch = "wasm32")]
            {
                lab.status = format!("Link copied: {}", crate::ui::page::copy_link(&query));
            }
            #[cfg(not(target_arch = "wasm32"))]
            {
                ui.ctx().copy_text(query.clone());
                lab.status = format!("Link (after the web page's address): {query}");
            }
            ui.close();
        }
    }

    /// The scene items: Open… through the dialog, and the typed path.
    #[cfg(not(target_arch = "wasm32"))]
    fn scene_items(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        if ui.button("Open scene file…").on_hover_text("A TOML scene file, in the file dialog").clicked() {
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
    }

    /// The snapshot items: Save as… and Open… through the dialog, the typed path
    /// with Save and Load, and the quick save keys.
    #[cfg(not(target_arch = "wasm32"))]
    fn snapshot_items(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
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
    }

    /// Quick save and back to it (F5, F9).
    fn quick_save_items(ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
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

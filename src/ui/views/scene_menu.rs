//! The Scene menu: the compiled scenes, the shipped scene files, then the builder's
//! items (a new experiment, a copy of this one to edit).

use std::path::Path;

use crate::scenes::file;
use crate::scenes::{SCENES, SceneEntry};
use crate::ui::lab::Lab;

/// The Scene menu; it keeps no state.
#[derive(Debug, Default)]
pub struct SceneMenu;

impl SceneMenu {
    /// Draws the menu's items; picking one switches the lab to it.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        for entry in SCENES {
            let current = entry.same(&lab.entry);
            if ui
                .selectable_label(current, &*entry.info().name)
                .on_hover_text(&*entry.info().summary)
                .clicked()
            {
                lab.switch_scene(entry);
                ui.close();
            }
        }
        ui.separator();
        for entry in file::shipped() {
            let path = |e: &SceneEntry| file::definition(e).map(|d| d.path().map(Path::to_path_buf));
            let current = lab.entry.info().name == entry.info().name && path(&lab.entry) == path(entry);
            let label = format!("{} (file)", entry.info().name);
            if ui.selectable_label(current, label).on_hover_text(&*entry.info().summary).clicked() {
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
        ui.separator();
        let new = ui
            .button("New experiment…")
            .on_hover_text("Build one of your own: an empty scene with the ground");
        if new.clicked() {
            lab.edit_new();
            ui.close();
        }
        let copy = ui
            .add_enabled(!lab.editing(), egui::Button::new("Edit a copy of this scene").shortcut_text("B"))
            .on_hover_text("Open the builder on this scene's particles and links, as they start");
        if copy.clicked() {
            lab.edit_copy();
            ui.close();
        }
    }
}

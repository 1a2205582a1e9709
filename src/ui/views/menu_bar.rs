//! The menu bar: File, Scene, View, the panel's toggle and Help, then the scene's
//! name, its clock, and a warning when the physics cannot keep up.

use super::file_menu::FileMenu;
use super::scene_menu::SceneMenu;
use super::view_menu::ViewMenu;
use crate::ui::keys::{self, Command};
use crate::ui::lab::Lab;
use crate::ui::layout::PanelLayout;
use crate::ui::style::WARNING_COLOR;

/// The menu bar and its menus' drafts.
#[derive(Debug, Default)]
pub struct MenuBar {
    /// The File menu (its typed paths).
    pub file: FileMenu,
    /// The Scene menu.
    pub scene: SceneMenu,
    /// The View menu.
    pub view: ViewMenu,
}

impl MenuBar {
    /// Draws the bar and its menus.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
        egui::MenuBar::new().ui(ui, |ui| {
            self.file.ui(ui, lab, layout);
            ui.menu_button("Scene", |ui| self.scene.ui(ui, lab));
            ui.menu_button("View", |ui| self.view.ui(ui, lab, layout));
            if ui
                .selectable_label(layout.open, "Panel")
                .on_hover_text("Hide or show the side panel (P)")
                .clicked()
            {
                keys::run(Command::Panel, lab, layout);
            }
            ui.menu_button("Help", |ui| {
                if ui.button("Controls and shortcuts (F1)").clicked() {
                    layout.help = true;
                    ui.close();
                }
                if ui
                    .button("About this scene")
                    .on_hover_text("The physics of the scene that is open: its formulas, what they leave out, what to try")
                    .clicked()
                {
                    layout.about = true;
                    ui.close();
                }
            });
            ui.separator();
            ui.label(egui::RichText::new(&*lab.entry.info().name).strong());
            ui.label(format!("t = {:.2} s", lab.scene.world().time()));
            if lab.paused {
                ui.colored_label(crate::ui::style::PAUSED_COLOR, "paused");
            }
            if let Some(note) = lab.time_scale_note() {
                ui.colored_label(WARNING_COLOR, note).on_hover_text(
                    "The physics cannot keep up with the time scale: each frame runs as many steps as its \
                     budget allows. Lower the time scale or the physics rate.",
                );
            }
        });
    }
}

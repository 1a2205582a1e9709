//! The Controls window (Help → Controls, F1): every key and mouse control, listed from
//! the same table the key handler reads.

use crate::ui::keys::SHORTCUTS;
use crate::ui::layout::PanelLayout;

/// The Controls window; whether it is open is part of the saved layout.
#[derive(Debug, Default)]
pub struct HelpWindow;

impl HelpWindow {
    /// The rows the window lists: keys and meaning.
    #[must_use]
    pub fn rows() -> Vec<(&'static str, &'static str)> {
        SHORTCUTS.iter().map(|s| (s.keys, s.meaning)).collect()
    }

    /// Shows the window while `layout.help` is set; its close button clears it.
    pub fn show(&mut self, ctx: &egui::Context, layout: &mut PanelLayout) {
        let mut open = layout.help;
        egui::Window::new("Controls").open(&mut open).resizable(false).show(ctx, |ui| {
            egui::Grid::new("shortcuts").num_columns(2).striped(true).show(ui, |ui| {
                for (keys, meaning) in Self::rows() {
                    ui.monospace(keys);
                    ui.label(meaning);
                    ui.end_row();
                }
            });
        });
        layout.help = open;
    }
}

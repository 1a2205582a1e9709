//! The Read-outs section: the scene's own figures (range, period, tension...), and
//! the colour keys of what the view paints.

use super::legends;
use crate::ui::lab::Lab;

/// The read-outs; they keep no state (the lab refreshes the figures a few times a
/// second).
#[derive(Debug, Default)]
pub struct Readouts;

impl Readouts {
    /// Draws the read-outs grid and the keys.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        egui::Grid::new("readouts").num_columns(2).striped(true).show(ui, |ui| {
            let predictions = lab.view.predictions;
            for row in lab.readouts().iter().filter(|row| predictions || !row.is_prediction()) {
                let name = ui.label(row.label);
                let value = ui.add(egui::Label::new(row.text.as_str()).wrap());
                if !row.help.is_empty() {
                    name.on_hover_text(row.help);
                    value.on_hover_text(row.help);
                }
                ui.end_row();
            }
        });
        if !lab.view.predictions {
            ui.label(egui::RichText::new("Predictions hidden: View > Predictions shows them").small());
        }
        super::runs::ui(ui, lab);
        if lab.view.color_by_speed {
            ui.separator();
            legends::speed_legend(ui);
        }
        legends::link_key(ui, lab);
    }
}

//! The table of runs, under the read-outs: a row for each completed measurement (a
//! round that landed), each column headed with its unit and explained on hover, to
//! 4 significant figures (the CSV holds every digit). Rows can be deleted one by one
//! or all; the table copies as tab-separated text for a spreadsheet and saves as CSV.

use crate::scenes::runs::{FIGURES, significant};
use crate::ui::lab::Lab;

/// Draws the table of runs of the lab's scene, if it keeps one.
pub fn ui(ui: &mut egui::Ui, lab: &mut Lab) {
    let (mut delete, mut clear, mut copy, mut save) = (None, false, false, false);
    {
        let Some(table) = lab.scene.runs() else { return };
        ui.separator();
        ui.label(egui::RichText::new("Table of runs").strong())
            .on_hover_text("A row for each round that lands: what it was fired with, then each measured value beside its prediction");
        if table.rows.is_empty() {
            ui.label(
                egui::RichText::new(
                    "Each round that lands adds a row: fire at several angles or speeds to compare them.",
                )
                .small(),
            );
            return;
        }
        // A parameter no run changed is said once beneath the table, not in every row.
        let first = &table.rows[0];
        let same = |c: usize| table.rows.iter().all(|row| row[c].to_bits() == first[c].to_bits());
        // With View → Predictions off, the predicted columns are not shown (the CSV keeps them).
        let predictions = lab.view.predictions;
        let hidden = |c: usize| !predictions && table.columns[c].is_prediction();
        let shown: Vec<usize> = (0..table.columns.len())
            .filter(|&c| !hidden(c) && (table.columns[c].always || !same(c)))
            .collect();
        egui::ScrollArea::horizontal().id_salt("runs scroll").show(ui, |ui| {
            egui::Grid::new("runs").striped(true).show(ui, |ui| {
                ui.label("");
                for &c in &shown {
                    let column = &table.columns[c];
                    ui.label(egui::RichText::new(column.heading).small().strong()).on_hover_text(column.help);
                }
                ui.end_row();
                for (k, row) in table.rows.iter().enumerate() {
                    if ui.small_button("×").on_hover_text(format!("Delete run {}", k + 1)).clicked() {
                        delete = Some(k);
                    }
                    for &c in &shown {
                        ui.label(significant(row[c], FIGURES));
                    }
                    ui.end_row();
                }
            });
        });
        let constant: Vec<String> = (0..table.columns.len())
            .filter(|&c| !shown.contains(&c) && !hidden(c))
            .map(|c| format!("{} {}", table.columns[c].heading, significant(first[c], FIGURES)))
            .collect();
        if !constant.is_empty() {
            ui.label(egui::RichText::new(format!("every run: {}", constant.join(", "))).small());
        }
        ui.horizontal(|ui| {
            copy = ui
                .button("Copy as text")
                .on_hover_text("Tab-separated, to paste into a spreadsheet")
                .clicked();
            save = ui.button("Save CSV").on_hover_text("Every digit, one row a run").clicked();
            clear = ui.button("Clear").on_hover_text("Delete every run").clicked();
        });
        if copy {
            ui.ctx().copy_text(table.tsv());
        }
        super::runs_plot::ui(ui, &table, predictions);
    }
    if copy {
        lab.status = "table of runs copied as tab-separated text".into();
    }
    if let Some(k) = delete {
        lab.scene.delete_runs(Some(k));
    }
    if clear {
        lab.scene.delete_runs(None);
    }
    if save {
        lab.save_runs();
    }
}

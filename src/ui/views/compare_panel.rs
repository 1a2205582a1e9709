//! The Compare section: pick one setting and its value for a second copy of the
//! scene, run it beside the original (both start again) or branch it from now, or
//! stop it. The setting being chosen is this view's draft.

use crate::physics::{Integrator, SolverKind};
use crate::ui::compare::Change;
use crate::ui::lab::{Lab, PHYSICS_RATE_RANGE};
use crate::ui::paint;
use crate::ui::style::{WARNING_COLOR, srgb};

/// The Compare form.
#[derive(Debug)]
pub struct ComparePanel {
    /// The change the next copy will run with.
    pub draft: Change,
}

impl Default for ComparePanel {
    fn default() -> Self {
        Self { draft: Change::Integrator(Integrator::ExplicitEuler) }
    }
}

/// The name of the setting a change is about, as the form's menu lists it.
fn key(change: &Change) -> &str {
    match change {
        Change::Integrator(_) => "integrator",
        Change::Solver(_) => "solver",
        Change::Rate(_) => "physics rate",
        Change::Param(name, _) => name,
    }
}

impl ComparePanel {
    /// The section's heading: it says when a copy is running.
    #[must_use]
    pub fn title(lab: &Lab) -> &'static str {
        if lab.compare.is_some() { "Compare (running)" } else { "Compare" }
    }

    /// Draws the running copy's state, or the form for a new one.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        if let Some(running) = &lab.compare {
            ui.colored_label(srgb(paint::COMPARE_COLOR), format!("copy: {}", running.change.describe()))
                .on_hover_text(
                    "Drawn as magenta ghosts over the original; its total energy and error are on the plots",
                );
            if let Some(reason) = &running.stopped {
                ui.colored_label(WARNING_COLOR, format!("stopped: {reason}"));
            }
            if ui.button("Stop the copy").clicked() {
                lab.stop_compare();
            }
            return;
        }
        ui.label("Run a second copy with one setting changed:");
        let mut draft = self.draft.clone();
        let params = lab.scene.params().clone();
        egui::ComboBox::from_id_salt("compare key").selected_text(key(&draft)).show_ui(ui, |ui| {
            let mut options = vec![
                Change::Integrator(Integrator::ExplicitEuler),
                Change::Solver(SolverKind::Paper),
                Change::Rate(60.0),
            ];
            options.extend(params.iter().map(|(param, value)| Change::Param(param.name.to_string(), value)));
            for option in options {
                let label = key(&option);
                if ui.selectable_label(key(&draft) == label, label).clicked() {
                    draft = option;
                }
            }
        });
        match &mut draft {
            Change::Integrator(integrator) => {
                egui::ComboBox::from_id_salt("compare integrator").selected_text(integrator.name()).show_ui(
                    ui,
                    |ui| {
                        for option in Integrator::ALL {
                            ui.selectable_value(integrator, option, option.name());
                        }
                    },
                );
            }
            Change::Solver(kind) => {
                egui::ComboBox::from_id_salt("compare solver").selected_text(kind.name()).show_ui(ui, |ui| {
                    for option in SolverKind::ALL {
                        ui.selectable_value(kind, option, option.name());
                    }
                });
            }
            Change::Rate(rate) => {
                ui.add(egui::DragValue::new(rate).range(PHYSICS_RATE_RANGE).suffix(" Hz"));
            }
            Change::Param(name, value) => {
                if let Some(param) = params.table().iter().find(|p| p.name == *name) {
                    let drag = egui::DragValue::new(value)
                        .range(param.min..=param.max)
                        .speed((param.max - param.min) / 200.0);
                    ui.add(if param.integer { drag.fixed_decimals(0) } else { drag });
                    if param.integer {
                        // A drag moves by fractions: a whole-number parameter takes the
                        // nearest whole one (a fraction would be refused).
                        *value = value.round();
                    }
                }
            }
        }
        self.draft = draft.clone();
        ui.horizontal(|ui| {
            if ui
                .button("Run the copy")
                .on_hover_text("Both the scene and its copy start again from the beginning")
                .clicked()
            {
                lab.start_compare(draft.clone());
            }
            if ui
                .button("Branch from now")
                .on_hover_text(
                    "The copy starts from the scene as it is now (a snapshot), with the one setting \
                     changed; the scene runs on undisturbed",
                )
                .clicked()
            {
                lab.branch_compare(draft);
            }
        });
    }
}

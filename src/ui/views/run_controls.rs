//! The Run section: pause, step, reset and defaults; the time scale and the physics
//! rate; the solver with its substeps, and the integrator.

use crate::physics::solver::SUBSTEP_RANGE;
use crate::physics::{Integrator, SolverKind};
use crate::ui::keys::{self, Command};
use crate::ui::lab::{Lab, PHYSICS_RATE_RANGE, TIME_SCALE_RANGE};
use crate::ui::layout::PanelLayout;

/// The run controls. They remember where the solver menu was drawn (for the window's
/// tests, which press where a person would).
#[derive(Debug, Default)]
pub struct RunControls {
    /// The solver menu's button in the last frame (points).
    pub solver_menu: Option<egui::Rect>,
}

impl RunControls {
    /// Draws the controls and applies what was changed.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
        ui.horizontal(|ui| {
            let label = if lab.paused { "Resume" } else { "Pause" };
            if ui.button(label).on_hover_text("Space").clicked() {
                keys::run(Command::Pause, lab, layout);
            }
            if ui.button("Step").on_hover_text("One physics step (.)").clicked() {
                keys::run(Command::Step, lab, layout);
            }
            if ui.button("Reset").on_hover_text("R").clicked() {
                keys::run(Command::Reset, lab, layout);
            }
            if ui
                .button("Restore defaults")
                .on_hover_text(
                    "The scene's parameters, solver, integrator, physics rate and view back to their defaults",
                )
                .clicked()
            {
                lab.restore_defaults();
            }
        });
        ui.add(
            egui::Slider::new(&mut lab.time_scale, TIME_SCALE_RANGE)
                .logarithmic(true)
                .text("time scale")
                .suffix("×"),
        )
        .on_hover_text("Simulated seconds per real second");
        ui.add(
            egui::Slider::new(&mut lab.physics_rate, PHYSICS_RATE_RANGE)
                .logarithmic(true)
                .text("physics rate")
                .suffix(" Hz"),
        )
        .on_hover_text("Fixed physics steps per simulated second; the frame rate does not change it");
        self.solver_menu = Some(solver_controls(ui, lab));
    }
}

/// The solver menu and, beside it, the soft solver's substeps (greyed for the paper's
/// resolver, which has none), and the integrator. Changes go through
/// [`Lab::set_solver`], which logs them. Returns the solver menu's rectangle.
fn solver_controls(ui: &mut egui::Ui, lab: &mut Lab) -> egui::Rect {
    let mut settings = lab.solver();
    let mut menu = egui::Rect::NOTHING;
    ui.horizontal(|ui| {
        menu = egui::ComboBox::from_id_salt("solver")
            .selected_text(settings.kind.name())
            .width(70.0)
            .show_ui(ui, |ui| {
                for kind in SolverKind::ALL {
                    ui.selectable_value(&mut settings.kind, kind, kind.name()).on_hover_text(kind.summary());
                }
            })
            .response
            .on_hover_text(settings.kind.summary())
            .rect;
        let soft = settings.kind == SolverKind::Soft;
        ui.add_enabled(
            soft,
            egui::DragValue::new(&mut settings.substeps).range(SUBSTEP_RANGE).suffix(" substeps"),
        )
        .on_hover_text("Substeps per physics step: more make piles and chains stiffer, and cost more")
        .on_disabled_hover_text("Only the soft solver takes substeps");
        ui.label("solver");
    });
    ui.horizontal(|ui| {
        egui::ComboBox::from_id_salt("integrator")
            .selected_text(settings.integrator.name())
            .width(150.0)
            .show_ui(ui, |ui| {
                for integrator in Integrator::ALL {
                    ui.selectable_value(&mut settings.integrator, integrator, integrator.name())
                        .on_hover_text(integrator.summary());
                }
            })
            .response
            .on_hover_text(settings.integrator.summary());
        ui.label("integrator");
    });
    if settings != lab.solver() {
        lab.set_solver(settings);
    }
    menu
}

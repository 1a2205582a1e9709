//! The View menu: what the 3D view draws (trails, labels, arrows, debug drawing,
//! colours, grid, stats, anti-aliasing), the side view, follow, the tape measure,
//! framing and the screenshot.

use crate::render::Trails;
use crate::render::frame::VECTOR_PARTICLE_LIMIT;
use crate::ui::keys::{self, Command};
use crate::ui::lab::Lab;
use crate::ui::layout::PanelLayout;

/// The View menu; its ticks are the lab's view state, so they always match the picture.
#[derive(Debug, Default)]
pub struct ViewMenu;

impl ViewMenu {
    /// Draws the menu's items and applies what was ticked.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
        let crowded = lab.scene.world().particles.len() > Trails::PARTICLE_LIMIT;
        ui.add_enabled(!crowded, egui::Checkbox::new(&mut lab.view.trails, "Trails"))
            .on_disabled_hover_text(format!("No trails above {} particles", Trails::PARTICLE_LIMIT));
        let mut tape = lab.tape;
        if ui
            .checkbox(&mut tape, "Tape measure (M)")
            .on_hover_text(
                "Click two points (a particle's centre, or the ground): the status line gives the distance",
            )
            .changed()
        {
            lab.set_tape(tape);
        }
        ui.checkbox(&mut lab.view.labels, "Labels")
            .on_hover_text("Names of objects and links, and metre ticks along the x axis");
        let mut side = lab.side_view;
        if ui
            .checkbox(&mut side, "2D side view (V)")
            .on_hover_text("Looking along -z with no perspective, as a textbook draws it; drag pans")
            .changed()
        {
            lab.set_side_view(side);
        }
        if ui
            .checkbox(&mut lab.follow, "Follow (the selected particle, or the newest)")
            .on_hover_text(
                "The camera keeps the selected particle, or else the round just fired, in the centre; \
                 off again on a new scene or Home",
            )
            .changed()
        {
            lab.follow_particle();
        }
        ui.checkbox(&mut lab.view.forces, "Force arrows (free-body diagram)").on_hover_text(
            "On the selected particle: each force as an arrow in its colour, to the scale the \
             inspector states",
        );
        ui.checkbox(&mut lab.view.all_vectors, "Vectors on every particle").on_hover_text(format!(
            "Velocity (and with force arrows, forces) on every particle, not only the selected one; \
             up to {VECTOR_PARTICLE_LIMIT} particles"
        ));
        ui.checkbox(&mut lab.view.contacts, "Contacts and link limits").on_hover_text(
            "Debug drawing: contact points with their normals (red where they overlap by more than \
             1 mm), a cable's full length and a spring's natural length",
        );
        ui.checkbox(&mut lab.view.swept, "Swept paths (last step)").on_hover_text(
            "For each particle that moved more than its radius in the last step: the path it swept, \
             from a ghost of where it started. Continuous collision has to catch everything along it.",
        );
        ui.checkbox(&mut lab.view.color_by_speed, "Colour by speed")
            .on_hover_text("Particles coloured by how fast they move; the scale is in the panel");
        ui.checkbox(&mut lab.view.predictions, "Predictions").on_hover_text(
            "The predicted read-outs and table columns, the next round's drag-free path and the ghost \
             of the exact solution. Off, a class predicts before it measures; a link can carry it off \
             (predictions=hidden).",
        );
        ui.checkbox(&mut lab.view.tension_colors, "Link colours by tension");
        ui.checkbox(&mut lab.view.grid, "Grid");
        ui.checkbox(&mut lab.view.stats, "Stats");
        ui.checkbox(&mut lab.view.msaa, "Anti-aliasing (4× MSAA)")
            .on_hover_text("Smoother edges; turn off for speed on a software GPU");
        ui.horizontal(|ui| {
            let label = ui.label("Text size");
            ui.add(
                egui::Slider::new(&mut layout.text_size, crate::ui::layout::TEXT_SIZE)
                    .step_by(f64::from(crate::ui::layout::TEXT_SIZE_STEP))
                    .suffix("%"),
            )
            .labelled_by(label.id)
            .on_hover_text("Larger text and controls, for a projector (Ctrl+= and Ctrl+-; Ctrl+0: 100%)");
        });
        ui.separator();
        if ui.button("Frame the scene (Home)").clicked() {
            keys::run(Command::Frame, lab, layout);
            ui.close();
        }
        if ui.button("Save screenshot (F12)").clicked() {
            keys::run(Command::Screenshot, lab, layout);
            ui.close();
        }
    }
}

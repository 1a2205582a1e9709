//! The Stats section: frame and physics timings, the solver's work (contacts, deepest
//! overlap, iterations), the energy ledger's figures and the state hash.

use crate::messages::{fixed, signed};
use crate::physics::SolverKind;
use crate::ui::lab::Lab;
use crate::ui::style::milliseconds;

/// The stats; they keep no state.
#[derive(Debug, Default)]
pub struct StatsPanel;

impl StatsPanel {
    /// The rows the section shows, name and value, as drawn.
    #[must_use]
    pub fn rows(lab: &Lab) -> Vec<(&'static str, String)> {
        let world = lab.scene.world();
        let report = world.last_report();
        let energy = world.energy();
        let stats = lab.stats;
        let mut rows = Vec::new();
        if stats.frame_ms > 0.0 {
            rows.push(("FPS", format!("{:.0} ({:.1} ms)", stats.fps, stats.frame_ms)));
            rows.push(("sim speed", format!("{:.2}× real time", stats.sim_speed)));
        } else {
            rows.push(("FPS", "off-screen".into()));
        }
        rows.push(("physics / step", milliseconds(stats.step_ms)));
        rows.push(("steps / frame", stats.steps_last_frame.to_string()));
        let profile = world.profile();
        rows.push(("  broad phase", milliseconds(profile.broad_phase_ms)));
        rows.push(("  narrow phase", milliseconds(profile.narrow_phase_ms)));
        rows.push(("  solve", milliseconds(profile.solve_ms)));
        if world.solver().kind == SolverKind::Soft {
            // The soft solve's parts, which add up to it (`Profile`).
            rows.push(("    colour", milliseconds(profile.color_ms)));
            rows.push(("    batches", milliseconds(profile.batch_ms)));
            rows.push(("    contact passes", milliseconds(profile.contact_passes_ms)));
            rows.push(("    particle sweeps", milliseconds(profile.particle_sweeps_ms)));
            rows.push(("    store", milliseconds(profile.store_ms)));
        }
        rows.push(("particles", world.particles.len().to_string()));
        rows.push(("step", world.steps().to_string()));
        rows.push(("state hash", lab.state_hash()));
        let solver = world.solver();
        rows.push((
            "solver",
            match solver.kind {
                SolverKind::Soft => format!("{}, {} substeps", solver.kind.name(), solver.substeps),
                SolverKind::Paper => solver.kind.name().to_string(),
            },
        ));
        rows.push(("contacts", world.contact_count().to_string()));
        rows.push(("deepest overlap", format!("{} mm", fixed(report.max_penetration * 1000.0, 2))));
        rows.push(("resolver iterations", report.iterations().to_string()));
        rows.push(("kinetic energy", format!("{} J", fixed(energy.kinetic, 2))));
        rows.push(("potential energy", format!("{} J", fixed(energy.potential, 2))));
        rows.push(("dissipated", format!("{} J", fixed(energy.dissipated, 2))));
        rows.push(("constraint error", format!("{} J", signed(energy.constraint, 3))));
        rows.push(("work put in", format!("{} J", fixed(energy.work, 2))));
        rows.push(("removed with particles", format!("{} J", fixed(energy.removed, 2))));
        rows.push(("integrator error", format!("{} J", signed(energy.error, 3))));
        rows
    }

    /// Draws the rows.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &Lab) {
        egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
            for (name, value) in Self::rows(lab) {
                ui.label(name);
                ui.monospace(value);
                ui.end_row();
            }
        });
    }
}

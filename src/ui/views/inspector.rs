//! The Inspector section: the selected particle, what it is, where, how fast, and the
//! forces on it with units; while paused its mass and velocity can be edited.

use glam::Vec3;

use crate::messages::fixed;
use crate::physics::ParticleId;
use crate::ui::lab::{ACCELERATION_ARROW, CONSTRAINT_FORCE, Lab, VELOCITY_ARROW};
use crate::ui::paint;
use crate::ui::style::srgb;

/// Text size of the inspector's values (points).
const VALUE_SIZE: f32 = 12.0;

/// The inspector: it remembers which particle it last showed, so that picking another
/// opens its section again.
#[derive(Debug, Default)]
pub struct Inspector {
    shown: Option<ParticleId>,
}

impl Inspector {
    /// True once when the selection changed to a particle since the last frame: the
    /// shell then opens the section, where the eye goes after a click.
    pub fn newly_selected(&mut self, lab: &Lab) -> bool {
        let changed = lab.selected != self.shown;
        self.shown = lab.selected;
        changed && lab.selected.is_some()
    }

    /// Draws the selected particle's rows (nothing when none is selected).
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        let Some(id) = lab.selected else { return };
        let world = lab.scene.world();
        let particles = &world.particles;
        let Some(i) = particles.index(id) else {
            lab.select(None);
            return;
        };
        let (p, v) = (particles.positions()[i], particles.velocities()[i]);
        let movable = particles.inverse_masses()[i] > 0.0;
        let mass = particles.mass(i);
        let net = if movable { lab.net_force(id) } else { Vec3::ZERO };
        let vector =
            |x: Vec3, unit: &str| format!("({}, {}, {}) {unit}", fixed(x.x, 1), fixed(x.y, 1), fixed(x.z, 1));
        ui.horizontal(|ui| {
            ui.label(egui::RichText::new(format!("Particle {}", id.0)).strong());
            if ui.small_button("clear").on_hover_text("Clear the selection (or click empty space)").clicked()
            {
                lab.select(None);
            }
        });
        let mut rows = vec![
            ("mass", if movable { format!("{mass:.3} kg") } else { "immovable".into() }),
            ("position", vector(p, "m")),
            ("velocity", vector(v, "m/s")),
            ("speed", format!("{} m/s", fixed(v.length(), 2))),
        ];
        if let Some(spin) = lab.spin(id) {
            rows.push(("angular velocity", vector(spin.angular_velocity, "rad/s")));
            rows.push(("surface speed", format!("{} m/s", fixed(spin.surface_speed, 2))));
            rows.push(("spin energy", format!("{} J", fixed(spin.energy, 3))));
        }
        let forces = lab.free_body(id);
        // Short names and monospace values of a fixed size: the grid then fits the
        // panel's width. The long names say what they mean when hovered.
        let name = |ui: &mut egui::Ui, text: &str, color: Option<egui::Color32>| {
            let (short, meaning) = match text {
                CONSTRAINT_FORCE => ("contacts, links", Some(CONSTRAINT_FORCE)),
                other => (other, None),
            };
            let mut text = egui::RichText::new(short);
            if let Some(color) = color {
                text = text.color(color);
            }
            let response = ui.label(text);
            if let Some(meaning) = meaning {
                response.on_hover_text(meaning);
            }
        };
        let value = |ui: &mut egui::Ui, text: String| {
            ui.label(egui::RichText::new(text).monospace().size(VALUE_SIZE));
        };
        egui::Grid::new("inspector").num_columns(2).striped(true).show(ui, |ui| {
            for (label, text) in rows {
                name(ui, label, None);
                value(ui, text);
                ui.end_row();
            }
            for (label, force) in &forces {
                name(ui, label, Some(srgb(paint::force_color(label))));
                value(ui, vector(*force, "N"));
                ui.end_row();
            }
            if movable {
                name(ui, "net force", Some(srgb(paint::force_color("net force"))));
                value(ui, vector(net, "N"));
                ui.end_row();
                name(ui, "acceleration", Some(srgb(paint::ACCELERATION_COLOR)));
                value(ui, vector(net / mass, "m/s²"));
                ui.end_row();
            }
        });
        let scale = if lab.view.forces {
            format!("forces 1 m per {} N", lab.force_scale())
        } else {
            format!("acceleration (red) 1 m per {} m/s²", 1.0 / ACCELERATION_ARROW)
        };
        ui.add(
            egui::Label::new(
                egui::RichText::new(format!(
                    "Arrows: velocity (green) 1 m per {} m/s; {scale}. Forces are computed \
                     from the state now; weight is mass times the particle's own gravity. Contacts \
                     and links have no force in a state: their row, shown while one acts, is what \
                     the last step's change of momentum needed beyond the other forces.",
                    1.0 / VELOCITY_ARROW,
                ))
                .small(),
            )
            .wrap(),
        );
        if lab.paused && movable {
            edit(ui, lab, id, mass, v);
        }
    }
}

/// The paused particle's mass and velocity, editable; a refused edit (a mass out of
/// range) says why in the status line.
fn edit(ui: &mut egui::Ui, lab: &mut Lab, id: ParticleId, mass: f32, v: Vec3) {
    let (mut new_mass, mut new_v) = (mass, v);
    ui.horizontal(|ui| {
        ui.label("edit:");
        ui.add(egui::DragValue::new(&mut new_mass).range(0.001..=1e6).speed(0.05).suffix(" kg"));
        for component in [&mut new_v.x, &mut new_v.y, &mut new_v.z] {
            ui.add(egui::DragValue::new(component).speed(0.05));
        }
        ui.label("m/s");
    });
    let particles = &mut lab.scene.world_mut().particles;
    let mass_change = (new_mass != mass).then(|| particles.set_mass(id, new_mass));
    let velocity_change = (new_v != v).then(|| particles.set_velocity(id, new_v));
    for error in [mass_change, velocity_change].into_iter().flatten().filter_map(Result::err) {
        lab.status = error.to_string();
    }
}

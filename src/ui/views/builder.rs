//! The builder's section of the panel: the tools, undo and redo, Play, what the Add
//! tool puts down, rows of many, the scene's gravity, ground and collisions, and the
//! selected particle's properties and links. Every change is an edit of the lab's
//! sketch (see `ui/lab/editing.rs`), undone with Ctrl+Z.

use glam::Vec3;

use crate::physics::solver::SUBSTEP_RANGE;
use crate::physics::{Integrator, SolverChoice, SolverKind, SolverSettings};
use crate::scenes::sketch::{Body, COLLISIONS, DragField, End, Float, GROUND, JoinKind};
use crate::ui::lab::{Lab, Pins, Purpose, Tool};

/// The builder's own settings that are not the sketch's.
#[derive(Debug)]
pub struct BuilderPanel {
    /// Particles a row adds.
    row_count: usize,
    /// Rows of a grid (1: a row).
    grid_rows: usize,
    /// Which of the top row are fixed.
    grid_pins: Pins,
    /// Their spacing (m).
    row_spacing: f32,
    /// The link between neighbours of a row (`None`: unlinked).
    row_link: Option<JoinKind>,
}

impl Default for BuilderPanel {
    fn default() -> Self {
        Self {
            row_count: 5,
            grid_rows: 1,
            grid_pins: Pins::First,
            row_spacing: 0.4,
            row_link: Some(JoinKind::Rod),
        }
    }
}

/// A vector's three fields in a row; true if one changed.
fn vector(ui: &mut egui::Ui, label: &str, v: &mut Vec3, speed: f64) -> bool {
    ui.horizontal(|ui| {
        let mut changed = false;
        for (axis, value) in [("x", &mut v.x), ("y", &mut v.y), ("z", &mut v.z)] {
            changed |= ui.add(egui::DragValue::new(value).speed(speed).prefix(format!("{axis} "))).changed();
        }
        ui.label(label);
        changed
    })
    .inner
}

impl BuilderPanel {
    /// Draws the section (only while the builder is open).
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        let Some(editor) = &lab.editor else { return };
        let (can_undo, can_redo) = (editor.can_undo(), editor.can_redo());
        ui.horizontal(|ui| {
            if ui.button("Play").on_hover_text("Run the experiment from this state (B)").clicked() {
                lab.play();
            }
            if ui.add_enabled(can_undo, egui::Button::new("Undo")).on_hover_text("Ctrl+Z").clicked() {
                lab.undo();
            }
            if ui
                .add_enabled(can_redo, egui::Button::new("Redo"))
                .on_hover_text("Ctrl+Shift+Z or Ctrl+Y")
                .clicked()
            {
                lab.redo();
            }
            if ui.button("Save scene as…").on_hover_text("Ctrl+Shift+S").clicked() {
                lab.requests.file = Some(Purpose::SaveScene);
            }
        });
        let Some(editor) = &mut lab.editor else { return };
        ui.horizontal(|ui| {
            ui.label("Tool");
            ui.selectable_value(&mut editor.tool, Tool::Add, "Add")
                .on_hover_text("Click in the view to put a particle there");
            ui.selectable_value(&mut editor.tool, Tool::Select, "Select")
                .on_hover_text("Click a particle to select it; drag one to move it");
            ui.selectable_value(&mut editor.tool, Tool::Join, "Link").on_hover_text(
                "Drag from a particle to another to link them, or to empty space to hang it from a fixed point",
            );
            ui.selectable_value(&mut editor.tool, Tool::Wall, "Wall").on_hover_text(
                "Drag to draw a finite wall: a ramp or a step in the side view, an upright wall on the ground in 3D",
            );
        });
        if editor.tool == Tool::Wall {
            ui.horizontal(|ui| {
                ui.label("Walls");
                ui.add(
                    egui::DragValue::new(&mut editor.wall_width).range(0.05..=100.0).speed(0.05).suffix(" m"),
                )
                .on_hover_text("Width across the drawn line (deep in the side view, high in 3D)");
                ui.label("wide");
            });
        }
        ui.horizontal_wrapped(|ui| {
            ui.label("Link with");
            for kind in JoinKind::ALL {
                ui.selectable_value(&mut editor.join_kind, kind, kind.name());
            }
        });
        if editor.join_kind.elastic() {
            ui.horizontal(|ui| {
                ui.label("k");
                ui.add(egui::DragValue::new(&mut editor.spring_k).range(0.1..=1e6).speed(1.0).suffix(" N/m"))
                    .on_hover_text("Spring constant of new springs and bungees");
            });
        }
        ui.horizontal(|ui| {
            ui.label("New particles");
            ui.add(
                egui::DragValue::new(&mut editor.new_body.mass).range(1e-3..=1e4).speed(0.05).suffix(" kg"),
            );
            ui.add(
                egui::DragValue::new(&mut editor.new_body.radius).range(0.0..=10.0).speed(0.01).suffix(" m"),
            );
        });
        self.row(ui, lab);
        self.scene(ui, lab);
        Self::walls(ui, lab);
        self.selection(ui, lab);
    }

    /// Each wall's size, restitution and friction, and a button to remove it.
    fn walls(ui: &mut egui::Ui, lab: &mut Lab) {
        let Some(editor) = &lab.editor else { return };
        let walls = editor.sketch().walls.clone();
        for (k, wall) in walls.iter().enumerate() {
            let mut edited = *wall;
            let mut remove = false;
            ui.horizontal(|ui| {
                let size = wall.size.map_or("unbounded".to_string(), |[l, w]| format!("{l:.2} × {w:.2} m"));
                ui.label(format!("Wall {k}: {size}"));
                ui.add(
                    egui::DragValue::new(&mut edited.restitution).range(0.0..=1.0).speed(0.01).prefix("e "),
                )
                .on_hover_text("Restitution");
                ui.add(egui::DragValue::new(&mut edited.friction).range(0.0..=2.0).speed(0.01).prefix("μ "))
                    .on_hover_text("Friction");
                remove = ui.small_button("remove").clicked();
            });
            if remove {
                lab.edit("remove a wall", |sketch, _| {
                    sketch.walls.remove(k);
                    true
                });
                lab.end_edit();
                return;
            }
            if edited != *wall {
                lab.edit("wall surface", |sketch, _| {
                    sketch.walls[k] = edited;
                    true
                });
            }
        }
    }

    /// Make many at once: a row or a grid of particles, linked (a chain, a cloth) or
    /// not (a block of balls to drop).
    fn row(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut self.row_count).range(1..=200).prefix("many: "))
                .on_hover_text("Particles along x");
            ui.add(egui::DragValue::new(&mut self.grid_rows).range(1..=100).prefix("× "))
                .on_hover_text("Rows downwards: more than one makes a grid (linked: a cloth)");
            ui.add(
                egui::DragValue::new(&mut self.row_spacing).range(0.01..=10.0).speed(0.01).suffix(" m apart"),
            );
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("its links");
            ui.selectable_value(&mut self.row_link, None, "none");
            for kind in JoinKind::ALL {
                ui.selectable_value(&mut self.row_link, Some(kind), kind.name());
            }
        });
        ui.horizontal(|ui| {
            ui.label("pinned");
            ui.selectable_value(&mut self.grid_pins, Pins::None, "none");
            ui.selectable_value(&mut self.grid_pins, Pins::First, "first");
            ui.selectable_value(&mut self.grid_pins, Pins::Corners, "top corners");
        });
        let hover = "Along x and downwards, from beside the selected particle (or 2 m above the origin)";
        let label = if self.grid_rows > 1 { "Add grid" } else { "Add row" };
        if ui.button(label).on_hover_text(hover).clicked() {
            lab.add_grid([self.row_count, self.grid_rows], self.row_spacing, self.row_link, self.grid_pins);
        }
    }

    /// The scene's name, gravity, ground and collisions.
    fn scene(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        let Some(editor) = &lab.editor else { return };
        let sketch = editor.sketch();
        let (mut name, mut g) = (sketch.name.clone(), sketch.g);
        let (mut ground, mut collisions) = (sketch.ground.is_some(), sketch.collisions.is_some());
        let (mut ground_surface, mut collision_surface) = (sketch.ground, sketch.collisions);
        // The physics rate and air drag on every particle.
        let mut rate = 1.0 / sketch.dt.unwrap_or(1.0 / 240.0);
        let everywhere = sketch.drags.iter().position(|d| d.targets.is_none());
        let mut k1 = everywhere.map_or(0.0, |k| sketch.drags[k].k1);
        let mut renamed = false;
        ui.horizontal(|ui| {
            ui.label("Name");
            let field = ui.add(egui::TextEdit::singleline(&mut name).desired_width(160.0));
            renamed = field.lost_focus() && !name.trim().is_empty();
        });
        let mut changed_g = false;
        let mut changed_surfaces = false;
        ui.horizontal(|ui| {
            changed_g = ui
                .add(egui::DragValue::new(&mut g).range(0.0..=30.0).speed(0.05).prefix("g ").suffix(" m/s²"))
                .changed();
            changed_surfaces |= ui.checkbox(&mut ground, "ground").changed();
            changed_surfaces |= ui
                .checkbox(&mut collisions, "collisions")
                .on_hover_text("Particles with a radius bounce off each other")
                .changed();
        });
        if renamed && name.trim() != sketch.name {
            lab.edit("rename", |sketch, _| {
                sketch.name = name.trim().to_string();
                true
            });
            lab.end_edit();
        }
        if changed_g {
            lab.edit("g", |sketch, _| {
                sketch.g = g;
                true
            });
        }
        let (mut changed_rate, mut changed_drag) = (false, false);
        ui.horizontal(|ui| {
            changed_rate = ui
                .add(egui::DragValue::new(&mut rate).range(10.0..=10_000.0).speed(1.0).suffix(" Hz"))
                .on_hover_text("Physics steps a second (the time step is one over it)")
                .changed();
            changed_drag = ui
                .add(
                    egui::DragValue::new(&mut k1)
                        .range(0.0..=100.0)
                        .speed(0.01)
                        .prefix("air drag ")
                        .suffix(" N·s/m"),
                )
                .on_hover_text("Linear drag on every particle, F = −k1 v")
                .changed();
        });
        if changed_rate {
            lab.edit("rate", |sketch, _| {
                sketch.dt = Some(1.0 / rate);
                true
            });
        }
        if changed_drag {
            lab.edit("air drag", |sketch, _| {
                match (everywhere, k1 > 0.0) {
                    (Some(k), true) => sketch.drags[k].k1 = k1,
                    (Some(k), false) if sketch.drags[k].k2 == 0.0 => {
                        sketch.drags.remove(k);
                    }
                    (Some(k), false) => sketch.drags[k].k1 = 0.0,
                    (None, true) => sketch.drags.push(DragField { k1, k2: 0.0, targets: None }),
                    (None, false) => return false,
                }
                true
            });
        }
        Self::solver(ui, lab);
        if changed_surfaces {
            lab.edit("surroundings", |sketch, _| {
                sketch.ground = ground.then_some(sketch.ground.unwrap_or(GROUND));
                sketch.collisions = collisions.then_some(sketch.collisions.unwrap_or(COLLISIONS));
                true
            });
            lab.end_edit();
            return;
        }
        // The bounce and friction of the ground and of particles against each other.
        let mut changed = false;
        for (what, surface) in
            [("ground", &mut ground_surface), ("between particles", &mut collision_surface)]
        {
            let Some(surface) = surface else { continue };
            ui.horizontal(|ui| {
                ui.label(what);
                changed |= ui
                    .add(
                        egui::DragValue::new(&mut surface.restitution)
                            .range(0.0..=1.0)
                            .speed(0.01)
                            .prefix("e "),
                    )
                    .on_hover_text("Restitution: the share of the approach speed a bounce gives back")
                    .changed();
                changed |= ui
                    .add(
                        egui::DragValue::new(&mut surface.friction).range(0.0..=2.0).speed(0.01).prefix("μ "),
                    )
                    .on_hover_text("Coulomb friction coefficient")
                    .changed();
            });
        }
        if changed {
            lab.edit("surface", |sketch, _| {
                (sketch.ground, sketch.collisions) = (ground_surface, collision_surface);
                true
            });
        }
    }

    /// Whether particle `i` floats in a liquid (buoyancy, the paper's Archimedes force
    /// generator), with the liquid's surface height and density.
    fn float(ui: &mut egui::Ui, lab: &mut Lab, i: usize, body: &Body) {
        let Some(editor) = &lab.editor else { return };
        let at = editor.sketch().floats.iter().position(|f| f.particle == i);
        let before = at.map(|k| editor.sketch().floats[k]);
        let mut floats = before.is_some();
        // Water, its surface level with the particle, which is a sphere of its radius (a
        // point: a 10 cm ball).
        let r = if body.radius > 0.0 { body.radius } else { 0.1 };
        let mut float = before.unwrap_or(Float {
            particle: i,
            surface: body.position.y,
            half_height: r,
            volume: 4.0 / 3.0 * std::f32::consts::PI * r * r * r,
            density: 1000.0,
        });
        ui.horizontal(|ui| {
            ui.checkbox(&mut floats, "floats").on_hover_text(
                "Buoyancy: a liquid lifts it with the weight of the liquid it displaces (ρ V g when under)",
            );
            if floats {
                ui.add(egui::DragValue::new(&mut float.surface).speed(0.01).prefix("surface ").suffix(" m"))
                    .on_hover_text("Height of the liquid's surface");
                ui.add(
                    egui::DragValue::new(&mut float.density)
                        .range(1.0..=20_000.0)
                        .speed(5.0)
                        .prefix("ρ ")
                        .suffix(" kg/m³"),
                )
                .on_hover_text("Density of the liquid (water: 1000 kg/m³)");
            }
        });
        let after = floats.then_some(float);
        if after != before {
            lab.edit("floats", |sketch, _| {
                sketch.floats.retain(|f| f.particle != i);
                sketch.floats.extend(after);
                true
            });
        }
    }

    /// The scene's own solver, substeps and integrator, saved with it (`[scene]
    /// solver`, `substeps`, `integrator`) and run by Play.
    fn solver(ui: &mut egui::Ui, lab: &mut Lab) {
        let Some(editor) = &lab.editor else { return };
        let before = editor.sketch().solver.over(SolverSettings::default());
        let mut solver = before;
        ui.horizontal(|ui| {
            let label = ui.label("solver");
            egui::ComboBox::from_id_salt("builder solver")
                .selected_text(solver.kind.name())
                .show_ui(ui, |ui| {
                    for kind in SolverKind::ALL {
                        ui.selectable_value(&mut solver.kind, kind, kind.name())
                            .on_hover_text(kind.summary());
                    }
                })
                .response
                .labelled_by(label.id)
                .on_hover_text("The scene's constraint solver, saved with it");
            if solver.kind == SolverKind::Soft {
                ui.add(egui::DragValue::new(&mut solver.substeps).range(SUBSTEP_RANGE).suffix(" substeps"))
                    .on_hover_text(
                        "Substeps per physics step: more make stiff links and tall piles converge",
                    );
            }
        });
        ui.horizontal(|ui| {
            let label = ui.label("integrator");
            egui::ComboBox::from_id_salt("builder integrator")
                .selected_text(solver.integrator.name())
                .show_ui(ui, |ui| {
                    for integrator in Integrator::ALL {
                        ui.selectable_value(&mut solver.integrator, integrator, integrator.name())
                            .on_hover_text(integrator.summary());
                    }
                })
                .response
                .labelled_by(label.id)
                .on_hover_text("How motion is advanced each (sub)step, saved with the scene");
        });
        if solver != before {
            lab.edit("solver", |sketch, _| {
                sketch.solver = SolverChoice::differing(&solver);
                true
            });
        }
    }

    /// The selected particle: where, how fast, how heavy, pinned, rolling; its links;
    /// duplicate and delete.
    fn selection(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        let Some(editor) = &lab.editor else { return };
        let Some(i) = editor.selected else {
            ui.label(egui::RichText::new("Select a particle to set its mass, speed and links").small());
            return;
        };
        let Some(before) = editor.sketch().bodies.get(i).cloned() else { return };
        // Names the other particles have: a name must be one particle's.
        let taken: Vec<String> = editor
            .sketch()
            .bodies
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != i)
            .filter_map(|(_, b)| b.name.clone())
            .collect();
        let links: Vec<(usize, String)> = editor
            .sketch()
            .joins_of(i)
            .map(|(k, j)| {
                let other = match j.b {
                    End::Body(b) if b == i => format!("particle {}", j.a),
                    End::Body(b) => format!("particle {b}"),
                    End::Anchor(_) => "a fixed point".to_string(),
                };
                (k, format!("{} {:.3} m to {other}", j.kind.name(), j.length))
            })
            .collect();
        ui.separator();
        ui.label(egui::RichText::new(format!("Particle {i}")).strong());
        let mut body = before.clone();
        let mut changed = None;
        ui.horizontal(|ui| {
            let mut name = body.name.clone().unwrap_or_default();
            let field = ui
                .add(egui::TextEdit::singleline(&mut name).hint_text("label").desired_width(110.0))
                .on_hover_text("Its label in the view (one particle's)");
            if field.lost_focus() {
                let name = name.trim().to_string();
                let name = (!name.is_empty() && !taken.contains(&name)).then_some(name);
                if name != body.name {
                    body.name = name;
                    changed = Some("label");
                }
            }
            let mut rgb = body.color.unwrap_or([0.9, 0.55, 0.1]);
            if ui.color_edit_button_rgb(&mut rgb).on_hover_text("Its colour in the view").changed() {
                body.color = Some(rgb);
                changed = Some("colour");
            }
            if body.color.is_some()
                && ui.small_button("palette").on_hover_text("The lab's own colour").clicked()
            {
                body.color = None;
                changed = Some("colour");
            }
        });
        if vector(ui, "position (m)", &mut body.position, 0.01) {
            changed = Some("position");
        }
        if vector(ui, "velocity (m/s)", &mut body.velocity, 0.05) {
            changed = Some("velocity");
        }
        ui.horizontal(|ui| {
            if ui
                .add(egui::DragValue::new(&mut body.mass).range(1e-3..=1e4).speed(0.05).suffix(" kg"))
                .changed()
            {
                changed = Some("mass");
            }
            if ui
                .add(egui::DragValue::new(&mut body.radius).range(0.0..=10.0).speed(0.01).suffix(" m"))
                .changed()
            {
                changed = Some("radius");
            }
            let damping =
                egui::DragValue::new(&mut body.damping).range(0.0..=1.0).speed(0.005).prefix("damping ");
            if ui.add(damping).on_hover_text("Fraction of velocity kept per second (1: none)").changed() {
                changed = Some("damping");
            }
        });
        ui.horizontal(|ui| {
            if ui.checkbox(&mut body.fixed, "pinned").changed() {
                changed = Some("pinned");
            }
            if ui
                .checkbox(&mut body.rolls, "rolls")
                .on_hover_text("A solid sphere that friction turns")
                .changed()
            {
                changed = Some("rolls");
            }
        });
        Self::float(ui, lab, i, &body);
        if let Some(change) = changed {
            let moved = body.position != before.position;
            lab.edit(change, |sketch, _| {
                sketch.bodies[i] = body;
                if moved {
                    sketch.fit_lengths(i);
                }
                true
            });
        }
        let mut remove_link = None;
        for (k, text) in &links {
            ui.horizontal(|ui| {
                ui.label(text);
                if ui.small_button("remove").clicked() {
                    remove_link = Some(*k);
                }
            });
        }
        if let Some(k) = remove_link {
            lab.edit("remove a link", |sketch, _| {
                sketch.joins.remove(k);
                true
            });
            lab.end_edit();
        }
        ui.horizontal(|ui| {
            if ui.button("Duplicate").on_hover_text("A copy beside it, unlinked").clicked() {
                let offset = Vec3::X * (before.radius * 2.0 + 0.1);
                lab.edit("duplicate", |sketch, editor| {
                    editor.selected = sketch.duplicate(i, offset).or(editor.selected);
                    true
                });
                lab.end_edit();
            }
            if ui.button("Delete").on_hover_text("Delete").clicked() {
                lab.delete_selected();
            }
        });
    }
}

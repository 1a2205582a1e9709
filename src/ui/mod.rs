//! The egui panel: menu bar, side panel (scene parameters, run controls, stats, energy
//! plot), help window, and the 3D view's mouse handling. The same code runs in the
//! window and in `render --ui`.

pub mod compare;
pub mod lab;
pub mod paint;
pub mod scene_files;

use egui::{Color32, Key, Modifiers, PointerButton, Rect, Sense, Stroke};
use glam::{Vec2, Vec3};

use crate::messages::{fixed, signed};
use crate::physics::LinkKind;
use crate::physics::solver::SUBSTEP_RANGE;
use crate::physics::{Integrator, SolverKind};
use crate::render::Trails;
use crate::render::frame::{
    SPEED_SCALE, VECTOR_PARTICLE_LIMIT, link_color, ramp_srgb, speed_fraction, tension_color,
    tension_reference,
};
use crate::scenes::{SCENES, SceneAction};
pub use lab::Lab;

/// Width of the side panel (points): fixed, so a long read-out wraps instead of
/// widening it, and narrow enough for the view to keep most of an 800x600 window.
pub const PANEL_WIDTH: f32 = 330.0;

/// Keyboard shortcuts, as shown in the Help window.
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("Space", "pause / resume"),
    (".", "one physics step"),
    ("R", "reset the scene"),
    ("F", "fire (projectile)"),
    ("P", "hide / show the panel"),
    ("V", "2D side view on / off"),
    ("Arrows / WASD", "move the load (bridge)"),
    ("Home", "frame the scene"),
    ("F12", "save a screenshot"),
    ("Ctrl+Q", "quit"),
    ("Left drag on a particle", "drag it (let go to throw)"),
    ("Left drag elsewhere", "orbit the camera"),
    ("Right or middle drag", "pan"),
    ("Wheel", "zoom"),
];

/// Draws the whole interface for one frame and handles its input. Returns the 3D
/// view's rectangle (in points).
pub fn show(ui: &mut egui::Ui, lab: &mut Lab) -> Rect {
    lab.poll_scene_file();
    shortcuts(ui.ctx(), lab);
    egui::Panel::top("menu").show(ui, |ui| menu_bar(ui, lab));
    if !lab.status.is_empty() {
        egui::Panel::bottom("status").show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.label(&lab.status);
                if ui.small_button("Dismiss").clicked() {
                    lab.status.clear();
                }
            });
        });
    }
    if lab.panel_open {
        egui::Panel::left("controls").exact_size(PANEL_WIDTH).resizable(false).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                // Long read-outs wrap instead of widening the panel.
                ui.set_max_width(PANEL_WIDTH - 16.0);
                side_panel(ui, lab);
            });
        });
    }
    let mut open = lab.show_help;
    egui::Window::new("Controls").open(&mut open).resizable(false).show(ui.ctx(), help);
    lab.show_help = open;
    egui::CentralPanel::no_frame().show(ui, |ui| view_3d(ui, lab)).inner
}

fn shortcuts(ctx: &egui::Context, lab: &mut Lab) {
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    ctx.input_mut(|input| {
        if input.consume_key(Modifiers::COMMAND, Key::Q) {
            lab.requests.quit = true;
        }
        if input.consume_key(Modifiers::NONE, Key::Space) {
            lab.paused = !lab.paused;
            log::info!("paused: {}", lab.paused);
            if lab.paused {
                // What the window test compares with `simulate`'s hash at that step.
                log::info!("paused at step {}, state hash {}", lab.scene.world().steps(), lab.state_hash());
            }
        }
        if input.consume_key(Modifiers::NONE, Key::F5) {
            lab.quick_save();
        }
        if input.consume_key(Modifiers::NONE, Key::F9) {
            lab.quick_load();
        }
        if input.consume_key(Modifiers::NONE, Key::Period) {
            lab.paused = true;
            lab.run_steps(1);
        }
        if input.consume_key(Modifiers::NONE, Key::R) {
            lab.reset();
        }
        if input.consume_key(Modifiers::NONE, Key::F) {
            lab.act(SceneAction::Fire);
        }
        if input.consume_key(Modifiers::NONE, Key::P) {
            lab.panel_open = !lab.panel_open;
            log::info!("panel open: {}", lab.panel_open);
        }
        if input.consume_key(Modifiers::NONE, Key::V) {
            let side = !lab.side_view;
            lab.set_side_view(side);
        }
        if input.consume_key(Modifiers::NONE, Key::Home) {
            lab.frame_scene();
        }
        if input.consume_key(Modifiers::NONE, Key::F12) {
            lab.requests.screenshot = true;
        }
        let step = crate::scenes::LOAD_STEP;
        for (keys, dx, dz) in [
            ([Key::ArrowLeft, Key::A], -step, 0.0),
            ([Key::ArrowRight, Key::D], step, 0.0),
            ([Key::ArrowUp, Key::W], 0.0, -step),
            ([Key::ArrowDown, Key::S], 0.0, step),
        ] {
            for key in keys {
                if input.consume_key(Modifiers::NONE, key) {
                    lab.act(SceneAction::MoveLoad { dx, dz });
                }
            }
        }
    });
}

fn menu_bar(ui: &mut egui::Ui, lab: &mut Lab) {
    egui::MenuBar::new().ui(ui, |ui| {
        scene_files::file_menu(ui, lab);
        ui.menu_button("Scene", |ui| {
            for entry in SCENES {
                let current = std::ptr::eq(entry, lab.entry);
                if ui.selectable_label(current, entry.info.name).on_hover_text(entry.info.summary).clicked() {
                    lab.switch_scene(entry);
                    ui.close();
                }
            }
            scene_files::scene_menu(ui, lab);
        });
        ui.menu_button("View", |ui| {
            let crowded = lab.scene.world().particles.len() > Trails::PARTICLE_LIMIT;
            ui.add_enabled(!crowded, egui::Checkbox::new(&mut lab.view.trails, "Trails"))
                .on_disabled_hover_text(format!("No trails above {} particles", Trails::PARTICLE_LIMIT));
            if ui
                .checkbox(&mut lab.tape, "Tape measure")
                .on_hover_text("Click two points (a particle's centre, or the ground): the status line gives the distance")
                .changed()
            {
                lab.tape_points.clear();
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
                .on_hover_text("The camera keeps the selected particle, or else the round just fired, in the centre")
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
            ui.checkbox(&mut lab.view.tension_colors, "Link colours by tension");
            ui.checkbox(&mut lab.view.grid, "Grid");
            ui.checkbox(&mut lab.view.stats, "Stats");
            ui.checkbox(&mut lab.view.msaa, "Anti-aliasing (4× MSAA)")
                .on_hover_text("Smoother edges; turn off for speed on a software GPU");
            ui.separator();
            if ui.button("Frame the scene (Home)").clicked() {
                lab.frame_scene();
                ui.close();
            }
            if ui.button("Save screenshot (F12)").clicked() {
                lab.requests.screenshot = true;
                ui.close();
            }
        });
        if ui.selectable_label(lab.panel_open, "Panel").on_hover_text("Hide or show the side panel (P)").clicked() {
            lab.panel_open = !lab.panel_open;
        }
        ui.menu_button("Help", |ui| {
            if ui.button("Controls and shortcuts").clicked() {
                lab.show_help = true;
                ui.close();
            }
        });
        ui.separator();
        ui.label(egui::RichText::new(lab.entry.info.name).strong());
        ui.label(format!("t = {:.2} s", lab.scene.world().time()));
        if lab.paused {
            ui.colored_label(Color32::from_rgb(240, 190, 60), "paused");
        }
        if let Some(note) = lab.time_scale_note() {
            ui.colored_label(Color32::from_rgb(240, 170, 60), note).on_hover_text(
                "The physics cannot keep up with the time scale: each frame runs as many steps as its \
                 budget allows. Lower the time scale or the physics rate.",
            );
        }
    });
}

/// The File menu's snapshot items: a path, Save and Load, and the quick save keys.
pub(crate) fn snapshot_menu(ui: &mut egui::Ui, lab: &mut Lab) {
    ui.label("Snapshot file");
    ui.add(egui::TextEdit::singleline(&mut lab.snapshot_path).desired_width(260.0)).on_hover_text(
        "A snapshot holds the whole state: scene, parameters, solver, every particle and link, time",
    );
    let path = std::path::PathBuf::from(lab.snapshot_path.trim());
    ui.horizontal(|ui| {
        if ui.button("Save snapshot").clicked() {
            lab.save_snapshot_to(&path);
            ui.close();
        }
        if ui
            .button("Load snapshot")
            .on_hover_text("A bad file changes nothing; the status line says why")
            .clicked()
        {
            lab.load_snapshot_from(&path);
            ui.close();
        }
    });
    ui.separator();
    if ui.button("Quick save (F5)").clicked() {
        lab.quick_save();
        ui.close();
    }
    if ui.button("Back to quick save (F9)").clicked() {
        lab.quick_load();
        ui.close();
    }
}

fn side_panel(ui: &mut egui::Ui, lab: &mut Lab) {
    ui.heading(lab.entry.info.name);
    ui.label(lab.entry.info.summary);
    ui.separator();

    ui.horizontal(|ui| {
        let label = if lab.paused { "Resume" } else { "Pause" };
        if ui.button(label).on_hover_text("Space").clicked() {
            lab.paused = !lab.paused;
        }
        if ui.button("Step").on_hover_text("One physics step (.)").clicked() {
            lab.paused = true;
            lab.run_steps(1);
        }
        if ui.button("Reset").on_hover_text("R").clicked() {
            lab.reset();
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
        egui::Slider::new(&mut lab.time_scale, TIME_SCALE.clone())
            .logarithmic(true)
            .text("time scale")
            .suffix("×"),
    )
    .on_hover_text("Simulated seconds per real second");
    ui.add(
        egui::Slider::new(&mut lab.physics_rate, PHYSICS_RATE.clone())
            .logarithmic(true)
            .text("physics rate")
            .suffix(" Hz"),
    )
    .on_hover_text("Fixed physics steps per simulated second; the frame rate does not change it");
    solver_controls(ui, lab);

    ui.separator();
    ui.label(egui::RichText::new("Parameters").strong());
    let mut changes = Vec::new();
    for (param, value) in lab.scene.params().iter() {
        let mut edited = value;
        let label = if param.unit.is_empty() {
            param.name.to_string()
        } else {
            format!("{} ({})", param.name, param.unit)
        };
        let response = ui
            .add(
                egui::Slider::new(&mut edited, param.min..=param.max)
                    .logarithmic(param.logarithmic)
                    // A typed value beyond the range reaches the lab, which clamps it
                    // and says so.
                    .clamping(egui::SliderClamping::Never)
                    .text(label),
            )
            .on_hover_text(param.help);
        if response.changed() && edited != value {
            changes.push((param.name, edited));
        }
        if let Some(warning) = lab.scene.param_warning(param.name, lab.integration_step()) {
            ui.colored_label(Color32::from_rgb(240, 170, 60), warning);
        }
    }
    for (name, value) in changes {
        lab.set_param_typed(name, value);
    }
    let presets = lab.entry.info.presets;
    if !presets.is_empty() {
        ui.label("Presets");
        ui.horizontal_wrapped(|ui| {
            for preset in presets {
                if ui.button(preset.name).on_hover_text(preset.help).clicked() {
                    lab.apply_preset(preset.name);
                }
            }
        });
    }
    let actions = lab.entry.info.actions;
    if !actions.is_empty() {
        ui.horizontal_wrapped(|ui| {
            for action in actions {
                if ui.button(action.label).on_hover_text(action.key).clicked() {
                    lab.act(action.action);
                }
            }
        });
    }

    compare_controls(ui, lab);

    ui.separator();
    egui::Grid::new("readouts").num_columns(2).striped(true).show(ui, |ui| {
        for (name, value) in lab.readouts() {
            ui.label(name.as_str());
            ui.add(egui::Label::new(value.as_str()).wrap());
            ui.end_row();
        }
    });
    if lab.view.color_by_speed {
        ui.separator();
        speed_legend(ui);
    }
    link_key(ui, lab);
    // Above the inspector and the stats, so it is in view at 1280x720.
    ui.separator();
    energy_plot(ui, lab);
    if ui
        .small_button("Export energy as CSV")
        .on_hover_text("Every sample kept, to the current directory")
        .clicked()
    {
        let path = std::path::PathBuf::from(format!(
            "energy-{}-t{:.0}s.csv",
            lab.entry.info.name,
            lab.scene.world().time()
        ));
        lab.status = match lab.export_energy_csv(&path) {
            Ok(()) => format!("energy written to {}", path.display()),
            Err(error) => format!("could not write {}: {error}", path.display()),
        };
    }
    error_plot(ui, lab);
    ui.separator();
    energy_bars(ui, lab);
    if lab.selected.is_some() {
        ui.separator();
        inspector(ui, lab);
    }

    if lab.view.stats {
        ui.separator();
        ui.label(egui::RichText::new("Stats").strong());
        let world = lab.scene.world();
        let report = world.last_report();
        let energy = world.energy();
        egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
            let mut row = |name: &str, value: String| {
                ui.label(name);
                ui.monospace(value);
                ui.end_row();
            };
            let stats = lab.stats;
            if stats.frame_ms > 0.0 {
                row("FPS", format!("{:.0} ({:.1} ms)", stats.fps, stats.frame_ms));
                row("sim speed", format!("{:.2}× real time", stats.sim_speed));
            } else {
                row("FPS", "off-screen".into());
            }
            row("physics / step", milliseconds(stats.step_ms));
            row("steps / frame", stats.steps_last_frame.to_string());
            let profile = world.profile();
            row("  broad phase", milliseconds(profile.broad_phase_ms));
            row("  narrow phase", milliseconds(profile.narrow_phase_ms));
            row("  solve", milliseconds(profile.solve_ms));
            row("particles", world.particles.len().to_string());
            row("step", world.steps().to_string());
            row("state hash", lab.state_hash());
            let solver = world.solver();
            row(
                "solver",
                match solver.kind {
                    SolverKind::Soft => format!("{}, {} substeps", solver.kind.name(), solver.substeps),
                    SolverKind::Paper => solver.kind.name().to_string(),
                },
            );
            row("contacts", world.contact_count().to_string());
            row("deepest overlap", format!("{:.2} mm", report.max_penetration * 1000.0));
            row("resolver iterations", report.iterations().to_string());
            row("kinetic energy", format!("{} J", fixed(energy.kinetic, 2)));
            row("potential energy", format!("{} J", fixed(energy.potential, 2)));
            row("dissipated", format!("{} J", fixed(energy.dissipated, 2)));
            row("work put in", format!("{} J", fixed(energy.work, 2)));
            row("removed with particles", format!("{} J", fixed(energy.removed, 2)));
            row("integrator error", format!("{} J", signed(energy.error, 3)));
        });
    }
}

/// The Compare section: pick one setting and its value for a second copy of the scene,
/// run it beside the original (both start again), or stop it.
fn compare_controls(ui: &mut egui::Ui, lab: &mut Lab) {
    use compare::Change;
    let header = if lab.compare.is_some() { "Compare (running)" } else { "Compare" };
    let section = egui::CollapsingHeader::new(header).id_salt("compare").default_open(lab.compare_open);
    let shown = section.show(ui, |ui| {
        if let Some(running) = &lab.compare {
            ui.colored_label(srgb(paint::COMPARE_COLOR), format!("copy: {}", running.change.describe()))
                .on_hover_text(
                    "Drawn as magenta ghosts over the original; its total energy and error are on the plots",
                );
            if let Some(reason) = &running.stopped {
                ui.colored_label(Color32::from_rgb(240, 170, 60), format!("stopped: {reason}"));
            }
            if ui.button("Stop the copy").clicked() {
                lab.stop_compare();
            }
            return;
        }
        ui.label("Run a second copy with one setting changed:");
        let mut draft = lab.compare_draft;
        let key = |change: &Change| match change {
            Change::Integrator(_) => "integrator",
            Change::Solver(_) => "solver",
            Change::Rate(_) => "physics rate",
            Change::Param(name, _) => name,
        };
        let params = lab.scene.params().clone();
        egui::ComboBox::from_id_salt("compare key").selected_text(key(&draft)).show_ui(ui, |ui| {
            let mut options = vec![
                Change::Integrator(Integrator::ExplicitEuler),
                Change::Solver(SolverKind::Paper),
                Change::Rate(60.0),
            ];
            options.extend(params.iter().map(|(param, value)| Change::Param(param.name, value)));
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
                ui.add(egui::DragValue::new(rate).range(PHYSICS_RATE.clone()).suffix(" Hz"));
            }
            Change::Param(name, value) => {
                if let Some(param) = params.table().iter().find(|p| p.name == *name) {
                    ui.add(
                        egui::DragValue::new(value)
                            .range(param.min..=param.max)
                            .speed((param.max - param.min) / 200.0),
                    );
                }
            }
        }
        lab.compare_draft = draft;
        ui.horizontal(|ui| {
            if ui
                .button("Run the copy")
                .on_hover_text("Both the scene and its copy start again from the beginning")
                .clicked()
            {
                lab.start_compare(draft);
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
    });
    // Kept with the settings once the section has finished opening or closing.
    if shown.openness == 0.0 || shown.openness == 1.0 {
        lab.compare_open = shown.openness == 1.0;
    }
}

/// `ms` milliseconds, as µs below one.
fn milliseconds(ms: f32) -> String {
    if ms < 1.0 { format!("{:.0} µs", ms * 1000.0) } else { format!("{ms:.1} ms") }
}

/// The solver menu and, beside it, the soft solver's substeps (greyed for the paper's
/// resolver, which has none). Changes go through [`Lab::set_solver`], which logs them.
fn solver_controls(ui: &mut egui::Ui, lab: &mut Lab) {
    let mut settings = lab.solver();
    ui.horizontal(|ui| {
        egui::ComboBox::from_id_salt("solver")
            .selected_text(settings.kind.name())
            .width(70.0)
            .show_ui(ui, |ui| {
                for kind in SolverKind::ALL {
                    ui.selectable_value(&mut settings.kind, kind, kind.name()).on_hover_text(kind.summary());
                }
            })
            .response
            .on_hover_text(settings.kind.summary());
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
}

/// A linear-RGB colour as egui's sRGB.
fn srgb([r, g, b]: [f32; 3]) -> Color32 {
    let channel = |c: f32| (c.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0 + 0.5) as u8;
    Color32::from_rgb(channel(r), channel(g), channel(b))
}

/// The key to the links' colours: a swatch per kind of link in the scene, or with
/// colours by tension the scale from the hardest push (cyan) through none (blue) to the
/// hardest pull (red), in N, as the view paints it this frame.
fn link_key(ui: &mut egui::Ui, lab: &Lab) {
    let links = lab.scene.world().links();
    if links.is_empty() {
        return;
    }
    ui.separator();
    if !lab.view.tension_colors {
        let mut kinds: Vec<LinkKind> = Vec::new();
        for link in &links {
            if !kinds.contains(&link.spec.kind) {
                kinds.push(link.spec.kind);
            }
        }
        ui.horizontal_wrapped(|ui| {
            ui.label(egui::RichText::new("Links").strong())
                .on_hover_text("View → Link colours by tension colours them by the force they carry");
            for kind in kinds {
                let (swatch, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), Sense::hover());
                ui.painter().rect_filled(swatch, 2.0, srgb(link_color(kind)));
                ui.label(kind.name().replace('_', " "));
            }
        });
        return;
    }
    let reference = tension_reference(&links);
    ui.label(egui::RichText::new("Link tension").strong()).on_hover_text(
        "Scaled to the link carrying the most this frame; the square root spreads the colours of \
         lightly loaded links",
    );
    let width = ui.available_width().min(280.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 30.0), Sense::hover());
    let painter = ui.painter_at(rect);
    let bar = Rect::from_min_size(rect.min, egui::vec2(rect.width(), 12.0));
    const BANDS: usize = 48;
    for band in 0..BANDS {
        // From -reference (left) to +reference (right).
        let tension = reference * (2.0 * (band as f32 + 0.5) / BANDS as f32 - 1.0);
        let left = bar.left() + bar.width() * band as f32 / BANDS as f32;
        let right = bar.left() + bar.width() * (band + 1) as f32 / BANDS as f32;
        let band_rect = Rect::from_x_y_ranges(left..=right + 0.5, bar.y_range());
        painter.rect_filled(band_rect, 0.0, srgb(tension_color(tension, reference)));
    }
    for (at, align, text) in [
        (0.0, egui::Align2::LEFT_TOP, format!("{:.0} N push", reference)),
        (0.5, egui::Align2::CENTER_TOP, "0".to_string()),
        (1.0, egui::Align2::RIGHT_TOP, format!("{:.0} N pull", reference)),
    ] {
        let x = bar.left() + bar.width() * at;
        painter.text(
            egui::pos2(x, bar.bottom() + 3.0),
            align,
            text,
            egui::FontId::proportional(11.0),
            Color32::GRAY,
        );
    }
}

/// The colour-by-speed scale: the ramp with speeds (m/s) under it.
fn speed_legend(ui: &mut egui::Ui) {
    ui.label(egui::RichText::new("Colour by speed").strong())
        .on_hover_text(format!("A fixed scale, square root of speed: {SPEED_SCALE} m/s and faster are red"));
    let width = ui.available_width().min(280.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 30.0), Sense::hover());
    let painter = ui.painter_at(rect);
    let bar = Rect::from_min_size(rect.min, egui::vec2(rect.width(), 12.0));
    const BANDS: usize = 48;
    for band in 0..BANDS {
        let [r, g, b] = ramp_srgb((band as f32 + 0.5) / BANDS as f32);
        let left = bar.left() + bar.width() * band as f32 / BANDS as f32;
        let right = bar.left() + bar.width() * (band + 1) as f32 / BANDS as f32;
        let band_rect = Rect::from_x_y_ranges(left..=right + 0.5, bar.y_range());
        painter.rect_filled(band_rect, 0.0, Color32::from_rgb(r, g, b));
    }
    for (speed, label) in
        [(0.0, "0"), (0.1, "0.1"), (1.0, "1"), (2.5, "2.5"), (5.0, "5"), (SPEED_SCALE, "10 m/s")]
    {
        let x = bar.left() + bar.width() * speed_fraction(speed);
        painter.line_segment(
            [egui::pos2(x, bar.bottom()), egui::pos2(x, bar.bottom() + 3.0)],
            Stroke::new(1.0, Color32::GRAY),
        );
        let align = match label {
            "0" => egui::Align2::LEFT_TOP,
            "10 m/s" => egui::Align2::RIGHT_TOP,
            _ => egui::Align2::CENTER_TOP,
        };
        painter.text(
            egui::pos2(x, bar.bottom() + 3.0),
            align,
            label,
            egui::FontId::proportional(11.0),
            Color32::GRAY,
        );
    }
}

const TIME_SCALE: std::ops::RangeInclusive<f32> = lab::TIME_SCALE_RANGE;
const PHYSICS_RATE: std::ops::RangeInclusive<f32> = lab::PHYSICS_RATE_RANGE;

/// Arrow scales of the inspector's vectors: metres of arrow per m/s of velocity and per
/// m/s² of acceleration (force over mass).
pub const VELOCITY_ARROW: f32 = 0.25;
/// See [`VELOCITY_ARROW`].
pub const ACCELERATION_ARROW: f32 = 0.1;

/// The selected particle: what it is, where, how fast, and the forces on it, with
/// units; while paused its mass and velocity can be edited.
fn inspector(ui: &mut egui::Ui, lab: &mut Lab) {
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
        if ui.small_button("clear").on_hover_text("Clear the selection (or click empty space)").clicked() {
            lab.select(None);
        }
    });
    let rows = [
        ("mass", if movable { format!("{mass:.3} kg") } else { "immovable".into() }),
        ("position", vector(p, "m")),
        ("velocity", vector(v, "m/s")),
        ("speed", format!("{:.2} m/s", v.length())),
    ];
    let forces = lab.free_body(id);
    let swatch = srgb;
    egui::Grid::new("inspector").num_columns(2).striped(true).show(ui, |ui| {
        for (name, value) in rows {
            ui.label(name);
            ui.monospace(value);
            ui.end_row();
        }
        for (name, force) in &forces {
            ui.colored_label(swatch(paint::force_color(name)), *name);
            ui.monospace(vector(*force, "N"));
            ui.end_row();
        }
        if movable {
            ui.colored_label(swatch(paint::force_color("net force")), "net force");
            ui.monospace(vector(net, "N"));
            ui.end_row();
            ui.colored_label(swatch(paint::ACCELERATION_COLOR), "acceleration");
            ui.monospace(vector(net / mass, "m/s²"));
            ui.end_row();
        }
    });
    let scale = if lab.view.forces {
        format!("forces 1 m per {} N", lab.force_scale())
    } else {
        format!("acceleration (red) 1 m per {:.0} m/s²", 1.0 / ACCELERATION_ARROW)
    };
    ui.add(
        egui::Label::new(
            egui::RichText::new(format!(
                "Arrows: velocity (green) 1 m per {:.0} m/s; {scale}. Forces are computed \
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
        // A refused edit (a mass out of range) says why in the status line.
        for error in [mass_change, velocity_change].into_iter().flatten().filter_map(Result::err) {
            lab.status = error.to_string();
        }
    }
}

/// One curve of the energy plot.
type EnergySeries = (&'static str, Color32, fn(&lab::EnergySample) -> f32);

/// Seconds of simulated time the energy plot shows (and scales to): a transient at the
/// start leaves the plot once it is this old.
const PLOT_SECONDS: f64 = 10.0;

/// Kinetic, potential and total energy over the last [`PLOT_SECONDS`], and the budget's
/// remainder (total + dissipated - work, less its start: zero but for the integrator's
/// error). The legend is a row above the curves; the scale fits what is shown.
fn energy_plot(ui: &mut egui::Ui, lab: &Lab) {
    let series: [EnergySeries; 5] = [
        ("kinetic", KINETIC_COLOR, |s| s.kinetic),
        ("potential", GRAVITY_COLOR, |s| s.potential),
        ("total", TOTAL_COLOR, |s| s.kinetic + s.potential),
        ("removed", REMOVED_COLOR, |s| s.removed),
        // What the budget leaves over: total + dissipated - work, less its start.
        ("integrator error", Color32::from_rgb(110, 210, 120), |s| s.error),
    ];
    ui.horizontal_wrapped(|ui| {
        ui.label(egui::RichText::new("Energy").strong()).on_hover_text(format!(
            "Potential energy's gravitational part is measured from {}.",
            lab.gravity_from().1
        ));
        for (name, color, _) in &series {
            ui.label(egui::RichText::new(*name).color(*color).small());
        }
        if lab.compare.is_some() {
            ui.label(egui::RichText::new("copy: total, error").color(srgb(paint::COMPARE_COLOR)).small());
        }
    });
    let mut curves: Vec<(Color32, Vec<(f64, f32)>)> = Vec::new();
    let Some(newest) = lab.energy.back() else { return };
    let since = newest.t - PLOT_SECONDS;
    for (_, color, value) in &series {
        curves.push((*color, lab.energy.iter().filter(|s| s.t >= since).map(|s| (s.t, value(s))).collect()));
    }
    if let Some(compare) = &lab.compare {
        let shown = || compare.energy.iter().filter(|s| s.t >= since);
        let copy = srgb(paint::COMPARE_COLOR);
        curves.push((copy, shown().map(|s| (s.t, s.kinetic + s.potential)).collect()));
        curves.push((copy, shown().map(|s| (s.t, s.error)).collect()));
    }
    line_plot(ui, &curves, 90.0, joules);
}

/// Curves of `(t, value)` over a shared time axis, scaled to fit what they show, with
/// the top and bottom of the scale written at the right in `unit`'s format.
/// The runs of a series between its breaks (a value that is not finite: no round in
/// flight, no exact answer), each drawn as its own line, so a plot never draws a line
/// across a gap where the series has no value.
pub fn segments(points: &[(f64, f32)]) -> impl Iterator<Item = &[(f64, f32)]> {
    points.split(|(_, v)| !v.is_finite()).filter(|run| !run.is_empty())
}

fn line_plot(ui: &mut egui::Ui, curves: &[(Color32, Vec<(f64, f32)>)], height: f32, unit: fn(f32) -> String) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(ui.available_width(), height), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_gray(20));
    let points = || curves.iter().flat_map(|(_, points)| points.iter()).filter(|(_, v)| v.is_finite());
    let (t0, t1) = points().fold((f64::MAX, f64::MIN), |(lo, hi), &(t, _)| (lo.min(t), hi.max(t)));
    let (low, high) = points().fold((f32::MAX, f32::MIN), |(lo, hi), &(_, v)| (lo.min(v), hi.max(v)));
    if t0 > t1 {
        return;
    }
    let span_t = (t1 - t0).max(1e-6);
    let span = (high - low).max(1e-6);
    let to_screen = |t: f64, v: f32| {
        egui::pos2(
            rect.left() + ((t - t0) / span_t) as f32 * rect.width(),
            rect.bottom() - 4.0 - (v - low) / span * (rect.height() - 8.0),
        )
    };
    for (color, points) in curves {
        for run in segments(points) {
            let line: Vec<egui::Pos2> = run.iter().map(|&(t, v)| to_screen(t, v)).collect();
            painter.add(egui::Shape::line(line, Stroke::new(1.5, *color)));
        }
    }
    for (corner, offset, align, value) in [
        (rect.right_top(), egui::vec2(-6.0, 4.0), egui::Align2::RIGHT_TOP, high),
        (rect.right_bottom(), egui::vec2(-6.0, -4.0), egui::Align2::RIGHT_BOTTOM, low),
    ] {
        painter.text(corner + offset, align, unit(value), egui::FontId::monospace(10.0), Color32::GRAY);
    }
}

/// Distance from the exact answer over the last [`PLOT_SECONDS`] (mm), where the scene
/// has one: how far the integrator has drifted from the closed form; the compared
/// copy's too.
fn error_plot(ui: &mut egui::Ui, lab: &Lab) {
    let Some(newest) = lab.energy.back() else { return };
    let since = newest.t - PLOT_SECONDS;
    let millimetres = |samples: &std::collections::VecDeque<lab::EnergySample>| -> Vec<(f64, f32)> {
        samples.iter().filter(|s| s.t >= since).map(|s| (s.t, s.exact_error * 1000.0)).collect()
    };
    let ours = millimetres(&lab.energy);
    // Gaps (no round in flight) stay in the series, to break its line there.
    let last = |points: &[(f64, f32)]| points.iter().rev().find(|(_, v)| v.is_finite()).map(|p| p.1);
    let Some(now) = last(&ours) else { return };
    ui.horizontal_wrapped(|ui| {
        ui.label(egui::RichText::new("Distance from the exact answer").strong()).on_hover_text(
            "How far the simulated particle (the newest round, or the bob) is from its ghost: the \
             closed form of its motion. Try another integrator or physics rate, or Compare them.",
        );
        ui.monospace(format!("{now:.2} mm"));
    });
    let mut curves = vec![(Color32::from_rgb(110, 210, 120), ours)];
    if let Some(compare) = &lab.compare {
        let theirs = millimetres(&compare.energy);
        if let Some(then) = last(&theirs) {
            ui.colored_label(
                srgb(paint::COMPARE_COLOR),
                format!("copy ({}): {then:.2} mm", compare.change.describe()),
            );
        }
        curves.push((srgb(paint::COMPARE_COLOR), theirs));
    }
    line_plot(ui, &curves, 50.0, |mm| format!("{} mm", fixed(mm, 2)));
}

/// PhET's energy bar chart: kinetic, gravitational, elastic, dissipated, removed and the
/// budget (total + dissipated + removed − work put in, which stays level), for the whole
/// scene or one particle (the selected one, else the scene's focus, springForces' bob),
/// without dissipation, which the world tracks only in total.
fn energy_bars(ui: &mut egui::Ui, lab: &mut Lab) {
    let chart = lab.energy_bars();
    let color = |name: &str| match name {
        "kinetic" => KINETIC_COLOR,
        "gravity" => GRAVITY_COLOR,
        "elastic" => ELASTIC_COLOR,
        "dissipated" => DISSIPATED_COLOR,
        "removed" => REMOVED_COLOR,
        _ => TOTAL_COLOR,
    };
    ui.horizontal_wrapped(|ui| {
        ui.label(egui::RichText::new(format!("Energy bars: {}", chart.subject)).strong()).on_hover_text(
            format!(
                "Gravitational energy is measured from {}; elastic includes buoyancy's. 'removed' is what \
             particles carried out when they left the scene. The budget bar, total + dissipated + \
             removed − work put in, stays level when the budget balances.",
                chart.reference
            ),
        );
        let particle = lab.selected.is_some() || lab.scene.energy_focus().is_some();
        if particle {
            let name = if lab.selected.is_some() { "selected" } else { "focus" };
            ui.selectable_value(&mut lab.bars_for_selected, false, "scene");
            ui.selectable_value(&mut lab.bars_for_selected, true, name);
        }
    });
    ui.label(egui::RichText::new(format!("gravity from {}", chart.reference)).small());
    let (rect, _) = ui.allocate_exact_size(egui::vec2(ui.available_width(), 110.0), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_gray(20));
    // Room for a value above and a name below each bar.
    let (top, bottom) = (rect.top() + 14.0, rect.bottom() - 14.0);
    let heights = chart.heights(bottom - top);
    let low = heights.iter().copied().fold(0.0, f32::min);
    let zero = bottom + low;
    painter.line_segment(
        [egui::pos2(rect.left(), zero), egui::pos2(rect.right(), zero)],
        Stroke::new(1.0, Color32::GRAY),
    );
    let slot = rect.width() / chart.bars.len() as f32;
    for (k, ((name, value), height)) in chart.bars.iter().zip(&heights).enumerate() {
        let x = rect.left() + slot * (k as f32 + 0.5);
        let (y0, y1) = (zero.min(zero - height), zero.max(zero - height));
        // 0 J is no bar (not a one-pixel stub a reader takes for a small energy).
        if *height != 0.0 {
            let bar = Rect::from_x_y_ranges(x - slot * 0.3..=x + slot * 0.3, y0..=y1.max(y0 + 0.5));
            painter.rect_filled(bar, 1.0, color(name));
        }
        painter.text(
            egui::pos2(x, y0 - 1.0),
            egui::Align2::CENTER_BOTTOM,
            joules(*value),
            egui::FontId::monospace(9.0),
            Color32::GRAY,
        );
        painter.text(
            egui::pos2(x, rect.bottom() - 1.0),
            egui::Align2::CENTER_BOTTOM,
            *name,
            egui::FontId::proportional(10.0),
            color(name),
        );
    }
}

/// Colours of the energy plot's and bars' kinds of energy.
const KINETIC_COLOR: Color32 = Color32::from_rgb(240, 140, 40);
/// See [`KINETIC_COLOR`].
const GRAVITY_COLOR: Color32 = Color32::from_rgb(80, 160, 240);
/// See [`KINETIC_COLOR`].
const ELASTIC_COLOR: Color32 = Color32::from_rgb(200, 110, 230);
/// See [`KINETIC_COLOR`].
const DISSIPATED_COLOR: Color32 = Color32::from_rgb(220, 80, 70);
/// See [`KINETIC_COLOR`].
const TOTAL_COLOR: Color32 = Color32::from_rgb(220, 220, 220);
/// See [`KINETIC_COLOR`].
const REMOVED_COLOR: Color32 = Color32::from_rgb(150, 150, 110);

/// An energy for the plot's scale: one decimal, or scientific notation once it is so
/// large (a spring exploding) that the digits would run off the plot.
pub fn joules(e: f32) -> String {
    if e.abs() >= 1e5 {
        format!("{e:.2e} J")
    } else if e.abs() >= 0.95 || e == 0.0 {
        format!("{} J", fixed(e, 1))
    } else {
        // A light particle's energies are a fraction of a joule: in mJ, not "0.0 J".
        format!("{} mJ", fixed(e * 1000.0, 1))
    }
}

fn help(ui: &mut egui::Ui) {
    egui::Grid::new("shortcuts").num_columns(2).striped(true).show(ui, |ui| {
        for (key, meaning) in SHORTCUTS {
            ui.monospace(*key);
            ui.label(*meaning);
            ui.end_row();
        }
    });
}

/// How near the pointer must be to a path point to show its tooltip (points).
const HOVER_RADIUS: f32 = 10.0;

/// The 3D view's input: drag particles, orbit, pan and zoom. Only input that reached
/// this area (not the panels) moves anything.
fn view_3d(ui: &mut egui::Ui, lab: &mut Lab) -> Rect {
    let rect = ui.max_rect();
    let response = ui.interact(rect, ui.scope_id().with("3d view"), Sense::click_and_drag());
    let size = Vec2::new(rect.width(), rect.height());
    let local = |p: egui::Pos2| Vec2::new(p.x - rect.left(), p.y - rect.top());
    lab.set_view_aspect(size.x / size.y.max(1.0));

    lab.hovered = response.hover_pos().and_then(|p| lab.pick(local(p), size));
    // A point of a recorded path under the pointer: its time, range and height.
    if let (None, Some(pointer)) = (lab.hovered, response.hover_pos()) {
        let mut points = Vec::new();
        lab.scene.hover_points(&mut points);
        let nearest = points
            .into_iter()
            .filter_map(|(point, text)| {
                let screen = lab.camera.project(point, size)?;
                Some((screen.distance(local(pointer)), text))
            })
            .filter(|(distance, _)| *distance <= HOVER_RADIUS)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, text)) = nearest {
            response.clone().on_hover_text_at_pointer(text);
        }
    }
    if response.drag_started_by(PointerButton::Primary) {
        // Press on a particle to drag it; anywhere else orbits. The drag starts only
        // after the pointer moved a little: pick where the button went down.
        if let Some(press) = ui.input(|i| i.pointer.press_origin()) {
            lab.start_grab(local(press), size);
        }
    }
    if response.dragged_by(PointerButton::Primary) {
        if lab.grab.is_some() {
            if let Some(p) = response.interact_pointer_pos() {
                lab.move_grab(local(p), size);
            }
        } else if lab.side_view {
            // The side view stays a side view: a drag pans it.
            let d = response.drag_delta();
            lab.camera.pan(Vec2::new(d.x, d.y), rect.height());
            lab.camera_moved = true;
        } else {
            let d = response.drag_delta();
            lab.camera.orbit(Vec2::new(d.x, d.y));
            lab.camera_moved = true;
        }
    }
    if response.drag_stopped() {
        lab.end_grab();
    }
    let click = response.interact_pointer_pos().filter(|_| response.clicked_by(PointerButton::Primary));
    if let Some(p) = click {
        if lab.tape {
            // With the tape measure on, a click places one of its ends.
            lab.tape_click(local(p), size);
        } else {
            // A click selects the particle under it for the inspector, or clears it.
            let picked = lab.pick(local(p), size);
            lab.select(picked);
        }
    }
    if response.dragged_by(PointerButton::Secondary) || response.dragged_by(PointerButton::Middle) {
        let d = response.drag_delta();
        lab.camera.pan(Vec2::new(d.x, d.y), rect.height());
        lab.camera_moved = true;
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            lab.camera.zoom(scroll / 50.0);
            lab.camera_moved = true;
        }
    }
    if lab.view.labels {
        paint::labels(ui, lab, rect);
    }
    if lab.scene.world().particles.is_empty()
        && lab.entry.info.actions.iter().any(|a| a.action == SceneAction::Fire)
    {
        ui.painter().text(
            rect.center_top() + egui::vec2(0.0, 24.0),
            egui::Align2::CENTER_TOP,
            "Press F (or the Fire button) to launch a round",
            egui::FontId::proportional(16.0),
            Color32::from_gray(200),
        );
    }
    rect
}

//! The panel re-laid as views (issue 19): the controls table the keys run and the
//! Help window lists, the inspector where the eye goes, the energy plot in view, the
//! sections as saved, the view state that follows the picture, the projectile's view
//! fitting its path, numbers that read as numbers, the plots' labels off the data,
//! the big Fire button, tearing cloth with the mouse, and no redraws while still.
//! Each runs the real interface headless (egui without a GPU) and reads what it drew.

use egui::{Event, Key, Modifiers, PointerButton, Pos2, Rect, Shape};
use glam::Vec2;
use particle_lab::messages::fixed;
use particle_lab::scenes::{SCENES, SceneAction};
use particle_lab::ui::keys::{Binding, Command, SHORTCUTS};
use particle_lab::ui::lab::round_scale;
use particle_lab::ui::views::help::HelpWindow;
use particle_lab::ui::views::scene_params::FIRE_HEIGHT;
use particle_lab::ui::{Lab, LabUi, PanelLayout, Section};

/// One laid-out frame: every text drawn, with where.
struct Frame {
    texts: Vec<(String, Rect, f32)>,
}

impl Frame {
    fn find(&self, text: &str) -> Option<&(String, Rect, f32)> {
        self.texts.iter().find(|(t, _, _)| t == text)
    }
}

/// Runs the interface for one frame at `size` points with `events`, returning what
/// it drew.
fn frame(ctx: &egui::Context, shell: &mut LabUi, lab: &mut Lab, size: [f32; 2], events: Vec<Event>) -> Frame {
    // Half a second a frame, so that a section's opening animation ends within one.
    let time = ctx.input(|i| i.time) + 0.5;
    let input = egui::RawInput {
        screen_rect: Some(Rect::from_min_size(Pos2::ZERO, egui::vec2(size[0], size[1]))),
        events,
        time: Some(time),
        ..Default::default()
    };
    let output = ctx.run_ui(input, |ui| {
        shell.show(ui, lab);
    });
    let mut texts = Vec::new();
    for clipped in &output.shapes {
        collect_texts(&clipped.shape, &mut texts);
    }
    Frame { texts }
}

fn collect_texts(shape: &Shape, out: &mut Vec<(String, Rect, f32)>) {
    match shape {
        Shape::Text(text) => {
            let size = text.galley.job.sections.first().map_or(0.0, |s| s.format.font_id.size);
            out.push((text.galley.text().to_string(), text.visual_bounding_rect(), size));
        }
        Shape::Vec(shapes) => shapes.iter().for_each(|s| collect_texts(s, out)),
        _ => {}
    }
}

/// A few frames so egui's layout settles; returns the last.
fn settle(ctx: &egui::Context, shell: &mut LabUi, lab: &mut Lab, size: [f32; 2]) -> Frame {
    for _ in 0..3 {
        frame(ctx, shell, lab, size, Vec::new());
    }
    frame(ctx, shell, lab, size, Vec::new())
}

fn key(key: Key) -> Vec<Event> {
    vec![Event::Key { key, physical_key: None, pressed: true, repeat: false, modifiers: Modifiers::NONE }]
}

fn click_at(ctx: &egui::Context, shell: &mut LabUi, lab: &mut Lab, size: [f32; 2], at: Pos2) {
    let button = |pressed| Event::PointerButton {
        pos: at,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    frame(ctx, shell, lab, size, vec![Event::PointerMoved(at)]);
    frame(ctx, shell, lab, size, vec![button(true)]);
    frame(ctx, shell, lab, size, vec![button(false)]);
}

const WIDE: [f32; 2] = [1280.0, 720.0];
const SMALL: [f32; 2] = [800.0, 600.0];

#[test]
fn the_help_window_lists_the_table_the_keys_run_with_every_command_once() {
    let rows = HelpWindow::rows();
    assert_eq!(rows.len(), SHORTCUTS.len());
    for (row, shortcut) in rows.iter().zip(SHORTCUTS) {
        assert_eq!(*row, (shortcut.keys, shortcut.meaning));
    }
    let listed: Vec<&str> = rows.iter().map(|(keys, _)| *keys).collect();
    for keys in ["F5", "F9", "M", "F1", "Space", "Home", "F12", "Ctrl+Q"] {
        assert!(listed.contains(&keys), "{keys} missing from the Help window: {listed:?}");
    }
    // Every command is reachable, and no key does two things.
    let commands = [
        Command::Pause,
        Command::Step,
        Command::Reset,
        Command::Fire,
        Command::QuickSave,
        Command::QuickLoad,
        Command::Panel,
        Command::SideView,
        Command::Tape,
        Command::Frame,
        Command::Screenshot,
        Command::Help,
        Command::Quit,
    ];
    for command in commands {
        assert!(SHORTCUTS.iter().any(|s| s.command == Some(command)), "{command:?} has no key");
    }
    let mut bound = Vec::new();
    for shortcut in SHORTCUTS {
        if let Binding::Keys(modifiers, keys) = shortcut.binding {
            for key in keys {
                assert!(!bound.contains(&(modifiers, *key)), "{key:?} bound twice");
                bound.push((modifiers, *key));
            }
        }
    }
}

#[test]
fn each_key_does_what_the_help_window_says() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("projectile", &[]).unwrap();
    let mut shell = LabUi::default();
    settle(&ctx, &mut shell, &mut lab, WIDE);

    frame(&ctx, &mut shell, &mut lab, WIDE, key(Key::Space));
    assert!(lab.paused, "Space pauses");
    let steps = lab.scene.world().steps();
    frame(&ctx, &mut shell, &mut lab, WIDE, key(Key::Period));
    assert_eq!(lab.scene.world().steps(), steps + 1, ". takes one step");
    frame(&ctx, &mut shell, &mut lab, WIDE, key(Key::M));
    assert!(lab.tape, "M turns the tape measure on");
    frame(&ctx, &mut shell, &mut lab, WIDE, key(Key::F1));
    assert!(shell.layout.help, "F1 opens the Controls window");
    let help = frame(&ctx, &mut shell, &mut lab, WIDE, Vec::new());
    assert!(help.find("tape measure on / off").is_some(), "the window lists M");
    frame(&ctx, &mut shell, &mut lab, WIDE, key(Key::F5));
    assert!(lab.status.starts_with("Quick save at t = "), "{}", lab.status);
    let rounds = lab.scene.world().particles.len();
    frame(&ctx, &mut shell, &mut lab, WIDE, key(Key::F));
    assert_eq!(lab.scene.world().particles.len(), rounds + 1, "F fires a round");
    frame(&ctx, &mut shell, &mut lab, WIDE, key(Key::F9));
    assert!(lab.status.starts_with("Back to the quick save"), "{}", lab.status);
    assert_eq!(lab.scene.world().particles.len(), rounds, "F9 goes back to before the round");
    frame(&ctx, &mut shell, &mut lab, WIDE, key(Key::P));
    assert!(!shell.layout.open, "P hides the panel");
}

#[test]
fn picking_a_particle_opens_the_inspector_at_the_top_of_the_panel() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("springForces", &[]).unwrap();
    // Collapsed as a user may have left it: picking opens it all the same.
    let mut shell = LabUi::new(PanelLayout { inspector: false, ..PanelLayout::default() });
    settle(&ctx, &mut shell, &mut lab, WIDE);
    assert!(shell.drawn(Section::Inspector).is_none(), "no inspector without a selection");
    let id = lab.scene.world().particles.ids()[1];
    lab.select(Some(id));
    let drawn = settle(&ctx, &mut shell, &mut lab, WIDE);
    let (first, rect) = shell.drawn[0];
    assert_eq!(first, Section::Inspector, "the inspector comes first");
    assert!(rect.top() < 120.0, "at the top of the panel: {rect:?}");
    assert!(shell.layout.inspector, "and opened");
    assert!(drawn.find(&format!("Particle {}", id.0)).is_some(), "its rows are drawn");
    let run = shell.drawn(Section::Run).unwrap();
    assert!(run.top() >= rect.bottom() - 1.0, "the run controls below it");
}

#[test]
fn the_energy_plot_is_in_view_without_scrolling_at_1280x720_on_every_scene() {
    for entry in SCENES {
        let ctx = egui::Context::default();
        let mut lab = Lab::from_entry(entry, &[], Default::default()).unwrap();
        let mut shell = LabUi::default();
        settle(&ctx, &mut shell, &mut lab, WIDE);
        let plot = shell.energy.plot.unwrap_or_else(|| panic!("{}: no energy plot", entry.info().name));
        assert!(
            plot.data.bottom() <= WIDE[1] && plot.data.height() > 50.0,
            "{}: the plot ends at y = {} in a 720-point window",
            entry.info().name,
            plot.data.bottom()
        );
    }
}

#[test]
fn sections_open_and_close_as_the_saved_layout_says() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("projectile", &[]).unwrap();
    let mut shell = LabUi::new(PanelLayout { energy: false, parameters: false, ..PanelLayout::default() });
    let drawn = settle(&ctx, &mut shell, &mut lab, WIDE);
    assert!(shell.energy.plot.is_none(), "a closed Energy section draws no plot");
    assert!(drawn.find("speed (m/s)").is_none(), "a closed Parameters section draws no slider");
    let header = shell.drawn(Section::Energy).unwrap();
    assert!(header.height() < 30.0, "only its header: {header:?}");
    // A click on its header opens it, and the layout (saved with the settings) says so.
    click_at(&ctx, &mut shell, &mut lab, WIDE, header.center());
    settle(&ctx, &mut shell, &mut lab, WIDE);
    assert!(shell.layout.energy, "opened by a click");
    assert!(shell.energy.plot.is_some());
}

#[test]
fn the_view_state_follows_the_picture_across_scenes_and_home_always_frames() {
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.set_side_view(true);
    lab.follow = true;
    lab.switch_scene(particle_lab::scenes::find("bridge").unwrap());
    assert!(lab.side_view && lab.camera.orthographic, "the side view's tick matches what is drawn");
    assert_eq!((lab.camera.yaw, lab.camera.pitch), (0.0, 0.0));
    assert!(!lab.follow, "follow is off on a new scene");
    lab.set_side_view(false);

    // Home with follow on: follow goes off and the camera is where framing puts it.
    let mut framed = Lab::new("projectile", &[]).unwrap();
    framed.frame_scene();
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.act(SceneAction::Fire);
    lab.follow = true;
    lab.run_steps(30);
    lab.camera.orbit(Vec2::new(120.0, 40.0));
    lab.camera_moved = true;
    lab.home();
    assert!(!lab.follow);
    assert!(!lab.camera_moved);
    assert_eq!(
        (lab.camera.yaw, lab.camera.pitch, lab.camera.distance),
        (framed.camera.yaw, framed.camera.pitch, framed.camera.distance)
    );
    assert!((lab.camera.target - framed.camera.target).length() < 1e-5);
}

/// True when every point the scene asks to keep in view projects inside the view.
fn path_in_view(lab: &Lab) -> bool {
    let mut points = Vec::new();
    lab.scene.framing_points(&mut points);
    assert!(!points.is_empty(), "the projectile has a predicted path");
    let view = Vec2::new(1000.0 * lab.view_aspect, 1000.0);
    let clip = lab.camera.view_projection(view.x / view.y);
    points.iter().all(|&p| {
        // Inside the view, and between the near and far planes (drawn, not clipped).
        let c = clip * p.extend(1.0);
        (0.0..=1.0).contains(&(c.z / c.w))
            && lab
                .camera
                .project(p, view)
                .is_some_and(|s| s.x >= 0.0 && s.x <= view.x && s.y >= 0.0 && s.y <= view.y)
    })
}

#[test]
fn the_projectile_view_fits_the_predicted_path_and_refits_when_the_launch_changes() {
    let mut lab = Lab::new("projectile", &[]).unwrap();
    assert!(path_in_view(&lab), "the default launch's landing is in view");
    let before = lab.camera.distance;
    lab.set_param("speed", 120.0);
    lab.set_param("g", 5.0);
    assert!(path_in_view(&lab), "a 120 m/s launch under g = 5 lands in view");
    assert!(lab.camera.distance > 5.0 * before, "by backing off: {} from {before}", lab.camera.distance);
    lab.set_view_aspect(0.8);
    assert!(path_in_view(&lab), "in a narrow view too");
    lab.set_side_view(true);
    assert!(path_in_view(&lab), "and in the side view");
    // Once the user moves the camera, a change of launch leaves it alone.
    lab.camera_moved = true;
    let camera = lab.camera;
    lab.set_param("speed", 30.0);
    assert_eq!(lab.camera, camera);
}

#[test]
fn numbers_read_as_numbers() {
    assert_eq!(round_scale(0.04).to_string(), "0.05", "1 m per 0.05 N, not 0.049999997");
    assert_eq!(round_scale(0.011).to_string(), "0.02");
    assert_eq!(round_scale(3.0).to_string(), "5");
    assert_eq!(round_scale(120.0).to_string(), "200");
    for x in [0.0013, 0.07, 0.3, 7.0, 33.0, 4e4] {
        let s = round_scale(x);
        assert!(s >= x * 0.9999 && s <= 5.0 * x, "{s} for {x}");
        assert!(s.to_string().len() <= 6, "{s}");
    }
    assert_eq!(fixed(-0.00001, 2), "0.00", "no -0.0");

    // Counts are whole numbers on their sliders: "balls 5", not "5.0".
    let ctx = egui::Context::default();
    let mut lab = Lab::new("cradle", &[]).unwrap();
    let mut shell = LabUi::default();
    let drawn = settle(&ctx, &mut shell, &mut lab, WIDE);
    for name in ["balls", "lifted"] {
        let (_, slider) = *shell.params.sliders.iter().find(|(n, _)| *n == name).unwrap();
        let value: Vec<&str> = drawn
            .texts
            .iter()
            .filter(|(t, r, _)| {
                slider.contains(r.center()) && t.chars().all(|c| c.is_ascii_digit() || c == '.')
            })
            .map(|(t, _, _)| t.as_str())
            .collect();
        assert_eq!(value.len(), 1, "{name}: {value:?}");
        assert!(!value[0].contains('.'), "{name} reads {}", value[0]);
    }
}

#[test]
fn legends_are_legible_and_plot_scales_sit_beside_the_data_with_compare_as_two_entries() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("springForces", &[]).unwrap();
    let mut shell = LabUi::default();
    lab.run_steps(120);
    let drawn = settle(&ctx, &mut shell, &mut lab, WIDE);
    let plot = shell.energy.plot.unwrap();
    assert!(plot.scale.left() >= plot.data.right(), "{plot:?}");
    let scale_texts: Vec<_> = drawn
        .texts
        .iter()
        .filter(|(t, r, _)| t.ends_with('J') && plot.scale.union(plot.data).contains(r.center()))
        .collect();
    assert_eq!(scale_texts.len(), 2, "the top and bottom of the scale: {scale_texts:?}");
    for (text, rect, _) in &scale_texts {
        assert!(!plot.data.intersects(*rect), "'{text}' lies on the curves: {rect:?} in {:?}", plot.data);
    }
    for entry in ["kinetic", "potential", "total", "integrator error"] {
        let (_, _, size) = drawn.find(entry).unwrap_or_else(|| panic!("no legend entry {entry}"));
        assert!(*size >= 12.0, "{entry} is {size} points high");
    }

    lab.start_compare(particle_lab::ui::compare::Change::Integrator(
        particle_lab::physics::Integrator::Verlet,
    ));
    lab.run_steps(60);
    let drawn = settle(&ctx, &mut shell, &mut lab, WIDE);
    assert!(
        shell.energy.legend.ends_with(&["copy total".to_string(), "copy error".to_string()]),
        "{:?}",
        shell.energy.legend
    );
    assert!(drawn.find("copy total").is_some() && drawn.find("copy error").is_some());
}

#[test]
fn fire_is_a_big_button_by_the_launch_sliders_and_it_fires() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("projectile", &[]).unwrap();
    let mut shell = LabUi::default();
    let drawn = settle(&ctx, &mut shell, &mut lab, SMALL);
    let (_, label, size) = drawn.find("Fire  (F)").expect("a Fire button");
    assert!(*size >= 16.0, "its label is {size} points");
    let (_, speed) = *shell.params.sliders.iter().find(|(n, _)| *n == "speed").unwrap();
    assert!(
        speed.top() > label.bottom() && speed.top() - label.bottom() < FIRE_HEIGHT * 3.0,
        "by the sliders"
    );
    let rounds = lab.scene.world().particles.len();
    click_at(&ctx, &mut shell, &mut lab, SMALL, label.center());
    assert_eq!(lab.scene.world().particles.len(), rounds + 1, "the button fired one round");
}

#[test]
fn a_hard_drag_tears_the_cloth_and_pulls_the_mass_it_is_joined_to() {
    let mut lab = Lab::new("cloth", &[]).unwrap();
    lab.run_steps(240);
    let links_before = lab.scene.world().links().len();
    let viewport = Vec2::new(1000.0 * lab.view_aspect, 1000.0);
    let world = lab.scene.world();
    let particles = &world.particles;
    // The free corner farthest from the pins (the lowest particle).
    let (corner, _) = (0..particles.len())
        .map(|i| (i, particles.positions()[i].y))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    let movable: f32 = (0..particles.len())
        .filter(|&i| particles.inverse_masses()[i] > 0.0)
        .map(|i| particles.mass(i))
        .sum();
    let at = lab.camera.project(particles.positions()[corner], viewport).unwrap();
    assert!(lab.start_grab(at, viewport), "pressed on the corner");
    let grab = lab.grab.unwrap();
    assert!(
        (grab.pulled_mass - movable).abs() < 1e-4 * movable,
        "pulls {} kg of {movable} kg",
        grab.pulled_mass
    );
    // Pull it 3 m down and away in the drag plane, and hold.
    lab.move_grab(at + Vec2::new(0.0, 400.0), viewport);
    lab.run_steps(240);
    let links_after = lab.scene.world().links().len();
    assert!(links_after < links_before, "no link tore: {links_after} of {links_before}");
    lab.end_grab();

    // A lone particle is pulled as before: no faster than the mouse's limit.
    let lone = particle_lab::ui::lab::mouse_pull_joined(glam::Vec3::X * 10.0, glam::Vec3::ZERO, 0.01, 1.0);
    assert_eq!(lone, particle_lab::ui::lab::mouse_pull(glam::Vec3::X * 10.0, glam::Vec3::ZERO, 0.01));
}

#[test]
fn a_paused_lab_asks_for_no_frames_and_a_running_one_does() {
    let mut lab = Lab::new("pendulum", &[]).unwrap();
    assert!(lab.needs_animation());
    lab.paused = true;
    assert!(!lab.needs_animation());
    // A paused, untouched interface asks egui for no repaint either.
    let ctx = egui::Context::default();
    let mut shell = LabUi::default();
    settle(&ctx, &mut shell, &mut lab, WIDE);
    let input = egui::RawInput {
        screen_rect: Some(Rect::from_min_size(Pos2::ZERO, egui::vec2(WIDE[0], WIDE[1]))),
        ..Default::default()
    };
    let output = ctx.run_ui(input, |ui| {
        shell.show(ui, &mut lab);
    });
    let delay = output.viewport_output[&egui::ViewportId::ROOT].repaint_delay;
    assert!(delay > std::time::Duration::from_secs(1), "egui asks for a repaint in {delay:?}");
}

#[test]
fn at_800x600_the_panel_leaves_the_view_most_of_the_window() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("bridge", &[]).unwrap();
    let mut shell = LabUi::default();
    settle(&ctx, &mut shell, &mut lab, SMALL);
    let run = shell.drawn(Section::Run).unwrap();
    assert!(run.right() <= particle_lab::ui::PANEL_WIDTH + 1.0);
    assert!(shell.run.solver_menu.is_some_and(|r| r.bottom() < SMALL[1]), "the run controls are in view");
}

/// File → Copy link (issue 20): in the window the status line gives the query string
/// of what is on screen, and that query opens the same experiment again.
#[test]
fn copy_link_in_the_file_menu_gives_the_query_that_opens_this_experiment() {
    use particle_lab::settings::{self, Launch, Store};
    use particle_lab::ui::lab::Link;
    let ctx = egui::Context::default();
    let mut shell = LabUi::default();
    let mut lab = Lab::new("bridge", &["g=4.5".into(), "load_x=2".into()]).unwrap();
    let size = [1280.0, 800.0];
    let menu = settle(&ctx, &mut shell, &mut lab, size).find("File").expect("the File menu").1;
    click_at(&ctx, &mut shell, &mut lab, size, menu.center());
    let item = frame(&ctx, &mut shell, &mut lab, size, Vec::new()).find("Copy link").expect("Copy link").1;
    click_at(&ctx, &mut shell, &mut lab, size, item.center());
    let query = lab.status.split_once(": ").map(|(_, q)| q.to_string()).expect(&lab.status);
    assert_eq!(query, Link::of(&lab, false).unwrap(), "{}", lab.status);
    assert!(
        query.starts_with("?scene=bridge&")
            && query.contains("set=g=4.5&")
            && query.contains("set=load_x=2&")
    );
    // The query, read back as a page would (its pairs split and decoded), opens it.
    let pairs: Vec<(String, String)> = query[1..]
        .split('&')
        .map(|p| {
            let (k, v) = p.split_once('=').unwrap();
            (k.to_string(), v.to_string())
        })
        .collect();
    let link = Link::parse(&pairs).unwrap();
    let dir = std::env::temp_dir().join(format!("particle-lab-panel-link-{}", std::process::id()));
    let again = settings::open(&Launch::from_args(&link.args).unwrap(), Store::in_dir(&dir)).unwrap().lab;
    let values = |lab: &Lab| {
        lab.scene.params().iter().map(|(p, v)| (p.name.to_string(), v.to_bits())).collect::<Vec<_>>()
    };
    assert_eq!(values(&again), values(&lab));
    assert_eq!(again.solver(), lab.solver());
    let _ = std::fs::remove_dir_all(dir);
}

/// View → Text size (issue 37, for a projector): Ctrl+= and Ctrl+- step the text size
/// by 10% within 100–250%, Ctrl+0 goes back to 100%, egui's zoom follows it (egui's own
/// Ctrl+= is off, so one press is one step), and the text drawn grows by as much.
#[test]
fn ctrl_plus_and_minus_step_the_text_size_and_the_text_grows_with_it() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("pendulum", &[]).unwrap();
    let mut shell = LabUi::default();
    let ctrl = |key| {
        vec![Event::Key {
            key,
            physical_key: None,
            pressed: true,
            repeat: false,
            modifiers: Modifiers::COMMAND,
        }]
    };
    let before = settle(&ctx, &mut shell, &mut lab, WIDE);
    let (_, _, size_before) = *before.find("Run").unwrap();
    assert_eq!(shell.layout.text_size, 100);
    frame(&ctx, &mut shell, &mut lab, WIDE, ctrl(Key::Equals));
    frame(&ctx, &mut shell, &mut lab, WIDE, ctrl(Key::Plus));
    assert_eq!(shell.layout.text_size, 120, "two steps of 10%");
    let after = settle(&ctx, &mut shell, &mut lab, WIDE);
    assert!((ctx.zoom_factor() - 1.2).abs() < 1e-6, "zoom {}", ctx.zoom_factor());
    // Text is laid out in points: the same size in points, 1.2 times the pixels.
    let (_, _, size_after) = *after.find("Run").unwrap();
    assert_eq!(size_after, size_before);
    assert!((ctx.pixels_per_point() - 1.2).abs() < 1e-6, "{}", ctx.pixels_per_point());
    frame(&ctx, &mut shell, &mut lab, WIDE, ctrl(Key::Minus));
    assert_eq!(shell.layout.text_size, 110);
    frame(&ctx, &mut shell, &mut lab, WIDE, ctrl(Key::Num0));
    assert_eq!(shell.layout.text_size, 100);
    frame(&ctx, &mut shell, &mut lab, WIDE, ctrl(Key::Minus));
    assert_eq!(shell.layout.text_size, 100, "not below 100%");
    for _ in 0..30 {
        frame(&ctx, &mut shell, &mut lab, WIDE, ctrl(Key::Equals));
    }
    assert_eq!(shell.layout.text_size, 250, "not above 250%");
    settle(&ctx, &mut shell, &mut lab, WIDE);
    assert!((ctx.zoom_factor() - 2.5).abs() < 1e-6);
    // A hand-edited settings file's 900% is held to the range.
    let layout = PanelLayout { text_size: 900, ..PanelLayout::default() };
    assert_eq!(layout.zoom(), 2.5);
}

/// A new scene opens at the top of its panel (issue 37): the panel scrolled down to the
/// last scene's read-outs comes back to the heading; the builder's edits, which keep
/// the scene, keep the place.
#[test]
fn a_new_scene_opens_at_the_top_of_its_panel() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("pendulum", &[]).unwrap();
    let mut shell = LabUi::default();
    let size = [1024.0, 600.0];
    // The scene's heading: its name in the heading's type (the menu bar names it too,
    // smaller).
    let heading_size = 16.0;
    let heading = |frame: &Frame, name: &str| {
        frame.texts.iter().find(|(t, _, size)| t == name && *size >= heading_size).map(|(_, r, _)| r.min.y)
    };
    let top = heading(&settle(&ctx, &mut shell, &mut lab, size), "pendulum").expect("the heading");
    // Scroll the panel well down.
    let over_panel = Pos2::new(100.0, 300.0);
    for _ in 0..10 {
        let wheel = Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(0.0, -200.0),
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Unknown,
            modifiers: Modifiers::NONE,
        };
        frame(&ctx, &mut shell, &mut lab, size, vec![Event::PointerMoved(over_panel), wheel]);
    }
    let scrolled = settle(&ctx, &mut shell, &mut lab, size);
    assert!(heading(&scrolled, "pendulum").is_none_or(|y| y < top - 100.0), "the wheel scrolled the panel");
    lab.switch_scene(particle_lab::scenes::find("bridge").unwrap());
    let opened = settle(&ctx, &mut shell, &mut lab, size);
    let y = heading(&opened, "bridge").expect("the new scene's heading is drawn");
    assert!((y - top).abs() < 1.0, "heading at {y}, the panel's top at {top}");
}

/// Issue 37: the File menu's items keep their places whether or not a scene file is
/// open (its "Watching" line went between them and moved every item below it).
#[test]
fn the_file_menus_items_keep_their_places_when_a_scene_file_is_open() {
    let size = [1280.0, 800.0];
    let items = ["Save snapshot as…", "Quick save (F5)", "Copy link"];
    let places = |lab: &mut Lab| {
        let ctx = egui::Context::default();
        let mut shell = LabUi::default();
        let menu = settle(&ctx, &mut shell, lab, size).find("File").expect("the File menu").1;
        click_at(&ctx, &mut shell, lab, size, menu.center());
        let drawn = frame(&ctx, &mut shell, lab, size, Vec::new());
        let watching = drawn.texts.iter().any(|(t, _, _)| t.starts_with("Watching "));
        let rects: Vec<Rect> = items.iter().map(|item| drawn.find(item).expect(item).1).collect();
        (rects, watching)
    };
    let (built_in, watching) = places(&mut Lab::new("bridge", &[]).unwrap());
    assert!(!watching);
    let dir = std::env::temp_dir().join(format!("particle-lab-panel-menu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("row.toml");
    std::fs::write(&path, "[scene]\nname = \"row\"\n\n[[particle]]\nposition = [0, 1, 0]\n").unwrap();
    let mut lab = Lab::new("bridge", &[]).unwrap();
    assert!(lab.open_scene_file(&path), "{}", lab.status);
    let (from_file, watching) = places(&mut lab);
    assert!(watching, "the open file is watched");
    assert_eq!(from_file, built_in, "every item in its place");
}

//! The builder, through its real UI (issue 38, "Your own experiment"): egui_kittest
//! drives the whole interface (`LabUi`, the window's panel, menus and view, without a
//! GPU) with clicks, drags and keys, finding buttons by their AccessKit labels, and the
//! view by where the camera shows the scene. Built this way: a spring dumbbell, a
//! five-ball cradle and a pendulum taken from a built-in scene; each saved as a scene
//! file, reopened, and run to the same state hash as the lab ran it.

use egui::{Event, Key, Modifiers, PointerButton, Pos2, Rect};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::{Vec2, Vec3};
use particle_lab::scenes::file;
use particle_lab::ui::lab::Lab;
use particle_lab::ui::shell::LabUi;

/// The interface and the lab it drives, and where the last frame drew the view.
struct Rig {
    ui: LabUi,
    lab: Lab,
    view: Rect,
}

fn harness(scene: &str) -> Harness<'static, Rig> {
    let rig =
        Rig { ui: LabUi::default(), lab: Lab::new(scene, &[]).expect("the scene"), view: Rect::NOTHING };
    let mut harness = Harness::builder()
        .with_size([1280.0, 800.0])
        .with_accessibility_check(false)
        .build_ui_state(|ui, rig: &mut Rig| rig.view = rig.ui.show(ui, &mut rig.lab), rig);
    harness.run_steps(2);
    harness
}

/// Where the view shows the point `p` (m).
fn screen(h: &Harness<'_, Rig>, p: Vec3) -> Pos2 {
    let view = h.state().view;
    let size = Vec2::new(view.width(), view.height());
    let s = h.state().lab.camera.project(p, size).expect("in front of the camera");
    view.min + egui::vec2(s.x, s.y)
}

fn press(h: &Harness<'_, Rig>, at: Pos2, pressed: bool) {
    h.event(Event::PointerButton {
        pos: at,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    });
}

/// A click at the view's point `p`.
fn click_at(h: &mut Harness<'_, Rig>, p: Vec3) {
    let at = screen(h, p);
    h.hover_at(at);
    h.run_steps(1);
    press(h, at, true);
    press(h, at, false);
    h.run_steps(2);
}

/// A drag from the view's point `from` to `to`, in steps as a hand moves.
fn drag(h: &mut Harness<'_, Rig>, from: Vec3, to: Vec3) {
    let (a, b) = (screen(h, from), screen(h, to));
    h.hover_at(a);
    h.run_steps(1);
    press(h, a, true);
    h.run_steps(1);
    for k in 1..=6 {
        h.hover_at(a + (b - a) * (k as f32 / 6.0));
        h.run_steps(1);
    }
    press(h, b, false);
    h.run_steps(2);
}

fn click(h: &mut Harness<'_, Rig>, label: &str) {
    h.get_by_label(label).click();
    h.run_steps(2);
}

fn key(h: &mut Harness<'_, Rig>, modifiers: Modifiers, key: Key) {
    h.key_press_modifiers(modifiers, key);
    h.run_steps(2);
}

fn counts(h: &Harness<'_, Rig>) -> (usize, usize) {
    let world = h.state().lab.scene.world();
    (world.particles.len(), world.links().len())
}

/// The state hash after `steps` steps of a scene file's text, opened afresh in a lab
/// of its own (as File → Open would).
fn hash_of_text(text: &str, steps: u32) -> u64 {
    let entry = file::load_text(text, "saved", None).expect("the saved file opens");
    // As `simulate --scene-file` runs it: with the solver the file names as its own.
    let solver = file::own_solver(&entry).over(particle_lab::physics::SolverSettings::default());
    let mut lab = Lab::from_entry(&entry, &[], solver).expect("a lab");
    lab.run_steps_recorded(u64::from(steps));
    assert_eq!(lab.scene.world().steps(), u64::from(steps));
    lab.scene.world().state_hash()
}

/// Plays what was built, runs `steps`, and checks the file Save writes runs there too.
fn play_and_compare(h: &mut Harness<'_, Rig>, steps: u32) {
    let (_, text) = h.state().lab.scene_file_text().expect("a built scene saves");
    click(h, "Play");
    let lab = &mut h.state_mut().lab;
    assert!(!lab.editing() && !lab.paused, "Play runs it");
    assert_eq!(lab.scene.world().steps(), 0, "Play starts from the state built");
    assert_eq!(hash_of_text(&text, 0), lab.scene.world().state_hash(), "at the start");
    lab.run_steps_recorded(u64::from(steps));
    assert_eq!(lab.scene.world().steps(), u64::from(steps));
    let ran = lab.scene.world().state_hash();
    assert_eq!(hash_of_text(&text, steps), ran, "the saved file runs elsewhere than the lab ran it:\n{text}");
    // Saved again, the same bytes.
    let entry = file::load_text(&text, "saved", None).unwrap();
    let again =
        file::written(&entry, &particle_lab::scenes::ParamValues::defaults(&entry.info().params)).unwrap();
    let reread = file::load_text(&again, "saved", None).unwrap();
    let twice =
        file::written(&reread, &particle_lab::scenes::ParamValues::defaults(&reread.info().params)).unwrap();
    assert_eq!(again, twice);
}

#[test]
fn a_spring_dumbbell_built_by_hand_saves_and_runs_the_same() {
    let mut h = harness("projectile");
    click(&mut h, "Scene");
    click(&mut h, "New experiment…");
    assert!(h.state().lab.editing());
    assert_eq!(counts(&h), (0, 0));
    // Two balls, a metre apart, in the side view's plane.
    let (a, b) = (Vec3::new(-0.5, 2.0, 0.0), Vec3::new(0.5, 2.0, 0.0));
    click_at(&mut h, a);
    click_at(&mut h, b);
    assert_eq!(counts(&h), (2, 0));
    // A spring between them, drawn from one to the other.
    click(&mut h, "Link");
    h.get_all_by_label("spring").next().expect("the link kind").click();
    h.run_steps(2);
    drag(&mut h, a, b);
    assert_eq!(counts(&h), (2, 1));
    let links = h.state().lab.scene.world().links();
    assert_eq!(links[0].spec.kind, particle_lab::physics::LinkKind::Spring);
    assert!((links[0].spec.rest - 1.0).abs() < 0.02, "rest length {}", links[0].spec.rest);
    // The second ball gets a sideways start: typed into its velocity's x.
    let editor = h.state().lab.editor.as_ref().unwrap();
    assert_eq!(editor.selected, Some(0), "the drag selected the ball it started on");
    play_and_compare(&mut h, 600);
    // Both balls fell and landed on the ground, the spring between them.
    let p = h.state().lab.scene.world().particles.positions().to_vec();
    assert!(p.iter().all(|x| x.y < 0.5), "{p:?}");
}

#[test]
fn a_five_ball_cradle_built_from_a_row_hangs_and_runs_the_same() {
    let mut h = harness("pendulum");
    click(&mut h, "Scene");
    click(&mut h, "New experiment…");
    // A row of five touching balls, unlinked (the first "none"), none pinned (the second).
    for k in 0..2 {
        h.get_all_by_label("none").nth(k).expect("links none, then pinned none").click();
        h.run_steps(2);
    }
    click(&mut h, "Add row");
    assert_eq!(counts(&h), (5, 0));
    // Each hung from a fixed point a metre above it by a cable drawn upwards.
    click(&mut h, "Link");
    h.get_all_by_label("cable").next().expect("the link kind").click();
    h.run_steps(2);
    let balls: Vec<Vec3> = h.state().lab.scene.world().particles.positions().to_vec();
    for ball in &balls {
        drag(&mut h, *ball, *ball + Vec3::Y);
    }
    assert_eq!(counts(&h), (5, 5));
    let kinds: Vec<&str> = h.state().lab.scene.world().links().iter().map(|l| l.spec.kind.name()).collect();
    assert!(kinds.iter().all(|k| *k == "support_cable"), "{kinds:?}");
    play_and_compare(&mut h, 480);
    // Hung still: each ball stays under its anchor.
    let after = h.state().lab.scene.world().particles.positions().to_vec();
    for (a, b) in balls.iter().zip(&after) {
        assert!(a.distance(*b) < 0.05, "{a} moved to {b}");
    }
}

#[test]
fn undo_redo_delete_and_duplicate_by_key_and_button() {
    let mut h = harness("projectile");
    click(&mut h, "Scene");
    click(&mut h, "New experiment…");
    for x in [-1.0, 0.0, 1.0] {
        click_at(&mut h, Vec3::new(x, 2.0, 0.0));
    }
    assert_eq!(counts(&h).0, 3);
    key(&mut h, Modifiers::COMMAND, Key::Z);
    assert_eq!(counts(&h).0, 2);
    click(&mut h, "Undo");
    assert_eq!(counts(&h).0, 1);
    key(&mut h, Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z);
    assert_eq!(counts(&h).0, 2);
    key(&mut h, Modifiers::COMMAND, Key::Y);
    assert_eq!(counts(&h).0, 3);
    click(&mut h, "Redo"); // nothing left to redo
    assert_eq!(counts(&h).0, 3);
    // Select the middle one (Select tool), duplicate it, delete it by key.
    click(&mut h, "Select");
    click_at(&mut h, Vec3::new(0.0, 2.0, 0.0));
    assert_eq!(h.state().lab.editor.as_ref().unwrap().selected, Some(1));
    click(&mut h, "Duplicate");
    assert_eq!(counts(&h).0, 4);
    key(&mut h, Modifiers::NONE, Key::Delete);
    assert_eq!(counts(&h).0, 3);
    // A drag moves a particle; undo puts it back.
    drag(&mut h, Vec3::new(-1.0, 2.0, 0.0), Vec3::new(-1.0, 3.0, 0.0));
    let moved = h.state().lab.scene.world().particles.positions()[0];
    assert!((moved.y - 3.0).abs() < 0.05, "{moved}");
    key(&mut h, Modifiers::COMMAND, Key::Z);
    let back = h.state().lab.scene.world().particles.positions()[0];
    assert!((back.y - 2.0).abs() < 0.05, "{back}");
}

#[test]
fn a_built_in_scene_edited_as_a_copy_runs_and_b_goes_back_to_building() {
    let mut h = harness("pendulum");
    let before = counts(&h);
    key(&mut h, Modifiers::NONE, Key::B);
    assert!(h.state().lab.editing());
    assert_eq!(counts(&h), before, "the copy holds the scene's particles and links");
    assert!(h.state().lab.entry.info().name.ends_with("(copy)"));
    // The bob, selected by a click.
    click(&mut h, "Select");
    let bob = *h.state().lab.scene.world().particles.positions().last().unwrap();
    click_at(&mut h, bob);
    assert!(h.state().lab.editor.as_ref().unwrap().selected.is_some());
    play_and_compare(&mut h, 240);
    // The copy swings as the pendulum it was copied from does.
    let mut original = Lab::new("pendulum", &[]).unwrap();
    original.run_steps_recorded(240);
    let (a, b) =
        (original.scene.world().particles.positions(), h.state().lab.scene.world().particles.positions());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!(x.distance(*y) < 1e-4, "the original at {x}, the copy at {y}");
    }
    // B again: back to building, the history kept (undo is there).
    key(&mut h, Modifiers::NONE, Key::B);
    assert!(h.state().lab.editing());
    assert_eq!(h.state().lab.scene.world().steps(), 0, "building shows the experiment as built");
}

#[test]
fn a_ramp_drawn_by_hand_carries_a_ball_down_and_off_its_end() {
    let mut h = harness("projectile");
    click(&mut h, "Scene");
    click(&mut h, "New experiment…");
    // A ramp from (-3, 3) down to (0, 0.5), drawn in the side view; its slope (0.83)
    // is steeper than its friction (0.5), so a ball slides.
    click(&mut h, "Wall");
    drag(&mut h, Vec3::new(-3.0, 3.0, 0.0), Vec3::new(0.0, 0.5, 0.0));
    let walls: Vec<_> =
        h.state().lab.scene.world().planes().filter(|p| p.extent.is_some()).copied().collect();
    assert_eq!(walls.len(), 1, "one finite wall");
    let extent = walls[0].extent.unwrap();
    assert!((2.0 * extent.half_along - 3.905).abs() < 0.05, "the ramp is {} m long", 2.0 * extent.half_along);
    // A ball just above its top.
    click(&mut h, "Add");
    click_at(&mut h, Vec3::new(-2.6, 3.0, 0.0));
    assert_eq!(counts(&h).0, 1);
    play_and_compare(&mut h, 720);
    // It slid down, off the end, and onto the ground beyond.
    let ball = h.state().lab.scene.world().particles.positions()[0];
    assert!(ball.x > 0.0 && (ball.y - 0.15).abs() < 0.05, "the ball ended at {ball}");
}

/// In 3D a click puts a particle on the ground near the point looked at, and where the
/// ground under the pointer is far off (towards the horizon, or above it) on the plane
/// through that point: never hundreds of metres away, out of sight.
#[test]
fn in_3d_a_click_never_puts_a_particle_out_by_the_horizon() {
    let mut h = harness("pendulum");
    key(&mut h, Modifiers::NONE, Key::B);
    assert!(h.state().lab.editing() && !h.state().lab.side_view);
    let view = h.state().view;
    for k in 1..10 {
        let at = Pos2::new(view.center().x + 40.0, view.top() + view.height() * k as f32 / 10.0);
        let before = counts(&h).0;
        h.hover_at(at);
        h.run_steps(1);
        press(&h, at, true);
        press(&h, at, false);
        h.run_steps(2);
        let lab = &h.state().lab;
        assert_eq!(counts(&h).0, before + 1, "a click at {at:?} added one");
        let placed = *lab.scene.world().particles.positions().last().unwrap();
        let reach = particle_lab::ui::lab::NEAR_GROUND * lab.camera.distance + 1e-3;
        assert!(placed.distance(lab.camera.target) <= reach, "a click at {at:?} put it at {placed}");
    }
}

/// A cloth: a grid of 5 × 3 joined by springs, hung by its top corners (the grid
/// the panel's Add grid makes; the drag values that size it have no label to find them
/// by, so the grid is asked of the lab directly). Every neighbour is joined; played,
/// the corners stay while the middle of the bottom row sags below where it started.
#[test]
fn a_cloth_built_from_a_grid_hangs_from_its_corners() {
    use particle_lab::scenes::sketch::JoinKind;
    use particle_lab::ui::lab::Pins;
    let mut h = harness("pendulum");
    click(&mut h, "Scene");
    click(&mut h, "New experiment…");
    h.state_mut().lab.add_grid([5, 3], 0.4, Some(JoinKind::Spring), Pins::Corners);
    h.run_steps(2);
    assert_eq!(counts(&h), (15, 4 * 3 + 5 * 2), "5 columns × 3 rows, each joined right and down");
    let fixed: Vec<bool> =
        h.state().lab.scene.world().particles.inverse_masses().iter().map(|&w| w == 0.0).collect();
    assert_eq!(fixed.iter().filter(|&&f| f).count(), 2);
    assert!(fixed[0] && fixed[4], "the top row's corners: {fixed:?}");
    let before = h.state().lab.scene.world().particles.positions().to_vec();
    click(&mut h, "Play");
    // A second of physics, as the lab runs it (the harness's frames carry no time).
    h.state_mut().lab.run_steps_recorded(240);
    let after = h.state().lab.scene.world().particles.positions().to_vec();
    assert_eq!(after[0], before[0]);
    assert_eq!(after[4], before[4]);
    assert!(after[12].y < before[12].y - 0.01, "the bottom middle sags: {} -> {}", before[12], after[12]);
}

/// The scene's own integrator and a particle floating in water, set in the builder's
/// panel: the saved file names them, and runs as the lab ran it.
#[test]
fn an_integrator_and_a_float_set_in_the_panel_are_saved_with_the_scene() {
    let mut h = harness("projectile");
    click(&mut h, "Scene");
    click(&mut h, "New experiment…");
    let ball = Vec3::new(0.0, 2.0, 0.0);
    click_at(&mut h, ball);
    assert_eq!(counts(&h), (1, 0));
    h.state_mut().lab.editor.as_mut().unwrap().selected = Some(0);
    h.run_steps(2);
    // The builder's integrator menu, by the label beside it.
    h.get_by_role_and_label(egui::accesskit::Role::ComboBox, "integrator").click();
    h.run_steps(2);
    h.get_all_by_label("verlet").last().expect("verlet in the open menu").click();
    h.run_steps(2);
    assert_eq!(h.state().lab.solver().integrator, particle_lab::physics::Integrator::Verlet);
    assert_eq!(h.state().lab.scene.world().solver().integrator, particle_lab::physics::Integrator::Verlet);
    click(&mut h, "floats");
    let (_, text) = h.state().lab.scene_file_text().expect("a built scene saves");
    assert!(text.contains("integrator = \"verlet\""), "{text}");
    assert!(text.contains("[[buoyancy]]"), "{text}");
    // Undone, the float goes and the integrator stays.
    key(&mut h, Modifiers::COMMAND, Key::Z);
    let (_, text) = h.state().lab.scene_file_text().unwrap();
    assert!(!text.contains("[[buoyancy]]") && text.contains("integrator = \"verlet\""), "{text}");
    // Undone again, the sketch names no integrator: the lab runs the default, not the
    // verlet an earlier state left behind.
    key(&mut h, Modifiers::COMMAND, Key::Z);
    assert_eq!(h.state().lab.solver().integrator, particle_lab::physics::Integrator::SemiImplicitEuler);
    key(&mut h, Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z);
    key(&mut h, Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z);
    let (_, text) = h.state().lab.scene_file_text().unwrap();
    assert!(text.contains("[[buoyancy]]") && text.contains("integrator = \"verlet\""), "{text}");
    play_and_compare(&mut h, 480);
    let world = &h.state().lab.scene.world();
    assert_eq!(world.solver().integrator, particle_lab::physics::Integrator::Verlet);
    assert_eq!(world.forces.len(), 1, "the liquid's buoyancy is the one force generator");
}

//! The view's labels (issue 19): one per object, never written over each other, at
//! the positions of the frame they are drawn in, and the side view's height scale.

use glam::{Vec2, Vec3};
use particle_lab::physics::SolverSettings;
use particle_lab::scenes::{self, SCENES, SceneAction};
use particle_lab::ui::paint::{self, LabelKind, PlacedLabel};
use particle_lab::ui::{Lab, LabUi};

/// Runs the panel and the view at `size` points as the window does (a few passes so
/// egui's layout settles) and returns the labels the last pass wrote and the view's
/// rectangle.
fn written(lab: &mut Lab, size: [f32; 2]) -> (Vec<PlacedLabel>, egui::Rect) {
    let ctx = egui::Context::default();
    let mut placed = Vec::new();
    let mut view = egui::Rect::NOTHING;
    let mut shell = LabUi::default();
    for _ in 0..3 {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(size[0], size[1]))),
            ..Default::default()
        };
        let _ = ctx.run_ui(input, |ui| {
            view = shell.show(ui, lab);
            placed = paint::labels(ui, lab, view);
        });
    }
    (placed, view)
}

fn every_lab() -> Vec<Lab> {
    let entries = SCENES.iter().chain(scenes::file::shipped());
    entries.map(|entry| Lab::from_entry(entry, &[], SolverSettings::default()).unwrap()).collect()
}

#[test]
fn no_object_or_link_is_named_twice() {
    for mut lab in every_lab() {
        lab.run_steps(30);
        let (placed, _) = written(&mut lab, [1280.0, 720.0]);
        let names: Vec<&str> =
            placed.iter().filter(|l| l.kind != LabelKind::Tick).map(|l| l.text.as_str()).collect();
        for (i, name) in names.iter().enumerate() {
            assert!(
                !names[..i].contains(name),
                "{}: '{name}' written twice: {names:?}",
                lab.entry.info().name
            );
        }
    }
    // springForces names its stiff spring's particle "stiff spring": the link is not named
    // again beside it.
    let mut lab = Lab::new("springForces", &[]).unwrap();
    let list = paint::label_list(&lab);
    assert_eq!(list.iter().filter(|l| l.text == "stiff spring").count(), 1, "{list:?}");
    assert_eq!(list.iter().filter(|l| l.text == "bungee").count(), 1, "{list:?}");
    let (placed, _) = written(&mut lab, [1280.0, 720.0]);
    assert!(placed.iter().any(|l| l.text == "bob"), "the bob lost its name: {placed:?}");
}

#[test]
fn labels_never_overprint_at_800_by_600_or_1280_by_720() {
    for size in [[800.0, 600.0], [1280.0, 720.0]] {
        for side_view in [false, true] {
            for mut lab in every_lab() {
                if side_view {
                    lab.set_view_option("side").unwrap();
                }
                lab.run_steps(60);
                let (placed, _) = written(&mut lab, size);
                let name = &lab.entry.info().name;
                for (i, a) in placed.iter().enumerate() {
                    for b in &placed[..i] {
                        assert!(
                            !a.rect.intersects(b.rect),
                            "{name} at {size:?} (side view {side_view}): '{}' {:?} over '{}' {:?}",
                            a.text,
                            a.rect,
                            b.text,
                            b.rect
                        );
                    }
                }
            }
        }
    }
    // The bob's crowd at 800x600 keeps the bob's own name.
    let mut lab = Lab::new("springForces", &[]).unwrap();
    lab.run_steps(150);
    let (placed, _) = written(&mut lab, [800.0, 600.0]);
    assert!(placed.iter().any(|l| l.text == "bob"), "{placed:?}");
}

/// A label is written where its object is in the state being drawn: the newest round's
/// name sits just above the round as it is now, step after step, with the camera
/// following it.
#[test]
fn labels_sit_at_this_frames_positions() {
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.set_view_option("follow").unwrap();
    lab.act(SceneAction::Fire);
    // A quarter of a second on, the round is clear of the launcher's label, which
    // would push its own aside in the wide frame of a 65 m flight.
    lab.run_steps(60);
    for steps in [20, 40, 60] {
        lab.run_steps(steps);
        let (placed, view) = written(&mut lab, [1280.0, 720.0]);
        let world = lab.scene.world();
        let round = world.particles.positions()[world.particles.len() - 1];
        let size = Vec2::new(view.width(), view.height());
        let anchor = lab.camera.project(round + Vec3::Y * 0.7, size).unwrap();
        let anchor = view.min + egui::vec2(anchor.x, anchor.y);
        let label = placed.iter().find(|l| l.text == "round").expect("the round is named");
        assert!(
            (label.rect.center().x - anchor.x).abs() < 0.5 && (label.rect.bottom() - anchor.y).abs() < 0.5,
            "after {steps} more steps 'round' is at {:?}, the round's anchor at {anchor:?}",
            label.rect
        );
    }
}

/// Issue 19: the side view had metre ticks along x only; it has a height scale.
#[test]
fn the_side_view_has_a_height_scale() {
    let ctx = egui::Context::default();
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.scene.act(SceneAction::Fire);
    lab.set_view_option("side").unwrap();
    let mut texts = Vec::new();
    let mut shell = LabUi::default();
    for _ in 0..3 {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 720.0))),
            ..Default::default()
        };
        let output = ctx.run_ui(input, |ui| {
            shell.show(ui, &mut lab);
        });
        texts = output
            .shapes
            .iter()
            .filter_map(|clipped| match &clipped.shape {
                egui::Shape::Text(text) => Some(text.galley.text().to_owned()),
                _ => None,
            })
            .collect();
    }
    assert!(texts.iter().any(|t| t == "height"), "no height scale: {texts:?}");
    // Marks every 5 m up the projectile's 17.4 m peak (36 points apart at least); the
    // ground's ticks along x are every 10 m, so "5 m" and "15 m" are the height scale's.
    for mark in ["0 m", "5 m", "10 m", "15 m"] {
        assert!(texts.iter().any(|t| t == mark), "no '{mark}' mark: {texts:?}");
    }
}

#[test]
fn height_marks_are_one_two_or_five_times_a_power_of_ten() {
    assert_eq!(paint::nice_step(0.7), 1.0);
    assert_eq!(paint::nice_step(1.0), 1.0);
    assert_eq!(paint::nice_step(1.3), 2.0);
    assert_eq!(paint::nice_step(3.0), 5.0);
    assert_eq!(paint::nice_step(6.0), 10.0);
    assert!((paint::nice_step(0.03) - 0.05).abs() < 1e-6);
}

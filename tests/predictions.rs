//! Predict, then measure (issue 37): View → Predictions off hides what the lab
//! predicts — the predicted read-outs, the table's predicted columns, the next round's
//! drag-free path and the ghost of the exact solution — so that a class predicts
//! before it measures; a link carries it (`predictions=hidden`), the settings keep it,
//! and nothing measured is hidden with it.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use particle_lab::render::frame::{FrameBuilder, ViewOptions};
use particle_lab::scenes::{self, SceneAction};
use particle_lab::ui::lab::{Lab, Link};
use particle_lab::ui::shell::LabUi;

/// A projectile lab with one round landed and one in the air.
fn projectile() -> Lab {
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.act(SceneAction::Fire);
    lab.run_steps(1000);
    lab.act(SceneAction::Fire);
    lab.run_steps(200);
    assert_eq!(lab.scene.runs().unwrap().rows.len(), 1, "one round landed");
    lab
}

fn harness(lab: Lab) -> Harness<'static, (LabUi, Lab)> {
    let mut h =
        Harness::builder().with_size([1280.0, 2400.0]).with_accessibility_check(false).build_ui_state(
            |ui, (shell, lab): &mut (LabUi, Lab)| {
                shell.show(ui, lab);
            },
            (LabUi::default(), lab),
        );
    h.run_steps(3);
    h
}

#[test]
fn hidden_predictions_leave_the_measurements_and_hide_every_prediction() {
    let mut h = harness(projectile());
    // Shown (the default): the predicted read-out and the table's predicted column.
    assert!(h.query_by_label("range to the ground (no drag, no damping)").is_some());
    assert!(h.query_by_label("predicted range (m)").is_some());
    assert!(h.query_by_label("range (m)").is_some());
    h.state_mut().1.view.predictions = false;
    h.run_steps(3);
    assert!(h.query_by_label("range to the ground (no drag, no damping)").is_none());
    assert!(h.query_by_label("peak (no drag, no damping)").is_none());
    assert!(h.query_by_label("predicted range (m)").is_none());
    // What was measured stays.
    assert!(h.query_by_label("range (m)").is_some());
    assert!(h.query_by_label("rounds in flight").is_some());
    assert!(h.query_by_label("Predictions hidden: View > Predictions shows them").is_some());
    // Every row the panel leaves out is one the scene marks a prediction, and the
    // scene has such rows: nothing else went.
    let lab = &mut h.state_mut().1;
    let rows = lab.scene.readout_rows(lab.dt());
    assert!(rows.iter().any(|row| row.is_prediction()));
    for row in &rows {
        let predicted = row.values.iter().any(|(key, _)| key.ends_with("_predicted_m"));
        assert_eq!(row.is_prediction(), predicted, "{}", row.label);
    }
}

#[test]
fn the_view_draws_the_ghost_and_the_drag_free_path_only_with_predictions() {
    let lab = projectile();
    let mut predicted = Vec::new();
    lab.scene.predictions(&mut predicted);
    assert!(predicted.len() > 10, "a ghost and the next round's dotted path: {}", predicted.len());
    let mut builder = FrameBuilder::default();
    let shown = builder.build(lab.scene.as_ref(), None, 0.0, ViewOptions::default(), None).spheres.len();
    let hidden_options = ViewOptions { predictions: false, ..ViewOptions::default() };
    let hidden = builder.build(lab.scene.as_ref(), None, 0.0, hidden_options, None).spheres.len();
    assert_eq!(shown - hidden, predicted.len());
    // The spring's ghost is a prediction too; the bridge predicts nothing.
    let mut spring = Vec::new();
    scenes::create_default("springForces").predictions(&mut spring);
    assert_eq!(spring.len(), 1);
    let mut bridge = Vec::new();
    scenes::create_default("bridge").predictions(&mut bridge);
    assert!(bridge.is_empty());
}

#[test]
fn a_link_carries_hidden_predictions_and_refuses_a_bad_value() {
    let mut lab = Lab::new("projectile", &[]).unwrap();
    assert!(!Link::of(&lab, false).unwrap().contains("predictions"), "shown is the default, not written");
    lab.view.predictions = false;
    let text = Link::of(&lab, false).unwrap();
    assert!(text.contains("predictions=hidden"), "{text}");
    let link = Link::parse_text(&text).unwrap();
    let mut opened = Lab::new("projectile", &[]).unwrap();
    assert!(opened.view.predictions);
    link.view.apply(&mut opened);
    assert!(!opened.view.predictions);
    let error = Link::parse_text("?scene=projectile&predictions=maybe").unwrap_err();
    assert_eq!(error, "invalid value 'maybe' for 'predictions': shown or hidden");
}

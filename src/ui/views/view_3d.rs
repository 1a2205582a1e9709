//! The 3D view's input: drag particles, select them, measure with the tape, orbit,
//! pan and zoom; the hover tooltips of a projectile's path; the labels painted over
//! the view. Only input that reached this area (not the panels) moves anything.

use egui::{Color32, PointerButton, Rect, Sense};
use glam::Vec2;

use crate::scenes::SceneAction;
use crate::ui::lab::Lab;
use crate::ui::paint;

/// The 3D view; it keeps no state (the camera is the lab's).
#[derive(Debug, Default)]
pub struct View3d;

impl View3d {
    /// Handles the view's input and paints its overlays; returns the view's rectangle.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab) -> Rect {
        view_3d(ui, lab)
    }
}

/// The builder's marks over the view: a ring round the selected particle, and the
/// link being drawn from its first end to the pointer.
fn paint_builder(ui: &egui::Ui, lab: &Lab, rect: Rect) {
    let Some(editor) = &lab.editor else { return };
    let size = Vec2::new(rect.width(), rect.height());
    let screen = |p: glam::Vec3| lab.camera.project(p, size).map(|s| rect.min + egui::vec2(s.x, s.y));
    let painter = ui.painter_at(rect);
    let accent = Color32::from_rgb(255, 200, 60);
    let bodies = &editor.sketch().bodies;
    if let Some(body) = editor.selected.and_then(|i| bodies.get(i))
        && let Some(centre) = screen(body.position)
    {
        // The ring's size on screen: the particle's radius projected beside it.
        let side = lab.camera.right() * body.radius;
        let radius = screen(body.position + side).map_or(8.0, |edge| centre.distance(edge)).max(6.0) + 4.0;
        painter.circle_stroke(centre, radius, egui::Stroke::new(2.0, accent));
    }
    if let Some(crate::ui::lab::Gesture::Join { from, to, .. }) = editor.gesture
        && let (Some(a), Some(b)) = (bodies.get(from).and_then(|b| screen(b.position)), screen(to))
    {
        painter.line_segment([a, b], egui::Stroke::new(2.0, accent));
    }
    if let Some(crate::ui::lab::Gesture::Wall { from, to }) = editor.gesture
        && let (Some(a), Some(b)) = (screen(from), screen(to))
    {
        painter.line_segment([a, b], egui::Stroke::new(4.0, accent));
    }
    let hint = match editor.tool {
        crate::ui::lab::Tool::Add => "Building · click to add a particle · drag one to move it",
        crate::ui::lab::Tool::Select => "Building · click to select · drag a particle to move it",
        crate::ui::lab::Tool::Join => {
            "Building · drag from a particle to another (or to empty space) to link"
        }
        crate::ui::lab::Tool::Wall => "Building · drag to draw a wall or a ramp",
    };
    painter.text(
        rect.center_top() + egui::vec2(0.0, 12.0),
        egui::Align2::CENTER_TOP,
        hint,
        egui::FontId::proportional(15.0),
        Color32::from_gray(220),
    );
}

/// How near the pointer must be to a path point to show its tooltip (points).
const HOVER_RADIUS: f32 = 10.0;

/// The 3D view's input: drag particles, orbit, pan and zoom. Only input that reached
/// this area (not the panels) moves anything.
pub fn view_3d(ui: &mut egui::Ui, lab: &mut Lab) -> Rect {
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
    let building = lab.editing();
    let mut building_gesture = building && lab.editor.as_ref().is_some_and(|e| e.gesture.is_some());
    if building && response.drag_started_by(PointerButton::Primary) {
        // In the builder a press on a particle moves or links it; elsewhere orbits.
        if let Some(press) = ui.input(|i| i.pointer.press_origin()) {
            building_gesture = lab.builder_press(local(press), size);
        }
    }
    if building_gesture
        && response.dragged_by(PointerButton::Primary)
        && let Some(p) = response.interact_pointer_pos()
    {
        lab.builder_drag(local(p), size);
    }
    if building_gesture
        && response.drag_stopped()
        && let Some(p) = ui.input(|i| i.pointer.latest_pos())
    {
        lab.builder_release(local(p), size);
    }
    if !building && response.drag_started_by(PointerButton::Primary) {
        // Press on a particle to drag it; anywhere else orbits. The drag starts only
        // after the pointer moved a little: pick where the button went down.
        if let Some(press) = ui.input(|i| i.pointer.press_origin()) {
            lab.start_grab(local(press), size);
        }
    }
    if !building_gesture && response.dragged_by(PointerButton::Primary) {
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
        if building {
            lab.builder_click(local(p), size);
        } else if lab.tape {
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
    if building {
        paint_builder(ui, lab, rect);
    }
    if lab.scene.world().particles.is_empty()
        && lab.entry.info().actions.iter().any(|a| a.action == SceneAction::Fire)
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

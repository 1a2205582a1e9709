//! The builder's edits, on its state (`builder_state`): a [`Sketch`] with its history
//! (undo, redo), the tool in hand, the selection, and the gestures in the view (add a particle where the
//! pointer is, drag one to move it, drag from one to another to link them). Every
//! edit writes the sketch as a scene file and loads it as the running scene, paused,
//! so that what is built is exactly what Play runs, Reset returns to, Save writes and
//! a link carries.

use glam::{Vec2, Vec3};

use super::builder_state::{Editor, Gesture, NEAR_GROUND, Tool, UNDO_LIMIT};
use super::model::Lab;
use crate::physics::SolverSettings;
use crate::scenes::file;
use crate::scenes::sketch::{Body, End, JoinKind, Sketch};

impl Lab {
    /// Whether the builder is open.
    #[must_use]
    pub fn editing(&self) -> bool {
        self.editor.as_ref().is_some_and(|e| e.open)
    }

    /// Opens the builder on a copy of the running scene as it was built (its
    /// particles, links, ground, walls and gravity; the status line names what a
    /// scene file cannot hold and is left out). The scene pauses.
    /// What was built and is playing goes back to the builder as it was left, its
    /// history kept.
    pub fn edit_copy(&mut self) {
        if self.editing() {
            return;
        }
        self.reset();
        let source = self.scene.source().map(|(text, _)| text.to_string());
        if let Some(editor) = &mut self.editor
            && source.is_some_and(|text| text == editor.sketch().text())
        {
            editor.open = true;
            editor.gesture = None;
            self.paused = true;
            self.status = "Building again: Play (B) runs it".into();
            log::info!("builder: back to building {}", self.entry.info().name);
            return;
        }
        let name = format!("{} (copy)", self.entry.info().name);
        let (mut sketch, left_out) = Sketch::from_scene(self.scene.as_ref(), &name);
        sketch.dt = Some(self.dt());
        self.status = if left_out.is_empty() {
            format!("Building: a copy of {}. Play runs it; Ctrl+Z undoes", self.entry.info().name)
        } else {
            format!("Building: a copy of {}, without {}", self.entry.info().name, left_out.join(", "))
        };
        log::info!("builder: editing a copy of {}", self.entry.info().name);
        self.open_editor(sketch);
    }

    /// Opens the builder on an empty experiment: the ground, gravity, and the side
    /// view to put particles on.
    pub fn edit_new(&mut self) {
        if self.editing() {
            return;
        }
        log::info!("builder: a new experiment");
        self.status = "Building a new experiment: click in the view to add particles".into();
        self.open_editor(Sketch::new("my-experiment"));
        self.set_side_view(true);
        self.camera.target = Vec3::new(0.0, 1.5, 0.0);
        self.camera.distance = 8.0;
        self.camera_moved = true;
    }

    fn open_editor(&mut self, sketch: Sketch) {
        self.paused = true;
        self.grab = None;
        self.select(None);
        let camera = (self.camera, self.camera_moved);
        self.editor = Some(Editor::new(sketch));
        self.load_sketch();
        (self.camera, self.camera_moved) = camera;
    }

    /// Closes the builder and runs the experiment from the edited state.
    pub fn play(&mut self) {
        if let Some(editor) = self.editor.as_mut().filter(|e| e.open) {
            editor.open = false;
            editor.gesture = None;
            log::info!("builder: play {}", self.entry.info().name);
            self.reset();
            self.paused = false;
            self.status = "Playing. B goes back to building".into();
        }
    }

    /// Loads the sketch as it stands as the running scene (paused, the camera kept).
    /// A sketch the loader refuses (it should not) leaves the scene and says why.
    fn load_sketch(&mut self) {
        let Some(editor) = &self.editor else { return };
        let sketch = editor.sketch();
        let text = sketch.text();
        match file::load_text(&text, &sketch.name, None) {
            Ok(entry) => {
                // The sketch names its solver whole: what it leaves out is the default,
                // not what an earlier state of it (or another scene) left behind.
                self.solver = sketch.solver.over(SolverSettings::default());
                let camera = (self.camera, self.camera_moved, self.side_view);
                let editor = self.editor.take();
                self.switch_scene(&entry);
                self.editor = editor;
                (self.camera, self.camera_moved, self.side_view) = camera;
                self.scene_file = None;
                self.paused = true;
            }
            Err(error) => {
                log::warn!("builder: {error}");
                self.status = format!("This edit cannot be built: {}", error.message);
            }
        }
    }

    /// Makes an edit: `change` names it (edits of the same name in a row are one
    /// step to undo), `edit` changes a copy of the sketch and says whether it did.
    pub fn edit(&mut self, change: &'static str, edit: impl FnOnce(&mut Sketch, &mut Editor) -> bool) {
        let Some(editor) = self.editor.as_mut().filter(|e| e.open) else { return };
        let mut sketch = editor.sketch().clone();
        if !edit(&mut sketch, editor) || sketch == *editor.sketch() {
            return;
        }
        editor.history.truncate(editor.at + 1);
        if editor.last_change == Some(change) && editor.at > 0 {
            editor.history[editor.at] = sketch;
        } else {
            editor.history.push(sketch);
            if editor.history.len() > UNDO_LIMIT + 1 {
                editor.history.remove(0);
            }
            editor.at = editor.history.len() - 1;
        }
        editor.last_change = Some(change);
        if let Some(selected) = editor.selected
            && selected >= editor.sketch().bodies.len()
        {
            editor.selected = None;
        }
        log::info!(
            "builder: {change} ({} particles, {} links)",
            editor.sketch().bodies.len(),
            editor.sketch().joins.len()
        );
        self.load_sketch();
    }

    /// Ends a run of edits of one name: the next is a step of its own to undo.
    pub fn end_edit(&mut self) {
        if let Some(editor) = &mut self.editor {
            editor.last_change = None;
        }
    }

    /// Undoes the last edit.
    pub fn undo(&mut self) {
        let Some(editor) = self.editor.as_mut().filter(|e| e.open) else { return };
        if editor.can_undo() {
            editor.at -= 1;
            editor.last_change = None;
            editor.gesture = None;
            editor.selected = editor.selected.filter(|&i| i < editor.sketch().bodies.len());
            log::info!("builder: undo ({} left)", editor.at);
            self.load_sketch();
        }
    }

    /// Redoes the last edit undone.
    pub fn redo(&mut self) {
        let Some(editor) = self.editor.as_mut().filter(|e| e.open) else { return };
        if editor.can_redo() {
            editor.at += 1;
            editor.last_change = None;
            editor.gesture = None;
            editor.selected = editor.selected.filter(|&i| i < editor.sketch().bodies.len());
            log::info!("builder: redo");
            self.load_sketch();
        }
    }

    /// Deletes the selected particle and its links.
    pub fn delete_selected(&mut self) {
        let Some(i) = self.editor.as_ref().filter(|e| e.open).and_then(|e| e.selected) else { return };
        self.edit("delete", |sketch, editor| {
            sketch.remove(i);
            editor.selected = None;
            true
        });
        self.end_edit();
    }

    /// The sketch's particle under `pixel` (fixed ones too), nearest first.
    #[must_use]
    pub fn pick_body(&self, pixel: Vec2, viewport: Vec2) -> Option<usize> {
        let editor = self.editor.as_ref()?;
        let (origin, direction) = self.camera.ray(pixel, viewport);
        let mut best: Option<(f32, usize)> = None;
        for (i, body) in editor.sketch().bodies.iter().enumerate() {
            let radius = body.radius.max(0.05) * 1.2 + 0.05;
            let to_center = body.position - origin;
            let along = to_center.dot(direction);
            let miss = to_center.length_squared() - along * along;
            if along > 0.0 && miss <= radius * radius && best.is_none_or(|(d, _)| along < d) {
                best = Some((along, i));
            }
        }
        best.map(|(_, i)| i)
    }

    /// Where a click at `pixel` puts a new particle of radius `radius`: in the side
    /// view on its plane (z = 0); in 3D on the ground under the pointer (resting on
    /// it), or, where the ground under the pointer is far off (near the horizon, or
    /// above it), on the plane through the point looked at, facing the camera. `None`
    /// where the pointer looks at no such point.
    #[must_use]
    pub fn place_point(&self, pixel: Vec2, viewport: Vec2, radius: f32) -> Option<Vec3> {
        let (origin, direction) = self.camera.ray(pixel, viewport);
        if self.side_view {
            return hit_plane(origin, direction, Vec3::ZERO, Vec3::Z);
        }
        let target = self.camera.target;
        let near = |p: &Vec3| p.distance(target) <= NEAR_GROUND * self.camera.distance;
        hit_plane(origin, direction, Vec3::new(0.0, radius, 0.0), Vec3::Y).filter(near).or_else(|| {
            hit_plane(origin, direction, target, (self.camera.eye() - target).normalize_or_zero())
        })
    }

    /// The normal of the plane a particle moves on under the pointer: the side
    /// view's (z stays), or in 3D the one facing the camera.
    fn drag_plane(&self) -> Vec3 {
        if self.side_view { Vec3::Z } else { (self.camera.eye() - self.camera.target).normalize_or_zero() }
    }

    /// A press at `pixel` in the view with the builder open (the start of a drag or
    /// a click): selects, starts a move or a link. True when it took the press (else
    /// the view orbits or pans).
    pub fn builder_press(&mut self, pixel: Vec2, viewport: Vec2) -> bool {
        let Some(tool) = self.editor.as_ref().map(|e| e.tool) else { return false };
        if tool == Tool::Wall {
            let Some(from) = self.place_point(pixel, viewport, 0.0) else { return false };
            if let Some(editor) = &mut self.editor {
                editor.gesture = Some(Gesture::Wall { from, to: from });
            }
            return true;
        }
        let picked = self.pick_body(pixel, viewport);
        let Some(index) = picked else { return false };
        let point = self.editor.as_ref().map_or(Vec3::ZERO, |e| e.sketch().bodies[index].position);
        let normal = self.drag_plane();
        let Some(editor) = &mut self.editor else { return false };
        editor.selected = Some(index);
        editor.gesture = Some(match tool {
            Tool::Select | Tool::Add => Gesture::Move { index, plane_point: point, normal },
            Tool::Join => Gesture::Join { from: index, to: point, normal },
            Tool::Wall => unreachable!("the wall tool's press is taken above"),
        });
        true
    }

    /// The pointer moved to `pixel` during a builder gesture: a moved particle
    /// follows it (shown at once, written when let go); a link's loose end follows it.
    pub fn builder_drag(&mut self, pixel: Vec2, viewport: Vec2) {
        let (origin, direction) = self.camera.ray(pixel, viewport);
        let placed = self.place_point(pixel, viewport, 0.0);
        let Some(editor) = &mut self.editor else { return };
        match &mut editor.gesture {
            Some(Gesture::Move { index, plane_point, normal }) => {
                if let Some(point) = hit_plane(origin, direction, *plane_point, *normal) {
                    let particles = &mut self.scene.world_mut().particles;
                    if *index < particles.len() {
                        particles.position[*index] = point;
                    }
                }
            }
            Some(Gesture::Join { from, to, normal }) => {
                let start = editor.history[editor.at].bodies[*from].position;
                if let Some(point) = hit_plane(origin, direction, start, *normal) {
                    *to = point;
                }
            }
            Some(Gesture::Wall { to, .. }) => {
                if let Some(point) = placed {
                    *to = point;
                }
            }
            None => {}
        }
    }

    /// The gesture ends with the pointer at `pixel`: a moved particle is written
    /// where it was put (its links take their new lengths), a link is made to the
    /// particle there, or to a fixed point where there is none.
    pub fn builder_release(&mut self, pixel: Vec2, viewport: Vec2) {
        let Some(gesture) = self.editor.as_mut().and_then(|e| e.gesture.take()) else { return };
        match gesture {
            Gesture::Move { index, .. } => {
                let particles = &self.scene.world().particles;
                let Some(&to) = particles.positions().get(index) else { return };
                self.edit("move", |sketch, _| {
                    let Some(body) = sketch.bodies.get_mut(index) else { return false };
                    body.position = to;
                    sketch.fit_lengths(index);
                    true
                });
            }
            Gesture::Join { from, to, .. } => {
                let end = match self.pick_body(pixel, viewport) {
                    Some(b) if b != from => End::Body(b),
                    Some(_) => return, // let go where it started: no link
                    None => End::Anchor(to),
                };
                let mut refused = None;
                self.edit("link", |sketch, editor| {
                    match sketch.join(editor.join_kind, from, end, editor.spring_k) {
                        Ok(()) => true,
                        Err(why) => {
                            refused = Some(why);
                            false
                        }
                    }
                });
                if let Some(why) = refused {
                    self.status = format!("No link: {why}");
                }
            }
            Gesture::Wall { from, to } => {
                let to = self.place_point(pixel, viewport, 0.0).unwrap_or(to);
                let width = self.editor.as_ref().map_or(2.0, |e| e.wall_width);
                match Sketch::wall_along(from, to, width) {
                    Some(wall) => self.edit("wall", |sketch, _| {
                        sketch.walls.push(wall);
                        true
                    }),
                    None => self.status = "No wall: drag further to draw one".into(),
                }
            }
        }
        self.end_edit();
    }

    /// A click at `pixel` (no drag) with the builder open: the Add tool puts a
    /// particle there (or selects the one clicked); the others select or clear.
    pub fn builder_click(&mut self, pixel: Vec2, viewport: Vec2) {
        let Some(editor) = &self.editor else { return };
        let (tool, template) = (editor.tool, editor.new_body.clone());
        let picked = self.pick_body(pixel, viewport);
        if tool == Tool::Add && picked.is_none() {
            let Some(point) = self.place_point(pixel, viewport, template.radius) else { return };
            let mut added = None;
            self.edit("add", |sketch, _| {
                added = sketch.add(Body { position: point, ..template });
                added.is_some()
            });
            self.end_edit();
            if let Some(editor) = &mut self.editor {
                editor.selected = added.or(editor.selected);
            }
            if added.is_none() {
                self.status =
                    format!("A sketch holds at most {} particles", crate::scenes::sketch::MAX_BODIES);
            }
        } else if let Some(editor) = &mut self.editor {
            editor.selected = picked;
        }
    }

    /// Adds a row of `count` particles `spacing` apart along x, from the selected
    /// particle (or 2 m above the origin), each linked to the next with `link`
    /// (none: unlinked), the first pinned if `pin_first`.
    pub fn add_row(&mut self, count: usize, spacing: f32, link: Option<JoinKind>, pin_first: bool) {
        self.add_grid([count, 1], spacing, link, if pin_first { Pins::First } else { Pins::None });
    }

    /// Adds `columns × rows` particles of the Add tool's kind, `spacing` apart: columns
    /// along x, rows downwards, from beside the selected particle (or 2 m above the
    /// origin). With `link`, each is joined to its neighbour on the right and the one
    /// below: a chain for one row, a cloth for many. `pins` fixes some of the top row.
    pub fn add_grid(
        &mut self,
        [columns, rows]: [usize; 2],
        spacing: f32,
        link: Option<JoinKind>,
        pins: Pins,
    ) {
        let Some(editor) = &self.editor else { return };
        let start = editor
            .selected
            .and_then(|i| editor.sketch().bodies.get(i))
            .map_or(Vec3::new(0.0, 2.0, 0.0), |b| b.position + Vec3::X * spacing);
        let (template, k) = (editor.new_body.clone(), editor.spring_k);
        let change = if rows > 1 { "add a grid" } else { "add a row" };
        self.edit(change, |sketch, _| {
            let first = sketch.bodies.len();
            for row in 0..rows {
                for column in 0..columns {
                    let fixed = row == 0
                        && match pins {
                            Pins::None => false,
                            Pins::First => column == 0,
                            Pins::Corners => column == 0 || column + 1 == columns,
                        };
                    let position = start + Vec3::new(column as f32, -(row as f32), 0.0) * spacing;
                    let Some(i) = sketch.add(Body { position, fixed, ..template.clone() }) else {
                        return sketch.bodies.len() > first;
                    };
                    if let Some(kind) = link {
                        if column > 0 {
                            let _ = sketch.join(kind, i - 1, End::Body(i), k);
                        }
                        if row > 0 {
                            let _ = sketch.join(kind, i - columns, End::Body(i), k);
                        }
                    }
                }
            }
            true
        });
        self.end_edit();
    }
}

/// Where the ray from `origin` along `direction` meets the plane through `point`
/// facing `normal`, ahead of the origin.
fn hit_plane(origin: Vec3, direction: Vec3, point: Vec3, normal: Vec3) -> Option<Vec3> {
    let facing = direction.dot(normal);
    if facing.abs() < 1e-6 {
        return None;
    }
    let t = (point - origin).dot(normal) / facing;
    (t > 0.0).then(|| origin + direction * t)
}

/// Which particles of a new row or grid's top row are fixed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pins {
    /// None: it falls.
    None,
    /// The first: a chain hanging from it.
    First,
    /// The first and last: a cloth hung by its corners.
    Corners,
}

//! The builder's state, plain data beside the lab (as `records` is): the sketch with its
//! history, the tool in hand, the selection and the gesture in progress. The edits
//! that change it are the lab's (`editing.rs`).

use glam::Vec3;

use crate::scenes::sketch::{Body, JoinKind, Sketch};

/// Most edits kept to undo.
pub const UNDO_LIMIT: usize = 200;

/// How far from the point looked at (in camera distances) a click in 3D may put a
/// particle on the ground; further off (towards the horizon) it goes on the plane
/// through that point instead.
pub const NEAR_GROUND: f32 = 2.0;

/// What a press in the view does while building.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Click selects; drag a particle to move it.
    Select,
    /// Click puts a new particle there.
    Add,
    /// Drag from a particle to another, or to empty space for a fixed point, to link them.
    Join,
    /// Drag a segment to draw a finite wall along it (a ramp in the side view, an
    /// upright wall on the ground in 3D).
    Wall,
}

/// An edit in progress in the view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Gesture {
    /// Moving particle `index` on the plane through `plane_point` facing `normal`.
    Move {
        /// The particle.
        index: usize,
        /// A point of the plane it moves on.
        plane_point: Vec3,
        /// The plane's normal.
        normal: Vec3,
    },
    /// Linking from particle `from`; the pointer is at `to` (m).
    Join {
        /// The first end.
        from: usize,
        /// Where the pointer is, on the plane through `from` facing the camera.
        to: Vec3,
        /// The plane's normal.
        normal: Vec3,
    },
    /// Drawing a wall from `from` to `to` (m).
    Wall {
        /// Where the drag started.
        from: Vec3,
        /// Where the pointer is.
        to: Vec3,
    },
}

/// The builder.
#[derive(Clone, Debug)]
pub struct Editor {
    /// Every state of the sketch kept, oldest first.
    pub(super) history: Vec<Sketch>,
    /// The one shown: `history[at]`.
    pub(super) at: usize,
    /// What the last edit changed, so that a slider dragged through many values
    /// is one step to undo.
    pub(super) last_change: Option<&'static str>,
    /// The tool in hand.
    pub tool: Tool,
    /// The selected particle.
    pub selected: Option<usize>,
    /// The kind of link the Join tool makes.
    pub join_kind: JoinKind,
    /// The spring constant of new springs and bungees (N/m).
    pub spring_k: f32,
    /// What the Add tool puts down.
    pub new_body: Body,
    /// The width of walls the Wall tool draws (m).
    pub wall_width: f32,
    /// An edit in progress in the view.
    pub gesture: Option<Gesture>,
    /// Building (the scene paused); false while what was built plays, to come back to.
    pub(super) open: bool,
}

impl Editor {
    pub(super) fn new(sketch: Sketch) -> Self {
        Self {
            history: vec![sketch],
            at: 0,
            last_change: None,
            tool: Tool::Add,
            selected: None,
            join_kind: JoinKind::Rod,
            spring_k: 50.0,
            new_body: Body { radius: 0.15, ..Body::default() },
            wall_width: 2.0,
            gesture: None,
            open: true,
        }
    }

    /// The sketch as it stands.
    #[must_use]
    pub fn sketch(&self) -> &Sketch {
        &self.history[self.at]
    }

    /// Whether there is an edit to undo.
    #[must_use]
    pub fn can_undo(&self) -> bool {
        self.at > 0
    }

    /// Whether there is an undone edit to redo.
    #[must_use]
    pub fn can_redo(&self) -> bool {
        self.at + 1 < self.history.len()
    }

    /// Edits kept to undo.
    #[must_use]
    pub fn undo_depth(&self) -> usize {
        self.at
    }
}

//! The lab: the running scene plus everything the panel controls (run state, view
//! options, camera, trails, the particle being dragged). Knows nothing of windows.
//!
//! Its rooms: `model` (the `Lab` and its scene), `clock` (stepping in real time),
//! `grab` (dragging and picking), `forces` (the inspector's forces and the arrows'
//! scale), `framing` (the camera: framing, side view, follow), `bars` (energy bars), `tape`,
//! `snapshots`, `runs_file` (the table of runs saved as CSV), `scene_file` (open and hot-reload a scene file, with `watch`), `editing`
//! (the builder's edits and gestures, on its state in the leaf `builder_state`), `link`
//! (a web page's query string as the window's command line, and the link of what is on
//! screen); and two leaves every room may read, `limits` (the constants) and
//! `records` (plain data). Only this facade re-exports; no room imports it.

mod bars;
mod builder_state;
pub mod carried;
mod clock;
mod editing;
mod forces;
mod framing;
mod grab;
pub mod limits;
mod link;
mod model;
pub mod records;
mod runs_file;
mod scene_file;
mod snapshots;
mod tape;
mod watch;

pub use crate::physics::inspect::CONSTRAINT_FORCE;
pub use builder_state::{Editor, Gesture, NEAR_GROUND, Tool, UNDO_LIMIT};
pub use editing::Pins;
pub use forces::{Spin, round_scale};
pub use grab::{mouse_pull, mouse_pull_joined};
pub use limits::*;
pub use link::{CARRIED_NAME, Link, LinkView};
pub use model::Lab;
pub use records::{EnergyBars, EnergySample, Grab, Purpose, Requests, Stats};

//! particle-lab: a real-time mass-aggregate particle physics lab.
//!
//! - [`physics`]: the engine (particles, forces, contacts, links, world). No graphics.
//! - [`scenes`]: the demos as data: each builds a world and declares its parameters.
//! - [`cli`]: the command line (`scenes`, `simulate`).

pub mod app;
pub mod cli;
pub mod messages;
pub mod physics;
pub mod render;
pub mod scenes;
pub mod snapshot;
pub mod ui;

//! particle-lab: a real-time mass-aggregate particle physics lab.
//!
//! - [`physics`]: the engine (particles, forces, contacts, links, world). No graphics.
//! - [`scenes`]: the demos as data: each builds a world and declares its parameters.
//! - [`cli`]: the command line (`scenes`, `simulate`, `render`).
//! - [`capture`]: off-screen frames of the lab, with or without the panel (`render`, the image tests).
//! - [`settings`]: what the window remembers from one launch to the next.
//! - `web` (in a browser only): the page's entry point, its link, canvas and GPU.

// An `unsafe fn`'s body is not one unsafe block: each unsafe operation in it is marked
// and says why it holds (`// SAFETY:`), as everywhere else.
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(clippy::undocumented_unsafe_blocks)]

pub mod app;
pub mod capture;
pub mod cli;
pub mod messages;
pub mod physics;
pub mod reading;
pub mod render;
pub mod scenes;
pub mod settings;
pub mod ui;
#[cfg(target_arch = "wasm32")]
pub mod web;
pub mod writing;

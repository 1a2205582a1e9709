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

// Without the `window` feature (on by default) the library is the engine alone, with
// the messages it words its errors in: what Miri runs (`scripts/miri.sh`).
#[cfg(feature = "window")]
pub mod app;
#[cfg(feature = "window")]
pub mod capture;
#[cfg(feature = "window")]
pub mod cli;
pub mod messages;
pub mod physics;
#[cfg(feature = "window")]
pub mod reading;
#[cfg(feature = "window")]
pub mod render;
#[cfg(feature = "window")]
pub mod scenes;
#[cfg(feature = "window")]
pub mod settings;
#[cfg(feature = "window")]
pub mod ui;
#[cfg(all(target_arch = "wasm32", feature = "window"))]
pub mod web;
#[cfg(feature = "window")]
pub mod writing;

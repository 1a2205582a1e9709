//! The egui interface: the shell that places the views, the views themselves (one per
//! tool), the lab they act on, and the painting of a frame. The same code runs in the
//! window and in `render --ui`.
//!
//! Rooms (each may import those listed after it, never one before):
//! - `shell` places the views of a frame and holds their state ([`LabUi`]);
//! - `views/` one struct per panel or menu, with its own drafts;
//! - `keys` the controls table and its handler; `layout` what the settings save of the
//!   panel; `plot` line plots; `style` colours and number formats;
//! - `page` (in a browser only) the web page around the canvas: its GPU, files,
//!   downloads, link and state element;
//! - `paint` the 3D frame and the labels over it;
//! - `path_completion` what a typed path completes to (a folder's entries, no egui);
//! - `compare` the Compare copy; `lab/` the model: scene, world, clocks, history.
//!
//! This file only re-exports; nothing in `ui/` imports it.

pub mod compare;
pub mod keys;
pub mod lab;
pub mod layout;
#[cfg(target_arch = "wasm32")]
pub mod page;
pub mod paint;
#[cfg(not(target_arch = "wasm32"))]
pub mod path_completion;
pub mod plot;
pub mod shell;
pub mod style;
pub mod views;

pub use lab::Lab;
pub use layout::{PanelLayout, Section};
pub use plot::segments;
pub use shell::{LabUi, PANEL_WIDTH};
pub use style::joules;

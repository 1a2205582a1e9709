//! The panel's views, one per tool, each a struct with its own state (a draft, a
//! remembered choice) and a `ui` method that draws it and applies what the user did
//! to the [`Lab`](crate::ui::lab::Lab), as egui's demo windows do. The shell
//! (`ui/shell.rs`) places them.

pub mod builder;
pub mod compare_panel;
pub mod energy;
pub mod file_menu;
pub mod help;
pub mod inspector;
pub mod legends;
pub mod menu_bar;
pub mod readouts;
pub mod run_controls;
pub mod runs;
pub mod runs_plot;
pub mod scene_menu;
pub mod scene_params;
pub mod stats;
pub mod view_3d;
pub mod view_menu;

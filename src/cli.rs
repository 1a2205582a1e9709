//! The command line: `scenes` lists the scenes, `simulate` runs one headless and prints
//! JSON Lines, `render` draws frames off-screen, `link` prints the link that opens a
//! scene in the web lab, `open` opens such a link in the window, `export` prints a
//! scene as a scene file and `fit` fits a line to a table of runs. Bad input gets one line on stderr and
//! exit code 2, never a panic.
//!
//! This file holds the flags (clap's derive) and their parsing; each command has its
//! room: [`list`] (`scenes`), [`simulate`] (`simulate`), [`render`] (`render`, one
//! frame) and [`record`] (`render --frames`).

use clap::{Parser, Subcommand};

pub mod clock;
pub mod export;
pub mod fit;
pub mod flags;
pub mod link;
pub mod list;
pub mod progress;
pub mod record;
pub mod render;
pub mod setup;
pub mod simulate;
pub mod usage;

pub use export::ExportArgs;
pub use fit::FitArgs;
pub use flags::{MAX_STEPS, SolverArgs};
pub use link::{LinkArgs, OpenArgs};
pub use list::{Format, about_scene, list_scenes};
pub use render::{MAX_IMAGE_SIDE, RenderArgs, render};
pub use simulate::{CSV_HEADER, RunPlan, SimulateArgs, StateFormat, prepare, simulate};

/// Exit code for input the user can fix.
pub const USAGE_ERROR: i32 = 2;

/// particle-lab: a real-time particle physics lab.
#[derive(Debug, Parser)]
#[command(name = "particle-lab", version, about, long_about = None)]
pub struct Cli {
    /// What to do; without a command the window opens.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// The scene to open the window on (a scene file is reloaded when it changes), its
    /// parameters and the solver.
    #[command(flatten)]
    pub choice: flags::SceneChoice,
    /// Open the window with the default settings, without reading the saved ones
    /// (they are replaced on exit).
    #[arg(long)]
    pub fresh: bool,
    /// Open on a snapshot (File → Save snapshot, or `simulate --save`): its scene,
    /// parameters, solver and time step, at the step it was saved.
    #[arg(long, value_name = "FILE.json", conflicts_with_all = ["scene", "scene_file", "set", "solver", "substeps", "integrator"])]
    pub from: Option<std::path::PathBuf>,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List every scene with its parameters.
    Scenes {
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
        /// Print the page on a scene's physics (the window's Help > About this scene)
        /// instead of the list
        #[arg(long, value_name = "SCENE")]
        about: Option<String>,
    },
    /// Run a scene headless and print its state as JSON Lines.
    Simulate(SimulateArgs),
    /// Step a scene and write one off-screen frame to a PNG (needs no display).
    Render(RenderArgs),
    /// Print the link that opens a scene in the web lab (a scene file not shipped is
    /// carried in the link)
    Link(LinkArgs),
    /// Open a link to an experiment (from File → Copy link or `link`) in the window
    Open(OpenArgs),
    /// Print a scene as a scene file (what File → Save scene as… writes), with the
    /// values `--set` gives as its defaults
    Export(ExportArgs),
    /// Print the least-squares line of one column of a table of runs (CSV) against
    /// another, as the panel's plot draws it
    Fit(FitArgs),
}

/// Parses the command line; on bad flags prints clap's error on one line, with its
/// suggestions, and exits 2.
#[must_use]
pub fn parse() -> Cli {
    match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => {
            use clap::error::ErrorKind;
            if matches!(
                error.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                error.exit();
            }
            // The subcommand typed, if any, for the help pointer when clap names none.
            let typed = std::env::args().nth(1).unwrap_or_default();
            let known =
                <Cli as clap::CommandFactory>::command().get_subcommands().any(|c| c.get_name() == typed);
            let command = if known { format!("particle-lab {typed}") } else { "particle-lab".into() };
            eprintln!("particle-lab: {}", usage::one_line(&error.render().to_string(), &command));
            std::process::exit(USAGE_ERROR);
        }
    }
}

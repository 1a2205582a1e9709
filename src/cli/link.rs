//! `link`: prints the link that opens an experiment in the web lab (what File → Copy
//! link gives in the window); and the flags of `open`, which opens such a link in the
//! window (read by [`Launch::from_link`](crate::settings::Launch::from_link)).

use super::flags::{MAX_STEPS, SceneChoice};
use crate::ui::Lab;
use crate::ui::lab::Link;

/// `particle-lab link`.
#[derive(Debug, clap::Args)]
pub struct LinkArgs {
    /// The scene, its parameters and the solver: a shipped scene is named in the link,
    /// any other scene file is carried in it whole (packed, after `#`).
    #[command(flatten)]
    pub choice: SceneChoice,
    /// Physics steps the page runs at once before it pauses, as `simulate --steps N`.
    #[arg(long, value_name = "N")]
    pub steps: Option<u64>,
    /// How the page shows it: side (the 2D side view) or 3d; without it, 3d.
    #[arg(long, value_name = "side|3d")]
    pub view: Option<String>,
    /// The web page's address to put in front (for example
    /// https://example.org/particle-lab/); without it the link starts at its `?` or
    /// `#`, to follow the page's address.
    #[arg(long, value_name = "URL")]
    pub base: Option<String>,
}

/// `particle-lab open`.
#[derive(Debug, clap::Args)]
pub struct OpenArgs {
    /// The link, as copied from the window (File → Copy link), the page's address bar
    /// or `particle-lab link`: `https://…/?scene=…`, `?scene=…` or `#file=…`.
    #[arg(value_name = "LINK")]
    pub link: String,
}

/// The link `args` ask for, or a one-line reason it cannot be made.
pub fn link(args: &LinkArgs) -> Result<String, String> {
    let entry = args.choice.entry()?;
    let solver = args.choice.solver.settings_for(&entry)?;
    let mut lab = Lab::from_entry(&entry, &args.choice.set, solver)?;
    match args.view.as_deref() {
        None | Some("3d") => {}
        Some("side") => lab.set_side_view(true),
        Some(other) => return Err(format!("invalid value '{other}' for '--view': side or 3d")),
    }
    if let Some(steps) = args.steps {
        if steps > MAX_STEPS {
            return Err(format!("--steps {steps} is out of range; valid range: 0 to {MAX_STEPS}"));
        }
        lab.run_steps_recorded(steps);
    }
    let link = Link::of(&lab, args.steps.is_some())?;
    Ok(format!("{}{link}", args.base.as_deref().unwrap_or_default()))
}

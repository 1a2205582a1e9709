//! `render`: builds a lab, steps it and writes one off-screen frame as a PNG (or hands
//! `--frames` to [`super::record`]).

use super::flags::{MAX_STEPS, SceneChoice};
use super::{progress, record};
use crate::scenes::snapshot::Snapshot;

/// Arguments of `render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The scene, its parameters and the solver.
    #[command(flatten)]
    pub choice: SceneChoice,
    /// Start from a snapshot instead of a scene's beginning; `--steps` then runs on
    /// from the step it was saved at.
    #[arg(long, value_name = "FILE.json", conflicts_with_all = ["scene", "scene_file", "set", "solver", "substeps", "integrator"])]
    pub from: Option<std::path::PathBuf>,
    /// Physics steps to run before the frame, at the scene's own rate.
    #[arg(long, default_value_t = 120)]
    pub steps: u64,
    /// Image size in pixels.
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = parse_size)]
    pub size: [u32; 2],
    /// Draw the panel over the scene, as the window does.
    #[arg(long)]
    pub ui: bool,
    /// Draw the path each fast particle swept in the last step (View → Swept paths).
    #[arg(long)]
    pub swept: bool,
    /// Select this particle (by id) for the inspector and its arrows, as a click does.
    #[arg(long, value_name = "ID")]
    pub select: Option<u32>,
    /// View options to turn on, as the View menu does, comma-separated: forces
    /// (free-body arrows), all-vectors, contacts (contacts and link limits), tension
    /// (links coloured by tension), side (the 2D side view), follow (the camera follows
    /// the newest particle), no-labels, no-trails.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub view: Vec<String>,
    /// Run a second copy of the scene with one setting changed, drawn as magenta
    /// ghosts over it (Compare in the panel): integrator=NAME, solver=NAME, rate=HZ or
    /// a scene parameter, KEY=VALUE.
    #[arg(long, value_name = "KEY=VALUE")]
    pub compare: Option<String>,
    /// Where to write the frame, a .png. With --frames, by the extension: run.png
    /// writes a numbered sequence run-0001.png, run-0002.png, ...; run.gif an animated
    /// GIF; run.apng an animated PNG. Animations loop and show each frame for the
    /// simulated time between frames (a GIF to 1/100 s, at least 0.02 s).
    #[arg(long, value_name = "FILE")]
    pub out: std::path::PathBuf,
    /// Record N frames (1 to 10000) instead of one: the first after --steps, then one
    /// every --every steps.
    #[arg(long, value_name = "N")]
    pub frames: Option<u32>,
    /// Physics steps between recorded frames (1 to 100000) [default: the steps
    /// nearest 1/30 s].
    #[arg(long, value_name = "K")]
    pub every: Option<u64>,
}

/// Largest image side `render` accepts (px).
pub const MAX_IMAGE_SIDE: u32 = 8192;

fn parse_size(text: &str) -> Result<[u32; 2], String> {
    let bad = || {
        format!(
            "'{}' is not a size like 1280x720 (each side 1 to {MAX_IMAGE_SIDE})",
            crate::messages::quote(text)
        )
    };
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |s: &str| s.trim().parse::<u32>().ok().filter(|v| (1..=MAX_IMAGE_SIDE).contains(v));
    Ok([side(w).ok_or_else(bad)?, side(h).ok_or_else(bad)?])
}

/// Runs `render`: builds the scene, steps it, draws one frame and writes the PNG.
/// Input errors come back as `Err((2, message))`, GPU or file errors as `Err((1, message))`.
pub fn render(args: &RenderArgs) -> Result<String, (u8, String)> {
    if args.steps > MAX_STEPS {
        return Err((2, format!("--steps {} is out of range; valid range: 0 to {MAX_STEPS}", args.steps)));
    }
    let container =
        record::Container::of(&args.out, args.frames.is_some(), args.every.is_some()).map_err(|e| (2, e))?;
    let mut lab = match &args.from {
        Some(path) => {
            let snapshot = Snapshot::load(path).map_err(|e| (2, e))?;
            crate::ui::Lab::from_snapshot(&snapshot)
                .map_err(|e| (2, format!("{}: {e}", crate::messages::path(path))))?
        }
        None => {
            let entry = args.choice.entry().map_err(|e| (2, e))?;
            let solver = args.choice.solver.settings_for(&entry).map_err(|e| (2, e))?;
            crate::ui::Lab::from_entry(&entry, &args.choice.set, solver).map_err(|e| (2, e))?
        }
    };
    lab.view.swept |= args.swept;
    for option in &args.view {
        lab.set_view_option(option).map_err(|e| (2, e))?;
    }
    if let Some(text) = &args.compare {
        let change = crate::ui::compare::Change::parse(text, &lab.entry).map_err(|e| (2, e))?;
        lab.start_compare(change);
        if lab.compare.is_none() {
            return Err((2, std::mem::take(&mut lab.status)));
        }
    }
    if args.from.is_none() {
        // As `simulate` does: a launcher's round at step 0 (the copy compared fires too).
        lab.fire_at_start();
    }
    if let Some(id) = args.select {
        let id = crate::physics::ParticleId(id);
        if lab.scene.world().particles.index(id).is_none() {
            let count = lab.scene.world().particles.len();
            return Err((
                2,
                format!("--select {}: no particle with that id ({count} particles at the start)", id.0),
            ));
        }
        lab.select(Some(id));
    }
    if let Some(frames) = args.frames {
        let plan = record::Plan::new(container, frames, args.every, args.steps, lab.dt(), MAX_STEPS)
            .map_err(|e| (2, e))?;
        return record::record(&mut lab, &plan, &args.out, args.size, args.ui, args.steps);
    }
    // The GPU before the steps: a missing driver is said before a long run.
    let mut capture = crate::capture::FrameCapture::new().map_err(|e| (1, e))?;
    let mut progress = progress::Progress::new(args.steps, "steps", progress::Progress::for_terminal(true));
    record::step(&mut lab, args.steps, &mut progress, 0);
    drop(progress);
    let pixels = capture.render(&mut lab, args.size, args.ui).map_err(|e| (1, e))?;
    record::write_png(&args.out, args.size, &pixels).map_err(|e| (1, e))?;
    let (out, name) = (crate::messages::path(&args.out), lab.scene.info().name.to_string());
    // A run that blew up (or whose step failed) fails, as `simulate` does; the frame
    // shows where it stopped.
    if lab.paused {
        return Err((
            1,
            format!("wrote {out}, but {name} stopped at step {}: {}", lab.scene.world().steps(), lab.status),
        ));
    }
    Ok(format!("wrote {out} ({}x{}, {name} after {} steps)", args.size[0], args.size[1], args.steps))
}

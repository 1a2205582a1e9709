//! The command line: `scenes` lists the scenes, `simulate` runs one headless and prints
//! JSON Lines. Bad input gets one line on stderr and exit code 2, never a panic.

use std::io::{self, Write};

use clap::{Parser, Subcommand, ValueEnum};
use glam::Vec3;
use serde::Serialize;

use crate::physics::broad_phase::BUDGET_HIT_MESSAGE;
use crate::physics::inspect::{self, ConstraintMeter};
use crate::physics::{
    Integrator, LinkEnd, LinkState, ParticleId, SolverKind, SolverSettings, World, solver::SUBSTEP_RANGE,
};
use crate::scenes::snapshot::Snapshot;
use crate::scenes::{self, SCENES, Scene};

pub mod clock;
pub mod progress;
pub mod record;
pub mod setup;
pub mod usage;

/// Exit code for input the user can fix.
pub const USAGE_ERROR: i32 = 2;

/// particle-lab: a real-time particle physics lab.
#[derive(Debug, Parser)]
#[command(name = "particle-lab", version, about, long_about = None)]
pub struct Cli {
    /// What to do; without a command the window opens.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Scene to open the window on.
    #[arg(long, global = false)]
    pub scene: Option<String>,
    /// Scene file (TOML) to open the window on, instead of --scene; reloaded when it
    /// changes.
    #[arg(long, value_name = "PATH")]
    pub scene_file: Option<std::path::PathBuf>,
    /// Set a scene parameter, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Solver choice for the window.
    #[command(flatten)]
    pub solver: SolverArgs,
    /// Open the window with the default settings, without reading the saved ones
    /// (they are replaced on exit).
    #[arg(long)]
    pub fresh: bool,
    /// Open on a snapshot (File → Save snapshot, or `simulate --save`): its scene,
    /// parameters, solver and time step, at the step it was saved.
    #[arg(long, value_name = "FILE.json", conflicts_with_all = ["scene", "scene_file", "set", "solver", "substeps", "integrator"])]
    pub from: Option<std::path::PathBuf>,
}

/// The solver flags shared by the window, `simulate` and `render`.
#[derive(Debug, Clone, clap::Args)]
pub struct SolverArgs {
    /// Constraint solver: soft (substepped soft contacts with friction, the default) or
    /// paper (the paper's worst-first resolver, with Coulomb friction).
    #[arg(long, value_name = "NAME", default_value = "soft")]
    pub solver: String,
    /// Substeps per physics step for the soft solver, 1 to 64.
    #[arg(long, value_name = "N", default_value_t = 4)]
    pub substeps: u32,
    /// Integrator: explicit-euler, semi-implicit-euler (the paper's, the default),
    /// verlet or rk4.
    #[arg(long, value_name = "NAME", default_value = "semi-implicit-euler")]
    pub integrator: String,
}

impl SolverArgs {
    /// The settings these flags ask for, or a one-line reason they are refused.
    pub fn settings(&self) -> Result<SolverSettings, String> {
        let kind = SolverKind::parse(&self.solver)?;
        if !SUBSTEP_RANGE.contains(&self.substeps) {
            return Err(format!(
                "--substeps {} is out of range; valid range: {} to {}",
                self.substeps,
                SUBSTEP_RANGE.start(),
                SUBSTEP_RANGE.end()
            ));
        }
        let integrator = Integrator::parse(&self.integrator)?;
        Ok(SolverSettings { kind, substeps: self.substeps, integrator, ..SolverSettings::default() })
    }
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List every scene with its parameters.
    Scenes {
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Run a scene headless and print its state as JSON Lines.
    Simulate(SimulateArgs),
    /// Step a scene and write one off-screen frame to a PNG (needs no display).
    Render(RenderArgs),
}

/// Arguments of `render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// Scene name (see `particle-lab scenes`).
    #[arg(long)]
    pub scene: Option<String>,
    /// Scene file (TOML), instead of --scene.
    #[arg(long, value_name = "PATH")]
    pub scene_file: Option<std::path::PathBuf>,
    /// Start from a snapshot instead of a scene's beginning; `--steps` then runs on
    /// from the step it was saved at.
    #[arg(long, value_name = "FILE.json", conflicts_with_all = ["scene", "scene_file", "set", "solver", "substeps", "integrator"])]
    pub from: Option<std::path::PathBuf>,
    /// Set a scene parameter, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Solver choice.
    #[command(flatten)]
    pub solver: SolverArgs,
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
            let solver = args.solver.settings().map_err(|e| (2, e))?;
            let entry = scenes::file::choose(args.scene.as_deref(), args.scene_file.as_deref())
                .map_err(|e| (2, e))?;
            crate::ui::Lab::from_entry(entry, &args.set, solver).map_err(|e| (2, e))?
        }
    };
    lab.view.swept |= args.swept;
    for option in &args.view {
        lab.set_view_option(option).map_err(|e| (2, e))?;
    }
    if let Some(text) = &args.compare {
        let change = crate::ui::compare::Change::parse(text, lab.entry).map_err(|e| (2, e))?;
        lab.start_compare(change);
        if lab.compare.is_none() {
            return Err((2, std::mem::take(&mut lab.status)));
        }
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
    let (out, name) = (crate::messages::path(&args.out), lab.scene.info().name);
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

/// Output format of `scenes`.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Format {
    /// Human-readable table.
    Text,
    /// One JSON array.
    Json,
}

/// Output format of `simulate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StateFormat {
    /// JSON Lines: one object per printed step.
    Json,
    /// CSV with a header: one row per particle per printed step, with the step's
    /// energy budget on every row (for a spreadsheet).
    Csv,
}

/// Arguments of `simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// Scene name (see `particle-lab scenes`).
    #[arg(long)]
    pub scene: Option<String>,
    /// Scene file (TOML), instead of --scene.
    #[arg(long, value_name = "PATH")]
    pub scene_file: Option<std::path::PathBuf>,
    /// Continue from a snapshot (File → Save in the window, or `--save`): its scene,
    /// parameters, solver and time step, at the step it was saved.
    #[arg(long, value_name = "FILE.json", conflicts_with_all = ["scene", "scene_file", "set", "solver", "substeps", "integrator"])]
    pub from: Option<std::path::PathBuf>,
    /// Write a snapshot of the last state to FILE after the run.
    #[arg(long, value_name = "FILE.json")]
    pub save: Option<std::path::PathBuf>,
    /// Set a scene parameter, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Solver choice.
    #[command(flatten)]
    pub solver: SolverArgs,
    /// Physics steps to run [default: the scene's own].
    #[arg(long)]
    pub steps: Option<u64>,
    /// Time step in seconds [default: the scene's own].
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f32>,
    /// Print every K-th step (step 0 and the last step are always printed).
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = StateFormat::Json)]
    pub format: StateFormat,
    /// Add to each particle of the JSON its net force "f" (N) and the forces that make
    /// it, by name ("forces": weight, each force generator, damping, and what contacts
    /// and links did over the last step), as the window's inspector shows them
    #[arg(long)]
    pub forces: bool,
}

/// Most steps `simulate` accepts in one run.
pub const MAX_STEPS: u64 = 100_000_000;

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

/// Runs `scenes`.
/// The scenes `scenes` lists: the compiled ones, then the shipped scene files.
fn listed() -> impl Iterator<Item = &'static scenes::SceneEntry> {
    SCENES.iter().chain(scenes::file::shipped().iter().copied())
}

pub fn list_scenes(format: Format, out: &mut impl Write) -> io::Result<()> {
    match format {
        Format::Json => {
            let list: Vec<SceneJson> = listed()
                .map(|entry| {
                    let info = entry.info;
                    SceneJson {
                        name: info.name,
                        summary: info.summary,
                        dt: clock::Step::of(info.dt).map_or(f64::from(info.dt), clock::Step::seconds),
                        default_steps: info.default_steps,
                        params: info
                            .params
                            .iter()
                            .map(|p| ParamJson {
                                name: p.name,
                                unit: p.unit,
                                default: p.default,
                                min: p.min,
                                max: p.max,
                                help: p.help,
                            })
                            .collect(),
                        presets: info.presets.iter().map(|p| p.name).collect(),
                        actions: info.actions.iter().map(|a| a.label).collect(),
                    }
                })
                .collect();
            serde_json::to_writer(&mut *out, &list)?;
            writeln!(out)
        }
        Format::Text => {
            for entry in listed() {
                let info = entry.info;
                writeln!(out, "{} — {}", info.name, info.summary)?;
                writeln!(
                    out,
                    "  dt {} s ({:.0} Hz), {} steps by default",
                    clock::Step::of(info.dt).map_or(info.dt.to_string(), |step| step.to_string()),
                    1.0 / info.dt,
                    info.default_steps
                )?;
                for p in info.params {
                    let unit = if p.unit.is_empty() { String::new() } else { format!(" {}", p.unit) };
                    writeln!(
                        out,
                        "  {:<12} {:>9}{unit:<6} [{} .. {}]  {}",
                        p.name, p.default, p.min, p.max, p.help
                    )?;
                }
                if !info.presets.is_empty() {
                    let names: Vec<_> = info.presets.iter().map(|p| p.name).collect();
                    writeln!(out, "  presets: {}", names.join(", "))?;
                }
                writeln!(out)?;
            }
            Ok(())
        }
    }
}

#[derive(Serialize)]
struct SceneJson {
    name: &'static str,
    summary: &'static str,
    /// The step it stands for (1/240 s), not its f32.
    dt: f64,
    default_steps: u32,
    params: Vec<ParamJson>,
    presets: Vec<&'static str>,
    actions: Vec<&'static str>,
}

#[derive(Serialize)]
struct ParamJson {
    name: &'static str,
    unit: &'static str,
    default: f32,
    min: f32,
    max: f32,
    help: &'static str,
}

/// Validated settings of a `simulate` run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunPlan {
    /// Steps to run.
    pub steps: u64,
    /// Time step (s).
    pub dt: f32,
    /// Print every this many steps.
    pub every: u64,
    /// How to print them.
    pub format: StateFormat,
    /// Where to write a snapshot of the last state, if anywhere.
    pub save: Option<std::path::PathBuf>,
    /// Print each particle's forces (`--forces`).
    pub forces: bool,
    /// The time step the steps before this run were taken at, for a run from a
    /// snapshot (s): its printed times go on from the world's own.
    pub saved_dt: Option<f32>,
}

/// Builds the scene and checks the numbers of a `simulate` run.
pub fn prepare(args: &SimulateArgs) -> Result<(Box<dyn Scene>, RunPlan), String> {
    let (scene, saved_dt) = match &args.from {
        Some(path) => {
            let snapshot = Snapshot::load(path)?;
            let scene = snapshot.restore().map_err(|e| format!("{}: {e}", crate::messages::path(path)))?;
            (scene, Some(snapshot.dt))
        }
        None => {
            let solver = args.solver.settings()?;
            let entry = scenes::file::choose(args.scene.as_deref(), args.scene_file.as_deref())?;
            let mut scene = scenes::build_entry(entry, &args.set)?;
            scene.world_mut().set_solver(solver).map_err(|e| e.to_string())?;
            (scene, None)
        }
    };
    let info = scene.info();
    let dt = args.dt.or(saved_dt).unwrap_or(info.dt);
    if !(dt > 0.0 && dt <= 1.0) {
        return Err(format!("--dt {dt} is out of range; valid range: greater than 0 up to 1 second"));
    }
    let steps = args.steps.unwrap_or(u64::from(info.default_steps));
    if steps > MAX_STEPS {
        return Err(format!("--steps {steps} is out of range; valid range: 0 to {MAX_STEPS}"));
    }
    if args.every == 0 {
        return Err("--every 0 is out of range; valid range: 1 or more".into());
    }
    let save = args.save.clone();
    if args.forces && args.format == StateFormat::Csv {
        return Err("--forces adds fields to the JSON; it cannot be used with --format csv".into());
    }
    let forces = args.forces;
    Ok((scene, RunPlan { steps, dt, every: args.every, format: args.format, save, forces, saved_dt }))
}

/// Header of `simulate --format csv`.
pub const CSV_HEADER: &str = "step,t,id,x,y,z,vx,vy,vz,r,m,kinetic,potential,dissipated,work,removed,error";

/// Runs `simulate`, writing one JSON object (or CSV rows) per printed step.
pub fn simulate(
    scene: &mut dyn Scene,
    plan: RunPlan,
    out: &mut impl Write,
) -> io::Result<Result<(), String>> {
    let mut links = Vec::new();
    let mut line = Vec::with_capacity(4096);
    // Times as the step stands for them (0.0208333 s), not as f32 steps add up.
    let clock = clock::Step::of(plan.dt);
    let start_steps = scene.world().steps();
    // A snapshot whose every step was one rate counts its time from step 0, so its
    // lines read as an unbroken run's do (3.3333333, not the f32 sum 3.333334), at
    // that rate or going on at another.
    let origin = clock::Origin::of(plan.saved_dt.unwrap_or(plan.dt), scene.world().time(), start_steps);
    let mut progress = progress::Progress::new(plan.steps, "steps", progress::Progress::for_terminal(false));
    if plan.format == StateFormat::Csv {
        writeln!(out, "{CSV_HEADER}")?;
    }
    // Step numbers go on from a snapshot's.
    let first = scene.world().steps();
    // With --forces: what contacts and links did to each particle over the last step.
    let (mut meter, mut constraint) = (ConstraintMeter::default(), Vec::new());
    // The pair budget's warning is said once a run, at the first step that hits it.
    let mut budget_told = false;
    for step in 0..=plan.steps {
        if step > 0 {
            if plan.forces {
                let world = scene.world();
                meter.before_step(world, world.particles.ids().iter().copied());
            }
            match scene.step(plan.dt) {
                Ok(report) if report.pair_budget_hit && !budget_told => {
                    budget_told = true;
                    eprintln!("particle-lab: warning: at step {}, {BUDGET_HIT_MESSAGE}", first + step);
                }
                Ok(_) => {}
                Err(error) => return Ok(Err(error.to_string())),
            }
            if plan.forces {
                constraint.clear();
                constraint.extend(meter.after_step(scene.world(), plan.dt));
            }
            progress.set(step);
            if !scene.world().is_finite() {
                out.flush()?;
                return Ok(Err(format!(
                    "the simulation blew up at step {step} (positions or velocities are no longer \
                     finite); try a smaller --dt, or a softer spring"
                )));
            }
        }
        if step == 0 || step == plan.steps || step % plan.every == 0 {
            line.clear();
            let t = clock.map_or(clock::to_f32_digits(scene.world().time()), |clock| {
                clock.time_from(origin, scene.world().steps() - start_steps)
            });
            match plan.format {
                StateFormat::Json => {
                    let forces = plan.forces.then_some(constraint.as_slice());
                    write_state(&mut line, first + step, t, scene.world(), &mut links, forces)?;
                    line.push(b'\n');
                }
                StateFormat::Csv => write_csv_rows(&mut line, first + step, t, scene.world())?,
            }
            out.write_all(&line)?;
            // Each printed step reaches a pipe as soon as it is computed.
            out.flush()?;
        }
    }
    out.flush()?;
    if let Some(path) = &plan.save {
        let saved = Snapshot::of(scene, plan.dt).and_then(|snapshot| snapshot.save(path));
        if let Err(error) = saved {
            return Ok(Err(error));
        }
    }
    Ok(Ok(()))
}

#[derive(Serialize)]
struct ParticleJson {
    id: u32,
    p: [f32; 3],
    v: [f32; 3],
    /// Radius (m).
    r: f32,
    /// Mass (kg); `null` for an immovable particle.
    m: Option<f32>,
    /// With `--forces`: the net force (N), the sum of `forces`.
    #[serde(skip_serializing_if = "Option::is_none")]
    f: Option<[f32; 3]>,
    /// With `--forces`: each force by name (N); a second of the same name gets " 2".
    #[serde(skip_serializing_if = "Option::is_none")]
    forces: Option<serde_json::Map<String, serde_json::Value>>,
}

#[derive(Serialize)]
struct LinkJson {
    kind: &'static str,
    a: u32,
    b: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    anchor: Option<[f32; 3]>,
    rest: f32,
    length: f32,
    tension: f32,
}

#[derive(Serialize)]
struct EnergyJson {
    kinetic: f32,
    potential: f32,
    /// Taken out since step 0 (damping, drag, contacts and links), cumulative (J).
    dissipated: f32,
    /// Put in from outside the steps since step 0, cumulative (J).
    work: f32,
    /// Carried out by particles removed since step 0, cumulative (J).
    removed: f32,
    /// kinetic + potential + dissipated + removed - work, minus its value at step 0: the
    /// integrator's error (J).
    error: f32,
}

#[derive(Serialize)]
struct StateJson {
    step: u64,
    t: f64,
    /// [`World::state_hash`] as 16 hex digits: equal hashes at a step, equal runs.
    hash: String,
    particles: Vec<ParticleJson>,
    links: Vec<LinkJson>,
    contacts: usize,
    resolver: ResolverJson,
    energy: EnergyJson,
}

#[derive(Serialize)]
struct ResolverJson {
    iterations: usize,
    max_penetration: f32,
}

/// A vector as printed: `+ 0` turns a component's negative zero (a velocity that has
/// never moved along an axis, times a negative factor) into 0, so no figure reads "-0".
fn figure(v: Vec3) -> Vec3 {
    v + Vec3::ZERO
}

/// One CSV row per particle (by id), each with the step's energy budget; `t` is the
/// time printed (s).
fn write_csv_rows(out: &mut Vec<u8>, step: u64, t: f64, world: &World) -> io::Result<()> {
    let p = &world.particles;
    let e = world.energy();
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by_key(|&i| p.ids()[i].0);
    for i in order {
        let (x, v) = (figure(p.positions()[i]), figure(p.velocities()[i]));
        let mass = if p.inverse_masses()[i] > 0.0 { p.mass(i).to_string() } else { String::new() };
        writeln!(
            out,
            "{step},{t},{},{},{},{},{},{},{},{},{mass},{},{},{},{},{},{}",
            p.ids()[i].0,
            x.x,
            x.y,
            x.z,
            v.x,
            v.y,
            v.z,
            p.radii()[i],
            e.kinetic,
            e.potential,
            e.dissipated,
            e.work,
            e.removed,
            e.error
        )?;
    }
    Ok(())
}

/// The state as one JSON object; `t` is the time printed (s). With `forces` (what
/// contacts and links did over the last step, by particle), each particle gets its
/// forces and their sum.
fn write_state(
    out: &mut Vec<u8>,
    step: u64,
    t: f64,
    world: &World,
    links: &mut Vec<LinkState>,
    forces: Option<&[(ParticleId, Vec3)]>,
) -> io::Result<()> {
    let p = &world.particles;
    let measured: Option<std::collections::HashMap<ParticleId, Vec3>> =
        forces.map(|list| list.iter().copied().collect());
    // Which particles a contact or link acts on, found in one pass, not one per particle.
    let mut constrained = Vec::new();
    if forces.is_some() {
        world.constrained_into(&mut constrained);
    }
    let mut particles: Vec<ParticleJson> = (0..p.len())
        .map(|i| {
            let id = p.ids()[i];
            let listed = measured
                .as_ref()
                .map(|measured| inspect::forces_given(world, id, measured.get(&id).copied(), constrained[i]));
            let f = listed.as_ref().map(|list| figure(list.iter().map(|(_, f)| *f).sum::<Vec3>()).to_array());
            let forces = listed.map(|list| {
                let mut named = serde_json::Map::new();
                for (name, force) in list {
                    let mut key = name.to_string();
                    let mut n = 1;
                    while named.contains_key(&key) {
                        n += 1;
                        key = format!("{name} {n}");
                    }
                    named.insert(key, serde_json::json!(figure(force).to_array()));
                }
                named
            });
            ParticleJson {
                id: id.0,
                p: figure(p.position[i]).to_array(),
                v: figure(p.velocity[i]).to_array(),
                r: p.radius[i],
                m: (p.inverse_mass[i] > 0.0).then(|| p.mass(i)),
                f,
                forces,
            }
        })
        .collect();
    particles.sort_by_key(|particle| particle.id);
    world.links_into(links);
    let links = links
        .iter()
        .map(|link| {
            let (b, anchor) = match link.spec.b {
                LinkEnd::Particle(id) => (Some(id.0), None),
                LinkEnd::Anchor(point) => (None, Some(point.to_array())),
            };
            LinkJson {
                kind: link.spec.kind.name(),
                a: link.spec.a.0,
                b,
                anchor,
                rest: link.spec.rest,
                length: link.length,
                tension: link.tension,
            }
        })
        .collect();
    let energy = world.energy();
    let state = StateJson {
        step,
        t,
        hash: crate::scenes::snapshot::hash_text(world.state_hash()),
        particles,
        links,
        contacts: world.contact_count(),
        resolver: ResolverJson {
            iterations: world.last_report().iterations(),
            max_penetration: world.last_report().max_penetration,
        },
        energy: EnergyJson {
            kinetic: energy.kinetic,
            potential: energy.potential,
            dissipated: energy.dissipated,
            work: energy.work,
            removed: energy.removed,
            error: energy.error,
        },
    };
    serde_json::to_writer(out, &state).map_err(io::Error::other)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::physics::ParticleDesc;

    #[test]
    fn particles_carry_radius_and_mass_and_immovable_ones_null() {
        let mut world = World::new();
        let desc = ParticleDesc { mass: 2.5, radius: 0.3, ..ParticleDesc::default() };
        world.add_particle(desc).unwrap();
        world.add_particle(ParticleDesc { immovable: true, position: Vec3::X, ..desc }).unwrap();
        let mut line = Vec::new();
        write_state(&mut line, 0, 0.0, &world, &mut Vec::new(), None).unwrap();
        let state: serde_json::Value = serde_json::from_slice(&line).unwrap();
        let particles = state["particles"].as_array().unwrap();
        assert_eq!(particles[0]["m"].as_f64(), Some(2.5));
        assert!((particles[0]["r"].as_f64().unwrap() - 0.3).abs() < 1e-6, "{}", particles[0]);
        assert!(particles[1]["m"].is_null(), "{}", particles[1]);
    }
}

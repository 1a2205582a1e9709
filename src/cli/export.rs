//! `export`: prints a scene as a scene file (what File → Save scene as… writes), with
//! the parameters `--set` gives as its defaults; a scene built into the program, or
//! the moment a snapshot holds, as plain particles and links (what the builder's
//! "Edit a copy" takes).

use crate::scenes::sketch::Sketch;
use crate::scenes::snapshot::Snapshot;
use crate::scenes::{self, SceneEntry, file};

/// `particle-lab export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// Scene name (see `particle-lab scenes`).
    #[arg(long)]
    pub scene: Option<String>,
    /// Scene file (TOML), instead of --scene.
    #[arg(long, value_name = "PATH")]
    pub scene_file: Option<std::path::PathBuf>,
    /// Set a scene parameter, KEY=VALUE (repeatable): the written file has it as the
    /// parameter's default.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// The moment a snapshot holds, as a new experiment: its particles where they are,
    /// moving as they move, with their links (instead of --scene / --scene-file).
    #[arg(long, value_name = "FILE.json", conflicts_with_all = ["scene", "scene_file", "set"])]
    pub from: Option<std::path::PathBuf>,
    /// Write the file here (replaced whole or not at all) instead of printing it.
    #[arg(long, value_name = "FILE.toml")]
    pub out: Option<std::path::PathBuf>,
}

/// A written scene file, and what the scene had that the file leaves out.
#[derive(Debug)]
pub struct Exported {
    /// The file's text.
    pub text: String,
    /// What a scene file cannot hold and was left out (a scene's own rules, a plate,
    /// drag): empty when the file holds all of it.
    pub left_out: Vec<String>,
}

/// The scene file `args` ask for, or a one-line reason it cannot be made.
pub fn export(args: &ExportArgs) -> Result<Exported, String> {
    if let Some(path) = &args.from {
        let snapshot = Snapshot::load(path)?;
        let (entry, scene) = snapshot.restore_with_entry()?;
        let name = format!("{} at step {}", entry.info().name, scene.world().steps());
        return Ok(as_sketch(&entry, scene.as_ref(), &name, snapshot.dt));
    }
    let entry = file::choose(args.scene.as_deref(), args.scene_file.as_deref())?;
    let mut values = scenes::ParamValues::defaults(&entry.info().params);
    for assignment in &args.set {
        values.assign(assignment).map_err(|e| e.to_string())?;
    }
    // The values must build (a count a file's rows cannot take is refused here, as
    // `simulate` would refuse it).
    let scene = scenes::create_entry(&entry, values.clone())?;
    if file::writable(&entry).is_ok() {
        return Ok(Exported { text: file::written(&entry, &values)?, left_out: Vec::new() });
    }
    Ok(as_sketch(&entry, scene.as_ref(), &format!("{} (copy)", entry.info().name), entry.info().dt))
}

/// A scene as a sketch: its particles, links, forces, surroundings and launcher. A
/// scene built into the program leaves behind what only its code does (see
/// [`own_rules`]).
fn as_sketch(entry: &SceneEntry, scene: &dyn scenes::Scene, name: &str, dt: f32) -> Exported {
    let (mut sketch, mut left_out) = Sketch::from_scene(scene, name);
    sketch.dt = Some(dt);
    if file::definition(entry).is_none() {
        left_out.insert(0, own_rules(&entry.info().name));
    }
    Exported { text: sketch.text(), left_out }
}

/// What a scene built into the program does that its copy does not: its sliders
/// (the copy keeps the values they had, and g, and a launcher's speed and angle),
/// presets and read-outs, and any rule of its own.
fn own_rules(name: &str) -> String {
    let rule = match name {
        "bridge" => ", and its movable load (the load's mass stays where it is)",
        "hourglass" => ", among them the flow gauges beside Beverloo's law",
        "springForces" => ", among them the bob's stopwatch and exact twin",
        _ => "",
    };
    format!("the sliders, presets and read-outs of '{name}'{rule}")
}

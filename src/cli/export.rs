//! `export`: prints a scene as a scene file (what File → Save scene as… writes), with
//! the parameters `--set` gives as its defaults.

use crate::scenes::{self, file};

/// `particle-lab export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// Scene name (see `particle-lab scenes`): one made from a scene file, such as the
    /// shipped chain.
    #[arg(long)]
    pub scene: Option<String>,
    /// Scene file (TOML), instead of --scene.
    #[arg(long, value_name = "PATH")]
    pub scene_file: Option<std::path::PathBuf>,
    /// Set a scene parameter, KEY=VALUE (repeatable): the written file has it as the
    /// parameter's default.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Write the file here (replaced whole or not at all) instead of printing it.
    #[arg(long, value_name = "FILE.toml")]
    pub out: Option<std::path::PathBuf>,
}

/// The scene file `args` ask for, or a one-line reason it cannot be made.
pub fn export(args: &ExportArgs) -> Result<String, String> {
    let entry = file::choose(args.scene.as_deref(), args.scene_file.as_deref())?;
    file::writable(&entry)?;
    let mut values = scenes::ParamValues::defaults(&entry.info().params);
    for assignment in &args.set {
        values.assign(assignment).map_err(|e| e.to_string())?;
    }
    // The values must build (a count a file's rows cannot take is refused here, as
    // `simulate` would refuse it).
    if let scenes::SceneEntry::File(definition) = &entry {
        definition.create(values.clone()).map_err(|e| e.to_string())?;
    }
    file::written(&entry, &values)
}

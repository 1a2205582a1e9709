//! The flags more than one command takes: the scene and its settings, the solver's,
//! and the bound on steps.

use crate::physics::{Integrator, SolverChoice, SolverKind, SolverSettings, solver::SUBSTEP_RANGE};
use crate::scenes::{self, SceneEntry};

/// The flags that choose a scene and its settings, shared by `simulate` and `render`.
#[derive(Debug, Clone, clap::Args)]
pub struct SceneChoice {
    /// Scene name (see `particle-lab scenes`).
    #[arg(long)]
    pub scene: Option<String>,
    /// Scene file (TOML), instead of --scene.
    #[arg(long, value_name = "PATH")]
    pub scene_file: Option<std::path::PathBuf>,
    /// Set a scene parameter, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Solver choice.
    #[command(flatten)]
    pub solver: SolverArgs,
}

impl SceneChoice {
    /// The scene these flags name (a registered scene, or a scene file read now), or a
    /// one-line reason.
    pub fn entry(&self) -> Result<SceneEntry, String> {
        scenes::file::choose(self.scene.as_deref(), self.scene_file.as_deref())
    }
}

/// The solver flags shared by the window, `simulate`, `render` and `link`. Each flag
/// not typed leaves the scene file's own choice (`[scene] solver`, `substeps`,
/// `integrator`), else the default.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct SolverArgs {
    /// Constraint solver: soft (substepped soft contacts with friction) or paper (the
    /// paper's worst-first resolver, with Coulomb friction). Default: the scene file's,
    /// else soft.
    #[arg(long, value_name = "NAME")]
    pub solver: Option<String>,
    /// Substeps per physics step for the soft solver, 1 to 64. Default: the scene
    /// file's, else 4.
    #[arg(long, value_name = "N")]
    pub substeps: Option<u32>,
    /// Integrator: explicit-euler, semi-implicit-euler (the paper's), verlet or rk4.
    /// Default: the scene file's, else semi-implicit-euler.
    #[arg(long, value_name = "NAME")]
    pub integrator: Option<String>,
}

impl SolverArgs {
    /// What these flags name, or a one-line reason they are refused.
    pub fn choice(&self) -> Result<SolverChoice, String> {
        let kind = self.solver.as_deref().map(SolverKind::parse).transpose()?;
        if let Some(substeps) = self.substeps
            && !SUBSTEP_RANGE.contains(&substeps)
        {
            return Err(format!(
                "--substeps {substeps} is out of range; valid range: {} to {}",
                SUBSTEP_RANGE.start(),
                SUBSTEP_RANGE.end()
            ));
        }
        let integrator = self.integrator.as_deref().map(Integrator::parse).transpose()?;
        Ok(SolverChoice { kind, substeps: self.substeps, integrator })
    }

    /// The settings for `entry`: these flags over the scene file's own choice over the
    /// defaults.
    pub fn settings_for(&self, entry: &SceneEntry) -> Result<SolverSettings, String> {
        Ok(self.choice()?.over(scenes::file::own_solver(entry).over(SolverSettings::default())))
    }
}

/// Most steps `simulate` accepts in one run (a link's `steps` has the same bound).
pub use crate::ui::lab::MAX_STEPS;

//! The flags more than one command takes: the scene and its settings, the solver's,
//! and the bound on steps.

use crate::physics::{Integrator, SolverKind, SolverSettings, solver::SUBSTEP_RANGE};
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

/// Most steps `simulate` accepts in one run (a link's `steps` has the same bound).
pub use crate::ui::lab::MAX_STEPS;

//! The solvers: what turns a step's contacts and links into motion.
//!
//! - [`settings`]: which solver, which integrator, and their settings, validated;
//! - [`report`]: what a step reports and how long its stages took;
//! - [`paper`]: the paper's (Cyclone's) pipeline and its one-at-a-time resolver;
//! - [`soft`]: the substepped soft-constraint solver, one file per stage.
//!
//! Imports everything below it (particles, links, contacts, forces, collision, the
//! integrators, the energy sums); only the world and the snapshot codec import it.

pub mod paper;
pub mod report;
pub mod settings;
pub mod soft;

pub use settings::{LinkSolver, SUBSTEP_RANGE, Softness, SolverChoice, SolverKind, SolverSettings};

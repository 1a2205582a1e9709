//! Compare: a second copy of the running scene with one setting changed (integrator,
//! solver, physics rate or any parameter), stepped beside the first and drawn as
//! translucent ghosts over it, with its energy and its distance from the exact answer
//! on the same plots. Like Solver2D and PEEL side by side, for students.

use std::collections::VecDeque;

use crate::messages::quote;
use crate::physics::{Integrator, LinkState, SolverKind, SolverSettings};
use crate::scenes::snapshot::Snapshot;
use crate::scenes::{Scene, SceneEntry};

use super::lab::limits::{HISTORY, PHYSICS_RATE_RANGE};
use super::lab::records::EnergySample;

/// The one setting the copy has changed.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// Another integrator.
    Integrator(Integrator),
    /// Another constraint solver.
    Solver(SolverKind),
    /// Another physics rate (Hz).
    Rate(f32),
    /// Another value of a scene parameter.
    Param(String, f32),
}

impl Change {
    /// Parses `KEY=VALUE`: `integrator=NAME`, `solver=NAME`, `rate=HZ` or a parameter of
    /// `entry`'s scene; a refusal is one line naming what is accepted.
    pub fn parse(text: &str, entry: &SceneEntry) -> Result<Self, String> {
        let Some((key, value)) = text.split_once('=') else {
            return Err(format!(
                "compare '{}': expected KEY=VALUE, e.g. integrator=rk4 or rate=60",
                quote(text)
            ));
        };
        let (key, value) = (key.trim(), value.trim());
        let number = || {
            value
                .parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("compare {}: '{}' is not a number", quote(key), quote(value)))
        };
        match key {
            "integrator" => Ok(Self::Integrator(Integrator::parse(value)?)),
            "solver" => Ok(Self::Solver(SolverKind::parse(value)?)),
            "rate" => {
                let rate = number()?;
                if PHYSICS_RATE_RANGE.contains(&rate) {
                    Ok(Self::Rate(rate))
                } else {
                    let range = PHYSICS_RATE_RANGE;
                    Err(format!(
                        "compare rate {rate} Hz is out of range; valid range: {} to {} Hz",
                        range.start(),
                        range.end()
                    ))
                }
            }
            name => {
                let Some(param) = entry.info().params.iter().find(|p| p.name == name) else {
                    let names: Vec<&str> = entry.info().params.iter().map(|p| &*p.name).collect();
                    return Err(format!(
                        "compare: unknown setting '{}'; valid: integrator, solver, rate, {}",
                        quote(name),
                        names.join(", ")
                    ));
                };
                let value = number()?;
                if !(param.min..=param.max).contains(&value) {
                    return Err(format!(
                        "compare {name} = {value} is out of range; valid range: {} to {}",
                        param.min, param.max
                    ));
                }
                Ok(Self::Param(param.name.to_string(), value))
            }
        }
    }

    /// What the copy changed, for the panel and the legend: "integrator = rk4".
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            Self::Integrator(integrator) => format!("integrator = {}", integrator.name()),
            Self::Solver(kind) => format!("solver = {}", kind.name()),
            Self::Rate(rate) => format!("rate = {rate} Hz"),
            Self::Param(name, value) => format!("{name} = {value}"),
        }
    }
}

/// The copy and its history.
pub struct Compare {
    /// The copy of the scene.
    pub scene: Box<dyn Scene>,
    /// What differs from the original.
    pub change: Change,
    /// Its physics step (s).
    pub dt: f32,
    /// Its energy and error over time, as the original's.
    pub energy: VecDeque<EnergySample>,
    /// It stopped: a value stopped being finite, or a step was refused. Says why.
    pub stopped: Option<String>,
    /// The copy's link states, reused by the once-a-frame finiteness check.
    links: Vec<LinkState>,
}

impl Compare {
    /// A fresh copy of `entry`'s scene with the original's parameters, solver and time
    /// step, and then `change` applied.
    pub fn new(
        entry: &SceneEntry,
        params: crate::scenes::ParamValues,
        solver: SolverSettings,
        dt: f32,
        change: Change,
    ) -> Result<Self, String> {
        let mut scene = entry.create(params);
        let mut solver = solver;
        let mut dt = dt;
        match &change {
            Change::Integrator(integrator) => solver.integrator = *integrator,
            Change::Solver(kind) => solver.kind = *kind,
            Change::Rate(rate) => dt = 1.0 / rate,
            Change::Param(name, value) => scene.set_param(name, *value).map_err(|e| e.to_string())?,
        }
        scene.world_mut().set_solver(solver).map_err(|e| e.to_string())?;
        let mut compare =
            Self { scene, change, dt, energy: VecDeque::new(), stopped: None, links: Vec::new() };
        compare.record();
        Ok(compare)
    }

    /// A copy that starts from a snapshot of the running scene (taken at time step
    /// `dt`) instead of from the beginning, then has `change` applied: what happens if
    /// the integrator changed now. A parameter the scene cannot change in flight
    /// rebuilds the copy from the beginning, as it would the original.
    pub fn branch(snapshot: &Snapshot, change: Change) -> Result<Self, String> {
        let mut scene = snapshot.restore()?;
        let mut solver = *scene.world().solver();
        let mut dt = snapshot.dt;
        match &change {
            Change::Integrator(integrator) => solver.integrator = *integrator,
            Change::Solver(kind) => solver.kind = *kind,
            Change::Rate(rate) => dt = 1.0 / rate,
            Change::Param(name, value) => scene.set_param(name, *value).map_err(|e| e.to_string())?,
        }
        if solver != *scene.world().solver() {
            scene.world_mut().set_solver(solver).map_err(|e| e.to_string())?;
        }
        let mut compare =
            Self { scene, change, dt, energy: VecDeque::new(), stopped: None, links: Vec::new() };
        compare.record();
        Ok(compare)
    }

    /// Puts the copy's solver change (if it is one) into `solver`.
    pub fn apply_to(&self, solver: &mut SolverSettings) {
        match self.change {
            Change::Integrator(integrator) => solver.integrator = integrator,
            Change::Solver(kind) => solver.kind = kind,
            Change::Rate(_) | Change::Param(..) => {}
        }
    }

    /// Steps the copy until it has caught up with the original's time `t` (s), to
    /// within half its own step.
    pub fn catch_up(&mut self, t: f64) {
        while self.stopped.is_none() && self.scene.world().time() + 0.5 * f64::from(self.dt) < t {
            if let Err(error) = self.scene.step(self.dt) {
                self.stopped = Some(error.to_string());
            } else if !self.scene.world().is_finite() {
                self.stopped = Some("the copy blew up (a value stopped being finite)".into());
            }
        }
        // Every other figure it shows (its energies), once a frame.
        if self.stopped.is_none()
            && let Some(what) = self.scene.world().first_non_finite(&mut self.links)
        {
            self.stopped = Some(format!("the copy blew up ({what} stopped being finite)"));
        }
        self.record();
    }

    fn record(&mut self) {
        let sample = EnergySample::of(self.scene.as_ref());
        if self.energy.back().is_some_and(|last| last.t == sample.t) {
            return;
        }
        if self.energy.len() == HISTORY {
            self.energy.pop_front();
        }
        self.energy.push_back(sample);
    }
}

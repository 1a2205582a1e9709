//! The lab itself: the running scene and the state around it (run state, solver,
//! camera, trails, history, selection, drag), built from a scene entry; switching
//! scenes, resetting, parameters, the solver and the Compare copy. The other rooms
//! of `lab/` add the clock, dragging, the camera, bars, the tape and snapshots.

use std::collections::VecDeque;
use web_time::Instant;

use glam::Vec3;

use super::limits::{FRAMING_ASPECT, HISTORY, MSAA_LIMIT, PHYSICS_BUDGET, READOUT_INTERVAL};
use super::records::{EnergySample, Grab, Joined, Requests, Stats};
use super::watch::Watch;
use crate::physics::inspect::ConstraintMeter;
use crate::physics::{LinkState, ParticleId, SolverKind, SolverSettings};
use crate::render::{OrbitCamera, Trails, ViewOptions};
use crate::scenes::snapshot::Snapshot;
use crate::scenes::{self, Scene, SceneAction, SceneEntry};
use crate::ui::compare::{Change, Compare};

/// Everything the panel shows and edits.
pub struct Lab {
    /// The running scene.
    pub scene: Box<dyn Scene>,
    /// Its registry entry (for a scene file, it keeps the file while it is the lab's).
    pub entry: SceneEntry,
    /// Physics stopped?
    pub paused: bool,
    /// Simulated seconds per real second.
    pub time_scale: f32,
    /// Physics steps per simulated second (Hz).
    pub physics_rate: f32,
    /// The solver every scene built here uses; kept across resets and scene changes.
    pub(super) solver: SolverSettings,
    pub(super) accumulator: f64,
    /// View toggles.
    pub view: ViewOptions,
    /// The camera.
    pub camera: OrbitCamera,
    /// Trails behind moving particles.
    pub trails: Trails,
    /// Timing figures.
    pub stats: Stats,
    /// Energy over time, for the plot.
    pub energy: VecDeque<EnergySample>,
    /// A message for the status line, e.g. where a screenshot went.
    pub status: String,
    /// A second copy of the scene with one setting changed, run beside it.
    pub compare: Option<Compare>,
    /// What the copy changes; kept so a reset rebuilds it.
    pub(super) compare_change: Option<Change>,
    /// The 2D side view: an orthographic camera looking along -z.
    pub side_view: bool,
    /// The camera follows the selected particle, or else the newest one (the round
    /// just fired).
    pub follow: bool,
    /// The energy bars show the selected particle instead of the whole scene.
    pub bars_for_selected: bool,
    /// The particle under the pointer.
    pub hovered: Option<ParticleId>,
    /// The particle being dragged.
    pub grab: Option<Grab>,
    /// Buffers for the mass a drag pulls along.
    pub(super) joined: Joined,
    /// The particle the inspector shows (clicked or dragged last).
    pub selected: Option<ParticleId>,
    /// Width over height of the 3D view (the window less the panel), for framing.
    pub view_aspect: f32,
    /// The user has orbited, panned or zoomed since the scene was last framed: a
    /// change of the view's shape then leaves the camera alone.
    pub camera_moved: bool,
    /// The tape measure: on, clicks place its ends instead of selecting.
    pub tape: bool,
    /// The tape's ends placed so far (0 to 2), in metres.
    pub tape_points: Vec<Vec3>,
    /// What contacts and links did to the selected particle over the last step (N),
    /// once a step has been measured since it was selected.
    pub constraint_force: Option<Vec3>,
    /// Measures [`Self::constraint_force`] across a step.
    pub(super) constraint_meter: ConstraintMeter,
    /// Requests for the window.
    pub requests: Requests,
    /// The open scene file, watched for changes (hot reload).
    pub scene_file: Option<Watch>,
    pub(super) last_frame: Option<Instant>,
    /// The scene's read-outs as last computed, and when, at which step and time step.
    pub(super) readouts: Vec<crate::scenes::Readout>,
    pub(super) readouts_taken: Option<(Instant, u64, f32)>,
    /// The scene has more than [`MSAA_LIMIT`] particles.
    pub(super) crowded: bool,
    /// MSAA was turned off because the scene became crowded.
    pub(super) msaa_dropped: bool,
    /// A physics rate and the time step it was set from (Hz, s): while the rate is
    /// that one, steps take exactly that time step, not `1 / rate` rounded twice, so
    /// the window steps with the bits `simulate` and a snapshot use.
    pub(super) rate_origin: (f32, f32),
    /// Where File → Save and Load snapshot write and read.
    pub snapshot_path: String,
    /// The state F5 saved, which F9 goes back to.
    pub(super) quick_save: Option<Snapshot>,
    /// The simulated time since which every movable particle (and the Compare copy's)
    /// has been asleep, as last recorded; none while something moves (see `Lab::at_rest`).
    pub(super) still_since: Option<f64>,
    /// The links' states, reused by the once-a-frame check that every figure shown is
    /// finite (`World::first_non_finite`).
    pub(super) finite_scratch: Vec<LinkState>,
    /// Wall-clock time a frame's physics may take ([`PHYSICS_BUDGET`]); `None` (in
    /// tests of the clock's arithmetic) for no limit.
    pub(super) physics_budget: Option<std::time::Duration>,
    /// The builder, while it is open.
    pub editor: Option<super::builder_state::Editor>,
}

impl Lab {
    /// A lab on `name` with `KEY=VALUE` settings, validated like `simulate`'s.
    pub fn new(name: &str, assignments: &[String]) -> Result<Self, String> {
        Self::with_solver(name, assignments, SolverSettings::default())
    }

    /// A lab on `name` with `KEY=VALUE` settings and the given solver.
    pub fn with_solver(name: &str, assignments: &[String], solver: SolverSettings) -> Result<Self, String> {
        Self::from_entry(scenes::find(name)?, assignments, solver)
    }

    /// A lab on a registered or loaded scene (a scene file) with `KEY=VALUE` settings
    /// and the given solver.
    pub fn from_entry(
        entry: &SceneEntry,
        assignments: &[String],
        solver: SolverSettings,
    ) -> Result<Self, String> {
        let mut scene = scenes::build_entry(entry, assignments)?;
        scene.world_mut().set_solver(solver).map_err(|e| e.to_string())?;
        let mut lab = Self {
            solver,
            camera: OrbitCamera::framing(scene.as_ref()),
            physics_rate: 1.0 / entry.info().dt,
            scene,
            entry: entry.clone(),
            paused: false,
            time_scale: 1.0,
            accumulator: 0.0,
            view: ViewOptions::default(),
            trails: Trails::default(),
            stats: Stats::default(),
            energy: VecDeque::with_capacity(HISTORY),
            status: String::new(),
            bars_for_selected: true,
            side_view: false,
            follow: false,
            compare: None,
            compare_change: None,
            hovered: None,
            grab: None,
            joined: Joined::default(),
            selected: None,
            constraint_force: None,
            constraint_meter: ConstraintMeter::default(),
            view_aspect: FRAMING_ASPECT,
            camera_moved: false,
            tape: false,
            tape_points: Vec::new(),
            requests: Requests::default(),
            scene_file: None,
            last_frame: None,
            readouts: Vec::new(),
            readouts_taken: None,
            crowded: false,
            msaa_dropped: false,
            rate_origin: (1.0 / entry.info().dt, entry.info().dt),
            snapshot_path: "snapshot.json".into(),
            quick_save: None,
            still_since: None,
            finite_scratch: Vec::new(),
            editor: None,
            physics_budget: Some(PHYSICS_BUDGET),
        };
        lab.apply_scene_view();
        lab.frame_scene();
        lab.follow_crowd();
        lab.record();
        Ok(lab)
    }

    /// The physics time step (s).
    #[must_use]
    pub fn dt(&self) -> f32 {
        let (rate, dt) = self.rate_origin;
        if self.physics_rate == rate { dt } else { 1.0 / self.physics_rate }
    }

    /// Runs at the physics time step `dt` (s) from now on.
    pub(super) fn set_dt(&mut self, dt: f32) {
        self.physics_rate = 1.0 / dt;
        self.rate_origin = (self.physics_rate, dt);
    }

    /// Switches to another scene with its default parameters.
    pub fn switch_scene(&mut self, entry: &SceneEntry) {
        log::info!("scene: {}", entry.info().name);
        // Another scene closes the builder (the builder's own loads keep it).
        self.editor = None;
        self.stop_compare();
        self.entry = entry.clone();
        self.scene = entry.create_default();
        self.set_dt(entry.info().dt);
        // A scene file that names its own solver, substeps or integrator runs with them
        // (the Run section shows them, and they stay for later scenes as any choice there).
        let own = scenes::file::own_solver(entry);
        if !own.is_empty() {
            let solver = own.over(self.solver);
            if solver != self.solver {
                log::info!(
                    "solver from the scene file: {} ({})",
                    solver.kind.name(),
                    solver.integrator.name()
                );
            }
            self.solver = solver;
        }
        // Follow is the scene's own: a new scene starts without it. The side view stays
        // as ticked, and the new scene is drawn that way.
        self.follow = false;
        self.apply_scene_view();
        self.restart();
        self.frame_scene();
        self.follow_crowd();
    }

    /// Sets the view toggles a scene has its own defaults for (trails, colour by
    /// speed); the others are the user's and stay as they are.
    pub(super) fn apply_scene_view(&mut self) {
        let info = self.entry.info();
        self.view.trails = info.trails;
        self.view.color_by_speed = info.color_by_speed;
    }

    /// Turns MSAA off when the scene grows past [`MSAA_LIMIT`] particles, and back on
    /// when it shrinks below if it was turned off that way and not turned on since.
    pub(super) fn follow_crowd(&mut self) {
        let crowded = self.scene.world().particles.len() > MSAA_LIMIT;
        if crowded == self.crowded {
            return;
        }
        self.crowded = crowded;
        if crowded && self.view.msaa {
            self.view.msaa = false;
            self.msaa_dropped = true;
            self.status = format!(
                "Anti-aliasing turned off above {MSAA_LIMIT} particles, for speed; the View menu turns it on"
            );
            log::info!("{}", self.status);
        } else if !crowded && std::mem::take(&mut self.msaa_dropped) && !self.view.msaa {
            self.view.msaa = true;
            log::info!("anti-aliasing back on");
        }
    }

    /// "Restore defaults": the scene's parameters, the solver, integrator, physics rate,
    /// time scale and view toggles go back to their defaults, and the scene starts again.
    /// The scene, the camera (unless the side view was on), the panel and a running
    /// comparison stay.
    pub fn restore_defaults(&mut self) {
        log::info!("restore defaults: {}", self.entry.info().name);
        self.solver = SolverSettings::default();
        self.physics_rate = 1.0 / self.entry.info().dt;
        self.time_scale = 1.0;
        self.view = ViewOptions::default();
        self.apply_scene_view();
        if self.side_view {
            self.set_side_view(false);
        }
        self.follow = false;
        self.scene = self.entry.create_default();
        self.restart();
        // A crowd keeps MSAA off, as when it was first built.
        self.crowded = false;
        self.msaa_dropped = false;
        self.follow_crowd();
        if self.status.is_empty() {
            self.status = format!(
                "Defaults restored for {}: parameters, solver, integrator, physics rate and view",
                self.entry.info().name
            );
        }
    }

    /// Rebuilds the current scene with its current parameters.
    pub fn reset(&mut self) {
        log::info!("reset: {}", self.entry.info().name);
        self.scene = self.entry.create(self.scene.params().clone());
        self.restart();
    }

    /// The solver in use.
    #[must_use]
    pub fn solver(&self) -> SolverSettings {
        self.solver
    }

    /// Switches solver or its settings for the running scene and every later one; a
    /// refusal goes to the status line and changes nothing.
    pub fn set_solver(&mut self, solver: SolverSettings) {
        match self.scene.world_mut().set_solver(solver) {
            Ok(()) => {
                match solver.kind {
                    SolverKind::Soft => log::info!("solver: soft with {} substeps", solver.substeps),
                    SolverKind::Paper => log::info!("solver: paper"),
                }
                log::info!("integrator: {}", solver.integrator.name());
                self.solver = solver;
                if let Some(compare) = &mut self.compare {
                    let mut theirs = solver;
                    compare.apply_to(&mut theirs);
                    let _ = compare.scene.world_mut().set_solver(theirs);
                }
                self.readouts_taken = None;
            }
            Err(error) => self.status = error.to_string(),
        }
    }

    pub(super) fn restart(&mut self) {
        // A new world starts with the default solver: give it the lab's. (Only if it
        // differs: setting it wakes particles, which would change a loaded snapshot.)
        if *self.scene.world().solver() != self.solver {
            self.scene.world_mut().set_solver(self.solver).expect("the lab's solver settings were validated");
        }
        self.accumulator = 0.0;
        // A new world (or the old one put back) is still only once seen so.
        self.still_since = None;
        self.status.clear();
        self.trails.clear();
        self.energy.clear();
        self.grab = None;
        self.hovered = None;
        // A new world numbers its particles afresh: an old selection or tape would
        // point at something else.
        self.select(None);
        self.tape_points.clear();
        self.readouts_taken = None;
        self.compare = None;
        if let Some(change) = self.compare_change.clone() {
            match Compare::new(&self.entry, self.scene.params().clone(), self.solver, self.dt(), change) {
                Ok(compare) => self.compare = Some(compare),
                Err(error) => {
                    self.compare_change = None;
                    self.status = error;
                }
            }
        }
        self.record();
    }

    /// Starts a copy of the scene with `change` beside it. Both start again from the
    /// beginning, so that they run in step from the same state.
    pub fn start_compare(&mut self, change: Change) {
        log::info!("compare: {}", change.describe());
        self.compare_change = Some(change);
        self.reset();
    }

    /// Starts a copy with `change` from the scene as it is now; the scene runs on
    /// undisturbed. A reset later starts both from the beginning, as
    /// [`Lab::start_compare`] does.
    pub fn branch_compare(&mut self, change: Change) {
        let branched = self.snapshot().and_then(|snapshot| Compare::branch(&snapshot, change.clone()));
        match branched {
            Ok(compare) => {
                log::info!("compare from t = {:.3} s: {}", self.scene.world().time(), change.describe());
                self.compare = Some(compare);
                self.compare_change = Some(change);
            }
            Err(error) => self.status = error,
        }
    }

    /// Stops the copy.
    pub fn stop_compare(&mut self) {
        self.compare = None;
        self.compare_change = None;
    }

    /// Changes a parameter of the running scene; a refusal goes to the status line. A
    /// change that rebuilds the world (a count, a size) says so there, and the plots and
    /// trails start again with it.
    pub fn set_param(&mut self, name: &str, value: f32) {
        let steps_before = self.scene.world().steps();
        match self.scene.set_param(name, value) {
            Ok(()) => {
                if let Some(compare) = &mut self.compare {
                    // The copy follows every change but the one it is about.
                    if !matches!(&compare.change, Change::Param(changed, _) if changed == name) {
                        let _ = compare.scene.set_param(name, value);
                        let mut solver = self.solver;
                        compare.apply_to(&mut solver);
                        let _ = compare.scene.world_mut().set_solver(solver);
                    }
                }
                // Some parameters rebuild the world, which then has the default solver.
                self.scene.world_mut().set_solver(self.solver).expect("validated when chosen");
                self.readouts_taken = None;
                log::info!("set {}.{name} = {value}", self.entry.info().name);
                if steps_before > 0 && self.scene.world().steps() == 0 {
                    self.restart();
                    self.status = format!("Changing {name} rebuilt the scene: it starts again from t = 0");
                }
                self.refit_camera();
                self.follow_crowd();
            }
            Err(error) => self.status = error.to_string(),
        }
    }

    /// Changes a parameter to a value typed in the panel: one beyond the slider's range
    /// is clamped to it, and the status line says so.
    pub fn set_param_typed(&mut self, name: &str, value: f32) {
        let Some(param) = self.scene.params().table().iter().find(|p| p.name == name).cloned() else {
            return;
        };
        let clamped = value.clamp(param.min, param.max);
        if clamped == value || value.is_nan() {
            self.set_param(name, value);
            return;
        }
        self.set_param(name, clamped);
        let unit = if param.unit.is_empty() { String::new() } else { format!(" {}", param.unit) };
        self.status = format!(
            "{name} = {value} is beyond its range ({} to {}{unit}): clamped to {clamped}{unit}",
            param.min, param.max
        );
    }

    /// Applies a preset of the current scene by name.
    pub fn apply_preset(&mut self, name: &str) {
        let Some(preset) = self.entry.info().presets.iter().find(|p| p.name == name) else { return };
        for &(key, value) in preset.values {
            self.set_param(key, value);
        }
        self.status = format!("preset: {} ({})", preset.name, preset.help);
    }

    /// Performs a scene action (fire, move the load).
    pub fn act(&mut self, action: SceneAction) {
        if let Some(compare) = &mut self.compare {
            compare.scene.act(action);
        }
        if self.scene.act(action) {
            self.readouts_taken = None;
            log::info!("action: {action:?}");
        }
    }

    /// The start of a run the user does not drive (`render`, a link with `steps`): a
    /// launcher fires one round at step 0, as `simulate` does
    /// ([`crate::scenes::fire_at_start`]), and the copy being compared fires with it.
    /// Opening and Reset never call it: in the window nothing flies until the user fires.
    pub fn fire_at_start(&mut self) {
        if crate::scenes::fires_at_start(self.scene.as_ref()) {
            self.act(SceneAction::Fire);
        }
    }

    /// The integrator's step (s): the physics step, divided by the substeps for the
    /// soft solver.
    #[must_use]
    pub fn integration_step(&self) -> f32 {
        match self.solver.kind {
            SolverKind::Soft => self.dt() / self.solver.substeps as f32,
            SolverKind::Paper => self.dt(),
        }
    }

    /// The scene's read-outs for the panel. While the scene runs they are recomputed
    /// at most every [`READOUT_INTERVAL`]; at once after a reset, a parameter change,
    /// an action, a single step or a new time step.
    pub fn readouts(&mut self) -> &[crate::scenes::Readout] {
        let (now, steps, dt) = (Instant::now(), self.scene.world().steps(), self.dt());
        let fresh = self.readouts_taken.is_some_and(|(taken, at_step, at_dt)| {
            at_dt == dt && (at_step == steps || now.duration_since(taken) < READOUT_INTERVAL)
        });
        if !fresh {
            self.readouts = self.scene.readout_rows(dt);
            self.readouts_taken = Some((now, steps, dt));
        }
        &self.readouts
    }

    /// Frames the scene again after a change of what it must show (a launch speed
    /// that moves the landing), unless the user has moved the camera since.
    fn refit_camera(&mut self) {
        if self.camera_moved {
            return;
        }
        let mut points = Vec::new();
        self.scene.framing_points(&mut points);
        if !points.is_empty() {
            self.frame_scene();
        }
    }
}

//! The lab: the running scene plus everything the panel controls (run state, view
//! options, camera, trails, the particle being dragged). Knows nothing of windows.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};

use crate::physics::broad_phase::BUDGET_HIT_MESSAGE;
pub use crate::physics::inspect::CONSTRAINT_FORCE;
use crate::physics::inspect::{self, ConstraintMeter};
use crate::physics::{ParticleId, SolverKind, SolverSettings};
use crate::render::frame::VECTOR_PARTICLE_LIMIT;
use crate::render::{OrbitCamera, Trails, ViewOptions};
use crate::scenes::snapshot::Snapshot;
use crate::scenes::{self, Scene, SceneAction, SceneEntry};

use super::compare::{Change, Compare};

/// Real time one frame may add to the physics (s): after a stall the rest is dropped
/// instead of running hundreds of catch-up steps.
pub const MAX_FRAME_TIME: f64 = 0.1;
/// Most physics steps one frame may run.
pub const MAX_STEPS_PER_FRAME: u32 = 64;
/// Wall time one frame may spend stepping the physics. A frame runs at least one step,
/// and no further step that would take it past this budget (judged by the last step's
/// time); the simulated time it had no room for is dropped. A scene whose step takes
/// tens of milliseconds (the pile at 100,000 spheres) then runs slower than real time
/// but stays interactive, instead of spending ever longer frames catching up.
pub const PHYSICS_BUDGET: Duration = Duration::from_millis(25);
/// Above this many particles the lab turns 4x MSAA off (and back on when a smaller
/// scene follows, unless the user chose otherwise in between): on a software GPU it
/// nearly triples the cost of drawing a crowd (100,000 spheres: about 175 ms a frame
/// with it, 60 ms without, on lavapipe).
pub const MSAA_LIMIT: usize = 20_000;
/// How often the scene's read-outs are recomputed while it runs (s). Some measure
/// every particle (the pile's takes milliseconds at 100,000 spheres): too slow for
/// every frame, and nobody reads numbers that change 60 times a second.
pub const READOUT_INTERVAL: Duration = Duration::from_millis(250);
/// Physics rates the panel offers (Hz).
pub const PHYSICS_RATE_RANGE: std::ops::RangeInclusive<f32> = 30.0..=1000.0;
/// Time scales the panel offers.
pub const TIME_SCALE_RANGE: std::ops::RangeInclusive<f32> = 0.05..=4.0;
/// Width over height of the 3D view the scenes' camera hints frame: a 1280x720 window
/// less the panel. Narrower views get the camera further back.
pub const FRAMING_ASPECT: f32 = 1.4;

/// The mouse spring's natural frequency (Hz): how quickly a dragged particle follows.
pub const MOUSE_HERTZ: f32 = 5.0;
/// The mouse spring's damping ratio: a little under critical, so it settles at once.
pub const MOUSE_DAMPING_RATIO: f32 = 0.7;
/// Most acceleration the mouse spring gives (m/s², about 15 g): enough to lift any
/// particle against the strongest gravity a scene offers, too little to fling one.
pub const MOUSE_MAX_ACCELERATION: f32 = 150.0;

/// The change of velocity the mouse spring gives in a step of `h` seconds to a particle
/// `offset` metres short of the pointer and moving at `v`: a damped spring integrated
/// implicitly (the soft step: stable for any `h`), then limited to
/// [`MOUSE_MAX_ACCELERATION`] over the step.
#[must_use]
pub fn mouse_pull(offset: Vec3, v: Vec3, h: f32) -> Vec3 {
    let omega = std::f32::consts::TAU * MOUSE_HERTZ;
    let (k, c) = (omega * omega, 2.0 * MOUSE_DAMPING_RATIO * omega);
    let dv = (offset * k - v * (c + k * h)) * h / (1.0 + c * h + k * h * h);
    dv.clamp_length_max(MOUSE_MAX_ACCELERATION * h)
}

/// Longest force arrow (m); see [`Lab::force_scale`].
pub const LONGEST_FORCE_ARROW: f32 = 2.0;

/// The smallest of 1, 2 or 5 times a power of ten that is at least `x` (at least 0.001).
#[must_use]
pub fn round_scale(x: f32) -> f32 {
    let x = x.max(1e-3);
    let power = 10f32.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * power).find(|&s| s >= x * 0.9999).unwrap_or(10.0 * power)
}

/// A factor with at most two decimals and no trailing zeros: 4, 1.2, 0.05.
fn short(x: f32) -> String {
    let text = format!("{x:.2}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Samples kept for the energy plot.
pub(crate) const HISTORY: usize = 600;

/// Timing figures for the stats block.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// Frames per second, smoothed.
    pub fps: f32,
    /// Time between frames (ms), smoothed.
    pub frame_ms: f32,
    /// Wall time per physics step (ms), smoothed.
    pub step_ms: f32,
    /// Physics steps run in the last frame.
    pub steps_last_frame: u32,
    /// Steps dropped so far because a frame took too long or the physics used up its
    /// budget ([`PHYSICS_BUDGET`]).
    pub dropped_steps: u64,
    /// Simulated seconds per real second over recent frames, smoothed: the time scale
    /// when the physics keeps up, less when steps are dropped.
    pub sim_speed: f32,
}

/// A sample of the energy plot.
#[derive(Clone, Copy, Debug)]
pub struct EnergySample {
    /// Simulated time (s).
    pub t: f64,
    /// Kinetic energy (J).
    pub kinetic: f32,
    /// Potential energy (J).
    pub potential: f32,
    /// Its gravitational part (J).
    pub gravitational: f32,
    /// Dissipated since the start, cumulative (J).
    pub dissipated: f32,
    /// Put in from outside since the start, cumulative (J).
    pub work: f32,
    /// Carried out by removed particles since the start, cumulative (J).
    pub removed: f32,
    /// The budget's remainder: the integrator's error (J).
    pub error: f32,
    /// Distance from the scene's exact answer (m), NaN where it has none.
    pub exact_error: f32,
}

impl EnergySample {
    /// The sample of a scene's current state.
    #[must_use]
    pub fn of(scene: &dyn Scene) -> Self {
        let world = scene.world();
        let energy = world.energy();
        // Gravitational energy from the scene's reference height (see `gravity_from`).
        let shift =
            scene.gravity_reference().map_or(0.0, |(height, _)| world.gravity_reference_shift(height));
        Self {
            t: world.time(),
            kinetic: energy.kinetic,
            potential: energy.potential + shift,
            gravitational: energy.gravitational + shift,
            dissipated: energy.dissipated,
            work: energy.work,
            removed: energy.removed,
            error: energy.error,
            exact_error: scene.exact_error().unwrap_or(f32::NAN),
        }
    }
}

/// The energy bars: whose energy they show, the height gravitational energy is
/// measured from, and each bar's name and value (J).
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyBars {
    /// "the scene", or the particle shown ("the bob", "particle 3").
    pub subject: String,
    /// Where gravitational energy is zero ("the ground (y = 0)").
    pub reference: String,
    /// Kinetic, gravitational, elastic and, for the scene, dissipated, removed and the
    /// budget; for a particle, its total.
    pub bars: Vec<(&'static str, f32)>,
}

impl EnergyBars {
    /// Each bar's height (signed, up positive) when `span` pixels stand for the range
    /// the bars cover (from the lowest value or 0 to the highest or 0). 0 J is no bar.
    #[must_use]
    pub fn heights(&self, span: f32) -> Vec<f32> {
        let low = self.bars.iter().map(|b| b.1).fold(0.0, f32::min);
        let high = self.bars.iter().map(|b| b.1).fold(0.0, f32::max);
        let range = high - low;
        self.bars
            .iter()
            .map(|&(_, value)| if range > 0.0 && value != 0.0 { value / range * span } else { 0.0 })
            .collect()
    }
}

/// A particle held by the mouse: it follows the pointer in the plane through its
/// grab point facing the camera.
#[derive(Clone, Copy, Debug)]
pub struct Grab {
    /// The particle.
    pub id: ParticleId,
    /// A point of the drag plane (m).
    pub plane_point: Vec3,
    /// The drag plane's normal.
    pub plane_normal: Vec3,
    /// Where the pointer puts it (m).
    pub target: Vec3,
}

/// Things the panel asks the window to do.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Requests {
    /// Save a screenshot after this frame.
    pub screenshot: bool,
    /// Close the window.
    pub quit: bool,
}

/// Everything the panel shows and edits.
pub struct Lab {
    /// The running scene.
    pub scene: Box<dyn Scene>,
    /// Its registry entry.
    pub entry: &'static SceneEntry,
    /// Physics stopped?
    pub paused: bool,
    /// Simulated seconds per real second.
    pub time_scale: f32,
    /// Physics steps per simulated second (Hz).
    pub physics_rate: f32,
    /// The solver every scene built here uses; kept across resets and scene changes.
    solver: SolverSettings,
    accumulator: f64,
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
    /// Show the controls window.
    pub show_help: bool,
    /// Show the side panel (P hides it, for a view across the whole window).
    pub panel_open: bool,
    /// A second copy of the scene with one setting changed, run beside it.
    pub compare: Option<Compare>,
    /// The change the Compare section has ready to run.
    pub compare_draft: Change,
    /// The Compare section is expanded (kept with the settings).
    pub compare_open: bool,
    /// What the copy changes; kept so a reset rebuilds it.
    compare_change: Option<Change>,
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
    constraint_meter: ConstraintMeter,
    /// Requests for the window.
    pub requests: Requests,
    /// The open scene file, watched for changes (hot reload).
    pub scene_file: Option<super::scene_files::Watch>,
    last_frame: Option<Instant>,
    /// The scene's read-outs as last computed, and when, at which step and time step.
    readouts: Vec<(String, String)>,
    readouts_taken: Option<(Instant, u64, f32)>,
    /// The scene has more than [`MSAA_LIMIT`] particles.
    crowded: bool,
    /// MSAA was turned off because the scene became crowded.
    msaa_dropped: bool,
    /// A physics rate and the time step it was set from (Hz, s): while the rate is
    /// that one, steps take exactly that time step, not `1 / rate` rounded twice, so
    /// the window steps with the bits `simulate` and a snapshot use.
    rate_origin: (f32, f32),
    /// Where File → Save and Load snapshot write and read.
    pub snapshot_path: String,
    /// The state F5 saved, which F9 goes back to.
    quick_save: Option<Snapshot>,
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
        entry: &'static SceneEntry,
        assignments: &[String],
        solver: SolverSettings,
    ) -> Result<Self, String> {
        let mut scene = scenes::build_entry(entry, assignments)?;
        scene.world_mut().set_solver(solver).map_err(|e| e.to_string())?;
        let mut lab = Self {
            solver,
            camera: OrbitCamera::from_hint(scene.camera()),
            physics_rate: 1.0 / entry.info.dt,
            scene,
            entry,
            paused: false,
            time_scale: 1.0,
            accumulator: 0.0,
            view: ViewOptions::default(),
            trails: Trails::default(),
            stats: Stats::default(),
            energy: VecDeque::with_capacity(HISTORY),
            status: String::new(),
            show_help: false,
            panel_open: true,
            bars_for_selected: true,
            side_view: false,
            follow: false,
            compare: None,
            compare_change: None,
            compare_draft: Change::Integrator(crate::physics::Integrator::ExplicitEuler),
            compare_open: false,
            hovered: None,
            grab: None,
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
            rate_origin: (1.0 / entry.info.dt, entry.info.dt),
            snapshot_path: "snapshot.json".into(),
            quick_save: None,
        };
        lab.apply_scene_view();
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
    fn set_dt(&mut self, dt: f32) {
        self.physics_rate = 1.0 / dt;
        self.rate_origin = (self.physics_rate, dt);
    }

    /// Switches to another scene with its default parameters.
    pub fn switch_scene(&mut self, entry: &'static SceneEntry) {
        log::info!("scene: {}", entry.info.name);
        self.stop_compare();
        self.entry = entry;
        self.scene = entry.create_default();
        self.set_dt(entry.info.dt);
        self.camera = OrbitCamera::from_hint(self.scene.camera());
        self.apply_scene_view();
        self.restart();
        self.follow_crowd();
    }

    /// Sets the view toggles a scene has its own defaults for (trails, colour by
    /// speed); the others are the user's and stay as they are.
    fn apply_scene_view(&mut self) {
        let info = self.entry.info;
        self.view.trails = info.trails;
        self.view.color_by_speed = info.color_by_speed;
    }

    /// Turns MSAA off when the scene grows past [`MSAA_LIMIT`] particles, and back on
    /// when it shrinks below if it was turned off that way and not turned on since.
    fn follow_crowd(&mut self) {
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
        log::info!("restore defaults: {}", self.entry.info.name);
        self.solver = SolverSettings::default();
        self.physics_rate = 1.0 / self.entry.info.dt;
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
                self.entry.info.name
            );
        }
    }

    /// Rebuilds the current scene with its current parameters.
    pub fn reset(&mut self) {
        log::info!("reset: {}", self.entry.info.name);
        self.scene = (self.entry.create)(self.scene.params().clone());
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

    fn restart(&mut self) {
        // A new world starts with the default solver: give it the lab's. (Only if it
        // differs: setting it wakes particles, which would change a loaded snapshot.)
        if *self.scene.world().solver() != self.solver {
            self.scene.world_mut().set_solver(self.solver).expect("the lab's solver settings were validated");
        }
        self.accumulator = 0.0;
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
        if let Some(change) = self.compare_change {
            match Compare::new(self.entry, self.scene.params().clone(), self.solver, self.dt(), change) {
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
        let branched = self.snapshot().and_then(|snapshot| Compare::branch(&snapshot, change));
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
                    if !matches!(compare.change, Change::Param(changed, _) if changed == name) {
                        let _ = compare.scene.set_param(name, value);
                        let mut solver = self.solver;
                        compare.apply_to(&mut solver);
                        let _ = compare.scene.world_mut().set_solver(solver);
                    }
                }
                // Some parameters rebuild the world, which then has the default solver.
                self.scene.world_mut().set_solver(self.solver).expect("validated when chosen");
                self.readouts_taken = None;
                log::info!("set {}.{name} = {value}", self.entry.info.name);
                if steps_before > 0 && self.scene.world().steps() == 0 {
                    self.restart();
                    self.status = format!("Changing {name} rebuilt the scene: it starts again from t = 0");
                }
                self.follow_crowd();
            }
            Err(error) => self.status = error.to_string(),
        }
    }

    /// Changes a parameter to a value typed in the panel: one beyond the slider's range
    /// is clamped to it, and the status line says so.
    pub fn set_param_typed(&mut self, name: &str, value: f32) {
        let Some(param) = self.scene.params().table().iter().find(|p| p.name == name) else { return };
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
        let Some(preset) = self.entry.info.presets.iter().find(|p| p.name == name) else { return };
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
    pub fn readouts(&mut self) -> &[(String, String)] {
        let (now, steps, dt) = (Instant::now(), self.scene.world().steps(), self.dt());
        let fresh = self.readouts_taken.is_some_and(|(taken, at_step, at_dt)| {
            at_dt == dt && (at_step == steps || now.duration_since(taken) < READOUT_INTERVAL)
        });
        if !fresh {
            self.readouts = self.scene.readouts(dt);
            self.readouts_taken = Some((now, steps, dt));
        }
        &self.readouts
    }

    /// Advances the physics by the real time since the last call, in fixed steps.
    pub fn advance(&mut self) {
        let now = Instant::now();
        let real_dt = self.last_frame.map_or(0.0, |last| now.duration_since(last).as_secs_f64());
        self.last_frame = Some(now);
        self.advance_by(real_dt);
    }

    /// Advances the physics by `real_dt` seconds of wall time: as many fixed steps as
    /// fit (scaled by the time scale), at most [`MAX_STEPS_PER_FRAME`]; after a stall
    /// longer than [`MAX_FRAME_TIME`] the rest is dropped, not caught up.
    pub fn advance_by(&mut self, real_dt: f64) {
        let smooth = |old: f32, new: f32| if old == 0.0 { new } else { old * 0.9 + new * 0.1 };
        if real_dt > 0.0 {
            self.stats.frame_ms = smooth(self.stats.frame_ms, (real_dt * 1000.0) as f32);
            self.stats.fps = 1000.0 / self.stats.frame_ms.max(1e-3);
        }
        self.stats.steps_last_frame = 0;
        if self.paused {
            self.stats.sim_speed = 0.0;
            return;
        }
        let dt = f64::from(self.dt());
        self.accumulator += real_dt.min(MAX_FRAME_TIME) * f64::from(self.time_scale);
        let wanted = (self.accumulator / dt).floor() as u64;
        let steps = wanted.min(u64::from(MAX_STEPS_PER_FRAME)) as u32;
        let ran = self.step_within(steps, Some(PHYSICS_BUDGET));
        if wanted > u64::from(ran) {
            self.stats.dropped_steps += wanted - u64::from(ran);
            self.accumulator = 0.0;
        } else {
            self.accumulator -= f64::from(ran) * dt;
        }
        if real_dt > 0.0 {
            self.stats.sim_speed = smooth(self.stats.sim_speed, (f64::from(ran) * dt / real_dt) as f32);
        }
    }

    /// When the physics cannot keep up with the time scale asked for (steps per frame
    /// at their cap, or over the physics budget): "running at 1.2× of 4× asked".
    #[must_use]
    pub fn time_scale_note(&self) -> Option<String> {
        let running = !self.paused && self.stats.frame_ms > 0.0;
        (running && self.stats.sim_speed < 0.9 * self.time_scale).then(|| {
            format!("running at {}× of {}× asked", short(self.stats.sim_speed), short(self.time_scale))
        })
    }

    /// Runs exactly `steps` physics steps now, paused or not.
    pub fn run_steps(&mut self, steps: u32) {
        if self.paused {
            // A single step from the panel: show its read-outs at once.
            self.readouts_taken = None;
        }
        self.step_within(steps, None);
    }

    /// Runs up to `steps` physics steps, stopping early (after at least one) when the
    /// next would likely end past `budget`; returns how many ran.
    fn step_within(&mut self, steps: u32, budget: Option<Duration>) -> u32 {
        if steps == 0 {
            return 0;
        }
        let started = Instant::now();
        let dt = self.dt();
        let mut ran = 0;
        let mut last_step = Duration::ZERO;
        for _ in 0..steps {
            if budget.is_some_and(|budget| ran > 0 && started.elapsed() + last_step > budget) {
                break;
            }
            let step_started = Instant::now();
            ran += 1;
            self.hold_grabbed(dt);
            if let Some(id) = self.selected {
                self.constraint_meter.before_step(self.scene.world(), [id]);
            }
            match self.scene.step(dt) {
                Ok(report) if report.pair_budget_hit && !self.status.contains(BUDGET_HIT_MESSAGE) => {
                    self.status = format!("Step {}: {BUDGET_HIT_MESSAGE}", self.scene.world().steps());
                    log::warn!("{}", self.status);
                }
                Ok(_) => {}
                Err(error) => {
                    self.status = error.to_string();
                    self.paused = true;
                    break;
                }
            }
            if !self.scene.world().is_finite() {
                self.status = "The simulation blew up (a value stopped being finite): paused. \
                               Lower the time step (raise the physics rate) or soften a spring, then Reset."
                    .into();
                log::warn!("{}", self.status);
                self.paused = true;
                break;
            }
            if self.selected.is_some() {
                self.constraint_force =
                    self.constraint_meter.after_step(self.scene.world(), dt).next().map(|(_, f)| f);
            }
            last_step = step_started.elapsed();
        }
        let per_step = started.elapsed().as_secs_f32() * 1000.0 / ran as f32;
        self.stats.step_ms =
            if self.stats.step_ms == 0.0 { per_step } else { self.stats.step_ms * 0.9 + per_step * 0.1 };
        self.stats.steps_last_frame = ran;
        self.record();
        self.follow_particle();
        ran
    }

    /// Runs `steps` physics steps one at a time, recording trails after each (for
    /// off-screen frames that should look like a window that ran that long).
    pub fn run_steps_recorded(&mut self, steps: u64) {
        for _ in 0..steps {
            self.run_steps(1);
            if self.paused {
                break;
            }
        }
    }

    /// Records trails (when shown) and the energy plot at the current simulated time.
    fn record(&mut self) {
        let t = self.scene.world().time();
        if self.view.trails {
            self.trails.record(self.scene.as_ref(), t);
        }
        if self.energy.len() == HISTORY {
            self.energy.pop_front();
        }
        self.energy.push_back(EnergySample::of(self.scene.as_ref()));
        let dt = self.dt();
        if let Some(compare) = &mut self.compare {
            // The copy runs at the original's rate unless the rate is what it changes.
            if !matches!(compare.change, Change::Rate(_)) {
                compare.dt = dt;
            }
            compare.catch_up(t);
        }
    }

    /// Places an end of the tape where `pixel` points: the centre of the particle
    /// there, else where the ray meets the ground (y = 0), else the plane through the
    /// camera's target facing it. A third click starts a new tape.
    pub fn tape_click(&mut self, pixel: Vec2, viewport: Vec2) {
        let point = match self.pick(pixel, viewport) {
            Some(id) => {
                let particles = &self.scene.world().particles;
                particles.index(id).map(|i| particles.positions()[i])
            }
            None => {
                let (origin, direction) = self.camera.ray(pixel, viewport);
                let ground = (direction.y < -1e-4).then(|| origin + direction * (-origin.y / direction.y));
                ground.or_else(|| {
                    let normal = (self.camera.eye() - self.camera.target).normalize_or_zero();
                    let facing = direction.dot(normal);
                    (facing.abs() > 1e-4)
                        .then(|| origin + direction * ((self.camera.target - origin).dot(normal) / facing))
                })
            }
        };
        let Some(point) = point else { return };
        if self.tape_points.len() == 2 {
            self.tape_points.clear();
        }
        self.tape_points.push(point);
        if let [a, b] = self.tape_points[..] {
            let d = b - a;
            self.status = format!(
                "tape: {:.3} m (Δx {}, Δy {}, Δz {} m)",
                d.length(),
                crate::messages::fixed(d.x, 3),
                crate::messages::fixed(d.y, 3),
                crate::messages::fixed(d.z, 3)
            );
            log::info!("{}", self.status);
        }
    }

    /// The forces on a particle now, one by one (N): from the current state, its
    /// weight, each force generator's and damping's ([`World::free_body`]); and, for the
    /// selected particle while a contact or link acts on it, what they did over the
    /// last step ([`Self::constraint_force`]), or for one asleep (at rest) what they hold.
    /// Empty for an immovable or unknown particle.
    #[must_use]
    pub fn free_body(&self, id: ParticleId) -> Vec<(&'static str, Vec3)> {
        let world = self.scene.world();
        if self.selected == Some(id) {
            inspect::forces_on(world, id, self.constraint_force)
        } else {
            world.free_body(id)
        }
    }

    /// The net force on a particle (N): the sum of [`Self::free_body`]. Computed from
    /// the state, so it is right the moment a particle is selected, paused or not.
    #[must_use]
    pub fn net_force(&self, id: ParticleId) -> Vec3 {
        self.free_body(id).iter().map(|(_, f)| *f).sum()
    }

    /// The particles that get arrows: the selected one, or with "all vectors" on every
    /// movable particle of a scene of at most [`VECTOR_PARTICLE_LIMIT`].
    #[must_use]
    pub fn vector_particles(&self) -> Vec<ParticleId> {
        let particles = &self.scene.world().particles;
        if self.view.all_vectors && particles.len() <= VECTOR_PARTICLE_LIMIT {
            let movable = particles.ids().iter().zip(particles.inverse_masses());
            movable.filter(|(_, w)| **w > 0.0).map(|(id, _)| *id).collect()
        } else {
            self.selected.into_iter().collect()
        }
    }

    /// The force arrows' scale (N per metre of arrow): from 1, 2, 5 times a power of
    /// ten, the smallest that keeps the largest force on the particles with arrows
    /// within [`LONGEST_FORCE_ARROW`].
    #[must_use]
    pub fn force_scale(&self) -> f32 {
        let largest = self
            .vector_particles()
            .into_iter()
            .flat_map(|id| self.free_body(id))
            .map(|(_, f)| f.length())
            .fold(0.0, f32::max);
        round_scale(largest / LONGEST_FORCE_ARROW)
    }

    /// Turns on a view option by the name `render --view` takes; an unknown name gets a
    /// one-line refusal that lists the known ones.
    pub fn set_view_option(&mut self, name: &str) -> Result<(), String> {
        match name.trim() {
            "forces" => self.view.forces = true,
            "no-forces" => self.view.forces = false,
            "all-vectors" => self.view.all_vectors = true,
            "contacts" => self.view.contacts = true,
            "tension" => self.view.tension_colors = true,
            "no-labels" => self.view.labels = false,
            "no-trails" => self.view.trails = false,
            "side" => self.set_side_view(true),
            "follow" => {
                self.follow = true;
                self.follow_particle();
            }
            other => {
                return Err(format!(
                    "--view {}: unknown view option; known: forces, no-forces, all-vectors, contacts, \
                     tension, side, follow, no-labels, no-trails",
                    crate::messages::quote(other)
                ));
            }
        }
        Ok(())
    }

    /// Selects a particle for the inspector (or none).
    pub fn select(&mut self, id: Option<ParticleId>) {
        if self.selected != id {
            self.selected = id;
            self.constraint_force = None;
        }
    }

    /// Pulls the dragged particle towards the pointer with a soft spring (Box2D's mouse
    /// joint): [`MOUSE_HERTZ`] and [`MOUSE_DAMPING_RATIO`], solved implicitly so it is
    /// stable at any step, and at most [`MOUSE_MAX_ACCELERATION`]. A whip of the mouse
    /// then throws a particle about as fast as the pointer moved, not hundreds of m/s.
    /// Its work goes into the energy budget as work put in from outside.
    fn hold_grabbed(&mut self, dt: f32) {
        let Some(grab) = self.grab else { return };
        let world = self.scene.world_mut();
        let Some(i) = world.particles.index(grab.id) else {
            self.grab = None;
            return;
        };
        if world.particles.inverse_mass[i] == 0.0 {
            return;
        }
        let (x, v) = (world.particles.position[i], world.particles.velocity[i]);
        world.particles.velocity[i] = v + mouse_pull(grab.target - x, v, dt);
    }

    /// The particle whose sphere the ray through `pixel` hits first, if any.
    #[must_use]
    pub fn pick(&self, pixel: Vec2, viewport: Vec2) -> Option<ParticleId> {
        let (origin, direction) = self.camera.ray(pixel, viewport);
        let particles = &self.scene.world().particles;
        let mut best: Option<(f32, ParticleId)> = None;
        for (i, &id) in particles.ids().iter().enumerate() {
            if particles.inverse_mass[i] == 0.0 {
                continue; // nothing moves an immovable particle: a press there orbits
            }
            // A little larger than drawn, so small particles are easy to catch.
            let radius = particles.radius[i].max(0.05) * 1.3 + 0.05;
            let to_center = particles.position[i] - origin;
            let along = to_center.dot(direction);
            let miss = to_center.length_squared() - along * along;
            if along > 0.0 && miss <= radius * radius && best.is_none_or(|(d, _)| along < d) {
                best = Some((along, id));
            }
        }
        best.map(|(_, id)| id)
    }

    /// Starts dragging the particle under `pixel`; false if there is none.
    pub fn start_grab(&mut self, pixel: Vec2, viewport: Vec2) -> bool {
        let Some(id) = self.pick(pixel, viewport) else { return false };
        let particles = &self.scene.world().particles;
        let Some(i) = particles.index(id) else { return false };
        let point = particles.position[i];
        let normal = (self.camera.eye() - self.camera.target).normalize_or_zero();
        self.grab = Some(Grab { id, plane_point: point, plane_normal: normal, target: point });
        self.select(Some(id));
        log::info!("grab: particle {}", id.0);
        true
    }

    /// Moves the drag target to where the ray through `pixel` meets the drag plane.
    /// While paused the particle goes straight there (at rest); running, the physics
    /// steps carry it.
    pub fn move_grab(&mut self, pixel: Vec2, viewport: Vec2) {
        let Some(grab) = &mut self.grab else { return };
        let (origin, direction) = self.camera.ray(pixel, viewport);
        let facing = direction.dot(grab.plane_normal);
        if facing.abs() > 1e-4 {
            let t = (grab.plane_point - origin).dot(grab.plane_normal) / facing;
            if t > 0.0 {
                grab.target = origin + direction * t;
            }
        }
        if self.paused {
            let (id, target) = (grab.id, grab.target);
            let particles = &mut self.scene.world_mut().particles;
            if let Some(i) = particles.index(id) {
                particles.position[i] = target;
                particles.velocity[i] = Vec3::ZERO;
            }
        }
    }

    /// Lets go of the dragged particle (it keeps the velocity it had).
    pub fn end_grab(&mut self) {
        self.grab = None;
    }

    /// The height gravitational energy is measured from in the bars and the plot (m),
    /// and its name: the scene's own reference, or the ground.
    #[must_use]
    pub fn gravity_from(&self) -> (f32, String) {
        match self.scene.gravity_reference() {
            Some((height, name)) => (height, format!("{name} (y = {height} m)")),
            None => (0.0, "the ground (y = 0)".into()),
        }
    }

    /// The particle the bars show, if they show one: the selected particle, else the
    /// scene's focus (springForces' bob), unless the user asked for the whole scene.
    #[must_use]
    pub fn bars_particle(&self) -> Option<(ParticleId, String)> {
        if !self.bars_for_selected {
            return None;
        }
        match self.selected {
            Some(id) => Some((id, format!("particle {}", id.0))),
            None => self.scene.energy_focus().map(|(id, name)| (id, name.to_string())),
        }
        .filter(|(id, _)| self.scene.world().particle_energy(*id).is_some())
    }

    /// The energy bars now ([`EnergyBars`]), gravitational energy from
    /// [`Self::gravity_from`].
    #[must_use]
    pub fn energy_bars(&self) -> EnergyBars {
        let world = self.scene.world();
        let (height, reference) = self.gravity_from();
        let particle =
            self.bars_particle().and_then(|(id, name)| Some((world.particle_energy(id)?, id, name)));
        let bars = match &particle {
            Some(((kinetic, gravitational, stored), id, _)) => {
                let i = world.particles.index(*id).expect("it has an energy");
                let shift = world.particles.accelerations()[i].y * world.particles.mass(i) * height;
                let gravitational = gravitational + shift + 0.0;
                vec![
                    ("kinetic", *kinetic),
                    ("gravity", gravitational),
                    ("elastic", *stored),
                    ("total", kinetic + gravitational + stored),
                ]
            }
            None => {
                let e = world.energy();
                let shift = world.gravity_reference_shift(height);
                vec![
                    ("kinetic", e.kinetic),
                    ("gravity", e.gravitational + shift),
                    ("elastic", e.potential - e.gravitational),
                    ("dissipated", e.dissipated),
                    ("removed", e.removed),
                    ("budget", e.kinetic + e.potential + shift + e.dissipated + e.removed - e.work),
                ]
            }
        };
        let subject = particle.map_or_else(|| "the scene".to_string(), |(_, _, name)| name);
        EnergyBars { subject, reference, bars }
    }

    /// Writes the energy history (every sample kept, not only the plotted window) as
    /// CSV to `path`: `t,kinetic,potential,total,dissipated,work,removed,error`, in J.
    pub fn export_energy_csv(&self, path: &std::path::Path) -> std::io::Result<()> {
        use std::io::Write;
        let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
        writeln!(out, "t,kinetic,potential,total,dissipated,work,removed,error")?;
        for s in &self.energy {
            let total = s.kinetic + s.potential;
            writeln!(
                out,
                "{},{},{},{total},{},{},{},{}",
                s.t, s.kinetic, s.potential, s.dissipated, s.work, s.removed, s.error
            )?;
        }
        out.flush()
    }

    /// Points the camera where the scene asks, backing off in a view narrower than the
    /// one the scenes' camera hints were made for, so the whole scene stays in sight.
    pub fn frame_scene(&mut self) {
        self.camera = OrbitCamera::from_hint(self.scene.camera());
        if self.view_aspect > 0.0 && self.view_aspect < FRAMING_ASPECT {
            self.camera.distance *= FRAMING_ASPECT / self.view_aspect;
        }
        if self.side_view {
            self.look_from_the_side();
        }
        self.camera_moved = false;
        self.follow_particle();
    }

    /// Turns the 2D side view on or off: on, the camera looks along -z at the same
    /// point with a parallel projection; off, the scene is framed again in 3D.
    pub fn set_side_view(&mut self, on: bool) {
        log::info!("side view: {on}");
        self.side_view = on;
        if on {
            self.look_from_the_side();
        } else {
            self.frame_scene();
        }
    }

    fn look_from_the_side(&mut self) {
        self.camera.orthographic = true;
        self.camera.yaw = 0.0;
        self.camera.pitch = 0.0;
        // Level with the target, which must be above the ground for the eye to be.
        self.camera.target.y = self.camera.target.y.max(0.5);
    }

    /// With follow on: puts the camera's target on the selected particle, or else the
    /// newest movable one (the highest id: the round just fired).
    pub fn follow_particle(&mut self) {
        if !self.follow {
            return;
        }
        let particles = &self.scene.world().particles;
        let chosen = self.selected.and_then(|id| particles.index(id)).or_else(|| {
            let movable =
                particles.ids().iter().enumerate().filter(|(i, _)| particles.inverse_masses()[*i] > 0.0);
            movable.max_by_key(|(_, id)| id.0).map(|(i, _)| i)
        });
        if let Some(i) = chosen {
            let p = particles.positions()[i];
            self.camera.target = if self.side_view {
                Vec3::new(p.x, p.y.max(0.5), self.camera.target.z)
            } else {
                Vec3::new(p.x, p.y.max(0.0), p.z)
            };
        }
    }

    /// Tells the lab the 3D view's shape; reframes the scene if it changed and the
    /// user has not moved the camera since it was last framed.
    pub fn set_view_aspect(&mut self, aspect: f32) {
        if aspect.is_finite() && aspect > 0.0 && (aspect - self.view_aspect).abs() > 0.01 {
            self.view_aspect = aspect;
            if !self.camera_moved {
                self.frame_scene();
            }
        }
    }
}

/// Snapshots: save and load the running scene (File menu, F5 and F9, `--from`).
impl Lab {
    /// A lab on the scene a snapshot holds, at the step it was saved, framed by the
    /// scene's camera hint.
    pub fn from_snapshot(snapshot: &Snapshot) -> Result<Self, String> {
        let (entry, scene) = snapshot.restore_with_entry()?;
        let mut lab = Self::from_entry(entry, &[], snapshot.world.solver())?;
        lab.install(entry, scene, snapshot.dt);
        lab.camera = OrbitCamera::from_hint(lab.scene.camera());
        Ok(lab)
    }

    /// The running scene as a snapshot.
    pub fn snapshot(&self) -> Result<Snapshot, String> {
        Snapshot::of(self.scene.as_ref(), self.dt())
    }

    /// Replaces the running scene with a snapshot's, keeping the camera; on an error
    /// nothing changes. The plots and trails start again from the loaded state, and a
    /// Compare copy stops (it would have to run from the scene's start to catch up).
    pub fn load_snapshot(&mut self, snapshot: &Snapshot) -> Result<(), String> {
        let (entry, scene) = snapshot.restore_with_entry()?;
        self.install(entry, scene, snapshot.dt);
        Ok(())
    }

    /// Makes a restored scene the running one, at time step `dt`.
    fn install(&mut self, entry: &'static SceneEntry, scene: Box<dyn Scene>, dt: f32) {
        self.stop_compare();
        self.entry = entry;
        self.scene = scene;
        self.solver = *self.scene.world().solver();
        self.set_dt(dt);
        self.apply_scene_view();
        self.restart();
        self.follow_crowd();
    }

    /// Writes a snapshot to `path`; the status line says where, or why not.
    pub fn save_snapshot_to(&mut self, path: &std::path::Path) {
        self.status = match self.snapshot().and_then(|snapshot| snapshot.save(path)) {
            Ok(()) => {
                let world = self.scene.world();
                let hash = scenes::snapshot::hash_text(world.state_hash());
                log::info!("saved snapshot {} at step {}, state hash {hash}", path.display(), world.steps());
                format!("Saved {} (step {}, t = {:.3} s)", path.display(), world.steps(), world.time())
            }
            Err(error) => error,
        };
    }

    /// Loads the snapshot at `path`; a bad file leaves the running scene as it was
    /// and the status line says what is wrong.
    pub fn load_snapshot_from(&mut self, path: &std::path::Path) {
        let loaded = Snapshot::load(path).and_then(|snapshot| {
            self.load_snapshot(&snapshot).map_err(|e| format!("{}: {e}", path.display()))
        });
        match loaded {
            Ok(()) => {
                let world = self.scene.world();
                log::info!("loaded snapshot {} at step {}", path.display(), world.steps());
                self.status =
                    format!("Loaded {} (step {}, t = {:.3} s)", path.display(), world.steps(), world.time());
            }
            Err(error) => {
                log::warn!("{error}");
                self.status = error;
            }
        }
    }

    /// F5: keeps the current state to go back to with F9.
    pub fn quick_save(&mut self) {
        match self.snapshot() {
            Ok(snapshot) => {
                self.status =
                    format!("Quick save at t = {:.3} s: F9 goes back to it", self.scene.world().time());
                self.quick_save = Some(snapshot);
            }
            Err(error) => self.status = error,
        }
    }

    /// F9: goes back to the state F5 kept, keeping the camera.
    pub fn quick_load(&mut self) {
        let Some(snapshot) = self.quick_save.take() else {
            self.status = "Nothing quick-saved yet: F5 saves, F9 goes back".into();
            return;
        };
        let result = self.load_snapshot(&snapshot);
        self.status = match result {
            Ok(()) => format!("Back to the quick save at t = {:.3} s", self.scene.world().time()),
            Err(error) => error,
        };
        self.quick_save = Some(snapshot);
    }

    /// The state hash of the running world, as the panel shows it.
    #[must_use]
    pub fn state_hash(&self) -> String {
        scenes::snapshot::hash_text(self.scene.world().state_hash())
    }
}

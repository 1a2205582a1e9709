//! The lab's clock: fixed physics steps from real time (scaled, capped, within a
//! budget), single steps, what each frame records (trails, the energy history), and
//! when the lab is at rest (nothing on screen would change: the window stops drawing,
//! the physics steps on without it).

use std::time::Duration;

use web_time::Instant;

use super::limits::{HISTORY, MAX_FRAME_TIME, MAX_STEPS_PER_FRAME, REST_DELAY, REST_TICK};
use super::model::Lab;
use super::records::EnergySample;
use crate::physics::Particles;
use crate::physics::broad_phase::BUDGET_HIT_MESSAGE;
use crate::ui::compare::Change;

/// A factor with at most two decimals and no trailing zeros: 4, 1.2, 0.05.
fn short(x: f32) -> String {
    let text = format!("{x:.2}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Whether every movable particle of `particles` is asleep (immovable ones never move;
/// no particles at all is still too).
fn all_asleep(particles: &Particles) -> bool {
    particles.inverse_masses().iter().enumerate().all(|(i, &w)| w == 0.0 || particles.is_asleep(i))
}

impl Lab {
    /// True while the picture changes by itself (the physics runs and something moves,
    /// or has moved within what the plots and trails still show): the window then draws
    /// every frame; otherwise it draws only on input (and, at rest, steps the physics
    /// every [`REST_TICK`] without drawing: see [`Self::advance_at_rest`]).
    #[must_use]
    pub fn needs_animation(&self) -> bool {
        !self.paused && !self.at_rest()
    }

    /// The lab is at rest: it runs (not paused), nothing is held by the mouse, every
    /// movable particle is asleep, and the Compare copy's too, and has been since at
    /// least [`REST_DELAY`] of simulated time ago, so the energy plot is a level line and
    /// the trails have faded. Nothing on screen then changes by itself but the clock's
    /// figure, which the physics keeps counting (see [`Self::advance_at_rest`]). Any
    /// change that wakes a particle (a parameter, a solver setting, a Fire, a reset, a
    /// reload, a snapshot) ends it at once, before the next step.
    #[must_use]
    pub fn at_rest(&self) -> bool {
        let now = self.scene.world().time();
        !self.paused
            && self.grab.is_none()
            && self.still_since.is_some_and(|since| now - since >= REST_DELAY)
            && self.still_now()
    }

    /// Every movable particle asleep, the Compare copy's too (unless it stopped).
    fn still_now(&self) -> bool {
        let copy_still = self
            .compare
            .as_ref()
            .is_none_or(|c| c.stopped.is_some() || all_asleep(&c.scene.world().particles));
        all_asleep(&self.scene.world().particles) && copy_still
    }

    /// When a lab at rest should next step its physics: [`REST_TICK`] after it last
    /// stepped; none when it is not at rest.
    #[must_use]
    pub fn next_rest_tick(&self) -> Option<Instant> {
        if !self.at_rest() {
            return None;
        }
        Some(self.last_frame.map_or_else(Instant::now, |last| last + REST_TICK))
    }

    /// Advances the physics by the real time since the last call, in fixed steps: a
    /// frame the window draws.
    pub fn advance(&mut self) {
        let now = Instant::now();
        let real_dt = self.last_frame.map_or(0.0, |last| now.duration_since(last).as_secs_f64());
        self.last_frame = Some(now);
        self.advance_by(real_dt);
    }

    /// At rest, steps the physics by the real time since it last stepped, as a frame
    /// would, without a frame: the same fixed steps in the same order as a window that
    /// kept drawing, so the world's time and step count keep pace with the clock (the
    /// state hash at a step is `simulate`'s, and what a scene does at a time happens on
    /// time), where leaving the time to the next frame would drop all but
    /// [`MAX_FRAME_TIME`] of it. An asleep world's step is cheap (a settled pile of 300
    /// spheres: about 0.02 ms). The frame rate figures are left alone: no frame was drawn.
    pub fn advance_at_rest(&mut self) {
        let now = Instant::now();
        let real_dt = self.last_frame.map_or(0.0, |last| now.duration_since(last).as_secs_f64());
        self.last_frame = Some(now);
        self.stats.steps_last_frame = 0;
        self.rest_tick(real_dt);
    }

    /// The physics of a tick at rest: `real_dt` of wall time in pieces of at most half
    /// [`MAX_STEPS_PER_FRAME`] steps each, since a tick (longer than a frame) at a high
    /// rate and time scale asks for more steps than one frame may take (1000 Hz at 4×
    /// is 200 steps in a 50 ms tick), and none of them is to be dropped.
    fn rest_tick(&mut self, real_dt: f64) {
        let steps_time = f64::from(self.dt()) / f64::from(self.time_scale).max(1e-6);
        let piece = 0.5 * f64::from(MAX_STEPS_PER_FRAME) * steps_time;
        let mut left = real_dt.min(MAX_FRAME_TIME);
        while left > 0.0 && !self.paused {
            let now = left.min(piece);
            self.step_for(now);
            left -= now;
        }
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
        // The builder shows the experiment as built: nothing runs until Play.
        if self.paused || self.editing() {
            self.stats.sim_speed = 0.0;
            return;
        }
        self.step_for(real_dt);
    }

    /// The physics of [`Self::advance_by`]: the fixed steps `real_dt` seconds of wall
    /// time ask for, within the caps, and the simulated speed that came of it.
    fn step_for(&mut self, real_dt: f64) {
        let smooth = |old: f32, new: f32| if old == 0.0 { new } else { old * 0.9 + new * 0.1 };
        let dt = f64::from(self.dt());
        self.accumulator += real_dt.min(MAX_FRAME_TIME) * f64::from(self.time_scale);
        let wanted = (self.accumulator / dt).floor() as u64;
        let steps = wanted.min(u64::from(MAX_STEPS_PER_FRAME)) as u32;
        let ran = self.step_within(steps, self.physics_budget);
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

    /// Runs exactly `steps` physics steps now, paused or not (not while building).
    pub fn run_steps(&mut self, steps: u32) {
        if self.editing() {
            return; // the builder shows the experiment as built; Play runs it
        }
        if self.paused {
            // A single step from the panel: show its read-outs at once.
            self.readouts_taken = None;
        }
        self.step_within(steps, None);
    }

    /// Runs up to `steps` physics steps, stopping early (after at least one) when the
    /// next would likely end past `budget`; returns how many ran.
    pub(super) fn step_within(&mut self, steps: u32, budget: Option<Duration>) -> u32 {
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
            // Positions and velocities every step (cheap); every other figure shown
            // (energies, tensions, inertia, accelerations) once a frame, below.
            if !self.scene.world().is_finite() {
                self.blew_up();
                break;
            }
            if self.selected.is_some() {
                self.constraint_force =
                    self.constraint_meter.after_step(self.scene.world(), dt).next().map(|(_, f)| f);
            }
            last_step = step_started.elapsed();
        }
        if !self.paused && self.scene.world().first_non_finite(&mut self.finite_scratch).is_some() {
            self.blew_up();
        }
        let per_step = started.elapsed().as_secs_f32() * 1000.0 / ran as f32;
        self.stats.step_ms =
            if self.stats.step_ms == 0.0 { per_step } else { self.stats.step_ms * 0.9 + per_step * 0.1 };
        self.stats.steps_last_frame = ran;
        self.record();
        self.follow_particle();
        ran
    }

    /// Pauses a world one of whose figures stopped being finite, naming the first
    /// ([`World::first_non_finite`](crate::physics::World::first_non_finite)) in the
    /// status line and the log.
    fn blew_up(&mut self) {
        let world = self.scene.world();
        let what = world.first_non_finite(&mut self.finite_scratch).unwrap_or_else(|| "a value".into());
        self.status = format!(
            "The simulation blew up at step {} ({what} stopped being finite): paused. Lower the time step \
             (raise the physics rate) or soften a spring, then Reset.",
            world.steps()
        );
        log::warn!("{}", self.status);
        self.paused = true;
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

    /// Records trails (when shown) and the energy plot at the current simulated time,
    /// and since when the lab has been still.
    pub(super) fn record(&mut self) {
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
        // A world put back to an earlier time is still only from then on.
        let since = self.still_since.filter(|&since| since <= t);
        self.still_since = if self.still_now() { Some(since.unwrap_or(t)) } else { None };
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::super::limits::{MAX_FRAME_TIME, MAX_STEPS_PER_FRAME, REST_DELAY, REST_TICK};
    use super::super::model::Lab;
    use super::super::records::Grab;
    use super::all_asleep;

    /// A small pile: twenty spheres that fall, settle and sleep within seconds.
    /// A small pile, its frames' wall-clock budget off: these tests check the clock's
    /// arithmetic, which a busy machine's slow steps must not stand in for.
    fn pile() -> Lab {
        let mut lab = Lab::new("pile", &["count=20".to_string()]).unwrap();
        lab.physics_budget = None;
        lab
    }

    /// Steps `lab` one physics step at a time until every movable particle is asleep
    /// (at most a minute of simulated time); returns the time it was first seen so.
    fn step_until_asleep(lab: &mut Lab) -> f64 {
        for _ in 0..3600 {
            lab.run_steps(1);
            if all_asleep(&lab.scene.world().particles) {
                return lab.scene.world().time();
            }
        }
        panic!("the pile never fell asleep");
    }

    /// Steps `lab` until it is at rest (at most two minutes); returns the time.
    fn step_until_at_rest(lab: &mut Lab) -> f64 {
        for _ in 0..7200 {
            lab.run_steps(1);
            if lab.at_rest() {
                return lab.scene.world().time();
            }
        }
        panic!("the lab never came to rest");
    }

    #[test]
    fn a_settled_pile_rests_once_its_plot_is_level_and_a_slider_wakes_it_at_once() {
        let mut lab = pile();
        assert!(!lab.at_rest() && lab.needs_animation(), "the spheres fall");
        let asleep = step_until_asleep(&mut lab);
        // Asleep, but the plot still shows the fall, and the trails the paths.
        assert!(!lab.at_rest() && lab.needs_animation(), "at rest as soon as asleep (t = {asleep})");
        let rest = step_until_at_rest(&mut lab);
        let dt = f64::from(lab.dt());
        assert!(
            rest >= asleep + REST_DELAY && rest <= asleep + REST_DELAY + 2.0 * dt,
            "asleep at {asleep} s, at rest at {rest} s"
        );
        assert!(!lab.needs_animation());
        assert!(lab.next_rest_tick().is_some(), "at rest, the physics still ticks");
        // The energy plot's last REST_DELAY is a level line: every sample the same.
        let newest = *lab.energy.back().unwrap();
        let shown = lab.energy.iter().filter(|s| s.t >= newest.t - REST_DELAY);
        for sample in shown {
            let same = |a: f32, b: f32| a.to_bits() == b.to_bits();
            let (t, sample, newest) = (sample.t, sample.energy, newest.energy);
            assert!(
                same(sample.kinetic, newest.kinetic)
                    && same(sample.potential, newest.potential)
                    && same(sample.constraint, newest.constraint)
                    && same(sample.error, newest.error)
                    && same(sample.removed, newest.removed),
                "the plot still moves at t = {t}"
            );
        }
        // Still at rest while it runs on.
        lab.run_steps(600);
        assert!(lab.at_rest());

        // A solver setting that wakes the spheres (sleeping turned off) ends the rest
        // at once, without rebuilding the world.
        let mut solver = lab.solver();
        solver.sleep = false;
        lab.set_solver(solver);
        assert!(!lab.at_rest() && lab.needs_animation(), "turning sleep off wakes it");
        solver.sleep = true;
        lab.set_solver(solver);
        step_until_at_rest(&mut lab);
        // One that leaves them asleep (another substep) changes nothing that moves.
        solver.substeps += 1;
        lab.set_solver(solver);
        assert!(lab.at_rest(), "the spheres sleep on");

        // A slider: at once, before any step.
        lab.set_param("friction", 0.4);
        assert!(!lab.at_rest() && lab.needs_animation(), "a slider change wakes it");
        assert!(lab.next_rest_tick().is_none());
        // It settles again, and rests again REST_DELAY later.
        step_until_at_rest(&mut lab);
        assert!(lab.at_rest());
    }

    #[test]
    fn a_swinging_pendulum_never_rests() {
        let mut lab = Lab::new("pendulum", &[]).unwrap();
        for _ in 0..30 {
            lab.run_steps(60);
            assert!(!lab.at_rest() && lab.needs_animation(), "at rest at t = {}", lab.scene.world().time());
        }
    }

    #[test]
    fn paused_held_reset_or_put_back_it_is_not_at_rest() {
        let mut lab = pile();
        step_until_at_rest(&mut lab);
        // Paused: the window draws on input only anyway, but the lab is not at rest
        // (nothing steps).
        lab.paused = true;
        assert!(!lab.at_rest() && !lab.needs_animation());
        lab.paused = false;
        assert!(lab.at_rest());
        // Held by the mouse.
        let id = lab.scene.world().particles.ids()[0];
        let at = lab.scene.world().particles.positions()[0];
        lab.grab = Some(Grab { id, plane_point: at, plane_normal: Vec3::Z, target: at, pulled_mass: 1.0 });
        assert!(!lab.at_rest() && lab.needs_animation(), "held");
        lab.grab = None;
        assert!(lab.at_rest());
        // F5 then F9: the world put back, its plot started again.
        lab.quick_save();
        lab.quick_load();
        assert!(!lab.at_rest(), "a snapshot put back is drawn until its plot is level");
        step_until_at_rest(&mut lab);
        // A reset: the spheres fall again.
        lab.reset();
        assert!(!lab.at_rest() && lab.needs_animation(), "reset");
    }

    #[test]
    fn at_rest_the_clock_keeps_counting_with_the_same_steps_as_a_window_that_draws() {
        // What the window does at rest, tick by tick, against one step at a time.
        let (mut ticked, mut stepped) = (pile(), pile());
        step_until_at_rest(&mut ticked);
        step_until_at_rest(&mut stepped);
        let start = ticked.scene.world().time();
        let ticks = 200;
        for _ in 0..ticks {
            ticked.rest_tick(REST_TICK.as_secs_f64());
            assert!(ticked.at_rest());
        }
        let steps = ticked.scene.world().steps() - stepped.scene.world().steps();
        stepped.run_steps(steps as u32);
        // The clock kept real time: 200 ticks are 10 s, to within a step.
        let counted = ticked.scene.world().time() - start;
        let real = ticks as f64 * REST_TICK.as_secs_f64();
        assert!((counted - real).abs() <= f64::from(ticked.dt()), "{counted} s counted in {real} s");
        assert_eq!(ticked.stats.dropped_steps, 0);
        // And the physics is the same, to the bit.
        assert_eq!(ticked.scene.world().time(), stepped.scene.world().time());
        assert_eq!(ticked.state_hash(), stepped.state_hash());
    }

    /// Issue 40: the window's blow-up check covers every figure the panel shows, not
    /// only positions and velocities. A figure that no step reads back into the
    /// motion (a bridge sphere's inverse moment of inertia: its spheres do not roll)
    /// made infinite leaves positions and velocities finite, and is still caught and
    /// named, within the frame.
    #[test]
    fn a_figure_that_is_not_a_position_or_velocity_going_infinite_pauses_and_is_named() {
        let mut lab = Lab::new("bridge", &[]).unwrap();
        lab.run_steps(10);
        assert!(!lab.paused && lab.status.is_empty(), "{}", lab.status);
        let world = lab.scene.world_mut();
        let i = world.particles.inverse_masses().iter().position(|&w| w > 0.0).unwrap();
        let id = world.particles.ids()[i].0;
        world.particles.inverse_inertia[i] = f32::INFINITY;
        lab.run_steps(3);
        assert!(lab.scene.world().is_finite(), "positions and velocities stay finite");
        assert!(lab.paused, "not paused: {}", lab.status);
        assert!(
            lab.status.contains(&format!("particle {id}'s inverse moment of inertia stopped being finite")),
            "{}",
            lab.status
        );
        // The step it stopped at is the one the status names.
        assert!(lab.status.contains(&format!("at step {}", lab.scene.world().steps())), "{}", lab.status);
    }

    /// At the highest rate and time scale the panel offers, a tick at rest asks for
    /// far more steps than a frame may take: none is dropped, the clock keeps pace.
    #[test]
    fn at_rest_at_the_highest_rate_and_time_scale_the_clock_keeps_pace() {
        let mut lab = pile();
        step_until_at_rest(&mut lab);
        lab.physics_rate = *super::super::limits::PHYSICS_RATE_RANGE.end();
        lab.time_scale = *super::super::limits::TIME_SCALE_RANGE.end();
        assert!(lab.at_rest(), "the spheres sleep on at another rate");
        let (start, dropped) = (lab.scene.world().time(), lab.stats.dropped_steps);
        let ticks = 20;
        for _ in 0..ticks {
            lab.rest_tick(REST_TICK.as_secs_f64());
        }
        let counted = lab.scene.world().time() - start;
        let asked = ticks as f64 * REST_TICK.as_secs_f64() * f64::from(lab.time_scale);
        assert!(
            (counted - asked).abs() <= f64::from(lab.dt()) * 1.001,
            "{counted} s counted of {asked} s asked"
        );
        assert_eq!(lab.stats.dropped_steps, dropped, "steps dropped at rest");
    }

    #[test]
    fn a_tick_at_rest_drops_no_time() {
        // A tick's time is within what a frame may add, and its steps within a frame's cap
        // at the default rates (60 to 240 Hz) and up to four times real time.
        assert!(REST_TICK.as_secs_f64() < MAX_FRAME_TIME);
        assert!(REST_TICK.as_secs_f64() * 240.0 * 4.0 < f64::from(MAX_STEPS_PER_FRAME));
    }
}

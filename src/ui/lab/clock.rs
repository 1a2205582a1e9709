//! The lab's clock: fixed physics steps from real time (scaled, capped, within a
//! budget), single steps, and what each frame records (trails, the energy history).

use std::time::Duration;

use web_time::Instant;

use super::limits::{HISTORY, MAX_FRAME_TIME, MAX_STEPS_PER_FRAME, PHYSICS_BUDGET};
use super::model::Lab;
use super::records::EnergySample;
use crate::physics::broad_phase::BUDGET_HIT_MESSAGE;
use crate::ui::compare::Change;

/// A factor with at most two decimals and no trailing zeros: 4, 1.2, 0.05.
fn short(x: f32) -> String {
    let text = format!("{x:.2}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

impl Lab {
    /// True while the picture changes by itself (the physics runs): the window then
    /// draws every frame; otherwise it draws only on input.
    #[must_use]
    pub fn needs_animation(&self) -> bool {
        !self.paused
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
    }
}

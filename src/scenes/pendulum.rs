//! pendulum: a chain of `links` rods hanging from a fixed pivot, released from `angle`.
//! One link is the simple pendulum, two the chaotic double pendulum. Its energy plot is
//! the check anyone can watch: undamped, the soft solver keeps the swing's energy
//! (0.07% lost in 10 s at 240 Hz for one 1 m link).
//!
//! Particle 0 is the bob nearest the pivot, particle 1 the next, and so on.

use std::borrow::Cow;

use glam::Vec3;

use super::runs::{Column, Runs, Table};
use super::{CameraHint, Param, ParamError, ParamTable, ParamValues, Scene, SceneEntry, SceneInfo};
use crate::physics::{Constraint, ParticleDesc, ParticleId, PhysicsError, ResolveReport, World};

/// Mass of each bob (kg).
const BOB_MASS: f32 = 1.0;
/// Drawn radius of each bob (m); bobs do not collide.
const BOB_RADIUS: f32 = 0.08;

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("links"), unit: Cow::Borrowed(""), default: 1.0, min: 1.0, max: 5.0, help: Cow::Borrowed("Number of rods in the chain (rounded; 2 is the chaotic double pendulum)"), logarithmic: false, integer: true },
    Param { name: Cow::Borrowed("length"), unit: Cow::Borrowed("m"), default: 1.0, min: 0.2, max: 3.0, help: Cow::Borrowed("Length of each rod"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("angle"), unit: Cow::Borrowed("°"), default: 90.0, min: -180.0, max: 180.0, help: Cow::Borrowed("Release angle of the chain from straight down (90 = horizontal)"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("damping"), unit: Cow::Borrowed(""), default: 1.0, min: 0.5, max: 1.0, help: Cow::Borrowed("Fraction of velocity kept per second (1 = no damping)"), logarithmic: false, integer: false },
    super::GRAVITY,
];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("pendulum"),
    summary: Cow::Borrowed("A chain of 1 to 5 rods from a pivot; two make the chaotic double pendulum"),
    dt: 1.0 / 240.0,
    default_steps: 2400,
    params: ParamTable::Static(PARAMS),
    ..super::TRACED
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

fn create(params: ParamValues) -> Box<dyn Scene> {
    Box::new(Pendulum::build(params))
}

/// The columns of a pendulum's table of runs: a row for each release of a single
/// pendulum, once its first whole swing is timed.
pub static RUN_COLUMNS: &[Column] = &[
    Column { key: "length_m", heading: "L (m)", help: "Length of the rod", always: false },
    Column {
        key: "angle_deg", heading: "θ₀ (°)", help: "Release angle from straight down", always: true
    },
    Column { key: "g_m_s2", heading: "g (m/s²)", help: "Gravitational acceleration", always: false },
    Column {
        key: "damping",
        heading: "damping",
        help: "Fraction of velocity kept per second",
        always: false,
    },
    Column {
        key: "period_s",
        heading: "period (s)",
        help: "Measured: the first whole swing after the release, between two crossings of the vertical \
               moving the same way",
        always: true,
    },
    Column {
        key: "period_predicted_s",
        heading: "2π√(L/g) (s)",
        help: "Predicted for small swings: leaves out the amplitude and damping",
        always: true,
    },
    Column {
        key: "period_exact_predicted_s",
        heading: "exact (s)",
        help: "Predicted for this amplitude, 4√(L/g)·K(sin(θ₀/2)): leaves out damping",
        always: true,
    },
];

/// The number of rods the parameters ask for.
fn links(params: &ParamValues) -> usize {
    params.get("links").round().clamp(1.0, 5.0) as usize
}

/// The fixed pivot: high enough that the chain never reaches the ground at y = 0.
fn pivot(params: &ParamValues) -> Vec3 {
    Vec3::new(0.0, links(params) as f32 * params.get("length") + 0.5, 0.0)
}

struct Pendulum {
    world: World,
    params: ParamValues,
    /// Mechanical energy at release (J), for the read-out.
    start_energy: f32,
    /// The stopwatch of a single pendulum: the times (s) the bob last crossed the
    /// vertical below the pivot moving towards +x, newest last, each placed within its
    /// step where the crossing falls; the period is the time between the two.
    crossings: [Option<f64>; 2],
    /// Whether this release's first whole swing has been timed (and put in the table).
    timed: bool,
    /// The table of runs, in [`RUN_COLUMNS`].
    runs: Runs,
}

impl Pendulum {
    fn build(params: ParamValues) -> Self {
        let (length, g, damping) = (params.get("length"), params.get("g"), params.get("damping"));
        let angle = params.get("angle").to_radians();
        let direction = Vec3::new(angle.sin(), -angle.cos(), 0.0);
        let pivot = pivot(&params);
        let mut world = World::new();
        let mut previous: Option<ParticleId> = None;
        for k in 1..=links(&params) {
            let bob = world
                .add_particle(ParticleDesc {
                    position: pivot + direction * (k as f32 * length),
                    acceleration: Vec3::new(0.0, -g, 0.0),
                    mass: BOB_MASS,
                    damping,
                    radius: BOB_RADIUS,
                    ..ParticleDesc::default()
                })
                .expect("parameter ranges keep every bob valid");
            let rod = match previous {
                None => Constraint::support_rod(bob, pivot, length),
                Some(up) => Constraint::rod(bob, up, length),
            };
            world.add_contact_generator(rod).expect("parameter ranges keep every rod valid");
            previous = Some(bob);
        }
        let energy = world.energy();
        Self {
            world,
            params,
            start_energy: energy.kinetic + energy.potential,
            crossings: [None; 2],
            timed: false,
            runs: Runs::new(RUN_COLUMNS),
        }
    }

    /// The small-swing and the exact period of a single pendulum at these parameters
    /// (s): `None` without gravity, the exact one `None` from 180°.
    fn predicted_periods(&self) -> Option<(f32, Option<f64>)> {
        let (length, g) = (self.params.get("length"), self.params.get("g"));
        if links(&self.params) != 1 || g <= 0.0 {
            return None;
        }
        let small = 2.0 * std::f32::consts::PI * (length / g).sqrt();
        let amplitude = f64::from(self.params.get("angle").to_radians());
        let exact = (amplitude.abs() < std::f64::consts::PI)
            .then(|| crate::physics::exact::pendulum_period(f64::from(length), f64::from(g), amplitude));
        Some((small, exact))
    }

    /// Puts this release's first timed swing in the table.
    fn add_run(&mut self, period: f64) {
        let Some((small, exact)) = self.predicted_periods() else { return };
        let p = |name| f64::from(self.params.get(name));
        let row = vec![
            p("length"),
            p("angle"),
            p("g"),
            p("damping"),
            period,
            f64::from(small),
            exact.unwrap_or(f64::NAN),
        ];
        self.runs.push(row);
    }

    /// The bob's offset along x from the pivot (m), for a single pendulum.
    fn bob_offset(&self) -> Option<f32> {
        if links(&self.params) != 1 {
            return None;
        }
        self.world.particles.positions().first().map(|p| p.x - pivot(&self.params).x)
    }

    /// The period the stopwatch measured over the last whole swing (s).
    fn measured_period(&self) -> Option<f64> {
        match self.crossings {
            [Some(a), Some(b)] => Some(b - a),
            _ => None,
        }
    }
}

impl Scene for Pendulum {
    fn gravity_reference(&self) -> Option<(f32, &'static str)> {
        Some((
            pivot(&self.params).y - links(&self.params) as f32 * self.params.get("length"),
            "the chain's lowest point at rest",
        ))
    }

    scene_basics!();

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        let mut params = self.params.clone();
        params.set(name, value)?;
        match name {
            "g" => {
                super::pull_down(&mut self.world, value);
                self.params = params;
            }
            "damping" => {
                super::damp_all(&mut self.world, value);
                self.params = params;
            }
            // The chain's shape and release: start again, the table kept.
            _ => {
                let mut running = std::mem::replace(self, Self::build(params));
                super::keep_solver(&running.world, &mut self.world);
                std::mem::swap(&mut self.runs, &mut running.runs);
            }
        }
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        let (before, t0) = (self.bob_offset(), self.world.time());
        let report = self.world.step(dt)?;
        if let (Some(x0), Some(x1)) = (before, self.bob_offset())
            && x0 < 0.0
            && x1 >= 0.0
        {
            let t = t0 + f64::from(-x0 / (x1 - x0)) * (self.world.time() - t0);
            self.crossings = [self.crossings[1], Some(t)];
            if let (false, Some(period)) = (self.timed, self.measured_period()) {
                self.timed = true;
                self.add_run(period);
            }
        }
        Ok(report)
    }

    fn save_state(&self) -> serde_json::Value {
        serde_json::json!({ "crossings": self.crossings, "timed": self.timed, "runs": self.runs.saved() })
    }

    fn runs(&self) -> Option<Table<'_>> {
        Some(self.runs.table())
    }

    fn delete_runs(&mut self, which: Option<usize>) -> bool {
        self.runs.delete(which);
        true
    }

    fn restore_state(&mut self, state: &super::RawValue) -> Result<(), String> {
        #[derive(serde::Deserialize)]
        struct Saved {
            #[serde(default)]
            crossings: [Option<f64>; 2],
            // Snapshots from before the table of runs have neither.
            #[serde(default)]
            timed: Option<bool>,
            #[serde(default)]
            runs: Vec<Vec<Option<f64>>>,
        }
        // A snapshot made before the stopwatch holds null: no crossing timed yet.
        let saved: Saved = if state.get() == "null" {
            Saved { crossings: [None; 2], timed: None, runs: Vec::new() }
        } else {
            super::read_state(state)?
        };
        let now = self.world.time();
        if saved.crossings.iter().flatten().any(|&t| !(t >= 0.0 && t <= now)) {
            return Err(format!("a stopwatch time is outside 0 to the world's {now:.3} s"));
        }
        let runs = self.runs.read(saved.runs)?;
        self.crossings = saved.crossings;
        // An old snapshot that had timed its swing already did not table it: leave it so.
        self.timed = saved.timed.unwrap_or(self.crossings.iter().all(Option::is_some));
        self.runs = runs;
        Ok(())
    }

    fn labels<'a>(&'a self, out: &mut Vec<(Vec3, &'a str)>) {
        out.push((pivot(&self.params) + Vec3::Y * 0.25, "pivot"));
        if let Some(&bob) = self.world.particles.positions().first() {
            out.push((bob + Vec3::Y * 0.25, "bob 0"));
        }
    }

    fn camera(&self) -> CameraHint {
        let reach = links(&self.params) as f32 * self.params.get("length");
        CameraHint {
            target: pivot(&self.params) - Vec3::Y * (0.4 * reach),
            distance: 3.2 * reach + 1.5,
            yaw: 0.0,
            pitch: 0.05,
        }
    }

    fn readout_rows(&self, _dt: f32) -> Vec<super::Readout> {
        use super::Readout;
        let energy = self.world.energy();
        let change = energy.kinetic + energy.potential - self.start_energy;
        let mut out = vec![
            Readout::new("energy since release", format!("{change:+.3} J"))
                .with("energy_change_j", change)
                .help(
                    "Kinetic plus potential energy now, less at the release. With no damping it should stay \
                 near zero: what it drifts by is the integrator's and the rods' error.",
                ),
        ];
        if let Some((period, exact)) = self.predicted_periods() {
            // Small swings only; a release far from the bottom swings more slowly.
            out.push(
                Readout::new("period of small swings 2π√(L/g)", format!("{period:.3} s"))
                    .with("period_predicted_s", period)
                    .help(
                        "The textbook's period, 2π√(L/g): exact only for swings so small that sin θ ≈ θ. \
                         Leaves out the amplitude (a 90° release swings about 18% slower), damping and \
                         the bob's size.",
                    ),
            );
            if let Some(exact) = exact {
                out.push(
                    Readout::new("period at this amplitude 4√(L/g)·K(sin θ₀/2)", format!("{exact:.3} s"))
                        .with_f64("period_exact_s", exact)
                        .help(
                            "The exact period of an ideal pendulum released at θ₀: 4√(L/g)·K(sin(θ₀/2)), K \
                             the complete elliptic integral of the first kind. Leaves out damping and the \
                             bob's size (a point mass on a massless rod).",
                        ),
                );
            }
            if let Some(measured) = self.measured_period() {
                out.push(
                    Readout::new("period measured over the last swing", format!("{measured:.3} s"))
                        .with_f64("period_s", measured)
                        .help(
                            "Measured: the time between the bob's last two crossings of the vertical below \
                             the pivot moving the same way, each placed within its step where it falls.",
                        ),
                );
            }
        }
        out
    }
}

//! cradle: Newton's cradle. `balls` equal spheres hang on cables from a row of anchors,
//! touching at rest; the first `lifted` are pulled back to `angle` and let go. With
//! restitution 1 the blow passes down the row and as many balls leave at the far end as
//! came in: the soft solver's impact stage bounces one pair at a time.
//!
//! The balls are particles 0.. in order along the row (left to right), so the lifted
//! ones come first and particle 0 is the outermost.

use std::borrow::Cow;

use glam::Vec3;

use super::runs::{Column, Runs, Table};
use super::{CameraHint, Param, ParamError, ParamTable, ParamValues, Scene, SceneEntry, SceneInfo};
use crate::physics::{Constraint, ParticleDesc, PhysicsError, ResolveReport, SphereCollisions, World};

/// Ball radius (m).
const RADIUS: f32 = 0.1;
/// Cable length (m).
const CABLE: f32 = 1.0;
/// Height of the anchors (m).
const TOP: f32 = 1.6;

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("balls"), unit: Cow::Borrowed(""), default: 5.0, min: 2.0, max: 9.0, help: Cow::Borrowed("Number of balls in the row (rounded)"), logarithmic: false, integer: true },
    Param { name: Cow::Borrowed("lifted"), unit: Cow::Borrowed(""), default: 1.0, min: 1.0, max: 8.0, help: Cow::Borrowed("Balls pulled back and released (rounded; at most balls - 1)"), logarithmic: false, integer: true },
    Param { name: Cow::Borrowed("angle"), unit: Cow::Borrowed("°"), default: 30.0, min: 1.0, max: 80.0, help: Cow::Borrowed("How far the lifted balls are pulled back on their cables"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("restitution"), unit: Cow::Borrowed(""), default: 1.0, min: 0.0, max: 1.0, help: Cow::Borrowed("Coefficient of restitution between the balls"), logarithmic: false, integer: false },
    super::GRAVITY,
];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("cradle"),
    summary: Cow::Borrowed("Newton's cradle: as many balls leave as came in"),
    dt: 1.0 / 240.0,
    default_steps: 2400,
    params: ParamTable::Static(PARAMS),
    presets: &[],
    actions: &[],
    trails: false,
    color_by_speed: false,
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

fn create(params: ParamValues) -> Box<dyn Scene> {
    Box::new(Cradle::build(params))
}

/// The columns of the cradle's table of runs: a row for each release, once the far
/// end's first swing out has reached its highest point.
pub static RUN_COLUMNS: &[Column] = &[
    Column { key: "balls", heading: "balls", help: "Balls in the row", always: false },
    Column { key: "lifted", heading: "lifted", help: "Balls pulled back and released", always: true },
    Column { key: "angle_deg", heading: "lifted to (°)", help: "The lifted balls' angle", always: true },
    Column {
        key: "restitution",
        heading: "e",
        help: "Coefficient of restitution between the balls",
        always: true,
    },
    Column { key: "g_m_s2", heading: "g (m/s²)", help: "Gravitational acceleration", always: false },
    Column {
        key: "balls_out",
        heading: "swung out",
        help: "Measured: balls at the far end that swung out, when the outermost reached its highest point \
               (those out by at least half as far as it)",
        always: true,
    },
    Column {
        key: "out_angle_deg",
        heading: "out to (°)",
        help: "Measured: the outermost ball's cable angle at the highest point of its first swing out",
        always: true,
    },
    Column {
        key: "balls_out_predicted",
        heading: "predicted out",
        help: "Predicted for elastic balls (e = 1), from momentum and energy kept: as many as came in. Leaves \
               out restitution below 1, after which more balls move with less",
        always: true,
    },
    Column {
        key: "out_angle_predicted_deg",
        heading: "predicted angle (°)",
        help: "Predicted for elastic balls (e = 1): as high as they were lifted. Leaves out restitution below 1 \
               and the cables' give",
        always: true,
    },
];

/// The number of balls, and of lifted balls: `lifted` is held to `balls - 1` (a
/// parameter range cannot depend on another parameter, so the scene clamps it and its
/// read-out says so).
fn counts(params: &ParamValues) -> (usize, usize) {
    let balls = params.get("balls").round().clamp(2.0, 9.0) as usize;
    let lifted = (params.get("lifted").round().max(1.0) as usize).min(balls - 1);
    (balls, lifted)
}

/// Anchor of ball `i` of `balls`, the row centred on x = 0.
fn anchor(i: usize, balls: usize) -> Vec3 {
    Vec3::new((i as f32 - (balls as f32 - 1.0) / 2.0) * 2.0 * RADIUS, TOP, 0.0)
}

struct Cradle {
    world: World,
    params: ParamValues,
    /// The outermost ball's velocity along the row after the last step, to catch it
    /// turning back at the top of its swing out.
    far_speed: f32,
    /// Whether this release's outcome is in the table.
    measured: bool,
    /// The table of runs, in [`RUN_COLUMNS`].
    runs: Runs,
}

impl Cradle {
    fn build(params: ParamValues) -> Self {
        let (balls, lifted) = counts(&params);
        let angle = params.get("angle").to_radians();
        let g = params.get("g");
        let mut world = World::new();
        for i in 0..balls {
            let top = anchor(i, balls);
            // Lifted balls swing back (to -x) on their taut cables, still touching.
            let swing = if i < lifted { angle } else { 0.0 };
            let position = top + Vec3::new(-swing.sin(), -swing.cos(), 0.0) * CABLE;
            let ball = world
                .add_particle(ParticleDesc {
                    position,
                    acceleration: Vec3::new(0.0, -g, 0.0),
                    mass: 1.0,
                    radius: RADIUS,
                    ..ParticleDesc::default()
                })
                .expect("parameter ranges keep every ball valid");
            world
                .add_contact_generator(Constraint::support_cable(ball, top, CABLE, 0.0))
                .expect("a constant cable is valid");
        }
        world
            .add_contact_generator(SphereCollisions::elastic(params.get("restitution")))
            .expect("restitution is range-checked");
        Self { world, params, far_speed: 0.0, measured: false, runs: Runs::new(RUN_COLUMNS) }
    }

    /// Each ball's displacement along the row from under its anchor (m).
    fn displacements(&self) -> Vec<f32> {
        let balls = self.world.particles.len();
        self.world.particles.positions().iter().enumerate().map(|(i, p)| p.x - anchor(i, balls).x).collect()
    }

    /// Watches the far end: when the outermost ball, having swung out, turns back, the
    /// release's outcome goes in the table.
    fn watch_the_far_end(&mut self) {
        let balls = self.world.particles.len();
        let Some(&v) = self.world.particles.velocities().last() else { return };
        let out = self.displacements();
        let far = out[balls - 1];
        if !self.measured && self.far_speed > 0.0 && v.x <= 0.0 && far > 0.0 {
            self.measured = true;
            let swung = out.iter().filter(|&&dx| dx > 0.5 * far).count();
            let p = self.world.particles.positions()[balls - 1];
            let angle = far.atan2(anchor(balls - 1, balls).y - p.y).to_degrees();
            let (_, lifted) = counts(&self.params);
            let row = vec![
                balls as f64,
                lifted as f64,
                f64::from(self.params.get("angle")),
                f64::from(self.params.get("restitution")),
                f64::from(self.params.get("g")),
                swung as f64,
                f64::from(angle),
                lifted as f64,
                f64::from(self.params.get("angle")),
            ];
            self.runs.push(row);
        }
        self.far_speed = v.x;
    }
}

impl Scene for Cradle {
    fn gravity_reference(&self) -> Option<(f32, &'static str)> {
        Some((TOP - CABLE, "the balls' rest height"))
    }

    scene_basics!();

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        let mut params = self.params.clone();
        params.set(name, value)?;
        if name == "g" {
            super::pull_down(&mut self.world, value);
            self.params = params;
        } else {
            // Anything else changes the row or its release: start again, the table kept.
            let mut running = std::mem::replace(self, Self::build(params));
            super::keep_solver(&running.world, &mut self.world);
            std::mem::swap(&mut self.runs, &mut running.runs);
        }
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        let report = self.world.step(dt)?;
        self.watch_the_far_end();
        Ok(report)
    }

    fn save_state(&self) -> serde_json::Value {
        serde_json::json!({ "far_speed": self.far_speed, "measured": self.measured, "runs": self.runs.saved() })
    }

    fn restore_state(&mut self, state: &super::RawValue) -> Result<(), String> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Saved {
            far_speed: f32,
            measured: bool,
            runs: Vec<Vec<Option<f64>>>,
        }
        // Snapshots from before the table of runs hold null: nothing measured there.
        if state.get() == "null" {
            (self.far_speed, self.measured, self.runs) = (0.0, true, Runs::new(RUN_COLUMNS));
            return Ok(());
        }
        let saved: Saved = super::read_state(state)?;
        if !saved.far_speed.is_finite() {
            return Err(format!("far_speed = {} is not a speed", saved.far_speed));
        }
        let runs = self.runs.read(saved.runs)?;
        (self.far_speed, self.measured) = (saved.far_speed, saved.measured);
        self.runs = runs;
        Ok(())
    }

    fn runs(&self) -> Option<Table<'_>> {
        Some(self.runs.table())
    }

    fn delete_runs(&mut self, which: Option<usize>) -> bool {
        self.runs.delete(which);
        true
    }

    fn camera(&self) -> CameraHint {
        CameraHint { target: Vec3::new(0.0, TOP - 0.6, 0.0), distance: 3.6, yaw: 0.0, pitch: 0.08 }
    }

    fn readout_rows(&self, _dt: f32) -> Vec<super::Readout> {
        use super::Readout;
        let (balls, lifted) = counts(&self.params);
        let asked = self.params.get("lifted").round() as usize;
        let lifted_text = if asked > lifted {
            format!("{lifted} of {balls} (asked {asked}; at most balls - 1)")
        } else {
            format!("{lifted} of {balls}")
        };
        // The speed the lifted balls reach at the bottom, √(2 g L (1 - cos θ)).
        let (g, angle) = (self.params.get("g"), self.params.get("angle").to_radians());
        let arriving = (2.0 * g * CABLE * (1.0 - angle.cos())).sqrt();
        vec![
            Readout::new("lifted", lifted_text)
                .with("lifted", lifted as f32)
                .with("balls", balls as f32)
                .with("lifted_asked", asked as f32)
                .help("Balls pulled aside and let go together; the same number should swing out at the far end"),
            Readout::new("speed at the bottom", format!("{arriving:.3} m/s"))
                .with("speed_at_bottom_predicted_m_s", arriving)
                .help(
                    "Predicted speed of the lifted balls at the bottom, from energy: v = √(2 g L (1 − cos θ)), L \
                     the cable's length and θ the lift angle. Leaves out damping and the cables' stretch.",
                ),
        ]
    }
}

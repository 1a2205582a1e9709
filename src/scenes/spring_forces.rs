//! springForces: a bob on an anchored spring, and beside it one example of every other
//! spring-like generator: a free spring between two particles, a bungee, a float in
//! water and a closed-form stiff spring.

use std::borrow::Cow;

use glam::{DVec3, Vec2, Vec3};

use super::ghost::{GHOST_COLOR, Ghost, Motion};
use super::runs::{Column, Runs, Table};
use super::{
    CameraHint, Marker, Param, ParamError, ParamTable, ParamValues, Scene, SceneEntry, SceneInfo, Water,
};
use crate::physics::exact::{SpringMotion, damping_rate};
use crate::physics::{
    Buoyancy, ForceId, GroundPlane, ParticleDesc, ParticleId, PhysicsError, ResolveReport, SphereCollisions,
    Spring, StiffSpring, World,
};

/// Where the bob's spring is fixed (m).
pub const BOB_ANCHOR: Vec3 = Vec3::new(-6.0, 7.0, 0.0);
/// How far left of the bob's anchor its ruler stands (m).
const RULER_OFFSET: f32 = 1.2;

/// Where the bungee is fixed (m).
pub const BUNGEE_ANCHOR: Vec3 = Vec3::new(3.0, 7.0, 0.0);
/// Where the stiff spring is fixed (m).
pub const STIFF_ANCHOR: Vec3 = Vec3::new(11.0, 4.0, 0.0);
/// The pool the float sits in.
pub const POOL: Water = Water { height: 1.5, center: Vec2::new(7.0, 0.0), half_extent: Vec2::new(1.5, 1.5) };
/// Volume of the float (m³): half submerged at 1 kg in water.
const FLOAT_VOLUME: f32 = 0.002;
const RADIUS: f32 = 0.3;

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("k"), unit: Cow::Borrowed("N/m"), default: 20.0, min: 1.0, max: 500.0, help: Cow::Borrowed("Spring constant of the springs and the bungee"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("rest_length"), unit: Cow::Borrowed("m"), default: 2.0, min: 0.5, max: 4.0, help: Cow::Borrowed("Length at which the springs exert no force"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("mass"), unit: Cow::Borrowed("kg"), default: 1.0, min: 0.1, max: 10.0, help: Cow::Borrowed("Mass of every particle in the scene"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("damping"), unit: Cow::Borrowed(""), default: 0.99, min: 0.5, max: 1.0, help: Cow::Borrowed("Fraction of velocity kept per second (1 = no damping)"), logarithmic: false, integer: false },
    super::GRAVITY,
    Param { name: Cow::Borrowed("stiff_k"), unit: Cow::Borrowed("N/m"), default: 10_000.0, min: 10.0, max: 1_000_000.0, help: Cow::Borrowed("Stiffness of the closed-form stiff spring (stable at any value)"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("stiff_zeta"), unit: Cow::Borrowed(""), default: 0.05, min: 0.0, max: 2.0, help: Cow::Borrowed("Damping ratio of the stiff spring (0 rings forever, 1 critical); apart from `damping`"), logarithmic: false, integer: false },
];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("springForces"),
    summary: Cow::Borrowed("A bob on a spring, a free spring, a bungee, buoyancy and a stiff spring"),
    dt: 1.0 / 240.0,
    default_steps: 1200,
    params: ParamTable::Static(PARAMS),
    ..super::TRACED
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

fn create(params: ParamValues) -> Box<dyn Scene> {
    Box::new(SpringForces::build(params).expect("parameter ranges keep every particle valid"))
}

/// The columns of springForces' table of runs: a row each time the bob's first whole
/// period is timed after it starts (opening, or a slider that starts it again).
pub static RUN_COLUMNS: &[Column] = &[
    Column { key: "k_n_m", heading: "k (N/m)", help: "Spring constant", always: true },
    Column { key: "mass_kg", heading: "m (kg)", help: "Mass of the bob", always: true },
    Column {
        key: "rest_length_m",
        heading: "rest length (m)",
        help: "The spring's rest length",
        always: false,
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
        help: "Measured: the bob's first whole period, between two turns at the bottom of its swing",
        always: true,
    },
    Column {
        key: "period_predicted_s",
        heading: "2π√(m/k) (s)",
        help: "Predicted: leaves out damping, which makes a swing slightly longer",
        always: true,
    },
];

struct SpringForces {
    world: World,
    params: ParamValues,
    bob: ParticleId,
    float_force: ForceId,
    float: ParticleId,
    /// The bob's exact twin: the damped harmonic oscillator about where the spring
    /// holds its weight (it moves on the vertical line under its anchor).
    ghost: Option<Ghost>,
    /// The stopwatch on the bob: its vertical velocity after the last step, the last
    /// time it turned at the bottom (s), and the period between the last two turns.
    stopwatch: (f32, Option<f64>, Option<f64>),
    /// Whether the bob's first period since it started has been timed (and tabled).
    timed: bool,
    /// The table of runs, in [`RUN_COLUMNS`].
    runs: Runs,
}

impl SpringForces {
    fn build(params: ParamValues) -> Result<Self, PhysicsError> {
        let (k, rest, mass) = (params.get("k"), params.get("rest_length"), params.get("mass"));
        let (damping, g) = (params.get("damping"), params.get("g"));
        let mut world = World::new();
        let mut add = |position: Vec3| {
            world.add_particle(ParticleDesc {
                position,
                acceleration: Vec3::new(0.0, -g, 0.0),
                mass,
                damping,
                radius: RADIUS,
                ..ParticleDesc::default()
            })
        };
        // The bob starts at rest with its spring at rest length, so gravity sets it going.
        let bob = add(BOB_ANCHOR - Vec3::Y * rest)?;
        // Two particles on the ground joined by a spring stretched by half its length.
        let left = add(Vec3::new(-3.0, RADIUS, 0.0))?;
        let right = add(Vec3::new(-3.0 + 1.5 * rest, RADIUS, 0.0))?;
        // The bungee's particle starts beside its anchor: it falls slack, then is caught.
        let jumper = add(BUNGEE_ANCHOR + Vec3::new(0.5, 0.0, 0.0))?;
        let float = add(Vec3::new(POOL.center.x, POOL.height + 2.5, POOL.center.y))?;
        let stiff = add(STIFF_ANCHOR + Vec3::new(0.8, 0.0, 0.0))?;

        world.add_force(Spring::anchored(bob, BOB_ANCHOR, k, rest))?;
        world.add_force(Spring::between(left, right, k, rest))?;
        world.add_force(Spring::anchored(jumper, BUNGEE_ANCHOR, k, rest).as_bungee())?;
        let float_force = world.add_force(float_buoyancy(float, g))?;
        world.add_force(StiffSpring::new(
            stiff,
            STIFF_ANCHOR,
            params.get("stiff_k"),
            params.get("stiff_zeta"),
        ))?;
        world.add_contact_generator(GroundPlane { height: 0.0, restitution: 0.2 })?;
        world.add_contact_generator(SphereCollisions::elastic(0.5))?;
        let mut scene = Self {
            world,
            params,
            bob,
            float_force,
            float,
            ghost: None,
            stopwatch: (0.0, None, None),
            timed: false,
            runs: Runs::new(RUN_COLUMNS),
        };
        scene.ghost = Ghost::new(&scene.world, bob, scene.bob_motion());
        Ok(scene)
    }

    /// The stopwatch: the bob turns at the bottom when its vertical velocity goes from
    /// down to up; the time between two turns is the period. The turn is placed
    /// between the two steps by where the velocity crosses zero.
    fn time_the_bob(&mut self, dt: f32) {
        let Some(i) = self.world.particles.index(self.bob) else { return };
        let vy = self.world.particles.velocities()[i].y;
        let (before, last_turn, _) = self.stopwatch;
        if before < 0.0 && vy >= 0.0 {
            let fraction = f64::from(-before / (vy - before));
            let turn = self.world.time() - f64::from(dt) * (1.0 - fraction);
            self.stopwatch.2 = last_turn.map(|t| turn - t);
            self.stopwatch.1 = Some(turn);
            if let (false, Some(period)) = (self.timed, self.stopwatch.2) {
                self.timed = true;
                self.add_run(period);
            }
        }
        self.stopwatch.0 = vy;
    }

    /// The spring's period 2π√(m/k) (s).
    fn predicted_period(&self) -> f32 {
        2.0 * std::f32::consts::PI * (self.params.get("mass") / self.params.get("k")).sqrt()
    }

    /// Puts the bob's first timed period since it started in the table.
    fn add_run(&mut self, period: f64) {
        let p = |name| f64::from(self.params.get(name));
        let row = vec![
            p("k"),
            p("mass"),
            p("rest_length"),
            p("g"),
            p("damping"),
            period,
            f64::from(self.predicted_period()),
        ];
        self.runs.push(row);
    }

    /// Heights (m) of the bob's natural-length line and of its equilibrium, `m g / k`
    /// below it.
    fn bob_lines(&self) -> (f32, f32) {
        let natural = BOB_ANCHOR.y - self.params.get("rest_length");
        let sag = self.params.get("mass") * self.params.get("g") / self.params.get("k");
        (natural, natural - sag)
    }

    /// The closed form of the bob's motion with the current parameters.
    fn bob_motion(&self) -> Motion {
        let p = &self.params;
        Motion::Spring(SpringMotion {
            anchor: BOB_ANCHOR.as_dvec3(),
            rest_offset: DVec3::new(0.0, -f64::from(p.get("rest_length")), 0.0),
            k: f64::from(p.get("k")),
            m: f64::from(p.get("mass")),
            g: DVec3::new(0.0, -f64::from(p.get("g")), 0.0),
            lambda: damping_rate(p.get("damping")),
        })
    }

    /// After a parameter change that keeps the world: the bob's ghost starts again
    /// from where the bob is, under the new parameters.
    fn restart_ghost(&mut self) {
        self.stopwatch = (0.0, None, None);
        self.timed = false;
        let motion = self.bob_motion();
        if let Some(ghost) = &mut self.ghost {
            ghost.restart(&self.world, motion);
        }
    }
}

fn float_buoyancy(target: ParticleId, g: f32) -> Buoyancy {
    Buoyancy { target, surface: POOL.height, half_height: RADIUS, volume: FLOAT_VOLUME, density: 1000.0, g }
}

/// How the bob's period is timed.
const PERIOD_HELP: &str = "Measured: the time between the bob's last two turns at the bottom of its swing \
    (its vertical velocity going from down to up), each placed within its step where it falls.";

/// What the bob's distance from its exact path is.
const EXACT_HELP: &str = "How far the bob is from the exact solution of its motion (the ghost), a damped \
    oscillation computed in closed form from the same start: the integrator's error so far.";

impl Scene for SpringForces {
    scene_basics!();

    fn energy_focus(&self) -> Option<(ParticleId, &'static str)> {
        Some((self.bob, "the bob"))
    }

    fn save_state(&self) -> serde_json::Value {
        serde_json::json!({ "ghost": self.ghost, "stopwatch": self.stopwatch, "timed": self.timed, "runs": self.runs.saved() })
    }

    fn restore_state(&mut self, state: &super::RawValue) -> Result<(), String> {
        #[derive(serde::Deserialize)]
        struct Saved {
            ghost: Option<Ghost>,
            stopwatch: (f32, Option<f64>, Option<f64>),
            // Snapshots from before the table of runs have neither.
            #[serde(default)]
            timed: Option<bool>,
            #[serde(default)]
            runs: Vec<Vec<Option<f64>>>,
        }
        let saved: Saved = super::read_state(state)?;
        let runs = self.runs.read(saved.runs)?;
        (self.ghost, self.stopwatch) = (saved.ghost, saved.stopwatch);
        // An old snapshot that had timed a period already did not table it: leave it so.
        self.timed = saved.timed.unwrap_or(self.stopwatch.2.is_some());
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

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        let mut params = self.params.clone();
        params.set(name, value)?;
        match name {
            "g" => {
                super::pull_down(&mut self.world, value);
                self.world
                    .forces
                    .replace(self.float_force, Box::new(float_buoyancy(self.float, value)))
                    .expect("g is range-checked, so the float's buoyancy is valid");
                self.params = params;
                self.restart_ghost();
            }
            "mass" => {
                let ids = self.world.particles.ids().to_vec();
                for id in ids {
                    self.world.particles.set_mass(id, value).expect("range checked above");
                }
                self.params = params;
                self.restart_ghost();
            }
            "damping" => {
                super::damp_all(&mut self.world, value);
                self.params = params;
                self.restart_ghost();
            }
            // Spring constants and lengths shape the whole scene: start it again.
            _ => {
                let restarted = Self::build(params).expect("parameter ranges keep every particle valid");
                let mut running = std::mem::replace(self, restarted);
                super::keep_solver(&running.world, &mut self.world);
                std::mem::swap(&mut self.runs, &mut running.runs);
            }
        }
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        if let Some(ghost) = &mut self.ghost {
            ghost.before_step(&self.world);
        }
        let report = self.world.step(dt)?;
        if let Some(ghost) = &mut self.ghost {
            ghost.after_step(&self.world);
        }
        self.time_the_bob(dt);
        Ok(report)
    }

    fn water(&self) -> Option<Water> {
        Some(POOL)
    }

    fn labels<'a>(&'a self, out: &mut Vec<(Vec3, &'a str)>) {
        // The objects first: where labels crowd, the view keeps the earlier ones.
        let p = self.world.particles.positions();
        let named = [(0, "bob"), (1, "free spring"), (3, "bungee"), (4, "float"), (5, "stiff spring")];
        for (i, name) in named {
            if let Some(&position) = p.get(i) {
                out.push((position + Vec3::Y * (RADIUS + 0.25), name));
            }
        }
        let (natural, equilibrium) = self.bob_lines();
        // Beside the lines' right ends, so they do not cover the bob.
        // The natural length's name above its line, the equilibrium's below its own, so
        // the two stay apart however little the spring sags.
        out.push((Vec3::new(BOB_ANCHOR.x + 1.6, natural + 0.05, 0.0), "natural length"));
        out.push((Vec3::new(BOB_ANCHOR.x + 1.5, equilibrium - 0.35, 0.0), "equilibrium"));
    }

    fn ruler(&self) -> Option<super::Ruler> {
        Some(super::Ruler { foot: Vec3::new(BOB_ANCHOR.x - RULER_OFFSET, 0.0, 0.0), height: BOB_ANCHOR.y })
    }

    /// The bob's natural-length line (where its spring exerts no force) and equilibrium
    /// line (where the spring holds its weight, `m g / k` lower); the ruler beside them
    /// is [`Scene::ruler`].
    fn outlines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        let (natural, equilibrium) = self.bob_lines();
        for y in [natural, equilibrium] {
            out.push((Vec3::new(BOB_ANCHOR.x - 0.7, y, 0.0), Vec3::new(BOB_ANCHOR.x + 0.7, y, 0.0)));
        }
    }

    fn predictions(&self, out: &mut Vec<Marker>) {
        if let Some(ghost) = &self.ghost {
            out.push(Marker {
                position: ghost.position(&self.world),
                radius: 0.8 * RADIUS,
                color: GHOST_COLOR,
            });
        }
    }

    fn camera(&self) -> CameraHint {
        CameraHint { target: Vec3::new(2.5, 3.5, 0.0), distance: 19.0, yaw: 0.0, pitch: 0.3 }
    }

    fn param_warning(&self, name: &str, h: f32) -> Option<String> {
        if !matches!(name, "k" | "mass") {
            return None;
        }
        // Semi-implicit Euler on a spring is stable while ω·h < 2; warn from 1.
        let omega_h = (self.params.get("k") / self.params.get("mass")).sqrt() * h;
        if omega_h >= 2.0 {
            Some(format!("ω·h = {omega_h:.2} ≥ 2: the springs explode; lower k, raise the mass or the rate"))
        } else if omega_h >= 1.0 {
            Some(format!("ω·h = {omega_h:.2}: the springs blow up at 2"))
        } else {
            None
        }
    }

    fn exact_error(&self) -> Option<f32> {
        self.ghost.as_ref().and_then(|ghost| ghost.error(&self.world))
    }

    fn readout_rows(&self, dt: f32) -> Vec<super::Readout> {
        use super::Readout;
        let (k, mass) = (self.params.get("k"), self.params.get("mass"));
        let omega = (k / mass).sqrt();
        let stiff_omega = (self.params.get("stiff_k") / mass).sqrt();
        let verdict = |w: f32| if w * dt < 2.0 { "stable" } else { "would explode explicitly" };
        let bob_y = self.world.particles.index(self.bob).map_or(0.0, |i| self.world.particles.position[i].y);
        let predicted = std::f32::consts::TAU / omega;
        let measured = match self.stopwatch.2 {
            Some(period) => Readout::new("bob's period, measured", format!("{period:.3} s"))
                .with_f64("period_s", period)
                .help(PERIOD_HELP),
            None => Readout::new("bob's period, measured", "timing…").help(PERIOD_HELP),
        };
        let error = match self.exact_error() {
            Some(e) => Readout::new("bob from its exact path", format!("{:.2} mm", e * 1000.0))
                .with("exact_path_error_m", e)
                .help(EXACT_HELP),
            None => Readout::new("bob from its exact path", "—").help(EXACT_HELP),
        };
        vec![
            Readout::new("spring period 2π√(m/k)", format!("{predicted:.3} s"))
                .with("period_predicted_s", predicted)
                .help(
                    "The period of a mass m on a spring of stiffness k: 2π√(m/k). Leaves out damping, \
                     which makes a swing slightly longer.",
                ),
            measured,
            Readout::new("spring ω·dt (explicit limit 2)", format!("{:.3} ({})", omega * dt, verdict(omega)))
                .with("omega_dt", omega * dt)
                .help(
                    "The spring's angular frequency ω = √(k/m) times the step: explicit Euler blows up \
                     above 2, and every integrator gets less accurate as it grows.",
                ),
            Readout::new(
                "stiff spring ω·dt",
                format!("{:.2} ({}; solved exactly)", stiff_omega * dt, verdict(stiff_omega)),
            )
            .with("stiff_omega_dt", stiff_omega * dt)
            .help(
                "The same number for the stiff spring, which the paper solves in closed form each step, \
                 so it stays stable however large it is.",
            ),
            Readout::new("bob height", format!("{bob_y:.3} m"))
                .with("bob_height_m", bob_y)
                .help("Height of the bob's centre above the ground"),
            error,
        ]
    }
}

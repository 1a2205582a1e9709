//! projectile: rounds fired from a launcher, as in the paper (g exaggerated to 20 m/s²,
//! 200 kg, damping 0.99) with Cyclone's ammo types as presets.

use std::borrow::Cow;

use glam::Vec3;

use super::ghost::{GHOST_COLOR, Ghost, Motion};
use super::{
    ActionInfo, CameraHint, Marker, Param, ParamError, ParamTable, ParamValues, Preset, Scene, SceneAction,
    SceneEntry, SceneInfo,
};
use crate::physics::exact::damping_rate;
use crate::physics::{Drag, ParticleDesc, ParticleId, PhysicsError, ResolveReport, SphereCollisions, World};

/// A round that can never land ([`can_land`]) is removed this old (s), as in Cyclone's
/// ballistic demo; one that can is kept until it lands, however long it flies.
pub const MAX_AGE: f64 = 5.0;
/// A round that can never land is removed this far from the launcher (m); one that can
/// is kept until it lands, however far it flies.
pub const MAX_DISTANCE: f32 = 200.0;
/// Slowest fall (m/s) that still counts as falling when gravity does not pull a round
/// down: drag alone slows such a round's fall for ever without stopping it.
pub const LANDING_FALL_SPEED: f32 = 1e-3;
/// Most dots drawn of the next round's predicted path; a long flight gets them further
/// apart than the usual [`PATH_INTERVAL`].
pub const PREDICTED_DOTS: usize = 200;
/// How much of a never-landing round's predicted flight is drawn (s).
pub const UNLANDED_SHOWN: f32 = 8.0;
/// Drawn and collision radius of a round (m).
pub const ROUND_RADIUS: f32 = 0.3;
/// Half the width of the target (m): a round landing this close to its centre hits.
pub const TARGET_HALF_WIDTH: f32 = 1.5;
/// Flights whose paths are kept and drawn, newest last.
pub const FLIGHTS_KEPT: usize = 5;
/// Time between the points kept of a flight's path (s).
pub const PATH_INTERVAL: f64 = 0.1;

/// A round's flight as recorded for the view: its path, and where it was launched,
/// peaked and landed. Times are since launch (s); positions in metres.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Flight {
    /// The round, while it flies.
    pub round: Option<ParticleId>,
    /// Points of the path, every [`PATH_INTERVAL`].
    pub path: Vec<(f64, Vec3)>,
    /// Where and when it left the launcher.
    pub launch: (f64, Vec3),
    /// Its highest point, once it started down.
    pub apex: Option<(f64, Vec3)>,
    /// Where and when it reached the ground (y = 0), if it did.
    pub landing: Option<(f64, Vec3)>,
    /// Its last recorded state: time, position, vertical velocity.
    last: (f64, Vec3, f32),
}

impl Flight {
    /// Hit or miss of the target whose centre is at `target` on the ground; `None`
    /// before landing.
    #[must_use]
    pub fn hit(&self, target: Vec3) -> Option<bool> {
        self.landing.map(|(_, p)| (p.x - target.x).abs() <= TARGET_HALF_WIDTH)
    }
}

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("g"), unit: Cow::Borrowed("m/s²"), default: 20.0, min: -5.0, max: 50.0, help: Cow::Borrowed("Gravitational acceleration, downwards (negative floats up)"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("speed"), unit: Cow::Borrowed("m/s"), default: 25.0, min: 0.0, max: 200.0, help: Cow::Borrowed("Launch speed of the next round"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("angle"), unit: Cow::Borrowed("°"), default: 45.0, min: -90.0, max: 90.0, help: Cow::Borrowed("Launch elevation above the horizontal"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("mass"), unit: Cow::Borrowed("kg"), default: 200.0, min: 0.1, max: 1000.0, help: Cow::Borrowed("Mass of the next round (matters when rounds collide)"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("damping"), unit: Cow::Borrowed(""), default: 0.99, min: 0.5, max: 1.0, help: Cow::Borrowed("Fraction of velocity a round keeps per second (1 = no drag)"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("height"), unit: Cow::Borrowed("m"), default: 1.5, min: 0.0, max: 50.0, help: Cow::Borrowed("Height of the launcher above the ground"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("k1"), unit: Cow::Borrowed("N·s/m"), default: 0.0, min: 0.0, max: 100.0, help: Cow::Borrowed("Linear drag of the next round, F = -k1 v (the paper's drag)"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("k2"), unit: Cow::Borrowed("N·s²/m²"), default: 0.0, min: 0.0, max: 10.0, help: Cow::Borrowed("Quadratic drag of the next round, F = -k2 |v| v"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("target"), unit: Cow::Borrowed("m"), default: 30.0, min: 1.0, max: 190.0, help: Cow::Borrowed("Distance of the target on the ground from the launcher"), logarithmic: false, integer: false },
];

#[rustfmt::skip]
static PRESETS: &[Preset] = &[
    Preset { name: "paper", help: "The paper's round: 200 kg, g = 20 m/s²", values: &[("g", 20.0), ("speed", 25.0), ("angle", 45.0), ("mass", 200.0), ("damping", 0.99)] },
    Preset { name: "pistol", help: "2 kg at 35 m/s, weak gravity", values: &[("g", 1.0), ("speed", 35.0), ("angle", 0.0), ("mass", 2.0), ("damping", 0.99)] },
    Preset { name: "artillery", help: "200 kg at (40, 30) m/s, g = 20 m/s²", values: &[("g", 20.0), ("speed", 50.0), ("angle", 36.869_9), ("mass", 200.0), ("damping", 0.99)] },
    Preset { name: "fireball", help: "1 kg at 10 m/s that floats upwards", values: &[("g", -0.6), ("speed", 10.0), ("angle", 0.0), ("mass", 1.0), ("damping", 0.9)] },
    Preset { name: "laser", help: "0.1 kg at 100 m/s, no gravity", values: &[("g", 0.0), ("speed", 100.0), ("angle", 0.0), ("mass", 0.1), ("damping", 0.99)] },
    Preset { name: "Earth", help: "g = 9.81 m/s², the round unchanged", values: &[("g", 9.81)] },
    Preset { name: "Moon", help: "g = 1.62 m/s², the round unchanged", values: &[("g", 1.62)] },
    Preset { name: "Mars", help: "g = 3.71 m/s², the round unchanged", values: &[("g", 3.71)] },
    Preset { name: "Jupiter", help: "g = 24.79 m/s², the round unchanged", values: &[("g", 24.79)] },
];

#[rustfmt::skip]
static ACTIONS: &[ActionInfo] = &[ActionInfo { label: "Fire", key: "F", action: SceneAction::Fire }];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("projectile"),
    summary: Cow::Borrowed("Rounds fired from a launcher: semi-implicit Euler with gravity and damping"),
    dt: 1.0 / 240.0,
    default_steps: 600,
    params: ParamTable::Static(PARAMS),
    presets: PRESETS,
    actions: ACTIONS,
    trails: true,
    color_by_speed: false,
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

fn create(params: ParamValues) -> Box<dyn Scene> {
    let mut world = World::new();
    world.add_contact_generator(SphereCollisions::elastic(0.8)).expect("a constant restitution in range");
    let mut scene = Projectile { world, params, rounds: Vec::new(), ghosts: Vec::new(), flights: Vec::new() };
    scene.fire().expect("default parameters describe a valid round");
    Box::new(scene)
}

struct Projectile {
    world: World,
    params: ParamValues,
    /// Live rounds and the time each was fired (s).
    rounds: Vec<(ParticleId, f64)>,
    /// The exact path of each round without quadratic drag (k2 = 0): the drag-free
    /// parabola, or its exponential form with linear drag and damping.
    ghosts: Vec<Ghost>,
    /// The last [`FLIGHTS_KEPT`] flights, newest last.
    flights: Vec<Flight>,
}

impl Projectile {
    fn gravity(&self) -> Vec3 {
        Vec3::new(0.0, -self.params.get("g"), 0.0)
    }

    fn launcher(&self) -> Vec3 {
        Vec3::new(0.0, self.params.get("height"), 0.0)
    }

    fn fire(&mut self) -> Result<ParticleId, PhysicsError> {
        let angle = self.params.get("angle").to_radians();
        let direction = Vec3::new(angle.cos(), angle.sin(), 0.0);
        let id = self.world.add_particle(ParticleDesc {
            position: self.launcher(),
            velocity: direction * self.params.get("speed"),
            acceleration: self.gravity(),
            mass: self.params.get("mass"),
            damping: self.params.get("damping"),
            radius: ROUND_RADIUS,
            immovable: false,
        })?;
        let (k1, k2) = (self.params.get("k1"), self.params.get("k2"));
        if k1 > 0.0 || k2 > 0.0 {
            // Its own drag generator, which goes when the round does.
            self.world.add_force(Drag { k1, k2, targets: vec![id] })?;
        }
        self.rounds.push((id, self.world.time()));
        if self.flights.len() == FLIGHTS_KEPT {
            self.flights.remove(0);
        }
        let (t, p, vy) = (self.world.time(), self.launcher(), direction.y * self.params.get("speed"));
        self.flights.push(Flight {
            round: Some(id),
            path: vec![(0.0, p)],
            launch: (t, p),
            last: (t, p, vy),
            ..Flight::default()
        });
        if k2 == 0.0 {
            let motion = self.motion(k1, self.params.get("mass"), self.params.get("damping"));
            self.ghosts.extend(Ghost::new(&self.world, id, motion));
        }
        Ok(id)
    }

    /// The target's centre, on the ground.
    fn target(&self) -> Vec3 {
        Vec3::new(self.launcher().x + self.params.get("target"), 0.0, 0.0)
    }

    /// Follows each flying round: a path point every [`PATH_INTERVAL`], the apex where
    /// its vertical velocity turns negative, the landing where it crosses y = 0 (both
    /// interpolated within the step).
    fn record_flights(&mut self) {
        let now = self.world.time();
        let particles = &self.world.particles;
        for flight in &mut self.flights {
            let Some(i) = flight.round.and_then(|id| particles.index(id)) else {
                flight.round = None;
                continue;
            };
            let (p, v) = (particles.positions()[i], particles.velocities()[i]);
            let (t0, p0, vy0) = flight.last;
            let launched = flight.launch.0;
            if flight.apex.is_none() && vy0 > 0.0 && v.y <= 0.0 {
                let f = vy0 / (vy0 - v.y);
                flight.apex = Some((t0 - launched + f64::from(f) * (now - t0), p0.lerp(p, f)));
            }
            if p.y <= 0.0 && p0.y > 0.0 {
                let f = p0.y / (p0.y - p.y);
                let at = p0.lerp(p, f);
                flight.landing =
                    Some((t0 - launched + f64::from(f) * (now - t0), Vec3::new(at.x, 0.0, at.z)));
                flight.round = None;
            }
            if flight.path.last().is_none_or(|(t, _)| now - launched - t >= PATH_INTERVAL - 1e-9) {
                flight.path.push((now - launched, p));
            }
            flight.last = (now, p, v.y);
        }
    }

    /// Where the next round would fly without drag (m): the launcher, then a point
    /// every [`PATH_INTERVAL`] of flight (further apart when more than
    /// [`PREDICTED_DOTS`] would be needed) until it lands, however far. A round that
    /// never lands (gravity off or upwards) is followed for [`UNLANDED_SHOWN`] or to
    /// [`MAX_DISTANCE`], whichever comes first.
    fn predicted_path(&self, out: &mut Vec<Vec3>) {
        let g = self.params.get("g");
        let angle = self.params.get("angle").to_radians();
        let launcher = self.launcher();
        let v = Vec3::new(angle.cos(), angle.sin(), 0.0) * self.params.get("speed");
        let flight = if g > 0.0 { ground_range_time(v.y, launcher.y, g) } else { UNLANDED_SHOWN };
        let interval = (PATH_INTERVAL as f32).max(flight / PREDICTED_DOTS as f32);
        out.push(launcher);
        for k in 1..=PREDICTED_DOTS {
            let t = k as f32 * interval;
            let p = launcher + v * t + Vec3::new(0.0, -0.5 * g * t * t, 0.0);
            if p.y < 0.0 || (g <= 0.0 && p.distance(launcher) > MAX_DISTANCE) {
                break;
            }
            out.push(p);
        }
    }

    /// The closed form of a round of mass `m` with linear drag `k1` and damping.
    fn motion(&self, k1: f32, m: f32, damping: f32) -> Motion {
        Motion::Projectile { g: self.gravity().as_dvec3(), lambda: f64::from(k1 / m) + damping_rate(damping) }
    }
}

impl Scene for Projectile {
    scene_basics!();

    fn keeps_particle(&self, _id: ParticleId) -> bool {
        // Every particle is a round, removed when it lands: a later world need not
        // hold the one fired at the start. The rounds the state names are checked.
        false
    }

    fn save_state(&self) -> serde_json::Value {
        serde_json::json!({ "rounds": self.rounds, "ghosts": self.ghosts, "flights": self.flights })
    }

    fn restore_state(&mut self, state: &super::RawValue) -> Result<(), String> {
        #[derive(serde::Deserialize)]
        struct Saved {
            rounds: Vec<(ParticleId, f64)>,
            ghosts: Vec<Ghost>,
            flights: Vec<Flight>,
        }
        let saved: Saved = super::read_state(state)?;
        let particles = &self.world.particles;
        if let Some((id, _)) = saved.rounds.iter().find(|(id, _)| particles.index(*id).is_none()) {
            return Err(format!("round {} is not a particle of the world", id.0));
        }
        // A round was fired at a time the world has passed: not before 0, not ahead of
        // the world's clock (its age decides when it is removed).
        let now = self.world.time();
        if let Some((id, fired)) = saved.rounds.iter().find(|(_, t)| !(*t >= 0.0 && *t <= now)) {
            let fired = if fired.abs() >= 1e6 { format!("{fired:e}") } else { format!("{fired}") };
            return Err(format!(
                "round {} was fired at t = {fired} s, outside 0 to the world's {now:.3} s",
                id.0
            ));
        }
        (self.rounds, self.ghosts, self.flights) = (saved.rounds, saved.ghosts, saved.flights);
        Ok(())
    }

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        self.params.set(name, value)?;
        if name == "g" {
            let gravity = self.gravity();
            self.world.set_acceleration_all(gravity).expect("g is range-checked");
            // Rounds in flight now fall differently: their ghosts start again from here.
            for ghost in &mut self.ghosts {
                if let Motion::Projectile { lambda, .. } = ghost.motion() {
                    ghost.restart(&self.world, Motion::Projectile { g: gravity.as_dvec3(), lambda });
                }
            }
        }
        // Launch settings apply to the next round fired.
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        for ghost in &mut self.ghosts {
            ghost.before_step(&self.world);
        }
        let report = self.world.step(dt)?;
        for ghost in &mut self.ghosts {
            ghost.after_step(&self.world);
        }
        self.record_flights();
        let now = self.world.time();
        let launcher = self.launcher();
        let g = self.params.get("g");
        let world = &mut self.world;
        self.rounds.retain(|&(id, fired)| {
            let Some(i) = world.particles.index(id) else { return false };
            let (p, v) = (world.particles.position[i], world.particles.velocity[i]);
            // A round goes when it lands, however far and long it flew; only one that
            // can never come down goes by Cyclone's age and distance limits.
            let lost = !can_land(g, v.y) && (now - fired > MAX_AGE || p.distance(launcher) > MAX_DISTANCE);
            let expired = p.y < 0.0 || lost;
            if expired {
                world.remove_particle(id);
            }
            !expired
        });
        let world = &self.world;
        self.ghosts.retain(|ghost| world.particles.index(ghost.particle).is_some());
        Ok(report)
    }

    fn act(&mut self, action: SceneAction) -> bool {
        match action {
            SceneAction::Fire => self.fire().is_ok(),
            SceneAction::MoveLoad { .. } => false,
        }
    }

    fn labels<'a>(&'a self, out: &mut Vec<(Vec3, &'a str)>) {
        out.push((self.launcher() + Vec3::new(0.0, 0.9, 0.0), "launcher"));
        out.push((self.target() + Vec3::new(0.0, 0.5, 0.0), "target"));
        let newest = self.rounds.last().and_then(|&(id, _)| self.world.particles.index(id));
        if let Some(i) = newest {
            out.push((self.world.particles.positions()[i] + Vec3::Y * 0.7, "round"));
        }
    }

    fn outlines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        // The target: a ring on the ground, TARGET_HALF_WIDTH across each way.
        let centre = self.target();
        const SIDES: usize = 32;
        for k in 0..SIDES {
            let at = |k: usize| {
                let a = std::f32::consts::TAU * k as f32 / SIDES as f32;
                centre + Vec3::new(a.cos(), 0.01, a.sin()) * TARGET_HALF_WIDTH
            };
            out.push((at(k), at(k + 1)));
        }
    }

    fn hover_points(&self, out: &mut Vec<(Vec3, String)>) {
        let launcher = self.launcher();
        let describe = |what: &str, (t, p): (f64, Vec3)| {
            format!(
                "{what}t = {t:.2} s, range {} m, height {} m",
                crate::messages::fixed(p.x - launcher.x, 2),
                crate::messages::fixed(p.y, 2)
            )
        };
        for flight in &self.flights {
            for &point in &flight.path {
                out.push((point.1, describe("", point)));
            }
            out.push((flight.launch.1, describe("launch: ", (0.0, flight.launch.1))));
            out.extend(flight.apex.map(|apex| (apex.1, describe("apex: ", apex))));
            out.extend(flight.landing.map(|landing| (landing.1, describe("landing: ", landing))));
        }
    }

    fn markers(&self, out: &mut Vec<Marker>) {
        // Each kept flight: dots every 0.1 s of its path, and its launch (green), apex
        // (yellow) and landing (red) points.
        for flight in &self.flights {
            for &(_, position) in &flight.path {
                out.push(Marker { position, radius: 0.09, color: [0.9, 0.75, 0.35] });
            }
            out.push(Marker { position: flight.launch.1, radius: 0.22, color: [0.2, 0.85, 0.3] });
            if let Some((_, position)) = flight.apex {
                out.push(Marker { position, radius: 0.22, color: [0.95, 0.85, 0.15] });
            }
            if let Some((_, position)) = flight.landing {
                out.push(Marker { position, radius: 0.22, color: [0.95, 0.25, 0.2] });
            }
        }
        // The target's centre: green once the last landed round hit it, else red.
        let target = self.target();
        let hit = self.flights.iter().rev().find_map(|f| f.hit(target)).unwrap_or(false);
        let color = if hit { [0.2, 0.9, 0.3] } else { [0.9, 0.2, 0.2] };
        out.push(Marker { position: target, radius: 0.3, color });
        for ghost in &self.ghosts {
            let position = ghost.position(&self.world);
            out.push(Marker { position, radius: 0.8 * ROUND_RADIUS, color: GHOST_COLOR });
        }
        let launcher = self.launcher();
        out.push(Marker { position: launcher, radius: 0.45, color: [0.3, 0.32, 0.35] });
        // The barrel, pointing where the next round goes: 1.5 m of overlapping balls.
        let aim = self.params.get("angle").to_radians();
        let barrel = Vec3::new(aim.cos(), aim.sin(), 0.0);
        for k in 1..=10 {
            let position = launcher + barrel * (0.15 * k as f32);
            out.push(Marker { position, radius: 0.16, color: [0.42, 0.44, 0.48] });
        }
        // Where the next round would go without drag, to its landing.
        let mut path = Vec::new();
        self.predicted_path(&mut path);
        for &position in &path[1..] {
            out.push(Marker { position, radius: 0.1, color: [0.55, 0.6, 0.7] });
        }
    }

    fn framing_points(&self, out: &mut Vec<Vec3>) {
        self.predicted_path(out);
        out.push(self.target());
    }

    fn camera(&self) -> CameraHint {
        CameraHint { target: Vec3::new(16.0, 5.0, 0.0), distance: 42.0, yaw: 0.0, pitch: 0.25 }
    }

    fn exact_error(&self) -> Option<f32> {
        self.ghosts.last().and_then(|ghost| ghost.error(&self.world))
    }

    fn readout_rows(&self, _dt: f32) -> Vec<super::Readout> {
        use super::Readout;
        let (g, v, h) = (self.params.get("g"), self.params.get("speed"), self.params.get("height"));
        let angle = self.params.get("angle").to_radians();
        let flying = self.rounds.len();
        let mut out = vec![
            Readout::new("rounds in flight", flying.to_string()).with("rounds_in_flight", flying as f32),
        ];
        let target = self.target();
        if let Some(flight) = self.flights.iter().rev().find(|f| f.landing.is_some()) {
            let (t, p) = flight.landing.expect("found by its landing");
            let off = p.x - target.x;
            let verdict = if flight.hit(target) == Some(true) {
                format!("HIT ({:.2} m from the centre)", off.abs())
            } else {
                format!("miss, {:.2} m {}", off.abs(), if off > 0.0 { "long" } else { "short" })
            };
            let hit = if flight.hit(target) == Some(true) { 1.0 } else { 0.0 };
            out.push(
                Readout::new("last landing", verdict).with("hit", hit).with("landing_off_target_m", off),
            );
            let range = p.x - flight.launch.1.x;
            out.push(
                Readout::new("  its range, flight time", format!("{range:.2} m in {t:.2} s"))
                    .with("range_m", range)
                    .with_f64("flight_time_s", t),
            );
        }
        if let Some(error) = self.exact_error() {
            out.push(
                Readout::new("newest round from its exact path", format!("{:.1} mm", error * 1000.0))
                    .with("exact_path_error_m", error),
            );
        }
        if g > 0.0 {
            let (vx, vy) = (v * angle.cos(), v * angle.sin());
            let peak = h + vy.max(0.0).powi(2) / (2.0 * g);
            out.push(Readout::new("peak (no drag)", format!("{peak:.2} m")).with("peak_predicted_m", peak));
            let ground = ground_range(vx, vy, h, g);
            out.push(
                Readout::new("range to the ground (no drag)", format!("{ground:.2} m"))
                    .with("range_predicted_m", ground),
            );
            // Back at launch height only if it went up first.
            let level = if vy > 0.0 {
                let level = 2.0 * vx * vy / g;
                Readout::new("range at launch height (no drag)", format!("{level:.2} m"))
                    .with("range_level_predicted_m", level)
            } else {
                Readout::new("range at launch height (no drag)", "never comes back up")
            };
            out.push(level);
        }
        out
    }
}

/// Whether a round moving up at `vy` (m/s) under gravity `g` (m/s², downwards) can
/// still reach the ground: always while gravity pulls down; with gravity off or
/// upwards only while it falls (faster than [`LANDING_FALL_SPEED`]).
#[must_use]
pub fn can_land(g: f32, vy: f32) -> bool {
    g > 0.0 || vy < -LANDING_FALL_SPEED
}

/// Time (s) a round launched upwards at `vy` (m/s) from height `h` (m) flies before reaching the
/// ground under gravity `g > 0`, without drag: `(vy + √(vy² + 2 g h)) / g`.
#[must_use]
pub fn ground_range_time(vy: f32, h: f32, g: f32) -> f32 {
    (vy + (vy * vy + 2.0 * g * h).sqrt()) / g
}

/// Horizontal distance (m) a round launched at `(vx, vy)` from height `h` flies before
/// reaching the ground under gravity `g > 0`, without drag: it lands at
/// `t = (vy + √(vy² + 2 g h)) / g`.
#[must_use]
pub fn ground_range(vx: f32, vy: f32, h: f32, g: f32) -> f32 {
    vx * (vy + (vy * vy + 2.0 * g * h).sqrt()) / g
}

//! A launcher, the projectile scene's and a scene file's (`[launcher]`): it fires
//! rounds at an aim, records each flight (its path, apex and landing), removes a round
//! when it lands, draws where the next round would go without drag or damping, and
//! follows each round with its exact path (a [`Ghost`]). It fires only when told: Fire
//! in the window, or once at step 0 of a headless run ([`super::fire_at_start`]).
//!
//! The ground a round lands on is the plane y = 0: a round goes when its centre
//! crosses it (there is no ground contact for it to bounce off, as in the paper's
//! ballistic demo).

use glam::Vec3;

use super::ghost::{GHOST_COLOR, Ghost, Motion};
use super::readout::Readout;
use super::runs::{Column, Runs, Table};
use super::{ActionInfo, Marker, SceneAction};
use crate::physics::exact::damping_rate;
use crate::physics::{Drag, ParticleDesc, ParticleId, PhysicsError, World};

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
/// Drawn and collision radius of the projectile scene's rounds (m), and a
/// `[launcher]`'s default.
pub const ROUND_RADIUS: f32 = 0.3;
/// Half the width of the target (m): a round landing this close to its centre hits.
pub const TARGET_HALF_WIDTH: f32 = 1.5;
/// Flights whose paths are kept and drawn, newest last.
pub const FLIGHTS_KEPT: usize = 5;
/// Time between the points kept of a flight's path (s).
pub const PATH_INTERVAL: f64 = 0.1;

/// The action a launcher gives its scene: Fire (F).
pub static FIRE: &[ActionInfo] = &[ActionInfo { label: "Fire", key: "F", action: SceneAction::Fire }];

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
    /// What it was fired with (absent in snapshots made before the table of runs).
    #[serde(default)]
    aim: Option<Aim>,
}

impl Flight {
    /// Hit or miss of the target whose centre is at `target` on the ground; `None`
    /// before landing.
    #[must_use]
    pub fn hit(&self, target: Vec3) -> Option<bool> {
        self.landing.map(|(_, p)| (p.x - target.x).abs() <= TARGET_HALF_WIDTH)
    }
}

/// What the next round is fired with.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aim {
    /// Where rounds leave from (m).
    pub position: Vec3,
    /// Launch speed (m/s).
    pub speed: f32,
    /// Elevation above the horizontal, towards +x (degrees).
    pub angle: f32,
    /// A round's mass (kg).
    pub mass: f32,
    /// A round's radius (m).
    pub radius: f32,
    /// Fraction of velocity a round keeps per second.
    pub damping: f32,
    /// Linear drag of a round (N·s/m).
    pub k1: f32,
    /// Quadratic drag of a round (N·s²/m²).
    pub k2: f32,
    /// Distance of the target on the ground from the launcher, along x (m); `None`:
    /// no target.
    pub target: Option<f32>,
    /// Downward gravity on the rounds (m/s²).
    pub g: f32,
}

/// The launcher and its rounds.
#[derive(Clone, Debug)]
pub struct Launcher {
    /// What the next round is fired with.
    pub aim: Aim,
    /// Whether a headless run fires a round at step 0 (see
    /// [`fire_at_start`](super::fire_at_start)); the window never fires by itself.
    pub fire_at_start: bool,
    /// Live rounds and the time each was fired (s).
    rounds: Vec<(ParticleId, f64)>,
    /// The exact path of each round without quadratic drag (k2 = 0): the drag-free
    /// parabola, or its exponential form with linear drag and damping.
    ghosts: Vec<Ghost>,
    /// The last [`FLIGHTS_KEPT`] flights, newest last.
    flights: Vec<Flight>,
    /// The table of runs: a row for each round that landed, in [`RUN_COLUMNS`].
    runs: Runs,
    /// A label for each kept flight (parallel to `flights`): the launch settings that
    /// tell the kept flights apart ("30°", "45° · 20 m/s"); empty where none differs.
    /// Made again whenever the flights change ([`Self::relabel`]).
    flight_labels: Vec<String>,
}

/// The launch settings a kept flight's label may name, each with how it is written.
#[allow(clippy::type_complexity)]
const TOLD_APART: [(fn(&Aim) -> f32, fn(f32) -> String); 8] = [
    (|a| a.angle, |x| format!("{}°", round2(x))),
    (|a| a.speed, |x| format!("{} m/s", round2(x))),
    (|a| a.g, |x| format!("g {}", round2(x))),
    (|a| a.mass, |x| format!("{} kg", round2(x))),
    (|a| a.damping, |x| format!("damping {}", round2(x))),
    (|a| a.k1, |x| format!("k1 {}", round2(x))),
    (|a| a.k2, |x| format!("k2 {}", round2(x))),
    (|a| a.position.y, |x| format!("h {} m", round2(x))),
];

/// `x` to two decimals at most, as a label writes it (45, 36.87, 0.99).
fn round2(x: f32) -> f32 {
    (x * 100.0).round() / 100.0
}

/// The columns of a launcher's table of runs: what the round was fired with, then
/// each measured value beside its drag-free prediction.
pub const RUN_COLUMNS: &[Column] = &[
    Column {
        key: "angle_deg",
        heading: "angle (°)",
        help: "Launch elevation above the horizontal",
        always: true,
    },
    Column { key: "speed_m_s", heading: "speed (m/s)", help: "Launch speed", always: true },
    Column { key: "g_m_s2", heading: "g (m/s²)", help: "Gravity when the round was fired", always: true },
    Column {
        key: "damping",
        heading: "damping",
        help: "Fraction of velocity the round kept per second",
        always: false,
    },
    Column { key: "k1", heading: "k1 (N·s/m)", help: "The round's linear drag", always: false },
    Column { key: "k2", heading: "k2 (N·s²/m²)", help: "The round's quadratic drag", always: false },
    Column {
        key: "height_m",
        heading: "height (m)",
        help: "Height of the launcher above the ground",
        always: false,
    },
    Column { key: "mass_kg", heading: "mass (kg)", help: "The round's mass", always: false },
    Column {
        key: "range_m",
        heading: "range (m)",
        help: "Measured: how far along x the round's centre came down to y = 0, found between the two steps \
               either side of the ground",
        always: true,
    },
    Column {
        key: "range_predicted_m",
        heading: "predicted range (m)",
        help: "vx (vy + √(vy² + 2 g h)) / g: no drag, no damping, exact time (blank without gravity)",
        always: true,
    },
    Column {
        key: "apex_m",
        heading: "apex (m)",
        help: "Measured: the highest point, where the vertical velocity turned from up to down (the launch \
               height for a round fired level or down)",
        always: true,
    },
    Column {
        key: "apex_predicted_m",
        heading: "predicted apex (m)",
        help: "h + vy² / (2 g): no drag, no damping (blank without gravity)",
        always: true,
    },
    Column {
        key: "flight_s",
        heading: "flight (s)",
        help: "Measured: time from launch to landing",
        always: true,
    },
    Column {
        key: "flight_predicted_s",
        heading: "predicted flight (s)",
        help: "(vy + √(vy² + 2 g h)) / g: no drag, no damping (blank without gravity)",
        always: true,
    },
];

/// The row of [`RUN_COLUMNS`] for a round fired with `aim` that peaked at height
/// `apex` (m, if it rose) and landed `range` m away after `flight` s.
#[must_use]
pub fn run_row(aim: &Aim, range: f32, apex: Option<f32>, flight: f64) -> Vec<f64> {
    let angle = aim.angle.to_radians();
    let (vx, vy) = (aim.speed * angle.cos(), aim.speed * angle.sin());
    let (h, g) = (aim.position.y, aim.g);
    let (range_predicted, apex_predicted, flight_predicted) = if g > 0.0 {
        let t = ground_range_time(vy, h, g);
        (f64::from(vx * t), f64::from(h + vy.max(0.0).powi(2) / (2.0 * g)), f64::from(t))
    } else {
        (f64::NAN, f64::NAN, f64::NAN)
    };
    vec![
        f64::from(aim.angle),
        f64::from(aim.speed),
        f64::from(aim.g),
        f64::from(aim.damping),
        f64::from(aim.k1),
        f64::from(aim.k2),
        f64::from(h),
        f64::from(aim.mass),
        f64::from(range),
        range_predicted,
        f64::from(apex.unwrap_or(h)),
        apex_predicted,
        flight,
        flight_predicted,
    ]
}

impl Launcher {
    /// A launcher with no round fired yet; with `fire_at_start`, a headless run fires
    /// one at step 0.
    #[must_use]
    pub fn new(aim: Aim, fire_at_start: bool) -> Self {
        Self {
            aim,
            fire_at_start,
            rounds: Vec::new(),
            ghosts: Vec::new(),
            flights: Vec::new(),
            runs: Runs::new(RUN_COLUMNS),
            flight_labels: Vec::new(),
        }
    }

    /// Labels each kept flight with the launch settings that differ between the kept
    /// flights, so that paths drawn side by side say what changed.
    fn relabel(&mut self) {
        let aims: Vec<Aim> = self.flights.iter().filter_map(|f| f.aim).collect();
        let differing: Vec<_> = TOLD_APART
            .iter()
            .filter(|(get, _)| aims.iter().any(|a| get(a).to_bits() != get(&aims[0]).to_bits()))
            .collect();
        self.flight_labels = self
            .flights
            .iter()
            .map(|f| match &f.aim {
                Some(aim) => {
                    differing.iter().map(|(get, write)| write(get(aim))).collect::<Vec<_>>().join(" · ")
                }
                None => String::new(),
            })
            .collect();
    }

    /// The labels of the kept flights, as [`Self::relabel`] made them.
    #[must_use]
    pub fn flight_labels(&self) -> &[String] {
        &self.flight_labels
    }

    /// Whether it has fired no round yet (a round that landed still counts as fired).
    #[must_use]
    pub fn fired_none(&self) -> bool {
        self.flights.is_empty()
    }

    /// The table of runs: a row for each round that landed.
    #[must_use]
    pub fn runs(&self) -> Table<'_> {
        self.runs.table()
    }

    /// Deletes run `k`, or every run with `None`.
    pub fn delete_runs(&mut self, which: Option<usize>) {
        self.runs.delete(which);
    }

    fn direction(&self) -> Vec3 {
        let angle = self.aim.angle.to_radians();
        Vec3::new(angle.cos(), angle.sin(), 0.0)
    }

    /// The target's centre, on the ground.
    fn target(&self) -> Option<Vec3> {
        self.aim.target.map(|d| Vec3::new(self.aim.position.x + d, 0.0, self.aim.position.z))
    }

    /// Fires a round into `world`; returns it.
    pub fn fire(&mut self, world: &mut World) -> Result<ParticleId, PhysicsError> {
        let aim = self.aim;
        let direction = self.direction();
        let id = world.add_particle(ParticleDesc {
            position: aim.position,
            velocity: direction * aim.speed,
            acceleration: Vec3::new(0.0, -aim.g, 0.0),
            mass: aim.mass,
            damping: aim.damping,
            radius: aim.radius,
            immovable: false,
        })?;
        if aim.k1 > 0.0 || aim.k2 > 0.0 {
            // Its own drag generator, which goes when the round does.
            world.add_force(Drag { k1: aim.k1, k2: aim.k2, targets: vec![id] })?;
        }
        self.rounds.push((id, world.time()));
        if self.flights.len() == FLIGHTS_KEPT {
            self.flights.remove(0);
        }
        let (t, p, vy) = (world.time(), aim.position, direction.y * aim.speed);
        self.flights.push(Flight {
            round: Some(id),
            path: vec![(0.0, p)],
            launch: (t, p),
            last: (t, p, vy),
            aim: Some(aim),
            ..Flight::default()
        });
        if aim.k2 == 0.0 {
            self.ghosts.extend(Ghost::new(world, id, self.motion(aim.k1, aim.mass, aim.damping)));
        }
        self.relabel();
        Ok(id)
    }

    /// The closed form of a round of mass `m` with linear drag `k1` and damping.
    fn motion(&self, k1: f32, m: f32, damping: f32) -> Motion {
        Motion::Projectile {
            g: Vec3::new(0.0, -self.aim.g, 0.0).as_dvec3(),
            lambda: f64::from(k1 / m) + damping_rate(damping),
        }
    }

    /// Gravity changed to `g` (m/s², downwards): the next round falls so, and the
    /// ghosts of rounds in flight start again from where the rounds are.
    pub fn set_gravity(&mut self, world: &World, g: f32) {
        self.aim.g = g;
        let gravity = Vec3::new(0.0, -g, 0.0).as_dvec3();
        for ghost in &mut self.ghosts {
            if let Motion::Projectile { lambda, .. } = ghost.motion() {
                ghost.restart(world, Motion::Projectile { g: gravity, lambda });
            }
        }
    }

    /// Call before the world steps.
    pub fn before_step(&mut self, world: &World) {
        for ghost in &mut self.ghosts {
            ghost.before_step(world);
        }
    }

    /// Call after the world stepped: follows the flights and removes the rounds that
    /// landed (or, never able to land, grew too old or went too far).
    pub fn after_step(&mut self, world: &mut World) {
        for ghost in &mut self.ghosts {
            ghost.after_step(world);
        }
        self.record_flights(world);
        let now = world.time();
        let (launcher, g) = (self.aim.position, self.aim.g);
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
        let world = &*world;
        self.ghosts.retain(|ghost| world.particles.index(ghost.particle).is_some());
    }

    /// Follows each flying round: a path point every [`PATH_INTERVAL`], the apex where
    /// its vertical velocity turns negative, the landing where it crosses y = 0 (both
    /// interpolated within the step).
    fn record_flights(&mut self, world: &World) {
        let now = world.time();
        let particles = &world.particles;
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
                let time = t0 - launched + f64::from(f) * (now - t0);
                flight.landing = Some((time, Vec3::new(at.x, 0.0, at.z)));
                flight.round = None;
                if let Some(aim) = &flight.aim {
                    let apex = flight.apex.map(|(_, p)| p.y);
                    self.runs.push(run_row(aim, at.x - flight.launch.1.x, apex, time));
                }
            }
            if flight.path.last().is_none_or(|(t, _)| now - launched - t >= PATH_INTERVAL - 1e-9) {
                flight.path.push((now - launched, p));
            }
            flight.last = (now, p, v.y);
        }
    }

    /// Whether `id` is a round this launcher fired and still follows.
    #[must_use]
    pub fn is_round(&self, id: ParticleId) -> bool {
        self.rounds.iter().any(|&(round, _)| round == id)
    }

    /// Its rounds, ghosts and flights, for a snapshot.
    #[must_use]
    pub fn save_state(&self) -> serde_json::Value {
        // A value there is none of (NaN) is written as null.
        serde_json::json!({
            "rounds": self.rounds,
            "ghosts": self.ghosts,
            "flights": self.flights,
            "runs": self.runs.saved(),
        })
    }

    /// Takes back what [`Self::save_state`] wrote, checked against `world`.
    pub fn restore_state(&mut self, world: &World, state: &super::RawValue) -> Result<(), String> {
        #[derive(serde::Deserialize)]
        struct Saved {
            rounds: Vec<(ParticleId, f64)>,
            ghosts: Vec<Ghost>,
            flights: Vec<Flight>,
            #[serde(default)]
            runs: Vec<Vec<Option<f64>>>,
        }
        let saved: Saved = super::read_state(state)?;
        let runs = self.runs.read(saved.runs)?;
        let particles = &world.particles;
        if let Some((id, _)) = saved.rounds.iter().find(|(id, _)| particles.index(*id).is_none()) {
            return Err(format!("round {} is not a particle of the world", id.0));
        }
        // A round was fired at a time the world has passed: not before 0, not ahead of
        // the world's clock (its age decides when it is removed).
        let now = world.time();
        if let Some((id, fired)) = saved.rounds.iter().find(|(_, t)| !(*t >= 0.0 && *t <= now)) {
            let fired = if fired.abs() >= 1e6 { format!("{fired:e}") } else { format!("{fired}") };
            return Err(format!(
                "round {} was fired at t = {fired} s, outside 0 to the world's {now:.3} s",
                id.0
            ));
        }
        (self.rounds, self.ghosts, self.flights) = (saved.rounds, saved.ghosts, saved.flights);
        self.runs = runs;
        self.relabel();
        Ok(())
    }

    /// Where the next round would fly without drag or damping (m): the launcher, then a
    /// point every [`PATH_INTERVAL`] of flight (further apart when more than
    /// [`PREDICTED_DOTS`] would be needed) until it lands, however far. A round that
    /// never lands (gravity off or upwards) is followed for [`UNLANDED_SHOWN`] or to
    /// [`MAX_DISTANCE`], whichever comes first.
    pub fn predicted_path(&self, out: &mut Vec<Vec3>) {
        let g = self.aim.g;
        let launcher = self.aim.position;
        let v = self.direction() * self.aim.speed;
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

    /// The names drawn beside the launcher, the target and the newest round.
    pub fn labels<'a>(&'a self, world: &World, out: &mut Vec<(Vec3, &'a str)>) {
        out.push((self.aim.position + Vec3::new(0.0, 0.9, 0.0), "launcher"));
        // Each kept path, where it came down (or its last point), says what set it apart.
        for (flight, label) in self.flights.iter().zip(&self.flight_labels) {
            let end = flight.landing.or(flight.path.last().copied()).map(|(_, p)| p);
            if let (Some(end), false) = (end, label.is_empty()) {
                out.push((end + Vec3::new(0.0, 0.6, 0.0), label));
            }
        }
        if let Some(target) = self.target() {
            out.push((target + Vec3::new(0.0, 0.5, 0.0), "target"));
        }
        let newest = self.rounds.last().and_then(|&(id, _)| world.particles.index(id));
        if let Some(i) = newest {
            out.push((world.particles.positions()[i] + Vec3::Y * 0.7, "round"));
        }
    }

    /// The target: a ring on the ground, [`TARGET_HALF_WIDTH`] across each way.
    pub fn outlines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        let Some(centre) = self.target() else { return };
        const SIDES: usize = 32;
        for k in 0..SIDES {
            let at = |k: usize| {
                let a = std::f32::consts::TAU * k as f32 / SIDES as f32;
                centre + Vec3::new(a.cos(), 0.01, a.sin()) * TARGET_HALF_WIDTH
            };
            out.push((at(k), at(k + 1)));
        }
    }

    /// The flights' points, each with its time, range and height.
    pub fn hover_points(&self, out: &mut Vec<(Vec3, String)>) {
        let launcher = self.aim.position;
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

    /// The flights, the target, the ghosts, the launcher and its barrel, and the next
    /// round's predicted path.
    pub fn markers(&self, out: &mut Vec<Marker>) {
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
        if let Some(target) = self.target() {
            let hit = self.flights.iter().rev().find_map(|f| f.hit(target)).unwrap_or(false);
            let color = if hit { [0.2, 0.9, 0.3] } else { [0.9, 0.2, 0.2] };
            out.push(Marker { position: target, radius: 0.3, color });
        }
        let launcher = self.aim.position;
        out.push(Marker { position: launcher, radius: 0.45, color: [0.3, 0.32, 0.35] });
        // The barrel, pointing where the next round goes: 1.5 m of overlapping balls.
        let barrel = self.direction();
        for k in 1..=10 {
            let position = launcher + barrel * (0.15 * k as f32);
            out.push(Marker { position, radius: 0.16, color: [0.42, 0.44, 0.48] });
        }
    }

    /// What it predicts: each round's exact path as a ghost, and where the next round
    /// would go without drag or damping, to its landing.
    pub fn predictions(&self, world: &World, out: &mut Vec<Marker>) {
        for ghost in &self.ghosts {
            let position = ghost.position(world);
            out.push(Marker { position, radius: 0.8 * self.aim.radius, color: GHOST_COLOR });
        }
        let mut path = Vec::new();
        self.predicted_path(&mut path);
        for &position in &path[1..] {
            out.push(Marker { position, radius: 0.1, color: [0.55, 0.6, 0.7] });
        }
    }

    /// The points a view frames: the next round's path, the target and every kept path.
    pub fn framing_points(&self, out: &mut Vec<Vec3>) {
        self.predicted_path(out);
        out.extend(self.target());
        // Every kept path, not only the next one's: its launch, apex and where it ends.
        for flight in &self.flights {
            out.push(flight.launch.1);
            out.extend(flight.apex.map(|(_, p)| p));
            out.extend(flight.landing.or(flight.path.last().copied()).map(|(_, p)| p));
        }
    }

    /// Distance of the newest round from its exact path (m).
    #[must_use]
    pub fn exact_error(&self, world: &World) -> Option<f32> {
        self.ghosts.last().and_then(|ghost| ghost.error(world))
    }

    /// The read-outs: rounds in flight, the last landing against the target, its
    /// range, the newest round's distance from its exact path, and the predictions for
    /// the next round, which leave out drag and damping (each label says so).
    #[must_use]
    pub fn readout_rows(&self, world: &World) -> Vec<Readout> {
        let Aim { g, speed: v, angle, .. } = self.aim;
        let (h, angle) = (self.aim.position.y, angle.to_radians());
        let flying = self.rounds.len();
        let mut out = vec![
            Readout::new("rounds in flight", flying.to_string())
                .with("rounds_in_flight", flying as f32)
                .help("Rounds fired and not yet landed; a round is removed when its centre reaches y = 0"),
        ];
        if let Some(flight) = self.flights.iter().rev().find(|f| f.landing.is_some()) {
            let (t, p) = flight.landing.expect("found by its landing");
            if let Some(target) = self.target() {
                let off = p.x - target.x;
                let verdict = if flight.hit(target) == Some(true) {
                    format!("HIT ({:.2} m from the centre)", off.abs())
                } else {
                    format!("miss, {:.2} m {}", off.abs(), if off > 0.0 { "long" } else { "short" })
                };
                let hit = if flight.hit(target) == Some(true) { 1.0 } else { 0.0 };
                out.push(
                    Readout::new("last landing", verdict)
                        .with("hit", hit)
                        .with("landing_off_target_m", off)
                        .help(
                            "Where the last round to land came down against the target: a hit within the \
                             target's half width of its centre, else how far long (beyond) or short",
                        ),
                );
            }
            let range = p.x - flight.launch.1.x;
            out.push(
                Readout::new("  its range, flight time", format!("{range:.2} m in {t:.2} s"))
                    .with("range_m", range)
                    .with_f64("flight_time_s", t)
                    .help(
                        "Measured: how far along x the last round came down from the launcher, and the time \
                         from launch to landing; the landing is placed between the two steps either side of \
                         the ground",
                    ),
            );
        }
        if let Some(error) = self.exact_error(world) {
            out.push(
                Readout::new("newest round from its exact path", format!("{:.1} mm", error * 1000.0))
                    .with("exact_path_error_m", error)
                    .help(
                        "How far the newest round is from its exact path (the ghost), computed in closed form \
                         from the same launch with the same gravity, damping and linear drag: the \
                         integrator's error so far. None with quadratic drag, which has no closed form.",
                    ),
            );
        }
        if g > 0.0 {
            let (vx, vy) = (v * angle.cos(), v * angle.sin());
            let peak = h + vy.max(0.0).powi(2) / (2.0 * g);
            out.push(
                Readout::new("peak (no drag, no damping)", format!("{peak:.2} m"))
                    .with("peak_predicted_m", peak)
                    .help(
                        "Predicted highest point of the next round: h + (v sin θ)² / 2g. Leaves out drag and \
                         damping, which bring the peak lower.",
                    ),
            );
            let ground = ground_range(vx, vy, h, g);
            out.push(
                Readout::new("range to the ground (no drag, no damping)", format!("{ground:.2} m"))
                    .with("range_predicted_m", ground)
                    .help(
                        "Predicted range of the next round to the ground: vx (vy + √(vy² + 2 g h)) / g, with \
                         vx = v cos θ, vy = v sin θ and h the launcher's height. Leaves out drag and \
                         damping, which shorten it.",
                    ),
            );
            // Back at launch height only if it went up first.
            let level = if vy > 0.0 {
                let level = 2.0 * vx * vy / g;
                Readout::new("range at launch height (no drag, no damping)", format!("{level:.2} m"))
                    .with("range_level_predicted_m", level)
                    .help(LEVEL_HELP)
            } else {
                Readout::new("range at launch height (no drag, no damping)", "never comes back up")
                    .help(LEVEL_HELP)
            };
            out.push(level);
        }
        out
    }
}

/// What the range at launch height is.
const LEVEL_HELP: &str = "Predicted distance at which the next round is back at the launcher's height, the \
    textbook's range on level ground: 2 vx vy / g = v² sin 2θ / g. Leaves out drag and damping, and the \
    launcher's height above the ground (see the range to the ground).";

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

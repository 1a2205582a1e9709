//! heap: grains poured from a hopper onto open ground build a heap, whose angle of
//! repose the scene measures once it has settled.
//!
//! The hopper stands over the middle of the ground: a square bin of finite walls on a
//! funnel of four walls at [`FUNNEL_ANGLE`] to the horizontal, down to a square outlet
//! `orifice` wide at height `drop`. The funnel is steeper than the grains' slide and
//! roll, so it empties (a flat-bottomed bin keeps a dead zone of grains beside its
//! opening: half of them, tried). The grains start in the bin as the hourglass's loose
//! random cloud, fill the funnel, drain through the outlet as a steady stream and pile
//! up on the ground (y = 0, unbounded) under it. The heap has settled when no grain
//! has come through for [`QUIET`] and every grain on the ground moves slower than
//! [`SETTLED_SPEED`]; then its angle of repose is measured from its surface
//! ([`pile::angle_of_repose`]) and a row goes into the table of runs.

use std::borrow::Cow;

use glam::Vec3;

use super::granular::{self, Material};
use super::hourglass::{GRAIN_DENSITY, grain_volume, starting_cloud};
use super::pile;
use super::runs::{Column, Runs, Table};
use super::{CameraHint, Param, ParamError, ParamTable, ParamValues, Readout, Scene, SceneEntry, SceneInfo};
use crate::physics::{DEFAULT_ROLLING_RESISTANCE, PhysicsError, Plane, ResolveReport, World};

/// How long no grain may come through the opening before the heap can count as
/// settled (s).
pub const QUIET: f64 = 1.0;
/// Speed below which every grain on the ground must be for the heap to count as
/// settled (m/s): the solver's own threshold for sleep.
pub const SETTLED_SPEED: f32 = 0.05;
/// The funnel's walls' angle to the horizontal (degrees): its corners' valleys then
/// fall at 51°, steeper than μ = 2's slide (63° would need more; the slider's top).
pub const FUNNEL_ANGLE: f32 = 60.0;

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("count"), unit: Cow::Borrowed(""), default: 1500.0, min: 10.0, max: 50_000.0, help: Cow::Borrowed("Number of grains poured (rounded to a whole number)"), logarithmic: true, integer: true },
    Param { name: Cow::Borrowed("radius"), unit: Cow::Borrowed("m"), default: 0.1, min: 0.01, max: 1.0, help: Cow::Borrowed("Radius of every grain"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("orifice"), unit: Cow::Borrowed("m"), default: 1.2, min: 0.05, max: 20.0, help: Cow::Borrowed("Width of the funnel's square outlet (below about 5 grain diameters it jams)"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("drop"), unit: Cow::Borrowed("m"), default: 1.2, min: 0.2, max: 50.0, help: Cow::Borrowed("Height of the funnel's outlet above the ground: grains that fall further hit the heap harder and spread it flatter; a heap that reaches the outlet stops the flow"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("friction"), unit: Cow::Borrowed(""), default: 0.5, min: 0.0, max: 2.0, help: Cow::Borrowed("Coulomb friction coefficient between grains, the hopper and the ground"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("rolling_resistance"), unit: Cow::Borrowed(""), default: DEFAULT_ROLLING_RESISTANCE, min: 0.0, max: 1.0, help: Cow::Borrowed("Rolling resistance coefficient of every contact: without it round grains roll apart and make no heap"), logarithmic: false, integer: false },
    Param { min: 0.1, ..super::GRAVITY },
];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("heap"),
    summary: Cow::Borrowed("Grains poured from a hopper onto open ground; the heap's angle of repose"),
    // The hourglass's step, for the same grains.
    dt: 1.0 / 120.0,
    default_steps: 2400,
    params: ParamTable::Static(PARAMS),
    ..granular::LOOK
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

/// The columns of the heap's table of runs: a row each time a heap settles.
pub static RUN_COLUMNS: &[Column] = &[
    Column { key: "count", heading: "grains", help: "Grains poured", always: false },
    Column { key: "radius_m", heading: "radius (m)", help: "Radius of every grain", always: false },
    Column { key: "orifice_m", heading: "outlet (m)", help: "Width of the funnel's outlet", always: false },
    Column { key: "friction", heading: "μ", help: "Coulomb friction coefficient", always: true },
    Column {
        key: "rolling_resistance",
        heading: "μ_r",
        help: "Rolling resistance coefficient",
        always: true,
    },
    Column { key: "g_m_s2", heading: "g (m/s²)", help: "Gravitational acceleration", always: false },
    Column {
        key: "heap_grains",
        heading: "in heap",
        help: "Measured: grains on the ground when the heap settled (any others stayed in the hopper)",
        always: true,
    },
    Column {
        key: "heap_height_m",
        heading: "height (m)",
        help: "Measured: the top of the highest grain on the ground",
        always: true,
    },
    Column {
        key: "repose_deg",
        heading: "repose (°)",
        help: "Measured: the angle of the heap's flank, fitted to its surface (see the read-out)",
        always: true,
    },
    Column {
        key: "settled_s",
        heading: "settled at (s)",
        help: "Measured: the time the heap came to rest",
        always: false,
    },
];

/// The hopper's measurements, all from the parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hopper {
    /// Grain radius (m).
    pub radius: f32,
    /// Grains poured.
    pub count: usize,
    /// Width of the funnel's square outlet (m).
    pub orifice: f32,
    /// Inner width of the bin (m): 2.5 outlets, and at least 12 grain diameters.
    pub width: f32,
    /// Height of the outlet above the ground (m).
    pub drop: f32,
    /// Height of the funnel, from its outlet to the bin (m).
    pub funnel: f32,
    /// Height of the bin's walls above the funnel (m).
    pub walls: f32,
}

impl Hopper {
    /// The hopper the parameters ask for.
    #[must_use]
    pub fn of(params: &ParamValues) -> Self {
        let (radius, orifice) = (params.get("radius"), params.get("orifice"));
        let count = params.get("count").round().max(1.0) as usize;
        let d = 2.0 * radius;
        let width = (2.5 * orifice).max(12.0 * d);
        let drop = params.get("drop");
        let funnel = 0.5 * (width - orifice).max(0.0) * FUNNEL_ANGLE.to_radians().tan();
        let top = starting_cloud(count, radius, width, 0).iter().fold(0.0f32, |top, p| top.max(p.y)) + radius;
        Self { radius, count, orifice, width, drop, funnel, walls: top.max(4.0 * d) }
    }

    /// Height of the bin's floor, the funnel's top (m).
    #[must_use]
    pub fn bin(&self) -> f32 {
        self.drop + self.funnel
    }

    /// The mass of one grain (kg): glass, as the hourglass's.
    #[must_use]
    pub fn grain_mass(&self) -> f32 {
        GRAIN_DENSITY * grain_volume(self.radius)
    }
}

fn build_world(params: &ParamValues, hopper: &Hopper) -> World {
    let (friction, rolling, g) = (params.get("friction"), params.get("rolling_resistance"), params.get("g"));
    let material = Material { restitution: 0.0, friction, rolling_resistance: rolling };
    let mut world = World::new();
    let surface = |plane: Plane| plane.with_rolling_resistance(rolling);
    let ground =
        Plane::new(Vec3::Y, Vec3::ZERO, 0.0, friction).expect("parameter ranges keep the ground valid");
    world.add_contact_generator(surface(ground)).expect("a valid ground");
    // For each side (the direction from the middle to it): the bin's wall, facing in,
    // from the funnel's top up `walls`, and the funnel's wall below it, facing in and
    // up, from the bin down to the outlet's edge. Each is a rectangle as wide as the
    // bin; the funnel's overlap at its corners, behind their neighbours.
    let (half, outlet, bin) = (hopper.width / 2.0, hopper.orifice / 2.0, hopper.bin());
    let (sin, cos) = FUNNEL_ANGLE.to_radians().sin_cos();
    let slant = hopper.funnel / sin;
    for side in [Vec3::NEG_X, Vec3::X, Vec3::NEG_Z, Vec3::Z] {
        let wall_center = side * half + Vec3::Y * (bin + hopper.walls / 2.0);
        let wall = Plane::new(-side, wall_center, 0.0, friction)
            .and_then(|plane| plane.with_extent(wall_center, Vec3::Y, hopper.walls, hopper.width))
            .expect("parameter ranges keep the walls valid");
        world.add_contact_generator(surface(wall)).expect("a valid wall");
        if slant > 0.0 {
            let funnel_center = side * 0.5 * (half + outlet) + Vec3::Y * (hopper.drop + hopper.funnel / 2.0);
            let normal = -side * sin + Vec3::Y * cos;
            let down_slope = side * cos + Vec3::Y * sin;
            let funnel = Plane::new(normal, funnel_center, 0.0, friction)
                .and_then(|plane| plane.with_extent(funnel_center, down_slope, slant, hopper.width))
                .expect("parameter ranges keep the funnel valid");
            world.add_contact_generator(surface(funnel)).expect("a valid funnel wall");
        }
    }
    granular::add_sphere_collisions(&mut world, material);
    let cloud: Vec<Vec3> = starting_cloud(hopper.count, hopper.radius, hopper.width, 0)
        .into_iter()
        .map(|p| p + Vec3::new(0.0, bin, 0.0))
        .collect();
    granular::add_spheres(&mut world, &cloud, hopper.grain_mass(), hopper.radius, g, true);
    world
}

fn create(params: ParamValues) -> Box<dyn Scene> {
    let hopper = Hopper::of(&params);
    Box::new(Heap {
        world: build_world(&params, &hopper),
        params,
        hopper,
        gauge: Gauge::default(),
        runs: Runs::new(RUN_COLUMNS),
    })
}

/// Whether the grain centred at `y` has come through the funnel's outlet at `drop`:
/// wholly below it.
fn on_the_ground(y: f32, radius: f32, drop: f32) -> bool {
    y < drop - radius
}

/// The grains through the funnel's outlet: their positions.
#[must_use]
pub fn heap_positions(world: &World, drop: f32) -> Vec<Vec3> {
    let p = &world.particles;
    p.position.iter().zip(&p.radius).filter(|(c, r)| on_the_ground(c.y, **r, drop)).map(|(c, _)| *c).collect()
}

/// What the scene measures as it runs, kept in snapshots.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Gauge {
    /// Grains through the opening so far.
    through: usize,
    /// When the last of them came through (s).
    last_through: f64,
    /// The heap once it settled: when, its grains, its height (m) and its angle of
    /// repose (degrees).
    settled: Option<Settled>,
    /// The world's time at the last step (s), to tell a world put back.
    now: f64,
}

/// A settled heap's measurements.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Settled {
    at: f64,
    grains: usize,
    height: f32,
    repose: f32,
}

struct Heap {
    world: World,
    params: ParamValues,
    hopper: Hopper,
    gauge: Gauge,
    /// The table of runs: a row for each heap that settled, in [`RUN_COLUMNS`].
    runs: Runs,
}

impl Heap {
    /// The heap's height: the top of its highest grain (m), 0 for none.
    fn height(&self, positions: &[Vec3]) -> f32 {
        positions.iter().map(|p| p.y + self.hopper.radius).fold(0.0, f32::max)
    }

    /// Measures the settled heap and adds its row to the table.
    fn settle(&mut self, now: f64) {
        let positions = heap_positions(&self.world, self.hopper.drop);
        let settled = Settled {
            at: now,
            grains: positions.len(),
            height: self.height(&positions),
            repose: pile::angle_of_repose(&positions, self.hopper.radius),
        };
        self.gauge.settled = Some(settled);
        let p = |name| f64::from(self.params.get(name));
        let row = vec![
            self.hopper.count as f64,
            p("radius"),
            p("orifice"),
            p("friction"),
            p("rolling_resistance"),
            p("g"),
            settled.grains as f64,
            f64::from(settled.height),
            f64::from(settled.repose),
            now,
        ];
        self.runs.push(row);
    }
}

impl Scene for Heap {
    scene_basics!();

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        if super::set_param_or_gravity(&mut self.params, &mut self.world, name, value)? {
            // Everything else shapes the hopper or the grains: pour them again.
            self.hopper = Hopper::of(&self.params);
            let running = std::mem::replace(&mut self.world, build_world(&self.params, &self.hopper));
            super::keep_solver(&running, &mut self.world);
        }
        // A new pour (or new gravity) is a new measurement; the table stays.
        self.gauge = Gauge { now: self.world.time(), last_through: self.world.time(), ..Gauge::default() };
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        let report = self.world.step(dt)?;
        let now = self.world.time();
        // A world put back (a reset) starts the measurement again.
        if now <= self.gauge.now {
            self.gauge = Gauge { last_through: now, ..Gauge::default() };
        }
        self.gauge.now = now;
        let (drop, p) = (self.hopper.drop, &self.world.particles);
        let mut through = 0;
        let mut fastest = 0.0f32;
        for ((c, &r), v) in p.position.iter().zip(&p.radius).zip(&p.velocity) {
            if on_the_ground(c.y, r, drop) {
                through += 1;
                fastest = fastest.max(v.length_squared());
            }
        }
        if through != self.gauge.through {
            self.gauge.through = through;
            self.gauge.last_through = now;
        }
        let quiet = now - self.gauge.last_through >= QUIET - 1e-9;
        if self.gauge.settled.is_none() && through > 0 && quiet && fastest < SETTLED_SPEED * SETTLED_SPEED {
            self.settle(now);
        }
        Ok(report)
    }

    fn save_state(&self) -> serde_json::Value {
        serde_json::json!({ "gauge": self.gauge, "runs": self.runs.saved() })
    }

    fn restore_state(&mut self, state: &super::RawValue) -> Result<(), String> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Saved {
            gauge: Gauge,
            runs: Vec<Vec<Option<f64>>>,
        }
        let saved: Saved = super::read_state(state)?;
        let (now, grains) = (self.world.time(), self.world.particles.len());
        let gauge = saved.gauge;
        let times = [gauge.now, gauge.last_through].into_iter().chain(gauge.settled.map(|s| s.at));
        if let Some(t) = times.into_iter().find(|t| !(t.is_finite() && (0.0..=now + 1e-9).contains(t))) {
            return Err(format!("gauge: a time of {t} s is outside 0 to the world's {now:.3} s"));
        }
        if gauge.through > grains || gauge.settled.is_some_and(|s| s.grains > grains) {
            return Err(format!("gauge: counts more grains than the {grains} there are"));
        }
        let runs = self.runs.read(saved.runs)?;
        self.gauge = gauge;
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

    fn outlines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        // The bin's square at its top and bottom, its upright edges, the funnel's
        // edges down to the outlet's square.
        let h = &self.hopper;
        let (half, outlet, bin, top) = (h.width / 2.0, h.orifice / 2.0, h.bin(), h.bin() + h.walls);
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let at = |(x, z): (f32, f32), size: f32, y: f32| Vec3::new(x * size, y, z * size);
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            for (size, y) in [(half, bin), (half, top), (outlet, h.drop)] {
                out.push((at(a, size, y), at(b, size, y)));
            }
            out.push((at(a, half, bin), at(a, half, top)));
            out.push((at(a, outlet, h.drop), at(a, half, bin)));
        }
    }

    fn camera(&self) -> CameraHint {
        let h = &self.hopper;
        let top = h.bin() + h.walls;
        // The heap's reach at 25°, from its volume (see `Hopper::of`).
        let volume = h.count as f32 * grain_volume(h.radius) / 0.55;
        let tan = 25f32.to_radians().tan();
        let reach = (3.0 * volume / (std::f32::consts::PI * tan)).cbrt();
        CameraHint {
            target: Vec3::new(0.0, 0.45 * top, 0.0),
            distance: top + 1.6 * reach.max(h.width),
            yaw: 0.6,
            pitch: 0.3,
        }
    }

    fn readout_rows(&self, _dt: f32) -> Vec<Readout> {
        let shown = super::readout::shown;
        let grains = self.world.particles.len();
        let positions = heap_positions(&self.world, self.hopper.drop);
        let height = self.height(&positions);
        let mut rows = vec![
            Readout::new("grains in the heap", format!("{} of {grains}", positions.len()))
                .with("heap_grains", positions.len() as f32)
                .with("grains", grains as f32)
                .help("Grains through the funnel's outlet, on the ground or falling to it"),
            Readout::new("heap height", shown(height, "m")).with("heap_height_m", height).help(
                "The top of the highest grain through the outlet: while grains still fall, the stream's",
            ),
        ];
        rows.push(match self.gauge.settled {
            Some(settled) => Readout::new("angle of repose", format!("{:.1}°", settled.repose))
                .with("repose_deg", settled.repose)
                .with_f64("settled_s", settled.at)
                .help(REPOSE_HELP),
            None => Readout::new("angle of repose", "measured when the heap settles…").help(REPOSE_HELP),
        });
        rows
    }
}

const REPOSE_HELP: &str = "The steepest slope the heap's flank keeps. Measured once the heap has settled \
     (no grain through the opening for 1 s, every grain on the ground slower than 0.05 m/s): the \
     highest grain top in rings two radii wide around the heap's axis, fitted by a straight line over \
     the flank (the rings between a fifth and four fifths of the radius within which 95% of the \
     grains lie), so the rounded top and grains rolled far out do not count. Friction and rolling \
     resistance hold it up: real glass beads rest at about 22° to 26°.";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hopper_holds_its_grains() {
        let params = ParamValues::defaults(&INFO.params);
        let hopper = Hopper::of(&params);
        let world = build_world(&params, &hopper);
        // Every grain starts in the bin, above the funnel and inside its walls.
        let half = hopper.width / 2.0;
        for p in world.particles.positions() {
            assert!(p.y > hopper.bin() + hopper.radius && p.y < hopper.bin() + hopper.walls, "{p}");
            assert!(p.x.abs() < half && p.z.abs() < half, "{p}");
        }
        assert_eq!(heap_positions(&world, hopper.drop).len(), 0);
    }
}

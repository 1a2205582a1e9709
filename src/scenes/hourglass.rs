//! hourglass: grains in a square container drain through a round opening in its floor,
//! and the measured flow is set beside Beverloo's law.
//!
//! The floor is a [`Plate`] in the plane y = 0 with an opening of diameter `orifice`
//! around the origin; the container's walls stand at x, z = ±width/2 and go on below
//! the floor to a basin at `y = -depth`, deep enough to hold every grain with the heap
//! they make there (so the heap never reaches the opening and chokes it). The grains
//! start above the floor as a loose random cloud (see [`starting_cloud`]) and roll
//! (solid spheres of glass, 2500 kg/m³); falling, they pack at random, as poured grains
//! do, rather than in the crystal a regular grid would settle into.
//!
//! Beverloo et al. (1961) found that the mass flow out of a flat-bottomed silo does not
//! depend on how full it is, and fits W = C ρ_b √g (D − k d)^{5/2} with C ≈ 0.58 and
//! k ≈ 1.5, for an opening of diameter D, grains of diameter d and the bed's bulk
//! density ρ_b. The scene measures both sides: the flow as the mass of grains that
//! crossed the floor in the last second, and ρ_b as the packing of the bed (see
//! [`bed_packing`]) times the grains' density.

use std::borrow::Cow;
use std::collections::VecDeque;

use glam::Vec3;

use super::granular::{self, Material, SplitMix64};
use super::runs::{Column, Runs, Table};
use super::{CameraHint, Param, ParamError, ParamTable, ParamValues, Scene, SceneEntry, SceneInfo};
use crate::physics::{DEFAULT_ROLLING_RESISTANCE, PhysicsError, Plate, ResolveReport, World};

/// Density of a grain: glass (kg/m³).
pub const GRAIN_DENSITY: f32 = 2500.0;
/// Beverloo's constant C (dimensionless).
pub const BEVERLOO_C: f32 = 0.58;
/// Beverloo's empty-annulus constant k (grain diameters).
pub const BEVERLOO_K: f32 = 1.5;
/// The span the measured flow is averaged over (s).
pub const FLOW_WINDOW: f64 = 1.0;
/// The steady part of a drain, as fractions of the grains through: it starts once a
/// tenth has passed (the start-up transient over) and ends when 45% have, while the
/// bed is still deeper than the opening is wide and the flow does not depend on its
/// depth, as Beverloo's law assumes. Below that the flow slows as the bed empties.
pub const STEADY_PART: (f32, f32) = (0.10, 0.45);
/// How often the drain's record takes a sample (s).
pub const DRAIN_SAMPLE: f64 = 0.1;
/// Most samples the drain's record keeps (an hour at [`DRAIN_SAMPLE`]).
const DRAIN_SAMPLES_KEPT: usize = 36_000;

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("orifice"), unit: Cow::Borrowed("m"), default: 1.4, min: 0.05, max: 50.0, help: Cow::Borrowed("Diameter of the opening in the floor"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("radius"), unit: Cow::Borrowed("m"), default: 0.1, min: 0.01, max: 2.0, help: Cow::Borrowed("Radius of every grain"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("count"), unit: Cow::Borrowed(""), default: 4000.0, min: 1.0, max: 200_000.0, help: Cow::Borrowed("Number of grains (rounded to a whole number)"), logarithmic: true, integer: true },
    Param { name: Cow::Borrowed("friction"), unit: Cow::Borrowed(""), default: 0.5, min: 0.0, max: 2.0, help: Cow::Borrowed("Coulomb friction coefficient between grains, walls and floor"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("seed"), unit: Cow::Borrowed(""), default: 0.0, min: 0.0, max: 1_000_000.0, help: Cow::Borrowed("Random start: which jitter the starting cloud gets (rounded; 0 is the shipped one)"), logarithmic: false, integer: true },
    Param { name: Cow::Borrowed("rolling_resistance"), unit: Cow::Borrowed(""), default: DEFAULT_ROLLING_RESISTANCE, min: 0.0, max: 1.0, help: Cow::Borrowed("Rolling resistance coefficient of every contact"), logarithmic: false, integer: false },
    // Some gravity: the grains must drain.
    Param { min: 0.1, ..super::GRAVITY },
];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("hourglass"),
    summary: Cow::Borrowed("Grains drain through an opening in a floor; the flow beside Beverloo's law"),
    // Half the pile's step: at 1/60 s the flow came out 10% slower than at 1/120 s for
    // an opening of 5 grains (tests/hourglass.rs), the contacts too soft for grains
    // this small to pass each other as quickly as they should.
    dt: 1.0 / 120.0,
    default_steps: 1200,
    params: ParamTable::Static(PARAMS),
    ..granular::LOOK
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

fn create(params: ParamValues) -> Box<dyn Scene> {
    let shape = Shape::of(&params);
    Box::new(Hourglass {
        world: build_world(&params, &shape),
        params,
        shape,
        samples: VecDeque::new(),
        packing: 0.0,
        drain: Vec::new(),
        tabled: false,
        runs: Runs::new(RUN_COLUMNS),
    })
}

/// The container's measurements, all from the parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Opening's diameter D (m).
    pub orifice: f32,
    /// Grain radius (m).
    pub radius: f32,
    /// Number of grains.
    pub count: usize,
    /// Inner width of the container (m): 2.5 openings, and at least 12 grain diameters.
    pub width: f32,
    /// Depth of the basin's floor below the opening (m).
    pub depth: f32,
    /// Height of the grains' starting grid (m).
    pub start_height: f32,
    /// Which random start: 0 is the shipped cloud, any other number another cloud.
    pub seed: u64,
}

impl Shape {
    /// The container the parameters ask for.
    #[must_use]
    pub fn of(params: &ParamValues) -> Self {
        let (orifice, radius) = (params.get("orifice"), params.get("radius"));
        let count = params.get("count").round().max(1.0) as usize;
        let seed = params.get("seed").round().max(0.0) as u64;
        let d = 2.0 * radius;
        let width = (2.5 * orifice).max(12.0 * d);
        // Every grain at a loose packing (0.55) over the basin's floor, plus the heap's
        // rise from the walls to the middle at 40°, plus room to fall.
        let bed = count as f32 * grain_volume(radius) / (0.55 * width * width);
        let depth = bed + 0.5 * width * 40f32.to_radians().tan() + 6.0 * d;
        let start_height =
            starting_cloud(count, radius, width, seed).iter().fold(0.0f32, |top, p| top.max(p.y)) + radius;
        Self { orifice, radius, count, width, depth, start_height, seed }
    }

    /// The mass of one grain (kg).
    #[must_use]
    pub fn grain_mass(&self) -> f32 {
        GRAIN_DENSITY * grain_volume(self.radius)
    }

    /// Beverloo's mass flow (kg/s) for a bed of packing fraction `packing` under
    /// gravity `g`: C ρ_b √g (D − k d)^{5/2}, zero for an opening of k grains or less.
    #[must_use]
    pub fn beverloo(&self, packing: f32, g: f32) -> f32 {
        let free = (self.orifice - BEVERLOO_K * 2.0 * self.radius).max(0.0);
        BEVERLOO_C * packing * GRAIN_DENSITY * g.sqrt() * free.powf(2.5)
    }
}

/// A sphere's volume (m³).
pub(super) fn grain_volume(radius: f32) -> f32 {
    4.0 / 3.0 * std::f32::consts::PI * radius.powi(3)
}

fn build_world(params: &ParamValues, shape: &Shape) -> World {
    let (friction, rolling, g) = (params.get("friction"), params.get("rolling_resistance"), params.get("g"));
    let mut world = World::new();
    let material = Material { restitution: 0.0, friction, rolling_resistance: rolling };
    granular::add_box(&mut world, -shape.depth, shape.width, material);
    let floor = Plate::new(Vec3::Y, Vec3::ZERO, shape.orifice / 2.0, 0.0, friction)
        .expect("parameter ranges keep the floor valid")
        .with_rolling_resistance(rolling);
    world.add_contact_generator(floor).expect("a plate from Plate::new is valid");
    granular::add_sphere_collisions(&mut world, material);
    let cloud = starting_cloud(shape.count, shape.radius, shape.width, shape.seed);
    granular::add_spheres(&mut world, &cloud, shape.grain_mass(), shape.radius, g, true);
    world
}

/// Spacing of the starting cloud's lattice, in grain diameters.
const CLOUD_SPACING: f32 = 1.5;
/// Largest offset of a grain from its lattice point on each axis, in grain diameters:
/// neighbours stay at least 1.5 − 2·0.25 = 1 diameter apart, so none overlap.
const CLOUD_JITTER: f32 = 0.25;
/// Seed of the shipped cloud (`seed` 0; every run with one seed is the same).
const CLOUD_SEED: u64 = 0x0000_0600_D61A_55E5_u64;

/// `count` grain centres above the floor: a lattice 1.5 diameters apart, filled layer
/// by layer from a diameter above the floor, each point moved at random by up to a
/// quarter diameter along each axis, all inside the container's walls. `seed` picks
/// the random offsets (0: the shipped cloud): a convergence study drains several
/// random starts, since whether an opening jams is a matter of chance.
#[must_use]
pub fn starting_cloud(count: usize, radius: f32, width: f32, seed: u64) -> Vec<Vec3> {
    let d = 2.0 * radius;
    let spacing = CLOUD_SPACING * d;
    let room = width - d - 2.0 * CLOUD_JITTER * d;
    let columns = ((room / spacing).floor() as usize + 1).max(1);
    let span = (columns - 1) as f32 * spacing;
    let mut random = SplitMix64(CLOUD_SEED ^ seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    // A uniform offset in ±CLOUD_JITTER diameters.
    let mut jitter = move || (random.unit() * 2.0 - 1.0) * CLOUD_JITTER * d;
    let mut positions = Vec::with_capacity(count);
    'fill: for layer in 0.. {
        for row in 0..columns {
            for column in 0..columns {
                if positions.len() == count {
                    break 'fill;
                }
                let base = Vec3::new(
                    column as f32 * spacing - span / 2.0,
                    d + layer as f32 * spacing,
                    row as f32 * spacing - span / 2.0,
                );
                positions.push(base + Vec3::new(jitter(), jitter(), jitter()));
            }
        }
    }
    positions
}

/// A flow as the panel shows it: to the 4 significant figures a second's count of
/// grains supports (3388 kg/s, not 3387.6196); `simulate` prints every digit.
fn sig(flow: f32) -> String {
    super::runs::significant(f64::from(flow), super::runs::FIGURES)
}

/// What the steady flow is and how it is measured.
const STEADY_HELP: &str = "Measured: the least-squares slope of the mass through the opening against time, \
    sampled every 0.1 s, from when a tenth of the grains had passed until 45% had: the bed is then still \
    deeper than the opening is wide, as Beverloo's law assumes. ± is the spread (standard deviation) of \
    the flow over each second of that part. Later the flow slows as the bed empties; that is not mixed in.";

/// What the flow read-out is and how it is measured.
const FLOW_HELP: &str = "The mass that fell through the opening in the last second of simulated time: grains \
    through now less a second ago, times a grain's mass, over the time between.";

/// Grains wholly below the floor: their centre more than a radius under y = 0.
#[must_use]
pub fn grains_through(world: &World) -> usize {
    let p = &world.particles;
    p.position.iter().zip(&p.radius).filter(|(c, r)| c.y < -**r).count()
}

/// The packing fraction of the bed resting in the container: the grains' volume over
/// the volume of a measuring cell, counting the grains whose centres lie in it. The
/// cell is a layer from one to five grain diameters above the floor (clear of the
/// ordered layer on the floor and of the free surface of a full container), and of the
/// floor's area it takes the square ring between a quarter of the width from the
/// middle and a diameter from the walls: the bed that stands still while the middle
/// flows (the flowing core is looser) and that is not ordered by a wall.
#[must_use]
pub fn bed_packing(world: &World, shape: &Shape) -> f32 {
    let d = 2.0 * shape.radius;
    let (inner, outer) = (shape.width / 4.0, shape.width / 2.0 - d);
    if outer <= inner {
        return 0.0;
    }
    let (bottom, top) = (d, 5.0 * d);
    let p = &world.particles;
    let inside = p
        .position
        .iter()
        .filter(|c| {
            let from_middle = c.x.abs().max(c.z.abs());
            c.y >= bottom && c.y < top && from_middle >= inner && from_middle < outer
        })
        .count();
    let cell = (4.0 * outer * outer - 4.0 * inner * inner) * (top - bottom);
    inside as f32 * grain_volume(shape.radius) / cell
}

struct Hourglass {
    world: World,
    params: ParamValues,
    shape: Shape,
    /// (time, grains through) after each step of the last [`FLOW_WINDOW`] and one more.
    samples: VecDeque<(f64, usize)>,
    /// The densest packing the bed has shown since the grains were poured: the bed at
    /// rest before the drain lowers it out of the measuring cell.
    packing: f32,
    /// (time, grains through) every [`DRAIN_SAMPLE`] since the start: the record the
    /// steady flow is fitted to.
    drain: Vec<(f64, usize)>,
    /// Whether this drain's steady flow is in the table.
    tabled: bool,
    /// The table of runs, in [`RUN_COLUMNS`].
    runs: Runs,
}

/// The columns of the hourglass's table of runs: a row for each drain, once its steady
/// part is over (45% of the grains through).
pub static RUN_COLUMNS: &[Column] = &[
    Column { key: "orifice_m", heading: "D (m)", help: "Diameter of the opening", always: true },
    Column { key: "radius_m", heading: "r (m)", help: "Radius of every grain", always: false },
    Column { key: "count", heading: "grains", help: "Grains poured", always: false },
    Column { key: "friction", heading: "μ", help: "Coulomb friction coefficient", always: false },
    Column {
        key: "rolling_resistance",
        heading: "μ_r",
        help: "Rolling resistance coefficient",
        always: false,
    },
    Column { key: "g_m_s2", heading: "g (m/s²)", help: "Gravitational acceleration", always: false },
    Column { key: "opening_grains", heading: "D/d", help: "The opening in grain diameters", always: true },
    Column {
        key: "packing",
        heading: "packing",
        help: "Measured: the bed's packing fraction before the drain lowered it",
        always: false,
    },
    Column {
        key: "steady_flow_kg_s",
        heading: "steady flow (kg/s)",
        help: "Measured: the least-squares flow from 10% to 45% of the grains through",
        always: true,
    },
    Column {
        key: "steady_flow_spread_kg_s",
        heading: "± (kg/s)",
        help: "Measured: the standard deviation of each second's flow in that part",
        always: true,
    },
    Column {
        key: "beverloo_predicted_kg_s",
        heading: "Beverloo (kg/s)",
        help: "Predicted by Beverloo's law, 0.58 ρ_b √g (D − 1.5 d)^(5/2), with the measured packing: an \
               empirical law for a deep bed that leaves out friction's detail",
        always: true,
    },
    Column {
        key: "steady_over_predicted",
        heading: "ratio",
        help: "The steady flow over Beverloo's",
        always: true,
    },
];

/// The steady flow of a drain: the least-squares slope of the discharged mass against
/// time over [`STEADY_PART`], and the spread of the flow over each second in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadyFlow {
    /// Mass flow (kg/s).
    pub flow: f32,
    /// Standard deviation of the flows over the whole seconds in the steady part (kg/s).
    pub spread: f32,
    /// Where the steady part began and ended (s).
    pub from: f64,
    /// See `from`.
    pub to: f64,
}

/// The steady flow of a drain recorded as `(time, grains through)` samples, `grains`
/// in all of `grain_mass` kg each: `None` until the steady part has lasted a second.
#[must_use]
pub fn steady_flow(record: &[(f64, usize)], grains: usize, grain_mass: f32) -> Option<SteadyFlow> {
    let (low, high) = (STEADY_PART.0 * grains as f32, STEADY_PART.1 * grains as f32);
    let steady: Vec<(f64, usize)> =
        record.iter().copied().filter(|&(_, n)| n as f32 >= low && n as f32 <= high).collect();
    let (from, to) = (steady.first()?.0, steady.last()?.0);
    if to - from < 1.0 {
        return None;
    }
    let mass = f64::from(grain_mass);
    let fit = super::runs::least_squares(steady.iter().map(|&(t, n)| (t, n as f64 * mass)))?;
    // The flow over each whole second from the start of the steady part.
    let mut flows = Vec::new();
    let mut start = steady[0];
    for &(t, n) in &steady[1..] {
        if t - start.0 >= 1.0 - 1e-9 {
            flows.push((n - start.1) as f64 * mass / (t - start.0));
            start = (t, n);
        }
    }
    let mean = flows.iter().sum::<f64>() / flows.len() as f64;
    let spread = (flows.iter().map(|f| (f - mean).powi(2)).sum::<f64>() / flows.len() as f64).sqrt();
    Some(SteadyFlow { flow: fit.slope as f32, spread: spread as f32, from, to })
}

impl Hourglass {
    /// Puts this drain's steady flow in the table, if its steady part lasted a second.
    fn add_run(&mut self) {
        let shape = &self.shape;
        let grains = self.world.particles.len();
        let Some(steady) = steady_flow(&self.drain, grains, shape.grain_mass()) else { return };
        let beverloo = shape.beverloo(self.packing, self.params.get("g"));
        let p = |name| f64::from(self.params.get(name));
        let row = vec![
            p("orifice"),
            p("radius"),
            grains as f64,
            p("friction"),
            p("rolling_resistance"),
            p("g"),
            f64::from(shape.orifice / (2.0 * shape.radius)),
            f64::from(self.packing),
            f64::from(steady.flow),
            f64::from(steady.spread),
            f64::from(beverloo),
            if beverloo > 0.0 { f64::from(steady.flow / beverloo) } else { f64::NAN },
        ];
        self.runs.push(row);
    }

    /// The mass flow over the last [`FLOW_WINDOW`] (kg/s), once a window's samples are in.
    fn flow(&self) -> Option<f32> {
        let (&(t1, n1), &(t0, n0)) = (self.samples.back()?, self.samples.front()?);
        (t1 - t0 >= FLOW_WINDOW - 1e-9)
            .then(|| (n1.saturating_sub(n0)) as f32 * self.shape.grain_mass() / (t1 - t0) as f32)
    }
}

impl Scene for Hourglass {
    scene_basics!();

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        if super::set_param_or_gravity(&mut self.params, &mut self.world, name, value)? {
            // Everything else shapes the container or the grains: pour them again.
            self.shape = Shape::of(&self.params);
            let running = std::mem::replace(&mut self.world, build_world(&self.params, &self.shape));
            super::keep_solver(&running, &mut self.world);
        }
        self.samples.clear();
        self.packing = 0.0;
        self.drain.clear();
        self.tabled = false;
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        let report = self.world.step(dt)?;
        let now = self.world.time();
        // A world put back (a snapshot, a reset) breaks the series: start it again.
        if self.samples.back().is_some_and(|&(t, _)| now <= t || now - t > 4.0 * f64::from(dt)) {
            self.samples.clear();
            self.packing = 0.0;
        }
        let through = grains_through(&self.world);
        self.samples.push_back((now, through));
        // The drain's record: a sample every DRAIN_SAMPLE, started again with the world.
        if self.drain.last().is_some_and(|&(t, _)| now <= t) {
            self.drain.clear();
            self.tabled = false;
        }
        let due = self.drain.last().is_none_or(|&(t, _)| now - t >= DRAIN_SAMPLE - 1e-9);
        if due && self.drain.len() < DRAIN_SAMPLES_KEPT {
            self.drain.push((now, through));
        }
        while self.samples.len() > 2 && now - self.samples[1].0 >= FLOW_WINDOW - 1e-9 {
            self.samples.pop_front();
        }
        self.packing = self.packing.max(bed_packing(&self.world, &self.shape));
        let grains = self.world.particles.len();
        if !self.tabled && through as f32 > STEADY_PART.1 * grains as f32 {
            self.tabled = true;
            self.add_run();
        }
        Ok(report)
    }

    fn runs(&self) -> Option<Table<'_>> {
        Some(self.runs.table())
    }

    fn delete_runs(&mut self, which: Option<usize>) -> bool {
        self.runs.delete(which);
        true
    }

    fn save_state(&self) -> serde_json::Value {
        // The gauges: the flow is measured over the last second of samples, and the
        // packing is the densest the bed has shown, so neither can be read off the
        // world alone.
        serde_json::json!({
            "samples": self.samples,
            "packing": self.packing,
            "drain": self.drain,
            "tabled": self.tabled,
            "runs": self.runs.saved(),
        })
    }

    fn restore_state(&mut self, state: &super::RawValue) -> Result<(), String> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Saved {
            samples: VecDeque<(f64, usize)>,
            packing: f32,
            #[serde(default)]
            drain: Vec<(f64, usize)>,
            // Snapshots from before the table of runs have neither.
            #[serde(default)]
            tabled: Option<bool>,
            #[serde(default)]
            runs: Vec<Vec<Option<f64>>>,
        }
        let saved: Saved = super::read_state(state)?;
        if !(saved.packing.is_finite() && (0.0..=1.0).contains(&saved.packing)) {
            return Err(format!("packing = {} is out of range; valid range: 0 to 1", saved.packing));
        }
        let (now, grains) = (self.world.time(), self.world.particles.len());
        if saved.drain.len() > DRAIN_SAMPLES_KEPT {
            return Err(format!(
                "drain: {} samples, more than the {DRAIN_SAMPLES_KEPT} kept",
                saved.drain.len()
            ));
        }
        // Each record: times within the world's, in order, counts never falling.
        let check = |name: &str, record: &mut dyn Iterator<Item = &(f64, usize)>| -> Result<(), String> {
            let mut last = (f64::NEG_INFINITY, 0);
            for &(t, through) in record {
                if !(t.is_finite() && t >= 0.0 && t <= now) {
                    return Err(format!(
                        "{name}: a sample at t = {t} s is outside 0 to the world's {now:.3} s"
                    ));
                }
                if t <= last.0 || through < last.1 || through > grains {
                    return Err(format!(
                        "{name}: each must be later than the one before and count no fewer grains \
                         (at most the {grains} there are); ({t} s, {through}) is not"
                    ));
                }
                last = (t, through);
            }
            Ok(())
        };
        check("samples", &mut saved.samples.iter())?;
        check("drain", &mut saved.drain.iter())?;
        let runs = self.runs.read(saved.runs)?;
        // An old snapshot past its steady part did not table it: leave it so.
        let past = saved.drain.last().is_some_and(|&(_, n)| n as f32 > STEADY_PART.1 * grains as f32);
        self.tabled = saved.tabled.unwrap_or(past);
        self.runs = runs;
        (self.samples, self.packing, self.drain) = (saved.samples, saved.packing, saved.drain);
        Ok(())
    }

    fn outlines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        let half = self.shape.width / 2.0;
        let (top, bottom) = (self.shape.start_height.max(4.0 * self.shape.radius), -self.shape.depth);
        let corners = [(-half, -half), (half, -half), (half, half), (-half, half)];
        for k in 0..4 {
            let (ax, az) = corners[k];
            let (bx, bz) = corners[(k + 1) % 4];
            for y in [top, 0.0, bottom] {
                out.push((Vec3::new(ax, y, az), Vec3::new(bx, y, bz)));
            }
            out.push((Vec3::new(ax, bottom, az), Vec3::new(ax, top, az)));
        }
        // The opening's rim.
        let (rim, sides) = (self.shape.orifice / 2.0, 32);
        let at = |k: usize| {
            let angle = k as f32 / sides as f32 * std::f32::consts::TAU;
            Vec3::new(rim * angle.cos(), 0.0, rim * angle.sin())
        };
        for k in 0..sides {
            out.push((at(k), at(k + 1)));
        }
    }

    fn camera(&self) -> CameraHint {
        let (top, bottom) = (self.shape.start_height, -self.shape.depth);
        let height = top - bottom;
        CameraHint {
            target: Vec3::new(0.0, 0.5 * (top + bottom), 0.0),
            distance: 1.2 * height + 1.5 * self.shape.width,
            yaw: 0.6,
            pitch: 0.25,
        }
    }

    fn ground(&self) -> f32 {
        -self.shape.depth
    }

    fn gravity_reference(&self) -> Option<(f32, &'static str)> {
        // Where every grain ends up: the basin's floor, not the plate they start on.
        Some((-self.shape.depth, "the basin's floor"))
    }

    fn readout_rows(&self, _dt: f32) -> Vec<super::Readout> {
        use super::Readout;
        let shape = &self.shape;
        let through = grains_through(&self.world);
        let grains = self.world.particles.len();
        let beverloo = shape.beverloo(self.packing, self.params.get("g"));
        let opening = shape.orifice / (2.0 * shape.radius);
        let mut rows = vec![
            Readout::new("opening / grain", format!("{opening:.1} diameters"))
                .with("opening_grains", opening)
                .help(
                    "The opening's diameter over a grain's (D/d). Below about 5 an arch of grains can \
                     span it and jam the flow; the wider, the rarer the jams.",
                ),
            Readout::new("grains through", format!("{through} of {grains}"))
                .with("grains_through", through as f32)
                .with("grains", grains as f32)
                .help("Grains wholly below the floor (their centre more than a radius under it), of all grains"),
            Readout::new("bed packing", format!("{:.3}", self.packing)).with("packing", self.packing).help(
                "The share of the bed's volume the grains fill: their volume over a layer one to five \
                 grain diameters above the floor, at its densest so far. Random close packing of \
                 equal spheres is about 0.64.",
            ),
            Readout::new("Beverloo's flow", format!("{} kg/s", sig(beverloo))).with("beverloo_kg_s", beverloo).help(
                "Beverloo's law for a silo's steady mass flow: W = C ρ_b √g (D − k d)^(5/2), with C = 0.58, \
                 k = 1.5, ρ_b the bed's density (packing × the grains' density), D the opening, d a \
                 grain's diameter. An empirical law for a deep bed: it leaves out the bed's height \
                 (it holds while the bed is more than about an opening deep) and friction's detail.",
            ),
        ];
        match self.flow() {
            Some(flow) => {
                rows.push(
                    Readout::new("flow (last 1 s)", format!("{} kg/s", sig(flow)))
                        .with("flow_kg_s", flow)
                        .help(FLOW_HELP),
                );
                if beverloo > 0.0 {
                    let ratio = flow / beverloo;
                    rows.push(
                        Readout::new("flow / Beverloo", format!("{ratio:.3}"))
                            .with("flow_over_beverloo", ratio)
                            .help(
                                "The last second's flow over Beverloo's. It falls as the bed drains below \
                                 an opening's depth, where the law no longer holds: compare the steady \
                                 flow's ratio instead.",
                            ),
                    );
                }
            }
            None => rows.push(Readout::new("flow (last 1 s)", "measuring…").help(FLOW_HELP)),
        }
        let (low, high) = (STEADY_PART.0 * 100.0, STEADY_PART.1 * 100.0);
        match steady_flow(&self.drain, grains, shape.grain_mass()) {
            Some(steady) => {
                rows.push(
                    Readout::new(
                        "steady flow (10–45% through)",
                        format!(
                            "{} ± {} kg/s over {:.1}–{:.1} s",
                            sig(steady.flow),
                            sig(steady.spread),
                            steady.from,
                            steady.to
                        ),
                    )
                    .with("steady_flow_kg_s", steady.flow)
                    .with("steady_flow_spread_kg_s", steady.spread)
                    .with_f64("steady_from_s", steady.from)
                    .with_f64("steady_to_s", steady.to)
                    .help(STEADY_HELP),
                );
                if beverloo > 0.0 {
                    let ratio = steady.flow / beverloo;
                    rows.push(
                        Readout::new("steady flow / Beverloo", format!("{ratio:.3}"))
                            .with("steady_flow_over_beverloo", ratio)
                            .help(
                                "The steady flow over Beverloo's: the figure to compare with the law, which \
                                 is for a bed deeper than the opening. Frictional, rolling-resistant spheres \
                                 give about 0.8 to 0.9 of it here.",
                            ),
                    );
                }
            }
            None => rows.push(
                Readout::new(
                    "steady flow (10–45% through)",
                    format!("waiting for {low:.0}% to {high:.0}% through…"),
                )
                .help(STEADY_HELP),
            ),
        }
        rows
    }
}

#[cfg(test)]
mod tests {
    use super::steady_flow;

    #[test]
    fn a_steady_drain_gives_its_rate_and_no_spread() {
        // 1000 grains of 0.01 kg, 100 a second: 1 kg/s. The steady part runs from 100
        // through (t = 1 s) to 450 (t = 4.5 s).
        let record: Vec<(f64, usize)> =
            (0..=100_u32).map(|k| (f64::from(k) * 0.1, k as usize * 10)).collect();
        let steady = steady_flow(&record, 1000, 0.01).unwrap();
        assert!((steady.flow - 1.0).abs() < 1e-5, "{steady:?}");
        assert!(steady.spread < 1e-5, "{steady:?}");
        assert!((steady.from - 1.0).abs() < 1e-9 && (steady.to - 4.5).abs() < 1e-9, "{steady:?}");
    }

    #[test]
    fn the_spread_is_that_of_each_seconds_flow_and_a_short_drain_has_none() {
        // Seconds of 80 and 120 grains a second in turn, 800 grains: the steady part
        // runs from 80 through (t = 1 s) to 360, whole seconds of 120 and 80 a second,
        // spread 20; the fit's slope is near their mean.
        let mut record = vec![(0.0, 0)];
        let mut n = 0;
        for k in 1..=100 {
            n += if (k - 1) / 10 % 2 == 0 { 8 } else { 12 };
            record.push((f64::from(k) * 0.1, n));
        }
        let steady = steady_flow(&record, 800, 1.0).unwrap();
        assert!((steady.flow - 100.0).abs() < 2.0, "{steady:?}");
        assert!((steady.spread - 20.0).abs() < 1e-3, "{steady:?}");
        // Under a second of steady part: nothing yet.
        assert_eq!(steady_flow(&record[..25], 100, 1.0), None);
    }
}

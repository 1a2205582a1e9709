//! pile: many spheres dropped into an open box, falling, piling up and coming to rest.
//! The scene the broad phase and the soft step were built for.
//!
//! `count` spheres start on a jittered grid (a fixed seed, so every run is the same)
//! above the ground and fall into a box whose inner walls stand at x, z = ±width/2 on
//! the ground plane y = 0, open at the top.

use std::borrow::Cow;

use glam::Vec3;

use super::granular::{self, Material, SplitMix64};
use super::{CameraHint, Param, ParamError, ParamTable, ParamValues, Scene, SceneEntry, SceneInfo};
use crate::physics::{DEFAULT_ROLLING_RESISTANCE, PhysicsError, ResolveReport, World};

/// Gap between neighbours on the starting grid, as a fraction of the diameter.
const GRID_GAP: f32 = 0.25;
/// Largest random offset of a starting position, as a fraction of the radius.
const JITTER: f32 = 0.2;
/// Seed of the starting jitter.
const SEED: u64 = 0x005E_ED0F_911E;

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("count"), unit: Cow::Borrowed(""), default: 2000.0, min: 1.0, max: 200_000.0, help: Cow::Borrowed("Number of spheres (rounded to a whole number)"), logarithmic: true, integer: true },
    Param { name: Cow::Borrowed("radius"), unit: Cow::Borrowed("m"), default: 0.5, min: 0.05, max: 2.0, help: Cow::Borrowed("Radius of every sphere"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("mass"), unit: Cow::Borrowed("kg"), default: 1.0, min: 0.01, max: 100.0, help: Cow::Borrowed("Mass of every sphere"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("width"), unit: Cow::Borrowed("m"), default: 16.0, min: 1.0, max: 1000.0, help: Cow::Borrowed("Inner width of the box (its walls stand at ±width/2)"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("restitution"), unit: Cow::Borrowed(""), default: 0.0, min: 0.0, max: 1.0, help: Cow::Borrowed("Coefficient of restitution between spheres, walls and ground"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("friction"), unit: Cow::Borrowed(""), default: 0.5, min: 0.0, max: 2.0, help: Cow::Borrowed("Coulomb friction coefficient between spheres, walls and ground"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("rolling_resistance"), unit: Cow::Borrowed(""), default: DEFAULT_ROLLING_RESISTANCE, min: 0.0, max: 1.0, help: Cow::Borrowed("Rolling resistance coefficient: the torque opposing a sphere's roll is at most this times its radius times the normal force"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("rolls"), unit: Cow::Borrowed(""), default: 1.0, min: 0.0, max: 1.0, help: Cow::Borrowed("1: solid spheres that roll (I = 2/5 m r²); 0: the paper's point masses, which slide but never turn"), logarithmic: false, integer: true },
    super::GRAVITY,
];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("pile"),
    summary: Cow::Borrowed("Spheres dropped into an open box pile up and come to rest"),
    dt: 1.0 / 60.0,
    default_steps: 600,
    params: ParamTable::Static(PARAMS),
    ..granular::LOOK
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

fn create(params: ParamValues) -> Box<dyn Scene> {
    Box::new(Pile { world: build_world(&params), params })
}

/// The number of spheres the parameters ask for.
fn count(params: &ParamValues) -> usize {
    params.get("count").round().max(1.0) as usize
}

/// Builds the pile's world: the box, the collisions and the spheres on their grid.
fn build_world(params: &ParamValues) -> World {
    let (radius, mass, width) = (params.get("radius"), params.get("mass"), params.get("width"));
    let (restitution, friction, g) = (params.get("restitution"), params.get("friction"), params.get("g"));
    let (rolling, rolls) = (params.get("rolling_resistance"), params.get("rolls") >= 0.5);
    let mut world = World::new();
    let material = Material { restitution, friction, rolling_resistance: rolling };
    granular::add_box(&mut world, 0.0, width, material);
    granular::add_sphere_collisions(&mut world, material);
    granular::add_spheres(&mut world, &starting_grid(count(params), radius, width), mass, radius, g, rolls);
    world
}

/// `count` positions on a jittered grid filling the box's floor layer by layer, the
/// lowest layer just above the ground. Odd layers sit over the hollows of the layer
/// below (one row and column fewer), so the spheres fall into a packed pile instead of
/// stacking in columns.
#[must_use]
pub fn starting_grid(count: usize, radius: f32, width: f32) -> Vec<Vec3> {
    let spacing = 2.0 * radius * (1.0 + GRID_GAP);
    // Columns that fit between the walls with the jitter (at least one).
    let room = width - 2.0 * radius * (1.0 + JITTER);
    let columns = ((room / spacing).floor() as usize + 1).max(1);
    let mut random = SplitMix64(SEED);
    let mut positions = Vec::with_capacity(count);
    let mut layer = 0;
    while positions.len() < count {
        let across = if layer % 2 == 1 && columns > 1 { columns - 1 } else { columns };
        let span = (across - 1) as f32 * spacing;
        let y = radius * (1.0 + GRID_GAP) + layer as f32 * spacing;
        for row in 0..across {
            for column in 0..across {
                if positions.len() == count {
                    break;
                }
                let mut jitter = || (random.unit() * 2.0 - 1.0) * JITTER * radius;
                let (dx, dz) = (jitter(), jitter());
                let x = column as f32 * spacing - span / 2.0 + dx;
                let z = row as f32 * spacing - span / 2.0 + dz;
                positions.push(Vec3::new(x, y, z));
            }
        }
        layer += 1;
    }
    positions
}

/// How settled a pile is: what the tests, the benchmark and the panel report.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PileQuality {
    /// Median speed of the spheres (m/s).
    pub median_speed: f32,
    /// Fastest sphere (m/s).
    pub max_speed: f32,
    /// Deepest overlap between two spheres, or a sphere and a wall or the ground (m),
    /// measured on the positions (not the solver's own estimate).
    pub deepest_overlap: f32,
    /// Spheres whose centre is outside the box or below the ground.
    pub escaped: usize,
}

/// Measures a pile in a box of inner width `width` on the ground `y = 0`.
#[must_use]
pub fn quality(world: &World, width: f32) -> PileQuality {
    let p = &world.particles;
    let mut speeds: Vec<f32> = p.velocity.iter().map(|v| v.length()).collect();
    let max_speed = speeds.iter().copied().fold(0.0, f32::max);
    let median_speed = if speeds.is_empty() {
        0.0
    } else {
        let middle = speeds.len() / 2;
        *speeds.select_nth_unstable_by(middle, f32::total_cmp).1
    };
    let half = width / 2.0;
    let mut deepest = 0.0f32;
    let mut escaped = 0;
    for (&c, &r) in p.position.iter().zip(&p.radius) {
        let gaps = [c.y, half - c.x, c.x + half, half - c.z, c.z + half];
        if gaps.iter().any(|&gap| gap < 0.0) {
            escaped += 1;
        }
        for gap in gaps {
            deepest = deepest.max(r - gap);
        }
    }
    let mut pairs = Vec::new();
    crate::physics::BroadPhase::new().find_pairs(&p.position, &p.radius, &mut pairs);
    for (a, b) in pairs {
        let (a, b) = (a as usize, b as usize);
        let overlap = p.radius[a] + p.radius[b] - p.position[a].distance(p.position[b]);
        deepest = deepest.max(overlap);
    }
    PileQuality { median_speed, max_speed, deepest_overlap: deepest, escaped }
}

/// The angle of repose (degrees) of a heap of spheres of `radius` on flat ground,
/// from its surface: the highest sphere top in rings `2 radius` wide around the heap's
/// axis (through the spheres' mean), fitted by least squares over the flank (rings
/// between a fifth and four fifths of the radius within which 95% of the spheres lie),
/// so that stray spheres rolled far out and the rounded top do not count. 90 for a
/// heap with no flank (a column still standing); 0 for no spheres.
#[must_use]
pub fn angle_of_repose(positions: &[Vec3], radius: f32) -> f32 {
    if positions.is_empty() {
        return 0.0;
    }
    let n = positions.len() as f32;
    let centre = positions.iter().fold(Vec3::ZERO, |sum, p| sum + *p) / n;
    let radial = |p: &Vec3| Vec3::new(p.x - centre.x, 0.0, p.z - centre.z).length();
    let mut distances: Vec<f32> = positions.iter().map(radial).collect();
    distances.sort_by(f32::total_cmp);
    let reach = distances[((0.95 * n) as usize).min(positions.len() - 1)];
    let ring = 2.0 * radius;
    let rings = (reach / ring).ceil() as usize + 1;
    let mut top = vec![f32::NEG_INFINITY; rings];
    for p in positions {
        let k = (radial(p) / ring) as usize;
        if k < rings {
            top[k] = top[k].max(p.y + radius);
        }
    }
    let points: Vec<(f32, f32)> = (0..rings)
        .map(|k| ((k as f32 + 0.5) * ring, top[k]))
        .filter(|&(r, y)| y.is_finite() && r >= 0.2 * reach && r <= 0.8 * reach)
        .collect();
    if points.len() < 3 {
        return 90.0;
    }
    let m = points.len() as f32;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| (a + x, b + y));
    let (sxx, sxy) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| (a + x * x, b + x * y));
    let slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
    (-slope).atan().to_degrees()
}

struct Pile {
    world: World,
    params: ParamValues,
}

impl Scene for Pile {
    scene_basics!();

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        if super::set_param_or_gravity(&mut self.params, &mut self.world, name, value)? {
            // Everything else shapes the pile from the start: drop it again.
            let running = std::mem::replace(&mut self.world, build_world(&self.params));
            super::keep_solver(&running, &mut self.world);
        }
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        self.world.step(dt)
    }

    fn outlines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        // The box's walls stand on the ground at x, z = ±width/2; drawn as a frame
        // as high as the spheres sat at the start, at least two diameters.
        let half = self.params.get("width") / 2.0;
        let radius = self.params.get("radius");
        let spacing = 2.0 * radius * (1.0 + GRID_GAP);
        let per_layer = ((2.0 * half / spacing).max(1.0)).powi(2);
        let height = ((count(&self.params) as f32 / per_layer).ceil() * spacing).max(4.0 * radius);
        let corners = [(-half, -half), (half, -half), (half, half), (-half, half)];
        for k in 0..4 {
            let (ax, az) = corners[k];
            let (bx, bz) = corners[(k + 1) % 4];
            for y in [0.0, height] {
                out.push((Vec3::new(ax, y, az), Vec3::new(bx, y, bz)));
            }
            out.push((Vec3::new(ax, 0.0, az), Vec3::new(ax, height, az)));
        }
    }

    fn camera(&self) -> CameraHint {
        let width = self.params.get("width");
        let spacing = 2.0 * self.params.get("radius") * (1.0 + GRID_GAP);
        let per_layer = ((width / spacing).max(1.0)).powi(2);
        let start_height = (count(&self.params) as f32 / per_layer).ceil() * spacing;
        let target = Vec3::new(0.0, (start_height * 0.3).min(width * 0.6), 0.0);
        CameraHint { target, distance: width * 1.9 + start_height * 0.5, yaw: 0.6, pitch: 0.45 }
    }

    fn readout_rows(&self, _dt: f32) -> Vec<super::Readout> {
        use super::Readout;
        let quality = quality(&self.world, self.params.get("width"));
        let spheres = self.world.particles.len();
        vec![
            Readout::new("spheres", spheres.to_string())
                .with("spheres", spheres as f32)
                .help("Spheres poured into the box, all of one size"),
            Readout::new("median speed", super::readout::shown(quality.median_speed, "m/s"))
                .with("median_speed_m_s", quality.median_speed)
                .help(
                    "Half the spheres move slower than this. A settled pile is near zero; a solver that \
                     leaves the pile boiling shows here first.",
                ),
            Readout::new("fastest sphere", super::readout::shown(quality.max_speed, "m/s"))
                .with("fastest_m_s", quality.max_speed)
                .help("The speed of the fastest sphere"),
            Readout::new("deepest overlap", super::readout::shown(quality.deepest_overlap * 1000.0, "mm"))
                .with("deepest_overlap_m", quality.deepest_overlap)
                .help(
                    "How far the deepest pair of spheres (or a sphere and a wall or the ground) sink into \
                     each other: the sum of radii less the distance of centres. Soft contacts give under \
                     load like a stiff spring; real spheres would not overlap at all.",
                ),
            Readout::new("outside the box", quality.escaped.to_string())
                .with("outside_box", quality.escaped as f32)
                .help(
                    "Spheres whose centre is outside the box or below the ground: a solver's failure, 0 here",
                ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spheres packed in a cone (a top at 10 m over a base whose radius the slope
    /// gives): the measured angle is the cone's within a degree and a half (the rings'
    /// tops sit up to a sphere's width off the surface).
    #[test]
    fn the_angle_of_a_cone_of_spheres_is_its_slope() {
        for degrees in [20.0f32, 30.0, 40.0] {
            let (radius, height) = (0.5, 10.0);
            let base = height / degrees.to_radians().tan();
            let mut positions = Vec::new();
            let step = 2.0 * radius;
            let cells = (base / step).ceil() as i32;
            for i in -cells..=cells {
                for k in -cells..=cells {
                    let (x, z) = (i as f32 * step, k as f32 * step);
                    let surface = height * (1.0 - (x * x + z * z).sqrt() / base);
                    let mut y = radius;
                    while y + radius <= surface {
                        positions.push(Vec3::new(x, y, z));
                        y += step;
                    }
                }
            }
            let angle = angle_of_repose(&positions, radius);
            assert!((angle - degrees).abs() < 1.5, "a {degrees}° cone measured {angle}°");
        }
        assert_eq!(angle_of_repose(&[], 0.5), 0.0);
        assert_eq!(angle_of_repose(&[Vec3::new(0.0, 0.5, 0.0); 3], 0.5), 90.0);
    }

    #[test]
    fn grid_fits_the_box_and_is_reproducible() {
        let a = starting_grid(500, 0.5, 6.0);
        assert_eq!(a, starting_grid(500, 0.5, 6.0));
        assert!(a.iter().all(|p| p.x.abs() <= 3.0 - 0.5 && p.z.abs() <= 3.0 - 0.5 && p.y >= 0.5), "{a:?}");
        // No two start overlapping.
        let mut pairs = Vec::new();
        crate::physics::broad_phase::all_pairs(&a, &[0.5; 500], &mut pairs);
        assert!(pairs.is_empty(), "{} overlapping pairs", pairs.len());
    }
}

//! A sketch: an experiment made by hand in the lab's builder, held as plain particles,
//! links and surroundings (numbers, no parameters or expressions), and written as a
//! scene file. The builder edits a sketch; every edit writes the sketch's file and
//! loads it as the running scene, so that what is built runs, resets, saves and
//! travels in a link exactly as any scene file does.
//!
//! A sketch can also be taken from a running world ("Edit a copy"): its particles as
//! they stand, its links (springs, stiff springs, rods, cables), drag, buoyancy,
//! ground, walls, plates, sphere collisions, gravity and time step. What the format
//! cannot carry (the rules of a scene built into the program: a projectile's launcher,
//! a bridge's movable load, an hourglass's gauges) is left out, and named.

use std::fmt::Write as _;

use glam::Vec3;

use super::Scene;
use super::file::{float32, toml_string};
use super::launcher::Aim;
use crate::physics::collision::ContactGenerator;
use crate::physics::state::SavedForce;
use crate::physics::{LinkEnd, LinkKind, SolverChoice, World};

/// Most particles a sketch holds (a scene file's limit).
pub const MAX_BODIES: usize = super::file::MAX_PARTICLES;

/// A particle of a sketch.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Position (m).
    pub position: Vec3,
    /// Velocity at the start (m/s).
    pub velocity: Vec3,
    /// Mass (kg).
    pub mass: f32,
    /// Radius (m).
    pub radius: f32,
    /// Fraction of velocity kept per second (1: no damping).
    pub damping: f32,
    /// Immovable.
    pub fixed: bool,
    /// A solid sphere that rolls.
    pub rolls: bool,
    /// Its label in the view (unique in the sketch), if it has one.
    pub name: Option<String>,
    /// Its colour in the view (0–1 components), if not the lab's palette's.
    pub color: Option<[f32; 3]>,
}

impl Default for Body {
    fn default() -> Self {
        Self {
            position: Vec3::ZERO,
            velocity: Vec3::ZERO,
            mass: 1.0,
            radius: 0.1,
            damping: 1.0,
            fixed: false,
            rolls: false,
            name: None,
            color: None,
        }
    }
}

/// The kinds of link the builder makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JoinKind {
    /// A fixed length.
    Rod,
    /// At most its length.
    Cable,
    /// Hooke's law, pushing and pulling.
    Spring,
    /// Hooke's law when stretched, slack when shorter.
    Bungee,
    /// A spring to a fixed point solved in closed form each step (stable at any
    /// stiffness); only to an anchor.
    StiffSpring,
}

impl JoinKind {
    /// Every kind, in the order the builder offers them.
    pub const ALL: [Self; 4] = [Self::Rod, Self::Cable, Self::Spring, Self::Bungee];

    /// Its name in the scene file format: the engine's name for the link it makes.
    #[must_use]
    pub fn name(self) -> &'static str {
        let kind = match self {
            Self::Rod => LinkKind::Rod,
            Self::Cable => LinkKind::Cable,
            Self::Spring => LinkKind::Spring,
            Self::Bungee => LinkKind::Bungee,
            Self::StiffSpring => LinkKind::StiffSpring,
        };
        kind.name()
    }

    /// Whether it has a spring constant.
    #[must_use]
    pub fn elastic(self) -> bool {
        matches!(self, Self::Spring | Self::Bungee | Self::StiffSpring)
    }
}

/// The second end of a link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum End {
    /// A particle, by its number in the sketch.
    Body(usize),
    /// A fixed point (m).
    Anchor(Vec3),
}

/// A link of a sketch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Join {
    /// What sort.
    pub kind: JoinKind,
    /// First end, a particle's number.
    pub a: usize,
    /// Second end.
    pub b: End,
    /// Rod length, cable maximum or spring rest length (m).
    pub length: f32,
    /// Spring constant (N/m), for springs and bungees.
    pub k: f32,
    /// Bounce of a cable snapping taut, 0 to 1 (0 for the other kinds).
    pub restitution: f32,
    /// A stiff spring's damping ratio (0 for the other kinds).
    pub damping_ratio: f32,
}

/// A wall: a plane through `point` facing `normal`, the whole plane or a rectangle of
/// it centred on `point`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    /// Unit normal, towards the free side.
    pub normal: Vec3,
    /// A point of it (m): a finite wall's centre.
    pub point: Vec3,
    /// A finite wall's length and width (m); `None`: the whole plane.
    pub size: Option<[f32; 2]>,
    /// The direction of a finite wall's length.
    pub along: Vec3,
    /// Restitution.
    pub restitution: f32,
    /// Friction.
    pub friction: f32,
    /// Rolling resistance against spheres that roll.
    pub rolling_resistance: f32,
}

/// A surface's restitution and friction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// Restitution, 0 to 1.
    pub restitution: f32,
    /// Coulomb friction coefficient.
    pub friction: f32,
    /// Rolling resistance against spheres that roll.
    pub rolling_resistance: f32,
}

/// A plane with a round opening: a silo's or an hourglass's floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floor {
    /// Unit normal.
    pub normal: Vec3,
    /// The opening's centre, a point of the plane (m).
    pub point: Vec3,
    /// The opening's diameter (m).
    pub opening: f32,
    /// Restitution, friction and rolling resistance.
    pub surface: Surface,
}

/// A drag force `−v (k1 + k2 |v|)`.
#[derive(Clone, Debug, PartialEq)]
pub struct DragField {
    /// Linear coefficient (N·s/m).
    pub k1: f32,
    /// Quadratic coefficient (N·s²/m²).
    pub k2: f32,
    /// The particles it acts on, by number; `None`: every particle.
    pub targets: Option<Vec<usize>>,
}

/// A liquid lifting one particle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Float {
    /// The floating particle's number.
    pub particle: usize,
    /// Height of the liquid's surface (m).
    pub surface: f32,
    /// Half the body's height (m).
    pub half_height: f32,
    /// The body's volume (m³).
    pub volume: f32,
    /// The liquid's density (kg/m³).
    pub density: f32,
}

/// An experiment made by hand.
#[derive(Clone, Debug, PartialEq)]
pub struct Sketch {
    /// Its name in the Scene menu.
    pub name: String,
    /// Downward acceleration (m/s²).
    pub g: f32,
    /// The physics time step (s); `None`: the format's default.
    pub dt: Option<f32>,
    /// The ground at y = 0, if it has one.
    pub ground: Option<Surface>,
    /// Particles with a radius collide with each other, if set.
    pub collisions: Option<Surface>,
    /// Walls besides the ground.
    pub walls: Vec<Wall>,
    /// Plates with an opening.
    pub plates: Vec<Floor>,
    /// Its particles.
    pub bodies: Vec<Body>,
    /// Its links.
    pub joins: Vec<Join>,
    /// Drag forces.
    pub drags: Vec<DragField>,
    /// Liquids lifting particles.
    pub floats: Vec<Float>,
    /// A launcher's aim, and whether a headless run fires a round at step 0.
    pub launcher: Option<(Aim, bool)>,
    /// The solver, substeps and integrator it names as its own (`[scene] solver`, …);
    /// what it does not name is the default.
    pub solver: SolverChoice,
}

/// The ground's surface when the builder adds one (the scene format's defaults).
pub const GROUND: Surface = Surface { restitution: 0.3, friction: 0.5, rolling_resistance: 0.1 };
/// Particles' surface when collisions are on (the scene format's defaults).
pub const COLLISIONS: Surface = Surface { restitution: 0.5, friction: 0.3, rolling_resistance: 0.1 };

impl Sketch {
    /// An empty experiment on the ground, under Earth's gravity, its particles
    /// colliding.
    #[must_use]
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            g: 9.81,
            dt: None,
            ground: Some(GROUND),
            collisions: Some(COLLISIONS),
            walls: Vec::new(),
            plates: Vec::new(),
            bodies: Vec::new(),
            joins: Vec::new(),
            drags: Vec::new(),
            floats: Vec::new(),
            launcher: None,
            solver: SolverChoice::default(),
        }
    }

    /// The world as it stands, as a sketch named `name`, with what it leaves out named
    /// (empty when it keeps everything).
    #[must_use]
    pub fn from_world(world: &World, name: &str) -> (Self, Vec<String>) {
        let mut sketch = Self::new(name);
        sketch.ground = None;
        sketch.collisions = None;
        sketch.solver = SolverChoice::differing(world.solver());
        let mut left_out: Vec<String> = Vec::new();
        let mut leave = |what: &str| {
            if !left_out.iter().any(|w| w == what) {
                left_out.push(what.to_string());
            }
        };
        let p = &world.particles;
        let number = |id| p.index(id);
        // Gravity: the particles' own acceleration where all movable ones share one
        // that points down.
        let mut g = None;
        for i in 0..p.len() {
            if p.inverse_masses()[i] == 0.0 {
                continue;
            }
            let a = p.accelerations()[i];
            let down = a.x == 0.0 && a.z == 0.0 && a.y <= 0.0;
            match g {
                None if down => g = Some(-a.y),
                Some(g) if down && -a.y == g => {}
                _ => leave("an acceleration that is not the same downward g on every particle"),
            }
        }
        sketch.g = g.unwrap_or(9.81);
        for i in 0..p.len() {
            let fixed = p.inverse_masses()[i] == 0.0;
            sketch.bodies.push(Body {
                position: p.positions()[i],
                velocity: if fixed { Vec3::ZERO } else { p.velocities()[i] },
                mass: if fixed { 1.0 } else { p.mass(i) },
                radius: p.radii()[i],
                damping: p.damping(i),
                fixed,
                rolls: p.rolls(i),
                name: None,
                color: None,
            });
            if p.angular_velocities()[i] != Vec3::ZERO {
                leave("the particles' spin");
            }
        }
        let Ok(state) = world.state() else {
            leave("everything but the particles (the world could not be read)");
            return (sketch, left_out);
        };
        for (_, force) in &state.forces {
            match force {
                SavedForce::Spring(s) => {
                    let (Some(a), b) = (number(s.a), s.b) else { continue };
                    let b = match b {
                        LinkEnd::Particle(id) => match number(id) {
                            Some(b) => End::Body(b),
                            None => continue,
                        },
                        LinkEnd::Anchor(point) => End::Anchor(point),
                    };
                    let kind = if s.bungee { JoinKind::Bungee } else { JoinKind::Spring };
                    sketch.joins.push(Join {
                        kind,
                        a,
                        b,
                        length: s.rest_length,
                        k: s.k,
                        restitution: 0.0,
                        damping_ratio: 0.0,
                    });
                }
                SavedForce::Gravity(_) => leave("gravity fields"),
                SavedForce::Drag(drag) => {
                    let mut targets: Vec<usize> = drag.targets.iter().filter_map(|&id| number(id)).collect();
                    // Every particle, in order, is the format's default.
                    let all = targets.len() == p.len() && targets.iter().enumerate().all(|(k, &i)| k == i);
                    if targets.is_empty() && !drag.targets.is_empty() {
                        continue;
                    }
                    targets.dedup();
                    sketch.drags.push(DragField {
                        k1: drag.k1,
                        k2: drag.k2,
                        targets: (!all).then_some(targets),
                    });
                }
                SavedForce::Buoyancy(b) => {
                    let Some(particle) = number(b.target) else { continue };
                    if b.g != sketch.g {
                        leave("buoyancy under another g than the particles'");
                    }
                    sketch.floats.push(Float {
                        particle,
                        surface: b.surface,
                        half_height: b.half_height,
                        volume: b.volume,
                        density: b.density,
                    });
                }
                SavedForce::StiffSpring(s) => {
                    let Some(a) = number(s.target) else { continue };
                    sketch.joins.push(Join {
                        kind: JoinKind::StiffSpring,
                        a,
                        b: End::Anchor(s.anchor),
                        length: 0.0,
                        k: s.k,
                        restitution: 0.0,
                        damping_ratio: s.damping_ratio,
                    });
                }
            }
        }
        for (_, generator) in &state.contact_generators {
            match generator {
                ContactGenerator::Plane(plane) => {
                    let surface = Surface {
                        restitution: plane.restitution,
                        friction: plane.friction,
                        rolling_resistance: plane.rolling_resistance,
                    };
                    if plane.normal == Vec3::Y && plane.offset == 0.0 && sketch.ground.is_none() {
                        sketch.ground = Some(surface);
                    } else {
                        let (point, size, along) = match plane.extent {
                            Some(e) => (e.center, Some([2.0 * e.half_along, 2.0 * e.half_across]), e.along),
                            None => (plane.normal * plane.offset, None, Vec3::X),
                        };
                        sketch.walls.push(Wall {
                            normal: plane.normal,
                            point,
                            size,
                            along,
                            restitution: plane.restitution,
                            friction: plane.friction,
                            rolling_resistance: plane.rolling_resistance,
                        });
                    }
                }
                ContactGenerator::Spheres(spheres) => {
                    sketch.collisions = Some(Surface {
                        restitution: spheres.restitution,
                        friction: spheres.friction,
                        rolling_resistance: spheres.rolling_resistance,
                    });
                }
                ContactGenerator::Link(link) => {
                    let Some(a) = number(link.a) else { continue };
                    let b = match link.b {
                        LinkEnd::Particle(id) => match number(id) {
                            Some(b) => End::Body(b),
                            None => continue,
                        },
                        LinkEnd::Anchor(point) => End::Anchor(point),
                    };
                    let kind = if link.rigid { JoinKind::Rod } else { JoinKind::Cable };
                    sketch.joins.push(Join {
                        kind,
                        a,
                        b,
                        length: link.length,
                        k: 0.0,
                        restitution: link.restitution,
                        damping_ratio: 0.0,
                    });
                }
                ContactGenerator::Plate(plate) => sketch.plates.push(Floor {
                    normal: plate.normal,
                    point: plate.center,
                    opening: 2.0 * plate.opening,
                    surface: Surface {
                        restitution: plate.restitution,
                        friction: plate.friction,
                        rolling_resistance: plate.rolling_resistance,
                    },
                }),
            }
        }
        (sketch, left_out)
    }

    /// The scene as it stands, as a sketch named `name`, with what it leaves out
    /// named: [`Self::from_world`] and the scene's launcher. At step 0 the copy's
    /// launcher fires at the start as the scene's does (a headless run fires one round
    /// there, [`super::fire_at_start`]), and any round already fired is left to it to
    /// fire again; later, rounds in flight are particles like any other, and the
    /// launcher waits to be fired.
    #[must_use]
    pub fn from_scene(scene: &dyn Scene, name: &str) -> (Self, Vec<String>) {
        let world = scene.world();
        let (mut sketch, left_out) = Self::from_world(world, name);
        for (id, color) in scene.particle_colors() {
            if let Some(i) = world.particles.index(*id) {
                sketch.bodies[i].color = Some(*color);
            }
        }
        for (id, label) in scene.particle_labels() {
            if let Some(i) = world.particles.index(*id) {
                sketch.bodies[i].name = Some(label.clone());
            }
        }
        let Some(launcher) = scene.launcher() else { return (sketch, left_out) };
        let at_start = world.steps() == 0;
        if at_start {
            let ids = world.particles.ids();
            let rounds: Vec<usize> = (0..ids.len()).filter(|&i| launcher.is_round(ids[i])).collect();
            for &i in rounds.iter().rev() {
                sketch.remove(i);
            }
            // A round's own drag goes with it: the launcher gives the next one its own.
            sketch.drags.retain(|d| d.targets.as_ref().is_none_or(|t| t.iter().all(|k| !rounds.contains(k))));
        }
        sketch.launcher = Some((launcher.aim, at_start && launcher.fire_at_start));
        (sketch, left_out)
    }

    /// Adds a particle; returns its number, or `None` at [`MAX_BODIES`].
    pub fn add(&mut self, body: Body) -> Option<usize> {
        if self.bodies.len() >= MAX_BODIES {
            return None;
        }
        self.bodies.push(body);
        Some(self.bodies.len() - 1)
    }

    /// Removes particle `i` and its links; the particles after it move down one.
    pub fn remove(&mut self, i: usize) {
        if i >= self.bodies.len() {
            return;
        }
        self.bodies.remove(i);
        self.joins.retain(|j| j.a != i && j.b != End::Body(i));
        let shift = |k: usize| if k > i { k - 1 } else { k };
        for j in &mut self.joins {
            j.a = shift(j.a);
            if let End::Body(b) = &mut j.b {
                *b = shift(*b);
            }
        }
        // What acted on it goes with it; what acts on the others follows their numbers.
        self.floats.retain(|f| f.particle != i);
        for f in &mut self.floats {
            f.particle = shift(f.particle);
        }
        for drag in &mut self.drags {
            if let Some(targets) = &mut drag.targets {
                targets.retain(|&k| k != i);
                targets.iter_mut().for_each(|k| *k = shift(*k));
            }
        }
        self.drags.retain(|d| d.targets.as_ref().is_none_or(|t| !t.is_empty()));
    }

    /// A copy of particle `i`, `offset` away; returns the copy's number.
    pub fn duplicate(&mut self, i: usize, offset: Vec3) -> Option<usize> {
        let mut body = self.bodies.get(i)?.clone();
        body.position += offset;
        // A name is one particle's: the copy has none.
        body.name = None;
        self.add(body)
    }

    /// Links particle `a` to `b` with `kind` (spring constant `k`), at the distance
    /// between them. Refused, with the reason, for a particle to itself, ends at one
    /// point, or a link that is already there.
    pub fn join(&mut self, kind: JoinKind, a: usize, b: End, k: f32) -> Result<(), String> {
        let Some(from) = self.bodies.get(a).map(|body| body.position) else {
            return Err("no such particle".into());
        };
        let to = match b {
            End::Body(b) if b == a => return Err("a link needs two different ends".into()),
            End::Body(b) => match self.bodies.get(b) {
                Some(body) => body.position,
                None => return Err("no such particle".into()),
            },
            End::Anchor(point) => point,
        };
        let length = from.distance(to);
        if length < 1e-4 {
            return Err("the two ends are at one point: move one first".into());
        }
        if kind == JoinKind::StiffSpring && matches!(b, End::Body(_)) {
            return Err("a stiff spring runs to a fixed point, not to a particle".into());
        }
        let same = |j: &Join| j.a == a && j.b == b || (End::Body(j.a) == b && j.b == End::Body(a));
        if self.joins.iter().any(same) {
            return Err("these two are already linked".into());
        }
        self.joins.push(Join { kind, a, b, length, k, restitution: 0.0, damping_ratio: 0.0 });
        Ok(())
    }

    /// The links with particle `i` at an end, by their numbers.
    pub fn joins_of(&self, i: usize) -> impl Iterator<Item = (usize, &Join)> + '_ {
        self.joins.iter().enumerate().filter(move |(_, j)| j.a == i || j.b == End::Body(i))
    }

    /// Every link between particles takes the distance they are at now as its length
    /// (after a particle moved, its rods keep it where it was put).
    pub fn fit_lengths(&mut self, moved: usize) {
        for j in &mut self.joins {
            if j.a != moved && j.b != End::Body(moved) {
                continue;
            }
            let from = self.bodies[j.a].position;
            let to = match j.b {
                End::Body(b) => self.bodies[b].position,
                End::Anchor(point) => point,
            };
            j.length = from.distance(to).max(1e-4);
        }
    }

    /// A finite wall along the segment `from`–`to` (m), `width` wide across it: in the
    /// side view's plane (both ends at z = 0) a ramp or a step facing up (or, upright,
    /// facing +x), `width` deep along z; on the ground (both at y = 0) an upright wall
    /// `width` high, facing +z (or, along z, +x). `None` for a segment too short.
    #[must_use]
    pub fn wall_along(from: Vec3, to: Vec3, width: f32) -> Option<Wall> {
        let along = to - from;
        let length = along.length();
        if length < 0.05 || !length.is_finite() || width <= 0.0 {
            return None;
        }
        let on_ground = from.y == 0.0 && to.y == 0.0 && (from.z != 0.0 || to.z != 0.0);
        let (normal, point) = if on_ground {
            let mut n = Vec3::Y.cross(along).normalize();
            if n.z < -1e-6 || (n.z.abs() <= 1e-6 && n.x < 0.0) {
                n = -n;
            }
            (n, 0.5 * (from + to) + Vec3::Y * (0.5 * width))
        } else {
            let mut n = Vec3::Z.cross(along).normalize();
            if n.y < -1e-6 || (n.y.abs() <= 1e-6 && n.x < 0.0) {
                n = -n;
            }
            (n, 0.5 * (from + to))
        };
        Some(Wall {
            normal,
            point,
            size: Some([length, width]),
            along: along / length,
            restitution: GROUND.restitution,
            friction: GROUND.friction,
            rolling_resistance: GROUND.rolling_resistance,
        })
    }

    /// The sketch as a scene file, as the format's writer writes it (so a sketch saved
    /// and exported again is the same bytes).
    #[must_use]
    pub fn text(&self) -> String {
        let raw = self.raw_text();
        super::file::canonical(&raw).unwrap_or(raw)
    }

    /// The sketch's tables, before the writer puts them in its order.
    fn raw_text(&self) -> String {
        let mut out = String::new();
        let _ = write!(out, "[scene]\nname = {}\n", toml_string(&self.name));
        out.push_str("summary = \"Particles and links, made in the builder or exported\"\n");
        if let Some(dt) = self.dt {
            let _ = writeln!(out, "dt = {}", float32(dt));
        }
        if let Some(kind) = self.solver.kind {
            let _ = writeln!(out, "solver = {}", toml_string(kind.name()));
        }
        if let Some(substeps) = self.solver.substeps {
            let _ = writeln!(out, "substeps = {substeps}");
        }
        if let Some(integrator) = self.solver.integrator {
            let _ = writeln!(out, "integrator = {}", toml_string(integrator.name()));
        }
        let _ = write!(
            out,
            "\n[[param]]\nname = \"g\"\nunit = \"m/s²\"\ndefault = {}\nmin = {}\nmax = {}\n\
             help = \"Gravitational acceleration, downwards\"\n",
            float32(self.g),
            float32(self.g.min(0.0)),
            float32(self.g.max(30.0))
        );
        if let Some((aim, _)) = &self.launcher {
            // The launch speed and angle as sliders, as in the projectile scene.
            let _ = write!(
                out,
                "\n[[param]]\nname = \"speed\"\nunit = \"m/s\"\ndefault = {}\nmin = 0\nmax = {}\n\
                 help = \"Launch speed of the next round\"\n\
                 \n[[param]]\nname = \"angle\"\nunit = \"°\"\ndefault = {}\nmin = -90\nmax = 90\n\
                 help = \"Launch elevation above the horizontal\"\n",
                float32(aim.speed),
                float32(aim.speed.max(200.0)),
                float32(aim.angle)
            );
        }
        let vector = |v: Vec3| format!("[{}, {}, {}]", float32(v.x), float32(v.y), float32(v.z));
        for body in &self.bodies {
            let _ = write!(out, "\n[[particle]]\nposition = {}\n", vector(body.position));
            if body.velocity != Vec3::ZERO && !body.fixed {
                let _ = writeln!(out, "velocity = {}", vector(body.velocity));
            }
            if !body.fixed {
                let _ = writeln!(out, "mass = {}", float32(body.mass));
            }
            let _ = writeln!(out, "radius = {}", float32(body.radius));
            if body.damping != 1.0 {
                let _ = writeln!(out, "damping = {}", float32(body.damping));
            }
            if body.fixed {
                out.push_str("fixed = true\n");
            }
            if body.rolls {
                out.push_str("rolls = true\n");
            }
            if let Some(name) = &body.name {
                let _ = writeln!(out, "name = {}", toml_string(name));
            }
            if let Some([r, g, b]) = body.color {
                let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
                let _ = writeln!(out, "color = \"#{:02x}{:02x}{:02x}\"", byte(r), byte(g), byte(b));
            }
        }
        for join in &self.joins {
            let _ = write!(out, "\n[[link]]\nkind = \"{}\"\na = {}\n", join.kind.name(), join.a);
            match join.b {
                End::Body(b) => {
                    let _ = writeln!(out, "b = {b}");
                }
                End::Anchor(point) => {
                    let _ = writeln!(out, "anchor = {}", vector(point));
                }
            }
            if join.kind != JoinKind::StiffSpring {
                let _ = writeln!(out, "length = {}", float32(join.length));
            }
            if join.kind.elastic() {
                let _ = writeln!(out, "k = {}", float32(join.k));
            }
            if join.restitution != 0.0 {
                let _ = writeln!(out, "restitution = {}", float32(join.restitution));
            }
            if join.damping_ratio != 0.0 {
                let _ = writeln!(out, "damping_ratio = {}", float32(join.damping_ratio));
            }
        }
        for drag in &self.drags {
            let _ = write!(out, "\n[[drag]]\nk1 = {}\nk2 = {}\n", float32(drag.k1), float32(drag.k2));
            if let Some(targets) = &drag.targets {
                let list: Vec<String> = targets.iter().map(usize::to_string).collect();
                let _ = writeln!(out, "targets = [{}]", list.join(", "));
            }
        }
        for float in &self.floats {
            let _ = write!(
                out,
                "\n[[buoyancy]]\nparticle = {}\nsurface = {}\nhalf_height = {}\nvolume = {}\ndensity = {}\n",
                float.particle,
                float32(float.surface),
                float32(float.half_height),
                float32(float.volume),
                float32(float.density)
            );
        }
        if let Some(ground) = self.ground {
            let _ = write!(
                out,
                "\n[ground]\nrestitution = {}\nfriction = {}\nrolling_resistance = {}\n",
                float32(ground.restitution),
                float32(ground.friction),
                float32(ground.rolling_resistance)
            );
        }
        for wall in &self.walls {
            let _ =
                write!(out, "\n[[wall]]\nnormal = {}\npoint = {}\n", vector(wall.normal), vector(wall.point));
            if let Some([length, width]) = wall.size {
                let _ = write!(
                    out,
                    "size = [{}, {}]\nalong = {}\n",
                    float32(length),
                    float32(width),
                    vector(wall.along)
                );
            }
            let _ = write!(
                out,
                "restitution = {}\nfriction = {}\nrolling_resistance = {}\n",
                float32(wall.restitution),
                float32(wall.friction),
                float32(wall.rolling_resistance)
            );
        }
        for plate in &self.plates {
            let _ = write!(
                out,
                "\n[[plate]]\nnormal = {}\npoint = {}\nopening = {}\nrestitution = {}\nfriction = {}\n\
                 rolling_resistance = {}\n",
                vector(plate.normal),
                vector(plate.point),
                float32(plate.opening),
                float32(plate.surface.restitution),
                float32(plate.surface.friction),
                float32(plate.surface.rolling_resistance)
            );
        }
        if let Some((aim, fire)) = &self.launcher {
            let _ = write!(
                out,
                "\n[launcher]\nposition = {}\nspeed = \"speed\"\nangle = \"angle\"\nmass = {}\nradius = {}\n\
                 damping = {}\nk1 = {}\nk2 = {}\n",
                vector(aim.position),
                float32(aim.mass),
                float32(aim.radius),
                float32(aim.damping),
                float32(aim.k1),
                float32(aim.k2)
            );
            if let Some(target) = aim.target {
                let _ = writeln!(out, "target = {}", float32(target));
            }
            let _ = writeln!(out, "fire_at_start = {fire}");
        }
        if let Some(c) = self.collisions {
            let _ = write!(
                out,
                "\n[collisions]\nrestitution = {}\nfriction = {}\nrolling_resistance = {}\n",
                float32(c.restitution),
                float32(c.friction),
                float32(c.rolling_resistance)
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::{Body, DragField, End, Float, JoinKind, Sketch};
    use crate::scenes::file;

    /// A spring dumbbell on a pinned rod, by hand.
    fn dumbbell() -> Sketch {
        let mut s = Sketch::new("dumbbell");
        let a = s.add(Body { position: Vec3::new(0.0, 2.0, 0.0), radius: 0.15, ..Body::default() }).unwrap();
        let b = s
            .add(Body {
                position: Vec3::new(1.0, 2.5, 0.0),
                mass: 2.0,
                name: Some("heavy".into()),
                color: Some([1.0, 0.2, 0.0]),
                ..Body::default()
            })
            .unwrap();
        let c = s.add(Body { position: Vec3::new(0.0, 3.0, 0.0), fixed: true, ..Body::default() }).unwrap();
        s.join(JoinKind::Spring, a, End::Body(b), 40.0).unwrap();
        s.join(JoinKind::Rod, a, End::Body(c), 0.0).unwrap();
        s.join(JoinKind::Cable, b, End::Anchor(Vec3::new(2.0, 4.0, 0.0)), 0.0).unwrap();
        s.walls.push(Sketch::wall_along(Vec3::new(-3.0, 2.0, 0.0), Vec3::new(1.0, 0.5, 0.0), 2.0).unwrap());
        s
    }

    #[test]
    fn a_sketch_written_loads_and_builds_what_it_holds() {
        let sketch = dumbbell();
        let text = sketch.text();
        let entry = file::load_text(&text, "dumbbell", None).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let scene = entry.create_default();
        let world = scene.world();
        assert_eq!(world.particles.len(), 3);
        assert_eq!(world.links().len(), 3);
        // Taken back from the scene it built, it is the same sketch, its label and
        // colour included; the view draws that colour.
        let (again, left_out) = Sketch::from_scene(scene.as_ref(), "dumbbell");
        assert!(left_out.is_empty(), "{left_out:?}");
        assert_eq!(again.bodies, sketch.bodies);
        assert_eq!(again.joins, sketch.joins);
        assert_eq!(again.text(), text);
        assert!(text.contains("name = \"heavy\"") && text.contains("color = \"#ff3300\""), "{text}");
    }

    #[test]
    fn removing_a_particle_takes_its_links_and_renumbers_the_rest() {
        let mut s = dumbbell();
        s.remove(0);
        assert_eq!(s.bodies.len(), 2);
        // Only the cable from the old particle 1 (now 0) to its anchor is left.
        assert_eq!(s.joins.len(), 1);
        assert_eq!(s.joins[0].a, 0);
        assert!(matches!(s.joins[0].b, End::Anchor(_)));
    }

    #[test]
    fn removing_a_particle_takes_the_liquid_and_drag_on_it_alone() {
        let mut s = dumbbell();
        let float =
            |particle| Float { particle, surface: 1.0, half_height: 0.1, volume: 0.004, density: 1000.0 };
        s.floats = vec![float(0), float(2)];
        s.drags = vec![
            DragField { k1: 1.0, k2: 0.0, targets: Some(vec![0]) },
            DragField { k1: 2.0, k2: 0.0, targets: Some(vec![0, 2]) },
            DragField { k1: 3.0, k2: 0.0, targets: None },
        ];
        s.remove(0);
        // The float on particle 0 went; the one on 2 is now on 1, still the same particle.
        assert_eq!(s.floats, vec![float(1)]);
        assert!(s.bodies[1].fixed, "particle 1 is the old 2, the pinned one");
        // Drag on 0 alone went; drag on 0 and 2 acts on the old 2; drag on all stays.
        let left: Vec<(f32, Option<Vec<usize>>)> =
            s.drags.iter().map(|d| (d.k1, d.targets.clone())).collect();
        assert_eq!(left, vec![(2.0, Some(vec![1])), (3.0, None)]);
        // And what is written still loads.
        file::load_text(&s.text(), "after", None).unwrap_or_else(|e| panic!("{e}"));
    }

    #[test]
    fn a_solver_named_is_written_and_read_back() {
        let mut s = dumbbell();
        s.solver = crate::physics::SolverChoice {
            kind: Some(crate::physics::SolverKind::Paper),
            substeps: None,
            integrator: Some(crate::physics::Integrator::Verlet),
        };
        let text = s.text();
        assert!(text.contains("solver = \"paper\"\nintegrator = \"verlet\""), "{text}");
        let entry = file::load_text(&text, "dumbbell", None).unwrap();
        assert_eq!(file::own_solver(&entry), s.solver);
        let scene = entry.create_default();
        assert_eq!(Sketch::from_scene(scene.as_ref(), "dumbbell").0.solver, s.solver);
    }

    #[test]
    fn links_are_refused_to_themselves_twice_or_at_one_point() {
        let mut s = dumbbell();
        assert!(s.join(JoinKind::Rod, 0, End::Body(0), 0.0).is_err());
        assert!(s.join(JoinKind::Rod, 1, End::Body(0), 0.0).is_err(), "already linked as a spring");
        let d = s.duplicate(0, Vec3::ZERO).unwrap();
        assert!(s.join(JoinKind::Rod, 0, End::Body(d), 0.0).is_err());
    }

    #[test]
    fn built_in_scenes_are_taken_as_copies_with_what_they_leave_out_named() {
        for entry in crate::scenes::SCENES {
            let scene = entry.create_default();
            let (sketch, left_out) = Sketch::from_world(scene.world(), &entry.info().name);
            assert_eq!(sketch.bodies.len(), scene.world().particles.len(), "{}", entry.info().name);
            let text = sketch.text();
            let loaded = file::load_text(&text, &entry.info().name, None);
            assert!(loaded.is_ok(), "{}: {:?} (left out {left_out:?})", entry.info().name, loaded.err());
        }
    }
}

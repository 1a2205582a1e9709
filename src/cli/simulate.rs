//! `simulate`: runs a scene headless and prints its state as JSON Lines or CSV, with
//! each particle's forces on request.

use std::io::{self, Write};

use clap::ValueEnum;
use glam::Vec3;
use serde::Serialize;

use super::flags::{MAX_STEPS, SceneChoice};
use super::{clock, progress};
use crate::physics::broad_phase::BUDGET_HIT_MESSAGE;
use crate::physics::inspect::{self, ConstraintMeter};
use crate::physics::{LinkEnd, LinkState, ParticleId, World};
use crate::scenes::snapshot::Snapshot;
use crate::scenes::{self, Scene};

/// Output format of `simulate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StateFormat {
    /// JSON Lines: one object per printed step.
    Json,
    /// CSV with a header: one row per particle per printed step, with the step's
    /// energy budget on every row (for a spreadsheet).
    Csv,
}

/// Arguments of `simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// The scene, its parameters and the solver.
    #[command(flatten)]
    pub choice: SceneChoice,
    /// Continue from a snapshot (File → Save in the window, or `--save`): its scene,
    /// parameters, solver and time step, at the step it was saved.
    #[arg(long, value_name = "FILE.json", conflicts_with_all = ["scene", "scene_file", "set", "solver", "substeps", "integrator"])]
    pub from: Option<std::path::PathBuf>,
    /// Write a snapshot of the last state to FILE after the run.
    #[arg(long, value_name = "FILE.json")]
    pub save: Option<std::path::PathBuf>,
    /// Write the scene's table of runs to FILE as CSV after the run: a row for each
    /// completed measurement (each round of the projectile, or of a scene file's
    /// launcher, that landed), its parameters beside what was measured and predicted.
    #[arg(long, value_name = "FILE.csv")]
    pub runs: Option<std::path::PathBuf>,
    /// Physics steps to run [default: the scene's own].
    #[arg(long)]
    pub steps: Option<u64>,
    /// Time step in seconds [default: the scene's own].
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f32>,
    /// Print every K-th step (step 0 and the last step are always printed).
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = StateFormat::Json)]
    pub format: StateFormat,
    /// Add to each particle of the JSON its net force "f" (N) and the forces that make
    /// it, by name ("forces": weight, each force generator, damping, and what contacts
    /// and links did over the last step), as the window's inspector shows them
    #[arg(long)]
    pub forces: bool,
}

/// Validated settings of a `simulate` run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunPlan {
    /// Steps to run.
    pub steps: u64,
    /// Time step (s).
    pub dt: f32,
    /// Print every this many steps.
    pub every: u64,
    /// How to print them.
    pub format: StateFormat,
    /// Where to write a snapshot of the last state, if anywhere.
    pub save: Option<std::path::PathBuf>,
    /// Where to write the table of runs (CSV), if anywhere.
    pub runs: Option<std::path::PathBuf>,
    /// Print each particle's forces (`--forces`).
    pub forces: bool,
    /// The time step the steps before this run were taken at, for a run from a
    /// snapshot (s): its printed times go on from the world's own.
    pub saved_dt: Option<f32>,
}

/// Builds the scene and checks the numbers of a `simulate` run.
pub fn prepare(args: &SimulateArgs) -> Result<(Box<dyn Scene>, RunPlan), String> {
    let (scene, saved_dt) = match &args.from {
        Some(path) => {
            let snapshot = Snapshot::load(path)?;
            let scene = snapshot.restore().map_err(|e| format!("{}: {e}", crate::messages::path(path)))?;
            (scene, Some(snapshot.dt))
        }
        None => {
            let entry = args.choice.entry()?;
            let solver = args.choice.solver.settings_for(&entry)?;
            let mut scene = scenes::build_entry(&entry, &args.choice.set)?;
            scene.world_mut().set_solver(solver).map_err(|e| e.to_string())?;
            // A launcher fires one round at step 0, as pressing F at once would; a
            // snapshot goes on as it was saved.
            scenes::fire_at_start(scene.as_mut());
            (scene, None)
        }
    };
    let info = scene.info();
    let dt = args.dt.or(saved_dt).unwrap_or(info.dt);
    if !crate::physics::error::time_step_in_range(dt) {
        return Err(format!(
            "--dt {} is out of range; valid range: {:e} to {} s",
            crate::physics::error::Shown::shown(&dt),
            crate::physics::error::MIN_TIME_STEP,
            crate::physics::error::MAX_TIME_STEP
        ));
    }
    let steps = args.steps.unwrap_or(u64::from(info.default_steps));
    if steps > MAX_STEPS {
        return Err(format!("--steps {steps} is out of range; valid range: 0 to {MAX_STEPS}"));
    }
    if args.every == 0 {
        return Err("--every 0 is out of range; valid range: 1 or more".into());
    }
    let save = args.save.clone();
    // Where the snapshot goes is checked before the run, so a long run is not lost to
    // a path that names a device, a FIFO or a directory.
    if let Some(path) = &save {
        crate::writing::target(path)
            .map_err(|e| format!("cannot write {}: {e}", crate::messages::path(path)))?;
    }
    let runs = args.runs.clone();
    if let Some(path) = &runs {
        if scene.runs().is_none() {
            return Err(format!(
                "--runs: {} keeps no table of runs (the projectile and scene files with a [launcher] do)",
                crate::messages::quote(&info.name)
            ));
        }
        crate::writing::target(path)
            .map_err(|e| format!("cannot write {}: {e}", crate::messages::path(path)))?;
    }
    if args.forces && args.format == StateFormat::Csv {
        return Err("--forces adds fields to the JSON; it cannot be used with --format csv".into());
    }
    let forces = args.forces;
    Ok((scene, RunPlan { steps, dt, every: args.every, format: args.format, save, runs, forces, saved_dt }))
}

/// Header of `simulate --format csv`.
pub const CSV_HEADER: &str =
    "step,t,id,x,y,z,vx,vy,vz,r,m,kinetic,potential,dissipated,constraint,work,removed,error";

/// Runs `simulate`, writing one JSON object (or CSV rows) per printed step.
pub fn simulate(
    scene: &mut dyn Scene,
    plan: RunPlan,
    out: &mut impl Write,
) -> io::Result<Result<(), String>> {
    let mut links = Vec::new();
    let mut line = Vec::with_capacity(4096);
    // Times as the step stands for them (0.0208333 s), not as f32 steps add up.
    let clock = clock::Step::of(plan.dt);
    let start_steps = scene.world().steps();
    // A snapshot whose every step was one rate counts its time from step 0, so its
    // lines read as an unbroken run's do (3.3333333, not the f32 sum 3.333334), at
    // that rate or going on at another.
    let origin = clock::Origin::of(plan.saved_dt.unwrap_or(plan.dt), scene.world().time(), start_steps);
    let mut progress = progress::Progress::new(plan.steps, "steps", progress::Progress::for_terminal(false));
    if plan.format == StateFormat::Csv {
        writeln!(out, "{CSV_HEADER}")?;
    }
    // Step numbers go on from a snapshot's.
    let first = scene.world().steps();
    // With --forces: what contacts and links did to each particle over the last step.
    let (mut meter, mut constraint) = (ConstraintMeter::default(), Vec::new());
    // The pair budget's warning is said once a run, at the first step that hits it.
    let mut budget_told = false;
    for step in 0..=plan.steps {
        if step > 0 {
            if plan.forces {
                let world = scene.world();
                meter.before_step(world, world.particles.ids().iter().copied());
            }
            match scene.step(plan.dt) {
                Ok(report) if report.pair_budget_hit && !budget_told => {
                    budget_told = true;
                    eprintln!("particle-lab: warning: at step {}, {BUDGET_HIT_MESSAGE}", first + step);
                }
                Ok(_) => {}
                Err(error) => return Ok(Err(error.to_string())),
            }
            if plan.forces {
                constraint.clear();
                constraint.extend(meter.after_step(scene.world(), plan.dt));
            }
            progress.set(step);
            if !scene.world().is_finite() {
                out.flush()?;
                return Ok(Err(format!(
                    "the simulation blew up at step {step} (positions or velocities are no longer \
                     finite); try a smaller --dt, or a softer spring"
                )));
            }
        }
        if step == 0 || step == plan.steps || step % plan.every == 0 {
            // Every figure printed, not only positions and velocities: an energy or a
            // tension can overflow while they are still finite.
            if let Some(what) = scene.world().first_non_finite(&mut links) {
                out.flush()?;
                return Ok(Err(format!(
                    "the simulation blew up at step {}: {what} is no longer a finite number; \
                     try a smaller --dt, or a softer spring",
                    first + step
                )));
            }
            line.clear();
            let t = clock.map_or(clock::to_f32_digits(scene.world().time()), |clock| {
                clock.time_from(origin, scene.world().steps() - start_steps)
            });
            match plan.format {
                StateFormat::Json => {
                    let forces = plan.forces.then_some(constraint.as_slice());
                    let readouts = scene.readout_values(plan.dt);
                    write_state(&mut line, first + step, t, scene.world(), &mut links, forces, &readouts)?;
                    line.push(b'\n');
                }
                StateFormat::Csv => write_csv_rows(&mut line, first + step, t, scene.world())?,
            }
            out.write_all(&line)?;
            // Each printed step reaches a pipe as soon as it is computed.
            out.flush()?;
        }
    }
    out.flush()?;
    if let Some(path) = &plan.save {
        let saved = Snapshot::of(scene, plan.dt).and_then(|snapshot| snapshot.save(path));
        if let Err(error) = saved {
            return Ok(Err(error));
        }
    }
    if let (Some(path), Some(table)) = (&plan.runs, scene.runs())
        && let Err(error) = crate::writing::write_atomic(path, table.csv().as_bytes())
    {
        return Ok(Err(format!("cannot write {}: {error}", crate::messages::path(path))));
    }
    Ok(Ok(()))
}

#[derive(Serialize)]
struct ParticleJson {
    id: u32,
    p: [f32; 3],
    v: [f32; 3],
    /// Angular velocity (rad/s) of a sphere that rolls; absent for a point mass.
    #[serde(skip_serializing_if = "Option::is_none")]
    w: Option<[f32; 3]>,
    /// Radius (m).
    r: f32,
    /// Mass (kg); absent for an immovable particle, which has `fixed` instead (its
    /// mass is unbounded, and no number stands for it).
    #[serde(skip_serializing_if = "Option::is_none")]
    m: Option<f32>,
    /// `true` for an immovable particle; absent for a movable one.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    fixed: bool,
    /// With `--forces`: the net force (N), the sum of `forces`.
    #[serde(skip_serializing_if = "Option::is_none")]
    f: Option<[f32; 3]>,
    /// With `--forces`: each force by name (N); a second of the same name gets " 2".
    #[serde(skip_serializing_if = "Option::is_none")]
    forces: Option<serde_json::Map<String, serde_json::Value>>,
}

#[derive(Serialize)]
struct LinkJson {
    kind: &'static str,
    a: u32,
    b: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    anchor: Option<[f32; 3]>,
    rest: f32,
    length: f32,
    tension: f32,
}

#[derive(Serialize)]
struct EnergyJson {
    /// Of motion and, for spheres that roll, of rotation (J).
    kinetic: f32,
    /// The rotational part of `kinetic`, `Σ ½ I ω²` (J); absent when nothing rolls.
    #[serde(skip_serializing_if = "Option::is_none")]
    rotational: Option<f32>,
    potential: f32,
    /// Lost since step 0 (damping, drag, inelastic bounces, friction), cumulative (J);
    /// never decreases.
    dissipated: f32,
    /// Taken out since step 0 by the constraint solve's corrections (negative: put in),
    /// cumulative (J): the solver's error.
    constraint: f32,
    /// Put in from outside the steps since step 0, cumulative (J).
    work: f32,
    /// Carried out by particles removed since step 0, cumulative (J).
    removed: f32,
    /// kinetic + potential + dissipated + constraint + removed - work, minus its value at
    /// step 0: the integrator's error (J).
    error: f32,
}

#[derive(Serialize)]
struct StateJson<'a> {
    step: u64,
    t: f64,
    /// [`World::state_hash`] as 16 hex digits: equal hashes at a step, equal runs.
    hash: String,
    particles: Vec<ParticleJson>,
    links: Vec<LinkJson>,
    contacts: usize,
    resolver: ResolverJson,
    energy: EnergyJson,
    /// The scene's read-outs by key, the numbers its panel shows; one that does not
    /// exist yet at this step (a measured period before a full swing) is absent.
    readouts: ReadoutsJson<'a>,
}

/// Read-outs as one JSON object, in the panel's order (a map would sort them). One
/// that is not a finite number (the lowest point of no particles) is left out rather
/// than printed as `null`: no number of a frame is ever `null`.
struct ReadoutsJson<'a>(&'a [(&'static str, f64)]);

impl Serialize for ReadoutsJson<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = serializer.serialize_map(None)?;
        for (key, value) in self.0.iter().filter(|(_, value)| value.is_finite()) {
            map.serialize_entry(key, value)?;
        }
        map.end()
    }
}

#[derive(Serialize)]
struct ResolverJson {
    iterations: usize,
    max_penetration: f32,
}

/// A vector as printed: `+ 0` turns a component's negative zero (a velocity that has
/// never moved along an axis, times a negative factor) into 0, so no figure reads "-0".
fn figure(v: Vec3) -> Vec3 {
    v + Vec3::ZERO
}

/// One CSV row per particle (by id), each with the step's energy budget; `t` is the
/// time printed (s).
fn write_csv_rows(out: &mut Vec<u8>, step: u64, t: f64, world: &World) -> io::Result<()> {
    let p = &world.particles;
    let e = world.energy();
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by_key(|&i| p.ids()[i].0);
    for i in order {
        let (x, v) = (figure(p.positions()[i]), figure(p.velocities()[i]));
        let mass = if p.inverse_masses()[i] > 0.0 { p.mass(i).to_string() } else { String::new() };
        writeln!(
            out,
            "{step},{t},{},{},{},{},{},{},{},{},{mass},{},{},{},{},{},{},{}",
            p.ids()[i].0,
            x.x,
            x.y,
            x.z,
            v.x,
            v.y,
            v.z,
            p.radii()[i],
            e.kinetic,
            e.potential,
            e.dissipated,
            e.constraint,
            e.work,
            e.removed,
            e.error
        )?;
    }
    Ok(())
}

/// The state as one JSON object with the scene's read-outs; `t` is the time printed
/// (s). With `forces` (what contacts and links did over the last step, by particle),
/// each particle gets its forces and their sum.
fn write_state(
    out: &mut Vec<u8>,
    step: u64,
    t: f64,
    world: &World,
    links: &mut Vec<LinkState>,
    forces: Option<&[(ParticleId, Vec3)]>,
    readouts: &[(&'static str, f64)],
) -> io::Result<()> {
    let p = &world.particles;
    let measured: Option<std::collections::HashMap<ParticleId, Vec3>> =
        forces.map(|list| list.iter().copied().collect());
    // Which particles a contact or link acts on, found in one pass, not one per particle.
    let mut constrained = Vec::new();
    if forces.is_some() {
        world.constrained_into(&mut constrained);
    }
    let mut particles: Vec<ParticleJson> = (0..p.len())
        .map(|i| {
            let id = p.ids()[i];
            let listed = measured
                .as_ref()
                .map(|measured| inspect::forces_given(world, id, measured.get(&id).copied(), constrained[i]));
            let f = listed.as_ref().map(|list| figure(list.iter().map(|(_, f)| *f).sum::<Vec3>()).to_array());
            let forces = listed.map(|list| {
                let mut named = serde_json::Map::new();
                for (name, force) in list {
                    let mut key = name.to_string();
                    let mut n = 1;
                    while named.contains_key(&key) {
                        n += 1;
                        key = format!("{name} {n}");
                    }
                    named.insert(key, serde_json::json!(figure(force).to_array()));
                }
                named
            });
            ParticleJson {
                id: id.0,
                p: figure(p.position[i]).to_array(),
                v: figure(p.velocity[i]).to_array(),
                w: p.rolls(i).then(|| figure(p.angular_velocities()[i]).to_array()),
                r: p.radius[i],
                m: (p.inverse_mass[i] > 0.0).then(|| p.mass(i)),
                fixed: p.inverse_mass[i] == 0.0,
                f,
                forces,
            }
        })
        .collect();
    particles.sort_by_key(|particle| particle.id);
    world.links_into(links);
    let links = links
        .iter()
        .map(|link| {
            let (b, anchor) = match link.spec.b {
                LinkEnd::Particle(id) => (Some(id.0), None),
                LinkEnd::Anchor(point) => (None, Some(point.to_array())),
            };
            LinkJson {
                kind: link.spec.kind.name(),
                a: link.spec.a.0,
                b,
                anchor,
                rest: link.spec.rest,
                length: link.length,
                tension: link.tension,
            }
        })
        .collect();
    let energy = world.energy();
    let state = StateJson {
        step,
        t,
        hash: crate::scenes::snapshot::hash_text(world.state_hash()),
        particles,
        links,
        contacts: world.contact_count(),
        resolver: ResolverJson {
            iterations: world.last_report().iterations(),
            max_penetration: world.last_report().max_penetration,
        },
        energy: EnergyJson {
            kinetic: energy.kinetic,
            rotational: p.any_rolling().then_some(energy.rotational),
            potential: energy.potential,
            dissipated: energy.dissipated,
            constraint: energy.constraint,
            work: energy.work,
            removed: energy.removed,
            error: energy.error,
        },
        readouts: ReadoutsJson(readouts),
    };
    serde_json::to_writer(out, &state).map_err(io::Error::other)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::physics::ParticleDesc;

    #[test]
    fn particles_carry_radius_and_mass_and_immovable_ones_fixed() {
        let mut world = World::new();
        let desc = ParticleDesc { mass: 2.5, radius: 0.3, ..ParticleDesc::default() };
        world.add_particle(desc).unwrap();
        world.add_particle(ParticleDesc { immovable: true, position: Vec3::X, ..desc }).unwrap();
        let mut line = Vec::new();
        write_state(&mut line, 0, 0.0, &world, &mut Vec::new(), None, &[]).unwrap();
        let state: serde_json::Value = serde_json::from_slice(&line).unwrap();
        let particles = state["particles"].as_array().unwrap();
        assert_eq!(particles[0]["m"].as_f64(), Some(2.5));
        assert!((particles[0]["r"].as_f64().unwrap() - 0.3).abs() < 1e-6, "{}", particles[0]);
        assert_eq!(particles[1].get("m"), None, "{}", particles[1]);
        assert_eq!(particles[1]["fixed"], serde_json::Value::Bool(true));
        assert_eq!(particles[0].get("fixed"), None, "a movable particle says nothing of it");
        assert!(!String::from_utf8(line).unwrap().contains("null"), "no number is printed as null");
    }

    #[test]
    fn read_outs_keep_the_panels_order_and_leave_out_what_is_not_a_number() {
        let world = World::new();
        let readouts =
            [("period_s", 2.5), ("lowest_m", f64::INFINITY), ("flow_kg_s", 0.125), ("ratio", f64::NAN)];
        let mut line = Vec::new();
        write_state(&mut line, 0, 0.0, &world, &mut Vec::new(), None, &readouts).unwrap();
        let text = String::from_utf8(line).unwrap();
        assert!(text.ends_with(r#""readouts":{"period_s":2.5,"flow_kg_s":0.125}}"#), "{text}");
    }
}

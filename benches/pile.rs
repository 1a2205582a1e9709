//! A settled pile of spheres, stepped by particle-lab and (with `--features peer`) by
//! rapier3d in the same process, so the ratio of their step times comes from one run.
//!
//! For every size the two engines drop the same spheres (radius 0.5 m, 1 kg, friction
//! 0.5, restitution 0, g = 9.81 m/s²) from the same jittered grid into the same open box
//! (ground y = 0, inner walls at x, z = ±width/2), with width chosen so every pile is
//! about ten layers deep. Both engines' spheres roll (rapier's balls rotate; ours are
//! set rolling, I = 2/5 m r²). Rapier has no rolling resistance, so the engine compared
//! with it, `particle-lab`, has none either; `lab rr 0.1` is particle-lab with the pile
//! scene's default rolling resistance (0.1), shown beside it for what it costs. Each pile is settled first (the engine's own defaults, both
//! threads), then criterion measures one step of 1/60 s on 1 thread and on all threads,
//! first with each engine's default sleeping (both put resting islands to sleep), then
//! with sleeping turned off. Criterion's measurements of the engines are followed by a
//! timing of our own (the median of 30 steps, the engines stepped in turn a few at a
//! time so that both sides of a ratio are timed across the same spells of the machine,
//! see [`time_in_turn`]) and a measurement of each pile from its positions, so no time
//! is reported without the quality it bought.
//!
//! Both engines sleep by default with the same rule (slower than 0.05 m/s for 0.5 s, a
//! whole island at once): rapier's `RigidBodyActivation::default()`, particle-lab's
//! `SolverSettings::default()`.
//!
//! Before the piles, both engines pour the same heap (see [`pour`]): 1,000 spheres
//! dropped one by one on open ground, and the heap's angle of repose is measured on
//! their positions with `pile::angle_of_repose`.
//!
//! Before the settled piles, each size is also timed while its contacts form (see
//! [`forming`]): fresh piles from the drop, steps 90 to 180 timed in turn, sleeping off.
//!
//! `cargo bench --bench pile --features peer -- --warm-up-time 1 --measurement-time 3
//! --sample-size 10`; `PILE_SIZES=1000,8000` picks the sizes (`PILE_SIZES=` none: the
//! pour only); `PILE_POUR=0` skips the pour; `PILE_FORMING=0` skips the piles while
//! their contacts form and `PILE_SETTLED=0` the settled piles; `PILE_LAB_ONLY=1` times
//! particle-lab alone while the contacts form (for quick measurements of a change);
//! `PILE_THREADS=2` picks the thread counts (default 1 and all); `PILE_PROFILE=1` prints where each
//! engine's last step went and its fastest sphere. Without the feature only particle-lab
//! runs. In test mode (`cargo test --benches`) a 300-sphere pile and a 60-sphere pour
//! check the plumbing in a few seconds.

use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, Throughput};
use glam::Vec3;
use particle_lab::physics::{DEFAULT_ROLLING_RESISTANCE, ParticleDesc, Plane, SphereCollisions, World};
use particle_lab::scenes::pile::{self, PileQuality};
use particle_lab::scenes::{self, Scene};
use rayon::{ThreadPool, ThreadPoolBuilder};

/// Sphere radius (m).
const RADIUS: f32 = 0.5;
/// Sphere mass (kg).
const MASS: f32 = 1.0;
/// Friction coefficient of spheres, walls and ground.
const FRICTION: f32 = 0.5;
/// Gravitational acceleration, downwards (m/s²).
const G: f32 = 9.81;
/// Time step (s): the pile scene's own.
const DT: f32 = 1.0 / 60.0;
/// Sizes up to which the piles forming are timed with each engine's default sleeping
/// too (issue 39 checks 8,000 spheres so, 100,000 awake).
const FORMING_SLEEP_UP_TO: usize = 10_000;
/// Sizes measured by `cargo bench`.
const SIZES: [usize; 4] = [1_000, 8_000, 10_000, 100_000];
/// Median speed below which a pile counts as settled (m/s).
const SETTLED_SPEED: f32 = 0.005;
/// The particle-lab engine the ratios are taken against: rolling spheres without
/// rolling resistance, as rapier's balls.
const LAB: &str = "particle-lab";

/// How much work a run does: a full benchmark or criterion's test mode.
#[derive(Clone, Copy)]
struct Plan {
    /// Fewest settling steps (the top layer needs about 2 s to land).
    settle_min: usize,
    /// Most settling steps.
    settle_max: usize,
    /// Steps after the pile has settled, so that resting islands can fall asleep (both
    /// engines wait 0.5 s by default).
    rest: usize,
    /// Steps after sleeping is switched off, before measuring.
    resettle: usize,
    /// Rounds of our own timing after criterion's measurements (see [`time_in_turn`]).
    rounds: usize,
    /// Steps from the drop at which the contacts-forming timing starts and ends (see
    /// [`forming`]).
    forming: (usize, usize),
}

const FULL: Plan =
    Plan { settle_min: 150, settle_max: 600, rest: 60, resettle: 60, rounds: 10, forming: (88, 180) };
const QUICK: Plan = Plan { settle_min: 20, settle_max: 40, rest: 2, resettle: 5, rounds: 1, forming: (3, 7) };

/// Steps each engine takes in a round of our own timing, timed after one untimed step.
const BLOCK: u64 = 3;

/// Inner width of the box for `n` spheres: about ten layers deep.
fn width_for(n: usize) -> f32 {
    (1.1 * (n as f32 / 10.0).sqrt() + 1.2).ceil()
}

/// One engine stepping one pile.
trait Engine: Send {
    /// Name in the table and in criterion's ids.
    fn name(&self) -> &'static str;
    /// Advances the pile by [`DT`] on the calling thread's rayon pool.
    fn step(&mut self);
    /// Positions and velocities of the spheres.
    fn state(&self) -> (Vec<Vec3>, Vec<Vec3>);
    /// Spheres asleep now.
    fn asleep(&self) -> usize;
    /// Turns sleeping on (with the engine's default thresholds) or off.
    fn set_sleep(&mut self, on: bool);
    /// Where the last step's time went, in the engine's own words.
    fn profile(&self) -> String;
}

/// Runs `steps` steps on `pool` and returns the wall time of each.
fn run(pool: &ThreadPool, engine: &mut dyn Engine, steps: u64) -> Vec<Duration> {
    pool.install(move || {
        (0..steps)
            .map(|_| {
                let start = Instant::now();
                engine.step();
                start.elapsed()
            })
            .collect()
    })
}

/// Our own timing of every engine under the same conditions: `rounds` rounds, each of
/// which steps every engine in turn, one untimed step (which fills the caches the other
/// engines emptied) and then [`BLOCK`] timed ones. How fast this virtual machine runs
/// changes from one second to the next (other processes; where the host puts the two
/// cores, see [`core_round_trip_ns`]), and timing the engines one after the other let
/// the two sides of a ratio draw different spells: taken in turn, every engine is
/// timed across the same spells. The wall time of each engine's timed steps.
fn time_in_turn(pool: &ThreadPool, engines: &mut [Box<dyn Engine>], rounds: usize) -> Vec<Vec<Duration>> {
    let mut times = vec![Vec::new(); engines.len()];
    for _ in 0..rounds {
        for (engine, times) in engines.iter_mut().zip(&mut times) {
            run(pool, engine.as_mut(), 1);
            times.extend(run(pool, engine.as_mut(), BLOCK));
        }
    }
    times
}

fn median(mut values: Vec<f32>) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    let middle = values.len() / 2;
    *values.select_nth_unstable_by(middle, f32::total_cmp).1
}

/// Measures a pile from positions and velocities with particle-lab's own ruler (the same
/// for both engines).
fn quality(positions: &[Vec3], velocities: &[Vec3], width: f32) -> PileQuality {
    let mut world = World::new();
    for (&position, &velocity) in positions.iter().zip(velocities) {
        world
            .add_particle(ParticleDesc {
                position,
                velocity,
                mass: MASS,
                radius: RADIUS,
                ..ParticleDesc::default()
            })
            .expect("a finite sphere");
    }
    pile::quality(&world, width)
}

/// Steps `engine` on `pool` until its median speed is below [`SETTLED_SPEED`] (checked
/// every 30 steps after `plan.settle_min`) or `plan.settle_max` steps have run, then
/// `plan.rest` more. The first `plan.settle_min` steps are the fall (the top layer
/// needs about 2 s to land): their mean time per step is printed with the pile's
/// quality at their end, and the quality again once it has settled.
fn settle(pool: &ThreadPool, engine: &mut dyn Engine, n: usize, width: f32, plan: Plan) {
    let start = Instant::now();
    let mut steps = 0;
    let mut speed = f32::INFINITY;
    while steps < plan.settle_max {
        let chunk =
            if steps < plan.settle_min { plan.settle_min - steps } else { 30 }.min(plan.settle_max - steps);
        let times = run(pool, engine, chunk as u64);
        steps += chunk;
        let (positions, velocities) = engine.state();
        speed = median(velocities.iter().map(|v| v.length()).collect());
        if steps == plan.settle_min {
            let ms = times.iter().map(Duration::as_secs_f32).sum::<f32>() * 1000.0 / chunk as f32;
            let q = quality(&positions, &velocities, width);
            eprintln!(
                "pile: {} n={n} falling: {chunk} steps from the drop, {ms:.1} ms/step on {} threads; then median \
                 speed {:.4} m/s, fastest {:.2} m/s, deepest overlap {:.2} mm, {} escaped; rt {} ns",
                engine.name(),
                pool.current_num_threads(),
                q.median_speed,
                q.max_speed,
                q.deepest_overlap * 1000.0,
                q.escaped,
                core_round_trip_ns().map_or_else(|| "-".into(), |ns| format!("{ns:.0}"))
            );
        }
        if speed < SETTLED_SPEED {
            break;
        }
    }
    run(pool, engine, plan.rest as u64);
    eprintln!(
        "pile: {} n={n} settled in {steps} + {} steps ({:.1} s wall), median speed then {speed:.4} m/s, {} asleep",
        engine.name(),
        plan.rest,
        start.elapsed().as_secs_f32(),
        engine.asleep()
    );
}

/// The pile while its contacts form: fresh piles (particle-lab, lab rr 0.1 and rapier3d
/// from the same grid; sleeping off, or with `sleep` each engine's default) stepped on
/// each pool from the drop to
/// `plan.forming.0` untimed (by step 88 the lowest layers have landed and the ones above
/// are landing on them), then to `plan.forming.1` timed in turn (see
/// [`time_in_turn`]), each pile measured at the end. The set-up of issue 39's check
/// (steps 90 to 180, both engines awake); the piles are built again for each pool so
/// that every thread count times the same steps. Prints one `forming:` line per engine
/// and pool, with the ratio to particle-lab on the others.
fn forming(
    pools: &[(usize, Arc<ThreadPool>)],
    n: usize,
    plan: Plan,
    sleep: bool,
    lab_only: bool,
    profile: bool,
) {
    let width = width_for(n);
    let (from, to) = plan.forming;
    let rounds = (to - from) / (BLOCK as usize + 1);
    for (threads, pool) in pools {
        let mut engines: Vec<Box<dyn Engine>> = vec![Box::new(Lab::new(n, width, 0.0, LAB))];
        if !lab_only {
            engines.push(Box::new(Lab::new(n, width, DEFAULT_ROLLING_RESISTANCE, "lab rr 0.1")));
            #[cfg(feature = "peer")]
            engines.push(Box::new(peer::Rapier::new(&pile::starting_grid(n, RADIUS, width), width)));
        }
        for engine in &mut engines {
            engine.set_sleep(sleep);
            run(pool, engine.as_mut(), from as u64);
        }
        let round_trip = core_round_trip_ns();
        let timed = time_in_turn(pool, &mut engines, rounds);
        let lab_ms = median(timed[0].iter().map(|t| t.as_secs_f32() * 1000.0).collect());
        for (engine, times) in engines.iter().zip(&timed) {
            let ms = median(times.iter().map(|t| t.as_secs_f32() * 1000.0).collect());
            let (positions, velocities) = engine.state();
            let q = quality(&positions, &velocities, width);
            let ratio = if engine.name() == LAB { String::from("-") } else { format!("{:.2}", ms / lab_ms) };
            eprintln!(
                "forming: {} n={n} threads={threads} sleep={} steps {from}-{}: {ms:.3} ms/step (median of {}), ratio to \
                 {LAB} {ratio}; then median speed {:.4} m/s, fastest {:.2} m/s, deepest overlap {:.2} mm, {} \
                 escaped, {} asleep; load {}, rt {} ns",
                engine.name(),
                if sleep { "on" } else { "off" },
                from + rounds * (BLOCK as usize + 1),
                times.len(),
                q.median_speed,
                q.max_speed,
                q.deepest_overlap * 1000.0,
                q.escaped,
                engine.asleep(),
                load_average().map_or_else(|| "-".into(), |l| format!("{l:.1}")),
                round_trip.map_or_else(|| "-".into(), |ns| format!("{ns:.0}"))
            );
            if profile {
                eprintln!("forming: {} last step: {}", engine.name(), engine.profile());
            }
        }
    }
}

/// particle-lab's pile scene.
struct Lab {
    scene: Box<dyn Scene>,
    name: &'static str,
}

impl Lab {
    /// The pile scene with rolling spheres and `rolling_resistance`, named `name`.
    fn new(n: usize, width: f32, rolling_resistance: f32, name: &'static str) -> Self {
        // Every setting spelled out, so that a change of the scene's defaults cannot make
        // the two piles differ.
        let settings = [
            format!("count={n}"),
            format!("width={width}"),
            format!("radius={RADIUS}"),
            format!("mass={MASS}"),
            format!("friction={FRICTION}"),
            format!("g={G}"),
            "restitution=0".to_string(),
            "rolls=1".to_string(),
            format!("rolling_resistance={rolling_resistance}"),
        ];
        let scene = scenes::build("pile", &settings).expect("valid pile parameters");
        assert!((scene.info().dt - DT).abs() < 1e-9, "the pile scene steps at 1/60 s");
        Self { scene, name }
    }
}

impl Engine for Lab {
    fn name(&self) -> &'static str {
        self.name
    }

    fn step(&mut self) {
        self.scene.step(DT).expect("a valid step");
    }

    fn state(&self) -> (Vec<Vec3>, Vec<Vec3>) {
        let p = &self.scene.world().particles;
        (p.positions().to_vec(), p.velocities().to_vec())
    }

    fn asleep(&self) -> usize {
        self.scene.world().particles.asleep_count()
    }

    fn set_sleep(&mut self, on: bool) {
        let world = self.scene.world_mut();
        let settings = *world.solver();
        world
            .set_solver(particle_lab::physics::SolverSettings { sleep: on, ..settings })
            .expect("valid settings");
    }

    fn profile(&self) -> String {
        let world = self.scene.world();
        format!("{:?}, {} contacts", world.profile(), world.contact_count())
    }
}

#[cfg(feature = "peer")]
mod peer {
    //! The same pile in rapier3d: dynamic bodies with ball colliders in a box of fixed
    //! cuboids, rapier's default integration parameters (dt 1/60 s, 4 solver iterations
    //! (substeps) of 1 PGS and 1 stabilisation iteration each, soft contacts 30 Hz
    //! between bodies and 60 Hz against fixed ones, damping ratio 10). Its balls rotate
    //! (rotations not locked), as particle-lab's rolling spheres do.

    use glam::Vec3;
    use rapier3d::prelude::{
        ColliderBuilder, IntegrationParameters, PhysicsWorld, RigidBodyActivation, RigidBodyBuilder,
        RigidBodyHandle, Vector,
    };

    use super::{DT, Engine, FRICTION, G, MASS, RADIUS};

    /// Thickness of the box's walls and floor (m).
    const THICKNESS: f32 = 1.0;

    pub struct Rapier {
        world: PhysicsWorld,
        spheres: Vec<RigidBodyHandle>,
    }

    impl Rapier {
        pub fn new(start: &[Vec3], width: f32) -> Self {
            let mut world = PhysicsWorld::new();
            world.gravity = Vector::new(0.0, -G, 0.0);
            world.integration_parameters =
                IntegrationParameters { dt: DT, ..IntegrationParameters::default() };
            // Inner faces at y = 0 and x, z = ±half; the walls stand well above the grid.
            let half = width / 2.0;
            let top = start.iter().map(|p| p.y).fold(0.0, f32::max) + 4.0 * RADIUS;
            let outer = half + THICKNESS;
            let boxes = [
                ([outer, THICKNESS, outer], [0.0, -THICKNESS, 0.0]),
                ([THICKNESS, top / 2.0, outer], [-outer, top / 2.0, 0.0]),
                ([THICKNESS, top / 2.0, outer], [outer, top / 2.0, 0.0]),
                ([outer, top / 2.0, THICKNESS], [0.0, top / 2.0, -outer]),
                ([outer, top / 2.0, THICKNESS], [0.0, top / 2.0, outer]),
            ];
            for ([hx, hy, hz], [x, y, z]) in boxes {
                let wall = ColliderBuilder::cuboid(hx, hy, hz)
                    .translation(Vector::new(x, y, z))
                    .friction(FRICTION)
                    .restitution(0.0);
                world.insert_collider(wall, None);
            }
            let spheres = start
                .iter()
                .map(|p| {
                    let body = RigidBodyBuilder::dynamic().translation(Vector::new(p.x, p.y, p.z));
                    let ball = ColliderBuilder::ball(RADIUS).mass(MASS).friction(FRICTION).restitution(0.0);
                    world.insert(body, ball).0
                })
                .collect();
            Self { world, spheres }
        }
    }

    /// The poured heap in rapier3d: balls dropped on a fixed cuboid (top face y = 0),
    /// friction [`FRICTION`], restitution 0, rotating freely (rapier has no rolling
    /// resistance).
    pub struct RapierHeap {
        world: PhysicsWorld,
        balls: Vec<RigidBodyHandle>,
    }

    impl RapierHeap {
        pub fn new() -> Self {
            let mut world = PhysicsWorld::new();
            world.gravity = Vector::new(0.0, -G, 0.0);
            world.integration_parameters =
                IntegrationParameters { dt: DT, ..IntegrationParameters::default() };
            let ground = ColliderBuilder::cuboid(200.0, THICKNESS, 200.0)
                .translation(Vector::new(0.0, -THICKNESS, 0.0))
                .friction(FRICTION)
                .restitution(0.0);
            world.insert_collider(ground, None);
            Self { world, balls: Vec::new() }
        }
    }

    impl super::Heap for RapierHeap {
        fn name(&self) -> &'static str {
            "rapier3d"
        }

        fn drop_sphere(&mut self, p: Vec3) {
            let body = RigidBodyBuilder::dynamic().translation(Vector::new(p.x, p.y, p.z));
            let ball = ColliderBuilder::ball(RADIUS).mass(MASS).friction(FRICTION).restitution(0.0);
            self.balls.push(self.world.insert(body, ball).0);
        }

        fn step(&mut self) {
            self.world.step();
        }

        fn state(&self) -> (Vec<Vec3>, Vec<Vec3>) {
            let vec = |v: Vector| Vec3::new(v.x, v.y, v.z);
            let bodies = &self.world.bodies;
            let positions = self.balls.iter().map(|&h| vec(bodies[h].translation())).collect();
            let velocities = self.balls.iter().map(|&h| vec(bodies[h].linvel())).collect();
            (positions, velocities)
        }

        fn all_asleep(&self) -> bool {
            self.balls.iter().all(|&h| self.world.bodies[h].is_sleeping())
        }
    }

    impl Engine for Rapier {
        fn name(&self) -> &'static str {
            "rapier3d"
        }

        fn step(&mut self) {
            self.world.step();
        }

        fn state(&self) -> (Vec<Vec3>, Vec<Vec3>) {
            let vec = |v: Vector| Vec3::new(v.x, v.y, v.z);
            let bodies = &self.world.bodies;
            let positions = self.spheres.iter().map(|&h| vec(bodies[h].translation())).collect();
            let velocities = self.spheres.iter().map(|&h| vec(bodies[h].linvel())).collect();
            (positions, velocities)
        }

        fn asleep(&self) -> usize {
            self.spheres.iter().filter(|&&h| self.world.bodies[h].is_sleeping()).count()
        }

        fn set_sleep(&mut self, on: bool) {
            // What `RigidBodyBuilder::can_sleep` does: negative thresholds never sleep.
            let (linear, angular) = if on {
                (
                    RigidBodyActivation::default_normalized_linear_threshold(),
                    RigidBodyActivation::default_angular_threshold(),
                )
            } else {
                (-1.0, -1.0)
            };
            for &h in &self.spheres {
                let activation = self.world.bodies[h].activation_mut();
                activation.normalized_linear_threshold = linear;
                activation.angular_threshold = angular;
            }
            if !on {
                self.world.wake_up_all(true);
            }
        }

        fn profile(&self) -> String {
            // Its stage timers need rapier's `profiler` feature; the counts do not.
            let counters = &self.world.physics_pipeline.counters;
            format!("{} contact pairs, {} contacts", counters.cd.ncontact_pairs, counters.solver.ncontacts)
        }
    }
}

/// Spheres in the poured heap.
const POURED: usize = 1000;
/// Steps between two spheres of the pour.
const POUR_EVERY: usize = 4;
/// Longest the poured heap is left to settle afterwards (s).
const POUR_SETTLE: f32 = 20.0;

/// A heap being poured on open ground (y = 0, friction [`FRICTION`]).
trait Heap {
    fn name(&self) -> &'static str;
    /// Drops a sphere of radius [`RADIUS`] and mass [`MASS`] at rest at `position`.
    fn drop_sphere(&mut self, position: Vec3);
    fn step(&mut self);
    /// Positions and velocities of the spheres.
    fn state(&self) -> (Vec<Vec3>, Vec<Vec3>);
    /// Whether every sphere sleeps.
    fn all_asleep(&self) -> bool;
}

/// particle-lab's heap: a world with the ground and sphere collisions, its spheres
/// rolling with `rolling_resistance`.
struct LabHeap {
    world: World,
    name: &'static str,
}

impl LabHeap {
    fn new(rolling_resistance: f32, name: &'static str) -> Self {
        let mut world = World::new();
        let ground = Plane::ground(0.0, 0.0, FRICTION).with_rolling_resistance(rolling_resistance);
        world.add_contact_generator(ground).expect("a valid ground");
        let spheres = SphereCollisions { rolling_resistance, ..SphereCollisions::new(0.0, FRICTION) };
        world.add_contact_generator(spheres).expect("valid sphere collisions");
        Self { world, name }
    }
}

impl Heap for LabHeap {
    fn name(&self) -> &'static str {
        self.name
    }

    fn drop_sphere(&mut self, position: Vec3) {
        let desc = ParticleDesc {
            position,
            acceleration: Vec3::new(0.0, -G, 0.0),
            mass: MASS,
            radius: RADIUS,
            ..ParticleDesc::default()
        };
        let id = self.world.add_particle(desc).expect("a valid sphere");
        self.world.particles.set_rolling(id, true).expect("a sphere with a radius");
    }

    fn step(&mut self) {
        self.world.step(DT).expect("a valid step");
    }

    fn state(&self) -> (Vec<Vec3>, Vec<Vec3>) {
        let p = &self.world.particles;
        (p.positions().to_vec(), p.velocities().to_vec())
    }

    fn all_asleep(&self) -> bool {
        self.world.particles.asleep_count() == self.world.particles.len()
    }
}

/// Pours `count` spheres on `heap`, one every [`POUR_EVERY`] steps, each dropped at
/// rest two radii above the top of the spheres that have landed (slower than 0.5 m/s)
/// and within 0.2 m of the axis (the same fixed jitter for every engine), then lets it
/// settle until every sphere sleeps or [`POUR_SETTLE`] seconds pass. The procedure of
/// `tests/granular.rs`. Returns the heap's angle of repose (degrees) and the seconds
/// it took to settle.
fn pour(heap: &mut dyn Heap, count: usize) -> (f32, f32) {
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut jitter = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        ((seed >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * 0.2
    };
    for step in 0..count * POUR_EVERY {
        if step % POUR_EVERY == 0 {
            let (positions, velocities) = heap.state();
            let landed = positions.iter().zip(&velocities).filter(|(_, v)| v.length() < 0.5);
            let y = landed.map(|(p, _)| p.y + RADIUS).fold(0.0, f32::max) + 2.0 * RADIUS;
            heap.drop_sphere(Vec3::new(jitter(), y, jitter()));
        }
        heap.step();
    }
    let mut settled = 0.0;
    while settled < POUR_SETTLE && !heap.all_asleep() {
        heap.step();
        settled += DT;
    }
    let (positions, _) = heap.state();
    (pile::angle_of_repose(&positions, RADIUS), settled)
}

/// The pour on every engine, with its angle of repose.
fn pour_all(pool: &ThreadPool, count: usize) {
    let mut heaps: Vec<Box<dyn Heap + Send>> = vec![
        Box::new(LabHeap::new(0.0, LAB)),
        Box::new(LabHeap::new(DEFAULT_ROLLING_RESISTANCE, "lab rr 0.1")),
    ];
    #[cfg(feature = "peer")]
    heaps.push(Box::new(peer::RapierHeap::new()));
    for heap in &mut heaps {
        let start = Instant::now();
        let (angle, settled) = pool.install(|| pour(heap.as_mut(), count));
        let (_, velocities) = heap.state();
        let median = median(velocities.iter().map(|v| v.length()).collect());
        eprintln!(
            "pour: {:<13} {count} spheres, angle of repose {angle:.1}°, settled {settled:.1} s after the last \
             (all asleep: {}), median speed {median:.4} m/s, {:.1} s wall",
            heap.name(),
            heap.all_asleep(),
            start.elapsed().as_secs_f32()
        );
    }
}

/// One row of the table.
struct Row {
    engine: &'static str,
    n: usize,
    sleep: bool,
    threads: usize,
    ms: f32,
    quality: PileQuality,
    asleep: usize,
    /// The machine's 1-minute load average when our timing ended (other processes
    /// compete for the cores).
    load: Option<f32>,
    /// The cores' round trip before and after our timing (ns), see
    /// [`core_round_trip_ns`].
    round_trip: [Option<f32>; 2],
}

/// Time for one thread to hand a cache line to another and get it back (ns): the
/// median of five means of 4,000 round trips of an atomic counter, after 20 ms for
/// the pools' threads to stop spinning; `None` on one core.
///
/// On the 2-vCPU virtual machines these figures come from, the host sometimes places
/// the two cores far apart: on 2026-12-04 (AMD EPYC) the round trip was 90–135 ns in
/// one mode and 380–450 ns in the other, and every 2-thread step of an 8,000-sphere
/// pile took 2.3–2.4 ms in the first and 4.0–4.3 ms in the second (slower than one
/// thread's 4.0), as the threads hand each other particles' velocities all step long.
/// So each row says which mode it was timed in.
fn core_round_trip_ns() -> Option<f32> {
    const ROUNDS: u64 = 4_000;
    if std::thread::available_parallelism().map_or(1, |n| n.get()) < 2 {
        return None;
    }
    std::thread::sleep(Duration::from_millis(20));
    let means: Vec<f32> = (0..5).map(|_| round_trips(ROUNDS)).collect();
    Some(median(means))
}

/// Mean of `rounds` round trips between this thread and a new one (ns), timed after
/// 100 untimed ones (so the new thread's start is not counted).
fn round_trips(rounds: u64) -> f32 {
    use std::sync::atomic::{AtomicU64, Ordering};
    const UNTIMED: u64 = 100;
    let turn = AtomicU64::new(0);
    let total = UNTIMED + rounds;
    let elapsed = std::thread::scope(|scope| {
        scope.spawn(|| {
            for round in 0..total {
                while turn.load(Ordering::Acquire) != 2 * round + 1 {
                    std::hint::spin_loop();
                }
                turn.store(2 * round + 2, Ordering::Release);
            }
        });
        let mut start = Instant::now();
        for round in 0..total {
            if round == UNTIMED {
                start = Instant::now();
            }
            turn.store(2 * round + 1, Ordering::Release);
            while turn.load(Ordering::Acquire) != 2 * round + 2 {
                std::hint::spin_loop();
            }
        }
        start.elapsed()
    });
    elapsed.as_secs_f32() * 1e9 / rounds as f32
}

/// The 1-minute load average (Linux).
fn load_average() -> Option<f32> {
    std::fs::read_to_string("/proc/loadavg").ok()?.split_whitespace().next()?.parse().ok()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    // Criterion's own rule: without `--bench`, or with `--test`, it only tests.
    let testing = !args.iter().any(|a| a == "--bench") || args.iter().any(|a| a == "--test");
    let plan = if testing { QUICK } else { FULL };
    let profile = std::env::var_os("PILE_PROFILE").is_some();
    let lab_only = std::env::var("PILE_LAB_ONLY").is_ok_and(|v| v == "1");
    let sizes: Vec<usize> = match std::env::var("PILE_SIZES") {
        Ok(list) => list
            .split(',')
            .filter(|s| !s.trim().is_empty())
            .map(|s| s.trim().parse().expect("PILE_SIZES: numbers separated by commas"))
            .collect(),
        Err(_) if testing => vec![300],
        Err(_) => SIZES.to_vec(),
    };
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let thread_counts: Vec<usize> = match std::env::var("PILE_THREADS") {
        Ok(list) => list
            .split(',')
            .map(|s| s.trim().parse().expect("PILE_THREADS: numbers separated by commas"))
            .collect(),
        Err(_) if all > 1 => vec![1, all],
        Err(_) => vec![1],
    };
    let pools: Vec<(usize, Arc<ThreadPool>)> = thread_counts
        .iter()
        .map(|&t| (t, Arc::new(ThreadPoolBuilder::new().num_threads(t).build().expect("a thread pool"))))
        .collect();
    let widest = &pools.last().expect("at least one pool").1;
    if std::env::var("PILE_POUR").map_or(true, |v| v != "0") {
        pour_all(widest, if testing { 60 } else { POURED });
    }

    if std::env::var("PILE_FORMING").map_or(true, |v| v != "0") {
        for &n in &sizes {
            forming(&pools, n, plan, false, lab_only, profile);
            if n <= FORMING_SLEEP_UP_TO {
                forming(&pools, n, plan, true, lab_only, profile);
            }
        }
    }
    let settled_sizes =
        if std::env::var("PILE_SETTLED").is_ok_and(|v| v == "0") { &[][..] } else { &sizes[..] };

    let mut criterion = Criterion::default().configure_from_args();
    let mut rows = Vec::new();
    for &n in settled_sizes {
        let width = width_for(n);
        let mut engines: Vec<Box<dyn Engine>> = vec![
            Box::new(Lab::new(n, width, 0.0, LAB)),
            Box::new(Lab::new(n, width, DEFAULT_ROLLING_RESISTANCE, "lab rr 0.1")),
        ];
        #[cfg(feature = "peer")]
        engines.push(Box::new(peer::Rapier::new(&pile::starting_grid(n, RADIUS, width), width)));
        for engine in &mut engines {
            settle(widest, engine.as_mut(), n, width, plan);
        }

        let mut group = criterion.benchmark_group(format!("pile_{n}"));
        group.throughput(Throughput::Elements(n as u64));
        group.sampling_mode(SamplingMode::Flat);
        for sleep in [true, false] {
            if !sleep {
                for engine in &mut engines {
                    engine.set_sleep(false);
                    run(widest, engine.as_mut(), plan.resettle as u64);
                }
            }
            let id = |engine: &dyn Engine, threads: usize| {
                format!("{}/sleep_{}/{threads}t", engine.name(), if sleep { "on" } else { "off" })
            };
            for (threads, pool) in &pools {
                for engine in &mut engines {
                    let engine = engine.as_mut();
                    group.bench_function(id(engine, *threads), |b| {
                        b.iter_custom(|iters| run(pool, &mut *engine, iters).into_iter().sum())
                    });
                }
                let round_trip_before = core_round_trip_ns();
                let timed = time_in_turn(pool, &mut engines, plan.rounds);
                let round_trip = core_round_trip_ns();
                let load = load_average();
                for (engine, times) in engines.iter_mut().zip(timed) {
                    let engine = engine.as_mut();
                    let id = id(engine, *threads);
                    let ms = median(times.iter().map(|t| t.as_secs_f32() * 1000.0).collect());
                    let (positions, velocities) = engine.state();
                    let quality = quality(&positions, &velocities, width);
                    let asleep = engine.asleep();
                    if profile {
                        let fastest =
                            (0..n).max_by(|&a, &b| velocities[a].length().total_cmp(&velocities[b].length()));
                        let fastest = fastest.map(|i| (positions[i], velocities[i])).unwrap_or_default();
                        eprintln!(
                            "pile: {id} last step: {}; fastest sphere at {:.2} moving {:.3}",
                            engine.profile(),
                            fastest.0,
                            fastest.1
                        );
                    }
                    rows.push(Row {
                        engine: engine.name(),
                        n,
                        sleep,
                        threads: *threads,
                        ms,
                        quality,
                        asleep,
                        load,
                        round_trip: [round_trip_before, round_trip],
                    });
                }
            }
        }
        group.finish();
    }
    criterion.final_summary();
    print_table(&rows);
}

fn print_table(rows: &[Row]) {
    eprintln!();
    eprintln!(
        "pile: ms/step = median of our own timing after criterion's (the engines in turn); quality measured on the positions afterwards;"
    );
    eprintln!("pile: load = 1-minute load average then (other processes share the cores)");
    eprintln!(
        "pile: rt ns = the two cores' round trip before/after our timing (core_round_trip_ns: high means far apart)"
    );
    eprintln!(
        "{:<13} {:>7} {:>5} {:>3} {:>9} {:>8} {:>10} {:>9} {:>10} {:>7} {:>7} {:>7} {:>5} {:>9}",
        "engine",
        "n",
        "sleep",
        "thr",
        "ms/step",
        "ns/p·st",
        "med v m/s",
        "max v m/s",
        "overlap mm",
        "escaped",
        "asleep",
        "rap/lab",
        "load",
        "rt ns"
    );
    for row in rows {
        let lab = rows
            .iter()
            .find(|r| r.engine == LAB && (r.n, r.sleep, r.threads) == (row.n, row.sleep, row.threads));
        let ratio = match lab {
            Some(lab) if row.engine != LAB && lab.ms > 0.0 => format!("{:.2}", row.ms / lab.ms),
            _ => String::new(),
        };
        let q = row.quality;
        eprintln!(
            "{:<13} {:>7} {:>5} {:>3} {:>9.3} {:>8.0} {:>10.4} {:>9.3} {:>10.2} {:>7} {:>7} {:>7} {:>5} {:>9}",
            row.engine,
            row.n,
            if row.sleep { "on" } else { "off" },
            row.threads,
            row.ms,
            row.ms * 1e6 / row.n as f32,
            q.median_speed,
            q.max_speed,
            q.deepest_overlap * 1000.0,
            q.escaped,
            row.asleep,
            ratio,
            row.load.map_or_else(|| "-".into(), |l| format!("{l:.1}")),
            row.round_trip.map(|ns| ns.map_or_else(|| "-".into(), |ns| format!("{ns:.0}"))).join("/")
        );
    }
}

//! Spheres that roll (issue 21) against the textbook's closed forms, on the soft
//! solver: a solid sphere (`I = 2/5 m r²`) rolling down a slope, sliding down one too
//! steep for its friction, turning from sliding to rolling on flat ground, and held or
//! slowed by rolling resistance.
//!
//! Each figure is checked against its closed form (PHYSICS.md, "Spheres that roll"),
//! and where it can be a second way from the output: the spin against the speed
//! (`ω r = v` once rolling), the rotational share of the kinetic energy (2/7 for a
//! rolling sphere), and the energy budget (rolling without slipping loses nothing).

use glam::Vec3;
use particle_lab::physics::*;

const G: f32 = 9.81;
const RADIUS: f32 = 0.25;
const MASS: f32 = 2.0;
const DT: f32 = 1.0 / 120.0;

/// A world with a plane of `degrees` falling towards +x (friction `mu`, rolling
/// resistance `rolling`) and one sphere at rest on it at the origin, that rolls (or
/// not). Returns the world, the sphere, the unit direction down the slope and the
/// plane's normal.
fn on_slope(degrees: f32, mu: f32, rolling: f32, rolls: bool) -> (World, ParticleId, Vec3, Vec3) {
    let (sin, cos) = degrees.to_radians().sin_cos();
    let normal = Vec3::new(sin, cos, 0.0);
    let mut world = World::new();
    let plane = Plane::new(normal, Vec3::ZERO, 0.0, mu).unwrap().with_rolling_resistance(rolling);
    world.add_contact_generator(plane).unwrap();
    let id = world
        .add_particle(ParticleDesc {
            position: normal * RADIUS,
            acceleration: Vec3::new(0.0, -G, 0.0),
            mass: MASS,
            radius: RADIUS,
            ..ParticleDesc::default()
        })
        .unwrap();
    if rolls {
        world.particles.set_rolling(id, true).unwrap();
    }
    (world, id, Vec3::new(cos, -sin, 0.0), normal)
}

fn run(world: &mut World, seconds: f32) {
    for _ in 0..(seconds / DT).round() as usize {
        world.step(DT).unwrap();
    }
}

fn state(world: &World, id: ParticleId) -> (Vec3, Vec3, Vec3) {
    let i = world.particles.index(id).unwrap();
    let p = &world.particles;
    (p.positions()[i], p.velocities()[i], p.angular_velocities()[i])
}

fn within(measured: f32, expected: f32, share: f32) -> bool {
    (measured - expected).abs() <= share * expected.abs()
}

/// Acceleration along `down` from the distance covered in `seconds` from rest.
fn acceleration(world: &mut World, id: ParticleId, down: Vec3, seconds: f32) -> f32 {
    let start = state(world, id).0;
    run(world, seconds);
    2.0 * (state(world, id).0 - start).dot(down) / (seconds * seconds)
}

#[test]
fn a_sphere_rolls_down_a_slope_at_five_sevenths_of_g_sin_theta() {
    for degrees in [10.0f32, 20.0, 30.0] {
        // μ = 0.5 is far above 2/7 tan θ (0.165 at 30°): no slipping.
        let (mut world, id, down, normal) = on_slope(degrees, 0.5, 0.0, true);
        let a = acceleration(&mut world, id, down, 2.0);
        let expected = 5.0 / 7.0 * G * degrees.to_radians().sin();
        assert!(within(a, expected, 0.01), "{degrees}°: a = {a} m/s², closed form {expected}");
        // Rolling without slipping: the contact point is at rest, ω × (-r n) = -v.
        let (_, v, w) = state(&world, id);
        let slip = v + w.cross(-normal * RADIUS);
        assert!(slip.length() < 0.01 * v.length(), "{degrees}°: slip {slip} at v = {v}");
        // A rolling solid sphere holds 2/7 of its kinetic energy in its spin, and
        // loses none of its energy.
        let e = world.energy();
        assert!(within(e.rotational, 2.0 / 7.0 * e.kinetic, 0.01), "{degrees}°: {e:?}");
        let drop = -(world.particles.positions()[0].y - normal.y * RADIUS) * MASS * G;
        assert!(within(e.kinetic, drop, 0.01), "{degrees}°: kinetic {} J, height lost {drop} J", e.kinetic);
        assert!(e.dissipated.abs() < 0.01 * drop, "{degrees}°: rolling dissipated {} J", e.dissipated);
    }
}

#[test]
fn a_point_mass_on_the_same_slope_slides_at_g_sin_theta_minus_friction() {
    // Without rolling, static friction holds it (tan 20° < 0.5): the paper's particle.
    let (mut world, id, down, _) = on_slope(20.0, 0.5, 0.0, false);
    let a = acceleration(&mut world, id, down, 2.0);
    assert!(a.abs() < 1e-3, "a point mass held by friction moved at {a} m/s²");
    assert_eq!(state(&world, id).2, Vec3::ZERO);
}

#[test]
fn a_sphere_slides_while_spinning_up_when_friction_is_below_two_sevenths_tan_theta() {
    let degrees = 30.0f32;
    let (sin, cos) = degrees.to_radians().sin_cos();
    let mu = 0.05; // 2/7 tan 30° = 0.165
    let (mut world, id, down, normal) = on_slope(degrees, mu, 0.0, true);
    let seconds = 1.5;
    let a = acceleration(&mut world, id, down, seconds);
    let expected = G * (sin - mu * cos);
    assert!(within(a, expected, 0.01), "a = {a} m/s², closed form {expected}");
    // Friction's torque μ m g cosθ r spins it up at α = 5 μ g cosθ / (2 r).
    let (_, v, w) = state(&world, id);
    let alpha = 5.0 * mu * G * cos / (2.0 * RADIUS);
    let spin = w.dot(normal.cross(down).normalize());
    assert!(within(spin, alpha * seconds, 0.01), "ω = {w}, closed form {} rad/s", alpha * seconds);
    // Still slipping: the surface moves slower than the centre.
    assert!(spin.abs() * RADIUS < 0.9 * v.length());
}

#[test]
fn a_sliding_sphere_on_flat_ground_rolls_on_at_five_sevenths_of_its_speed() {
    let (mu, v0) = (0.3f32, 5.0f32);
    let (mut world, id, _, _) = on_slope(0.0, mu, 0.0, true);
    world.particles.set_velocity(id, Vec3::new(v0, 0.0, 0.0)).unwrap();
    // Slipping lasts 2 v0 / (7 μ g) and covers 12 v0² / (49 μ g).
    let t_roll = 2.0 * v0 / (7.0 * mu * G);
    let slid = 12.0 * v0 * v0 / (49.0 * mu * G);
    let seconds = 2.0;
    run(&mut world, seconds);
    let (p, v, w) = state(&world, id);
    assert!(within(v.x, 5.0 / 7.0 * v0, 0.01), "v = {v}, closed form {}", 5.0 / 7.0 * v0);
    assert!(within(-w.z * RADIUS, v.x, 0.01), "rolling: ω r = {} against v = {}", -w.z * RADIUS, v.x);
    let expected = slid + 5.0 / 7.0 * v0 * (seconds - t_roll);
    assert!(within(p.x, expected, 0.01), "x = {} m, closed form {expected}", p.x);
    // It lost 2/7 of its kinetic energy to friction, once, and then no more.
    let e = world.energy();
    let lost = 0.5 * MASS * v0 * v0 * 2.0 / 7.0;
    assert!(within(e.dissipated, lost, 0.01), "dissipated {} J, closed form {lost}", e.dissipated);
    assert!(e.error.abs() < 1e-3 * lost, "budget error {} J", e.error);
}

#[test]
fn rolling_resistance_slows_a_rolling_sphere_at_five_sevenths_of_mu_r_g() {
    let (mu_r, v0) = (0.05f32, 3.0f32);
    let (mut world, id, _, _) = on_slope(0.0, 0.5, mu_r, true);
    world.particles.set_velocity(id, Vec3::new(v0, 0.0, 0.0)).unwrap();
    world.particles.set_angular_velocity(id, Vec3::new(0.0, 0.0, -v0 / RADIUS)).unwrap();
    // The torque μ_r r m g opposes the spin; rolling, the sphere slows at 5/7 μ_r g
    // and stops after v0² / (2 · 5/7 μ_r g).
    let deceleration = 5.0 / 7.0 * mu_r * G;
    let seconds = 2.0;
    run(&mut world, seconds);
    let (_, v, _) = state(&world, id);
    let expected = v0 - deceleration * seconds;
    assert!(within(v.x, expected, 0.01), "v = {} m/s, closed form {expected}", v.x);
    run(&mut world, 2.0 * v0 / deceleration);
    let (p, v, w) = state(&world, id);
    let stop = v0 * v0 / (2.0 * deceleration);
    assert!(v.length() < 1e-3 && w.length() < 1e-2, "still moving: v = {v}, ω = {w}");
    assert!(within(p.x, stop, 0.01), "stopped after {} m, closed form {stop}", p.x);
}

#[test]
fn rolling_resistance_holds_a_sphere_on_a_gentle_slope_only() {
    // Held while tan θ ≤ μ_r: 4° (tan 0.070) holds with μ_r = 0.1, 8° (0.141) does not.
    let (mut world, id, down, _) = on_slope(4.0, 0.5, 0.1, true);
    let start = state(&world, id).0;
    run(&mut world, 3.0);
    let moved = (state(&world, id).0 - start).dot(down);
    assert!(moved.abs() < 1e-3, "held sphere moved {moved} m");
    let (mut world, id, down, _) = on_slope(8.0, 0.5, 0.1, true);
    let a = acceleration(&mut world, id, down, 2.0);
    // It rolls, slowed by the resistance: 5/7 g (sin θ - μ_r cos θ).
    let (sin, cos) = 8.0f32.to_radians().sin_cos();
    let expected = 5.0 / 7.0 * G * (sin - 0.1 * cos);
    assert!(within(a, expected, 0.02), "a = {a} m/s², closed form {expected}");
}

#[test]
fn a_pushed_sphere_of_the_pile_scene_slides_rolls_and_stops_where_the_closed_form_says() {
    // One sphere of the pile scene, landed, pushed along the floor at 4 m/s without
    // spin. It slides (slowed at μ g) while friction spins it up against the rolling
    // resistance (α = 5 g (μ - μ_r) / 2r) until v = ω r, then rolls, slowed at
    // 5/7 μ_r g, to a stop.
    let (mu, mu_r, v0) = (0.5f32, 0.1f32, 4.0f32);
    let settings = ["count=1".to_string(), format!("friction={mu}"), format!("rolling_resistance={mu_r}")];
    let mut scene = particle_lab::scenes::build("pile", &settings).unwrap();
    let dt = 1.0 / 240.0;
    for _ in 0..1200 {
        scene.step(dt).unwrap();
    }
    let world = scene.world_mut();
    let id = world.particles.ids()[0];
    assert!(world.particles.velocities()[0].length() < 1e-3, "landed and still moving");
    let start = world.particles.positions()[0];
    world.particles.set_velocity(id, Vec3::new(v0, 0.0, 0.0)).unwrap();
    for _ in 0..1500 {
        scene.step(dt).unwrap();
    }
    let t1 = 2.0 * v0 / (G * (7.0 * mu - 5.0 * mu_r));
    let v1 = v0 - mu * G * t1;
    let expected = v0 * t1 - 0.5 * mu * G * t1 * t1 + v1 * v1 / (2.0 * 5.0 / 7.0 * mu_r * G);
    let p = &scene.world().particles;
    let travelled = p.positions()[0].x - start.x;
    assert!(p.velocities()[0].length() < 1e-3, "still moving at {}", p.velocities()[0]);
    assert!(within(travelled, expected, 0.01), "travelled {travelled} m, closed form {expected} m");
}

#[test]
fn a_snapshot_keeps_spin_and_orientation_and_replays_bit_for_bit() {
    use particle_lab::scenes::snapshot::Snapshot;
    // A small pile of rolling spheres, caught while they tumble.
    let mut scene = particle_lab::scenes::build("pile", &["count=200".into(), "width=4".into()]).unwrap();
    let dt = scene.info().dt;
    for _ in 0..90 {
        scene.step(dt).unwrap();
    }
    let spinning = scene.world().particles.angular_velocities().iter().filter(|w| w.length() > 0.1).count();
    assert!(spinning > 50, "only {spinning} spheres spin: nothing to save");
    let text = Snapshot::of(scene.as_ref(), dt).unwrap().to_json();
    let mut restored = Snapshot::from_json(&text).unwrap().restore().unwrap();
    let (a, b) = (&scene.world().particles, &restored.world().particles);
    assert_eq!(a.angular_velocities(), b.angular_velocities());
    assert_eq!(a.orientations(), b.orientations());
    assert_eq!(scene.world().state_hash(), restored.world().state_hash());
    for _ in 0..120 {
        scene.step(dt).unwrap();
        restored.step(dt).unwrap();
    }
    assert_eq!(scene.world().state_hash(), restored.world().state_hash(), "replay drifted");
    assert_eq!(scene.world().particles.orientations(), restored.world().particles.orientations());
    // The orientation follows the spin: a quaternion of unit length that turned.
    let q = scene.world().particles.orientations();
    assert!(q.iter().all(|q| (q.length() - 1.0).abs() < 1e-4));
    assert!(q.iter().filter(|q| q.w < 0.999).count() > 50, "orientations never turned");
}

#[test]
fn a_snapshot_from_before_spheres_rolled_still_loads_as_point_masses() {
    use particle_lab::scenes::snapshot::Snapshot;
    let mut scene = particle_lab::scenes::build("pile", &["count=20".into(), "rolls=0".into()]).unwrap();
    let dt = scene.info().dt;
    for _ in 0..30 {
        scene.step(dt).unwrap();
    }
    let text = Snapshot::of(scene.as_ref(), dt).unwrap().to_json();
    // Take out what older versions did not write.
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let particles = json.pointer_mut("/world/particles").expect("the snapshot's particle store");
    let store = particles.as_object_mut().unwrap();
    for field in ["inverse_inertia", "rolling", "angular_velocity", "orientation"] {
        assert!(store.remove(field).is_some(), "no {field} in the snapshot");
    }
    // As a file edited by hand: its checksum and hash taken out too.
    let top = json.as_object_mut().unwrap();
    top.remove("checksum");
    top.remove("hash");
    let old = serde_json::to_string(&json).unwrap();
    let restored = Snapshot::from_json(&old).unwrap().restore().unwrap();
    assert_eq!(restored.world().state_hash(), scene.world().state_hash());
}

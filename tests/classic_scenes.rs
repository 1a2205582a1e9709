//! The pendulum and cradle scenes (issue 8): what they must show, measured.

use glam::Vec3;
use particle_lab::scenes;

fn build(name: &str, set: &[&str]) -> Box<dyn scenes::Scene> {
    scenes::build(name, &set.iter().map(|s| s.to_string()).collect::<Vec<_>>()).unwrap()
}

fn mechanical(scene: &dyn scenes::Scene) -> f32 {
    let e = scene.world().energy();
    e.kinetic + e.potential
}

#[test]
fn the_pendulum_keeps_its_energy_single_and_double() {
    for (links, seconds) in [("links=1", 10.0), ("links=2", 10.0)] {
        let mut scene = build("pendulum", &[links]);
        let dt = scene.info().dt;
        let n = scene.world().particles.len();
        assert_eq!(n, if links == "links=1" { 1 } else { 2 });
        // Swing energy: every bob can fall from the pivot's height to the chain's length.
        let start = mechanical(&*scene);
        let swing: f32 = (1..=n).map(|k| 9.81 * k as f32).sum();
        for _ in 0..(seconds / dt) as usize {
            scene.step(dt).unwrap();
        }
        let change = (mechanical(&*scene) - start) / swing;
        assert!(change.abs() <= 0.01, "{links}: energy changed by {:.3}% of the swing", change * 100.0);
        // Particle 0 is the first bob: 1 m from the pivot; the second 1 m from it.
        let p = scene.world().particles.positions();
        let pivot = Vec3::new(0.0, n as f32 + 0.5, 0.0);
        assert!((p[0].distance(pivot) - 1.0).abs() < 0.01, "{links}: bob 0 at {}", p[0]);
        if n == 2 {
            assert!((p[1].distance(p[0]) - 1.0).abs() < 0.01, "bob 1 at {}", p[1]);
        }
    }
}

#[test]
fn a_damped_pendulum_runs_down() {
    let mut scene = build("pendulum", &["damping=0.5"]);
    let dt = scene.info().dt;
    let start = mechanical(&*scene);
    for _ in 0..(10.0 / dt) as usize {
        scene.step(dt).unwrap();
    }
    let lost = start - mechanical(&*scene);
    assert!(lost > 0.9 * 9.81, "damping 0.5 should take most of the swing: lost {lost} J");
    assert!((scene.world().energy().dissipated - lost).abs() < 0.01 * lost, "the budget counts it");
}

/// Steps the cradle until the last ball's speed jumps (the blow has arrived), then a
/// little longer; returns each ball's x velocity.
fn after_the_blow(set: &[&str]) -> Vec<f32> {
    let mut scene = build("cradle", set);
    let dt = scene.info().dt;
    let n = scene.world().particles.len();
    for _ in 0..(2.0 / dt) as usize {
        scene.step(dt).unwrap();
        if scene.world().particles.velocities()[n - 1].x > 0.2 {
            break;
        }
    }
    for _ in 0..4 {
        scene.step(dt).unwrap();
    }
    scene.world().particles.velocities().iter().map(|v| v.x).collect()
}

#[test]
fn the_cradle_sends_out_as_many_balls_as_were_lifted() {
    for (balls, lifted) in [(5, 1), (5, 2), (7, 3), (2, 1)] {
        let set = [format!("balls={balls}"), format!("lifted={lifted}")];
        let v = after_the_blow(&[&set[0], &set[1]]);
        assert_eq!(v.len(), balls);
        // The lifted balls arrive at √(2 g L (1 - cos 30°)) = 1.62 m/s.
        let arriving = (2.0 * 9.81 * (1.0 - 30f32.to_radians().cos())).sqrt();
        for (i, &speed) in v.iter().enumerate() {
            if i >= balls - lifted {
                assert!(speed >= 0.9 * arriving, "{balls}/{lifted}: ball {i} should leave: {v:?}");
            } else {
                assert!(speed.abs() <= 0.05 * arriving, "{balls}/{lifted}: ball {i} should stay: {v:?}");
            }
        }
    }
}

#[test]
fn the_cradles_balls_are_in_order_with_the_lifted_first() {
    let scene = build("cradle", &["balls=5", "lifted=2", "angle=40"]);
    let p = scene.world().particles.positions();
    assert!(p.windows(2).all(|w| w[0].x < w[1].x), "left to right: {p:?}");
    // The lifted two are raised; the rest hang at the same height.
    assert!(p[0].y > p[2].y + 0.1 && (p[0].y - p[1].y).abs() < 1e-5, "{p:?}");
    assert!(p[2..].iter().all(|q| (q.y - p[2].y).abs() < 1e-6), "{p:?}");
    // The hanging ones touch, and so do the two lifted together: 2 r = 0.2 m apart.
    for w in p[2..].windows(2).chain([&p[0..2]]) {
        assert!((w[0].distance(w[1]) - 0.2).abs() < 1e-5, "{p:?}");
    }
}

#[test]
fn the_cradle_holds_lifted_to_balls_minus_one_and_refuses_bad_values() {
    // lifted's own range is 1 to 8; more than balls - 1 is held there and said so.
    let scene = build("cradle", &["balls=3", "lifted=8"]);
    let readout = scene.readouts(1.0 / 240.0);
    let lifted = &readout.iter().find(|(k, _)| k == "lifted").unwrap().1;
    assert!(lifted.starts_with("2 of 3"), "{lifted}");
    let p = scene.world().particles.positions();
    assert!(p[1].y > p[2].y + 0.01, "two lifted: {p:?}");
    for bad in ["balls=10", "balls=1", "lifted=0", "restitution=1.5", "angle=nan"] {
        let result = scenes::build("cradle", &[bad.to_string()]);
        assert!(result.is_err(), "{bad} accepted");
    }
    for bad in ["links=6", "links=0", "length=-1", "damping=2"] {
        assert!(scenes::build("pendulum", &[bad.to_string()]).is_err(), "{bad} accepted");
    }
}

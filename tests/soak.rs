//! Soak: every scene (compiled, and the shipped files) for 100,000 steps, with a parameter moved to a random value within
//! its slider's range every 50 steps, as a restless student would. No step may fail,
//! panic or leave a number that is not finite.

mod common;

use particle_lab::scenes::{self, SCENES, Scene};
use particle_lab::ui::Lab;

use common::Random;

const STEPS: u32 = 100_000;
const EVERY: u32 = 50;

/// The slider range the soak draws from: the parameter's own, except the pile's, the
/// hourglass's and the heap's grain counts, held to 400 so that 100,000 steps fit in a test run
/// (their cost is per sphere; the other parameters still go over their whole range).
fn range(scene: &str, name: &str, min: f32, max: f32) -> (f32, f32) {
    if matches!(scene, "pile" | "hourglass" | "heap") && name == "count" {
        (min, max.min(400.0))
    } else {
        (min, max)
    }
}

fn soak(name: &str, seed: u64) {
    let entry = scenes::find(name).unwrap();
    let start = if matches!(name, "pile" | "hourglass" | "heap") {
        vec!["count=300".to_string()]
    } else {
        Vec::new()
    };
    let mut lab = Lab::new(name, &start).unwrap();
    // The projectile's first round, as a headless run fires it at step 0.
    lab.fire_at_start();
    let mut random = Random(seed);
    let mut changes = Vec::new();
    let mut stepped = 0;
    for step in 0..STEPS {
        if step % EVERY == 0 {
            let params = &entry.info().params;
            let param = &params[(random.next() % params.len() as u64) as usize];
            let (min, max) = range(name, &param.name, param.min, param.max);
            let u = random.unit();
            let value = if param.logarithmic && min > 0.0 {
                (min.ln() + u * (max.ln() - min.ln())).exp().clamp(min, max)
            } else {
                min + u * (max - min)
            };
            // A whole-number parameter's slider moves in whole numbers.
            let value = if param.integer { value.round() } else { value };
            lab.set_param(&param.name, value);
            changes.push((step, param.name.clone(), value));
            if changes.len() > 8 {
                changes.remove(0);
            }
        }
        let before = lab.scene.world().steps();
        lab.run_steps(1);
        assert_eq!(lab.scene.world().steps(), before + 1, "{name}: step {step} did not run");
        stepped += 1;
        let scene: &dyn Scene = lab.scene.as_ref();
        let world = scene.world();
        let energy = world.energy();
        let finite = world.is_finite() && energy.kinetic.is_finite() && energy.potential.is_finite();
        assert!(
            finite && !lab.paused,
            "{name}, seed {seed}: step {step} left '{}' (finite: {finite}); last changes (step, parameter, \
             value): {changes:?}",
            lab.status
        );
    }
    assert_eq!(stepped, STEPS);
    eprintln!("{name}: {stepped} steps, {} particles at the end", lab.scene.world().particles.len());
}

#[test]
fn projectile_soaks() {
    soak("projectile", 1);
}

#[test]
fn spring_forces_soaks() {
    soak("springForces", 2);
}

#[test]
fn bridge_soaks() {
    soak("bridge", 3);
}

#[test]
fn pile_soaks() {
    soak("pile", 4);
}

#[test]
fn pendulum_soaks() {
    soak("pendulum", 5);
}

#[test]
fn cradle_soaks() {
    soak("cradle", 6);
}

#[test]
fn hourglass_soaks() {
    soak("hourglass", 11);
}

#[test]
fn heap_soaks() {
    soak("heap", 12);
}

#[test]
fn the_chain_file_soaks() {
    soak("chain", 7);
}

#[test]
fn the_cloth_file_soaks() {
    soak("cloth", 8);
}

#[test]
fn the_platform_file_soaks() {
    soak("platform", 9);
}

#[test]
fn the_blob_file_soaks() {
    soak("blob", 10);
}

#[test]
fn every_compiled_scene_and_shipped_file_is_soaked() {
    let soaked = [
        "projectile",
        "springForces",
        "bridge",
        "pile",
        "pendulum",
        "cradle",
        "hourglass",
        "heap",
        "chain",
        "cloth",
        "platform",
        "blob",
    ];
    for entry in SCENES.iter().chain(scenes::file::shipped()) {
        assert!(soaked.contains(&entry.info().name.as_ref()), "add a soak test for {}", entry.info().name);
    }
}

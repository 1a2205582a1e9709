//! The pile: many spheres come to rest, quickly and without overlapping.

#[allow(unused_imports)]
use particle_lab::physics::{SolverKind, SolverSettings};
use particle_lab::scenes::{self, pile};

fn settle(count: usize, seconds: f32, set: &[&str]) -> (Box<dyn scenes::Scene>, Vec<pile::PileQuality>) {
    let mut assignments = vec![format!("count={count}")];
    assignments.extend(set.iter().map(|s| s.to_string()));
    let mut scene = scenes::build("pile", &assignments).unwrap();
    let dt = scene.info().dt;
    let width = scene.params().get("width");
    let mut history = Vec::new();
    let steps = (seconds / dt).round() as usize;
    for step in 1..=steps {
        scene.step(dt).unwrap();
        if step % 60 == 0 {
            history.push(pile::quality(scene.world(), width));
        }
    }
    (scene, history)
}

#[test]
#[ignore = "probe: prints how a pile settles"]
fn probe_pile() {
    let count: usize = std::env::var("COUNT").ok().and_then(|c| c.parse().ok()).unwrap_or(2000);
    let started = std::time::Instant::now();
    let (scene, history) = settle(count, 10.0, &[]);
    for (i, q) in history.iter().enumerate() {
        println!("t={:>3}s {:?}", i + 1, q);
    }
    println!("{:?} wall {:?} contacts {}", scene.world().profile(), started.elapsed(), scene.world().contact_count());
}

#[test]
#[ignore = "probe"]
fn probe_fall() {
    let mut scene = scenes::build("pile", &["count=3".into()]).unwrap();
    for step in 0..5 {
        let w = scene.world();
        println!("{step} p={:?} v={:?} a={:?} contacts={}", w.particles.position, w.particles.velocity, w.particles.acceleration, w.contact_count());
        scene.step(1.0 / 60.0).unwrap();
    }
}

#[test]
#[ignore = "probe: cost per step of a big pile"]
fn probe_big() {
    let count: usize = std::env::var("COUNT").ok().and_then(|c| c.parse().ok()).unwrap_or(100_000);
    let width = (1.1 * (count as f32 / 10.0).sqrt() + 1.2).ceil();
    let mut scene = scenes::build("pile", &[format!("count={count}"), format!("width={width}")]).unwrap();
    let dt = scene.info().dt;
    for step in 1..=600 {
        let t = std::time::Instant::now();
        scene.step(dt).unwrap();
        if step % 30 == 0 {
            let q = pile::quality(scene.world(), width);
            println!("step {step} {:.1} ms {:?} contacts {} {:?}", t.elapsed().as_secs_f32() * 1e3, scene.world().profile(), scene.world().contact_count(), q);
        }
    }
}

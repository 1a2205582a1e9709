//! Links keep their energy (issue 18, item 7): ideal rods do no work, so an undamped
//! chain or cloth of rods keeps its mechanical energy, and its rods their lengths.
//!
//! **Swing energy** here is kinetic plus gravitational energy (the world's own
//! [`Energy`]) minus the gravitational energy of the same rig at rest: the energy the
//! rig can swing with, zero once it hangs still. The rest state is found a second,
//! independent way: the same scene, heavily damped, run until it stops. The share kept
//! after `seconds` is `swing(end) / swing(start)`.
//!
//! Status: the chain and cloth figures are not met yet (their tests are ignored, with
//! today's numbers). What was measured on the way, 20 s at 240 Hz:
//! - The loss does not fall with more substeps at the default joint stiffness (chain
//!   27% kept at 4, 16 and 64 substeps: `joint_hertz` stays 240 Hz), but does with
//!   stiffer joints: 94% at 16 substeps and 98% at 64 with the clamp's 960 and 3840 Hz.
//!   The soft rods' stretch, damped and relaxed away, is the chain's sink.
//! - At 4 substeps, stiffer feedback than a quarter of the substep rate, or more
//!   Gauss-Seidel passes over the links, gains energy as often as it loses it.
//! - Rigid rods solved as SHAKE (impulse along the start direction so that the ends
//!   end the substep a rod's length apart; post-stabilised positions; 16 passes) keep
//!   the chain's 92.9% (strain 0.008%) and the 3-link pendulum's 99.96%, but the cloth
//!   only 33%, and its straight pinned edge never comes to rest.
//! - The cloth loses most of its energy even at 64 substeps and 3840 Hz (45% kept,
//!   strain 0.12%), pinned at one corner too: its rod net locks up as it folds.
//!
//! Measured in a later session (stop 23), same 20 s, shipped defaults unless said:
//! - Driving each rod's change of length over the whole substep to zero (the secant
//!   rate `(|d + h v| - |d|) / h` in place of `u·v`, which removes the `h²v²/(2L)`
//!   a turning rod lengthens by each substep) barely helps: chain 28.3%, cloth 20.4%,
//!   3-link pendulum 99.72% (from 99.89%). The turning rods' projection is not the sink.
//! - Joints at 1000 Hz with the clamp raised from `0.25 / h` to `1 / h` and 8
//!   Gauss-Seidel passes over the links: chain 97.5% (strain 0.03%), pendulum 99.93%,
//!   cloth 28% (strain 0.57%); at 60 Hz chain 22%, cloth 13%, pendulum 99.4%. But with
//!   4 passes, or at 2000 Hz, the damped chain or cloth never comes to rest, and a
//!   32-cell cloth of 0.7 m under g = 23 blows up (tests/soak.rs): not a default.
//! - The cloth's loss shrinks with the substep, not with passes: 16 substeps at
//!   4000 Hz keep 51% (32 passes at 4 substeps: 17%). Pinning it so that no row of
//!   rods is held straight between two pins (one corner; corners (0,0) and (1,-1))
//!   keeps no more, so the straight pinned edge is not the sink either.
//! - The loss is steady, not a burst at the first fold: the cloth keeps 94% at 2 s,
//!   77% at 4 s, 34% at 10 s; the chain 81%, 65%, 38%. The world's ledger books it as
//!   dissipated by the constraints (chain 0.84 J of 1.15 J, cloth 8.6 J of 10.4 J,
//!   integrator error under 0.3 mJ), so the budget is honest about it.
//! - The joints' damping ratio does not matter (0.3 to 10: chain 25-32%, cloth
//!   14-21%). Leaving the links out of the relax pass keeps the chain's 91% (it swings
//!   between 85% and 113% as the soft rods store and return energy) but not the
//!   cloth's (19%): the cloth loses its energy in the biased solve itself.

use glam::Vec3;
use particle_lab::physics::*;
use particle_lab::scenes::{self, Scene};

const G: f32 = 9.81;

fn mechanical(world: &World) -> f64 {
    let e = world.energy();
    f64::from(e.kinetic) + f64::from(e.gravitational)
}

/// Largest relative stretch of any rod in the world.
fn strain(world: &World) -> f32 {
    world.links().iter().map(|l| (l.length - l.spec.rest).abs() / l.spec.rest).fold(0.0, f32::max)
}

/// Gravitational energy of a scene built with `params`, damped to rest (J).
fn at_rest(name: &str, params: &[&str]) -> f64 {
    let mut args: Vec<String> = params.iter().map(|s| s.to_string()).collect();
    args.push("damping=0.2".into());
    let mut scene = scenes::build(name, &args).unwrap();
    for _ in 0..(60.0 * 240.0) as usize {
        scene.step(1.0 / 240.0).unwrap();
    }
    let e = scene.world().energy();
    assert!(e.kinetic < 1e-4, "{name} not at rest after 60 s: kinetic {} J", e.kinetic);
    f64::from(e.gravitational)
}

/// What a run kept: share of the swing energy, largest rod strain seen at any step.
#[derive(Debug)]
struct Kept {
    share: f64,
    strain: f32,
}

fn run(mut scene: Box<dyn Scene>, rest: f64, hz: f32, seconds: f32) -> Kept {
    let start = mechanical(scene.world()) - rest;
    let mut worst = 0.0f32;
    for _ in 0..(seconds * hz).round() as usize {
        scene.step(1.0 / hz).unwrap();
        worst = worst.max(strain(scene.world()));
    }
    Kept { share: (mechanical(scene.world()) - rest) / start, strain: worst }
}

/// The shipped chain (assets/scenes/chain.toml: 20 rods between two pins), undamped.
fn chain(hz: f32, seconds: f32) -> Kept {
    let rest = at_rest("chain", &[]);
    run(scenes::build("chain", &["damping=1".into()]).unwrap(), rest, hz, seconds)
}

/// The shipped cloth at 10 × 10 particles, undamped, too strong to tear.
fn cloth(hz: f32, seconds: f32) -> Kept {
    let params = ["cells=10", "tear=1000"];
    let rest = at_rest("cloth", &params);
    let mut args: Vec<String> = params.iter().map(|s| s.to_string()).collect();
    args.push("damping=1".into());
    run(scenes::build("cloth", &args).unwrap(), rest, hz, seconds)
}

/// Share of its swing energy (`m g L` per bob below the pivot, 1 kg bobs, 1 m rods,
/// released horizontal) a pendulum of `links` rods keeps, and its largest strain.
fn pendulum(links: usize, hz: f32, seconds: f32) -> Kept {
    let mut world = World::new();
    let mut previous = None;
    for k in 1..=links {
        let desc = ParticleDesc {
            position: Vec3::new(k as f32, 0.0, 0.0),
            acceleration: Vec3::new(0.0, -G, 0.0),
            mass: 1.0,
            ..ParticleDesc::default()
        };
        let id = world.add_particle(desc).unwrap();
        let link = match previous {
            None => Constraint::support_rod(id, Vec3::ZERO, 1.0),
            Some(up) => Constraint::rod(id, up, 1.0),
        };
        world.add_contact_generator(link).unwrap();
        previous = Some(id);
    }
    // At rest the bobs hang at -1, -2, ... m: gravitational energy -Σ m g k.
    let rest: f64 = -(1..=links).map(|k| f64::from(G) * k as f64).sum::<f64>();
    let start = mechanical(&world) - rest;
    let mut worst = 0.0f32;
    for _ in 0..(seconds * hz).round() as usize {
        world.step(1.0 / hz).unwrap();
        worst = worst.max(strain(&world));
    }
    Kept { share: (mechanical(&world) - rest) / start, strain: worst }
}

#[test]
#[ignore = "issue 18, item 7, not met yet: the chain keeps 26.9% (rods strained 0.26%)"]
fn an_undamped_chain_keeps_its_swing_energy_and_its_lengths() {
    // Measured on the soft step as shipped: 26.9% kept over 20 s at 240 Hz, largest
    // rod strain 0.264%.
    let kept = chain(240.0, 20.0);
    assert!(kept.share >= 0.90, "chain kept {:.1}% of its swing energy", kept.share * 100.0);
    assert!(kept.share <= 1.01, "chain gained energy: {:.1}%", kept.share * 100.0);
    assert!(kept.strain <= 1e-3, "a rod strained {:.3}%", kept.strain * 100.0);
}

#[test]
#[ignore = "issue 18, item 7, not met yet: the cloth keeps 17.6% (rods strained 2.5%)"]
fn an_undamped_cloth_keeps_its_swing_energy_and_its_lengths() {
    // Measured on the soft step as shipped: 17.6% kept over 20 s at 240 Hz, largest
    // rod strain 2.49% (its pinned edge is a straight row of rods exactly as long as
    // the pins are apart, which no rigid rod can let sag).
    let kept = cloth(240.0, 20.0);
    assert!(kept.share >= 0.80, "cloth kept {:.1}% of its swing energy", kept.share * 100.0);
    assert!(kept.share <= 1.01, "cloth gained energy: {:.1}%", kept.share * 100.0);
    assert!(kept.strain <= 1e-3, "a rod strained {:.3}%", kept.strain * 100.0);
}

#[test]
fn a_three_link_pendulum_keeps_its_swing_energy() {
    // 99.89% kept at 240 Hz (the 0.2% lost); 94.1% at 60 Hz, not asserted.
    let kept = pendulum(3, 240.0, 20.0);
    assert!((kept.share - 1.0).abs() <= 0.01, "kept {:.2}% at 240 Hz", kept.share * 100.0);
    assert!(kept.strain <= 1e-3, "a rod strained {:.3}%", kept.strain * 100.0);
}

/// The figures at 60 and 240 Hz:
/// `cargo test --release --test joint_energy report_figures -- --ignored --nocapture`.
#[test]
#[ignore = "prints figures"]
fn report_figures() {
    for hz in [60.0, 240.0] {
        let (c, k, p) = (chain(hz, 20.0), cloth(hz, 20.0), pendulum(3, hz, 20.0));
        println!(
            "{hz} Hz, 20 s: chain {:.1}% (strain {:.3}%), cloth {:.1}% (strain {:.3}%), \
             3-link pendulum {:.2}% (strain {:.3}%)",
            c.share * 100.0,
            c.strain * 100.0,
            k.share * 100.0,
            k.strain * 100.0,
            p.share * 100.0,
            p.strain * 100.0
        );
    }
}

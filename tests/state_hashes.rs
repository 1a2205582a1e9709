//! Pinned runs: the state hash of every shipped scene after 600 steps, on both solvers
//! and every integrator. A change that is meant to leave the physics alone (moving
//! code between rooms, renaming, splitting a file) must leave every hash here as it
//! is; a change that is meant to alter a run updates its lines here and says why in
//! its commit.
//!
//! The hashes cover every particle's position, velocity and flags, the step count, the
//! time and the solver's memory (`World::state_hash`), so equal hashes are equal runs
//! to the bit. `PRINT_STATE_HASHES=1 cargo test --release --test state_hashes --
//! --nocapture` prints the table as found, to paste below after an intended change.

use particle_lab::physics::{Integrator, SolverKind};
use particle_lab::scenes::{self, SceneAction, snapshot::hash_text};

const STEPS: usize = 600;

/// (scene, solver, integrator) → hash after [`STEPS`] steps at the scene's own `dt`.
#[rustfmt::skip]
const PINNED: &[(&str, &str, &str, &str)] = &[
    ("projectile", "soft", "explicit-euler", "639999d4ee51cdee"),
    ("projectile", "soft", "semi-implicit-euler", "0e38d81d06365a14"),
    ("projectile", "soft", "verlet", "c666b8ac74cad4ec"),
    ("projectile", "soft", "rk4", "0b064f159948f558"),
    ("projectile", "paper", "explicit-euler", "03f4ad6655c60e54"),
    ("projectile", "paper", "semi-implicit-euler", "00de6d3b368719cf"),
    ("projectile", "paper", "verlet", "ddac5cff46690524"),
    ("projectile", "paper", "rk4", "a3b1ee3d4e267a8e"),
    ("springForces", "soft", "explicit-euler", "d59f40134bbef74c"),
    ("springForces", "soft", "semi-implicit-euler", "94c30c5010438565"),
    ("springForces", "soft", "verlet", "7c8a8c18a110ab0f"),
    ("springForces", "soft", "rk4", "19ce8152804c501c"),
    ("springForces", "paper", "explicit-euler", "97fca43d56b53195"),
    ("springForces", "paper", "semi-implicit-euler", "281fe61f4032b98c"),
    ("springForces", "paper", "verlet", "0efa430f211e6120"),
    ("springForces", "paper", "rk4", "6bbcec53bb422dd1"),
    ("bridge", "soft", "explicit-euler", "400d450849fcb0d1"),
    ("bridge", "soft", "semi-implicit-euler", "40f64b60aa7167bc"),
    ("bridge", "soft", "verlet", "d45aeaea3d903285"),
    ("bridge", "soft", "rk4", "fb6b933c572a48fe"),
    ("bridge", "paper", "explicit-euler", "1f01cc8e0991bf65"),
    ("bridge", "paper", "semi-implicit-euler", "bc7b8aa83342144b"),
    ("bridge", "paper", "verlet", "22413821eb4bbd47"),
    ("bridge", "paper", "rk4", "5fdaab1766741ff8"),
    ("pile", "soft", "explicit-euler", "44c39a041a76e1eb"),
    ("pile", "soft", "semi-implicit-euler", "50234408519f5953"),
    ("pile", "soft", "verlet", "894e1df803c91b2e"),
    ("pile", "soft", "rk4", "711a803b4ed2db75"),
    ("pile", "paper", "explicit-euler", "efde7af4574d9b53"),
    ("pile", "paper", "semi-implicit-euler", "a45cb74d9d8560aa"),
    ("pile", "paper", "verlet", "9978b4a2986cd25b"),
    ("pile", "paper", "rk4", "01b3ce8f9a707729"),
    ("pendulum", "soft", "explicit-euler", "1dbbfd313c66c1e9"),
    ("pendulum", "soft", "semi-implicit-euler", "e34ee4889934861b"),
    ("pendulum", "soft", "verlet", "107babecda9509cf"),
    ("pendulum", "soft", "rk4", "7cf5af3471f0c05e"),
    ("pendulum", "paper", "explicit-euler", "9ae6c8a514209961"),
    ("pendulum", "paper", "semi-implicit-euler", "e82fd807317e52ca"),
    ("pendulum", "paper", "verlet", "4a172079a9188764"),
    ("pendulum", "paper", "rk4", "474d2893155d7799"),
    ("cradle", "soft", "explicit-euler", "b27c9784bb256acc"),
    ("cradle", "soft", "semi-implicit-euler", "9088c6ff37fe1823"),
    ("cradle", "soft", "verlet", "e811c1229ef3f85c"),
    ("cradle", "soft", "rk4", "eb9c1615a02f3c2e"),
    ("cradle", "paper", "explicit-euler", "230d9a41fe863513"),
    ("cradle", "paper", "semi-implicit-euler", "9411dc4f0dd56e05"),
    ("cradle", "paper", "verlet", "55cb7c27bf688468"),
    ("cradle", "paper", "rk4", "801d065f4e273b3a"),
    ("chain", "soft", "explicit-euler", "e6846c7849a79a29"),
    ("chain", "soft", "semi-implicit-euler", "17a3c85d6ebe12e3"),
    ("chain", "soft", "verlet", "ab6ab1b2e6ccd677"),
    ("chain", "soft", "rk4", "5badb8c31634a3b5"),
    ("chain", "paper", "explicit-euler", "448fab00148b914e"),
    ("chain", "paper", "semi-implicit-euler", "edf44004087be24d"),
    ("chain", "paper", "verlet", "0cf07785bc4f9ac5"),
    ("chain", "paper", "rk4", "29fe929960b04256"),
    ("cloth", "soft", "explicit-euler", "827d72f39fadb08b"),
    ("cloth", "soft", "semi-implicit-euler", "cff15e0708e1af3c"),
    ("cloth", "soft", "verlet", "d950c12a59c17cc6"),
    ("cloth", "soft", "rk4", "0ffa712e1016c7f8"),
    ("cloth", "paper", "explicit-euler", "bdfe70a5eafff60f"),
    ("cloth", "paper", "semi-implicit-euler", "231a8a29b91bc4e5"),
    ("cloth", "paper", "verlet", "bbaedafb28018382"),
    ("cloth", "paper", "rk4", "4097e39bc5ab9903"),
    ("platform", "soft", "explicit-euler", "066763af850f4fb0"),
    ("platform", "soft", "semi-implicit-euler", "8d98e75edd5f777c"),
    ("platform", "soft", "verlet", "66781c01a4682484"),
    ("platform", "soft", "rk4", "8db9ecf4635721d1"),
    ("platform", "paper", "explicit-euler", "cb05143943bb15ba"),
    ("platform", "paper", "semi-implicit-euler", "fadbf2cff7018694"),
    ("platform", "paper", "verlet", "4b650f62f03e30fa"),
    ("platform", "paper", "rk4", "8b08483efeaa650a"),
    ("blob", "soft", "explicit-euler", "bd64d9d13728234e"),
    ("blob", "soft", "semi-implicit-euler", "6a162353b5e85a8e"),
    ("blob", "soft", "verlet", "3658f77ead29be74"),
    ("blob", "soft", "rk4", "f5ef7dd2fb044d1a"),
    ("blob", "paper", "explicit-euler", "28708167f2e7c21b"),
    ("blob", "paper", "semi-implicit-euler", "a0958f52375256d7"),
    ("blob", "paper", "verlet", "a24cddaa4c5472e2"),
    ("blob", "paper", "rk4", "da8cd4ea30f22b27"),
    ("hourglass", "soft", "explicit-euler", "c930db035158e9b6"),
    ("hourglass", "soft", "semi-implicit-euler", "83af2b9f8c77be70"),
    ("hourglass", "soft", "verlet", "4062f2b7ae2538cd"),
    ("hourglass", "soft", "rk4", "6af1ccd677846cbd"),
    ("hourglass", "paper", "explicit-euler", "8d410f96a3608b66"),
    ("hourglass", "paper", "semi-implicit-euler", "72c2f7c4a51f9b17"),
    ("hourglass", "paper", "verlet", "aeed0f8401cddc8d"),
    ("hourglass", "paper", "rk4", "91739d059a59c182"),
];

/// Parameters a scene is pinned with where its defaults would make the table slow: the
/// hourglass with 1,000 grains (its default is 4,000).
fn pinned_with(scene: &str) -> Vec<String> {
    if scene == "hourglass" { vec!["count=1000".into()] } else { Vec::new() }
}

fn run(scene: &str, kind: SolverKind, integrator: Integrator) -> String {
    let mut scene = scenes::build(scene, &pinned_with(scene)).unwrap();
    let mut settings = *scene.world().solver();
    settings.kind = kind;
    settings.integrator = integrator;
    scene.world_mut().set_solver(settings).unwrap();
    let dt = scene.info().dt;
    for step in 0..STEPS {
        // Scenes with actions take them on the way, so the pin covers what a user does:
        // the projectile fires a round at the start and another at step 200.
        if step == 0 || step == 200 {
            scene.act(SceneAction::Fire);
        }
        scene.step(dt).unwrap_or_else(|e| panic!("{} step {step}: {e}", scene.info().name));
    }
    hash_text(scene.world().state_hash())
}

#[test]
fn every_scene_runs_to_its_pinned_hash() {
    let print = std::env::var_os("PRINT_STATE_HASHES").is_some();
    let mut found = Vec::new();
    for name in scenes::scene_names() {
        // The pile is pinned at its default size (2,000 spheres).
        for kind in SolverKind::ALL {
            for integrator in Integrator::ALL {
                found.push((name, kind.name(), integrator.name(), run(name, kind, integrator)));
            }
        }
    }
    if print {
        for (scene, solver, integrator, hash) in &found {
            println!("    ({scene:?}, {solver:?}, {integrator:?}, {hash:?}),");
        }
    }
    let mut differ = Vec::new();
    for (scene, solver, integrator, hash) in &found {
        let pinned = PINNED.iter().find(|p| (p.0, p.1, p.2) == (*scene, *solver, *integrator));
        match pinned {
            Some(p) if p.3 == hash => {}
            Some(p) => differ.push(format!("{scene} {solver} {integrator}: {hash}, pinned {}", p.3)),
            None => differ.push(format!("{scene} {solver} {integrator}: {hash}, not pinned")),
        }
    }
    assert_eq!(
        found.len(),
        PINNED.len(),
        "the table pins {} runs, the registry has {}",
        PINNED.len(),
        found.len()
    );
    assert!(differ.is_empty(), "{} of {} runs changed:\n{}", differ.len(), found.len(), differ.join("\n"));
}

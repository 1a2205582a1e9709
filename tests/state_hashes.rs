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
    ("bridge", "soft", "explicit-euler", "940b0deb05984dea"),
    ("bridge", "soft", "semi-implicit-euler", "93451f281485c50c"),
    ("bridge", "soft", "verlet", "de3f214d43b252fc"),
    ("bridge", "soft", "rk4", "0d28f6fb9a9b38df"),
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
    ("pendulum", "soft", "explicit-euler", "ab9f822991e7d6d6"),
    ("pendulum", "soft", "semi-implicit-euler", "8fee43a7c2ec68f3"),
    ("pendulum", "soft", "verlet", "4b9254ab45a30453"),
    ("pendulum", "soft", "rk4", "83f55f061cd05619"),
    ("pendulum", "paper", "explicit-euler", "9ae6c8a514209961"),
    ("pendulum", "paper", "semi-implicit-euler", "e82fd807317e52ca"),
    ("pendulum", "paper", "verlet", "4a172079a9188764"),
    ("pendulum", "paper", "rk4", "474d2893155d7799"),
    ("cradle", "soft", "explicit-euler", "14b1ef6dd9d8f39d"),
    ("cradle", "soft", "semi-implicit-euler", "6b41425ba1500bf8"),
    ("cradle", "soft", "verlet", "4f51b0d2164a5698"),
    ("cradle", "soft", "rk4", "98dcce7298dce46a"),
    ("cradle", "paper", "explicit-euler", "230d9a41fe863513"),
    ("cradle", "paper", "semi-implicit-euler", "9411dc4f0dd56e05"),
    ("cradle", "paper", "verlet", "55cb7c27bf688468"),
    ("cradle", "paper", "rk4", "801d065f4e273b3a"),
    ("chain", "soft", "explicit-euler", "59a83926495f9028"),
    ("chain", "soft", "semi-implicit-euler", "a029b50abf748c6d"),
    ("chain", "soft", "verlet", "df264b0425a31246"),
    ("chain", "soft", "rk4", "0e5b73f6ea397e68"),
    ("chain", "paper", "explicit-euler", "448fab00148b914e"),
    ("chain", "paper", "semi-implicit-euler", "edf44004087be24d"),
    ("chain", "paper", "verlet", "0cf07785bc4f9ac5"),
    ("chain", "paper", "rk4", "29fe929960b04256"),
    ("cloth", "soft", "explicit-euler", "981808ea9ad8f101"),
    ("cloth", "soft", "semi-implicit-euler", "bd4dbf18543d06d5"),
    ("cloth", "soft", "verlet", "68fc45e97e8a6843"),
    ("cloth", "soft", "rk4", "bf9e6bb4ec37eb0b"),
    ("cloth", "paper", "explicit-euler", "bd9726b4eceb22f2"),
    ("cloth", "paper", "semi-implicit-euler", "e12fe5e472beeb7c"),
    ("cloth", "paper", "verlet", "84b9da1e9e4b023e"),
    ("cloth", "paper", "rk4", "fc714ebf20172cab"),
    ("platform", "soft", "explicit-euler", "1f04ab83e2b401b9"),
    ("platform", "soft", "semi-implicit-euler", "e3786861b51c465c"),
    ("platform", "soft", "verlet", "3e3669f524657fc7"),
    ("platform", "soft", "rk4", "b238a598a1391bbe"),
    ("platform", "paper", "explicit-euler", "cb05143943bb15ba"),
    ("platform", "paper", "semi-implicit-euler", "fadbf2cff7018694"),
    ("platform", "paper", "verlet", "4b650f62f03e30fa"),
    ("platform", "paper", "rk4", "8b08483efeaa650a"),
    ("blob", "soft", "explicit-euler", "bad058960523e074"),
    ("blob", "soft", "semi-implicit-euler", "52043e4567f6297e"),
    ("blob", "soft", "verlet", "3658f77ead29be74"),
    ("blob", "soft", "rk4", "f5ef7dd2fb044d1a"),
    ("blob", "paper", "explicit-euler", "28708167f2e7c21b"),
    ("blob", "paper", "semi-implicit-euler", "a0958f52375256d7"),
    ("blob", "paper", "verlet", "a24cddaa4c5472e2"),
    ("blob", "paper", "rk4", "da8cd4ea30f22b27"),
    ("hourglass", "soft", "explicit-euler", "159eb4696beb0afb"),
    ("hourglass", "soft", "semi-implicit-euler", "b6eff5f184b3f1f3"),
    ("hourglass", "soft", "verlet", "d22a67ac797be0d2"),
    ("hourglass", "soft", "rk4", "394973a6649914d8"),
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

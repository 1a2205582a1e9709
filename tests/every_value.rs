//! Every value a user can give a parameter runs: each parameter of each scene (the
//! compiled ones and the shipped files) at its minimum, maximum, default and −0, through
//! each door a value comes in by — `simulate --set` (the table walked is the one
//! `scenes --format json` prints), the window's slider on a running lab (with the panel
//! drawn and a frame rendered, as the window does), a lab opened with the value (as
//! `render --set` and saved settings open it) and Compare with the value changed — plus
//! random values within range for every parameter at once, in a proptest.
//!
//! springForces at `g = 0` (in its range of 0 to 30) panicked through every one of these
//! doors before buoyancy accepted a world without weight (issue 17, finding 1).

use std::process::Command;

use particle_lab::capture::FrameCapture;
use particle_lab::scenes::{self, SCENES, SceneEntry};
use particle_lab::ui::Lab;
use particle_lab::ui::compare::Change;
use proptest::prelude::*;

/// Steps run with each value: enough for the first contacts, springs and rounds.
const STEPS: u32 = 30;
/// The panel is 330 points wide: the frame leaves room for a little of the scene.
const SIZE: [u32; 2] = [480, 320];

fn binary() -> Command {
    Command::new(env!("CARGO_BIN_EXE_particle-lab"))
}

/// The values tried for one parameter: its ends, its default and −0 (which is in range
/// wherever 0 is).
fn values(min: f64, max: f64, default: f64) -> [f64; 4] {
    [min, max, default, -0.0]
}

fn in_range(value: f64, min: f64, max: f64) -> bool {
    value >= min && value <= max
}

/// A message a user is shown: one line, no panic text, no backtrace.
fn assert_one_line(what: &str, stderr: &str) {
    assert!(!stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"), "{what} panicked:\n{stderr}");
    assert!(stderr.trim_end().lines().count() <= 1, "{what}: more than one line:\n{stderr}");
}

/// Every scene the lab offers: compiled and shipped as files.
fn entries() -> Vec<&'static SceneEntry> {
    SCENES.iter().chain(scenes::file::shipped()).collect()
}

/// The biggest values of the count-like parameters make scenes that take seconds a
/// step (the pile and the hourglass at 200,000 spheres); they are run, but for fewer
/// steps.
fn steps_for(scene: &str, name: &str, value: f64) -> u32 {
    if matches!(scene, "pile" | "hourglass") && name == "count" && value > 10_000.0 { 2 } else { STEPS }
}

#[test]
fn simulate_runs_every_parameter_at_its_ends_its_default_and_minus_zero() {
    let output = binary().args(["scenes", "--format", "json"]).output().unwrap();
    assert!(output.status.success());
    let table: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let mut runs = 0;
    for scene in table.as_array().expect("a list of scenes") {
        let name = scene["name"].as_str().unwrap();
        for param in scene["params"].as_array().unwrap() {
            let key = param["name"].as_str().unwrap();
            let [min, max, default] = ["min", "max", "default"].map(|k| param[k].as_f64().unwrap());
            for value in values(min, max, default) {
                let text = if value == 0.0 && value.is_sign_negative() {
                    "-0".to_string()
                } else {
                    value.to_string()
                };
                let steps = steps_for(name, key, value).to_string();
                let output = binary()
                    .args(["simulate", "--scene", name, "--set", &format!("{key}={text}")])
                    .args(["--steps", &steps, "--every", &steps])
                    .output()
                    .unwrap();
                let stderr = String::from_utf8_lossy(&output.stderr);
                let what = format!("simulate --scene {name} --set {key}={text}");
                assert_one_line(&what, &stderr);
                if in_range(value, min, max) {
                    assert!(output.status.success(), "{what}: exit {:?}: {stderr}", output.status.code());
                    let stdout = String::from_utf8_lossy(&output.stdout);
                    let last: serde_json::Value =
                        serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
                    assert_eq!(last["step"].as_u64(), Some(u64::from(steps_for(name, key, value))), "{what}");
                } else {
                    // −0 below a positive minimum: refused as a usage error, in one line.
                    assert_eq!(output.status.code(), Some(2), "{what}: {stderr}");
                    assert!(stderr.contains("out of range"), "{what}: {stderr}");
                }
                runs += 1;
            }
        }
    }
    // Eleven scenes with 64 parameters between them, four values each.
    assert!(runs >= 4 * 64, "only {runs} runs: the table is missing scenes or parameters");
}

/// The doors of the window for one value: the slider moved on a running lab (the panel
/// drawn and a frame rendered after it), a lab opened on the value, and Compare with
/// the value as the change.
fn window_doors(gpu: &mut FrameCapture, entry: &'static SceneEntry, name: &'static str, value: f32) {
    let scene = &*entry.info().name;
    let steps = steps_for(scene, name, f64::from(value));
    // The slider: the scene runs a little, then the value is set, as a drag does.
    let mut lab = Lab::from_entry(entry, &[], Default::default()).unwrap();
    // A launcher's round in flight, as `render` fires it at step 0.
    lab.fire_at_start();
    lab.run_steps(5);
    lab.set_param(name, value);
    lab.run_steps(steps);
    gpu.render(&mut lab, SIZE, true).unwrap_or_else(|e| panic!("{scene} {name}={value}: {e}"));
    assert!(!lab.status.contains("panicked"), "{}", lab.status);

    // Opened on the value: `render --set`, `--set` in the window, saved settings.
    let assignment = format!("{name}={value}");
    let mut lab = Lab::from_entry(entry, &[assignment], Default::default()).unwrap();
    lab.start_compare(Change::Param(name.to_string(), value));
    lab.fire_at_start();
    lab.run_steps(steps);
    gpu.render(&mut lab, SIZE, true).unwrap_or_else(|e| panic!("{scene} {name}={value}: {e}"));
}

#[test]
fn the_window_and_render_take_every_parameter_at_its_ends_its_default_and_minus_zero() {
    let mut gpu = FrameCapture::new().expect("headless rendering needs a GPU adapter (bash scripts/test.sh)");
    let mut tried = 0;
    for entry in entries() {
        for param in entry.info().params.iter() {
            let (min, max, default) = (f64::from(param.min), f64::from(param.max), f64::from(param.default));
            for value in values(min, max, default) {
                if in_range(value, min, max) {
                    window_doors(&mut gpu, entry, &param.name, value as f32);
                    tried += 1;
                } else {
                    // Out of range: the slider cannot reach it and a typed value is refused.
                    let mut lab = Lab::from_entry(entry, &[], Default::default()).unwrap();
                    lab.set_param(&param.name, value as f32);
                    assert!(lab.status.contains("out of range"), "{}: {}", param.name, lab.status);
                    assert!(!lab.status.contains('\n'));
                }
            }
        }
    }
    assert!(tried >= 3 * 64, "only {tried} values tried");
}

/// A value for each parameter of `entry`, from fractions of their ranges.
fn random_values(entry: &'static SceneEntry, fractions: &[f64]) -> Vec<(&'static str, f32)> {
    entry
        .info()
        .params
        .iter()
        .zip(fractions.iter().cycle())
        .map(|(p, f)| {
            // The pile's count stays small: a proptest case must be quick.
            let max = if p.name == "count" { p.min.max(400.0_f32.min(p.max)) } else { p.max };
            let value = f64::from(p.min) + f * (f64::from(max) - f64::from(p.min));
            // A whole-number parameter takes whole numbers only (a fraction is refused).
            let value = if p.integer { value.round() } else { value };
            (&*p.name, (value as f32).clamp(p.min, max))
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Random values within range for every parameter at once (a third of them at an
    /// end of their range, where the panics were), both through `--set` at the start
    /// and through the sliders of a running scene.
    #[test]
    fn random_values_within_range_run_in_every_scene(
        which in 0usize..11,
        fractions in proptest::collection::vec(prop_oneof![Just(0.0), Just(1.0), 0.0f64..=1.0], 9),
        paper in any::<bool>(),
    ) {
        let all = entries();
        let entry = all[which % all.len()];
        let values = random_values(entry, &fractions);
        let assignments: Vec<String> = values.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let mut solver = particle_lab::physics::SolverSettings::default();
        if paper {
            solver.kind = particle_lab::physics::SolverKind::Paper;
        }
        let mut lab = Lab::from_entry(entry, &assignments, solver)
            .map_err(|e| TestCaseError::fail(format!("{}: {e}", entry.info().name)))?;
        lab.fire_at_start();
        lab.run_steps(STEPS);
        let mut lab = Lab::from_entry(entry, &[], solver).unwrap();
        lab.fire_at_start();
        lab.run_steps(3);
        for (name, value) in values {
            lab.set_param(name, value);
            prop_assert!(!lab.status.contains("out of range"), "{}: {}", name, lab.status);
        }
        lab.run_steps(STEPS);
        let _ = lab.readouts();
    }
}

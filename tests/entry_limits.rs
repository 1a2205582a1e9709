//! A value that cannot be stored is refused where it enters (issue 40): a scene file,
//! a `--set` value, a `--dt` or a snapshot field that would lead to a figure that is
//! not finite gets one line naming it and its limit, and a non-zero exit; `simulate`
//! never prints `null` for a number with exit 0; whole numbers are whole.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_particle-lab")).args(args).output().expect("binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("particle-lab-entry-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// The run is refused with exit 2 and one line on stderr holding every one of `words`,
/// and printed nothing on stdout.
fn refused(output: &Output, words: &[&str]) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "refused with exit 2: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for word in words {
        assert!(stderr.contains(word), "{word:?} in {stderr:?}");
    }
    assert!(output.stdout.is_empty(), "nothing printed before the refusal");
}

const ONE: &str = "[scene]\nname = \"one\"\n[[particle]]\nposition = [0, 1, 0]\n";

#[test]
fn whole_number_parameters_refuse_fractions() {
    refused(
        &run(&["simulate", "--scene", "pile", "--set", "count=2.5", "--steps", "1"]),
        &["count", "2.5", "whole"],
    );
    refused(
        &run(&["simulate", "--scene", "pile", "--set", "rolls=0.5", "--steps", "1"]),
        &["rolls", "0.5", "whole"],
    );
    // A whole number is still taken, and exactly.
    let ok = run(&["simulate", "--scene", "pile", "--set", "count=3", "--steps", "1", "--every", "5"]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let dir = scratch("whole");
    let row = "[scene]\nname = \"row\"\n[[row]]\ncount = 2.5\nstart = [0, 1, 0]\nstep = [1, 0, 0]\n";
    refused(
        &run(&["simulate", "--scene-file", &write(&dir, "row.toml", row), "--steps", "1"]),
        &["row.toml:4:9", "count = 2.5", "whole"],
    );
    // An expression that lands a rounding error from a whole number is that number.
    let near = row.replace("2.5", "\"0.3 * 10\"");
    let out = run(&["simulate", "--scene-file", &write(&dir, "near.toml", &near), "--steps", "0"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let line: serde_json::Value =
        serde_json::from_slice(out.stdout.split(|&b| b == b'\n').next().unwrap()).unwrap();
    assert_eq!(line["particles"].as_array().unwrap().len(), 3);
    let pin = row.replace("count = 2.5", "count = 3\npin = [1.5]");
    let pinned = run(&["simulate", "--scene-file", &write(&dir, "pin.toml", &pin), "--steps", "1"]);
    assert_eq!(pinned.status.code(), Some(2), "{}", String::from_utf8_lossy(&pinned.stderr));
    let param = "[scene]\nname = \"p\"\n[[param]]\nname = \"n\"\ndefault = 2.5\nmin = 1\nmax = 5\ninteger = true\n\
                 [[row]]\ncount = \"n\"\nstart = [0, 1, 0]\nstep = [1, 0, 0]\n";
    refused(
        &run(&["simulate", "--scene-file", &write(&dir, "param.toml", param), "--steps", "1"]),
        &["whole"],
    );
    // Booleans are booleans.
    let rolls = format!("{ONE}rolls = 0.5\n");
    refused(
        &run(&["simulate", "--scene-file", &write(&dir, "rolls.toml", &rolls), "--steps", "1"]),
        &["boolean"],
    );
}

#[test]
fn figures_that_would_overflow_are_refused_at_the_door() {
    let dir = scratch("door");
    let cases: &[(&str, String, &[&str])] = &[
        ("tiny-sphere", format!("{ONE}radius = 1e-30\nrolls = true\n"), &["radius", "1e-30", "1e-6"]),
        ("huge-sphere", format!("{ONE}radius = 1e30\nrolls = true\n"), &["radius", "1e30", "1e6"]),
        ("fast", format!("{ONE}velocity = [3e38, 0, 0]\n"), &["velocity", "1e8"]),
        (
            "far",
            "[scene]\nname = \"far\"\n[[particle]]\nposition = [0, 1e20, 0]\n".into(),
            &["position", "1e9"],
        ),
        (
            "stiff",
            format!(
                "{ONE}[[link]]\nkind = \"stiff_spring\"\na = 0\nanchor = [0, 3, 0]\nk = 1e30\nlength = 0.1\n"
            ),
            &["stiff spring k", "1e30", "1e9"],
        ),
        (
            "spring",
            format!("{ONE}[[link]]\nkind = \"spring\"\na = 0\nanchor = [0, 3, 0]\nk = 1e30\n"),
            &["spring k", "1e9"],
        ),
        ("gravity", format!("[scene]\nname = \"g\"\ngravity = 1e30\n{}", &ONE[21..]), &["1e6"]),
    ];
    for (name, text, words) in cases {
        let file = write(&dir, &format!("{name}.toml"), text);
        refused(&run(&["simulate", "--scene-file", &file, "--steps", "1"]), words);
    }
    refused(
        &run(&["simulate", "--scene", "bridge", "--dt", "1e-45", "--steps", "2"]),
        &["--dt", "1e-45", "1e-6"],
    );
    // The limits themselves are accepted.
    let edge = format!("{ONE}radius = 1e-6\nrolls = true\nvelocity = [1e8, 0, 0]\n");
    let out =
        run(&["simulate", "--scene-file", &write(&dir, "edge.toml", &edge), "--steps", "3", "--dt", "1e-6"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// What found it: a pinned particle in buoyancy printed `"m": null`. A fixed particle
/// now says `"fixed": true`, the liquid does no work on it, and its snapshot reopens.
#[test]
fn a_pinned_particle_in_buoyancy_prints_no_null_and_reopens() {
    let dir = scratch("buoy");
    let text = "[scene]\nname = \"buoy\"\n[[particle]]\nposition = [0, 1, 0]\nfixed = true\n\
                [[buoyancy]]\nparticle = 0\nsurface = 2\nhalf_height = 0.5\nvolume = 1\n";
    let file = write(&dir, "buoy.toml", text);
    let snapshot = dir.join("buoy.json");
    let snapshot = snapshot.to_str().unwrap();
    let out = run(&["simulate", "--scene-file", &file, "--steps", "20", "--every", "5", "--save", snapshot]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(!text.contains("null"), "{text}");
    for line in text.lines() {
        let line: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(line["particles"][0]["fixed"], true);
        // Held still, the particle has no energy of any kind: ½mv² = 0, and neither
        // gravity nor the liquid moves it through a height.
        assert_eq!(line["energy"]["potential"], 0.0, "{line}");
        assert_eq!(line["energy"]["kinetic"], 0.0);
    }
    let on = run(&["simulate", "--from", snapshot, "--steps", "1"]);
    assert!(on.status.success(), "{}", String::from_utf8_lossy(&on.stderr));
}

/// A spring so stiff for its mass that the explicit step overshoots: the energy
/// overflows a step or more before the positions do. The run stops there, naming the
/// figure, and no line before it holds a `null`.
#[test]
fn a_blow_up_is_caught_at_the_first_figure_that_overflows() {
    let dir = scratch("blow");
    let text = "[scene]\nname = \"blow\"\ngravity = 0\n[[particle]]\nposition = [0, 1, 0]\nmass = 1e-3\n\
                [[link]]\nkind = \"spring\"\na = 0\nanchor = [0, 0, 0]\nk = 1e6\nlength = 0.5\n";
    let file = write(&dir, "blow.toml", text);
    let out = run(&["simulate", "--scene-file", &file, "--steps", "400", "--integrator", "explicit-euler"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("blew up at step") && stderr.contains("no longer a finite number"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(stdout.lines().count() > 1, "it ran some steps first");
    // `"b": null` is an anchored link's missing second particle, not a number.
    assert!(!stdout.replace("\"b\":null", "").contains("null"), "no figure was printed as null");
    // The step it names is the one after the last printed.
    let last: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    let named = format!("step {}", last["step"].as_u64().unwrap() + 1);
    assert!(stderr.contains(&named), "{named} in {stderr}");
    // Saving it is refused too, rather than writing a file that will not open.
    let saved = dir.join("blow.json");
    let out = run(&[
        "simulate",
        "--scene-file",
        &file,
        "--steps",
        "400",
        "--every",
        "1000",
        "--integrator",
        "explicit-euler",
        "--save",
        saved.to_str().unwrap(),
    ]);
    assert_ne!(out.status.code(), Some(0));
    assert!(!saved.exists(), "no snapshot of a world that blew up");
}

/// A snapshot edited by hand (its seals deleted) to a speed that is finite but whose
/// energy is not is refused on opening, naming the energy.
#[test]
fn a_snapshot_whose_energy_overflows_is_refused_naming_it() {
    let dir = scratch("edited");
    let file = dir.join("s.json");
    let file = file.to_str().unwrap();
    let out = run(&["simulate", "--scene", "springForces", "--steps", "5", "--every", "10", "--save", file]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut snapshot: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    let object = snapshot.as_object_mut().unwrap();
    object.remove("hash");
    object.remove("checksum");
    let velocity = &mut snapshot["world"]["particles"]["velocity"][0];
    *velocity = serde_json::json!([1e30, 0.0, 0.0]);
    std::fs::write(file, serde_json::to_string(&snapshot).unwrap()).unwrap();
    refused(&run(&["simulate", "--from", file, "--steps", "1"]), &["kinetic energy", "finite"]);
}

/// Reading is bounded by what it costs: a snapshot under the size limit whose scene
/// state is a huge array is read into the scene's own types, never into a tree of JSON
/// values (about 16 bytes a `0,`: 8 GB for 512 MB of them). Run with its address space
/// capped at 1.5 GB, the process refuses the file in one line instead of aborting.
#[test]
fn a_huge_scene_state_is_refused_within_bounded_memory() {
    let dir = scratch("huge");
    for (scene, inner) in [("projectile", "[0,0,"), ("hourglass", "{\"packing\":0.5,\"samples\":[")] {
        let file = dir.join(format!("{scene}.json"));
        let out = run(&[
            "simulate",
            "--scene",
            scene,
            "--set",
            "count=50",
            "--steps",
            "2",
            "--every",
            "9",
            "--save",
            file.to_str().unwrap(),
        ]);
        let out = if out.status.success() {
            out
        } else {
            run(&[
                "simulate",
                "--scene",
                scene,
                "--steps",
                "2",
                "--every",
                "9",
                "--save",
                file.to_str().unwrap(),
            ])
        };
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let mut snapshot: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
        let object = snapshot.as_object_mut().unwrap();
        object.remove("hash");
        object.remove("checksum");
        object.insert("scene_state".into(), serde_json::Value::String("PLACEHOLDER".into()));
        let text = serde_json::to_string(&snapshot).unwrap();
        // 120 MB of pairs: each a sample at t = 0, which the hourglass refuses (samples
        // must grow later), and an array where the projectile wants an object.
        let pairs = 20_000_000;
        let mut state = String::with_capacity(inner.len() + 6 * pairs + 8);
        state.push_str(inner);
        for k in 0..pairs {
            state.push_str(if k + 1 < pairs { "[0,0]," } else { "[0,0]" });
        }
        state.push_str(if scene == "projectile" { ",0]" } else { "]}" });
        std::fs::write(&file, text.replace("\"PLACEHOLDER\"", &state)).unwrap();
        drop(state);
        let command = format!(
            "ulimit -v 1500000; exec {} simulate --from {} --steps 1",
            env!("CARGO_BIN_EXE_particle-lab"),
            file.display()
        );
        let output = Command::new("sh").args(["-c", &command]).output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{scene}: refused, not aborted: {stderr}");
        assert!(stderr.contains("scene_state"), "{scene}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        let _ = std::fs::remove_file(&file);
    }
}

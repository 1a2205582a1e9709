//! Scenes as files (issue 10, section 2): the TOML format builds what it says, its
//! parameters reach `--set` and the sliders, bad files get one line naming the line
//! and column, hot reload, and a reference image for each shipped scene.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use particle_lab::capture::FrameCapture;
use particle_lab::physics::{LinkKind, SolverSettings};
use particle_lab::render::offscreen::{read_png, write_png};
use particle_lab::scenes::{self, Scene, file};
use particle_lab::ui::Lab;
use proptest::prelude::*;

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .expect("binary runs")
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("particle-lab-scene-files-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Loads a scene from text as a file named `test.toml`; the error as its one line.
fn load(text: &str) -> Result<Box<dyn Scene>, String> {
    let entry = file::load_text(text, "test.toml", None).map_err(|e| e.to_string())?;
    scenes::build_entry(&entry, &[])
}

fn load_err(text: &str) -> String {
    match load(text) {
        Ok(_) => panic!("loaded, but should not have:\n{text}"),
        Err(message) => message,
    }
}

fn rods(scene: &dyn Scene) -> Vec<f32> {
    scene
        .world()
        .links()
        .iter()
        .filter(|l| matches!(l.spec.kind, LinkKind::Rod))
        .map(|l| l.spec.rest)
        .collect()
}

#[test]
fn the_chain_is_a_row_of_rods_as_long_as_the_v_it_starts_in() {
    let chain = scenes::build("chain", &[]).unwrap();
    assert_eq!(chain.world().particles.len(), 21);
    let lengths = rods(chain.as_ref());
    assert_eq!(lengths.len(), 20);
    // A V of depth 1 over a span of 3 in 20 pieces: each (3/20, 2/20) long.
    let expected = (0.15f32 * 0.15 + 0.1 * 0.1).sqrt();
    for length in &lengths {
        assert!((length - expected).abs() < 1e-5, "rod of {length} m, expected {expected}");
    }
    let p = &chain.world().particles;
    assert_eq!(p.inverse_masses()[0], 0.0, "first bead pinned");
    assert_eq!(p.inverse_masses()[20], 0.0, "last bead pinned (-1)");
    assert_eq!(p.inverse_masses()[10], 10.0, "a 0.1 kg bead");

    let short = scenes::build("chain", &["links=10".into(), "span=2".into()]).unwrap();
    let lengths = rods(short.as_ref());
    assert_eq!(lengths.len(), 10);
    let expected = (0.2f32 * 0.2 + 0.2 * 0.2).sqrt();
    assert!(lengths.iter().all(|l| (l - expected).abs() < 1e-5), "{lengths:?}");
}

#[test]
fn the_chain_settles_into_a_catenary_and_keeps_its_lengths() {
    let mut chain = scenes::build("chain", &[]).unwrap();
    for _ in 0..2400 {
        chain.step(1.0 / 240.0).unwrap();
    }
    let world = chain.world();
    for link in world.links() {
        let stretch = (link.length - link.spec.rest).abs() / link.spec.rest;
        assert!(stretch < 0.01, "a rod is {:.2}% off its length", stretch * 100.0);
    }
    // Hanging, the middle is lowest and above the V's tip (a catenary is shallower).
    let y: Vec<f32> = world.particles.positions().iter().map(|p| p.y).collect();
    let lowest = y.iter().copied().fold(f32::MAX, f32::min);
    assert!((y[10] - lowest).abs() < 0.02, "the middle bead hangs lowest: {y:?}");
    assert!(lowest > 2.0 && lowest < 2.5, "lowest point {lowest} m");
}

#[test]
fn a_grid_makes_rows_times_cols_particles_with_structural_and_shear_links() {
    let cloth = scenes::build("cloth", &[]).unwrap();
    let world = cloth.world();
    assert_eq!(world.particles.len(), 14 * 14);
    // 2 * 14 * 13 along rows and columns.
    assert_eq!(rods(cloth.as_ref()).len(), 364);
    let w = world.particles.inverse_masses();
    assert_eq!((w[0], w[13]), (0.0, 0.0), "the two corners of row 0 are pinned");
    assert_eq!(w.iter().filter(|&&w| w == 0.0).count(), 2);
    let small = scenes::build("cloth", &["cells=5".into()]).unwrap();
    assert_eq!(small.world().particles.len(), 25);
    assert_eq!(rods(small.as_ref()).len(), 2 * 5 * 4);

    // 3 rows of 4: 3 * 3 + 2 * 4 structural, 2 * 2 * 3 diagonal, each as long as it starts.
    let grid = load(
        "[scene]\nname = \"g\"\n[[grid]]\nrows = 3\ncols = 4\nstep_col = [0.3, 0, 0]\nstep_row = [0, 0, 0.4]\n\
         link = \"cable\"\nshear = true\npin = [[-1, -1]]\n",
    )
    .unwrap();
    let links = grid.world().links();
    assert_eq!(links.len(), 17 + 12);
    assert!(links.iter().all(|l| l.spec.kind == LinkKind::Cable));
    let mut lengths: Vec<f32> = links.iter().map(|l| (l.spec.rest * 100.0).round() / 100.0).collect();
    lengths.dedup();
    lengths.sort_by(f32::total_cmp);
    lengths.dedup();
    assert_eq!(lengths, [0.3, 0.4, 0.5]);
    assert_eq!(grid.world().particles.inverse_masses()[11], 0.0, "[-1, -1] is the last");
}

#[test]
fn the_cloth_tears_above_the_tension_set_and_not_below() {
    let links = |scene: &dyn Scene| scene.world().links().len();
    let mut strong = scenes::build("cloth", &["tear=1000".into()]).unwrap();
    let mut weak = scenes::build("cloth", &["tear=2".into()]).unwrap();
    let before = links(strong.as_ref());
    for _ in 0..240 {
        strong.step(1.0 / 240.0).unwrap();
        weak.step(1.0 / 240.0).unwrap();
    }
    assert_eq!(links(strong.as_ref()), before, "no link reaches 1000 N");
    let left = links(weak.as_ref());
    assert!(left < before - 10, "at 2 N links tear: {left} of {before} left");
    let torn = weak.readouts(1.0 / 240.0).into_iter().find(|(k, _)| k == "links torn").unwrap().1;
    assert_eq!(torn, (before - left).to_string());
}

#[test]
fn the_platform_has_six_particles_and_fifteen_rods_and_the_ball_rolls_down_it() {
    let mut platform = scenes::build("platform", &[]).unwrap();
    let frame: Vec<_> = platform
        .world()
        .links()
        .into_iter()
        .filter(|l| match l.spec.b {
            particle_lab::physics::LinkEnd::Particle(b) => l.spec.a.0 < 6 && b.0 < 6,
            particle_lab::physics::LinkEnd::Anchor(_) => false,
        })
        .collect();
    assert_eq!(frame.len(), 15, "Cyclone's platform has 15 rods between its 6 particles");
    let start = platform.world().particles.positions()[6];
    for _ in 0..480 {
        platform.step(1.0 / 240.0).unwrap();
    }
    let p = platform.world().particles.positions();
    // The weight is right of the pivot: the right end goes down, the ball rolls right.
    assert!(p[4].y < 1.0, "right end at {} m", p[4].y);
    assert!(p[2].y > 2.5, "left end at {} m", p[2].y);
    assert!(p[6].x > start.x + 0.5, "the ball rolled from x = {} to {}", start.x, p[6].x);
    for link in &frame {
        assert!((link.length - link.spec.rest).abs() < 0.02 * link.spec.rest, "a rod stretched");
    }
}

#[test]
fn the_blob_falls_squashes_and_keeps_its_ring() {
    let mut blob = scenes::build("blob", &[]).unwrap();
    let world = blob.world();
    assert_eq!(world.particles.len(), 37);
    let springs = world.links().iter().filter(|l| l.spec.kind == LinkKind::Spring).count();
    assert_eq!(springs, 36 + 36, "a closed ring of 36 and 36 spokes");
    let mut lowest_centre = f32::MAX;
    for _ in 0..1200 {
        blob.step(1.0 / 240.0).unwrap();
        lowest_centre = lowest_centre.min(blob.world().particles.positions()[0].y);
    }
    let p = blob.world().particles.positions();
    assert!(p.iter().all(|q| q.y > 0.0), "nothing went through the ground");
    // Round, the centre would rest at the ring's radius and a bead's, 0.86 m: it
    // squashes below that on landing, and a little at rest.
    assert!(lowest_centre < 0.6, "the centre came down to {lowest_centre} m");
    assert!(p[0].y > 0.6 && p[0].y < 0.8, "at rest the centre is at {} m", p[0].y);
}

#[test]
fn parameters_reach_set_and_the_sliders_and_g_acts_at_once() {
    let blob = scenes::build("blob", &["beads=8".into(), "height=3".into()]).unwrap();
    assert_eq!(blob.world().particles.len(), 9);
    assert_eq!(blob.params().get("height"), 3.0);
    let names: Vec<&str> = blob.info().params.iter().map(|p| &*p.name).collect();
    assert_eq!(names, ["beads", "radius", "k", "height", "damping", "g"], "g is added to every file scene");

    let mut chain = scenes::build("chain", &[]).unwrap();
    for _ in 0..10 {
        chain.step(1.0 / 240.0).unwrap();
    }
    chain.set_param("g", 1.62).unwrap();
    assert_eq!(chain.world().steps(), 10, "changing g does not rebuild");
    assert_eq!(chain.world().particles.accelerations()[5].y, -1.62);
    chain.set_param("links", 8.0).unwrap();
    assert_eq!((chain.world().steps(), chain.world().particles.len()), (0, 9), "links rebuilds");
    assert_eq!(chain.world().particles.accelerations()[5].y, -1.62, "keeping g");
    let error = chain.set_param("links", 1000.0).unwrap_err().to_string();
    assert_eq!(error, "'links' = 1000 is out of range; valid range: 4 to 60");

    // Through the binary: --scene-file and --set.
    let out =
        run(&["simulate", "--scene-file", "assets/scenes/blob.toml", "--set", "beads=6", "--steps", "2"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let first: serde_json::Value =
        serde_json::from_slice(out.stdout.split(|&b| b == b'\n').next().unwrap()).unwrap();
    assert_eq!(first["particles"].as_array().unwrap().len(), 7);
    assert_eq!(first["links"].as_array().unwrap().len(), 12);
}

#[test]
fn a_solver_change_survives_a_rebuild() {
    let mut lab = Lab::from_entry(scenes::find("chain").unwrap(), &[], SolverSettings::default()).unwrap();
    let mut solver = lab.solver();
    solver.substeps = 9;
    lab.set_solver(solver);
    lab.set_param("span", 2.0);
    assert_eq!(lab.scene.world().solver().substeps, 9);
}

#[test]
fn expressions_use_parameters_and_the_row_index() {
    let text = r#"
[scene]
name = "sums"

[[param]]
name = "m"
default = 2
min = 1
max = 10

[[particle]]
name = "a"
position = [0, "m * 2 + 1", "-(m - 4) ^ 2"]
mass = "sqrt(m * 8)"
velocity = ["cos(pi)", "sin(rad(90))", 0]

[[row]]
count = "m + 1"
position = ["i * 0.5", 1, 0]
mass = "1 + i"
"#;
    let scene = load(text).unwrap();
    let p = &scene.world().particles;
    assert_eq!(p.positions()[0].to_array(), [0.0, 5.0, -4.0]);
    assert_eq!(p.mass(0), 4.0);
    assert!((p.velocities()[0] - glam::Vec3::new(-1.0, 1.0, 0.0)).length() < 1e-6);
    assert_eq!(p.len(), 4);
    assert_eq!(p.positions()[3].x, 1.0);
    assert_eq!(p.mass(3), 3.0);
    let entry = file::load_text(text, "test.toml", None).unwrap();
    let bigger = scenes::build_entry(&entry, &["m=8".into()]).unwrap();
    assert_eq!(bigger.world().particles.len(), 10);
    assert_eq!(bigger.world().particles.positions()[0].y, 17.0);
}

#[test]
fn bad_files_get_one_line_with_line_and_column() {
    let base = "[scene]\nname = \"t\"\n[[param]]\nname = \"mass\"\ndefault = 1\nmin = 0.1\nmax = 5\n";
    // An unknown name in an expression: the column of the name inside the quotes.
    let error = load_err(&format!("{base}[[particle]]\nposition = [0, 1, 0]\nmass = \"2 * mas\"\n"));
    assert_eq!(
        error,
        "test.toml:10:13: in the expression \"2 * mas\": unknown name 'mas'; valid names here: mass, g, pi"
    );
    // A link to particle 99 of 3.
    let error = load_err(&format!(
        "{base}[[row]]\ncount = 3\nstart = [0, 0, 0]\n[[link]]\nkind = \"rod\"\na = 0\nb = 99\n"
    ));
    assert_eq!(error, "test.toml:14:5: particle 99 is out of range: the file makes 3 particles (0 to 2)");
    // TOML syntax: where, and what was expected.
    let error = load_err("[scene]\nname = \"t\"\n[[particle]]\nposition = [0, 1 0]\n");
    assert!(error.starts_with("test.toml:4:"), "{error}");
    assert_eq!(error.lines().count(), 1, "{error}");
    // A misspelt key is refused where it is.
    let error = load_err("[scene]\nname = \"t\"\n[[particle]]\npositon = [0, 1, 0]\n");
    assert!(error.starts_with("test.toml:4:1: unknown field `positon`"), "{error}");
    // A value of the wrong type.
    let error = load_err("[scene]\nname = \"t\"\n[[particle]]\nposition = [0, true, 0]\n");
    assert!(error.starts_with("test.toml:4:16:") && error.contains("a number or an expression"), "{error}");
    // A value out of its range, from an expression.
    let error = load_err(&format!("{base}[[particle]]\nposition = [0, 1, 0]\nmass = \"mass - 1\"\n"));
    assert_eq!(error, "test.toml:10:8: mass = 0 is out of range; valid range: 1e-9 to 1e12 kg");
    // Three values for a vector.
    let error = load_err("[scene]\nname = \"t\"\n[[particle]]\nposition = [0, 1]\n");
    assert_eq!(error, "test.toml:4:12: expected three values [x, y, z], found 2");
    // An unknown kind of link, and a name that is not there.
    let error = load_err("[scene]\nname = \"t\"\n[[row]]\ncount = 2\nstart = [0, 0, 0]\nlink = \"rood\"\n");
    assert_eq!(
        error,
        "test.toml:6:8: unknown link kind 'rood'; valid kinds: rod, cable, spring, bungee, stiff_spring"
    );
    let error = load_err(
        "[scene]\nname = \"t\"\n[[row]]\nname = \"r\"\ncount = 2\nstart = [0, 0, 0]\n[[link]]\nkind = \"rod\"\na = \"r.5\"\nb = \"q\"\n",
    );
    assert_eq!(error, "test.toml:9:5: index 5 of 'r' is out of range: it has 2 (0 to 1)");
    // A default outside its range.
    let error = load_err("[scene]\nname = \"t\"\n[[param]]\nname = \"k\"\ndefault = 9\nmin = 0\nmax = 5\n");
    assert_eq!(error, "test.toml:5:11: default = 9 is out of range; valid range: 0 to 5");
}

#[test]
fn absurd_arrays_are_refused_before_they_are_made() {
    let error = load_err("[scene]\nname = \"t\"\n[[grid]]\nrows = 1000\ncols = 1000\n");
    assert_eq!(
        error,
        "test.toml:5:8: 1000 rows of 1000 make 1000000 particles; a scene file makes at most 200000"
    );
    let error = load_err("[scene]\nname = \"t\"\n[[row]]\ncount = 1e9\nstart = [0, 0, 0]\n");
    assert!(
        error.starts_with("test.toml:4:9: count = 1000000000 is out of range; valid range: 1 to 200000"),
        "{error}"
    );
    // Ten thousand is fine.
    let scene =
        load("[scene]\nname = \"t\"\n[[grid]]\nrows = 100\ncols = 100\nlink = \"spring\"\nk = 10\n").unwrap();
    assert_eq!(scene.world().particles.len(), 10_000);
}

#[test]
fn the_command_line_takes_exactly_one_of_scene_and_scene_file() {
    let one_line = |out: &Output| {
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        stderr
    };
    let both = run(&["simulate", "--scene", "bridge", "--scene-file", "assets/scenes/chain.toml"]);
    assert_eq!(
        one_line(&both).trim_end(),
        "particle-lab: give either --scene NAME or --scene-file PATH, not both"
    );
    let neither = run(&["render", "--out", "x.png"]);
    assert!(one_line(&neither).contains("--scene-file PATH"));
    let missing = run(&["simulate", "--scene-file", "no/such.toml"]);
    assert_eq!(one_line(&missing).trim_end(), "particle-lab: no/such.toml: cannot read it: no such file");

    let dir = scratch_dir("cli");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[scene]\nname = \"bad\"\n[[particle]]\nposition = [0, \"h\", 0]\n").unwrap();
    let out = run(&["simulate", "--scene-file", bad.to_str().unwrap()]);
    let stderr = one_line(&out);
    assert!(
        stderr.starts_with(&format!("particle-lab: {}:4:17: in the expression \"h\"", bad.display())),
        "{stderr}"
    );
    let out =
        run(&["render", "--scene-file", bad.to_str().unwrap(), "--out", dir.join("x.png").to_str().unwrap()]);
    assert!(one_line(&out).contains(":4:17:"));
    // A shipped scene by name, as a compiled one.
    let out = run(&["simulate", "--scene", "cloth", "--steps", "1", "--set", "cells=4"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn a_file_scene_gives_its_source_text_and_path() {
    let dir = scratch_dir("source");
    let path = dir.join("one.toml");
    let text = "[scene]\nname = \"one\"\n[[particle]]\nposition = [0, 1, 0]\n";
    std::fs::write(&path, text).unwrap();
    let entry = file::load_path(&path).unwrap();
    let scene = scenes::build_entry(&entry, &[]).unwrap();
    let (source, from) = scene.source().unwrap();
    assert_eq!(source, text);
    assert_eq!(from, Some(path.as_path()));
    assert!(scenes::build("bridge", &[]).unwrap().source().is_none());
}

/// Polls the lab as the window does each frame until `done` or 10 s pass.
fn poll_until(lab: &mut Lab, done: impl Fn(&Lab) -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(10) {
        lab.poll_scene_file();
        if done(lab) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    false
}

#[test]
fn an_edited_file_reloads_keeping_the_camera_and_a_bad_edit_keeps_the_scene() {
    let dir = scratch_dir("reload");
    let path = dir.join("row.toml");
    let text = |count: &str| {
        format!(
            "[scene]\nname = \"row\"\n[[param]]\nname = \"gap\"\ndefault = 0.5\nmin = 0.1\nmax = 2\n\
             [[row]]\ncount = {count}\nstart = [0, 1, 0]\nstep = [\"gap\", 0, 0]\n"
        )
    };
    std::fs::write(&path, text("3")).unwrap();
    let entry = file::load_path(&path).unwrap();
    let mut lab = Lab::from_entry(&entry, &["gap=0.8".into()], SolverSettings::default()).unwrap();
    lab.watch_scene_file();
    lab.camera.distance = 42.0;
    std::thread::sleep(Duration::from_millis(100));

    std::fs::write(&path, text("5")).unwrap();
    assert!(poll_until(&mut lab, |lab| lab.scene.world().particles.len() == 5), "the edit was not reloaded");
    assert_eq!(lab.camera.distance, 42.0, "the camera stays");
    assert_eq!(lab.scene.params().get("gap"), 0.8, "the slider's value stays");
    assert_eq!(lab.scene.world().particles.positions()[4].x, 3.2);

    std::fs::write(&path, text("\"5 +\"")).unwrap();
    assert!(poll_until(&mut lab, |lab| !lab.status.is_empty() && !lab.status.starts_with("Reloaded")));
    assert_eq!(
        lab.status,
        format!(
            "{}:9:13: in the expression \"5 +\": expected a number, a parameter name or '(', found the end",
            path.display()
        )
    );
    assert_eq!(lab.scene.world().particles.len(), 5, "the running scene stays");

    // Opening another file from the File menu; a missing one leaves the scene.
    assert!(!lab.open_scene_file(Path::new("no/such.toml")));
    assert_eq!(lab.status, "no/such.toml: cannot read it: no such file");
    assert_eq!(lab.scene.world().particles.len(), 5);
}

/// Every shipped file, by name, with its text.
fn shipped() -> Vec<(&'static str, &'static str)> {
    file::SHIPPED.to_vec()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn truncated_and_mutated_files_load_or_give_one_line(
        which in 0usize..4,
        cut in 0.0f64..1.0,
        edits in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 0..6),
    ) {
        let (name, text) = shipped()[which];
        let mut bytes = text.as_bytes().to_vec();
        bytes.truncate(((bytes.len() as f64) * (0.2 + 0.8 * cut)) as usize);
        for (at, byte) in edits {
            if bytes.is_empty() { break; }
            let k = ((bytes.len() as f64 * at) as usize).min(bytes.len() - 1);
            // Printable ASCII, digits and the characters TOML cares about most.
            const CHARS: &[u8] = b"0123456789.-+=[]\"',#\n abcxyz_";
            bytes[k] = CHARS[usize::from(byte) % CHARS.len()];
        }
        let text = String::from_utf8_lossy(&bytes).to_string();
        match file::load_text(&text, name, None) {
            Ok(entry) => {
                let scene = scenes::build_entry(&entry, &[]).unwrap();
                prop_assert!(scene.world().particles.len() <= file::MAX_PARTICLES);
            }
            Err(error) => {
                let line = error.to_string();
                prop_assert_eq!(line.lines().count(), 1, "{}", line);
                prop_assert!(line.starts_with(name), "{}", line);
            }
        }
    }
}

// Reference images ---------------------------------------------------------------

const SIZE: [u32; 2] = [400, 300];
const CHANNEL_TOLERANCE: u8 = 24;
const PIXEL_TOLERANCE: f64 = 0.005;

/// Renders a shipped scene after `steps` and compares it with `tests/golden/NAME.png`
/// (`UPDATE_GOLDEN=1` rewrites it; a mismatch writes `-actual` and `-difference`).
fn matches_golden(capture: &mut FrameCapture, scene: &str, set: &[&str], steps: u64, golden: &str) {
    let set: Vec<String> = set.iter().map(|s| (*s).to_string()).collect();
    let mut lab = Lab::new(scene, &set).unwrap();
    lab.run_steps_recorded(steps);
    let actual = capture.render(&mut lab, SIZE, false).unwrap();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let reference = dir.join(format!("{golden}.png"));
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        write_png(&reference, SIZE, &actual).unwrap();
        return;
    }
    let (expected, size) = read_png(&reference).unwrap_or_else(|e| panic!("{e}; UPDATE_GOLDEN=1 makes it"));
    assert_eq!(size, SIZE);
    let mut difference = Vec::with_capacity(actual.len());
    let mut different = 0usize;
    for (a, e) in actual.chunks_exact(4).zip(expected.chunks_exact(4)) {
        if a.iter().zip(e).take(3).any(|(x, y)| x.abs_diff(*y) > CHANNEL_TOLERANCE) {
            different += 1;
        }
        difference.extend((0..3).map(|c| a[c].abs_diff(e[c]).saturating_mul(4)));
        difference.push(255);
    }
    let share = different as f64 / f64::from(SIZE[0] * SIZE[1]);
    if share > PIXEL_TOLERANCE {
        write_png(&dir.join(format!("{golden}-actual.png")), SIZE, &actual).unwrap();
        write_png(&dir.join(format!("{golden}-difference.png")), SIZE, &difference).unwrap();
        panic!("{golden}: {:.2}% of pixels differ from {}", share * 100.0, reference.display());
    }
}

#[test]
fn every_shipped_scene_file_matches_its_reference_image() {
    let mut capture =
        FrameCapture::new().unwrap_or_else(|e| panic!("headless rendering needs a GPU adapter: {e}"));
    matches_golden(&mut capture, "chain", &[], 240, "file-chain");
    matches_golden(&mut capture, "cloth", &[], 480, "file-cloth");
    matches_golden(&mut capture, "cloth", &["tear=10"], 200, "file-cloth-torn");
    matches_golden(&mut capture, "platform", &[], 300, "file-platform");
    matches_golden(&mut capture, "blob", &[], 165, "file-blob");

    // The same through the command line, from the file.
    let out = std::env::temp_dir().join(format!("particle-lab-scene-file-{}.png", std::process::id()));
    let run = run(&[
        "render",
        "--scene-file",
        "assets/scenes/blob.toml",
        "--steps",
        "3",
        "--size",
        "64x48",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(String::from_utf8_lossy(&run.stdout).contains("64x48, blob after 3 steps"));
    assert_eq!(read_png(&out).unwrap().1, [64, 48]);
}

#[test]
fn an_edited_default_takes_effect_on_reload() {
    let dir = scratch_dir("default");
    let path = dir.join("n.toml");
    let text = |n: u32| {
        format!(
            "[scene]\nname = \"n\"\n[[param]]\nname = \"n\"\ndefault = {n}\nmin = 1\nmax = 9\n\
             [[row]]\ncount = \"n\"\nstart = [0, 1, 0]\n"
        )
    };
    std::fs::write(&path, text(3)).unwrap();
    let mut lab = Lab::from_entry(&file::load_path(&path).unwrap(), &[], SolverSettings::default()).unwrap();
    lab.watch_scene_file();
    std::thread::sleep(Duration::from_millis(100));
    std::fs::write(&path, text(4)).unwrap();
    assert!(
        poll_until(&mut lab, |lab| lab.scene.world().particles.len() == 4),
        "the new default was not taken"
    );
    assert_eq!(lab.scene.params().get("n"), 4.0);
}

/// A small fixed-seed generator, so the soak is the same every run.
fn lcg(state: &mut u64) -> f32 {
    *state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
    (*state >> 40) as f32 / (1u64 << 24) as f32
}

/// Steps every shipped scene, changing a parameter at random (within its slider's
/// range) every 50 steps; fails on an error or a non-finite state.
fn soak(steps: u32) {
    let mut seed = 7;
    for entry in file::shipped() {
        let mut scene = entry.create_default();
        let params = &entry.info().params;
        for step in 0..steps {
            if step % 50 == 0 {
                let p = &params[(lcg(&mut seed) * params.len() as f32) as usize % params.len()];
                let value = p.min + (p.max - p.min) * lcg(&mut seed);
                // A whole-number parameter's slider moves in whole numbers.
                let value = if p.integer { value.round() } else { value };
                scene.set_param(&p.name, value).unwrap_or_else(|e| panic!("{}: {e}", entry.info().name));
            }
            scene.step(entry.info().dt).unwrap();
            assert!(scene.world().is_finite(), "{} went non-finite at step {step}", entry.info().name);
        }
    }
}

#[test]
fn shipped_scenes_stay_finite_with_parameters_changed_at_random() {
    soak(3000);
}

/// The issue's soak: 100,000 steps a scene (minutes; `-- --ignored` runs it).
#[test]
#[ignore]
fn shipped_scenes_survive_the_long_soak() {
    soak(100_000);
}

#[test]
fn every_kind_of_link_force_and_contact_can_be_declared() {
    let text = r#"
[scene]
name = "kinds"

[[particle]]
name = "a"
position = [0, 2, 0]
[[particle]]
name = "b"
position = [1, 2, 0]
[[particle]]
name = "float"
position = [3, 0.5, 0]
radius = 0.2

[[link]]
kind = "rod"
a = "a"
b = "b"
[[link]]
kind = "cable"
a = "a"
b = "b"
length = 1.5
restitution = 0.5
[[link]]
kind = "spring"
a = "a"
b = "b"
k = 10
length = 0.5
[[link]]
kind = "bungee"
a = "a"
b = "b"
k = 10
[[link]]
kind = "rod"
a = "a"
anchor = [0, 3, 0]
[[link]]
kind = "cable"
a = "b"
anchor = [1, 3.5, 0]
[[link]]
kind = "stiff_spring"
a = "float"
anchor = [3, 1, 0]
k = 1e6
damping_ratio = 0.5

[[drag]]
k1 = 0.1
k2 = 0.01
targets = ["a", 1]

[[buoyancy]]
particle = "float"
surface = 0.5
half_height = 0.2
volume = 0.02

[ground]
height = -1

[[wall]]
normal = [1, 0, 0]
point = [-4, 0, 0]

[collisions]
restitution = 0.2
"#;
    let mut scene = load(text).unwrap();
    let mut kinds: Vec<&str> = scene.world().links().iter().map(|l| l.spec.kind.name()).collect();
    kinds.sort_unstable();
    assert_eq!(kinds, ["bungee", "cable", "rod", "spring", "stiff_spring", "support_cable", "support_rod"]);
    // Drag, buoyancy, two springs and the stiff spring are forces.
    assert_eq!(scene.world().forces.len(), 5);
    let water = scene.water().expect("buoyancy draws its water");
    assert_eq!(water.height, 0.5);
    for _ in 0..240 {
        scene.step(1.0 / 240.0).unwrap();
    }
    assert!(scene.world().is_finite());
    // The stiff spring holds the float near its anchor against its weight and buoyancy.
    let float = scene.world().particles.positions()[2];
    assert!((float - glam::Vec3::new(3.0, 1.0, 0.0)).length() < 0.01, "float at {float}");

    let error = load_err(
        "[scene]\nname = \"t\"\n[[particle]]\nposition = [0, 0, 0]\n[[link]]\nkind = \"stiff_spring\"\na = 0\nb = 0\nk = 5\n",
    );
    assert_eq!(error, "test.toml:8:5: a stiff spring joins a particle to an `anchor`, not to `b`");
}

#[test]
fn a_value_the_file_cannot_be_built_with_is_refused_and_the_scene_stays() {
    let text = "[scene]\nname = \"t\"\n[[param]]\nname = \"m\"\ndefault = 3\nmin = 0\nmax = 5\n\
                [[particle]]\nposition = [0, 1, 0]\nmass = \"m - 1\"\n";
    let mut scene = load(text).unwrap();
    scene.step(1.0 / 240.0).unwrap();
    let error = scene.set_param("m", 0.5).unwrap_err().to_string();
    assert_eq!(
        error,
        "'m' cannot take that value: test.toml:10:8: mass = -0.5 is out of range; valid range: 1e-9 to 1e12 kg"
    );
    assert_eq!((scene.params().get("m"), scene.world().steps()), (3.0, 1), "nothing changed");
    assert_eq!(scene.world().particles.mass(0), 2.0);
    let entry = file::load_text(text, "test.toml", None).unwrap();
    let error = scenes::build_entry(&entry, &["m=0.5".into()]).err().unwrap();
    assert_eq!(error, "test.toml:10:8: mass = -0.5 is out of range; valid range: 1e-9 to 1e12 kg");
}

/// `[scene] solver`, `substeps` and `integrator` (issue 38: the scene's own solver):
/// `simulate` runs a file that names them as the same file without them with the flags
/// typed; a flag typed wins over the file; the window's lab takes them on opening the
/// file; bad values get one line at their place.
#[test]
fn a_scene_files_own_solver_runs_as_the_flags_would_and_a_flag_typed_wins() {
    let dir = scratch_dir("own-solver");
    let body = "[[row]]\ncount = 4\nstart = [0, 2, 0]\nstep = [0.3, 0, 0]\nlink = \"rod\"\npin = [0]\n";
    let plain = dir.join("plain.toml");
    std::fs::write(&plain, format!("[scene]\nname = \"swing\"\n{body}")).unwrap();
    let own = dir.join("own.toml");
    std::fs::write(
        &own,
        format!("[scene]\nname = \"swing\"\nsolver = \"paper\"\nsubsteps = 8\nintegrator = \"rk4\"\n{body}"),
    )
    .unwrap();
    let last_hash = |args: &[&str]| -> String {
        let out = run(&[&["simulate", "--steps", "300", "--every", "300"], args].concat());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8(out.stdout).unwrap();
        let json: serde_json::Value = serde_json::from_str(text.lines().last().unwrap()).unwrap();
        json["hash"].as_str().expect("a hash").to_string()
    };
    let (plain, own) = (plain.to_str().unwrap(), own.to_str().unwrap());
    let flagged =
        last_hash(&["--scene-file", plain, "--solver", "paper", "--substeps", "8", "--integrator", "rk4"]);
    assert_eq!(last_hash(&["--scene-file", own]), flagged, "the file's own solver");
    assert_ne!(last_hash(&["--scene-file", plain]), flagged, "the solver makes a difference here");
    // A flag typed is laid over the file's choice.
    assert_eq!(
        last_hash(&["--scene-file", own, "--integrator", "verlet"]),
        last_hash(&["--scene-file", plain, "--solver", "paper", "--substeps", "8", "--integrator", "verlet"])
    );
    // The window's lab, opening the file, runs with it and shows it.
    let mut lab = Lab::new("projectile", &[]).unwrap();
    assert!(lab.open_scene_file(Path::new(own)));
    let solver = lab.solver();
    assert_eq!(
        (solver.kind, solver.substeps, solver.integrator),
        (particle_lab::physics::SolverKind::Paper, 8, particle_lab::physics::Integrator::Rk4)
    );
    assert_eq!(*lab.scene.world().solver(), solver);
    // Written back, the keys stay.
    let text = file::written(&lab.entry, lab.scene.params()).unwrap();
    assert!(text.contains("solver = \"paper\"\nsubsteps = 8\nintegrator = \"rk4\""), "{text}");
    // Bad values, at their place.
    let error = load_err("[scene]\nname = \"t\"\nsolver = \"fast\"\n");
    assert_eq!(error, "test.toml:3:10: unknown solver 'fast'; valid solvers: soft, paper");
    let error = load_err("[scene]\nname = \"t\"\nsubsteps = 0\n");
    assert_eq!(error, "test.toml:3:12: substeps = 0 is out of range; valid range: 1 to 64");
    let error = load_err("[scene]\nname = \"t\"\nintegrator = \"euler\"\n");
    assert!(error.starts_with("test.toml:3:14: unknown integrator 'euler'"), "{error}");
}

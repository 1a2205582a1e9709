//! The `scenes` and `simulate` commands of the real binary.

use std::process::{Command, Output};

use serde_json::Value;

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_particle-lab")).args(args).output().expect("binary runs")
}

fn json_lines(output: &Output) -> Vec<Value> {
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|line| serde_json::from_str(line).unwrap_or_else(|e| panic!("bad JSON line {line}: {e}")))
        .collect()
}

#[test]
fn scenes_lists_every_scene_in_text_and_json() {
    let text = run(&["scenes"]);
    assert!(text.status.success());
    let text = String::from_utf8_lossy(&text.stdout);
    for name in [
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
    ] {
        assert!(text.contains(name), "{name} missing from:\n{text}");
    }
    let json = run(&["scenes", "--format", "json"]);
    assert!(json.status.success());
    let list: Value = serde_json::from_slice(&json.stdout).unwrap();
    let list = list.as_array().unwrap();
    assert_eq!(list.len(), 12, "eight compiled scenes and four shipped files");
    let projectile = list.iter().find(|s| s["name"] == "projectile").unwrap();
    let g = projectile["params"].as_array().unwrap().iter().find(|p| p["name"] == "g").unwrap();
    assert_eq!(g["default"], 9.81, "Earth's g (issue 37)");
    assert_eq!(g["unit"], "m/s²");
    assert!(projectile["dt"].as_f64().unwrap() > 0.0);
    for name in ["speed", "angle", "mass", "damping", "height"] {
        assert!(projectile["params"].as_array().unwrap().iter().any(|p| p["name"] == name), "no {name}");
    }
}

#[test]
fn simulate_prints_the_documented_schema() {
    let out = run(&["simulate", "--scene", "bridge", "--steps", "10", "--every", "4"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let lines = json_lines(&out);
    let steps: Vec<u64> = lines.iter().map(|l| l["step"].as_u64().unwrap()).collect();
    assert_eq!(steps, vec![0, 4, 8, 10], "step 0, every 4th, and the last");
    let first = &lines[0];
    assert_eq!(first["t"], 0.0);
    let particles = first["particles"].as_array().unwrap();
    assert_eq!(particles.len(), 12);
    assert_eq!(particles[0]["id"], 0);
    assert_eq!(particles[0]["p"].as_array().unwrap().len(), 3);
    assert_eq!(particles[0]["v"].as_array().unwrap().len(), 3);
    // Radius and mass, so the state can be rebuilt elsewhere: the bridge's deck
    // particles are 0.2 m and 1 kg plus their share of the 10 kg load.
    assert!((particles[0]["r"].as_f64().unwrap() - 0.2).abs() < 1e-6, "{}", particles[0]);
    let total: f64 = particles.iter().map(|p| p["m"].as_f64().unwrap()).sum();
    assert!((total - 22.0).abs() < 1e-3, "12 x 1 kg + 10 kg load, got {total}");
    let links = first["links"].as_array().unwrap();
    let count = |kind: &str| links.iter().filter(|l| l["kind"] == kind).count();
    assert_eq!((count("rod"), count("cable"), count("support_cable")), (6, 10, 12));
    let rod = links.iter().find(|l| l["kind"] == "rod").unwrap();
    assert_eq!(rod["rest"], 2.0);
    assert!((rod["length"].as_f64().unwrap() - 2.0).abs() < 1e-6);
    assert!(rod["b"].is_u64());
    let support = links.iter().find(|l| l["kind"] == "support_cable").unwrap();
    assert!(support["b"].is_null(), "anchored links have b = null");
    assert!(first["energy"]["kinetic"].is_number() && first["energy"]["potential"].is_number());
    let last_t = lines[3]["t"].as_f64().unwrap();
    assert!((last_t - 10.0 / 240.0).abs() < 1e-6, "t = {last_t}");
}

#[test]
fn simulate_spring_forces_lists_every_spring_kind() {
    let out = run(&["simulate", "--scene", "springForces", "--steps", "1"]);
    assert!(out.status.success());
    let lines = json_lines(&out);
    let kinds: Vec<&str> =
        lines[0]["links"].as_array().unwrap().iter().map(|l| l["kind"].as_str().unwrap()).collect();
    for kind in ["spring", "bungee", "stiff_spring"] {
        assert!(kinds.contains(&kind), "{kind} missing: {kinds:?}");
    }
}

/// Straight up at 10 m/s under 10 m/s² for 1 s in steps of 0.01 s with the given solver
/// flags; returns (step-0 velocity, height at the end).
fn straight_up(solver: &[&str]) -> (serde_json::Value, f64) {
    let mut args = vec![
        "simulate",
        "--scene",
        "projectile",
        "--set",
        "speed=10",
        "--set",
        "angle=90",
        "--set",
        "g=10",
        "--set",
        "damping=1",
        "--dt",
        "0.01",
        "--steps",
        "100",
        "--every",
        "100",
    ];
    args.extend_from_slice(solver);
    let out = run(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let lines = json_lines(&out);
    (lines[0]["particles"][0]["v"].clone(), lines[1]["particles"][0]["p"][1].as_f64().unwrap())
}

#[test]
fn simulate_applies_set_and_dt() {
    // Semi-implicit Euler's closed form after m steps of h: y0 + v0 m h - g h² m(m+1)/2.
    let closed_form = |h: f64, m: f64| 1.5 + 10.0 * m * h - 10.0 * h * h * m * (m + 1.0) / 2.0;
    let (v0, y) = straight_up(&["--solver", "paper"]);
    assert!(v0[0].as_f64().unwrap().abs() < 1e-5 && (v0[1].as_f64().unwrap() - 10.0).abs() < 1e-5);
    assert!((y - closed_form(0.01, 100.0)).abs() < 1e-3, "paper: y {y}");
    // The soft solver integrates in substeps: 4 of 0.0025 s per step by default, 8 here.
    let (_, y) = straight_up(&[]);
    assert!((y - closed_form(0.0025, 400.0)).abs() < 1e-3, "soft: y {y}");
    let (_, y) = straight_up(&["--solver", "soft", "--substeps", "8"]);
    assert!((y - closed_form(0.00125, 800.0)).abs() < 1e-3, "soft, 8 substeps: y {y}");
}

#[test]
fn simulate_uses_the_integrator_asked_for() {
    // Under a constant force Verlet and RK4 are exact: 1.5 + 10 t - 5 t² = 6.5 m at 1 s,
    // where semi-implicit Euler is 0.05 m low (paper solver, h = 0.01 s) and explicit
    // Euler 0.05 m high.
    for (name, expected) in
        [("verlet", 6.5), ("rk4", 6.5), ("semi-implicit-euler", 6.45), ("explicit-euler", 6.55)]
    {
        let (_, y) = straight_up(&["--solver", "paper", "--integrator", name]);
        assert!((y - expected).abs() < 1e-3, "{name}: y {y}, expected {expected}");
    }
}

#[test]
fn bad_solver_flags_get_one_line() {
    assert_usage_error(
        &["simulate", "--scene", "bridge", "--solver", "pgs"],
        &["unknown solver 'pgs'", "soft, paper"],
    );
    assert_usage_error(&["simulate", "--scene", "bridge", "--substeps", "0"], &["--substeps 0", "1 to 64"]);
    assert_usage_error(
        &["render", "--scene", "bridge", "--substeps", "65", "--out", "x.png"],
        &["--substeps 65"],
    );
    assert_usage_error(&["--solver", "nope"], &["unknown solver 'nope'"]);
    assert_usage_error(
        &["simulate", "--scene", "bridge", "--integrator", "leapfrog"],
        &["unknown integrator 'leapfrog'", "explicit-euler, semi-implicit-euler, verlet, rk4"],
    );
    assert_usage_error(
        &["render", "--scene", "bridge", "--integrator", "x", "--out", "x.png"],
        &["integrator"],
    );
}

fn assert_usage_error(args: &[&str], expected: &[&str]) {
    let out = run(args);
    assert_eq!(out.status.code(), Some(2), "{args:?} should exit 2");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: one line, got:\n{stderr}");
    assert!(stderr.starts_with("particle-lab: "), "{args:?}: no prefix: {stderr}");
    assert_no_source_paths(&stderr);
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    for word in expected {
        assert!(stderr.contains(word), "{args:?}: '{word}' not in: {stderr}");
    }
    assert!(out.stdout.is_empty(), "{args:?} printed to stdout");
}

#[test]
fn bad_input_gets_one_line_and_exit_code_2() {
    assert_usage_error(&["simulate", "--scene", "nope"], &["nope", "projectile", "springForces", "bridge"]);
    assert_usage_error(
        &["simulate", "--scene", "bridge", "--set", "bogus=1"],
        &["bogus", "load_x", "load_mass"],
    );
    assert_usage_error(&["simulate", "--scene", "bridge", "--set", "g=abc"], &["abc", "g"]);
    assert_usage_error(&["simulate", "--scene", "bridge", "--set", "g=NaN"], &["NaN"]);
    assert_usage_error(&["simulate", "--scene", "bridge", "--set", "g=inf"], &["inf"]);
    assert_usage_error(&["simulate", "--scene", "bridge", "--set", "g=1000"], &["1000", "0", "30"]);
    assert_usage_error(&["simulate", "--scene", "bridge", "--set", "g"], &["KEY=VALUE"]);
    assert_usage_error(&["simulate", "--scene", "bridge", "--dt", "0"], &["--dt"]);
    assert_usage_error(&["simulate", "--scene", "bridge", "--dt", "-1"], &["--dt"]);
    assert_usage_error(&["simulate", "--scene", "bridge", "--steps", "ten"], &["ten"]);
    assert_usage_error(&["simulate", "--scene", "bridge", "--every", "0"], &["--every"]);
    assert_usage_error(&["simulate"], &["--scene"]);
    assert_usage_error(&["scenes", "--format", "xml"], &["xml"]);
    assert_usage_error(&["frobnicate"], &["frobnicate"]);
}

#[test]
fn scene_names_forgive_case_and_dashes() {
    let out = run(&["simulate", "--scene", "spring-forces", "--steps", "1"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn a_run_that_blows_up_fails_clearly_instead_of_printing_null() {
    // ω·dt = sqrt(500/0.1) * 0.1 ≈ 7: the explicit springs explode.
    let out = run(&[
        "simulate",
        "--scene",
        "springForces",
        "--set",
        "k=500",
        "--set",
        "mass=0.1",
        "--dt",
        "0.1",
        "--steps",
        "200",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("blew up") && stderr.contains("--dt"), "{stderr}");
    for line in json_lines(&out) {
        for particle in line["particles"].as_array().unwrap() {
            let numbers = particle["p"].as_array().unwrap().iter().chain(particle["v"].as_array().unwrap());
            assert!(numbers.clone().all(Value::is_number), "printed a non-finite state: {particle}");
        }
    }
}

#[test]
fn simulate_writes_csv_with_the_same_numbers_as_json() {
    let base = ["simulate", "--scene", "bridge", "--steps", "30", "--every", "10"];
    let csv = run(&[&base[..], &["--format", "csv"]].concat());
    assert!(csv.status.success(), "{}", String::from_utf8_lossy(&csv.stderr));
    let text = String::from_utf8(csv.stdout.clone()).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("step,t,id,x,y,z,vx,vy,vz,r,m,kinetic,potential,dissipated,constraint,work,removed,error")
    );
    let rows: Vec<Vec<f64>> =
        lines.map(|l| l.split(',').map(|field| field.parse::<f64>().unwrap_or(f64::NAN)).collect()).collect();
    // The bridge has 12 particles; steps 0, 10, 20 and 30 are printed.
    assert_eq!(rows.len(), 12 * 4);
    assert!(rows.iter().all(|r| r.len() == 18));
    let json = json_lines(&run(&base));
    let last = &json[3];
    let row = rows.iter().find(|r| r[0] == 30.0 && r[2] == 5.0).unwrap();
    let particle = last["particles"].as_array().unwrap().iter().find(|p| p["id"] == 5).unwrap();
    for axis in 0..3 {
        assert_eq!(row[3 + axis], particle["p"][axis].as_f64().unwrap(), "position of particle 5");
    }
    assert_eq!(row[13], last["energy"]["dissipated"].as_f64().unwrap());
    assert_eq!(row[14], last["energy"]["constraint"].as_f64().unwrap());
    assert_eq!(row[16], last["energy"]["removed"].as_f64().unwrap());
    assert_eq!(row[17], last["energy"]["error"].as_f64().unwrap());
}

/// A message names no source file or crate path.
fn assert_no_source_paths(message: &str) {
    for sign in ["/src/", ".rs:", ".cargo", "/rustc/", "registry"] {
        assert!(!message.contains(sign), "'{sign}' in: {message}");
    }
}

#[test]
fn clap_errors_get_the_prefix_and_keep_their_suggestion() {
    assert_usage_error(
        &["simulate", "--sene", "bridge"],
        &["particle-lab: unexpected argument '--sene' found", "a similar argument exists: '--scene'"],
    );
    assert_usage_error(
        &["simulat", "--scene", "bridge"],
        &["unrecognized subcommand 'simulat'", "a similar subcommand exists: 'simulate'"],
    );
    assert_usage_error(
        &["render", "--scene", "bridge"],
        &["required arguments were not provided: --out <FILE>", "'particle-lab render --help'"],
    );
    assert_usage_error(
        &["scenes", "--format", "jsn"],
        &["invalid value 'jsn'", "text, json", "'particle-lab scenes --help'"],
    );
    assert_usage_error(
        &["render", "--scene", "bridge", "--frames", "many", "--out", "x.gif"],
        &["invalid value 'many' for '--frames <N>'"],
    );
    assert_usage_error(&["--steps", "3"], &["unexpected argument '--steps'"]);
}

#[test]
fn help_and_version_still_print_to_stdout_and_succeed() {
    let version = run(&["--version"]);
    assert_eq!(version.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&version.stdout).trim(),
        format!("particle-lab {}", env!("CARGO_PKG_VERSION"))
    );
    let help = run(&["render", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    let help = String::from_utf8_lossy(&help.stdout);
    for words in ["--frames <N>", "--every <K>", "run-0001.png", ".gif", ".apng"] {
        assert!(help.contains(words), "'{words}' not in render --help:\n{help}");
    }
    assert!(run(&["--help"]).stderr.is_empty());
}

/// An environment change: `(name, Some(value))` sets, `(name, None)` removes.
type Env<'a> = (&'a str, Option<&'a str>);

/// The binary with `args` and environment changes.
fn run_with(args: &[&str], env: &[Env]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_particle-lab"));
    command.args(args).env_remove("RUST_LOG");
    for (name, value) in env {
        match value {
            Some(value) => command.env(name, value),
            None => command.env_remove(name),
        };
    }
    command.output().expect("binary runs")
}

#[test]
fn failures_outside_the_command_line_say_so_in_our_words() {
    let no_display = [("DISPLAY", None), ("WAYLAND_DISPLAY", None), ("WAYLAND_SOCKET", None)];
    // The one line for `args` under `env`: its exit code and the words it must hold.
    let check = |args: &[&str], env: &[Env], code: i32, expected: &[&str]| {
        let out = run_with(args, env);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: one line, got:\n{stderr}");
        assert!(stderr.starts_with("particle-lab: "), "{args:?}: {stderr}");
        assert_no_source_paths(&stderr);
        for words in expected {
            assert!(stderr.contains(words), "{args:?}: '{words}' not in: {stderr}");
        }
    };
    check(&[], &no_display, 1, &["no display", "neither DISPLAY nor WAYLAND_DISPLAY is set", "Xvfb"]);
    check(
        &["--scene", "bridge"],
        &[("DISPLAY", Some(":1234567")), ("WAYLAND_DISPLAY", None)],
        1,
        &["the display DISPLAY=:1234567 does not answer", "Xvfb"],
    );
    check(
        &["render", "--scene", "bridge", "--size", "64x64", "--out", "x.png"],
        &[("VK_ICD_FILENAMES", Some("/nonexistent.json")), ("VK_DRIVER_FILES", Some("/nonexistent.json"))],
        1,
        &["no GPU adapter found", "mesa-vulkan-drivers and libvulkan1"],
    );
    check(&["render", "--scene", "bridge", "--frames", "2", "--out", "x.jpg"], &[], 2, &[".gif or .apng"]);
    check(&["simulate", "--scene", "bridge", "--every", "-3"], &[], 2, &["'-3'"]);
}

#[test]
fn simulate_prints_times_as_short_decimals() {
    // 1/240 s steps: step 5 is at 0.0208333 s (not 0.020833334419876337).
    let out = run(&["simulate", "--scene", "bridge", "--steps", "5"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let times: Vec<&str> =
        text.lines().map(|l| l.split("\"t\":").nth(1).unwrap().split(',').next().unwrap()).collect();
    assert_eq!(times, ["0.0", "0.0041667", "0.0083333", "0.0125", "0.0166667", "0.0208333"]);
    assert!(
        out.stderr.is_empty(),
        "piped, simulate prints nothing on stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A decimal --dt prints as typed, in CSV too.
    let csv = run(&["simulate", "--scene", "bridge", "--steps", "3", "--dt", "0.01", "--format", "csv"]);
    let text = String::from_utf8_lossy(&csv.stdout);
    let times: Vec<&str> = text.lines().skip(1).step_by(12).map(|l| l.split(',').nth(1).unwrap()).collect();
    assert_eq!(times, ["0", "0.01", "0.02", "0.03"]);
}

#[test]
fn a_json_line_is_readable_while_simulate_still_runs() {
    use std::io::BufRead;
    let mut child = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--scene", "pile", "--steps", "100000000", "--every", "1000000"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("binary runs");
    let mut line = String::new();
    std::io::BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    let state: Value = serde_json::from_str(&line).unwrap_or_else(|e| panic!("bad first line {line}: {e}"));
    assert_eq!(state["step"], 0);
    assert_eq!(state["particles"].as_array().unwrap().len(), 2000);
    assert!(running, "the first line arrived only when the run ended");
}

/// A scratch directory for one test's files.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn render_frames_writes_a_numbered_png_sequence() {
    let dir = scratch("sequence");
    let out = dir.join("run.png");
    let args = ["render", "--scene", "projectile", "--size", "96x64", "--steps", "10", "--frames", "4"];
    let result = run(&[&args[..], &["--every", "6", "--out", out.to_str().unwrap()]].concat());
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["run-0001.png", "run-0002.png", "run-0003.png", "run-0004.png"]);
    let frames: Vec<Vec<u8>> = names
        .iter()
        .map(|name| {
            let (pixels, size) = particle_lab::render::offscreen::read_png(&dir.join(name)).unwrap();
            assert_eq!(size, [96, 64], "{name}");
            pixels
        })
        .collect();
    assert_ne!(frames[0], frames[3], "the round moved between the first frame and the last");
    assert!(
        result.stderr.is_empty(),
        "no progress bar into a pipe: {}",
        String::from_utf8_lossy(&result.stderr)
    );
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(stdout.contains("4 frames") && stdout.contains("steps 10 to 28"), "{stdout}");
}

#[test]
fn render_frames_writes_a_gif_and_an_apng_timed_by_the_simulation() {
    let dir = scratch("animations");
    // 8 steps of 1/240 s: frames 1/30 s apart.
    let base =
        ["render", "--scene", "bridge", "--size", "80x48", "--steps", "0", "--frames", "5", "--every", "8"];
    let gif_path = dir.join("run.gif");
    let result = run(&[&base[..], &["--out", gif_path.to_str().unwrap()]].concat());
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(std::fs::File::open(&gif_path).unwrap()).unwrap();
    assert_eq!((decoder.width(), decoder.height()), (80, 48));
    let mut delays = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        delays.push(frame.delay);
    }
    // 3.33 hundredths a frame, the rounding carried: 3, 4, 3, 3, 4.
    assert_eq!(delays, [3, 4, 3, 3, 4], "five frames, 1/30 s apart");

    let apng_path = dir.join("run.apng");
    let result = run(&[&base[..], &["--out", apng_path.to_str().unwrap()]].concat());
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&apng_path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let control = reader.info().animation_control.expect("an animated PNG");
    assert_eq!((control.num_frames, control.num_plays), (5, 0), "five frames, looping");
    let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
    let mut frames = 0;
    while frames < 5 {
        let info = reader.next_frame(&mut buffer).unwrap();
        assert_eq!((info.width, info.height), (80, 48));
        let fctl = reader.info().frame_control.expect("each frame has its timing");
        assert_eq!((fctl.delay_num, fctl.delay_den), (1, 30), "frame {frames}");
        frames += 1;
    }
    assert!(reader.next_frame(&mut buffer).is_err(), "no sixth frame");
}

/// A private Xvfb display (no window manager), killed on drop.
struct VirtualDisplay {
    name: String,
    server: std::process::Child,
    /// One display at a time: two servers started together by tests running in
    /// parallel were seen to leave a test's app facing a display that had gone
    /// ("DISPLAY=:0 does not answer") once the other test ended its own.
    _serial: std::sync::MutexGuard<'static, ()>,
}

static ONE_DISPLAY_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

impl VirtualDisplay {
    /// Starts Xvfb and waits until its display answers; a server that does not within
    /// 10 s (seen once on a busy CI machine) is started again, up to three times.
    fn start() -> Self {
        use std::io::BufRead;
        // A test that failed holding the lock has let go of its display all the same.
        let serial = ONE_DISPLAY_AT_A_TIME.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        for _ in 0..3 {
            let mut server = Command::new("Xvfb")
                // -noreset: the server does not reset when its last client (our probe) leaves,
                // which could catch the app's connection mid-reset.
                .args(["-displayfd", "1", "-screen", "0", "1280x800x24", "-nolisten", "tcp", "-noreset"])
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::null())
                .spawn()
                .expect("Xvfb starts ('bash scripts/test.sh' installs it)");
            let mut number = String::new();
            std::io::BufReader::new(server.stdout.take().unwrap()).read_line(&mut number).unwrap();
            let name = format!(":{}", number.trim());
            let start = std::time::Instant::now();
            while start.elapsed().as_secs() < 10 {
                let probe = Command::new("xdotool")
                    .env("DISPLAY", &name)
                    .arg("getdisplaygeometry")
                    .output()
                    .is_ok_and(|o| o.status.success());
                if probe {
                    return Self { name, server, _serial: serial };
                }
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
            // Not answering: end this server (keeping the lock) and start another.
            let _ = server.kill();
            let _ = server.wait();
        }
        panic!("Xvfb did not answer, three times");
    }

    /// Starts the app that `command` builds (with DISPLAY set to this display and its
    /// stderr to `log`) and waits up to 60 s for its window; fails with its stderr if
    /// it exits first. A start that finds the display not answering while the display
    /// answers our probe (seen once on a loaded CI machine, the app's XOpenDisplay
    /// failing a moment after xdotool's succeeded) is tried again, up to three times:
    /// that is the test machine's X server, not what these tests check.
    fn open_window(&self, command: impl Fn() -> Command, log: &std::path::Path) -> std::process::Child {
        for attempt in 1..=3 {
            let mut app = command()
                .env("DISPLAY", &self.name)
                .stdout(std::process::Stdio::null())
                .stderr(std::fs::File::create(log).unwrap())
                .spawn()
                .unwrap();
            let start = std::time::Instant::now();
            loop {
                if self.has_window("^particle-lab$") {
                    return app;
                }
                if app.try_wait().unwrap().is_some() {
                    break;
                }
                assert!(start.elapsed().as_secs() < 60, "no window");
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
            let stderr = std::fs::read_to_string(log).unwrap();
            let flake = stderr.contains("does not answer") && self.answers() && attempt < 3;
            assert!(flake, "exited: {stderr}");
            eprintln!("the app found {} not answering (attempt {attempt}); starting it again", self.name);
        }
        unreachable!("returned or failed above")
    }

    fn answers(&self) -> bool {
        Command::new("xdotool")
            .env("DISPLAY", &self.name)
            .arg("getdisplaygeometry")
            .output()
            .is_ok_and(|o| o.status.success())
    }

    fn has_window(&self, title: &str) -> bool {
        Command::new("xdotool")
            .env("DISPLAY", &self.name)
            .args(["search", "--name", title])
            .output()
            .is_ok_and(|o| !o.stdout.is_empty())
    }
}

impl Drop for VirtualDisplay {
    fn drop(&mut self) {
        let _ = self.server.kill();
        let _ = self.server.wait();
    }
}

#[test]
fn the_window_is_quiet_when_nothing_is_wrong_and_names_the_driver_when_one_is() {
    let display = VirtualDisplay::start();
    let dir = scratch("window");
    let log = dir.join("stderr.txt");
    // No RUST_LOG, no XDG_RUNTIME_DIR: a server or CI machine without a login session.
    let mut app = display.open_window(
        || {
            let mut app = Command::new(env!("CARGO_BIN_EXE_particle-lab"));
            app.args(["--scene", "bridge"])
                .current_dir(&dir)
                .env_remove("WAYLAND_DISPLAY")
                .env_remove("RUST_LOG")
                .env_remove("XDG_RUNTIME_DIR");
            app
        },
        &log,
    );
    // Let it draw a few frames (the GPU is set up by then).
    std::thread::sleep(std::time::Duration::from_secs(2));
    assert!(app.try_wait().unwrap().is_none(), "exited: {}", std::fs::read_to_string(&log).unwrap());
    app.kill().unwrap();
    app.wait().unwrap();
    let stderr = std::fs::read_to_string(&log).unwrap();
    assert!(
        stderr.is_empty(),
        "a window left alone prints nothing (no XDG_RUNTIME_DIR lines, no info):\n{stderr}"
    );

    let out = run_with(
        &["--scene", "bridge"],
        &[
            ("DISPLAY", Some(&display.name)),
            ("WAYLAND_DISPLAY", None),
            ("VK_ICD_FILENAMES", Some("/nonexistent.json")),
            ("VK_DRIVER_FILES", Some("/nonexistent.json")),
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "said once:\n{stderr}");
    assert!(stderr.starts_with("particle-lab: no GPU adapter found"), "{stderr}");
    assert!(stderr.contains("mesa-vulkan-drivers and libvulkan1"), "{stderr}");
    assert_no_source_paths(&stderr);
}

#[test]
fn scenes_give_time_steps_as_the_rates_they_stand_for() {
    let text = run(&["scenes"]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("dt 1/240 s (240 Hz)"), "{text}");
    assert!(text.contains("dt 1/60 s (60 Hz)"), "the pile: {text}");
    let json = run(&["scenes", "--format", "json"]);
    let list: Value = serde_json::from_slice(&json.stdout).unwrap();
    let dt = |name: &str| list.as_array().unwrap().iter().find(|s| s["name"] == name).unwrap()["dt"].as_f64();
    assert_eq!(dt("projectile"), Some(1.0 / 240.0), "not the f32's 0.004166666883975267");
    assert_eq!(dt("pile"), Some(1.0 / 60.0));
}

#[test]
fn a_long_render_shows_progress_on_a_terminal_and_clears_it() {
    // `script` gives the command a terminal and prints what reached it.
    let dir = scratch("terminal");
    let command = format!(
        "'{}' render --scene bridge --size 320x200 --steps 0 --frames 150 --every 1 --out '{}'",
        env!("CARGO_BIN_EXE_particle-lab"),
        dir.join("run.png").display()
    );
    let out = Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .output()
        .expect("script (util-linux) runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let screen = String::from_utf8_lossy(&out.stdout);
    assert!(screen.contains("/149 steps"), "no progress bar on the terminal:\n{screen}");
    // The bar is wiped ("\r", erase line) before the summary.
    let last = screen.rsplit('\r').find(|part| !part.trim().is_empty()).unwrap_or("");
    assert!(last.trim_start_matches("\u{1b}[2K").starts_with("wrote "), "{last:?}");
}

/// The `t` of every line `simulate` printed, and of every CSV row.
fn times(output: &Output, csv: bool) -> Vec<f64> {
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let text = String::from_utf8_lossy(&output.stdout);
    if csv {
        text.lines().skip(1).map(|l| l.split(',').nth(1).unwrap().parse().unwrap()).collect()
    } else {
        json_lines(output).iter().map(|l| l["t"].as_f64().unwrap()).collect()
    }
}

/// Issue 17, finding 8: continued at another rate, `simulate --from` prints the
/// world's own time, in JSON and CSV alike (it printed 0.2, 0.3 for a world at 0.154,
/// 0.254 with `--dt 0.1`, and 0, 1, 2 with `--dt 1`).
#[test]
fn simulate_from_at_another_rate_prints_the_worlds_own_time() {
    let dir = scratch("other-rate");
    let start = dir.join("start.json");
    let start = start.to_str().unwrap();
    // The pendulum keeps its particles (a round at 1 s steps leaves the scene and the CSV).
    let saved = run(&["simulate", "--scene", "pendulum", "--steps", "37", "--every", "100", "--save", start]);
    assert!(saved.status.success(), "{}", String::from_utf8_lossy(&saved.stderr));
    let world_time = |path: &str| {
        let snapshot: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        snapshot["world"]["time"].as_f64().unwrap()
    };
    let t0 = world_time(start);
    assert!((t0 - 37.0 / 240.0).abs() < 1e-6, "{t0}");
    for dt in ["0.1", "1"] {
        let end = dir.join(format!("end-{dt}.json"));
        let end = end.to_str().unwrap();
        let args = ["simulate", "--from", start, "--dt", dt, "--steps", "2", "--save", end];
        let json = times(&run(&args), false);
        let t_end = world_time(end);
        let step: f64 = dt.parse().unwrap();
        assert_eq!(json.len(), 3, "{json:?}");
        for (i, t) in json.iter().enumerate() {
            let world = t0 + step * i as f64;
            assert!((t - world).abs() < 1e-6, "--dt {dt}: line {i} says t = {t}; the world is at {world}");
        }
        assert!(
            (json[2] - t_end).abs() < 1e-6,
            "--dt {dt}: the last t {} is not the world's {t_end}",
            json[2]
        );
        let csv = times(&run(&[&args[..7], &["--format", "csv"]].concat()), true);
        let mut rows: Vec<f64> = csv.clone();
        rows.dedup();
        assert_eq!(rows, json, "--dt {dt}: CSV and JSON print the same times");
    }
    // At the rate it was saved at, the lines still read as an unbroken run's.
    let same = run(&["simulate", "--from", start, "--steps", "3"]);
    let text = String::from_utf8_lossy(&same.stdout);
    let printed: Vec<&str> =
        text.lines().map(|l| l.split("\"t\":").nth(1).unwrap().split(',').next().unwrap()).collect();
    assert_eq!(printed, ["0.1541667", "0.1583333", "0.1625", "0.1666667"]);
}

/// Issue 17, finding 10: a world that blows up makes `render` exit 1, as `simulate`
/// does, with the frame still written to show where it stopped.
#[test]
fn render_exits_1_when_the_world_blows_up_as_simulate_does() {
    let dir = scratch("render-blow-up");
    // ω·dt = sqrt(500/0.1) * 0.1 ≈ 7: the explicit springs explode within 200 steps.
    let hot = dir.join("hot.json");
    let hot = hot.to_str().unwrap();
    let saved = run(&[
        "simulate",
        "--scene",
        "springForces",
        "--set",
        "k=500",
        "--set",
        "mass=0.1",
        "--dt",
        "0.1",
        "--steps",
        "1",
        "--save",
        hot,
    ]);
    assert!(saved.status.success(), "{}", String::from_utf8_lossy(&saved.stderr));
    let out = dir.join("blow.png");
    let result =
        run(&["render", "--from", hot, "--steps", "200", "--size", "64x48", "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "stderr: {stderr}");
    assert!(stderr.contains("blew up") && stderr.contains("stopped at step"), "{stderr}");
    assert!(out.exists(), "the frame is written");
}

/// Issue 17, finding 10: a recording stopped part way leaves nothing at `--out`; it is
/// written beside it and renamed there when complete.
#[test]
fn an_interrupted_recording_leaves_no_partial_file_at_out() {
    for extension in ["gif", "apng"] {
        let dir = scratch(&format!("interrupted-{extension}"));
        let out = dir.join(format!("run.{extension}"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
            .args(["render", "--scene", "bridge", "--size", "320x240", "--steps", "0", "--frames", "10000"])
            .args(["--every", "8", "--out", out.to_str().unwrap()])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // Until the recording has started writing, then stop it as Ctrl-C would.
        let started = std::time::Instant::now();
        let written = |dir: &std::path::Path| {
            std::fs::read_dir(dir).unwrap().any(|e| e.unwrap().metadata().unwrap().len() > 1000)
        };
        while !written(&dir) && started.elapsed().as_secs() < 60 {
            assert!(child.try_wait().unwrap().is_none(), "{extension}: the recording ended early");
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        assert!(written(&dir), "{extension}: nothing written in 60 s");
        child.kill().unwrap();
        child.wait().unwrap();
        assert!(!out.exists(), "{extension}: a partial recording was left at --out");
        // Finished, the same recording is at --out and nothing is left beside it.
        let result = run(&[
            "render",
            "--scene",
            "bridge",
            "--size",
            "80x48",
            "--steps",
            "0",
            "--frames",
            "3",
            "--every",
            "8",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.contains(&format!("run.{extension}")), "{names:?}");
        assert_eq!(
            names,
            [format!("run.{extension}")],
            "the killed run's temporary file was replaced and renamed"
        );
    }
}

/// Issue 17, finding 7: whatever part of the program refuses a typed value, the line
/// that says so stays one line: a newline or an escape typed into a name is shown as
/// an escape, not echoed raw.
#[test]
fn typed_control_characters_never_break_the_one_line_rule() {
    let dir = scratch("control-characters");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let cases: [&[&str]; 6] = [
        &["simulate", "--scene", "pend\nulum"],
        &["simulate", "--scene", "pendulum", "--solver", "so\nft"],
        &["simulate", "--scene", "pendulum", "--integrator", "rk\r4\u{1b}[2J"],
        &["render", "--scene", "pendulum", "--view", "fo\nrces", "--out", out],
        &["render", "--scene", "pendulum", "--compare", "ra\nte=3", "--out", out],
        &["render", "--scene", "pendulum", "--out", "x\ny.jpg"],
    ];
    for args in cases {
        let output = run(args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: one line: {stderr:?}");
        assert!(!stderr.contains(['\r', '\u{1b}']), "{args:?}: {stderr:?}");
        assert!(stderr.contains("\\n") || stderr.contains("\\r"), "{args:?}: shown as an escape: {stderr:?}");
    }
}

/// Issue 17, finding 10: a long name typed where a scene, setting or option goes is
/// quoted cut to a readable length, not echoed whole.
#[test]
fn a_long_typed_value_is_cut_in_its_message() {
    let long = "x".repeat(20_000);
    let set = format!("{long}=1");
    let size = format!("{long}x1");
    let compare = format!("{long}=1");
    let cases: [&[&str]; 7] = [
        &["simulate", "--scene", &long],
        &["simulate", "--scene", "pendulum", "--set", &set],
        &["simulate", "--scene", "pendulum", "--solver", &long],
        &["simulate", "--scene", "pendulum", "--integrator", &long],
        &["render", "--scene", "pendulum", "--view", &long, "--out", "x.png"],
        &["render", "--scene", "pendulum", "--compare", &compare, "--out", "x.png"],
        &["render", "--scene", "pendulum", "--size", &size, "--out", "x.png"],
    ];
    for args in cases {
        let output = run(args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{:?}: {stderr}", &args[..2]);
        assert_eq!(stderr.lines().count(), 1, "one line: {stderr:?}");
        assert!(stderr.chars().count() < 400, "{} characters: {}", stderr.chars().count(), &stderr[..300]);
        assert!(stderr.contains("more characters"), "says it was cut: {stderr}");
    }
}

/// Issue 17, finding 7: a directory where settings.json should be gave the window two
/// lines, one on reading it and one when the autosave could not write over it. Now it
/// is set aside like any unusable file: one line, and the settings are saved.
#[test]
fn a_directory_in_place_of_the_settings_file_gives_the_window_one_line() {
    let display = VirtualDisplay::start();
    let dir = scratch("settings-directory");
    let config = dir.join("config");
    let log = dir.join("stderr.txt");
    let mut app = display.open_window(
        || {
            // Made again for each start, in case a start that failed set it aside.
            let _ = std::fs::remove_file(config.join("particle-lab").join("settings.json"));
            std::fs::create_dir_all(config.join("particle-lab").join("settings.json")).unwrap();
            let mut app = Command::new(env!("CARGO_BIN_EXE_particle-lab"));
            app.env("XDG_CONFIG_HOME", &config).env_remove("WAYLAND_DISPLAY").env_remove("RUST_LOG");
            app
        },
        &log,
    );
    // The autosave runs every 2 s: past two of them.
    std::thread::sleep(std::time::Duration::from_secs(5));
    app.kill().unwrap();
    app.wait().unwrap();
    let stderr = std::fs::read_to_string(&log).unwrap();
    assert_eq!(stderr.lines().count(), 1, "one line:\n{stderr}");
    assert!(stderr.contains("the settings file") && stderr.contains("it is a directory"), "{stderr}");
    assert!(config.join("particle-lab").join("settings.json").is_file(), "the settings were saved");
}

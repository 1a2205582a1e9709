//! Settings that persist (issue 10, section 3): the round trip through the file, what
//! the command line overrides, `--fresh`, Restore defaults, and every kind of unusable
//! file (each set aside with one warning line, the lab left at its defaults), with a
//! property test over truncated and mutated files.

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::Vec3;
use particle_lab::physics::{Integrator, SolverKind, SolverSettings};
use particle_lab::render::ViewOptions;
use particle_lab::settings::{self, FILE_NAME, Launch, Loaded, Settings, Store};
use particle_lab::ui::{Lab, PanelLayout};
use proptest::prelude::*;

/// A fresh, empty directory for one test's settings.
fn temp_dir(tag: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let n = COUNT.fetch_add(1, Ordering::Relaxed);
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("settings-{tag}-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A bridge lab with something changed in every part that persists.
fn changed_lab() -> Lab {
    let mut lab = Lab::new("bridge", &[]).unwrap();
    lab.set_param("g", 5.0);
    lab.set_param("load_x", 2.5);
    lab.set_solver(SolverSettings {
        kind: SolverKind::Paper,
        integrator: Integrator::Rk4,
        substeps: 9,
        ..SolverSettings::default()
    });
    lab.physics_rate = 120.0;
    lab.time_scale = 0.5;
    lab.view.tension_colors = true;
    lab.view.grid = false;
    lab.view.msaa = false;
    lab.view.trails = false;
    lab.view.contacts = true;
    lab.view.predictions = false;
    lab.camera.target = Vec3::new(1.0, 2.0, -3.0);
    lab.camera.distance = 7.5;
    lab.camera.yaw = 0.75;
    lab.camera.pitch = 0.25;
    lab.camera_moved = true;
    lab
}

/// A panel with every saved part changed: hidden, help open, sections flipped.
fn changed_panel() -> PanelLayout {
    PanelLayout {
        open: false,
        help: true,
        compare: true,
        energy: false,
        stats: false,
        run: false,
        text_size: 180,
        ..PanelLayout::default()
    }
}

/// What a window opened with no settings and no flags shows.
fn defaults() -> Settings {
    Settings::of(
        &Lab::new(settings::DEFAULT_SCENE, &[]).unwrap(),
        &PanelLayout::default(),
        settings::DEFAULT_WINDOW,
    )
}

fn open(launch: &Launch, dir: &Path) -> settings::Opened {
    settings::open(launch, Store::in_dir(dir)).unwrap()
}

#[test]
fn everything_saved_comes_back_at_the_next_launch() {
    let dir = temp_dir("round-trip");
    let saved = Settings::of(&changed_lab(), &changed_panel(), [1000, 650]);
    assert!(Store::in_dir(&dir).save(&saved).unwrap(), "a first save writes the file");

    let opened = open(&Launch::default(), &dir);
    assert_eq!(opened.warning, None);
    assert_eq!(
        Settings::of(&opened.lab, &opened.layout, opened.window),
        saved,
        "every saved field comes back"
    );
    let lab = &opened.lab;
    assert_eq!(lab.entry.info().name, "bridge");
    assert_eq!(lab.scene.params().get("g"), 5.0);
    assert_eq!(lab.scene.params().get("load_x"), 2.5);
    assert_eq!(lab.scene.params().get("load_mass"), 10.0, "an unchanged parameter keeps its default");
    let solver = lab.solver();
    assert_eq!((solver.kind, solver.integrator, solver.substeps), (SolverKind::Paper, Integrator::Rk4, 9));
    assert_eq!(lab.scene.world().solver().kind, SolverKind::Paper, "the world runs the saved solver");
    assert_eq!((lab.physics_rate, lab.time_scale), (120.0, 0.5));
    assert!(
        lab.view.tension_colors && lab.view.contacts && !lab.view.grid && !lab.view.msaa && !lab.view.trails
    );
    assert!(!lab.follow && !lab.side_view);
    assert_eq!(lab.camera.distance, 7.5);
    assert_eq!((lab.camera.yaw, lab.camera.pitch), (0.75, 0.25));
    assert!(lab.camera_moved, "a restored camera is not reframed when the window's shape is first seen");
    assert_eq!(opened.layout, changed_panel(), "the panel and its sections come back");
    assert_eq!(opened.window, [1000, 650]);
    assert!(opened.summary.starts_with("settings restored from "), "{}", opened.summary);
    assert!(
        opened
            .summary
            .contains("scene bridge [g=5 load_mass=10 load_x=2.5 load_z=0.5], solver paper, integrator rk4"),
        "{}",
        opened.summary
    );
}

#[test]
fn the_file_is_pretty_versioned_json_and_unchanged_settings_are_not_rewritten() {
    let dir = temp_dir("format");
    let mut store = Store::in_dir(&dir);
    let saved = Settings::of(&changed_lab(), &changed_panel(), [800, 600]);
    assert!(store.save(&saved).unwrap());
    let text = std::fs::read_to_string(dir.join(FILE_NAME)).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["version"], 1);
    assert_eq!(json["scene"], "bridge");
    assert_eq!(json["params"]["g"], 5.0);
    assert_eq!(json["solver"]["kind"], "paper");
    assert_eq!(json["solver"]["integrator"], "rk4");
    assert_eq!(json["view"]["tension_colors"], true);
    assert_eq!(json["window"]["width"], 800);
    assert!(text.lines().count() > 30, "one field a line, for a person to read:\n{text}");
    assert!(!store.save(&saved).unwrap(), "the same settings are not written twice");
    assert!(!dir.join("settings.json.tmp").exists(), "the temporary file is renamed into place");
}

#[test]
fn a_first_launch_and_fresh_start_from_the_defaults_and_fresh_does_not_read_the_file() {
    let dir = temp_dir("fresh");
    let first = open(&Launch::default(), &dir);
    assert_eq!(Settings::of(&first.lab, &first.layout, first.window), defaults());
    assert!(first.summary.starts_with("settings none saved yet at "), "{}", first.summary);

    std::fs::write(dir.join(FILE_NAME), Settings::of(&changed_lab(), &changed_panel(), [900, 700]).to_text())
        .unwrap();
    let before = std::fs::read(dir.join(FILE_NAME)).unwrap();
    let fresh = open(&Launch { fresh: true, ..Launch::default() }, &dir);
    assert_eq!(
        Settings::of(&fresh.lab, &fresh.layout, fresh.window),
        defaults(),
        "--fresh ignores the saved bridge"
    );
    assert!(fresh.summary.starts_with("settings --fresh: starting from the defaults"), "{}", fresh.summary);
    assert_eq!(std::fs::read(dir.join(FILE_NAME)).unwrap(), before, "--fresh leaves the file alone");

    // Even an unusable file is not looked at with --fresh.
    std::fs::write(dir.join(FILE_NAME), "{ not json").unwrap();
    let fresh = open(&Launch { fresh: true, ..Launch::default() }, &dir);
    assert_eq!(fresh.warning, None);
    assert!(dir.join(FILE_NAME).exists() && !dir.join("settings.json.bad").exists());
}

#[test]
fn typed_flags_win_over_the_saved_settings_each_on_its_own() {
    let dir = temp_dir("flags");
    Store::in_dir(&dir).save(&Settings::of(&changed_lab(), &changed_panel(), [1000, 650])).unwrap();

    // --solver soft: the saved integrator and substeps stay.
    let opened = open(&Launch { solver: Some(SolverKind::Soft), ..Launch::default() }, &dir);
    let solver = opened.lab.solver();
    assert_eq!((solver.kind, solver.integrator, solver.substeps), (SolverKind::Soft, Integrator::Rk4, 9));
    assert!(opened.summary.contains("from the command line: --solver"), "{}", opened.summary);

    // --integrator and --substeps alone.
    let launch = Launch { integrator: Some(Integrator::Verlet), substeps: Some(2), ..Launch::default() };
    let solver = open(&launch, &dir).lab.solver();
    assert_eq!((solver.kind, solver.integrator, solver.substeps), (SolverKind::Paper, Integrator::Verlet, 2));

    // --set on the saved scene: over the saved values.
    let opened = open(&Launch { set: vec!["g=7".into()], ..Launch::default() }, &dir);
    let params = opened.lab.scene.params();
    assert_eq!((params.get("g"), params.get("load_x")), (7.0, 2.5));
    assert_eq!(opened.lab.physics_rate, 120.0);

    // --scene naming the saved scene: the same as not typing it.
    let opened = open(&Launch { scene: Some("Bridge".into()), ..Launch::default() }, &dir);
    assert_eq!(opened.lab.scene.params().get("load_x"), 2.5);
    assert_eq!(opened.lab.camera.distance, 7.5);

    // Another scene: its own parameters, rate, camera, trails and colours; the rest saved.
    let opened = open(&Launch { scene: Some("pendulum".into()), ..Launch::default() }, &dir);
    let lab = &opened.lab;
    assert_eq!(lab.entry.info().name, "pendulum");
    assert_eq!(lab.scene.params().get("g"), 9.81, "the bridge's g does not carry over");
    assert_eq!(lab.physics_rate, Lab::new("pendulum", &[]).unwrap().physics_rate, "the pendulum's own rate");
    assert!(!lab.camera_moved, "the bridge's camera is not put on the pendulum");
    assert!(lab.view.trails, "the pendulum's own trails");
    assert_eq!(lab.solver().kind, SolverKind::Paper, "the saved solver still applies");
    assert!(lab.view.tension_colors && !lab.view.grid && !opened.layout.open);

    // A bad flag is still a usage error, and the file stays.
    let error =
        settings::open(&Launch { set: vec!["bogus=1".into()], ..Launch::default() }, Store::in_dir(&dir))
            .err()
            .unwrap();
    assert!(error.contains("unknown parameter 'bogus'"), "{error}");
    let error =
        settings::open(&Launch { scene: Some("nope".into()), ..Launch::default() }, Store::in_dir(&dir))
            .err()
            .unwrap();
    assert!(error.contains("unknown scene 'nope'"), "{error}");
    assert!(dir.join(FILE_NAME).exists());
    // A mistyped scene is refused before the file is looked at: even a bad one stays.
    std::fs::write(dir.join(FILE_NAME), "not json").unwrap();
    assert!(
        settings::open(&Launch { scene: Some("nope".into()), ..Launch::default() }, Store::in_dir(&dir))
            .is_err()
    );
    assert_eq!(std::fs::read_to_string(dir.join(FILE_NAME)).unwrap(), "not json");
}

#[test]
fn a_saved_side_view_comes_back_orthographic_with_its_camera() {
    let dir = temp_dir("side");
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.set_side_view(true);
    // Follow comes back too (it then puts the target on the newest round, once fired).
    lab.follow = true;
    lab.camera.target.x = 12.0;
    lab.camera.distance = 30.0;
    lab.camera_moved = true;
    Store::in_dir(&dir).save(&Settings::of(&lab, &PanelLayout::default(), [1280, 720])).unwrap();
    let opened = open(&Launch::default(), &dir);
    assert!(opened.lab.side_view && opened.lab.follow, "{}", opened.summary);
    assert!(opened.lab.camera.orthographic);
    assert_eq!(opened.lab.camera.distance, 30.0);
    assert_eq!((opened.lab.camera.yaw, opened.lab.camera.pitch), (0.0, 0.0));
}

#[test]
fn restore_defaults_resets_parameters_solver_rate_and_view_and_keeps_the_scene_and_camera() {
    let mut lab = changed_lab();
    lab.follow = true;
    let camera = lab.camera;
    lab.restore_defaults();
    assert_eq!(lab.entry.info().name, "bridge");
    let fresh = Lab::new("bridge", &[]).unwrap();
    assert_eq!(lab.scene.params(), fresh.scene.params());
    assert_eq!(lab.solver(), SolverSettings::default());
    assert_eq!(*lab.scene.world().solver(), SolverSettings::default(), "the world runs the default solver");
    assert_eq!((lab.physics_rate, lab.time_scale), (fresh.physics_rate, 1.0));
    assert_eq!(lab.view, fresh.view);
    assert_eq!(lab.view, ViewOptions { trails: false, ..ViewOptions::default() }, "the bridge has no trails");
    assert!(!lab.follow && !lab.side_view);
    assert_eq!(lab.camera, camera, "the camera stays");
    assert_eq!(lab.scene.world().steps(), 0, "the scene starts again");
    assert!(lab.status.starts_with("Defaults restored for bridge"), "{}", lab.status);

    // From the side view, back to the framed 3D view.
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.set_side_view(true);
    lab.restore_defaults();
    assert!(!lab.side_view && !lab.camera.orthographic);
}

/// A valid file's text with `field` (a JSON pointer) replaced by `value`.
fn with(pointer: &str, value: serde_json::Value) -> String {
    let mut json: serde_json::Value =
        serde_json::to_value(Settings::of(&changed_lab(), &changed_panel(), [1000, 650])).unwrap();
    *json.pointer_mut(pointer).unwrap_or_else(|| panic!("no {pointer}")) = value;
    serde_json::to_string_pretty(&json).unwrap()
}

/// Opens on a settings file holding `bytes`: it must be set aside with one warning line
/// containing `reason`, and the lab must be at its defaults.
fn assert_set_aside(bytes: &[u8], reason: &str) {
    let dir = temp_dir("bad");
    let file = dir.join(FILE_NAME);
    std::fs::write(&file, bytes).unwrap();
    let opened = open(&Launch::default(), &dir);
    let warning = opened.warning.unwrap_or_else(|| panic!("no warning for a file with {reason}"));
    assert!(warning.starts_with("particle-lab: the settings file "), "{warning}");
    assert!(warning.contains(reason), "'{reason}' not in: {warning}");
    assert!(
        warning.ends_with(&format!(
            "moved it to {} and started from the defaults",
            dir.join("settings.json.bad").display()
        )),
        "{warning}"
    );
    assert!(!warning.contains('\n'), "one line: {warning}");
    assert!(!file.exists(), "the unusable file is moved away");
    assert_eq!(std::fs::read(dir.join("settings.json.bad")).unwrap(), bytes, "moved as it was");
    assert_eq!(
        Settings::of(&opened.lab, &opened.layout, opened.window),
        defaults(),
        "the lab starts from the defaults"
    );
    assert!(opened.summary.contains("was unusable; starting from the defaults"), "{}", opened.summary);
}

#[test]
fn every_kind_of_unusable_file_is_set_aside_with_one_warning() {
    use serde_json::json;
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (b"{ \"version\": 1, ".to_vec(), "not valid JSON: EOF while parsing"),
        (b"".to_vec(), "not valid JSON"),
        (b"[1, 2, 3]".to_vec(), "no version number"),
        (b"\xff\xfe{}".to_vec(), "not UTF-8 text"),
        (
            with("/version", json!(2)).into_bytes(),
            "version 2, from a newer particle-lab (this one reads version 1)",
        ),
        (with("/version", json!(0)).into_bytes(), "its version is 0"),
        (with("/version", json!("1")).into_bytes(), "its version is \"1\""),
        (with("/physics_rate", json!("fast")).into_bytes(), "invalid type: string \"fast\", expected f32"),
        (with("/view/grid", json!(1)).into_bytes(), "invalid type: integer `1`, expected a boolean"),
        (with("/params", json!([1, 2])).into_bytes(), "invalid type: sequence, expected a map"),
        (with("/window/width", json!(-5)).into_bytes(), "invalid value: integer `-5`, expected u32"),
        (with("/scene", json!("moonbase")).into_bytes(), "scene: unknown scene 'moonbase'"),
        (with("/params/g", json!(99.0)).into_bytes(), "'g' = 99 is out of range; valid range: 0 to 30"),
        (with("/params", json!({"g": 1.0, "wobble": 1.0})).into_bytes(), "unknown parameter 'wobble'"),
        (with("/solver/kind", json!("pgs")).into_bytes(), "solver.kind: unknown solver 'pgs'"),
        (with("/solver/integrator", json!("leapfrog")).into_bytes(), "unknown integrator 'leapfrog'"),
        (
            with("/solver/substeps", json!(0)).into_bytes(),
            "solver.substeps = 0 is out of range; valid range: 1 to 64",
        ),
        (with("/physics_rate", json!(5000.0)).into_bytes(), "physics_rate = 5000 is out of range"),
        (with("/physics_rate", json!(1e300)).into_bytes(), "number out of range at line 32"),
        (with("/time_scale", json!(0.0)).into_bytes(), "time_scale = 0 is out of range"),
        (with("/camera/pitch", json!(3.0)).into_bytes(), "camera.pitch = 3 is out of range"),
        (with("/camera/distance", json!(-1.0)).into_bytes(), "camera.distance = -1 is out of range"),
        (
            with("/camera/target", json!([0.0, 1.0])).into_bytes(),
            "invalid length 2, expected an array of length 3",
        ),
        (
            with("/window/height", json!(10)).into_bytes(),
            "window.height = 10 is out of range; valid range: 240 to 16384",
        ),
        (with("/panel", json!({"open": true, "colour": true})).into_bytes(), "unknown field `colour`"),
        (with("/camera", json!(null)).into_bytes(), "invalid type: null, expected struct CameraSettings"),
    ];
    for (bytes, reason) in cases {
        assert_set_aside(&bytes, reason);
    }
    // A missing part is unusable; a missing toggle or parameter takes its default.
    let mut json: serde_json::Value = serde_json::from_str(&with("/version", json!(1))).unwrap();
    json.as_object_mut().unwrap().remove("solver");
    assert_set_aside(json.to_string().as_bytes(), "missing field `solver`");
    let mut json: serde_json::Value = serde_json::from_str(&with("/version", json!(1))).unwrap();
    json["view"].as_object_mut().unwrap().remove("grid");
    json["params"].as_object_mut().unwrap().remove("load_x");
    let restored = Settings::parse(&json.to_string()).unwrap();
    assert!(restored.view.grid, "a missing toggle takes its default (on)");
    let dir = temp_dir("partial");
    std::fs::write(dir.join(FILE_NAME), json.to_string()).unwrap();
    assert_eq!(open(&Launch::default(), &dir).lab.scene.params().get("load_x"), 0.0);
}

#[test]
fn an_older_bad_file_is_replaced_and_a_new_one_is_written_after_it() {
    let dir = temp_dir("replace");
    std::fs::write(dir.join("settings.json.bad"), "old").unwrap();
    std::fs::write(dir.join(FILE_NAME), "garbage").unwrap();
    let mut opened = open(&Launch::default(), &dir);
    assert!(opened.warning.is_some());
    assert_eq!(std::fs::read_to_string(dir.join("settings.json.bad")).unwrap(), "garbage");
    // The session's settings are written as usual after that.
    assert!(opened.store.save(&Settings::of(&opened.lab, &opened.layout, opened.window)).unwrap());
    assert!(matches!(Store::in_dir(&dir).load(), Loaded::Restored(s) if s == defaults()));
}

#[test]
fn a_settings_file_that_cannot_be_written_is_an_error_message_not_a_panic() {
    let dir = temp_dir("unwritable");
    // The config "directory" is a file: nothing can be created under it.
    let blocker = dir.join("particle-lab");
    std::fs::write(&blocker, "a file").unwrap();
    let mut store = Store::in_dir(&blocker);
    let error = store.save(&defaults()).unwrap_err();
    assert!(error.starts_with("cannot save the settings to "), "{error}");
    assert!(error.contains("particle-lab/settings.json"), "{error}");
    // A directory where the file should be: unusable, reported, moved aside (so the
    // save on exit does not fail with a second line).
    let dir = temp_dir("directory");
    std::fs::create_dir(dir.join(FILE_NAME)).unwrap();
    let opened = open(&Launch::default(), &dir);
    let warning = opened.warning.unwrap();
    assert!(warning.starts_with("particle-lab: the settings file "), "{warning}");
    assert!(warning.contains("is unusable (it is a directory, not a regular file)"), "{warning}");
    assert!(dir.join("settings.json.bad").is_dir(), "moved aside");
    assert_eq!(Settings::of(&opened.lab, &opened.layout, opened.window), defaults());
}

#[test]
fn the_binary_honours_xdg_config_home_and_warns_once_about_a_bad_file_even_without_a_display() {
    let dir = temp_dir("binary");
    let config = dir.join("particle-lab");
    std::fs::create_dir_all(&config).unwrap();
    std::fs::write(config.join(FILE_NAME), "{\"version\": 1, \"scene\": 3}").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .env("XDG_CONFIG_HOME", &dir)
        .env("RUST_LOG", "warn")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("settings")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(warnings[0].starts_with("particle-lab: the settings file "), "{stderr}");
    assert!(warnings[0].contains("invalid type: integer `3`, expected a string"), "{stderr}");
    assert!(config.join("settings.json.bad").exists() && !config.join(FILE_NAME).exists());
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(output.status.code(), Some(1), "then it stops for want of a display:\n{stderr}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Any truncation of a valid file is refused with a reason, never a panic.
    #[test]
    fn a_truncated_file_is_refused(cut in 0usize..10_000) {
        let text = Settings::of(&changed_lab(), &changed_panel(), [1000, 650]).to_text();
        let body = text.trim_end();
        let cut = cut % body.len();
        let error = Settings::parse(&body[..cut]).unwrap_err();
        prop_assert!(!error.is_empty());
    }

    /// Bytes replaced, inserted or removed anywhere: parsing never panics, and a file
    /// it accepts holds valid settings that save and read back the same.
    #[test]
    fn a_mutated_file_parses_to_valid_settings_or_is_refused(
        edits in prop::collection::vec((0usize..10_000, 0u8..3, any::<u8>()), 1..6)
    ) {
        let mut bytes = Settings::of(&changed_lab(), &changed_panel(), [1000, 650]).to_text().into_bytes();
        for (at, kind, byte) in edits {
            let at = at % bytes.len();
            match kind {
                0 => bytes[at] = byte,
                1 => bytes.insert(at, byte),
                _ => { bytes.remove(at); }
            }
        }
        if let Ok(text) = std::str::from_utf8(&bytes)
            && let Ok(settings) = Settings::parse(text)
        {
            prop_assert_eq!(Settings::parse(&settings.to_text()).unwrap(), settings);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// Opening on a damaged file: either it is used (and stays where it was) or it is
    /// set aside with one warning and the lab is at its defaults; never a panic.
    #[test]
    fn opening_on_a_damaged_file_restores_it_or_falls_back_to_the_defaults_with_a_warning(
        cut in 0usize..10_000,
        digit_at in 0usize..10_000,
        digit in b'0'..=b'9',
    ) {
        let dir = temp_dir("prop");
        let file = dir.join(FILE_NAME);
        let mut bytes = Settings::of(&changed_lab(), &changed_panel(), [1000, 650]).to_text().into_bytes();
        // A changed digit (a value that may leave its range) and maybe a truncation.
        let digits: Vec<usize> = (0..bytes.len()).filter(|i| bytes[*i].is_ascii_digit()).collect();
        bytes[digits[digit_at % digits.len()]] = digit;
        if cut % 2 == 0 {
            bytes.truncate(cut % bytes.len());
        }
        std::fs::write(&file, &bytes).unwrap();
        let opened = open(&Launch::default(), &dir);
        match &opened.warning {
            None => {
                prop_assert!(file.exists());
                let expected = Settings::parse(std::str::from_utf8(&bytes).unwrap()).unwrap();
                prop_assert_eq!(Settings::of(&opened.lab, &opened.layout, opened.window), expected);
            }
            Some(warning) => {
                prop_assert!(warning.starts_with("particle-lab: the settings file "), "{}", warning);
                prop_assert!(!warning.contains('\n'));
                prop_assert!(!file.exists() && dir.join("settings.json.bad").exists());
                prop_assert_eq!(Settings::of(&opened.lab, &opened.layout, opened.window), defaults());
            }
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// The startup line of the real binary opened on `args` with the settings in `dir`
/// (no display: the settings are read and logged before the window is asked for).
fn startup_line(dir: &Path, args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(args)
        .env("XDG_CONFIG_HOME", dir)
        .env("RUST_LOG", "warn,particle_lab=info")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    stderr
        .lines()
        .find(|l| l.contains("[particle_lab::app]: settings "))
        .unwrap_or_else(|| panic!("{stderr}"))
        .to_string()
}

#[test]
fn the_binary_tells_typed_flags_from_their_defaults() {
    let dir = temp_dir("typed");
    std::fs::create_dir_all(dir.join("particle-lab")).unwrap();
    Store::in_dir(&dir.join("particle-lab"))
        .save(&Settings::of(&changed_lab(), &changed_panel(), [1000, 650]))
        .unwrap();
    let line = startup_line(&dir, &[]);
    assert!(
        line.contains("settings restored from ") && line.contains("solver paper, integrator rk4"),
        "{line}"
    );
    // Typed at their default values, they still win over the saved paper solver and rk4.
    let line = startup_line(&dir, &["--solver", "soft", "--integrator", "semi-implicit-euler"]);
    assert!(line.contains("from the command line: --solver --integrator"), "{line}");
    assert!(line.contains("solver soft (9 substeps), integrator semi-implicit-euler"), "{line}");
    let line = startup_line(&dir, &["--substeps", "4", "--set", "g=3"]);
    assert!(line.contains("scene bridge [g=3 load_mass=10 load_x=2.5"), "{line}");
    assert!(line.contains("solver paper, integrator rk4"), "{line}");
    let line = startup_line(&dir, &["--fresh", "--scene", "cradle"]);
    assert!(line.contains("settings --fresh: starting from the defaults"), "{line}");
    assert!(line.contains("scene cradle [") && line.contains("solver soft (4 substeps)"), "{line}");
}

/// A copy of the shipped chain under another file and scene name, in `dir`: a scene
/// file of the user's, which no scene name finds.
fn user_scene_file(dir: &Path) -> PathBuf {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/chain.toml"))
            .unwrap();
    assert!(text.contains("name = \"chain\"\n"));
    let path = dir.join("my-hanging-chain.toml");
    std::fs::write(&path, text.replacen("name = \"chain\"\n", "name = \"hanging\"\n", 1)).unwrap();
    path
}

/// Settings saved from a window on the scene file in `scenes` with `links=8`, a moved
/// camera and a hidden panel, written to the settings in `dir`.
fn save_on_scene_file(dir: &Path, scene_file: &Path) -> Settings {
    let launch = Launch { scene_file: Some(scene_file.to_path_buf()), ..Launch::default() };
    let mut lab = open(&launch, &temp_dir("scene-file-first")).lab;
    lab.set_param("links", 8.0);
    lab.camera.distance = 6.5;
    lab.camera_moved = true;
    lab.view.grid = false;
    lab.time_scale = 0.25;
    let panel = PanelLayout { open: false, ..PanelLayout::default() };
    let saved = Settings::of(&lab, &panel, [900, 600]);
    assert!(Store::in_dir(dir).save(&saved).unwrap());
    saved
}

#[test]
fn a_scene_file_is_saved_by_its_path_and_opened_again_with_its_values_and_watched() {
    let scenes = temp_dir("scene-file-scenes");
    let dir = temp_dir("scene-file");
    let scene_file = user_scene_file(&scenes);
    let saved = save_on_scene_file(&dir, &scene_file);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join(FILE_NAME)).unwrap()).unwrap();
    assert_eq!(json["version"], 1, "an optional field: the format's version stays");
    assert_eq!(json["scene"], "hanging");
    assert_eq!(json["scene_file"], scene_file.to_str().unwrap());
    assert_eq!(json["params"]["links"], 8.0);

    let opened = open(&Launch::default(), &dir);
    assert_eq!(opened.warning, None);
    assert_eq!(Settings::of(&opened.lab, &opened.layout, opened.window), saved, "everything comes back");
    let mut lab = opened.lab;
    assert_eq!(lab.entry.info().name, "hanging");
    let definition = particle_lab::scenes::file::definition(&lab.entry).expect("a file scene");
    assert_eq!(definition.path(), Some(scene_file.as_path()), "the user's file, opened again");
    let source = definition.source().to_string();
    assert_eq!(lab.scene.params().get("links"), 8.0);
    assert_eq!(lab.scene.params().get("span"), 3.0);
    assert_eq!(lab.camera.distance, 6.5, "the scene's camera comes back with it");
    assert!(!opened.layout.open && !lab.view.grid && lab.time_scale == 0.25);
    assert!(
        opened.summary.contains(&format!("scene hanging (file {}) [", scene_file.display())),
        "{}",
        opened.summary
    );

    // The window watches it as it does for --scene-file: an edit reloads it.
    lab.watch_scene_file();
    std::thread::sleep(std::time::Duration::from_millis(100));
    let edited = format!("{source}# edited\n");
    std::fs::write(&scene_file, &edited).unwrap();
    let start = std::time::Instant::now();
    while particle_lab::scenes::file::definition(&lab.entry).unwrap().source() != edited {
        assert!(start.elapsed().as_secs() < 10, "the saved scene file is not watched");
        lab.poll_scene_file();
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert_eq!(lab.scene.params().get("links"), 8.0, "the reload keeps the values");

    // A relative --scene-file is saved absolute, so a launch from elsewhere finds it.
    let relative = scene_file.strip_prefix(std::env::current_dir().unwrap()).unwrap();
    let relative_dir = temp_dir("scene-file-relative");
    save_on_scene_file(&relative_dir, relative);
    let text = std::fs::read_to_string(relative_dir.join(FILE_NAME)).unwrap();
    assert!(Settings::parse(&text).unwrap().scene_file == Some(scene_file.display().to_string()), "{text}");

    // Typed, the same file is the saved scene (its values come back); another scene wins.
    let launch = Launch { scene_file: Some(scene_file.clone()), ..Launch::default() };
    assert_eq!(open(&launch, &dir).lab.scene.params().get("links"), 8.0);
    let opened = open(&Launch { scene: Some("chain".into()), ..Launch::default() }, &dir);
    assert_eq!(opened.warning, None);
    assert!(particle_lab::scenes::file::definition(&opened.lab.entry).unwrap().path() != Some(&scene_file));
    assert_eq!(opened.lab.scene.params().get("links"), 20.0, "the shipped chain has its own values");
}

#[test]
fn a_shipped_scene_file_is_saved_by_its_name_only() {
    let dir = temp_dir("shipped-file");
    let saved = Settings::of(&Lab::new("chain", &[]).unwrap(), &PanelLayout::default(), [900, 600]);
    assert_eq!((saved.scene.as_str(), &saved.scene_file), ("chain", &None));
    Store::in_dir(&dir).save(&saved).unwrap();
    assert!(!std::fs::read_to_string(dir.join(FILE_NAME)).unwrap().contains("scene_file"));
    let reopened = open(&Launch::default(), &dir);
    assert_eq!(Settings::of(&reopened.lab, &reopened.layout, [900, 600]), saved);
}

/// Opens on settings saved on a scene file after `break_it` did something to the
/// file: one warning line naming it, the default scene, the rest of the settings, and
/// the settings file left where it was, unchanged.
fn assert_starts_on_the_default_scene(tag: &str, break_it: impl Fn(&Path), reason: &str) {
    let scenes = temp_dir(&format!("{tag}-scenes"));
    let dir = temp_dir(tag);
    let scene_file = user_scene_file(&scenes);
    save_on_scene_file(&dir, &scene_file);
    let before = std::fs::read(dir.join(FILE_NAME)).unwrap();
    break_it(&scene_file);

    let opened = open(&Launch::default(), &dir);
    assert_eq!(
        opened.warning.as_deref(),
        Some(
            format!(
                "particle-lab: the scene file {} saved in the settings cannot be opened ({reason}); starting on \
                 projectile, and the settings keep it for the next start",
                scene_file.display()
            )
            .as_str()
        )
    );
    let status = opened.warning.as_deref().unwrap().replacen("particle-lab: the", "The", 1);
    assert_eq!(opened.lab.status, status, "the status line says it too");
    let lab = &opened.lab;
    assert_eq!(lab.entry.info().name, "projectile");
    assert_eq!(lab.scene.params(), Lab::new("projectile", &[]).unwrap().scene.params());
    assert!(!lab.camera_moved, "the chain's camera is not put on the projectile");
    assert!(!opened.layout.open && !lab.view.grid && lab.time_scale == 0.25, "the rest of the settings stay");
    assert_eq!(opened.window, [900, 600]);
    assert!(opened.summary.starts_with("settings restored from "), "{}", opened.summary);
    assert_eq!(std::fs::read(dir.join(FILE_NAME)).unwrap(), before, "the settings file stays as it was");
    assert!(!dir.join("settings.json.bad").exists(), "and is not set aside");
    // With --from the snapshot names the scene: the saved file is not looked for.
    let launch = Launch { from: Some("snapshot.json".into()), ..Launch::default() };
    assert_eq!(open(&launch, &dir).warning, None);
}

#[test]
fn a_saved_scene_file_that_is_gone_or_broken_starts_on_the_default_scene_keeping_the_rest() {
    assert_starts_on_the_default_scene(
        "gone",
        |file| std::fs::remove_file(file).unwrap(),
        "cannot read it: no such file",
    );
    assert_starts_on_the_default_scene(
        "broken",
        |file| std::fs::write(file, "[scene]\nname = 3\n").unwrap(),
        "line 2, column 8: invalid type: integer `3`, expected a string",
    );
}

/// Replaces the user's scene file with something that cannot be read as one.
fn unreadable(file: &Path, how: &str) {
    let _ = std::fs::remove_file(file);
    match how {
        "gone" => {}
        "fifo" => assert!(Command::new("mkfifo").arg(file).status().unwrap().success()),
        "device" => std::os::unix::fs::symlink("/dev/zero", file).unwrap(),
        _ => unreachable!("{how}"),
    }
}

/// Issue 40, "Nothing lost": a saved scene file that cannot be read at start (gone, a
/// FIFO, a device) is reported once, in the status line and the log, and stays in the
/// settings through the window's autosave with its values, camera and physics rate,
/// beside whatever else the user changed; the next start tries it again and, once it
/// is back, opens it as it was.
#[test]
fn an_unreadable_saved_scene_file_is_kept_through_an_autosave_and_opens_once_it_is_back() {
    for (how, reason) in [
        ("gone", "cannot read it: no such file"),
        ("fifo", "cannot read it: it is a FIFO (named pipe), not a regular file"),
        ("device", "cannot read it: it is a device, not a regular file"),
    ] {
        let scenes = temp_dir(&format!("kept-{how}-scenes"));
        let dir = temp_dir(&format!("kept-{how}"));
        let scene_file = user_scene_file(&scenes);
        let saved = save_on_scene_file(&dir, &scene_file);
        unreadable(&scene_file, how);

        let mut opened = open(&Launch::default(), &dir);
        let warning = opened.warning.clone().unwrap_or_default();
        assert!(
            warning.contains(reason) && warning.ends_with("the settings keep it for the next start"),
            "{warning}"
        );
        assert!(opened.lab.status.starts_with("The scene file ") && opened.lab.status.contains(reason));
        assert_eq!(opened.lab.entry.info().name, "projectile");
        assert!(opened.kept.is_some());
        // The user changes things on the scene the window opened on; the window autosaves.
        opened.lab.time_scale = 2.0;
        opened.lab.set_param("angle", 30.0);
        opened.lab.camera_moved = true;
        let layout = PanelLayout { open: true, ..opened.layout };
        std::thread::sleep(settings::AUTOSAVE_INTERVAL);
        let (mut store, mut kept) = (opened.store, opened.kept);
        store.autosave(|| Settings::keeping(&mut kept, &opened.lab, &layout, [1000, 700]));
        let after = Settings::parse(&std::fs::read_to_string(dir.join(FILE_NAME)).unwrap()).unwrap();
        assert_eq!(after.scene_file, saved.scene_file, "{how}: the file is still named");
        assert_eq!(after.scene, "hanging");
        assert_eq!(after.params, saved.params, "{how}: with its values");
        assert_eq!(after.params["links"], 8.0);
        assert_eq!((after.camera, after.physics_rate), (saved.camera, saved.physics_rate));
        assert_eq!(
            (after.view.trails, after.view.color_by_speed),
            (saved.view.trails, saved.view.color_by_speed)
        );
        assert!(after.time_scale == 2.0 && after.panel.open, "{how}: what the user changed is saved too");
        assert_eq!([after.window.width, after.window.height], [1000, 700]);

        // Still unreadable: the next start says so again and keeps it again.
        let again = open(&Launch::default(), &dir);
        assert_eq!(again.warning.as_deref(), Some(warning.as_str()));
        assert_eq!(again.kept.as_ref().map(|k| &k.scene_file), Some(&saved.scene_file));

        // Back: the next start opens it as it was, and says nothing. (What stood in its
        // place goes first; a gone file has nothing in its place.)
        if how != "gone" {
            std::fs::remove_file(&scene_file).unwrap();
        }
        assert_eq!(user_scene_file(&scenes), scene_file);
        let back = open(&Launch::default(), &dir);
        assert_eq!(
            (back.warning.as_deref(), back.lab.status.as_str(), back.kept.is_none()),
            (None, "", true)
        );
        assert_eq!(back.lab.entry.info().name, "hanging");
        assert_eq!(back.lab.scene.params().get("links"), 8.0);
        assert_eq!(back.lab.camera.distance, 6.5, "with its camera");
        assert_eq!(back.lab.time_scale, 2.0);
    }
}

/// ... until the user opens another scene: that is the new choice, and it replaces
/// the kept file for good (going back to the scene the window opened on included).
#[test]
fn opening_another_scene_replaces_a_kept_scene_file() {
    let scenes = temp_dir("replaced-scenes");
    let dir = temp_dir("replaced");
    let scene_file = user_scene_file(&scenes);
    save_on_scene_file(&dir, &scene_file);
    unreadable(&scene_file, "gone");
    let mut opened = open(&Launch::default(), &dir);
    let layout = opened.layout;
    let kept = &mut opened.kept;
    assert_eq!(Settings::keeping(kept, &opened.lab, &layout, [900, 600]).scene, "hanging");
    opened.lab.switch_scene(particle_lab::scenes::find("chain").unwrap());
    let now = Settings::keeping(kept, &opened.lab, &layout, [900, 600]);
    assert_eq!((now.scene.as_str(), &now.scene_file), ("chain", &None));
    assert!(kept.is_none(), "dropped");
    opened.lab.switch_scene(particle_lab::scenes::find(settings::DEFAULT_SCENE).unwrap());
    let now = Settings::keeping(kept, &opened.lab, &layout, [900, 600]);
    assert_eq!((now.scene.as_str(), &now.scene_file), ("projectile", &None), "for good");

    // A scene file opened is the choice as well.
    let mut opened = open(&Launch::default(), &dir);
    let other = user_scene_file(&temp_dir("replaced-other"));
    assert!(opened.lab.open_scene_file(&other));
    let now = Settings::keeping(&mut opened.kept, &opened.lab, &opened.layout, [900, 600]);
    assert_eq!(now.scene_file, Some(other.display().to_string()));
    assert!(opened.kept.is_none());
}

#[test]
fn saved_values_that_no_longer_fit_an_edited_scene_file_give_way_to_its_defaults() {
    let scenes = temp_dir("unfit-scenes");
    let dir = temp_dir("unfit");
    let scene_file = user_scene_file(&scenes);
    save_on_scene_file(&dir, &scene_file);
    // The file's links now go up to 6 only: the saved 8 is out of range.
    let text = std::fs::read_to_string(&scene_file).unwrap();
    std::fs::write(
        &scene_file,
        text.replacen("max = 60\n", "max = 6\n", 1).replacen("default = 20\n", "default = 5\n", 1),
    )
    .unwrap();
    let opened = open(&Launch::default(), &dir);
    let warning = opened.warning.unwrap();
    assert!(
        warning.starts_with(&format!(
            "particle-lab: the values saved for the scene file {} no longer fit it (",
            scene_file.display()
        )),
        "{warning}"
    );
    assert!(warning.contains("'links' = 8 is out of range"), "{warning}");
    assert!(warning.ends_with("); opening it with its defaults"), "{warning}");
    assert_eq!(opened.lab.entry.info().name, "hanging");
    assert_eq!(opened.lab.scene.params().get("links"), 5.0);
    assert!(!dir.join("settings.json.bad").exists());
    // --set still has to fit.
    let error =
        settings::open(&Launch { set: vec!["links=9".into()], ..Launch::default() }, Store::in_dir(&dir))
            .err()
            .unwrap();
    assert!(error.contains("'links' = 9 is out of range"), "{error}");
}

#[test]
fn the_binary_warns_once_about_a_saved_scene_file_that_is_gone_and_keeps_the_settings() {
    let dir = temp_dir("binary-scene-file");
    let config = dir.join("particle-lab");
    std::fs::create_dir_all(&config).unwrap();
    let scene_file = user_scene_file(&temp_dir("binary-scene-file-scenes"));
    save_on_scene_file(&config, &scene_file);
    std::fs::remove_file(&scene_file).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .env("XDG_CONFIG_HOME", &dir)
        .env("RUST_LOG", "warn")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("settings")).collect();
    assert_eq!(
        warnings,
        [format!(
            "particle-lab: the scene file {} saved in the settings cannot be opened (cannot read it: no such \
             file); starting on projectile, and the settings keep it for the next start",
            particle_lab::messages::path(&scene_file)
        )],
        "{stderr}"
    );
    assert!(config.join(FILE_NAME).exists() && !config.join("settings.json.bad").exists());
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Loads the settings in `dir` on another thread: `None` if that did not finish in
/// 20 s (a read that blocks).
fn load_within_20_s(dir: &Path) -> Option<(Loaded, std::time::Duration)> {
    let dir = dir.to_path_buf();
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let started = std::time::Instant::now();
        let loaded = Store::in_dir(&dir).load();
        let _ = send.send((loaded, started.elapsed()));
    });
    receive.recv_timeout(std::time::Duration::from_secs(20)).ok()
}

fn unusable_warning(loaded: Loaded) -> String {
    match loaded {
        Loaded::Unusable { warning } => warning,
        other => panic!("not unusable: {other:?}"),
    }
}

/// Issue 17, finding 4: a settings file that is a FIFO, a link to a device or too large
/// is unusable at once: one line, the defaults, no wait for a writer, no endless read.
#[test]
fn a_settings_file_that_is_a_fifo_a_device_or_huge_is_unusable_at_once() {
    let dir = temp_dir("fifo");
    let file = dir.join(FILE_NAME);
    assert!(Command::new("mkfifo").arg(&file).status().unwrap().success());
    let (loaded, took) = load_within_20_s(&dir).expect("reading a FIFO as the settings file blocked");
    let warning = unusable_warning(loaded);
    assert!(warning.contains("it is a FIFO (named pipe), not a regular file"), "{warning}");
    assert!(warning.ends_with("started from the defaults"), "{warning}");
    assert!(!warning.contains('\n'), "{warning}");
    assert!(took.as_secs() < 5, "at once: {took:?}");
    assert!(!file.exists(), "the FIFO is moved aside, so the next save can write the file");
    let opened = open(&Launch::default(), &dir);
    assert_eq!(opened.warning, None, "nothing is left in the way");

    let dir = temp_dir("device");
    let file = dir.join(FILE_NAME);
    std::os::unix::fs::symlink("/dev/zero", &file).unwrap();
    let (loaded, _) = load_within_20_s(&dir).expect("reading /dev/zero as the settings file did not stop");
    let warning = unusable_warning(loaded);
    assert!(warning.contains("it is a device, not a regular file"), "{warning}");
    assert!(std::fs::symlink_metadata(&file).is_err(), "the link is moved aside");

    let dir = temp_dir("huge");
    let file = dir.join(FILE_NAME);
    let mut text = with("/version", serde_json::json!(1));
    text.push_str(&" ".repeat(2 << 20));
    std::fs::write(&file, &text).unwrap();
    let warning = unusable_warning(Store::in_dir(&dir).load());
    assert!(warning.contains("it is larger than the limit of 1 MB"), "{warning}");
}

/// Issue 17, finding 7: a directory where the settings file should be gives one line
/// (it was one on reading and a second when the window saved on exit), and a path with
/// a newline or an escape in it is shown with escapes, on the same line.
#[test]
fn a_directory_in_place_of_the_settings_file_gives_one_line_and_paths_stay_on_it() {
    let dir = temp_dir("dir\nname\u{1b}[2J");
    std::fs::create_dir_all(dir.join(FILE_NAME)).unwrap();
    let mut store = Store::in_dir(&dir);
    let warning = unusable_warning(store.load());
    assert!(!warning.contains('\n') && !warning.contains('\u{1b}'), "one line: {warning:?}");
    assert!(warning.contains("dir\\nname\\u{1b}[2J"), "{warning}");
    assert!(warning.contains("it is a directory, not a regular file"), "{warning}");
    assert!(!warning.contains("os error"), "{warning}");
    assert!(store.save(&defaults()).is_ok(), "the save on exit then works: no second line");
    assert_eq!(Settings::parse(&std::fs::read_to_string(dir.join(FILE_NAME)).unwrap()).unwrap(), defaults());
}

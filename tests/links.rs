//! Links to experiments (issue 20): a web page's query string is read as the window's
//! command line. Checked here on the desktop, where the same code runs: a link gives
//! the launch its flags would, refuses what they refuse with the same line, and the
//! link the lab writes of itself opens the same experiment again.

use std::process::Command;

use particle_lab::physics::{Integrator, SolverKind};
use particle_lab::settings::{self, Launch, Store};
use particle_lab::ui::lab::Link;

fn pairs(query: &str) -> Vec<(String, String)> {
    query
        .trim_start_matches('?')
        .split('&')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let (k, v) = p.split_once('=').unwrap_or((p, ""));
            (decode(k), decode(v))
        })
        .collect()
}

/// Percent-decoding, written out here so the test does not trust the encoder's twin.
fn decode(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            out.push(u8::from_str_radix(&text[i + 1..i + 3], 16).unwrap());
            i += 3;
        } else {
            out.push(if bytes[i] == b'+' { b' ' } else { bytes[i] });
            i += 1;
        }
    }
    String::from_utf8(out).unwrap()
}

fn open_link(query: &str) -> Result<(Link, Launch), String> {
    let link = Link::parse(&pairs(query))?;
    let launch = Launch::from_args(&link.args)?;
    Ok((link, launch))
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("particle-lab-links-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// What the binary says (stderr, exit code) for a window command line, without a
/// display: a bad flag is refused before any window opens.
fn typed(args: &[&str]) -> (String, Option<i32>) {
    let out = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("XDG_CONFIG_HOME", scratch("typed"))
        .output()
        .unwrap();
    (String::from_utf8_lossy(&out.stderr).trim().to_string(), out.status.code())
}

#[test]
fn a_link_gives_the_launch_its_flags_would() {
    let (link, launch) =
        open_link("?scene=bridge&set=load_x=1.5&set=g=5&solver=paper&integrator=rk4&steps=240").unwrap();
    assert_eq!(link.steps, Some(240));
    assert!(!link.webgl2_only);
    assert_eq!(launch.scene.as_deref(), Some("bridge"));
    assert_eq!(launch.set, ["load_x=1.5", "g=5"]);
    assert_eq!(launch.solver, Some(SolverKind::Paper));
    assert_eq!(launch.integrator, Some(Integrator::Rk4));
    // Not in the link: the saved choice is kept, as when the flag is not typed.
    assert_eq!(launch.substeps, None);
    let (link, _) = open_link("?gpu=webgl2").unwrap();
    assert!(link.webgl2_only);
}

#[test]
fn a_bad_link_is_refused_with_the_line_a_typed_flag_gets() {
    // A value the parser refuses: the first line of the binary's own message.
    let error = open_link("?solver=bogus").unwrap_err();
    let (stderr, code) = typed(&["--solver", "bogus"]);
    assert_eq!(code, Some(2), "{stderr}");
    let first = stderr.lines().next().unwrap();
    assert!(first.contains(&error), "link: {error}\ntyped: {first}");
    assert!(error.contains("bogus"), "{error}");

    // A parameter out of range is refused when the lab opens, as the window does.
    let (_, launch) = open_link("?scene=bridge&set=load_x=99").unwrap();
    let dir = scratch("range");
    let Err(error) = settings::open(&launch, Store::in_dir(&dir)) else { panic!("load_x=99 opened") };
    let (stderr, code) = typed(&["--scene", "bridge", "--set", "load_x=99"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(stderr, format!("particle-lab: {error}"));

    // The page's own keys and unknown ones: one line naming what is allowed.
    let error = Link::parse(&pairs("?steps=ten")).unwrap_err();
    assert!(error.contains("'ten'") && error.contains("steps"), "{error}");
    let error = Link::parse(&pairs("?gpu=cuda")).unwrap_err();
    assert!(error.contains("webgl2"), "{error}");
    let error = Link::parse(&pairs("?colour=red")).unwrap_err();
    assert!(error.contains("'colour'") && error.contains("scene, set"), "{error}");
    for error in [open_link("?scene=nosuch").err(), open_link("?substeps=0").err()].into_iter().flatten() {
        assert_eq!(error.lines().count(), 1, "{error}");
    }
}

/// `steps=N` leaves the lab paused at step N with `simulate --steps N`'s state hash.
#[test]
fn a_link_with_steps_shows_the_moment_simulate_reaches() {
    for (query, args) in [
        ("?scene=bridge&steps=240", vec!["--scene", "bridge"]),
        (
            "?scene=projectile&set=g=5&solver=paper&integrator=rk4&steps=300",
            vec!["--scene", "projectile", "--set", "g=5", "--solver", "paper", "--integrator", "rk4"],
        ),
    ] {
        let (link, launch) = open_link(query).unwrap();
        let mut lab = settings::open(&launch, Store::in_dir(&scratch("steps"))).unwrap().lab;
        link.run_steps(&mut lab);
        assert!(lab.paused, "{query}: paused at the moment");
        let steps = link.steps.unwrap();
        assert_eq!(lab.scene.world().steps(), steps, "{query}");
        let out = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
            .arg("simulate")
            .args(&args)
            .args(["--steps", &steps.to_string()])
            .output()
            .unwrap();
        let text = String::from_utf8(out.stdout).unwrap();
        let last: serde_json::Value = serde_json::from_str(text.lines().last().unwrap()).unwrap();
        assert_eq!(last["step"].as_u64(), Some(steps), "{query}");
        assert_eq!(last["hash"].as_str(), Some(lab.state_hash().as_str()), "{query}");
    }
}

/// The link the lab writes of itself ("Copy link") opens the same experiment: every
/// parameter, the solver, its substeps and the integrator, at the same step.
#[test]
fn the_link_of_what_is_on_screen_opens_it_again() {
    let (_, first) =
        open_link("?scene=springForces&set=g=3.25&solver=paper&substeps=7&integrator=verlet").unwrap();
    let mut lab = settings::open(&first, Store::in_dir(&scratch("copy-a"))).unwrap().lab;
    lab.scene.set_param("g", 7.123_456_7).unwrap();
    lab.run_steps_recorded(123);
    let query = Link::of(&lab, true).unwrap();
    assert!(query.starts_with("?scene=springForces&"), "{query}");
    let (link, again) = open_link(&query).unwrap();
    let mut copy = settings::open(&again, Store::in_dir(&scratch("copy-b"))).unwrap().lab;
    let params: Vec<_> = copy.scene.params().iter().map(|(p, v)| (p.name.to_string(), v.to_bits())).collect();
    let wanted: Vec<_> = lab.scene.params().iter().map(|(p, v)| (p.name.to_string(), v.to_bits())).collect();
    assert_eq!(params, wanted, "{query}");
    assert_eq!(copy.solver(), lab.solver(), "{query}");
    link.run_steps(&mut copy);
    assert_eq!(copy.state_hash(), lab.state_hash(), "{query}");
}

/// Runs the binary with `args`; its stdout, stderr and exit code.
fn binary(args: &[&str]) -> (String, String, Option<i32>) {
    let out = Command::new(env!("CARGO_BIN_EXE_particle-lab")).args(args).output().unwrap();
    let text = |bytes: Vec<u8>| String::from_utf8(bytes).unwrap();
    (text(out.stdout), text(out.stderr), out.status.code())
}

/// Issue 38: Copy link on a scene file of one's own gave `?scene=ramp&…`, which the page
/// answered with "unknown scene 'ramp'". A scene file that is not shipped now travels
/// in the link, packed, after the `#` (never sent to a server): read back as the page
/// and `particle-lab open` read it, it is the same file byte for byte, opens the same
/// experiment, and after the link's steps has `simulate`'s state hash for that file.
/// The lab's own link of what it opened is the same link again.
#[test]
fn a_link_to_a_scene_file_of_ones_own_carries_it_and_opens_the_same_experiment() {
    let dir = scratch("own-files");
    for name in ["chain", "cloth", "platform", "blob"] {
        let shipped =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("assets/scenes/{name}.toml"));
        let original = std::fs::read_to_string(&shipped).unwrap();
        // Renamed, so no longer a shipped scene: only the link can carry it.
        let text = original.replacen(&format!("name = \"{name}\""), &format!("name = \"my-{name}\""), 1);
        assert_ne!(text, original, "{name}: renamed");
        let file = dir.join(format!("my-{name}.toml"));
        std::fs::write(&file, &text).unwrap();
        let file = file.to_str().unwrap();
        let base = "https://example.org/lab/";
        let (stdout, stderr, code) =
            binary(&["link", "--scene-file", file, "--set", "g=5", "--steps", "90", "--base", base]);
        assert_eq!(code, Some(0), "{name}: {stderr}");
        let typed = stdout.trim();
        assert!(typed.starts_with("https://example.org/lab/#file="), "{name}: {typed}");
        assert!(!typed.contains('?'), "{name}: nothing of it before the '#', for a server's log");

        let link = Link::parse_text(typed).unwrap();
        assert_eq!(link.scene_text.as_deref(), Some(text.as_str()), "{name}: carried byte for byte");
        let mut launch = Launch::from_args(&link.args).unwrap();
        launch.scene_text = link.scene_text.clone();
        let mut lab = settings::open(&launch, Store::in_dir(&scratch(&format!("own-{name}")))).unwrap().lab;
        assert_eq!(lab.entry.info().name, format!("my-{name}"));
        assert_eq!(lab.scene.params().get("g"), 5.0, "{name}: with its parameters");
        link.run_steps(&mut lab);
        assert!(lab.paused);
        let (stdout, stderr, code) =
            binary(&["simulate", "--scene-file", file, "--set", "g=5", "--steps", "90"]);
        assert_eq!(code, Some(0), "{name}: {stderr}");
        let last: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
        assert_eq!(last["step"], 90, "{name}");
        assert_eq!(last["hash"].as_str(), Some(lab.state_hash().as_str()), "{name}: the same experiment");
        assert_eq!(
            format!("{base}{}", Link::of(&lab, true).unwrap()),
            typed,
            "{name}: Copy link gives it again"
        );

        // The shipped file itself is named, as the page knows it.
        let (stdout, _, code) = binary(&["link", "--scene-file", shipped.to_str().unwrap()]);
        assert_eq!(code, Some(0));
        assert!(stdout.starts_with(&format!("?scene={name}&")), "{stdout}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene file too big for a link says so at once, and what to do instead, rather
/// than giving a link that some program would cut; a damaged or foreign link is one
/// line, exit 2.
#[test]
fn a_scene_too_big_for_a_link_and_a_damaged_link_are_one_line() {
    let dir = scratch("too-big");
    // Particles at positions no compressor can guess: a few thousand distinct numbers.
    let mut text = String::from("[scene]\nname = \"scatter\"\n");
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    for _ in 0..600 {
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % 1_000_000) as f64 / 1000.0
        };
        text.push_str(&format!(
            "\n[[particle]]\nposition = [{}, {}, {}]\nradius = 0.05\n",
            next(),
            next(),
            next()
        ));
    }
    let file = dir.join("scatter.toml");
    std::fs::write(&file, &text).unwrap();
    let (stdout, stderr, code) = binary(&["link", "--scene-file", file.to_str().unwrap()]);
    assert_eq!((stdout.as_str(), code), ("", Some(2)), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("more than the 8 KB a link can carry") && stderr.contains("save the scene file"),
        "{stderr}"
    );
    // It does run: the file is good, only too big for a link.
    let (_, stderr, code) = binary(&["simulate", "--scene-file", file.to_str().unwrap(), "--steps", "1"]);
    assert_eq!(code, Some(0), "{stderr}");

    let both =
        format!("?scene=bridge#file={}", particle_lab::ui::lab::carried::pack("[scene]\nname = \"x\"\n"));
    for (link, words) in [
        ("example.org/lab", "is not a link to an experiment"),
        ("https://example.org/lab/#file=abc", "damaged"),
        ("#file=a", "cut short"),
        ("#file=%zz", "broken escape"),
        (both.as_str(), "not both"),
    ] {
        let (_, stderr, code) = binary(&["open", link]);
        assert_eq!(code, Some(2), "{link}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{link}: {stderr}");
        assert!(stderr.contains(words), "{link}: {stderr}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A link opens at its own physics rate (`rate=HZ`, written when the lab's differs from
/// the scene's), or the scene's own, never at a rate saved in the settings: otherwise
/// `steps=N` would not reach the state it promises.
#[test]
fn a_link_opens_at_its_own_rate_not_a_saved_one() {
    use particle_lab::settings::Settings;
    // Settings saved on bridge at 90 Hz.
    let dir = scratch("rate");
    let (_, launch) = open_link("?scene=bridge").unwrap();
    let mut saved_lab = settings::open(&launch, Store::in_dir(&dir)).unwrap().lab;
    saved_lab.physics_rate = 90.0;
    let panel = particle_lab::settings::PanelSettings::default();
    assert!(Store::in_dir(&dir).save(&Settings::of(&saved_lab, &panel, [900, 600])).unwrap());
    let (_, plain) = open_link("").unwrap();
    assert_eq!(settings::open(&plain, Store::in_dir(&dir)).unwrap().lab.physics_rate, 90.0, "saved");

    // A lab at 120 Hz: its link says so, and opens at 120 Hz over the saved 90.
    let (_, first) = open_link("?scene=bridge&set=g=5").unwrap();
    let mut lab = settings::open(&first, Store::in_dir(&scratch("rate-a"))).unwrap().lab;
    lab.physics_rate = 120.0;
    lab.run_steps_recorded(200);
    let query = Link::of(&lab, true).unwrap();
    assert!(query.contains("&rate=120&"), "{query}");
    let copy_launch = Launch::from_link(&query).unwrap();
    let mut copy = settings::open(&copy_launch, Store::in_dir(&dir)).unwrap().lab;
    assert_eq!(copy.physics_rate, 120.0);
    Link::parse_text(&query).unwrap().run_steps(&mut copy);
    assert_eq!(copy.state_hash(), lab.state_hash(), "{query}");

    // Without `rate`, the scene's own rate (240 Hz), not the saved 90.
    let at_own = Launch::from_link("?scene=bridge&steps=240").unwrap();
    let own = settings::open(&at_own, Store::in_dir(&dir)).unwrap().lab;
    assert_eq!(own.dt(), own.entry.info().dt);
    assert!(Link::of(&own, false).unwrap().find("rate=").is_none());
    // A rate out of the panel's range is one line.
    let error = Launch::from_link("?scene=bridge&rate=5").unwrap_err();
    assert!(error.contains("'rate'") && error.contains("30 to 1000"), "{error}");
    let error = Launch::from_link("?scene=bridge&steps=18446744073709551615").unwrap_err();
    assert!(error.contains("0 to 100000000"), "{error}");
}

/// A scene carried by a link has no home to open again from: the settings saved from
/// it name the default scene (the rest kept), so the next plain start opens cleanly
/// instead of setting the whole settings file aside as unusable.
#[test]
fn settings_saved_on_a_carried_scene_open_again_on_the_default_scene() {
    use particle_lab::settings::Settings;
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/chain.toml"))
        .unwrap()
        .replacen("name = \"chain\"", "name = \"sent-chain\"", 1);
    let link = format!("#file={}", particle_lab::ui::lab::carried::pack(&text));
    let dir = scratch("carried-settings");
    let mut lab = settings::open(&Launch::from_link(&link).unwrap(), Store::in_dir(&dir)).unwrap().lab;
    assert_eq!(lab.entry.info().name, "sent-chain");
    lab.time_scale = 0.5;
    let panel = particle_lab::settings::PanelSettings::default();
    let saved = Settings::of(&lab, &panel, [900, 600]);
    assert_eq!((saved.scene.as_str(), saved.params.len(), &saved.scene_file), ("projectile", 0, &None));
    assert!(Store::in_dir(&dir).save(&saved).unwrap());
    let (_, plain) = open_link("").unwrap();
    let again = settings::open(&plain, Store::in_dir(&dir)).unwrap();
    assert_eq!(again.warning, None, "the settings are usable");
    assert_eq!(again.lab.entry.info().name, "projectile");
    assert_eq!(again.lab.time_scale, 0.5, "the rest kept");
}

/// Issue 38: a link carries the view (side or 3D) and the camera. The link of a lab
/// in the side view with its camera moved opens a lab in the side view with the same
/// camera; `link --view side` makes such a link; bad values are one line.
#[test]
fn a_link_carries_the_view_and_the_camera() {
    let (_, first) = open_link("?scene=pendulum").unwrap();
    let mut lab = settings::open(&first, Store::in_dir(&scratch("view-a"))).unwrap().lab;
    lab.set_side_view(true);
    lab.camera.target = glam::Vec3::new(0.25, 1.5, -0.5);
    lab.camera.distance = 6.5;
    lab.camera_moved = true;
    let query = Link::of(&lab, false).unwrap();
    assert!(query.contains("&view=side"), "{query}");
    assert!(query.contains("&camera=0.25,1.5,-0.5,6.5,"), "{query}");
    let (link, again) = open_link(&query).unwrap();
    let mut copy = settings::open(&again, Store::in_dir(&scratch("view-b"))).unwrap().lab;
    assert!(!copy.side_view);
    link.view.apply(&mut copy);
    assert!(copy.side_view && copy.camera_moved);
    let (a, b) = (lab.camera, copy.camera);
    assert!(a.target.distance(b.target) < 1e-6 && (a.distance - b.distance).abs() < 1e-6, "{a:?} {b:?}");
    assert!((a.yaw - b.yaw).abs() < 1e-5 && (a.pitch - b.pitch).abs() < 1e-5, "{a:?} {b:?}");
    assert_eq!(a.orthographic, b.orthographic, "the side view's camera is parallel");

    let (out, err, code) = binary(&["link", "--scene", "pendulum", "--view", "side"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.trim().ends_with("&view=side"), "{out}");
    let (out, _, _) = binary(&["link", "--scene", "pendulum"]);
    assert!(out.trim().ends_with("&view=3d"), "{out}");
    let (_, err, code) = binary(&["link", "--scene", "pendulum", "--view", "top"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("side or 3d") && err.lines().count() == 1, "{err}");
    for bad in
        ["view=top", "camera=1,2,3", "camera=0,0,0,-1,0,0", "camera=0,0,0,5,0,120", "camera=a,b,c,d,e,f"]
    {
        let error = Link::parse(&pairs(&format!("?scene=pendulum&{bad}"))).unwrap_err();
        assert!(error.contains("invalid value") && !error.contains('\n'), "{bad}: {error}");
    }
}

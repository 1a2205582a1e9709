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
    let query = Link::of(&lab, true);
    assert!(query.starts_with("?scene=springForces&"), "{query}");
    let (link, again) = open_link(&query).unwrap();
    let mut copy = settings::open(&again, Store::in_dir(&scratch("copy-b"))).unwrap().lab;
    let params: Vec<_> = copy.scene.params().iter().map(|(p, v)| (p.name, v.to_bits())).collect();
    let wanted: Vec<_> = lab.scene.params().iter().map(|(p, v)| (p.name, v.to_bits())).collect();
    assert_eq!(params, wanted, "{query}");
    assert_eq!(copy.solver(), lab.solver(), "{query}");
    link.run_steps(&mut copy);
    assert_eq!(copy.state_hash(), lab.state_hash(), "{query}");
}

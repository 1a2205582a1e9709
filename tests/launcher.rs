//! A scene file's `[launcher]`: the projectile scene's launcher in the format. Its
//! rounds fly as the closed form says, a slider that moves only the aim does not
//! restart the scene, Fire works, a snapshot taken mid-flight reopens, and it fires by
//! itself only at the start of a headless run, unless `fire_at_start = false`.

use particle_lab::scenes::snapshot::Snapshot;
use particle_lab::scenes::{self, Scene, SceneAction, file};

const DT: f32 = 1.0 / 240.0;

/// A launcher over an open field beside one fixed post, its speed a slider.
const FIELD: &str = r#"
[scene]
name = "field"

[[param]]
name = "speed"
unit = "m/s"
default = 14
min = 0
max = 40

[[particle]]
position = [8, 1.5, 3]
radius = 0.3
fixed = true

[launcher]
position = [0, 1, 0]
speed = "speed"
angle = 40
mass = 2
radius = 0.2
target = 20
"#;

/// The field as a headless run starts it: its first round fired at step 0.
fn field() -> Box<dyn Scene> {
    let mut scene = file::load_text(FIELD, "field", None).expect("the field loads").create_default();
    assert!(scenes::fire_at_start(scene.as_mut()), "fire_at_start is true unless it says otherwise");
    scene
}

/// A read-out's value by its JSON name.
fn readout(scene: &dyn Scene, key: &str) -> Option<f64> {
    scene.readout_rows(DT).iter().flat_map(|row| row.values.iter()).find(|v| v.0 == key).map(|v| v.1)
}

fn run(scene: &mut dyn Scene, steps: usize) {
    for _ in 0..steps {
        scene.step(DT).expect("the field steps");
    }
}

/// The round fired at the start lands where the drag-free parabola says, to within
/// the semi-implicit Euler step's error; the landing is computed from the path, the
/// prediction from the launch values.
#[test]
fn the_first_round_lands_where_the_parabola_says() {
    let mut scene = field();
    assert_eq!(scene.info().actions.len(), 1, "a launcher gives the scene its Fire action");
    assert_eq!(readout(scene.as_ref(), "rounds_in_flight"), Some(1.0));
    run(scene.as_mut(), 600);
    assert_eq!(readout(scene.as_ref(), "rounds_in_flight"), Some(0.0), "the round landed and went");
    assert_eq!(scene.world().particles.len(), 1, "only the post is left");
    let range = readout(scene.as_ref(), "range_m").expect("a landing");
    // The closed form, here: from 1 m up at 14 m/s and 40 degrees under 9.81 m/s².
    let (g, v, h, a) = (9.81_f64, 14.0_f64, 1.0_f64, 40.0_f64.to_radians());
    let (vx, vy) = (v * a.cos(), v * a.sin());
    let exact = vx * (vy + (vy * vy + 2.0 * g * h).sqrt()) / g;
    assert!((range - exact).abs() < 0.01 * exact, "range {range} m against {exact} m");
    let predicted = readout(scene.as_ref(), "range_predicted_m").expect("a prediction");
    assert!((predicted - exact).abs() < 1e-4 * exact, "prediction {predicted} m against {exact} m");
}

/// Moving the speed slider changes the next round only: the round in flight and the
/// clock go on; Fire sends a second round at the new speed.
#[test]
fn a_speed_slider_aims_the_next_round_without_a_restart() {
    let mut scene = field();
    run(scene.as_mut(), 100);
    let before = (scene.world().time(), scene.world().particles.len());
    scene.set_param("speed", 30.0).expect("in range");
    assert_eq!((scene.world().time(), scene.world().particles.len()), before, "nothing restarted");
    assert!(scene.act(SceneAction::Fire));
    assert_eq!(readout(scene.as_ref(), "rounds_in_flight"), Some(2.0));
    let p = &scene.world().particles;
    let fastest = p.velocities().iter().map(|v| v.length()).fold(0.0_f32, f32::max);
    assert!((fastest - 30.0).abs() < 1e-4, "the new round leaves at 30 m/s, fastest is {fastest}");
    // A slider that changes the world (here g is in [scene] gravity only: applied at
    // once) keeps the clock too; the rounds fall by the new g.
    scene.set_param("g", 1.62).expect("in range");
    assert_eq!(scene.world().time(), before.0);
}

/// A snapshot taken while two rounds fly reopens with its rounds, flights and ghosts,
/// and runs on to the same state as the scene it was taken from.
#[test]
fn a_snapshot_mid_flight_reopens_and_runs_on_the_same() {
    let mut scene = field();
    run(scene.as_mut(), 120);
    assert!(scene.act(SceneAction::Fire));
    run(scene.as_mut(), 30);
    let snapshot = Snapshot::of(scene.as_ref(), DT).expect("a snapshot");
    let text = snapshot.to_json();
    let mut reopened = Snapshot::from_json(&text).expect("it reads back").restore().expect("it reopens");
    assert_eq!(readout(reopened.as_ref(), "rounds_in_flight"), Some(2.0));
    run(scene.as_mut(), 600);
    run(reopened.as_mut(), 600);
    assert_eq!(reopened.world().state_hash(), scene.world().state_hash());
    assert_eq!(readout(reopened.as_ref(), "range_m"), readout(scene.as_ref(), "range_m"));
}

/// Issue 37: built, a launcher fires nothing (the window waits for Fire, after a Reset
/// and after a slider that rebuilds the world too); a headless run fires one round at
/// step 0, once, and none with `fire_at_start = false`.
#[test]
fn a_launcher_fires_by_itself_only_at_the_start_of_a_headless_run() {
    let text = FIELD.replace(
        "[[particle]]",
        "[[param]]\nname = \"post\"\ndefault = 8\nmin = 1\nmax = 20\n\n[[particle]]",
    );
    let text = text.replace("position = [8, 1.5, 3]", "position = [\"post\", 1.5, 3]");
    let definition = file::load_text(&text, "field", None).expect("the field loads");
    let mut scene = definition.create_default();
    assert_eq!(scene.world().particles.len(), 1, "built: the post, no round");
    assert_eq!(readout(scene.as_ref(), "rounds_in_flight"), Some(0.0));
    // A slider that moves the post rebuilds the world: still no round.
    scene.set_param("post", 12.0).expect("in range");
    assert_eq!(scene.world().particles.len(), 1, "rebuilt: the post, no round");
    assert!(scenes::fires_at_start(scene.as_ref()));
    assert!(scenes::fire_at_start(scene.as_mut()));
    assert_eq!(readout(scene.as_ref(), "rounds_in_flight"), Some(1.0));
    assert!(!scenes::fire_at_start(scene.as_mut()), "once");
    // Not at a later step either, for a launcher that has not fired yet.
    let mut later = definition.create_default();
    run(later.as_mut(), 1);
    assert!(!scenes::fire_at_start(later.as_mut()), "only at step 0");
    // fire_at_start = false: a headless run waits for Fire as the window does.
    let quiet = text.replace("target = 20", "target = 20\nfire_at_start = false");
    let mut scene = file::load_text(&quiet, "field", None).expect("it loads").create_default();
    assert!(!scenes::fire_at_start(scene.as_mut()));
    assert_eq!(readout(scene.as_ref(), "rounds_in_flight"), Some(0.0));
    assert!(scene.act(SceneAction::Fire), "Fire still fires");
}

/// Bad launcher values are refused in one line naming the key.
#[test]
fn bad_launcher_values_are_refused_by_name() {
    let cases = [
        ("angle = 40", "angle = 120", "angle"),
        ("speed = \"speed\"", "speed = -1", "speed"),
        ("mass = 2", "mass = 0", "mass"),
    ];
    for (good, bad, key) in cases {
        let text = FIELD.replace(good, bad);
        let error = file::load_text(&text, "field", None).err().map(|e| e.to_string());
        let error = error.unwrap_or_else(|| panic!("{bad} was taken"));
        assert!(error.contains(key) && !error.contains('\n'), "{bad}: {error}");
    }
}

/// Paths that compare (issue 37): rounds fired at 30°, 45° and 60° are each labelled
/// with the angle, the one setting that differs; a second difference (the speed) joins
/// the labels; and Home frames every kept path's landing, not only the next round's.
#[test]
fn kept_paths_say_what_differs_and_home_frames_them_all() {
    let mut lab = particle_lab::ui::lab::Lab::new("projectile", &[]).unwrap();
    for angle in [30.0, 45.0, 60.0] {
        lab.set_param("angle", angle);
        lab.act(SceneAction::Fire);
        lab.run_steps(1000);
    }
    let labels = |lab: &particle_lab::ui::lab::Lab| {
        let mut out = Vec::new();
        lab.scene.labels(&mut out);
        out.into_iter().map(|(_, text)| text.to_string()).collect::<Vec<_>>()
    };
    let shown = labels(&lab);
    for angle in ["30°", "45°", "60°"] {
        assert!(shown.iter().any(|l| l == angle), "{angle} in {shown:?}");
    }
    // The next round at another speed: now both settings tell the paths apart.
    lab.set_param("speed", 15.0);
    lab.act(SceneAction::Fire);
    lab.run_steps(1000);
    let shown = labels(&lab);
    assert!(shown.iter().any(|l| l == "30° · 25 m/s"), "{shown:?}");
    assert!(shown.iter().any(|l| l == "60° · 15 m/s"), "{shown:?}");
    // Aim the next round short and near: Home still frames the 45° round, the longest.
    lab.set_param("angle", 80.0);
    lab.set_param("speed", 5.0);
    lab.home();
    let size = glam::Vec2::new(1280.0, 720.0);
    let mut points = Vec::new();
    lab.scene.framing_points(&mut points);
    let mut landings = Vec::new();
    lab.scene.markers(&mut landings);
    // The landing markers (red) of the kept flights.
    let landed: Vec<glam::Vec3> =
        landings.iter().filter(|m| m.color == [0.95, 0.25, 0.2]).map(|m| m.position).collect();
    assert_eq!(landed.len(), 4);
    for p in landed {
        assert!(points.contains(&p), "Home frames the landing at {p}");
        let s = lab.camera.project(p, size).expect("in front of the camera");
        assert!((0.0..=size.x).contains(&s.x) && (0.0..=size.y).contains(&s.y), "{p} drawn at {s}");
    }
}

//! Headless render tests on wgpu's adapter (Mesa's lavapipe on CI): every scene against a
//! reference image, plus checks of specific content.
//!
//! Set `UPDATE_GOLDEN=1` to rewrite the references in `tests/golden/`. On a mismatch the
//! test writes `<scene>-actual.png` and `<scene>-difference.png` next to the reference.

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::Vec2;
use particle_lab::capture::FrameCapture;
use particle_lab::render::offscreen::{read_png, write_png};
use particle_lab::scenes::SCENES;
use particle_lab::ui::Lab;

/// Not a multiple of 64 wide, so read-back has to unpad rows.
const SIZE: [u32; 2] = [400, 300];
const STEPS: u64 = 120;
/// A channel may differ by this much before the pixel counts as different.
const CHANNEL_TOLERANCE: u8 = 24;
/// Share of pixels allowed to differ.
const PIXEL_TOLERANCE: f64 = 0.005;

fn capture() -> FrameCapture {
    FrameCapture::new().unwrap_or_else(|e| {
        panic!("headless rendering needs a GPU adapter: {e}; 'bash scripts/test.sh' installs Mesa's lavapipe")
    })
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn pixel(image: &[u8], size: [u32; 2], x: u32, y: u32) -> [u8; 4] {
    let i = ((y * size[0] + x) * 4) as usize;
    [image[i], image[i + 1], image[i + 2], image[i + 3]]
}

fn differs(a: [u8; 4], b: [u8; 4], tolerance: u8) -> bool {
    a.iter().zip(&b).any(|(x, y)| x.abs_diff(*y) > tolerance)
}

/// Compares with the reference image; on a mismatch writes the actual image and a
/// difference image and fails.
fn compare_with_golden(name: &str, actual: &[u8], size: [u32; 2]) {
    let dir = golden_dir();
    let reference_path = dir.join(format!("{name}.png"));
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::create_dir_all(&dir).unwrap();
        write_png(&reference_path, size, actual).unwrap();
        return;
    }
    let (expected, expected_size) = read_png(&reference_path)
        .unwrap_or_else(|e| panic!("{e}; run with UPDATE_GOLDEN=1 to create the reference"));
    assert_eq!(expected_size, size, "{name}: reference has another size");
    let mut difference = Vec::with_capacity(actual.len());
    let mut different = 0usize;
    for (a, e) in actual.chunks_exact(4).zip(expected.chunks_exact(4)) {
        let (a, e) = ([a[0], a[1], a[2], a[3]], [e[0], e[1], e[2], e[3]]);
        if differs(a, e, CHANNEL_TOLERANCE) {
            different += 1;
        }
        for c in 0..3 {
            difference.push(a[c].abs_diff(e[c]).saturating_mul(4));
        }
        difference.push(255);
    }
    let share = different as f64 / f64::from(size[0] * size[1]);
    if share > PIXEL_TOLERANCE {
        write_png(&dir.join(format!("{name}-actual.png")), size, actual).unwrap();
        write_png(&dir.join(format!("{name}-difference.png")), size, &difference).unwrap();
        panic!(
            "{name}: {:.2}% of pixels differ from {} (allowed {:.2}%); wrote {name}-actual.png and \
             {name}-difference.png beside it",
            share * 100.0,
            reference_path.display(),
            PIXEL_TOLERANCE * 100.0
        );
    }
}

#[test]
fn every_scene_matches_its_reference_image() {
    let mut capture = capture();
    for entry in SCENES {
        let mut lab = Lab::new(&entry.info().name, &[]).unwrap();
        // As `render` draws it: the projectile's round fired at step 0.
        lab.fire_at_start();
        lab.run_steps_recorded(STEPS);
        let image = capture.render(&mut lab, SIZE, false).unwrap();
        assert_eq!(image.len(), (SIZE[0] * SIZE[1] * 4) as usize);
        compare_with_golden(&entry.info().name, &image, SIZE);
    }
}

/// The way for GPUs without vertex storage (WebGL2): spheres as instances. It draws
/// every scene as the storage path does, pixel for pixel up to rasteriser rounding, and
/// so matches the same reference images.
#[test]
fn spheres_drawn_as_instances_look_as_spheres_read_from_storage() {
    use particle_lab::render::SpherePath;
    let mut storage = FrameCapture::with_sphere_path(Some(SpherePath::Storage)).unwrap();
    let mut instanced = FrameCapture::with_sphere_path(Some(SpherePath::Instanced)).unwrap();
    for entry in SCENES {
        let mut lab = Lab::new(&entry.info().name, &[]).unwrap();
        lab.fire_at_start();
        lab.run_steps_recorded(STEPS);
        let a = storage.render(&mut lab, SIZE, false).unwrap();
        let b = instanced.render(&mut lab, SIZE, false).unwrap();
        let different = a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(a, b)| a != b).count();
        assert!(
            different * 1000 < a.len() / 4,
            "{}: {different} pixels differ between the paths",
            entry.info().name
        );
        let spheres = a.chunks_exact(4).filter(|p| p[0] > 100 || p[1] > 100 || p[2] > 100).count();
        assert!(spheres > 0, "{}: something bright (a sphere) is drawn", entry.info().name);
        compare_with_golden(&entry.info().name, &b, SIZE);
    }
}

#[test]
fn the_falling_pile_is_coloured_by_speed() {
    let mut capture = capture();
    let mut lab = Lab::new("pile", &[]).unwrap();
    assert!(lab.view.color_by_speed, "the pile opens coloured by speed");
    // Mid-fall: spheres from rest at the bottom to several m/s at the top.
    lab.run_steps_recorded(45);
    let image = capture.render(&mut lab, SIZE, false).unwrap();
    compare_with_golden("pile-falling", &image, SIZE);
    // The highest sphere falls fastest: drawn at the hot end of the ramp.
    let particles = &lab.scene.world().particles;
    let top = (0..particles.len())
        .max_by(|&a, &b| particles.positions()[a].y.total_cmp(&particles.positions()[b].y))
        .unwrap();
    let speed = particles.velocities()[top].length();
    assert!(speed > 5.0, "the top sphere falls at {speed} m/s");
    let size = Vec2::new(SIZE[0] as f32, SIZE[1] as f32);
    let screen = lab.camera.project(particles.positions()[top], size).unwrap();
    let [r, g, b, _] = pixel(&image, SIZE, screen.x.round() as u32, screen.y.round() as u32);
    assert!(r > g && r > b + 80, "a sphere at {speed} m/s is drawn ({r}, {g}, {b}), not red");
}

#[test]
fn each_particle_is_drawn_where_the_camera_projects_it() {
    let mut capture = capture();
    for entry in SCENES {
        let mut lab = Lab::new(&entry.info().name, &[]).unwrap();
        lab.fire_at_start();
        lab.run_steps_recorded(STEPS);
        let size = Vec2::new(SIZE[0] as f32, SIZE[1] as f32);
        // The first particle in sight: picking at its projected centre finds it (in a
        // pile most are hidden behind others).
        let particles = &lab.scene.world().particles;
        let i = (0..particles.len())
            .find(|&i| {
                let screen = lab.camera.project(particles.positions()[i], size);
                screen.is_some_and(|s| lab.pick(s, size) == particles.id(i))
            })
            .unwrap_or_else(|| panic!("{}: no particle in sight", entry.info().name));
        let (id, centre, radius) = (particles.ids()[i], particles.positions()[i], particles.radii()[i]);
        let screen = lab.camera.project(centre, size).unwrap();
        let (x, y) = (screen.x.round() as u32, screen.y.round() as u32);
        assert!(x < SIZE[0] && y < SIZE[1], "{}: particle {i} is off screen at {screen}", entry.info().name);
        // Only the particle's own colour changes when it is highlighted (yellow), so a
        // pixel that turns yellow at its projected centre is the sphere itself.
        let plain = capture.render(&mut lab, SIZE, false).unwrap();
        lab.hovered = Some(id);
        let lit = capture.render(&mut lab, SIZE, false).unwrap();
        lab.hovered = None;
        let (before, after) = (pixel(&plain, SIZE, x, y), pixel(&lit, SIZE, x, y));
        assert!(differs(before, after, 30), "{}: ({x}, {y}) is {before:?} either way", entry.info().name);
        assert!(
            after[0] > 120 && after[1] > 100 && after[2] + 40 < after[0],
            "{}: not yellow: {after:?}",
            entry.info().name
        );
        // Well outside the highlighted sphere (1.15 r) nothing changed colour.
        let edge = lab.camera.project(centre + lab.camera.right() * radius * 3.0, size).unwrap();
        let (ex, ey) = (edge.x.round() as u32, edge.y.round() as u32);
        if ex < SIZE[0] && ey < SIZE[1] {
            let (b, a) = (pixel(&plain, SIZE, ex, ey), pixel(&lit, SIZE, ex, ey));
            assert!(!differs(b, a, 8), "{}: ({ex}, {ey}) outside the sphere changed", entry.info().name);
        }
    }
}

#[test]
fn the_ui_draws_a_panel_over_the_scene() {
    let mut capture = capture();
    let size = [900, 600];
    let mut lab = Lab::new("bridge", &[]).unwrap();
    lab.run_steps_recorded(STEPS);
    let bare = capture.render(&mut lab, size, false).unwrap();
    let with_ui = capture.render(&mut lab, size, true).unwrap();
    // The left panel and the menu bar cover what the bare frame shows there.
    let mut covered = 0;
    let mut total = 0;
    for y in (40..size[1]).step_by(7) {
        for x in (0..200).step_by(7) {
            total += 1;
            if differs(pixel(&bare, size, x, y), pixel(&with_ui, size, x, y), 8) {
                covered += 1;
            }
        }
    }
    assert!(covered as f64 > 0.5 * total as f64, "panel covers only {covered} of {total} samples");
    // The menu bar runs across the top, over the sky.
    let top = (300..size[0])
        .step_by(20)
        .filter(|&x| differs(pixel(&bare, size, x, 8), pixel(&with_ui, size, x, 8), 8));
    assert!(top.count() > 20, "no menu bar across the top");
}

/// Issue 40, "big renders within the memory they need": a frame larger than a tile is
/// drawn tile by tile, each with its piece of the view's projection and of the panel.
/// Drawn in tiles of 97 pixels (so that tiles cut through spheres, links, the grid and
/// the panel's text, and the last tile of a row overlaps the one before it), the frame
/// must look as the same frame drawn whole.
#[test]
fn a_frame_drawn_in_tiles_looks_as_the_frame_drawn_whole() {
    let size = [333, 217];
    for with_ui in [false, true] {
        let mut whole_capture = capture();
        let mut tiled_capture = capture();
        tiled_capture.set_tile_side(97);
        let plan = tiled_capture.plan(size);
        assert_eq!(plan.target, [97, 97]);
        assert_eq!(plan.tiles.len(), 4 * 3, "{plan:?}");
        assert!(plan.tiles.contains(&[333 - 97, 217 - 97]), "the last tile ends at the corner: {plan:?}");
        let mut lab = Lab::new("bridge", &[]).unwrap();
        lab.run_steps_recorded(STEPS);
        let whole = whole_capture.render(&mut lab, size, with_ui).unwrap();
        let tiled = tiled_capture.render(&mut lab, size, with_ui).unwrap();
        assert_eq!(tiled_capture.target_size(), Some([97, 97]), "no target larger than a tile");
        assert_eq!(whole.len(), tiled.len());
        let different = whole
            .chunks_exact(4)
            .zip(tiled.chunks_exact(4))
            .filter(|(a, b)| differs([a[0], a[1], a[2], a[3]], [b[0], b[1], b[2], b[3]], CHANNEL_TOLERANCE))
            .count();
        let share = different as f64 / f64::from(size[0] * size[1]);
        if share > PIXEL_TOLERANCE {
            let dir = std::env::temp_dir();
            write_png(&dir.join("particle-lab-tiled.png"), size, &tiled).unwrap();
            write_png(&dir.join("particle-lab-whole.png"), size, &whole).unwrap();
        }
        assert!(
            share <= PIXEL_TOLERANCE,
            "with_ui {with_ui}: {:.2}% of pixels differ between the tiled and the whole frame (written to \
             the temp folder)",
            share * 100.0
        );
        // And the frame is not blank: the bridge's spheres are in it.
        let distinct: std::collections::HashSet<_> =
            tiled.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect();
        assert!(distinct.len() > 100, "only {} colours", distinct.len());
    }
}

/// Issue 40: `render --size 8192x8192` (the largest size it takes) peaked at 3 GB. In
/// tiles it stays under 1.5 GB, as the kernel counts the process's resident memory
/// (its peak, `ru_maxrss`, read with `wait4`).
#[test]
fn the_largest_render_stays_under_one_and_a_half_gigabytes() {
    let dir = std::env::temp_dir().join(format!("particle-lab-big-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("big.png");
    let child = binary()
        .args(["render", "--scene", "bridge", "--steps", "60", "--size", "8192x8192", "--ui", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid value of that plain C struct, and wait4 writes
    // only into the two places it is given, for our own child, which is not waited on
    // by anything else (the Child handle is dropped without a wait).
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let waited = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    drop(child);
    assert_eq!(waited, pid, "wait4 failed");
    assert!(libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0, "render failed: status {status}");
    // On Linux ru_maxrss is in kilobytes.
    let peak_mb = usage.ru_maxrss as f64 / 1024.0;
    let (pixels, size) = read_png(&out).unwrap();
    assert_eq!(size, [8192, 8192]);
    // Not a blank image: the spheres, links, grid and panel give it many colours.
    let distinct: std::collections::HashSet<_> =
        pixels.chunks_exact(4).step_by(97).map(|p| [p[0], p[1], p[2]]).collect();
    assert!(distinct.len() > 100, "only {} colours", distinct.len());
    drop(pixels);
    std::fs::remove_dir_all(&dir).ok();
    assert!(peak_mb < 1536.0, "render --size 8192x8192 peaked at {peak_mb:.0} MB");
    // And it did need the image itself (256 MB): the figure is the whole process's.
    assert!(peak_mb > 256.0, "a peak of {peak_mb:.0} MB cannot hold the 256 MB image");
}

/// Issue 38: a scene file's `[[wall]]` was not drawn at all (only a ball's trail showed
/// the slope). A ramp is drawn: the frame with it differs from the same scene without
/// it, along a band that runs down the slope, in 3D and in the side view.
#[test]
fn a_scene_files_wall_is_drawn_in_3d_and_in_the_side_view() {
    let dir = std::env::temp_dir().join(format!("particle-lab-wall-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let ball = "[scene]\nname = \"ramp\"\n\n[[particle]]\nposition = [0, 2, 0]\nradius = 0.2\n";
    let ramp = "\n[[wall]]\nnormal = [0.5, 1, 0]\npoint = [0, 0.5, 0]\n";
    let bare_file = dir.join("bare.toml");
    let ramp_file = dir.join("ramp.toml");
    std::fs::write(&bare_file, ball).unwrap();
    std::fs::write(&ramp_file, format!("{ball}{ramp}")).unwrap();
    for view in [None, Some("side")] {
        let frame = |file: &Path, name: &str| {
            let out = dir.join(name);
            let mut command = binary();
            command.args(["render", "--steps", "1", "--size", "320x240", "--scene-file"]).arg(file);
            if let Some(view) = view {
                command.args(["--view", view]);
            }
            let result = command.arg("--out").arg(&out).output().unwrap();
            assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
            read_png(&out).unwrap()
        };
        let (bare, size) = frame(&bare_file, "bare.png");
        let (with_wall, _) = frame(&ramp_file, "ramp.png");
        let differ = |x: u32, y: u32| differs(pixel(&bare, size, x, y), pixel(&with_wall, size, x, y), 8);
        let different =
            (0..size[1]).flat_map(|y| (0..size[0]).map(move |x| (x, y))).filter(|&(x, y)| differ(x, y));
        let different: Vec<(u32, u32)> = different.collect();
        assert!(different.len() > 200, "{view:?}: the wall changed only {} pixels", different.len());
        // A line across a slope, not a spot: what it changed spans most of the frame's
        // width.
        let (left, right) = different.iter().fold((u32::MAX, 0), |(l, r), &(x, _)| (l.min(x), r.max(x)));
        assert!(right - left > size[0] / 2, "{view:?}: the wall spans x {left} to {right} only");
    }
    std::fs::remove_dir_all(&dir).ok();
}

fn binary() -> Command {
    Command::new(env!("CARGO_BIN_EXE_particle-lab"))
}

#[test]
fn render_command_writes_a_png_of_any_size() {
    let dir = std::env::temp_dir().join(format!("particle-lab-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("odd.png");
    let result = binary()
        .args([
            "render",
            "--scene",
            "springForces",
            "--set",
            "k=50",
            "--steps",
            "30",
            "--size",
            "333x217",
            "--ui",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let (pixels, size) = read_png(&out).unwrap();
    assert_eq!(size, [333, 217]);
    assert_eq!(pixels.len(), 333 * 217 * 4);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_command_rejects_bad_input_with_exit_code_2() {
    for (args, word) in [
        (vec!["render", "--scene", "bridge", "--size", "0x100", "--out", "x.png"], "0x100"),
        (vec!["render", "--scene", "bridge", "--size", "big", "--out", "x.png"], "big"),
        (vec!["render", "--scene", "bridge", "--out", "x.jpg"], "png"),
        (vec!["render", "--scene", "nope", "--out", "x.png"], "valid scenes"),
        (vec!["render", "--scene", "bridge", "--set", "g=-1", "--out", "x.png"], "range"),
    ] {
        let result = binary().args(&args).output().unwrap();
        assert_eq!(result.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(word), "{args:?}: {stderr}");
    }
}

#[test]
fn without_a_gpu_adapter_it_says_what_to_install() {
    // Ask wgpu for a backend this platform does not have: no adapter at all.
    let result = binary()
        .env("WGPU_BACKEND", "dx12")
        .args(["render", "--scene", "bridge", "--out", "never.png"])
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&result.stderr);
    let last = stderr.trim_end().lines().last().unwrap_or("");
    assert!(last.contains("no GPU adapter") && last.contains("mesa-vulkan-drivers"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!Path::new("never.png").exists());
}

#[test]
fn swept_paths_show_how_far_a_fast_round_went_in_the_last_step() {
    use particle_lab::render::{FrameBuilder, ViewOptions};
    let set = ["speed=150".to_string(), "angle=10".to_string()];
    let mut scene = particle_lab::scenes::build("projectile", &set).unwrap();
    assert!(particle_lab::scenes::fire_at_start(scene.as_mut()));
    for _ in 0..3 {
        scene.step(1.0 / 60.0).unwrap();
    }
    let mut builder = FrameBuilder::default();
    let options = ViewOptions { trails: false, swept: false, ..ViewOptions::default() };
    let without = builder.build(scene.as_ref(), None, 0.0, options, None).clone();
    let with = builder.build(scene.as_ref(), None, 0.0, ViewOptions { swept: true, ..options }, None).clone();
    assert!(without.trails.is_empty());
    assert_eq!(with.trails.len(), 1, "one band for the one fast round");
    let (p, moved) = (scene.world().particles.positions()[0], scene.world().last_motion()[0]);
    // At 150 m/s a step of 1/60 s carries the round 2.5 m, eight times its radius.
    assert!((moved.length() - 2.5).abs() < 0.1, "{moved}");
    let band = with.trails[0];
    assert_eq!(band.to, p.to_array());
    assert!((glam::Vec3::from(band.from) - (p - moved)).length() < 1e-5);
    // And a ghost where it started, besides the round and the launcher's markers.
    assert_eq!(with.spheres.len(), without.spheres.len() + 1);
}

/// The lab's tools against reference frames: free-body arrows on the springForces bob,
/// contacts and link limits in the cradle, links coloured by tension on the bridge, the
/// 2D side view of a projectile's flight with its markers and target, and a compared
/// copy drawn as magenta ghosts.
#[test]
fn the_lab_tools_match_their_reference_images() {
    use particle_lab::physics::Integrator;
    use particle_lab::ui::compare::Change;
    let mut capture = capture();
    let cases: [(&str, &str, &[&str], u64); 5] = [
        ("tools-forces", "springForces", &["forces"], 120),
        ("tools-contacts", "cradle", &["contacts"], 60),
        ("tools-tension", "bridge", &["tension", "contacts"], 120),
        ("tools-side-view", "projectile", &["side"], 500),
        ("tools-follow", "projectile", &["follow"], 200),
    ];
    for (name, scene, options, steps) in cases {
        let mut lab = Lab::new(scene, &[]).unwrap();
        for option in options {
            lab.set_view_option(option).unwrap();
        }
        if name == "tools-forces" {
            lab.select(Some(particle_lab::physics::ParticleId(0)));
        }
        // A flight to draw: the projectile's round, fired at step 0 as `render` fires it.
        lab.fire_at_start();
        lab.run_steps_recorded(steps);
        let image = capture.render(&mut lab, SIZE, false).unwrap();
        compare_with_golden(name, &image, SIZE);
    }

    let mut lab = Lab::new("springForces", &["k=80".into()]).unwrap();
    lab.start_compare(Change::Integrator(Integrator::ExplicitEuler));
    lab.run_steps_recorded(600);
    let image = capture.render(&mut lab, SIZE, false).unwrap();
    compare_with_golden("tools-compare", &image, SIZE);
    // The copy's free spring, whose ends explicit Euler swings ever wider (11 cm apart
    // from the original's after 2.5 s), is a magenta ghost. (The stiff spring takes its
    // closed-form step under every integrator, so its copy stays where the original is.)
    let copy = lab.compare.as_ref().unwrap().scene.world();
    let ghost = copy.particles.positions()[1];
    let ours = lab.scene.world().particles.positions()[1];
    assert!(ghost.distance(ours) > 0.05, "the copies differ: {ghost} vs {ours}");
    assert!(copy.particles.positions()[5].distance(lab.scene.world().particles.positions()[5]) < 1e-3);
    let size = Vec2::new(SIZE[0] as f32, SIZE[1] as f32);
    // On the ghost's far side from the original, where only the ghost is drawn.
    let radius = copy.particles.radii()[1];
    let far_side = ghost + (ghost - ours).normalize() * radius * 0.8;
    let at = lab.camera.project(far_side, size).unwrap();
    let [r, g, b, _] = pixel(&image, SIZE, at.x.round() as u32, at.y.round() as u32);
    assert!(r > g + 30 && b > g + 30, "the copy's ghost is drawn ({r}, {g}, {b}), not magenta");
}

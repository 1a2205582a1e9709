//! Finite walls (issue 38, "Walls are finite and always drawn"): a `[[wall]]` with a
//! `size` is a rectangle of its plane. A ball rolls down a ramp and falls off its end
//! (where the unbounded plane would carry it on), a ball beside a wall falls past it,
//! and a ball behind one passes through from behind — with both solvers.

use particle_lab::physics::{Plane, SolverKind, SolverSettings};
use particle_lab::scenes::file;

/// A ball on a ramp from (-3, 3) down to (0, 1.5), 2 m wide, over the ground; the
/// ramp's friction (0.1) is under the slope's tangent (0.5), so the ball slides.
fn ramp(finite: bool, ball_z: f32) -> String {
    // The ramp's plane: through (-1.5, 2.25), sloping down by 1.5 over 3 m.
    let size = if finite { "size = [3.3541, 2]\n" } else { "" };
    format!(
        "[scene]\nname = \"ramp\"\n\n[[particle]]\nposition = [-2.7, 3.0, {ball_z}]\nradius = 0.1\n\n\
         [ground]\n\n[[wall]]\nnormal = [0.5, 1, 0]\npoint = [-1.5, 2.25, 0]\nfriction = 0.1\n{size}"
    )
}

/// Runs `text` for `steps` at 240 Hz with `solver`; the ball's path.
fn path(text: &str, solver: SolverKind, steps: usize) -> Vec<glam::Vec3> {
    let entry = file::load_text(text, "ramp", None).unwrap_or_else(|e| panic!("{e}"));
    let mut scene = entry.create_default();
    let settings = SolverSettings { kind: solver, ..SolverSettings::default() };
    scene.world_mut().set_solver(settings).unwrap();
    let dt = entry.info().dt;
    (0..steps)
        .map(|_| {
            scene.step(dt).unwrap();
            scene.world().particles.positions()[0]
        })
        .collect()
}

/// Height of the ramp's plane above x (m).
fn plane_y(x: f32) -> f32 {
    2.25 - 0.5 * (x + 1.5)
}

#[test]
fn a_ball_rolls_down_a_finite_ramp_and_falls_off_its_end() {
    for solver in [SolverKind::Soft, SolverKind::Paper] {
        let finite = path(&ramp(true, 0.0), solver, 960);
        let endless = path(&ramp(false, 0.0), solver, 960);
        // On the ramp it rests on the plane, as on the unbounded one.
        let on = finite.iter().find(|p| p.x > -2.0 && p.x < -0.5).expect("it rolls down the ramp");
        assert!((on.y - 0.1 - plane_y(on.x)).abs() < 0.05, "{solver:?}: {on} is not on the ramp");
        // Past the end (x = 0) the finite ramp lets it fall: 0.8 m on, a ball leaving at
        // 4 to 5 m/s has dropped 0.15 m or so below the plane's line (g x² / 2 v²).
        let past = finite.iter().find(|p| p.x > 0.8).expect("it leaves the ramp");
        assert!(plane_y(past.x) + 0.1 - past.y > 0.05, "{solver:?}: still on the ramp's line at {past}");
        let last = finite.last().unwrap();
        assert!((last.y - 0.1).abs() < 0.05, "{solver:?}: it ends on the ground, at {last}");
        // The unbounded plane carries it on down its line instead.
        let carried = endless.iter().filter(|p| p.x > 0.2 && p.x < 2.4);
        assert!(carried.clone().count() > 10, "{solver:?}: it went on past the end");
        for p in carried {
            assert!((p.y - 0.1 - plane_y(p.x)).abs() < 0.05, "{solver:?}: the unbounded ramp let go at {p}");
        }
    }
}

#[test]
fn a_ball_beside_a_finite_wall_falls_past_it() {
    // Dropped 1.5 m to the side of the 2 m wide ramp: it falls straight to the ground.
    for solver in [SolverKind::Soft, SolverKind::Paper] {
        let beside = path(&ramp(true, 1.5), solver, 480);
        let last = beside.last().unwrap();
        assert!((last.y - 0.1).abs() < 0.02 && (last.x + 2.7).abs() < 1e-3, "{solver:?}: {last}");
    }
}

#[test]
fn a_wall_is_only_over_its_rectangle_and_on_its_free_side() {
    let plane = Plane::new(glam::Vec3::Y, glam::Vec3::ZERO, 0.3, 0.5)
        .unwrap()
        .with_extent(glam::Vec3::new(1.0, 5.0, 0.0), glam::Vec3::X, 4.0, 2.0)
        .unwrap();
    // Its centre is the point's foot on the plane.
    assert_eq!(plane.extent.unwrap().center, glam::Vec3::new(1.0, 0.0, 0.0));
    let covered = |x: f32, y: f32, z: f32| plane.covers(glam::Vec3::new(x, y, z));
    assert!(covered(1.0, 0.1, 0.0) && covered(2.99, 0.1, 0.99) && covered(-0.99, 0.1, -0.99));
    assert!(!covered(3.01, 0.1, 0.0) && !covered(1.0, 0.1, 1.01) && !covered(-1.01, 0.1, 0.0));
    assert!(!covered(1.0, -0.01, 0.0), "behind it");
    // Unusable sizes and directions are refused with the reason.
    let base = Plane::new(glam::Vec3::Y, glam::Vec3::ZERO, 0.3, 0.5).unwrap();
    assert!(base.with_extent(glam::Vec3::ZERO, glam::Vec3::X, 0.0, 1.0).is_err());
    assert!(base.with_extent(glam::Vec3::ZERO, glam::Vec3::Y, 1.0, 1.0).is_err(), "along the normal");
    assert!(base.with_extent(glam::Vec3::NAN, glam::Vec3::X, 1.0, 1.0).is_err());
}

#[test]
fn a_bad_wall_size_is_one_line_at_its_place() {
    for (size, expected) in [("[3]", "expected two lengths"), ("[3, -1]", "width"), ("[0, 1]", "length")] {
        let text = ramp(false, 0.0) + &format!("size = {size}\n");
        let Err(error) = file::load_text(&text, "ramp.toml", None) else { panic!("{size} was accepted") };
        let error = error.to_string();
        assert!(error.starts_with("ramp.toml:") && error.contains(expected), "{size}: {error}");
    }
    let text = ramp(true, 0.0) + "along = [0.5, 1, 0]\n";
    let Err(error) = file::load_text(&text, "ramp.toml", None) else {
        panic!("along the normal was accepted")
    };
    let error = error.to_string();
    assert!(error.contains("along"), "{error}");
}

/// A finite wall is drawn as its rectangle: every line the view draws for it (the
/// scene's outlines, which the renderer draws in both views and in `render`) lies on
/// its plane and within its rectangle; an unbounded wall's patch reaches beyond.
#[test]
fn a_finite_wall_is_drawn_as_its_rectangle() {
    for (finite, within) in [(true, true), (false, false)] {
        let entry = file::load_text(&ramp(finite, 0.0), "ramp", None).unwrap();
        let scene = entry.create_default();
        let mut lines = Vec::new();
        scene.outlines(&mut lines);
        assert!(!lines.is_empty(), "the wall is drawn");
        let plane = *scene.world().planes().find(|p| p.normal != glam::Vec3::Y).unwrap();
        // The ramp's rectangle, worked out from the file: centred on (-1.5, 2.25, 0),
        // 3.3541 m down the slope, 2 m along z.
        let down = glam::Vec3::new(1.0, -0.5, 0.0).normalize();
        let centre = glam::Vec3::new(-1.5, 2.25, 0.0);
        let inside = |p: glam::Vec3| {
            let d = p - centre;
            d.dot(down).abs() <= 3.3541 / 2.0 + 1e-3 && d.z.abs() <= 1.0 + 1e-3
        };
        for &(a, b) in &lines {
            for p in [a, b] {
                assert!(plane.distance(p).abs() < 1e-3, "{p} is off the wall's plane");
            }
        }
        let all_inside = lines.iter().all(|&(a, b)| inside(a) && inside(b));
        assert_eq!(all_inside, within, "finite {finite}: lines {lines:?}");
    }
}

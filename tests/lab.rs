//! The lab behind the panel: fixed-step timing, picking and dragging particles.

use std::time::Instant;

use glam::Vec2;
use particle_lab::scenes::{self, SCENES, SceneAction};
use particle_lab::ui::Lab;
use particle_lab::ui::lab::{MAX_STEPS_PER_FRAME, MSAA_LIMIT, PHYSICS_BUDGET, READOUT_INTERVAL};

#[test]
fn frames_run_whole_fixed_steps_and_carry_the_remainder() {
    let mut lab = Lab::new("bridge", &[]).unwrap();
    let dt = f64::from(lab.dt());
    // 2.5 steps of time: 2 now, the half carried over, so the next 0.5 makes a third.
    lab.advance_by(2.5 * dt);
    assert_eq!(lab.scene.world().steps(), 2);
    lab.advance_by(0.5 * dt);
    assert_eq!(lab.scene.world().steps(), 3);
    // The physics rate is independent of the frame rate: 1 s of frames at any rate
    // gives 240 steps at 240 Hz.
    let mut lab = Lab::new("bridge", &[]).unwrap();
    for _ in 0..60 {
        lab.advance_by(1.0 / 60.0);
    }
    let steps = lab.scene.world().steps();
    assert!((239..=240).contains(&steps), "{steps} steps in 1 s at 240 Hz");
}

#[test]
fn a_stall_drops_time_instead_of_spiralling() {
    let mut lab = Lab::new("bridge", &[]).unwrap();
    // At 1000 Hz even the capped 0.1 s of a stall is 100 steps: more than a frame may run.
    lab.physics_rate = 1000.0;
    lab.advance_by(5.0);
    let steps = lab.scene.world().steps();
    assert_eq!(steps, u64::from(MAX_STEPS_PER_FRAME), "after a 5 s stall");
    assert!(lab.stats.dropped_steps >= 30, "dropped {}", lab.stats.dropped_steps);
    // The next normal frame runs a normal number of steps, not a backlog.
    lab.advance_by(1.0 / 60.0);
    assert!(lab.stats.steps_last_frame <= 17, "backlog of {} steps", lab.stats.steps_last_frame);
}

#[test]
fn pause_and_time_scale() {
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.paused = true;
    lab.advance_by(0.5);
    assert_eq!(lab.scene.world().steps(), 0, "paused");
    lab.run_steps(1);
    assert_eq!(lab.scene.world().steps(), 1, "Step runs one step while paused");
    lab.paused = false;
    lab.time_scale = 0.5;
    let dt = f64::from(lab.dt());
    lab.advance_by(0.05);
    assert_eq!(lab.scene.world().steps(), 1 + (0.025 / dt).floor() as u64, "half speed");
}

#[test]
fn reset_keeps_parameters_and_switching_scenes_works() {
    let mut lab = Lab::new("projectile", &["g=7".into()]).unwrap();
    lab.act(SceneAction::Fire);
    lab.run_steps(10);
    lab.reset();
    assert_eq!(lab.scene.world().steps(), 0);
    assert_eq!(lab.scene.params().get("g"), 7.0, "reset keeps the user's settings");
    assert_eq!(lab.scene.world().particles.len(), 0, "no round until the user fires (issue 37)");
    for entry in particle_lab::scenes::SCENES {
        lab.switch_scene(entry);
        assert_eq!(lab.entry.info().name, entry.info().name);
        assert_eq!(lab.view.trails, entry.info().trails);
    }
}

/// Issue 37: the projectile fired a round by itself when it opened and on Reset, while
/// the view said "Press F". In the window nothing flies until the user fires: not on
/// opening, not while it runs, not after Reset, Restore defaults or a switch of scene;
/// Fire sends one round.
#[test]
fn the_window_fires_nothing_until_the_user_fires() {
    let in_flight = |lab: &Lab| {
        let values = lab.scene.readout_values(lab.dt());
        let rounds = values.iter().find(|(key, _)| *key == "rounds_in_flight").expect("the read-out").1;
        assert_eq!(rounds as usize, lab.scene.world().particles.len(), "every particle is a round");
        rounds
    };
    let mut lab = Lab::new("projectile", &[]).unwrap();
    assert_eq!(in_flight(&lab), 0.0, "just opened");
    lab.run_steps(240);
    assert_eq!(in_flight(&lab), 0.0, "a second later");
    lab.act(SceneAction::Fire);
    assert_eq!(in_flight(&lab), 1.0, "Fire sends one round");
    lab.run_steps(60);
    assert_eq!(in_flight(&lab), 1.0);
    lab.reset();
    assert_eq!((lab.scene.world().steps(), in_flight(&lab)), (0, 0.0), "after Reset");
    lab.run_steps(240);
    assert_eq!(in_flight(&lab), 0.0, "a second after Reset");
    lab.act(SceneAction::Fire);
    assert_eq!(in_flight(&lab), 1.0, "Fire after Reset");
    lab.restore_defaults();
    assert_eq!(in_flight(&lab), 0.0, "after Restore defaults");
    lab.switch_scene(scenes::find("bridge").unwrap());
    lab.switch_scene(scenes::find("projectile").unwrap());
    assert_eq!(in_flight(&lab), 0.0, "after switching back to it");
}

#[test]
fn a_bad_slider_value_is_refused_with_a_message() {
    let mut lab = Lab::new("bridge", &[]).unwrap();
    lab.set_param("g", 1000.0);
    assert_eq!(lab.scene.params().get("g"), 9.81);
    assert!(lab.status.contains("out of range"), "{}", lab.status);
}

#[test]
fn picking_finds_the_particle_under_the_pointer_and_dragging_moves_it() {
    let mut lab = Lab::new("bridge", &["g=0".into()]).unwrap();
    let size = Vec2::new(800.0, 600.0);
    let target = lab.scene.world().particles.positions()[3];
    let id = lab.scene.world().particles.id(3).unwrap();
    let pixel = lab.camera.project(target, size).unwrap();
    assert_eq!(lab.pick(pixel, size), Some(id));
    assert_eq!(lab.pick(Vec2::new(5.0, 5.0), size), None, "nothing in the sky corner");
    assert!(lab.start_grab(pixel, size));
    // Drag it 60 pixels up the screen and let the physics follow.
    lab.move_grab(pixel - Vec2::new(0.0, 60.0), size);
    let goal = lab.grab.unwrap().target;
    assert!(goal.y > target.y + 0.1, "the drag target rose: {goal}");
    lab.run_steps(30);
    let index = lab.scene.world().particles.index(id).unwrap();
    let now = lab.scene.world().particles.positions()[index];
    assert!(now.distance(goal) < now.distance(target) + 1e-3, "it moved towards the pointer: {now}");
    assert!(now.y > target.y, "{now} vs {target}");
    lab.end_grab();
    assert!(lab.grab.is_none());
    assert!(lab.scene.world().is_finite());
}

#[test]
fn dragging_while_paused_moves_the_particle_at_once() {
    let mut lab = Lab::new("springForces", &[]).unwrap();
    lab.paused = true;
    let size = Vec2::new(800.0, 600.0);
    let start = lab.scene.world().particles.positions()[0];
    let pixel = lab.camera.project(start, size).unwrap();
    assert!(lab.start_grab(pixel, size));
    lab.move_grab(pixel + Vec2::new(40.0, 0.0), size);
    let now = lab.scene.world().particles.positions()[0];
    assert!(now.distance(start) > 0.3, "moved from {start} to {now}");
    assert_eq!(lab.scene.world().steps(), 0, "no physics ran");
}

#[test]
fn colour_by_speed_defaults_to_the_scene_on_opening_and_switching() {
    for entry in SCENES {
        let lab = Lab::new(&entry.info().name, &[]).unwrap();
        assert_eq!(lab.view.color_by_speed, entry.info().color_by_speed, "{} opened", entry.info().name);
    }
    let pile = scenes::find("pile").unwrap();
    assert!(pile.info().color_by_speed, "the pile is the scene that wants it");
    let mut lab = Lab::new("pile", &[]).unwrap();
    // The user's choice holds until another scene is opened ...
    lab.view.color_by_speed = false;
    lab.reset();
    lab.set_param("friction", 0.3);
    assert!(!lab.view.color_by_speed, "reset and parameters keep the user's choice");
    // ... which brings its own default, whatever was chosen before.
    lab.switch_scene(scenes::find("bridge").unwrap());
    assert!(!lab.view.color_by_speed);
    lab.view.color_by_speed = true;
    lab.switch_scene(pile);
    assert!(lab.view.color_by_speed);
    lab.switch_scene(scenes::find("projectile").unwrap());
    assert!(!lab.view.color_by_speed, "projectile after the user had it on");
}

#[test]
fn read_outs_are_recomputed_a_few_times_a_second_not_every_frame() {
    let mut lab = Lab::new("pile", &[]).unwrap();
    let speed =
        |lab: &mut Lab| lab.readouts().iter().find(|row| row.label == "median speed").unwrap().text.clone();
    let started = Instant::now();
    let at_rest = speed(&mut lab);
    lab.run_steps(2);
    let after_two_steps = speed(&mut lab);
    // Only meaningful if this machine took less than the interval for two steps.
    if started.elapsed() < READOUT_INTERVAL {
        assert_eq!(after_two_steps, at_rest, "recomputed within {READOUT_INTERVAL:?}");
    }
    std::thread::sleep(READOUT_INTERVAL);
    assert_ne!(speed(&mut lab), at_rest, "stale after {READOUT_INTERVAL:?}: the spheres fall");
    // A reset shows its numbers at once.
    lab.reset();
    assert_eq!(speed(&mut lab), at_rest);
}

#[test]
fn a_slow_physics_step_is_not_run_more_than_the_frame_budget_allows() {
    // At 100,000 spheres one step takes tens of milliseconds on these machines.
    let mut lab = Lab::new("pile", &["count=100000".into(), "width=111".into()]).unwrap();
    let dt = f64::from(lab.dt());
    let wanted = (0.1 / dt).floor() as u64;
    let started = Instant::now();
    lab.advance_by(0.1);
    let took = started.elapsed();
    let ran = lab.stats.steps_last_frame;
    assert!(ran >= 1, "a frame always advances the physics");
    assert_eq!(lab.scene.world().steps(), u64::from(ran));
    assert_eq!(lab.stats.dropped_steps, wanted - u64::from(ran), "the rest is dropped, not owed");
    // It stops before a step that would end past the budget (judged by the last one).
    let per_step = took / ran;
    assert!(took <= PHYSICS_BUDGET + per_step * 2, "{ran} steps took {took:?} against {PHYSICS_BUDGET:?}");
}

#[test]
fn a_crowd_turns_msaa_off_and_a_smaller_scene_turns_it_back_on() {
    let crowd = (MSAA_LIMIT + 1) as f32;
    let mut lab = Lab::new("pile", &[format!("count={crowd}"), "width=60".into()]).unwrap();
    assert!(!lab.view.msaa, "opened on a crowd");
    assert!(lab.status.contains("Anti-aliasing turned off"), "{}", lab.status);
    lab.switch_scene(scenes::find("bridge").unwrap());
    assert!(lab.view.msaa, "back on for the bridge");
    // The count slider crossing the limit does the same.
    lab.switch_scene(scenes::find("pile").unwrap());
    assert!(lab.view.msaa);
    lab.set_param("count", crowd);
    assert!(!lab.view.msaa, "the count slider made a crowd");
    // What the user chooses afterwards stands.
    lab.view.msaa = true;
    lab.set_param("friction", 0.3);
    lab.reset();
    assert!(lab.view.msaa, "turned back on by the user");
}

#[test]
fn the_inspector_shows_the_forces_of_the_state_the_moment_a_particle_is_selected() {
    use particle_lab::ui::lab::CONSTRAINT_FORCE;
    // Issue 18, item 4: paused with a 200 kg round in flight selected, the inspector
    // showed a weight of 4,000 N and a net force of zero until a step was taken, and
    // "contacts and links" of (0.1, -0.1, 0) N on a round that touched nothing.
    let mut lab = Lab::new("projectile", &["damping=1".into(), "g=20".into()]).unwrap();
    lab.paused = true;
    lab.act(SceneAction::Fire);
    let id = lab.scene.world().particles.ids()[0];
    lab.select(Some(id));
    let weight = glam::Vec3::new(0.0, -200.0 * 20.0, 0.0);
    assert_eq!(lab.net_force(id), weight, "m g before any step");
    for _ in 0..30 {
        lab.run_steps(1);
        assert!(
            lab.free_body(id).iter().all(|(name, _)| *name != CONSTRAINT_FORCE),
            "{:?}",
            lab.free_body(id)
        );
        assert_eq!(lab.net_force(id), weight, "nothing but its weight acts in flight");
    }
    // With damping, the net force is weight plus m ln(d) v from the velocity now.
    let mut lab = Lab::new("projectile", &["damping=0.9".into(), "mass=2".into(), "g=20".into()]).unwrap();
    lab.act(SceneAction::Fire);
    let id = lab.scene.world().particles.ids()[0];
    lab.select(Some(id));
    lab.run_steps(10);
    let world = lab.scene.world();
    let i = world.particles.index(id).unwrap();
    let v = world.particles.velocities()[i];
    let expected = glam::Vec3::new(0.0, -40.0, 0.0) + v * (2.0 * 0.9_f32.ln());
    assert!((lab.net_force(id) - expected).length() < 1e-4, "{} N, expected {expected} N", lab.net_force(id));

    // On the ground of the pile, a resting sphere's weight is held by its contact: the
    // row appears, labelled as the last step's, and the net force is nothing.
    let mut lab = Lab::new("pile", &["count=1".into()]).unwrap();
    let id = lab.scene.world().particles.ids()[0];
    lab.select(Some(id));
    lab.paused = true;
    for _ in 0..120 {
        lab.run_steps(1);
    }
    let forces = lab.free_body(id);
    let contact = forces.iter().find(|(name, _)| *name == CONSTRAINT_FORCE).expect("the ground holds it");
    assert!((contact.1 - glam::Vec3::new(0.0, 9.81, 0.0)).length() < 0.05, "{forces:?}");
    assert!(lab.net_force(id).length() < 0.05, "resting: {} N", lab.net_force(id));
    // Clearing the selection forgets the measured contact force.
    lab.select(None);
    assert_eq!(lab.constraint_force, None);
    // Awake (sleeping off), the row is the contact's impulse over the last step, which
    // holds the weight: measured, not inferred from rest.
    let awake = particle_lab::physics::SolverSettings { sleep: false, ..Default::default() };
    let mut lab = Lab::with_solver("pile", &["count=1".into()], awake).unwrap();
    let id = lab.scene.world().particles.ids()[0];
    lab.select(Some(id));
    lab.paused = true;
    for _ in 0..240 {
        lab.run_steps(1);
    }
    assert!(!lab.scene.world().particles.is_asleep(0));
    let forces = lab.free_body(id);
    let contact = forces.iter().find(|(name, _)| *name == CONSTRAINT_FORCE).expect("the ground holds it");
    assert!((contact.1 - glam::Vec3::new(0.0, 9.81, 0.0)).length() < 0.05, "{forces:?}");
}

#[test]
fn the_energy_history_exports_as_csv() {
    let mut lab = Lab::new("springForces", &[]).unwrap();
    lab.paused = true;
    for _ in 0..10 {
        lab.run_steps(1);
    }
    let path = std::env::temp_dir().join(format!("particle-lab-energy-{}.csv", std::process::id()));
    lab.export_energy_csv(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,kinetic,potential,total,dissipated,constraint,work,removed,error"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), lab.energy.len());
    let last = rows.last().unwrap();
    let energy = lab.scene.world().energy();
    assert!((last[1] - f64::from(energy.kinetic)).abs() < 1e-3 && (last[3] - last[1] - last[2]).abs() < 1e-3);
}

#[test]
fn the_tape_measure_reads_the_distance_between_two_particles_or_ground_points() {
    // springForces' free spring: two spheres 1.5 x rest length = 3 m apart at the start.
    let mut lab = Lab::new("springForces", &[]).unwrap();
    lab.tape = true;
    let size = Vec2::new(1280.0, 720.0);
    let (a, b) = {
        let p = lab.scene.world().particles.positions();
        (p[1], p[2])
    };
    for point in [a, b] {
        let pixel = lab.camera.project(point, size).unwrap();
        lab.tape_click(pixel, size);
    }
    assert_eq!(lab.tape_points, vec![a, b], "snapped to the particles' centres");
    assert!(lab.status.starts_with("tape: 3.000 m"), "{}", lab.status);
    // A third click starts again; on empty ground it lands on y = 0 under the pointer.
    let ground = glam::Vec3::new(4.0, 0.0, 3.0);
    let pixel = lab.camera.project(ground, size).unwrap();
    lab.tape_click(pixel, size);
    assert_eq!(lab.tape_points.len(), 1);
    assert!((lab.tape_points[0] - ground).length() < 0.01, "{}", lab.tape_points[0]);
}

#[test]
fn every_scene_is_framed_whole_in_a_narrow_view_and_the_users_camera_is_kept() {
    // An 800x600 window less the 300-pixel panel: a 500x575 view.
    let size = Vec2::new(500.0, 575.0);
    for entry in SCENES {
        let mut lab = Lab::new(&entry.info().name, &[]).unwrap();
        lab.set_view_aspect(size.x / size.y);
        let particles = &lab.scene.world().particles;
        for (i, &p) in particles.positions().iter().enumerate().take(2000) {
            let screen = lab.camera.project(p, size);
            let inside = screen.is_some_and(|s| s.x >= 0.0 && s.x <= size.x && s.y >= 0.0 && s.y <= size.y);
            assert!(inside, "{}: particle {i} at {p} is outside the view ({screen:?})", entry.info().name);
        }
    }
    // Once the user has moved the camera, a new view shape does not reframe it.
    let mut lab = Lab::new("bridge", &[]).unwrap();
    lab.camera.zoom(3.0);
    lab.camera_moved = true;
    let distance = lab.camera.distance;
    lab.set_view_aspect(0.5);
    assert_eq!(lab.camera.distance, distance);
    lab.frame_scene();
    assert!(lab.camera.distance > distance, "Home reframes for the narrow view");
}

/// Issue 38, "the view finds the experiment": a scene file 500 m from the origin and
/// one a kilometre wide open framed, in 3D and in the side view, and Home frames them
/// again after the camera was moved away: every particle in the view, and the
/// experiment not a speck in it (its particles span a tenth of the view or more).
/// Millimetre particles too: framed from centimetres, and drawn at their own size
/// there (see `tiny_particles_are_drawn_at_their_own_size_up_close`).
#[test]
fn scene_files_at_any_place_and_scale_are_framed_in_3d_and_the_side_view() {
    let size = Vec2::new(980.0, 700.0);
    let files = [
        (
            "far",
            "[[particle]]\nposition = [500, 3, 40]\nradius = 0.2\n\n[[particle]]\nposition = [501.5, 3, 40]\nradius = 0.2\n",
        ),
        (
            "tiny",
            "[[particle]]\nposition = [0.002, 0.004, 0]\nradius = 0.001\n\n[[particle]]\nposition = [0.007, 0.004, 0]\nradius = 0.001\n",
        ),
        (
            "wide",
            "[[row]]\ncount = 11\nstart = [-500, 30, 0]\nstep = [100, 0, 0]\nradius = 5\npin = [0, -1]\nlink = \"rod\"\n",
        ),
    ];
    for (name, body) in files {
        let text = format!("[scene]\nname = \"{name}\"\n\n{body}");
        let entry = particle_lab::scenes::file::load_text(&text, name, None).unwrap();
        for side in [false, true] {
            let mut lab =
                Lab::from_entry(&entry, &[], particle_lab::physics::SolverSettings::default()).unwrap();
            lab.set_view_aspect(size.x / size.y);
            if side {
                lab.set_side_view(true);
            }
            // Moved far off, then Home.
            lab.camera.target += glam::Vec3::new(3000.0, 0.0, 0.0);
            lab.home();
            let positions = lab.scene.world().particles.positions().to_vec();
            let screen: Vec<Vec2> = positions
                .iter()
                .map(|&p| {
                    lab.camera.project(p, size).unwrap_or_else(|| panic!("{name}: {p} behind the camera"))
                })
                .collect();
            for (p, s) in positions.iter().zip(&screen) {
                let inside = s.x >= 0.0 && s.x <= size.x && s.y >= 0.0 && s.y <= size.y;
                assert!(inside, "{name} (side {side}): {p} lands at {s}, outside the view");
            }
            let (lo, hi) = screen
                .iter()
                .fold((Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)), |(lo, hi), &s| (lo.min(s), hi.max(s)));
            let span = (hi - lo).max_element();
            assert!(
                span > 0.1 * size.x.min(size.y),
                "{name} (side {side}): the particles span only {span} px"
            );
        }
    }
}

#[test]
fn a_reset_clears_the_selection_and_the_tape() {
    let mut lab = Lab::new("springForces", &[]).unwrap();
    lab.select(Some(lab.scene.world().particles.ids()[2]));
    lab.tape_points.push(glam::Vec3::ONE);
    lab.reset();
    assert_eq!(lab.selected, None);
    assert!(lab.tape_points.is_empty());
}

/// The 2D side view looks along -z with no perspective: points that differ only in
/// depth land on the same pixel, and the ray back through that pixel passes through
/// them. Follow puts the camera's target on the newest round.
#[test]
fn the_side_view_is_orthographic_and_follow_tracks_the_newest_round() {
    use glam::Vec3;
    let mut lab = Lab::new("projectile", &[]).unwrap();
    let size = Vec2::new(900.0, 600.0);
    let near = lab.camera.project(Vec3::new(3.0, 2.0, 2.0), size).unwrap();
    let far = lab.camera.project(Vec3::new(3.0, 2.0, -2.0), size).unwrap();
    assert!(near.distance(far) > 1.0, "perspective: depth moves a point on screen");
    lab.set_side_view(true);
    assert!(lab.camera.orthographic && lab.camera.yaw == 0.0 && lab.camera.pitch == 0.0);
    let near = lab.camera.project(Vec3::new(3.0, 2.0, 2.0), size).unwrap();
    let far = lab.camera.project(Vec3::new(3.0, 2.0, -2.0), size).unwrap();
    assert!(near.distance(far) < 1e-3, "{near} vs {far}");
    let (origin, direction) = lab.camera.ray(near, size);
    assert!((direction - Vec3::NEG_Z).length() < 1e-4, "{direction}");
    let miss = (Vec3::new(3.0, 2.0, 0.0) - origin).cross(direction).length();
    assert!(miss < 1e-3, "the ray passes {miss} m from the point");
    // Off again: framed in 3D.
    lab.set_side_view(false);
    assert!(!lab.camera.orthographic);

    lab.follow = true;
    lab.act(SceneAction::Fire);
    lab.run_steps(120);
    let round = lab.scene.world().particles.positions()[0];
    assert!(
        (lab.camera.target.x - round.x).abs() < 1e-4 && round.x > 5.0,
        "{} vs {round}",
        lab.camera.target
    );
}

/// Dragging is a soft spring with a force limit: a whip that puts the pointer 50 m
/// away for a second moves the particle at most the limit's acceleration times the
/// time, not the hundreds of m/s a teleport gives; a still pointer is reached.
#[test]
fn dragging_is_a_soft_spring_with_a_limit() {
    use glam::Vec3;
    use particle_lab::ui::lab::{MOUSE_MAX_ACCELERATION, mouse_pull};
    let h = 1.0 / 240.0;
    let (mut x, mut v) = (Vec3::ZERO, Vec3::ZERO);
    let target = Vec3::new(50.0, 0.0, 0.0);
    let mut fastest = 0.0f32;
    for _ in 0..60 {
        v += mouse_pull(target - x, v, h);
        x += v * h;
        fastest = fastest.max(v.length());
    }
    // A quarter of a second at the limit.
    assert!(fastest <= MOUSE_MAX_ACCELERATION * 0.25 + 1e-3, "{fastest} m/s");
    assert!(fastest > 0.9 * MOUSE_MAX_ACCELERATION * 0.25, "the limit, not less: {fastest}");
    // A nearby pointer is reached and held without overshoot to speak of.
    let (mut x, mut v) = (Vec3::ZERO, Vec3::ZERO);
    let target = Vec3::new(0.3, 0.2, 0.0);
    for _ in 0..240 {
        v += mouse_pull(target - x, v, h);
        x += v * h;
    }
    assert!(x.distance(target) < 1e-3 && v.length() < 1e-2, "{x} {v}");
}

/// A value typed beyond a slider's range is clamped and the status line says so; a
/// parameter that rebuilds the world says that.
#[test]
fn typed_values_are_clamped_and_rebuilds_are_announced() {
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.set_param_typed("speed", 500.0);
    assert_eq!(lab.scene.params().get("speed"), 200.0);
    assert!(lab.status.contains("clamped to 200"), "{}", lab.status);
    let mut lab = Lab::new("pendulum", &[]).unwrap();
    lab.run_steps(10);
    lab.set_param("links", 3.0);
    assert!(lab.status.contains("rebuilt"), "{}", lab.status);
    assert_eq!(lab.energy.len(), 1, "the plot starts again with the new world");
}

/// Compare runs a copy with one setting changed in step with the original: the same
/// simulated time, its own rate when that is the change, and it shows what the change
/// does (explicit Euler drifts from the exact answer far more than the default).
#[test]
fn compare_runs_a_copy_with_one_setting_changed() {
    use particle_lab::physics::Integrator;
    use particle_lab::ui::compare::Change;
    let mut lab = Lab::new("springForces", &["k=80".into()]).unwrap();
    lab.run_steps(50);
    lab.start_compare(Change::Integrator(Integrator::ExplicitEuler));
    assert_eq!(lab.scene.world().steps(), 0, "both start again");
    lab.run_steps(600);
    let compare = lab.compare.as_ref().expect("running");
    assert_eq!(compare.scene.world().time(), lab.scene.world().time());
    assert_eq!(compare.scene.world().solver().integrator, Integrator::ExplicitEuler);
    let (ours, theirs) = (lab.scene.exact_error().unwrap(), compare.scene.exact_error().unwrap());
    assert!(theirs > 10.0 * ours, "explicit Euler {theirs} m vs semi-implicit {ours} m");
    // A reset keeps the copy; another scene drops it.
    lab.reset();
    assert!(lab.compare.is_some());
    lab.switch_scene(scenes::find("bridge").unwrap());
    assert!(lab.compare.is_none());

    // Another rate: the copy takes its own steps and keeps within half of one.
    let mut lab = Lab::new("pendulum", &[]).unwrap();
    lab.start_compare(Change::parse("rate=60", &lab.entry).unwrap());
    lab.run_steps(240);
    let compare = lab.compare.as_ref().unwrap();
    assert_eq!(compare.scene.world().steps(), 60);
    // Another parameter: the copy has it, the original does not; other changes reach both.
    let mut lab = Lab::new("projectile", &[]).unwrap();
    lab.start_compare(Change::parse("k1=20", &lab.entry).unwrap());
    lab.set_param("g", 9.81);
    let copy = lab.compare.as_ref().unwrap().scene.params();
    assert_eq!((copy.get("k1"), copy.get("g")), (20.0, 9.81));
    assert_eq!(lab.scene.params().get("k1"), 0.0);
    // Refusals name what is accepted.
    let error = Change::parse("mass=0", &lab.entry).unwrap_err();
    assert!(error.contains("valid range"), "{error}");
    assert!(Change::parse("integrator=leapfrog", &lab.entry).is_err());
}

/// A bridge that has come to rest and fallen asleep still reports the tension in its
/// links (the key and the colours by tension show it), not zero.
#[test]
fn a_sleeping_bridge_still_reports_its_tension() {
    let mut lab = Lab::new("bridge", &["load_mass=30".into(), "load_x=2.5".into()]).unwrap();
    let max_tension = |lab: &Lab| lab.scene.world().links().iter().map(|l| l.tension).fold(0.0, f32::max);
    // Step until it falls asleep, remembering the tension of its last awake step.
    let mut awake = 0.0;
    for _ in 0..4000 {
        if lab.scene.world().last_report().asleep > 0 {
            break;
        }
        awake = max_tension(&lab);
        lab.run_steps(1);
    }
    assert!(lab.scene.world().last_report().asleep > 0, "the bridge should fall asleep");
    lab.run_steps(240);
    let report = lab.scene.world().last_report();
    assert!(report.asleep > 0, "still asleep: {report:?}");
    let asleep = max_tension(&lab);
    assert!(awake > 30.0, "{awake} N");
    assert!((asleep - awake).abs() < 0.2 * awake, "asleep {asleep} N vs awake {awake} N");
}

#[test]
fn the_inspector_shows_a_rolling_spheres_spin_and_its_energy() {
    // Issue 21: one sphere of the pile scene, landed, pushed along the floor without
    // spin; friction turns it until it rolls. The inspector's ω, surface speed and spin
    // energy against the same figures computed here from the sphere's mass and radius.
    let mut lab = Lab::new("pile", &["count=1".into(), "rolling_resistance=0".into()]).unwrap();
    lab.paused = true;
    lab.run_steps(120);
    let id = lab.scene.world().particles.ids()[0];
    lab.select(Some(id));
    lab.scene.world_mut().particles.set_velocity(id, glam::Vec3::new(3.0, 0.0, 0.0)).unwrap();
    assert_eq!(lab.spin(id).unwrap().energy, 0.0, "pushed without spin");
    lab.run_steps(120);
    let spin = lab.spin(id).expect("a pile sphere rolls");
    let world = lab.scene.world();
    let (m, r) = (world.particles.mass(0), world.particles.radii()[0]);
    let w = world.particles.angular_velocities()[0];
    let v = world.particles.velocities()[0];
    assert_eq!(spin.angular_velocity, w);
    let expected = 0.5 * (0.4 * m * r * r) * w.length_squared();
    assert!(
        (spin.energy - expected).abs() < 1e-5 * expected,
        "{} J against ½ I ω² = {expected} J",
        spin.energy
    );
    // Rolling without slipping: the surface turns as fast as the centre moves, and the
    // spin holds 2/7 of the kinetic energy, which the world's budget counts.
    assert!((spin.surface_speed - v.length()).abs() < 0.01 * v.length(), "{spin:?} at {v}");
    let e = world.energy();
    assert!((e.rotational - spin.energy).abs() < 1e-5, "{e:?}");
    assert!((e.rotational - 2.0 / 7.0 * e.kinetic).abs() < 0.01 * e.kinetic, "{e:?}");
    // A point mass has no spin to show.
    let lab = Lab::new("pile", &["count=1".into(), "rolls=0".into()]).unwrap();
    assert_eq!(lab.spin(lab.scene.world().particles.ids()[0]), None);
}

/// A particle a millimetre across, framed, is drawn at its own radius, not at the
/// least radius the view gives point particles seen from afar; from afar it gets that
/// least radius again.
#[test]
fn tiny_particles_are_drawn_at_their_own_size_up_close() {
    use particle_lab::render::frame::{MIN_DRAWN_RADIUS, decoration_scale};
    use particle_lab::render::{FrameBuilder, ViewOptions};
    let text =
        "[scene]\nname = \"tiny\"\n\n[[particle]]\nposition = [0, 0.004, 0]\nradius = 0.001\nfixed = true\n";
    let entry = particle_lab::scenes::file::load_text(text, "tiny", None).unwrap();
    let mut lab = Lab::from_entry(&entry, &[], particle_lab::physics::SolverSettings::default()).unwrap();
    lab.set_view_aspect(1.4);
    lab.home();
    assert!(lab.camera.distance < 0.05, "framed from {} m", lab.camera.distance);
    let mut builder = FrameBuilder::default();
    builder.decoration_scale = decoration_scale(lab.camera.distance);
    builder.build(lab.scene.as_ref(), None, 0.0, ViewOptions::default(), None);
    assert_eq!(builder.frame.spheres[0].radius, 0.001);
    // Its projected radius: a few pixels or more in a 700 px view.
    let size = Vec2::new(980.0, 700.0);
    let centre = lab.camera.project(glam::Vec3::new(0.0, 0.004, 0.0), size).unwrap();
    let edge = lab.camera.project(glam::Vec3::new(0.0, 0.005, 0.0), size).unwrap();
    assert!(centre.distance(edge) > 5.0, "drawn {} px across", centre.distance(edge));
    builder.decoration_scale = decoration_scale(20.0);
    builder.build(lab.scene.as_ref(), None, 0.0, ViewOptions::default(), None);
    assert_eq!(builder.frame.spheres[0].radius, MIN_DRAWN_RADIUS);
}

/// A scene file's `color` is the colour the view draws that particle in; the others
/// keep the lab's palette.
#[test]
fn a_particles_colour_from_its_file_is_drawn() {
    use particle_lab::render::{FrameBuilder, ViewOptions};
    let text = "[scene]\nname = \"colours\"\n\n[[particle]]\nposition = [0, 1, 0]\n\n[[particle]]\nposition = [1, 1, 0]\ncolor = \"#ff3300\"\n";
    let entry = particle_lab::scenes::file::load_text(text, "colours", None).unwrap();
    let scene = entry.create_default();
    let mut builder = FrameBuilder::default();
    builder.build(scene.as_ref(), None, 0.0, ViewOptions::default(), None);
    assert_eq!(builder.frame.spheres[1].color, [1.0, 0.2, 0.0, 1.0]);
    assert_ne!(builder.frame.spheres[0].color, [1.0, 0.2, 0.0, 1.0], "the others keep the palette");
    // A colour that is not one is refused in one line, naming the key.
    let bad = text.replace("#ff3300", "orange");
    let error = particle_lab::scenes::file::load_text(&bad, "colours", None).err().unwrap().to_string();
    assert!(error.contains("color") && !error.contains('\n'), "{error}");
}

/// Issue 37: at 1024×600 (a view of 694×570 points beside the panel) the side view's
/// Home keeps the launcher clear of the height scale at its left edge, and the landing
/// in view on the right.
#[test]
fn home_in_the_side_view_keeps_the_launcher_clear_of_the_height_scale() {
    let mut lab = Lab::new("projectile", &[]).unwrap();
    let size = Vec2::new(694.0, 570.0);
    lab.set_view_aspect(size.x / size.y);
    lab.set_side_view(true);
    lab.home();
    let launcher = lab.camera.project(glam::Vec3::new(0.0, 1.5, 0.0), size).unwrap();
    // The scale's line stands 52 points in, its labels left of it.
    assert!(launcher.x > 60.0, "the launcher at {launcher} hides behind the height scale");
    let mut points = Vec::new();
    lab.scene.framing_points(&mut points);
    for p in points {
        let s = lab.camera.project(p, size).unwrap();
        assert!(s.x >= 0.0 && s.x <= size.x && s.y >= 0.0 && s.y <= size.y, "{p} drawn at {s}");
    }
}

//! Every scene's read-outs as `simulate` prints them, each computed a second way: from
//! the particles and links of the same frames, or from a closed form with the scene's
//! parameters. Run through the binary, as a user's script would read them.

use std::process::Command;

use serde_json::Value;

/// The frames `simulate` prints for `args`, parsed.
fn frames(args: &[&str]) -> Vec<Value> {
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .arg("simulate")
        .args(args)
        .output()
        .expect("the binary runs");
    assert!(output.status.success(), "simulate {args:?}: {}", String::from_utf8_lossy(&output.stderr));
    let text = String::from_utf8(output.stdout).expect("JSON is UTF-8");
    text.lines().map(|line| serde_json::from_str(line).expect("each line is one JSON object")).collect()
}

/// A read-out of a frame, if the frame has it.
fn readout(frame: &Value, key: &str) -> Option<f64> {
    frame["readouts"].get(key).map(|value| value.as_f64().expect("a read-out is a number"))
}

/// A read-out the frame must have.
fn must(frame: &Value, key: &str) -> f64 {
    readout(frame, key).unwrap_or_else(|| panic!("no {key} at step {}: {}", frame["step"], frame["readouts"]))
}

fn particles(frame: &Value) -> &Vec<Value> {
    frame["particles"].as_array().expect("a particle list")
}

fn vector(value: &Value) -> [f64; 3] {
    let v = value.as_array().expect("a vector");
    [0, 1, 2].map(|i| v[i].as_f64().expect("a number"))
}

fn speed(particle: &Value) -> f64 {
    let [x, y, z] = vector(&particle["v"]);
    (x * x + y * y + z * z).sqrt()
}

/// `a` and `b` agree to `relative` of `b` (an f32 figure against an f64 one).
fn close(a: f64, b: f64, relative: f64) -> bool {
    (a - b).abs() <= relative * b.abs().max(1e-9)
}

#[test]
fn projectile_predictions_are_the_closed_forms_and_its_range_is_where_the_round_came_down() {
    let (v, angle, h, g, target) = (25.0_f64, 45.0_f64.to_radians(), 1.5, 9.81, 30.0);
    // The defaults: no damping, no drag, so the round flies the closed-form parabola the
    // predictions describe, and lands after 3.69 s (885 steps).
    let run = frames(&["--scene", "projectile", "--steps", "1000", "--every", "1"]);
    let (vx, vy) = (v * angle.cos(), v * angle.sin());
    let first = &run[0];
    let ground = vx * (vy + (vy * vy + 2.0 * g * h).sqrt()) / g;
    assert!(close(must(first, "range_predicted_m"), ground, 1e-6), "{}", first["readouts"]);
    assert!(close(must(first, "range_level_predicted_m"), v * v * (2.0 * angle).sin() / g, 1e-6));
    assert!(close(must(first, "peak_predicted_m"), h + vy * vy / (2.0 * g), 1e-6));

    // The frame before the round is gone holds it last above the ground: carry it down
    // its parabola to y = 0, from its own position and velocity.
    let landed = run.iter().position(|frame| readout(frame, "range_m").is_some()).expect("the round lands");
    assert!(particles(&run[landed]).is_empty(), "a landed round is removed");
    let before = &run[landed - 1];
    let round = &particles(before)[0];
    let ([x, y, _], [ux, uy, _]) = (vector(&round["p"]), vector(&round["v"]));
    let fall = (uy + (uy * uy + 2.0 * g * y).sqrt()) / g;
    let (range, time) = (x + ux * fall, before["t"].as_f64().expect("a time") + fall);
    let now = &run[landed];
    // The launcher stands at x = 0; within a step's travel of the extrapolation.
    assert!((must(now, "range_m") - range).abs() < 0.01, "{} against {range}", now["readouts"]);
    assert!((must(now, "flight_time_s") - time).abs() < 1e-3, "{} against {time}", now["readouts"]);
    assert!((must(now, "landing_off_target_m") - (range - target)).abs() < 0.01);
    // And the measured flight is the predicted one, to semi-implicit Euler's error.
    assert!(close(must(now, "range_m"), ground, 0.005), "{} against {ground}", now["readouts"]);
    assert_eq!(must(now, "rounds_in_flight"), 0.0);

    // Off its exact path: the round against the parabola from the launcher, fired at 0 s.
    for frame in run[..landed].iter().step_by(40) {
        let t = frame["t"].as_f64().expect("a time");
        let [x, y, z] = vector(&particles(frame)[0]["p"]);
        let (ex, ey) = (vx * t, h + vy * t - g * t * t / 2.0);
        let off = ((x - ex).powi(2) + (y - ey).powi(2) + z * z).sqrt();
        assert!(
            (must(frame, "exact_path_error_m") - off).abs() < 1e-4,
            "{} against {off}",
            frame["readouts"]
        );
    }
    assert_eq!(must(first, "rounds_in_flight"), particles(first).len() as f64);
    assert_eq!(must(first, "rounds_in_flight"), 1.0, "fired at step 0");
}

/// Times of the upward crossings of `level` by the series (t, y), interpolated.
fn upward_crossings(series: &[(f64, f64)], level: f64) -> Vec<f64> {
    series
        .windows(2)
        .filter(|w| w[0].1 < level && w[1].1 >= level)
        .map(|w| w[0].0 + (level - w[0].1) / (w[1].1 - w[0].1) * (w[1].0 - w[0].0))
        .collect()
}

/// The mean interval between successive crossings (s).
fn mean_period(crossings: &[f64]) -> f64 {
    assert!(crossings.len() >= 3, "too few crossings: {crossings:?}");
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

#[test]
fn spring_periods_are_the_closed_form_and_the_bobs_own_swings() {
    let (k, mass) = (20.0_f64, 1.0);
    let run = frames(&["--scene", "springForces", "--set", "damping=1", "--steps", "1200", "--every", "1"]);
    let predicted = std::f64::consts::TAU * (mass / k).sqrt();
    let last = run.last().expect("frames");
    assert!(close(must(last, "period_predicted_s"), predicted, 1e-6), "{}", last["readouts"]);
    assert!(readout(&run[0], "period_s").is_none(), "no period before a swing is timed");

    // The bob is the particle at the printed height; time its swings from its heights.
    let series: Vec<(f64, f64)> =
        run.iter().map(|frame| (frame["t"].as_f64().expect("a time"), must(frame, "bob_height_m"))).collect();
    let bob = particles(last).iter().find(|p| vector(&p["p"])[1] == must(last, "bob_height_m"));
    assert!(bob.is_some(), "some particle stands at bob_height_m");
    let (low, high) =
        series.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(_, y)| (lo.min(y), hi.max(y)));
    let swings = mean_period(&upward_crossings(&series, (low + high) / 2.0));
    assert!(close(must(last, "period_s"), swings, 0.005), "{} against {swings}", last["readouts"]);
    assert!(close(swings, predicted, 0.01), "{swings} against {predicted}");
    // ω·dt from the parameters and the scene's step, 1/240 s.
    assert!(close(must(last, "omega_dt"), (k / mass).sqrt() / 240.0, 1e-6));
    assert!(close(must(last, "stiff_omega_dt"), (10_000.0 / mass).sqrt() / 240.0, 1e-6));
}

#[test]
fn the_pendulums_period_is_its_own_swings_and_its_energy_change_is_the_frames() {
    let (length, g) = (1.0_f64, 9.81);
    // A small release, where 2π√(L/g) holds (10°: 0.2% slower).
    let run = frames(&["--scene", "pendulum", "--set", "angle=10", "--steps", "2400", "--every", "1"]);
    let predicted = std::f64::consts::TAU * (length / g).sqrt();
    let first = &run[0];
    assert!(close(must(first, "period_predicted_s"), predicted, 1e-6), "{}", first["readouts"]);
    let series: Vec<(f64, f64)> = run
        .iter()
        .map(|frame| (frame["t"].as_f64().expect("a time"), vector(&particles(frame)[0]["p"])[0]))
        .collect();
    let crossings = upward_crossings(&series, 0.0);
    let swings = mean_period(&crossings);
    assert!(close(swings, must(first, "period_predicted_s"), 0.01), "{swings} against {predicted}");
    // The measured period is the last whole swing the frames show.
    let last = run.last().expect("frames");
    let last_swing = crossings[crossings.len() - 1] - crossings[crossings.len() - 2];
    assert!(close(must(last, "period_s"), last_swing, 1e-4), "{} against {last_swing}", last["readouts"]);
    // The exact period for 10°, from its series in the amplitude θ₀:
    // T = 2π√(L/g) (1 + θ₀²/16 + 11 θ₀⁴/3072 + 173 θ₀⁶/737280 + …).
    let a = 10.0_f64.to_radians();
    let series_t =
        predicted * (1.0 + a.powi(2) / 16.0 + 11.0 * a.powi(4) / 3072.0 + 173.0 * a.powi(6) / 737_280.0);
    assert!(close(must(first, "period_exact_s"), series_t, 1e-6), "{} against {series_t}", first["readouts"]);

    let budget = |frame: &Value| {
        frame["energy"]["kinetic"].as_f64().unwrap() + frame["energy"]["potential"].as_f64().unwrap()
    };
    assert_eq!(must(first, "energy_change_j"), 0.0);
    for frame in run.iter().step_by(240) {
        let change = budget(frame) - budget(first);
        assert!(
            (must(frame, "energy_change_j") - change).abs() < 1e-4,
            "{} against {change}",
            frame["readouts"]
        );
    }
}

#[test]
fn the_cradles_lifted_ball_reaches_the_predicted_speed() {
    let (g, angle) = (9.81_f64, 30.0_f64.to_radians());
    let run = frames(&["--scene", "cradle", "--set", "lifted=2", "--steps", "240", "--every", "1"]);
    let first = &run[0];
    // The cable's length as the frame gives it, for √(2 g L (1 − cos θ)).
    let cable = first["links"][0]["rest"].as_f64().expect("a cable");
    let predicted = (2.0 * g * cable * (1.0 - angle.cos())).sqrt();
    assert!(close(must(first, "speed_at_bottom_predicted_m_s"), predicted, 1e-6), "{}", first["readouts"]);
    // The balls are the movable particles; the lifted ones stand above the rest.
    let balls = particles(first).iter().filter(|p| p["fixed"] != Value::Bool(true)).count();
    let lowest = particles(first).iter().map(|p| vector(&p["p"])[1]).fold(f64::INFINITY, f64::min);
    let lifted = particles(first).iter().filter(|p| vector(&p["p"])[1] > lowest + 1e-3).count();
    assert_eq!((must(first, "balls"), must(first, "lifted")), (balls as f64, lifted as f64));
    assert_eq!(must(first, "lifted_asked"), 2.0);
    // The fastest any ball goes in the first quarter swing and the collision after it.
    let fastest = run.iter().flat_map(|frame| particles(frame).iter().map(speed)).fold(0.0, f64::max);
    assert!(close(fastest, predicted, 0.02), "{fastest} against {predicted}");
}

#[test]
fn the_piles_read_outs_are_its_spheres_speeds_and_positions() {
    let width = 16.0;
    let run = frames(&["--scene", "pile", "--set", "count=300", "--steps", "240", "--every", "60"]);
    for frame in &run {
        let spheres = particles(frame);
        assert_eq!(must(frame, "spheres"), spheres.len() as f64);
        let mut speeds: Vec<f64> = spheres.iter().map(speed).collect();
        speeds.sort_by(f64::total_cmp);
        let fastest = speeds.last().copied().unwrap_or(0.0);
        assert!(close(must(frame, "fastest_m_s"), fastest, 1e-5), "{} against {fastest}", frame["readouts"]);
        let median = speeds[speeds.len() / 2];
        assert!(
            close(must(frame, "median_speed_m_s"), median, 1e-5),
            "{} against {median}",
            frame["readouts"]
        );
        let half = width / 2.0;
        let outside = spheres
            .iter()
            .filter(|p| {
                let [x, y, z] = vector(&p["p"]);
                y < 0.0 || x.abs() > half || z.abs() > half
            })
            .count();
        assert_eq!(must(frame, "outside_box"), outside as f64);
        // The deepest overlap, of a pair or of a sphere and the floor or a wall, over
        // every pair (the scene finds its pairs with the broad phase).
        let spots: Vec<([f64; 3], f64)> =
            spheres.iter().map(|p| (vector(&p["p"]), p["r"].as_f64().expect("a radius"))).collect();
        let mut deepest = 0.0_f64;
        for (i, &([x, y, z], r)) in spots.iter().enumerate() {
            for gap in [y, half - x, x + half, half - z, z + half] {
                deepest = deepest.max(r - gap);
            }
            for &(q, s) in &spots[i + 1..] {
                let apart = ((x - q[0]).powi(2) + (y - q[1]).powi(2) + (z - q[2]).powi(2)).sqrt();
                deepest = deepest.max(r + s - apart);
            }
        }
        assert!(
            (must(frame, "deepest_overlap_m") - deepest).abs() < 1e-5,
            "{} against {deepest}",
            frame["readouts"]
        );
    }
}

#[test]
fn the_hourglass_counts_its_grains_and_its_flows_are_beverloo_and_the_counts() {
    let g = 9.81_f64;
    // Frames 0.1 s apart (12 steps at 120 Hz): the flow's 1 s window is ten frames.
    let run = frames(&["--scene", "hourglass", "--set", "count=600", "--steps", "480", "--every", "12"]);
    let through = |frame: &Value| {
        particles(frame).iter().filter(|p| vector(&p["p"])[1] < -p["r"].as_f64().expect("a radius")).count()
    };
    let grain = &particles(&run[0])[0];
    let (r, m) = (grain["r"].as_f64().unwrap(), grain["m"].as_f64().unwrap());
    // The default opening, 1.4 m, in grain diameters.
    assert!(close(must(&run[0], "opening_grains"), 1.4 / (2.0 * r), 1e-6), "{}", run[0]["readouts"]);
    for (i, frame) in run.iter().enumerate() {
        assert_eq!(must(frame, "grains"), particles(frame).len() as f64);
        assert_eq!(must(frame, "grains_through"), through(frame) as f64, "at step {}", frame["step"]);
        // Beverloo's W = 0.58 ρ_b √g (D − 1.5 d)^{5/2}, the bulk density the bed's
        // packing times the grains' own, from a grain's mass and radius.
        let density = m / (4.0 / 3.0 * std::f64::consts::PI * r.powi(3));
        let (d, packing) = (2.0 * r, must(frame, "packing"));
        let opening = must(frame, "opening_grains") * d;
        let beverloo = 0.58 * packing * density * g.sqrt() * (opening - 1.5 * d).max(0.0).powf(2.5);
        assert!(
            close(must(frame, "beverloo_kg_s"), beverloo, 1e-4),
            "{} against {beverloo}",
            frame["readouts"]
        );
        match i.checked_sub(10) {
            // The series starts after the first step, so a full second is in after it.
            Some(earlier) if frame["t"].as_f64().unwrap() > 1.0 + 1e-6 => {
                let flow = (through(frame) - through(&run[earlier])) as f64 * m;
                assert!(close(must(frame, "flow_kg_s"), flow, 1e-4), "{} against {flow}", frame["readouts"]);
                assert!(close(must(frame, "flow_over_beverloo"), flow / beverloo, 1e-3));
            }
            _ => assert!(readout(frame, "flow_kg_s").is_none(), "no flow before a second is measured"),
        }
    }
    assert!(must(run.last().unwrap(), "grains_through") > 0.0, "grains went through in 4 s");
}

#[test]
fn the_bridges_read_outs_are_its_particles_and_its_resolver() {
    for frame in &frames(&["--scene", "bridge", "--steps", "240", "--every", "40"]) {
        let lowest = particles(frame).iter().map(|p| vector(&p["p"])[1]).fold(f64::INFINITY, f64::min);
        let fastest = particles(frame).iter().map(speed).fold(0.0, f64::max);
        assert_eq!(must(frame, "lowest_m"), lowest);
        assert!(close(must(frame, "fastest_m_s"), fastest, 1e-5), "{} against {fastest}", frame["readouts"]);
        assert_eq!(must(frame, "max_penetration_m"), frame["resolver"]["max_penetration"].as_f64().unwrap());
    }
}

#[test]
fn a_scene_files_read_outs_count_its_particles_links_and_torn_links() {
    let run = frames(&["--scene", "cloth", "--set", "tear=5", "--steps", "480", "--every", "48"]);
    let first = &run[0];
    let links = |frame: &Value| frame["links"].as_array().expect("a link list").len();
    for frame in &run {
        assert_eq!(must(frame, "particles"), particles(frame).len() as f64);
        assert_eq!(must(frame, "links"), links(frame) as f64);
        // A torn link leaves the list.
        assert_eq!(must(frame, "links_torn"), (links(first) - links(frame)) as f64, "{}", frame["readouts"]);
    }
    assert!(must(run.last().unwrap(), "links_torn") > 0.0, "a 5 N cloth tears");
}

/// Released horizontally, the pendulum swings 18% slower than 2π√(L/g): its measured
/// period is the exact one for its amplitude, 4√(L/g)·K(sin 45°), not the small-swing one.
#[test]
fn a_wide_swing_takes_the_exact_period_for_its_amplitude() {
    let run = frames(&["--scene", "pendulum", "--set", "angle=90", "--steps", "1800", "--every", "1800"]);
    let last = run.last().expect("frames");
    let (measured, exact) = (must(last, "period_s"), must(last, "period_exact_s"));
    let small = must(last, "period_predicted_s");
    assert!(close(measured, exact, 0.01), "measured {measured} s against the exact {exact} s");
    assert!(exact > 1.15 * small && exact < 1.2 * small, "{exact} against {small}");
}

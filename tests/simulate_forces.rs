//! `simulate --forces` (issue 18, item 4): each particle's net force `f` and the forces
//! that make it, computed from the state, checked against the closed form and against
//! the momentum the printed velocities show.

use std::process::Command;

use serde_json::Value;

fn simulate(args: &[&str]) -> Vec<Value> {
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--forces"])
        .args(args)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8_lossy(&output.stdout).lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

fn vector(value: &Value) -> [f64; 3] {
    let a = value.as_array().expect("a vector");
    [0, 1, 2].map(|k| a[k].as_f64().unwrap())
}

#[test]
fn a_free_particles_net_force_is_m_g_exactly_at_step_zero() {
    // A 200 kg round, undamped, in flight: weight alone (under the paper's g, a round
    // 4,000 N).
    let lines = simulate(&["--scene", "projectile", "--set", "g=20", "--set", "damping=1", "--steps", "0"]);
    let round = &lines[0]["particles"][0];
    assert_eq!(vector(&round["f"]), [0.0, -200.0 * 20.0, 0.0], "{round}");
    assert_eq!(vector(&round["forces"]["weight"]), [0.0, -4000.0, 0.0]);
    assert!(round["forces"].get("contacts and links (last step)").is_none(), "it touches nothing: {round}");
}

#[test]
fn the_net_force_is_the_change_of_momentum_the_printed_velocities_show() {
    // With damping 0.9, f = m g + m ln(0.9) v; the velocities one step apart give the
    // same force as m Δv / dt, to the step's O(dt) curvature.
    let lines =
        simulate(&["--scene", "projectile", "--set", "damping=0.9", "--set", "mass=2", "--steps", "60"]);
    let dt = 1.0 / 240.0;
    for pair in lines.windows(2).skip(1) {
        let (a, b) = (&pair[0]["particles"][0], &pair[1]["particles"][0]);
        let (va, vb, f) = (vector(&a["v"]), vector(&b["v"]), vector(&a["f"]));
        for k in 0..3 {
            let measured = 2.0 * (vb[k] - va[k]) / dt;
            assert!((measured - f[k]).abs() <= 0.002 * f[k].abs().max(1.0), "axis {k}: {measured} vs {f:?}");
        }
        let sum: f64 = a["forces"].as_object().unwrap().values().map(|v| vector(v)[1]).sum();
        assert!((sum - f[1]).abs() < 1e-3, "f is the sum of the forces: {a}");
    }
}

#[test]
fn a_bridge_particle_shows_what_its_rods_and_cables_do() {
    // Resting on its links, a deck particle's net force is nearly zero: the links'
    // row holds its weight.
    // The paper solver never sleeps: the row is measured, not inferred from rest.
    let lines = simulate(&["--scene", "bridge", "--solver", "paper", "--steps", "1200", "--every", "1200"]);
    let last = lines.last().unwrap();
    let deck = last["particles"].as_array().unwrap().iter().find(|p| p["id"] == 4).unwrap();
    let forces = deck["forces"].as_object().unwrap();
    let held = vector(forces.get("contacts and links (last step)").expect("its links hold it"));
    let weight = vector(&forces["weight"]);
    assert!((held[1] + weight[1]).abs() < 0.02 * weight[1].abs(), "{deck}");
    assert!(vector(&deck["f"])[1].abs() < 0.02 * weight[1].abs(), "{deck}");
}

#[test]
fn forces_are_json_only() {
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--scene", "bridge", "--forces", "--format", "csv"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("--forces") && stderr.lines().count() == 1, "{stderr}");
}

#[test]
fn no_printed_figure_reads_minus_zero() {
    // Issue 18, item 3: "kinetic": -0.0 once the sky was empty, "tension": -0.0 on a
    // slack rod, a damping force's untouched z of -0.0.
    let scenes: [&[&str]; 3] = [
        // The round lands after 885 steps: the sky is empty by the last frame.
        &["--scene", "projectile", "--steps", "1000", "--every", "100"],
        &["--scene", "bridge", "--steps", "300", "--every", "100"],
        &["--scene", "springForces", "--steps", "300", "--every", "100"],
    ];
    for args in scenes {
        let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
            .args(["simulate", "--forces"])
            .args(args)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&output.stdout);
        assert!(!text.is_empty());
        for (at, _) in text.match_indices("-0.0") {
            let next = text[at + 4..].chars().next();
            assert!(next.is_some_and(|c| c.is_ascii_digit() || c == 'e'), "{args:?}: a -0.0 at {at}");
        }
    }
}

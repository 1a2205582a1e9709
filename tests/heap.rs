//! The heap (issue 37): grains poured from a funnel onto open ground settle into a heap
//! whose angle of repose the scene measures, and each settled heap is a row of the
//! table of runs. Run through `simulate` as a user would, and every figure checked
//! from the printed positions by the test's own arithmetic.
//!
//! Measured (release build, 2026-12-06, the defaults: 1,500 glass grains of radius
//! 0.1 m, μ 0.5, outlet 1.2 m wide and 1.2 m up): the heap grows to the outlet (the
//! fixed-funnel method) and settles at 14.1 s at 25.7°; at rolling resistance 0.05 it
//! rests at 22.4°, at 0.2 at 28.7°, and at 0 it never comes to rest: round grains
//! without rolling resistance roll apart.

use std::collections::HashMap;
use std::process::Command;

use glam::Vec3;

fn lab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_particle-lab"))
}

/// The last frame of `simulate --scene heap` with `sets`, and the table of runs it wrote.
fn pour(name: &str, sets: &[&str]) -> (serde_json::Value, Vec<HashMap<String, f64>>) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("heap-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("runs.csv");
    let mut command = lab();
    command.args(["simulate", "--scene", "heap", "--every", "100000", "--runs"]).arg(&csv);
    for set in sets {
        command.args(["--set", set]);
    }
    let out = command.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let last = serde_json::from_str(text.lines().last().unwrap()).unwrap();
    let table = std::fs::read_to_string(&csv).unwrap();
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows = lines
        .map(|line| {
            header.iter().map(|k| k.to_string()).zip(line.split(',').map(|v| v.parse().unwrap())).collect()
        })
        .collect();
    (last, rows)
}

/// The frame's particles: centre and radius.
fn grains(frame: &serde_json::Value) -> Vec<(Vec3, f32)> {
    frame["particles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let c: Vec<f32> = p["p"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap() as f32).collect();
            (Vec3::new(c[0], c[1], c[2]), p["r"].as_f64().unwrap() as f32)
        })
        .collect()
}

fn readout(frame: &serde_json::Value, key: &str) -> Option<f64> {
    frame["readouts"][key].as_f64()
}

#[test]
fn a_poured_heap_settles_at_its_angle_of_repose_and_adds_a_run() {
    let (frame, rows) = pour("default", &[]);
    let drop = 1.2f32;
    // The grains on the ground, by the test's own count from the positions.
    let heap: Vec<(Vec3, f32)> = grains(&frame).into_iter().filter(|(c, r)| c.y < drop - r).collect();
    assert_eq!(readout(&frame, "heap_grains"), Some(heap.len() as f64));
    let top = heap.iter().map(|(c, r)| c.y + r).fold(0.0f32, f32::max);
    assert_eq!(readout(&frame, "heap_height_m").map(|h| h as f32), Some(top));
    // A heap of round, frictional, rolling-resistant grains: a physical angle.
    let repose = readout(&frame, "repose_deg").expect("the heap settled within the run") as f32;
    assert!((20.0..=32.0).contains(&repose), "repose {repose}°");
    // The same fit on the printed positions (the heap does not move once settled).
    let positions: Vec<Vec3> = heap.iter().map(|(c, _)| *c).collect();
    let again = particle_lab::scenes::pile::angle_of_repose(&positions, 0.1);
    assert!((again - repose).abs() < 0.1, "refitted {again}° against {repose}°");
    // And a second way: a cone's slope from its height over its reach (the radius
    // within which 95% of the grains lie, around their mean), which the rounded top
    // makes a little flatter than the flank.
    let n = positions.len() as f32;
    let centre = positions.iter().fold(Vec3::ZERO, |s, p| s + *p) / n;
    let mut reach: Vec<f32> =
        positions.iter().map(|p| Vec3::new(p.x - centre.x, 0.0, p.z - centre.z).length()).collect();
    reach.sort_by(f32::total_cmp);
    let cone = (top / reach[(0.95 * n) as usize]).atan().to_degrees();
    assert!((cone - repose).abs() < 6.0, "height over reach gives {cone}°, the fit {repose}°");
    // One heap, one row: its parameters and what the panel showed.
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    let expected = [("count", 1500.0), ("radius_m", 0.1), ("orifice_m", 1.2), ("friction", 0.5)];
    for (key, value) in expected {
        assert!((row[key] - value).abs() < 1e-6, "{key} = {}", row[key]);
    }
    assert_eq!(row["repose_deg"] as f32, repose);
    assert_eq!(Some(row["settled_s"]), readout(&frame, "settled_s"));
    assert_eq!(Some(row["heap_grains"]), readout(&frame, "heap_grains"));
    let settled = row["settled_s"];
    assert!(settled > 1.0 && settled < 20.0, "settled at {settled} s");
}

#[test]
fn rolling_resistance_holds_the_heap_up() {
    let angle = |rr: &str| {
        let (frame, rows) = pour(&format!("rr{rr}"), &[&format!("rolling_resistance={rr}")]);
        (readout(&frame, "repose_deg"), rows.len())
    };
    let (low, high, none) = (angle("0.05"), angle("0.2"), angle("0"));
    let (low, high) = (low.0.expect("0.05 settles"), high.0.expect("0.2 settles"));
    assert!(high > low + 3.0, "μ_r 0.2 at {high}°, 0.05 at {low}°");
    // Without rolling resistance round grains keep rolling: no heap settles, no row.
    assert_eq!(none, (None, 0), "μ_r 0 settled");
}

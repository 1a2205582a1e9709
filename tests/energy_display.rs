//! The energy display (issue 18, item 8): gravitational energy from a reference that
//! shows the exchange, bars that default to the particle a scene is about, 0 J drawn as
//! no bar, and plots that break where their series breaks. Each figure is computed a
//! second way here, from the particles' states or a closed form.

use glam::Vec3;
use particle_lab::scenes::{self, SceneAction};
use particle_lab::ui::lab::EnergyBars;
use particle_lab::ui::{Lab, joules, segments};

fn bar(bars: &EnergyBars, name: &str) -> f32 {
    bars.bars.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("no {name} bar: {bars:?}")).1
}

#[test]
fn the_cradles_gravity_is_measured_from_where_its_balls_hang() {
    // Before: from the ground, 30 J of height drowned the 1.3 J the lifted ball swaps.
    let lab = Lab::new("cradle", &[]).unwrap();
    let bars = lab.energy_bars();
    assert!(bars.reference.contains("rest height"), "{bars:?}");
    // Closed form: one 1 kg ball lifted 30° on a 1 m cable is m g L (1 − cos 30°) up.
    let lifted = 9.81 * 1.0 * (1.0 - 30f32.to_radians().cos());
    assert!(
        (bar(&bars, "gravity") - lifted).abs() < 1e-3 * lifted.max(1.0),
        "{bars:?}, closed form {lifted} J"
    );
    // The same from the states, at every step of a swing: Σ m g (y − 0.6).
    let mut lab = lab;
    for _ in 0..300 {
        lab.run_steps(1);
        let world = lab.scene.world();
        let p = &world.particles;
        let from_states: f32 = (0..p.len()).map(|i| p.mass(i) * 9.81 * (p.positions()[i].y - 0.6)).sum();
        let shown = bar(&lab.energy_bars(), "gravity");
        assert!((shown - from_states).abs() < 1e-3, "{shown} J shown, {from_states} J from the states");
    }
    // The plot's potential is measured from the same height.
    let sample = lab.energy.back().unwrap();
    assert!(sample.energy.potential < 2.0, "{sample:?}");
}

#[test]
fn spring_forces_bars_show_the_bob_until_the_scene_is_asked_for() {
    // Before: the scene's bars, where the stiff spring's kilojoules swamp the bob's joules.
    let mut lab = Lab::new("springForces", &[]).unwrap();
    lab.run_steps(100);
    let bars = lab.energy_bars();
    assert_eq!(bars.subject, "the bob");
    let world = lab.scene.world();
    let p = &world.particles;
    let (m, v, y) = (p.mass(0), p.velocities()[0], p.positions()[0].y);
    assert!((bar(&bars, "kinetic") - 0.5 * m * v.length_squared()).abs() < 1e-4, "{bars:?}");
    assert!((bar(&bars, "gravity") - m * 9.81 * y).abs() < 1e-3, "{bars:?}");
    // Its spring, 2 m long at rest from (−6, 7, 0): ½ k (|p − anchor| − 2)².
    let stretch = (p.positions()[0] - Vec3::new(-6.0, 7.0, 0.0)).length() - 2.0;
    assert!((bar(&bars, "elastic") - 0.5 * 20.0 * stretch * stretch).abs() < 1e-3, "{bars:?}");
    lab.bars_for_selected = false;
    let scene = lab.energy_bars();
    assert_eq!(scene.subject, "the scene");
    assert!(bar(&scene, "dissipated") > 100.0, "the stiff spring's damping: {scene:?}");
}

#[test]
fn the_pendulums_bars_show_its_rods_error_as_the_constraint_bar_and_the_budget_level() {
    // The pendulum: no dissipated bar (nothing dissipates), a constraint bar that
    // is the world's constraint term, and a budget bar (total + dissipated + constraint
    // + removed - work) that stays at the start's total, to the integrator's error; the
    // plot's samples carry the same term.
    let mut lab = Lab::new("pendulum", &[]).unwrap();
    lab.paused = true;
    let total = |bars: &EnergyBars| bar(bars, "kinetic") + bar(bars, "gravity") + bar(bars, "elastic");
    let start = total(&lab.energy_bars());
    let mut swung = 0.0f32;
    for _ in 0..600 {
        lab.run_steps(1);
        let bars = lab.energy_bars();
        let e = lab.scene.world().energy();
        assert_eq!(bar(&bars, "dissipated"), 0.0, "{bars:?}");
        assert_eq!(bar(&bars, "constraint"), e.constraint, "{bars:?}");
        assert!((bar(&bars, "budget") - start).abs() < 1e-4, "{bars:?}, start {start} J");
        let sample = lab.energy.back().unwrap();
        assert_eq!(sample.energy.constraint, e.constraint);
        swung = swung.max(e.constraint.abs());
    }
    assert!(swung > 1e-4, "the rods' error is shown: up to {swung} J");
}

#[test]
fn zero_joules_is_no_bar_and_small_energies_are_shown_in_millijoules() {
    // A 5 g particle: its bars and labels agree, and an empty one is not drawn.
    let bars = EnergyBars {
        subject: "particle 0".into(),
        reference: "the ground (y = 0)".into(),
        bars: vec![("kinetic", 0.004), ("gravity", 0.0), ("elastic", 0.001), ("total", 0.005)],
    };
    let heights = bars.heights(100.0);
    assert_eq!(heights[1], 0.0);
    assert!((heights[0] - 80.0).abs() < 1e-3 && (heights[2] - 20.0).abs() < 1e-3, "{heights:?}");
    assert!((heights[3] - 100.0).abs() < 1e-3);
    assert_eq!(joules(0.004), "4.0 mJ");
    assert_eq!(joules(0.0), "0.0 J");
    assert_eq!(joules(-0.0), "0.0 J");
    assert_eq!(joules(-0.00001), "0.0 mJ", "never -0.0");
    assert_eq!(joules(12.345), "12.3 J");
    // A heap's kilojoules to 4 significant figures, so neighbouring bars' labels fit.
    assert_eq!(joules(63_514.1), "63.51 kJ");
    assert_eq!(joules(-1_666.9), "-1.667 kJ");
    assert_eq!(joules(716_400.0), "716.4 kJ");
    assert_eq!(joules(2_500_000.0), "2.500 MJ");
    assert_eq!(joules(3.2e10), "3.20e10 J");
    for e in [1_234.5f32, 98_765.4, 4_321_000.0] {
        let (number, unit) =
            joules(e).split_once(' ').map(|(n, u)| (n.parse::<f32>().unwrap(), u.to_string())).unwrap();
        let scale = if unit == "kJ" { 1e3 } else { 1e6 };
        assert!((number * scale / e - 1.0).abs() < 5e-4, "{e} shown as {}", joules(e));
    }
    // Negative bars hang below the zero line, in proportion.
    let signed = EnergyBars { bars: vec![("gravity", -2.0), ("kinetic", 6.0)], ..bars };
    assert_eq!(signed.heights(80.0), vec![-20.0, 60.0]);
}

#[test]
fn the_exact_answer_plot_breaks_between_rounds() {
    // Before: a diagonal line joined the last round's distance to the next round's.
    assert_eq!(segments(&[(0.0, 1.0), (1.0, 2.0), (2.0, f32::NAN), (3.0, 4.0)]).count(), 2);
    let entry = scenes::find("projectile").unwrap();
    let mut lab = Lab::from_entry(entry, &["speed=5".into()], Default::default()).unwrap();
    // The first round lands and goes (no exact answer then), a second is fired.
    lab.act(SceneAction::Fire);
    for _ in 0..400 {
        lab.run_steps(1);
    }
    assert!(lab.energy.back().unwrap().exact_error.is_nan(), "no round in flight");
    lab.act(SceneAction::Fire);
    for _ in 0..30 {
        lab.run_steps(1);
    }
    let series: Vec<(f64, f32)> = lab.energy.iter().map(|s| (s.t, s.exact_error)).collect();
    assert_eq!(segments(&series).count(), 2, "one line per round");
}

/// The zero height of gravitational energy is said to the figures a panel shows
/// (issue 37: the hourglass said "y = -5.1552753 m"), and a round height stays round;
/// the bars themselves use the full height.
#[test]
fn the_zero_height_is_said_to_four_figures() {
    let hourglass = Lab::new("hourglass", &[]).unwrap();
    let (height, said) = hourglass.gravity_from();
    assert!((height + 5.155_275).abs() < 1e-5, "{height}");
    assert_eq!(said, "the basin's floor (y = -5.155 m)");
    let (height, said) = Lab::new("pendulum", &[]).unwrap().gravity_from();
    assert_eq!(height, 0.5);
    assert!(said.ends_with("(y = 0.5 m)"), "{said}");
}

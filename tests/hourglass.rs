//! The hourglass (issue 21): grains draining through an opening in a floor flow at the
//! rate Beverloo's law gives, W = C ρ_b √g (D − k d)^{5/2} (C = 0.58, k = 1.5), for
//! openings of 5 and 10 grain diameters, within 30%; and the scene's read-outs say
//! what the test measures.
//!
//! Each measurement here is the test's own: it counts the grains below the floor from
//! their positions after every step, fits the discharged mass against time by least
//! squares over the steady part of the drain (from a tenth of the grains through to
//! [`STEADY_END`]: the bed is then still deeper than the opening is wide, where the flow
//! does not depend on the depth), and measures the bed's bulk density itself before the
//! drain has lowered the bed, in a different cell from the scene's (a cylindrical shell
//! about the opening's axis).
//!
//! Measured (release build, the scene's defaults but for the opening and the count,
//! 2026-12-06, after issue 39's contact changes): D = 5 d flows at 0.860 of Beverloo's
//! rate with bulk packing 0.569, and D = 10 d at 0.853 with 0.569 (2026-12-03: 0.817
//! with 0.595, and 0.813 with 0.591), so C ≈ 0.47 here: frictional (μ 0.5),
//! rolling-resistant (0.1) spheres flow a little slower than Beverloo's sand and seeds,
//! well within the 30% the issue allows. An earlier version measured that without
//! rolling resistance the ratio rises by about 0.07, and halving the step by about 0.05.

use particle_lab::scenes::{self, Scene};

const G: f32 = 9.81;
/// The fraction of the grains through at which the steady part of a drain ends.
const STEADY_END: f32 = 0.45;

struct Drain {
    /// Least-squares mass flow over the steady part (kg/s).
    flow: f32,
    /// The bed's packing fraction, measured by the test.
    packing: f32,
    /// The grains' diameter (m) and the opening's (m).
    d: f32,
    orifice: f32,
    grain_mass: f32,
    /// The scene's own read-outs at the end, and their numbers.
    readouts: Vec<(String, String)>,
    values: Vec<(&'static str, f64)>,
    /// Grains through at the end, by the test's count, of `count`.
    through: usize,
    count: usize,
    /// (time, through) of every step.
    series: Vec<(f64, usize)>,
}

/// Drains `count` grains of `radius` through an opening of `diameters` grain diameters
/// at the scene's own step, measuring as it goes.
fn drain(diameters: f32, count: usize, radius: f32) -> Drain {
    let d = 2.0 * radius;
    let orifice = diameters * d;
    let assignments = [format!("orifice={orifice}"), format!("radius={radius}"), format!("count={count}")];
    let mut scene = scenes::build("hourglass", &assignments).unwrap();
    let dt = scene.info().dt;
    let grain_mass = scene.world().particles.mass(0);
    let mut series = Vec::new();
    let mut packing = 0.0f32;
    let count_through = |scene: &dyn Scene| {
        let p = &scene.world().particles;
        p.positions().iter().zip(p.radii()).filter(|(c, r)| c.y < -**r).count()
    };
    let (low, high) = ((0.10 * count as f32) as usize, (STEADY_END * count as f32) as usize);
    for _ in 0..20_000 {
        scene.step(dt).unwrap();
        let through = count_through(scene.as_ref());
        series.push((scene.world().time(), through));
        if through < low {
            packing = packing.max(shell_packing(scene.as_ref(), orifice, radius));
        }
        if through > high + count / 20 {
            break;
        }
    }
    let steady: Vec<(f64, f64)> = series
        .iter()
        .filter(|&&(_, n)| n >= low && n <= high)
        .map(|&(t, n)| (t, n as f64 * f64::from(grain_mass)))
        .collect();
    assert!(steady.len() > 60, "the steady part lasted {} steps", steady.len());
    let flow = slope(&steady) as f32;
    let through = count_through(scene.as_ref());
    let values = scene.readout_values(dt);
    Drain {
        flow,
        packing,
        d,
        orifice,
        grain_mass,
        readouts: scene.readouts(dt),
        values,
        through,
        count,
        series,
    }
}

/// Packing fraction of the grains whose centres lie in a cylindrical shell about the
/// opening's axis, from 1.5 to 4.5 diameters above the floor and between 1.5 openings
/// and 1.5 openings plus 2 diameters from the axis: the static bed beside the flowing core.
fn shell_packing(scene: &dyn Scene, orifice: f32, radius: f32) -> f32 {
    let d = 2.0 * radius;
    let half = (1.25 * orifice).max(6.0 * d);
    let (r0, r1) = (half - 3.0 * d, half - d);
    let (y0, y1) = (1.5 * d, 4.5 * d);
    let p = &scene.world().particles;
    let inside = p
        .positions()
        .iter()
        .filter(|c| {
            let r = (c.x * c.x + c.z * c.z).sqrt();
            c.y >= y0 && c.y < y1 && r >= r0 && r < r1
        })
        .count();
    let volume = std::f32::consts::PI * (r1 * r1 - r0 * r0) * (y1 - y0);
    inside as f32 * (4.0 / 3.0 * std::f32::consts::PI * radius.powi(3)) / volume
}

/// Least-squares slope of y against x.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) =
        points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| (a + (x - mx) * (y - my), b + (x - mx) * (x - mx)));
    sxy / sxx
}

fn beverloo(packing: f32, orifice: f32, d: f32) -> f32 {
    0.58 * packing * 2500.0 * G.sqrt() * (orifice - 1.5 * d).powf(2.5)
}

/// Beverloo's flow and the test's measured one for an opening of `diameters` grain
/// diameters and `count` grains (a bed at least 1.5 openings deep).
fn check_beverloo(diameters: f32, count: usize) {
    let run = drain(diameters, count, 0.1);
    let predicted = beverloo(run.packing, run.orifice, run.d);
    let ratio = run.flow / predicted;
    println!(
        "D = {diameters} d: flow {:.1} kg/s, bulk packing {:.3}, Beverloo {:.1} kg/s, measured/Beverloo {ratio:.3}",
        run.flow, run.packing, predicted
    );
    assert!((0.55..0.68).contains(&run.packing), "a poured bed packs at 0.55-0.68, got {:.3}", run.packing);
    assert!(
        (0.7..1.3).contains(&ratio),
        "D = {diameters} d: {:.1} kg/s is {ratio:.3} of Beverloo's {predicted:.1}",
        run.flow
    );
    check_readouts(&run);
}

/// The scene's read-outs against the test's own count and arithmetic.
fn check_readouts(run: &Drain) {
    let value = |name: &str| {
        let (_, text) = run
            .readouts
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("no {name} in {:?}", run.readouts));
        text.split_whitespace().next().unwrap().parse::<f32>().unwrap_or_else(|_| panic!("{name}: {text}"))
    };
    assert_eq!(value("grains through") as usize, run.through, "{:?}", run.readouts);
    // The flow over the last second, from the test's series: the grains through now less
    // those through a second ago, at a grain's mass.
    let (t1, n1) = *run.series.last().unwrap();
    let &(t0, n0) = run.series.iter().rev().find(|&&(t, _)| t1 - t >= 1.0 - 1e-9).unwrap();
    let flow = (n1 - n0) as f32 * run.grain_mass / (t1 - t0) as f32;
    let shown = value("flow (last 1 s)");
    assert!((shown - flow).abs() <= 1e-3 * flow + 1e-3, "flow shown {shown}, counted {flow}");
    // Beverloo's flow from the packing shown, by the law written out here.
    let packing = value("bed packing");
    let beverloo_shown = value("Beverloo's flow");
    let expected = beverloo(packing, run.orifice, run.d);
    assert!(
        (beverloo_shown - expected).abs() <= 2e-3 * expected,
        "Beverloo shown {beverloo_shown}, from packing {packing}: {expected}"
    );
    let ratio = value("flow / Beverloo");
    assert!((ratio - shown / beverloo_shown).abs() < 2e-3, "ratio shown {ratio}, {shown} / {beverloo_shown}");
    // The steady flow the scene fitted to its record (a sample every 0.1 s) over the
    // same part of the drain as the test's fit to every step: the two agree.
    let number = |key: &str| {
        run.values.iter().find(|(k, _)| *k == key).unwrap_or_else(|| panic!("no {key} in {:?}", run.values)).1
            as f32
    };
    let steady = number("steady_flow_kg_s");
    assert!(
        (steady / run.flow - 1.0).abs() < 0.02,
        "steady flow shown {steady}, the test's fit {}",
        run.flow
    );
    let spread = number("steady_flow_spread_kg_s");
    assert!(spread > 0.0 && spread < 0.25 * steady, "spread {spread} of a steady {steady}");
    let (from, to) = (number("steady_from_s"), number("steady_to_s"));
    let low = (0.10 * run.count as f32) as usize;
    let started = run.series.iter().find(|&&(_, n)| n >= low).unwrap().0 as f32;
    assert!(
        from >= started - 1e-3 && from < started + 0.11,
        "steady from {from} s; 10% through at {started} s"
    );
    assert!(to > from + 1.0);
    let steady_ratio = number("steady_flow_over_beverloo");
    assert!((steady_ratio - steady / beverloo_shown).abs() < 2e-3);
}

#[test]
fn five_diameters_flow_at_beverloos_rate() {
    check_beverloo(5.0, 3000);
}

#[test]
fn ten_diameters_flow_at_beverloos_rate() {
    check_beverloo(10.0, 10_500);
}

/// Issue 39: whether an opening of 5 grain diameters jammed seemed to turn on the step
/// (it flowed at 120 and 200 Hz and jammed at 100 and 240), but it was chance at every
/// step: of five random starts, two jammed after 100 to 175 grains at each of 120, 240
/// and 480 Hz. An arch of grains held by rolling resistance against twist as well as
/// rolling, and by heavily damped contacts, was too strong. Two starts that jammed
/// then (seed 1 at 120 Hz after 134 grains, seed 0 at 240 Hz after 126) must now flow:
/// 3.5 s passes more than 150 grains (207 and 312 measured), and more than 30 still
/// pass in its last second (52 and 76).
#[test]
fn an_opening_of_five_grains_drains_at_either_rate_issue_39() {
    for (rate, seed) in [(120.0f32, 1), (240.0, 0)] {
        let assignments = ["orifice=1".to_string(), "count=3000".into(), format!("seed={seed}")];
        let mut scene = scenes::build("hourglass", &assignments).unwrap();
        let count_through = |scene: &dyn Scene| {
            let p = &scene.world().particles;
            p.positions().iter().zip(p.radii()).filter(|(c, r)| c.y < -**r).count()
        };
        let steps = (3.5 * rate).round() as usize;
        let mut a_second_before_the_end = 0;
        for step in 1..=steps {
            scene.step(1.0 / rate).unwrap();
            if step == steps - rate as usize {
                a_second_before_the_end = count_through(scene.as_ref());
            }
        }
        let through = count_through(scene.as_ref());
        let last_second = through - a_second_before_the_end;
        println!("{rate} Hz, seed {seed}: {through} grains through, {last_second} in the last second");
        assert!(
            through > 150 && last_second > 30,
            "{rate} Hz, seed {seed}: {through}, {last_second} in the last 1 s"
        );
    }
}

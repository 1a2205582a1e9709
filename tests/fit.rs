//! From table to graph (issue 37): the least-squares line of one column of a table of
//! runs against another. `particle-lab fit` on the rows `simulate --runs` wrote,
//! checked against the closed form (a drag-free apex is h + v² sin²θ / 2g, a straight
//! line in v²) and against the same fit done here by the textbook's raw sums; bad input
//! gets one line; and the panel's plot, driven through its UI, says the same figures.

use std::process::Command;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use particle_lab::scenes::SceneAction;
use particle_lab::ui::lab::Lab;
use particle_lab::ui::shell::LabUi;

fn lab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_particle-lab"))
}

fn folder(name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("fit-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const SPEEDS: [f64; 4] = [10.0, 20.0, 30.0, 40.0];

/// One `simulate --runs` file per launch speed at 45°, g 9.81, no damping.
fn runs_at_speeds(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    SPEEDS
        .iter()
        .map(|speed| {
            let csv = dir.join(format!("speed-{speed}.csv"));
            let out = lab()
                .args(["simulate", "--scene", "projectile", "--set", "damping=1", "--set", "g=9.81"])
                .args(["--set", &format!("speed={speed}"), "--steps", "2000", "--every", "2000"])
                .args(["--runs", csv.to_str().unwrap()])
                .output()
                .unwrap();
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            csv
        })
        .collect()
}

fn column(path: &std::path::Path, key: &str) -> f64 {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let c = lines.next().unwrap().split(',').position(|k| k == key).unwrap();
    lines.next().unwrap().split(',').nth(c).unwrap().parse().unwrap()
}

fn field(json: &serde_json::Value, key: &str) -> f64 {
    json[key].as_f64().unwrap_or_else(|| panic!("{key} in {json}"))
}

#[test]
fn apex_against_speed_squared_is_the_closed_forms_line() {
    let dir = folder("apex");
    let files = runs_at_speeds(&dir);
    let out = lab()
        .arg("fit")
        .args(&files)
        .args(["--x", "speed_m_s", "--y", "apex_m", "--square-x"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["n"], 4);
    let (slope, intercept, r2) = (field(&json, "slope"), field(&json, "intercept"), field(&json, "r2"));
    // The closed form: apex = h + sin²45° / (2 g) · v², h = 1.5 m.
    let expected = 0.5 / (2.0 * 9.81);
    assert!((slope / expected - 1.0).abs() < 2e-3, "slope {slope} against {expected}");
    assert!((intercept - 1.5).abs() < 0.01, "intercept {intercept}");
    assert!(r2 > 0.99999, "R² {r2}");
    // The same fit by the textbook's raw sums, from the files' own numbers.
    let xs: Vec<f64> = files.iter().map(|f| column(f, "speed_m_s").powi(2)).collect();
    let ys: Vec<f64> = files.iter().map(|f| column(f, "apex_m")).collect();
    let n = xs.len() as f64;
    let (sx, sy) = (xs.iter().sum::<f64>(), ys.iter().sum::<f64>());
    let sxx: f64 = xs.iter().map(|x| x * x).sum();
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| x * y).sum();
    let syy: f64 = ys.iter().map(|y| y * y).sum();
    let b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let a = (sy - b * sx) / n;
    let r = (n * sxy - sx * sy) / ((n * sxx - sx * sx) * (n * syy - sy * sy)).sqrt();
    assert!((slope - b).abs() < 1e-9 * b.abs(), "{slope} against {b}");
    assert!((intercept - a).abs() < 1e-6, "{intercept} against {a}");
    assert!((r2 - r * r).abs() < 1e-9, "{r2} against {}", r * r);
}

#[test]
fn bad_input_gets_one_line() {
    let dir = folder("bad");
    let good = runs_at_speeds(&dir)[0].clone();
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "a,b\n1,x\n").unwrap();
    let other = dir.join("other.csv");
    std::fs::write(&other, "a,b\n1,2\n").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![good.display().to_string(), "--x".into(), "spd".into(), "--y".into(), "apex_m".into()],
            "no column 'spd'",
        ),
        (
            vec![bad.display().to_string(), "--x".into(), "a".into(), "--y".into(), "b".into()],
            "'x' is not a number",
        ),
        (
            vec![
                dir.join("none.csv").display().to_string(),
                "--x".into(),
                "a".into(),
                "--y".into(),
                "b".into(),
            ],
            "cannot read",
        ),
        (
            vec![good.display().to_string(), "--x".into(), "speed_m_s".into(), "--y".into(), "apex_m".into()],
            "1 row with both values",
        ),
        (
            vec![
                good.display().to_string(),
                other.display().to_string(),
                "--x".into(),
                "speed_m_s".into(),
                "--y".into(),
                "apex_m".into(),
            ],
            "other columns",
        ),
    ];
    for (args, says) in cases {
        let out = lab().arg("fit").args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(out.stdout.is_empty());
    }
}

/// The panel's plot, opened by its label, fits the rows the lab measured and says the
/// same slope, intercept and R² as [`Table::fit`](particle_lab::scenes::runs::Table::fit)
/// computes from the rows, to its four figures.
#[test]
fn the_panels_plot_says_the_fit_of_the_rows_it_shows() {
    let mut lab = Lab::new("projectile", &["damping=1".into(), "g=9.81".into()]).unwrap();
    lab.scene.delete_runs(None);
    // Each round lands within 1,000 steps (the 50° one flies 3.98 s, 955 steps).
    for angle in [20.0, 35.0, 50.0] {
        lab.set_param("angle", angle);
        lab.act(SceneAction::Fire);
        lab.run_steps(1000);
    }
    let rows = lab.scene.runs().unwrap().rows.len();
    assert!(rows >= 3, "{rows} rows");
    let mut h =
        Harness::builder().with_size([1280.0, 2400.0]).with_accessibility_check(false).build_ui_state(
            |ui, (shell, lab): &mut (LabUi, Lab)| {
                shell.show(ui, lab);
            },
            (LabUi::default(), lab),
        );
    h.run_steps(2);
    h.get_by_label("Plot two columns").click();
    h.run_steps(3);
    let table = h.state().1.scene.runs().unwrap();
    let x = particle_lab::scenes::runs::Axis { column: table.column("angle_deg").unwrap(), squared: false };
    let y = particle_lab::scenes::runs::Axis { column: table.column("range_m").unwrap(), squared: false };
    let fit = table.fit(x, y).unwrap();
    let said = particle_lab::ui::views::runs_plot::describe(&fit, &table, x, y);
    assert!(said.starts_with("slope ") && said.contains(" m per °") && said.contains("R² "), "{said}");
    assert!(said.contains(&format!("({} runs)", fit.n)), "{said}");
    h.get_by_label(&said);
    // The figures in the text are the fit's, read back.
    let number = |after: &str| -> f64 {
        said.split(after)
            .nth(1)
            .unwrap()
            .split_whitespace()
            .next()
            .unwrap()
            .trim_end_matches(',')
            .parse()
            .unwrap()
    };
    assert!((number("slope ") / fit.slope - 1.0).abs() < 1e-3);
    assert!((number("intercept ") / fit.intercept - 1.0).abs() < 1e-3);
    assert!((number("R² ") - fit.r2).abs() < 1e-3);
}

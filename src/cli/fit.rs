//! `fit`: the least-squares line of one column of a table of runs against another, read
//! from CSV files (the panel's Save CSV, `simulate --runs`), as the panel's plot fits
//! it: the same [`least_squares`], the same slope, intercept, R² and count, printed as
//! one JSON line.

use crate::scenes::runs::least_squares;

/// `particle-lab fit`.
#[derive(Debug, clap::Args)]
pub struct FitArgs {
    /// CSV files of runs, read as one table (each with the same header): a file from
    /// the panel's Save CSV, or one `simulate --runs` file per run.
    #[arg(required = true, value_name = "FILE.csv")]
    pub files: Vec<std::path::PathBuf>,
    /// The column on the x axis, by its key in the header (`angle_deg`).
    #[arg(long, value_name = "KEY")]
    pub x: String,
    /// The column on the y axis, by its key in the header (`range_m`).
    #[arg(long, value_name = "KEY")]
    pub y: String,
    /// Fit against the square of x (apex against speed²).
    #[arg(long)]
    pub square_x: bool,
    /// Fit the square of y (period² against mass).
    #[arg(long)]
    pub square_y: bool,
}

/// The fit `args` ask for as a JSON line, or a one-line reason there is none.
pub fn fit(args: &FitArgs) -> Result<String, String> {
    let mut header: Option<Vec<String>> = None;
    let mut points = Vec::new();
    for path in &args.files {
        let shown = crate::messages::path(path);
        let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
        let mut lines = text.lines().filter(|line| !line.trim().is_empty());
        let first: Vec<String> = lines
            .next()
            .ok_or_else(|| format!("{shown} is empty: a table of runs starts with a header of column keys"))?
            .split(',')
            .map(|key| key.trim().to_string())
            .collect();
        match &header {
            Some(header) if *header != first => {
                return Err(format!(
                    "{shown} has other columns than {}",
                    crate::messages::path(&args.files[0])
                ));
            }
            _ => header = Some(first.clone()),
        }
        let column = |key: &str| {
            first.iter().position(|k| k == key).ok_or_else(|| {
                format!(
                    "{shown} has no column '{}'; its columns: {}",
                    crate::messages::quote(key),
                    first.join(", ")
                )
            })
        };
        let (x, y) = (column(&args.x)?, column(&args.y)?);
        for (k, line) in lines.enumerate() {
            let cells: Vec<&str> = line.split(',').collect();
            let value = |c: usize, squared: bool| -> Result<f64, String> {
                let cell = cells.get(c).map_or("", |cell| cell.trim());
                if cell.is_empty() {
                    return Ok(f64::NAN);
                }
                let v: f64 = cell.parse().map_err(|_| {
                    format!("{shown}, row {}: '{}' is not a number", k + 1, crate::messages::quote(cell))
                })?;
                Ok(if squared { v * v } else { v })
            };
            points.push((value(x, args.square_x)?, value(y, args.square_y)?));
        }
    }
    let fit = least_squares(points.iter().copied()).ok_or_else(|| {
        format!(
            "no line: {} with both values, and a line needs two rows with different {}",
            rows(count(&points)),
            args.x
        )
    })?;
    Ok(serde_json::json!({
        "x": args.x,
        "y": args.y,
        "square_x": args.square_x,
        "square_y": args.square_y,
        "n": fit.n,
        "slope": fit.slope,
        "intercept": fit.intercept,
        "r2": fit.r2,
    })
    .to_string())
}

fn count(points: &[(f64, f64)]) -> usize {
    points.iter().filter(|(x, y)| x.is_finite() && y.is_finite()).count()
}

fn rows(n: usize) -> String {
    if n == 1 { "1 row".into() } else { format!("{n} rows") }
}

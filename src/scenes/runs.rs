//! A table of runs: a row for each completed measurement (a round that landed, …),
//! the parameters it was made with beside each measured value and its prediction, as
//! a class writes them down to compare runs. The panel shows it, `simulate --runs`
//! writes it, and it travels in snapshots with its scene.

/// A column of a table of runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Column {
    /// Its name in CSV and JSON: snake_case, the unit in the name (`range_m`).
    pub key: &'static str,
    /// Its heading in the panel, unit included.
    pub heading: &'static str,
    /// What it is and how it is measured or predicted: the panel's tooltip.
    pub help: &'static str,
    /// Shown in the panel even when every run has the same value (a measurement, or
    /// the parameter a class varies); the others are shown once they differ, and
    /// said once beneath the table while they do not.
    pub always: bool,
}

impl Column {
    /// Whether the column is a measurement (its help begins "Measured"), not a
    /// parameter or a prediction.
    #[must_use]
    pub fn is_measured(&self) -> bool {
        self.help.starts_with("Measured")
    }

    /// Whether the column is a prediction (its key says `predicted`).
    #[must_use]
    pub fn is_prediction(&self) -> bool {
        self.key.contains("predicted")
    }
}

/// A scene's table of runs: its columns and rows (one value per column; NaN where
/// there is none, such as a prediction without gravity).
#[derive(Clone, Copy, Debug)]
pub struct Table<'a> {
    /// The columns, in order.
    pub columns: &'static [Column],
    /// The rows, oldest first.
    pub rows: &'a [Vec<f64>],
}

/// Significant figures the panel shows a run's values and a fit's figures with (the
/// CSV and JSON hold every digit).
pub const FIGURES: usize = 4;

/// Most rows a table keeps: the oldest goes first.
pub const MAX_ROWS: usize = 1000;

impl Table<'_> {
    /// The table as CSV: a header of the keys, then a row per run, each value in full
    /// (the fewest digits that read back the same), an empty field where there is none.
    #[must_use]
    pub fn csv(&self) -> String {
        self.text(',', |c| c.key)
    }

    /// The table as tab-separated text for a spreadsheet's paste, headed by the
    /// columns' headings.
    #[must_use]
    pub fn tsv(&self) -> String {
        self.text('\t', |c| c.heading)
    }

    fn text(&self, separator: char, name: impl Fn(&Column) -> &'static str) -> String {
        let mut out = String::new();
        let header: Vec<&str> = self.columns.iter().map(&name).collect();
        out.push_str(&header.join(&separator.to_string()));
        out.push('\n');
        for row in self.rows {
            let cells: Vec<String> = row.iter().map(|&x| full(x)).collect();
            out.push_str(&cells.join(&separator.to_string()));
            out.push('\n');
        }
        out
    }
}

/// A scene's runs: its columns and the rows measured so far, oldest first, at most
/// [`MAX_ROWS`] (the oldest goes first). Every scene that keeps a table keeps one of
/// these, and its snapshots save [`Runs::saved`] and read it back with
/// [`Runs::read`].
#[derive(Clone, Debug)]
pub struct Runs {
    columns: &'static [Column],
    rows: Vec<Vec<f64>>,
}

impl Runs {
    /// No rows yet, in `columns`.
    #[must_use]
    pub const fn new(columns: &'static [Column]) -> Self {
        Self { columns, rows: Vec::new() }
    }

    /// The table to show, write as CSV or plot.
    #[must_use]
    pub fn table(&self) -> Table<'_> {
        Table { columns: self.columns, rows: &self.rows }
    }

    /// Adds a row (a value per column, NaN where there is none), dropping the oldest
    /// once [`MAX_ROWS`] are kept.
    pub fn push(&mut self, row: Vec<f64>) {
        debug_assert_eq!(row.len(), self.columns.len(), "a value per column");
        if self.rows.len() == MAX_ROWS {
            self.rows.remove(0);
        }
        self.rows.push(row);
    }

    /// Deletes row `k`, or every row with `None`; a row that is not there is no change.
    pub fn delete(&mut self, which: Option<usize>) {
        match which {
            Some(k) if k < self.rows.len() => {
                self.rows.remove(k);
            }
            Some(_) => {}
            None => self.rows.clear(),
        }
    }

    /// The rows as a snapshot keeps them: `null` where a value is NaN (JSON has none).
    #[must_use]
    pub fn saved(&self) -> Vec<Vec<Option<f64>>> {
        self.rows.iter().map(|row| row.iter().map(|&x| (!x.is_nan()).then_some(x)).collect()).collect()
    }

    /// The rows a snapshot kept ([`Runs::saved`]), in these columns; the error says
    /// which row does not fit.
    pub fn read(&self, saved: Vec<Vec<Option<f64>>>) -> Result<Self, String> {
        if let Some(row) = saved.iter().find(|row| row.len() != self.columns.len()) {
            return Err(format!(
                "a run has {} values; this table's runs have {}",
                row.len(),
                self.columns.len()
            ));
        }
        if saved.len() > MAX_ROWS {
            return Err(format!("{} runs, more than the {MAX_ROWS} kept", saved.len()));
        }
        let rows = saved.into_iter().map(|row| row.into_iter().map(|x| x.unwrap_or(f64::NAN)).collect());
        Ok(Self { columns: self.columns, rows: rows.collect() })
    }
}

/// `x` in the fewest digits that read back the same: as an `f32` when it is one (the
/// engine's figures), else as an `f64`; empty for NaN.
#[must_use]
pub fn full(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else if f64::from(x as f32) == x {
        format!("{}", x as f32)
    } else {
        format!("{x}")
    }
}

/// `x` to `figures` significant figures, as the panel shows a measurement (a blank
/// for NaN): 39.12, 0.004167, and in scientific notation where the whole part alone
/// has more digits than that, or below 1e-4 (1.235e5).
#[must_use]
pub fn significant(x: f64, figures: usize) -> String {
    if x.is_nan() {
        return String::new();
    }
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i32;
    if magnitude < -4 || magnitude >= figures as i32 {
        return format!("{:.*e}", figures.saturating_sub(1), x);
    }
    let decimals = (figures as i32 - 1 - magnitude).max(0) as usize;
    format!("{x:.decimals$}")
}

/// A straight line fitted to a table's points by least squares, as a spreadsheet's
/// trend line: y ≈ slope · x + intercept, with R², the share of y's variance the
/// line accounts for (1: every point on it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// Points fitted (rows where both values exist).
    pub n: usize,
    /// Slope, in y's unit per x's.
    pub slope: f64,
    /// Where the line crosses x = 0, in y's unit.
    pub intercept: f64,
    /// Coefficient of determination, 0 to 1 (1 when every y is the same: the flat line
    /// through them is exact).
    pub r2: f64,
}

/// The least-squares line through `points`; points with a NaN or infinite value are
/// left out. `None` with fewer than two points left, or with every x the same (no
/// line is defined).
///
/// Sums about the means (not the textbook's raw sums of squares), so that values far
/// from zero (a launch time of 1e5 s, a height of 6.4e6 m) do not cancel away.
#[must_use]
pub fn least_squares(points: impl IntoIterator<Item = (f64, f64)> + Clone) -> Option<Fit> {
    let finite = |&(x, y): &(f64, f64)| x.is_finite() && y.is_finite();
    let (mut n, mut sum_x, mut sum_y) = (0_usize, 0.0, 0.0);
    for (x, y) in points.clone().into_iter().filter(finite) {
        n += 1;
        sum_x += x;
        sum_y += y;
    }
    if n < 2 {
        return None;
    }
    let (mean_x, mean_y) = (sum_x / n as f64, sum_y / n as f64);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (x, y) in points.into_iter().filter(finite) {
        let (dx, dy) = (x - mean_x, y - mean_y);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let r2 = if syy > 0.0 { (sxy * sxy / (sxx * syy)).min(1.0) } else { 1.0 };
    Some(Fit { n, slope, intercept: mean_y - slope * mean_x, r2 })
}

/// One axis of a plot of a table: a column, or its square (period² against mass).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Axis {
    /// The column's index in the table.
    pub column: usize,
    /// Plot the column's value squared.
    pub squared: bool,
}

impl Axis {
    /// The axis's value in `row`.
    #[must_use]
    pub fn value(self, row: &[f64]) -> f64 {
        let x = row[self.column];
        if self.squared { x * x } else { x }
    }

    /// The axis's label from its column's heading: "range (m)", or squared
    /// "period² (s²)", "g² ((m/s²)²)".
    #[must_use]
    pub fn label(self, columns: &[Column]) -> String {
        let heading = columns[self.column].heading;
        if !self.squared {
            return heading.to_string();
        }
        match heading.rsplit_once(" (") {
            Some((name, unit)) => {
                let unit = unit.trim_end_matches(')');
                let simple = !unit.contains(['/', '·', '²', ' ']);
                if simple { format!("{name}² ({unit}²)") } else { format!("{name}² (({unit})²)") }
            }
            None => format!("{heading}²"),
        }
    }

    /// The axis's unit, as its label gives it ("" for a count or a ratio).
    #[must_use]
    pub fn unit(self, columns: &[Column]) -> String {
        let label = self.label(columns);
        match label.split_once(" (") {
            Some((_, unit)) => unit[..unit.len() - 1].to_string(),
            None => String::new(),
        }
    }
}

impl Table<'_> {
    /// The index of the column named `key`.
    #[must_use]
    pub fn column(&self, key: &str) -> Option<usize> {
        self.columns.iter().position(|c| c.key == key)
    }

    /// The points of `x` against `y`, one per row.
    pub fn points(&self, x: Axis, y: Axis) -> impl Iterator<Item = (f64, f64)> + Clone + '_ {
        self.rows.iter().map(move |row| (x.value(row), y.value(row)))
    }

    /// The least-squares line of `y` against `x` over every row.
    #[must_use]
    pub fn fit(&self, x: Axis, y: Axis) -> Option<Fit> {
        least_squares(self.points(x, y))
    }
}

#[cfg(test)]
mod tests {
    use super::{Axis, Column, Table, full, least_squares, significant};

    static TWO: &[Column] = &[
        Column { key: "a_m", heading: "a (m)", help: "Measured: a", always: true },
        Column { key: "b_predicted_m", heading: "b (m)", help: "Predicted: b", always: true },
    ];

    #[test]
    fn runs_keep_the_newest_rows_delete_and_travel_through_a_snapshot() {
        let mut runs = super::Runs::new(TWO);
        for k in 0..super::MAX_ROWS + 2 {
            runs.push(vec![k as f64, f64::NAN]);
        }
        let table = runs.table();
        assert_eq!(table.rows.len(), super::MAX_ROWS, "the oldest go first");
        assert_eq!(table.rows[0][0], 2.0);
        runs.delete(Some(0));
        runs.delete(Some(5_000)); // not there: no change
        assert_eq!(runs.table().rows.len(), super::MAX_ROWS - 1);
        assert_eq!(runs.table().rows[0][0], 3.0);
        // A NaN is saved as null and read back as NaN.
        let saved = runs.saved();
        assert_eq!(saved[0], vec![Some(3.0), None]);
        let back = runs.read(saved).unwrap();
        assert_eq!(back.table().rows.len(), runs.table().rows.len());
        assert!(back.table().rows[0][1].is_nan());
        assert!(runs.read(vec![vec![Some(1.0)]]).unwrap_err().contains("a run has 1 values"));
        runs.delete(None);
        assert!(runs.table().rows.is_empty());
    }

    const COLUMNS: &[Column] = &[
        Column { key: "angle_deg", heading: "angle (°)", help: "", always: true },
        Column { key: "range_m", heading: "range (m)", help: "", always: true },
    ];

    #[test]
    fn csv_and_tsv_hold_every_row_in_full() {
        let rows = vec![vec![45.0, f64::from(39.118_946_f32)], vec![30.0, f64::NAN]];
        let table = Table { columns: COLUMNS, rows: &rows };
        assert_eq!(table.csv(), "angle_deg,range_m\n45,39.118946\n30,\n");
        assert_eq!(table.tsv(), "angle (°)\trange (m)\n45\t39.118946\n30\t\n");
        // What the CSV says reads back to the same numbers.
        let back: f32 = table.csv().lines().nth(1).unwrap().split(',').nth(1).unwrap().parse().unwrap();
        assert_eq!(f64::from(back), rows[0][1]);
        assert_eq!(full(0.1), "0.1");
    }

    #[test]
    fn significant_figures_are_those_asked() {
        assert_eq!(significant(39.118_946, 4), "39.12");
        assert_eq!(significant(3512.0625, 4), "3512");
        assert_eq!(significant(0.004_166_7, 4), "0.004167");
        assert_eq!(significant(-5.155_275_3, 4), "-5.155");
        assert_eq!(significant(123_456.0, 4), "1.235e5");
        assert_eq!(significant(f64::NAN, 4), "");
    }

    #[test]
    fn a_line_through_exact_points_is_found_exactly() {
        // y = 3 x - 2 at five points: slope 3, intercept -2, R² 1.
        let points: Vec<(f64, f64)> = (0..5).map(|k| (f64::from(k), 3.0 * f64::from(k) - 2.0)).collect();
        let fit = least_squares(points.iter().copied()).unwrap();
        assert_eq!(fit.n, 5);
        assert!((fit.slope - 3.0).abs() < 1e-12 && (fit.intercept + 2.0).abs() < 1e-12, "{fit:?}");
        assert!((fit.r2 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn anscombes_first_set_gives_its_published_line() {
        // Anscombe (1973), set I: y = 3.00 + 0.500 x, R² = 0.67 (to the digits published).
        let x = [10.0, 8.0, 13.0, 9.0, 11.0, 14.0, 6.0, 4.0, 12.0, 7.0, 5.0];
        let y = [8.04, 6.95, 7.58, 8.81, 8.33, 9.96, 7.24, 4.26, 10.84, 4.82, 5.68];
        let fit = least_squares(x.into_iter().zip(y)).unwrap();
        assert_eq!(fit.n, 11);
        assert!((fit.slope - 0.500).abs() < 5e-4, "{fit:?}");
        assert!((fit.intercept - 3.00).abs() < 5e-3, "{fit:?}");
        assert!((fit.r2 - 0.67).abs() < 5e-3, "{fit:?}");
        // R² is also the square of the correlation computed from raw sums.
        let n = 11.0;
        let (sx, sy) = (x.iter().sum::<f64>(), y.iter().sum::<f64>());
        let sxx: f64 = x.iter().map(|a| a * a).sum();
        let syy: f64 = y.iter().map(|a| a * a).sum();
        let sxy: f64 = x.iter().zip(&y).map(|(a, b)| a * b).sum();
        let r = (n * sxy - sx * sy) / ((n * sxx - sx * sx) * (n * syy - sy * sy)).sqrt();
        assert!((fit.r2 - r * r).abs() < 1e-12);
    }

    #[test]
    fn a_fit_needs_two_points_apart_and_skips_blanks() {
        assert_eq!(least_squares([(1.0, 2.0)]), None);
        assert_eq!(least_squares([(1.0, 2.0), (1.0, 5.0)]), None);
        let fit = least_squares([(0.0, 1.0), (f64::NAN, 7.0), (2.0, 5.0), (3.0, f64::NAN)]).unwrap();
        assert_eq!((fit.n, fit.slope, fit.intercept), (2, 2.0, 1.0));
        // Every y the same: the flat line is exact.
        assert_eq!(least_squares([(0.0, 4.0), (1.0, 4.0)]).unwrap().r2, 1.0);
        // Far from zero, the sums about the means keep the slope.
        let far: Vec<(f64, f64)> = (0..4).map(|k| (1e9 + f64::from(k), 2.0 * f64::from(k))).collect();
        assert!((least_squares(far).unwrap().slope - 2.0).abs() < 1e-6);
    }

    #[test]
    fn a_squared_axis_squares_its_values_and_its_unit() {
        let columns = &[
            Column { key: "period_s", heading: "period (s)", help: "", always: true },
            Column { key: "g_m_s2", heading: "g (m/s²)", help: "", always: true },
            Column { key: "ratio", heading: "ratio", help: "", always: true },
        ];
        let period = Axis { column: 0, squared: true };
        assert_eq!(period.label(columns), "period² (s²)");
        assert_eq!(period.unit(columns), "s²");
        assert_eq!(Axis { column: 1, squared: true }.label(columns), "g² ((m/s²)²)");
        assert_eq!(Axis { column: 1, squared: false }.unit(columns), "m/s²");
        assert_eq!(Axis { column: 2, squared: true }.label(columns), "ratio²");
        assert_eq!(Axis { column: 2, squared: false }.unit(columns), "");
        assert_eq!(period.value(&[3.0, 0.0, 0.0]), 9.0);
    }
}

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

/// A scene's table of runs: its columns and rows (one value per column; NaN where
/// there is none, such as a prediction without gravity).
#[derive(Clone, Copy, Debug)]
pub struct Table<'a> {
    /// The columns, in order.
    pub columns: &'static [Column],
    /// The rows, oldest first.
    pub rows: &'a [Vec<f64>],
}

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

#[cfg(test)]
mod tests {
    use super::{Column, Table, full, significant};

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
}

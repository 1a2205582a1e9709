//! A scene's read-outs: the rows the panel shows, each with the numbers it was
//! formatted from, which `simulate` prints. One source for both, so the panel never
//! shows a figure the command line cannot give.

/// One row of the panel's Read-outs section and the numbers behind its text.
#[derive(Clone, Debug, PartialEq)]
pub struct Readout {
    /// What the panel writes on the left: "bob's period, measured".
    pub label: &'static str,
    /// What it writes on the right, formatted from `values`: "1.234 s". A row may be
    /// text alone ("timing…") while its number does not exist yet.
    pub text: String,
    /// The row's numbers, each under a stable snake_case key that ends in its unit
    /// (`period_s`, `flow_kg_s`; counts and ratios have none), as `simulate` prints
    /// them: unrounded, in the precision the scene computed them in.
    pub values: Vec<(&'static str, f64)>,
    /// The panel's tooltip: what it is, how it is measured, and for a prediction its
    /// formula and what the formula leaves out.
    pub help: &'static str,
}

/// A measured value as a read-out shows it, with its unit: to the significant figures a
/// measurement supports (4, [`FIGURES`](super::runs::FIGURES)), where `simulate` and the
/// table's CSV keep every digit. `shown(0.000_213_7, "m/s")` is "0.0002137 m/s".
#[must_use]
pub fn shown(value: f32, unit: &str) -> String {
    let number = super::runs::significant(f64::from(value), super::runs::FIGURES);
    if unit.is_empty() { number } else { format!("{number} {unit}") }
}

impl Readout {
    /// A row with no numbers yet: add them with [`Readout::with`].
    #[must_use]
    pub fn new(label: &'static str, text: impl Into<String>) -> Self {
        Self { label, text: text.into(), values: Vec::new(), help: "" }
    }

    /// Whether the row is a prediction (a value under a `…_predicted_…` or `…_exact_s`
    /// key, or Beverloo's law and the flow against it), which View → Predictions off
    /// hides so that a class predicts before it measures.
    #[must_use]
    pub fn is_prediction(&self) -> bool {
        self.values.iter().any(|(key, _)| {
            key.contains("predicted") || key.ends_with("_exact_s") || key.contains("beverloo")
        })
    }

    /// The row with its tooltip.
    #[must_use]
    pub fn help(mut self, help: &'static str) -> Self {
        self.help = help;
        self
    }

    /// The row with one more number, computed in f32, under `key`. It is kept as the
    /// f64 nearest the f32's shortest decimal, so 1.1 prints as 1.1, not as the
    /// 1.100000023841858 a bare widening gives, and reads back to the same f32.
    #[must_use]
    pub fn with(self, key: &'static str, value: f32) -> Self {
        let widened = if value.is_finite() {
            value.to_string().parse().expect("an f32's decimal is an f64's")
        } else {
            f64::from(value)
        };
        self.with_f64(key, widened)
    }

    /// The row with one more number, computed in f64, under `key`.
    #[must_use]
    pub fn with_f64(mut self, key: &'static str, value: f64) -> Self {
        self.values.push((key, value));
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_f32_read_out_keeps_its_shortest_decimal() {
        let row = Readout::new("peak", "1.10 m").with("peak_m", 1.1).with("flow_kg_s", 0.1 + 0.2);
        // A bare widening would give 1.100000023841858; the decimal reads back as the f32.
        assert_ne!(f64::from(1.1_f32), 1.1);
        assert_eq!(row.values[0], ("peak_m", 1.1));
        assert_eq!(row.values[1].1 as f32, 0.1_f32 + 0.2);
        assert_eq!(row.values[1].1.to_string(), (0.1_f32 + 0.2).to_string());
    }

    #[test]
    fn a_shown_value_has_four_significant_figures_and_its_unit() {
        assert_eq!(shown(0.000_213_7, "m/s"), "0.0002137 m/s");
        assert_eq!(shown(-5.155_275_3, "m"), "-5.155 m");
        assert_eq!(shown(3512.0625, "kg/s"), "3512 kg/s");
        assert_eq!(shown(0.0, "m"), "0 m");
        assert_eq!(shown(0.5, ""), "0.5000");
        // The number reads back to within half a unit of its last figure.
        for x in [1.234_567_f32, 98.765_43, 0.012_345_67] {
            let back: f32 = shown(x, "").parse().expect("a number");
            let last = 10f32.powi(x.log10().floor() as i32 - 3);
            assert!((back - x).abs() <= 0.5 * last * 1.0001, "{x} shown as {back}");
        }
    }

    #[test]
    fn a_read_out_that_is_not_a_number_stays_so() {
        let row = Readout::new("lowest", "").with("lowest_m", f32::INFINITY).with("ratio", f32::NAN);
        assert_eq!(row.values[0].1, f64::INFINITY);
        assert!(row.values[1].1.is_nan());
    }
}

//! From table to graph: any two columns of the table of runs (or their squares)
//! plotted against each other, with the least-squares line and its slope, intercept
//! and R², as a class does in a spreadsheet (range against angle; apex against speed²).
//! The fit is [`Table::fit`]; `particle-lab fit` prints the same figures from a CSV.

use crate::scenes::runs::{Axis, Column, FIGURES, Fit, Table, significant};

/// What the plot shows, by column key so that it outlives the table's rows; kept in
/// egui's memory for the panel.
#[derive(Clone, Debug, Default)]
struct Choice {
    x: Option<&'static str>,
    y: Option<&'static str>,
    square_x: bool,
    square_y: bool,
}

impl Choice {
    /// The axes for `columns`: the chosen keys, or by default the first column (what
    /// a class varies, the angle) against the first measured one (the range).
    fn axes(&self, columns: &[Column]) -> (Axis, Axis) {
        let find = |key: Option<&str>| key.and_then(|key| columns.iter().position(|c| c.key == key));
        let x = find(self.x).unwrap_or(0);
        let y = find(self.y).or_else(|| columns.iter().position(Column::is_measured)).unwrap_or(0);
        (Axis { column: x, squared: self.square_x }, Axis { column: y, squared: self.square_y })
    }
}

/// The fit's line as a person writes it, units included: "slope 0.4087 m per °,
/// intercept 2.1 m, R² 0.9987 (5 runs)".
#[must_use]
pub fn describe(fit: &Fit, table: &Table<'_>, x: Axis, y: Axis) -> String {
    let (x_unit, y_unit) = (x.unit(table.columns), y.unit(table.columns));
    let per = match (y_unit.is_empty(), x_unit.is_empty()) {
        (_, true) => y_unit.clone(),
        (true, false) => format!("per {x_unit}"),
        (false, false) => format!("{y_unit} per {x_unit}"),
    };
    format!(
        "slope {} {per}, intercept {} {y_unit}, R² {} ({} runs)",
        significant(fit.slope, FIGURES),
        significant(fit.intercept, FIGURES),
        significant(fit.r2, FIGURES),
        fit.n
    )
    .replace("  ", " ")
    .replace(" ,", ",")
}

/// Draws the plot of the table under it: two column pickers (each with a "squared" box),
/// the points, the fitted line and its figures.
/// With `predictions` false (View → Predictions off) the predicted columns are not
/// offered.
pub fn ui(ui: &mut egui::Ui, table: &Table<'_>, predictions: bool) {
    egui::CollapsingHeader::new("Plot two columns").id_salt("runs plot").show(ui, |ui| {
        let id = egui::Id::unique("runs plot choice");
        let mut choice: Choice = ui.data(|d| d.get_temp(id)).unwrap_or_default();
        if !predictions {
            // A predicted column chosen before the predictions were hidden is dropped.
            let predicted = |key: Option<&str>| {
                key.and_then(|k| table.column(k)).is_some_and(|c| table.columns[c].is_prediction())
            };
            if predicted(choice.x) {
                choice.x = None;
            }
            if predicted(choice.y) {
                choice.y = None;
            }
        }
        let (x, y) = choice.axes(table.columns);
        egui::Grid::new("runs plot axes").num_columns(3).show(ui, |ui| {
            ui.label("y");
            pick(ui, "plot y", table.columns, y.column, &mut choice.y, predictions);
            ui.checkbox(&mut choice.square_y, "squared").on_hover_text("Plot y² (period² against mass)");
            ui.end_row();
            ui.label("against x");
            pick(ui, "plot x", table.columns, x.column, &mut choice.x, predictions);
            ui.checkbox(&mut choice.square_x, "squared").on_hover_text("Plot x² (apex against speed²)");
            ui.end_row();
        });
        let (x, y) = choice.axes(table.columns);
        ui.data_mut(|d| d.insert_temp(id, choice));
        let points: Vec<[f64; 2]> =
            table.points(x, y).filter(|(a, b)| a.is_finite() && b.is_finite()).map(|(a, b)| [a, b]).collect();
        let fit = table.fit(x, y);
        let line = fit.map(|fit| {
            let lo = points.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
            let hi = points.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
            vec![[lo, fit.slope * lo + fit.intercept], [hi, fit.slope * hi + fit.intercept]]
        });
        egui_plot::Plot::new("runs plot area")
            .height(180.0)
            .width(ui.available_width())
            // Tick labels closer than egui_plot's 60 px: a panel-wide plot has room
            // for only three or four.
            .custom_x_axes(vec![
                egui_plot::AxisHints::new_x().label(x.label(table.columns)).label_spacing(30.0..=50.0),
            ])
            .y_axis_label(y.label(table.columns))
            .allow_scroll(false)
            .show(ui, |plot| {
                plot.points(egui_plot::Points::new("runs", points).radius(3.5));
                if let Some(line) = line {
                    plot.line(egui_plot::Line::new("least-squares line", line));
                }
            });
        let text = match &fit {
            Some(fit) => describe(fit, table, x, y),
            None => "a line needs two runs with different x".to_string(),
        };
        ui.label(egui::RichText::new(text).small()).on_hover_text(
            "The straight line y = slope·x + intercept that makes the sum of the squared vertical distances \
             to the points least. R² is the share of y's spread about its mean that the line accounts for: \
             1 when every point is on it. A curve (range against angle) fits a line poorly: plot what the \
             theory makes straight (apex against speed², flight time against speed).",
        );
    });
}

/// A column picker: sets `chosen` to the key picked; predicted columns only with
/// `predictions`.
fn pick(
    ui: &mut egui::Ui,
    salt: &str,
    columns: &[Column],
    current: usize,
    chosen: &mut Option<&'static str>,
    predictions: bool,
) {
    egui::ComboBox::from_id_salt(salt).selected_text(columns[current].heading).show_ui(ui, |ui| {
        for column in columns.iter().filter(|c| predictions || !c.is_prediction()) {
            if ui.selectable_label(column.key == columns[current].key, column.heading).clicked() {
                *chosen = Some(column.key);
            }
        }
    });
}

//! The Energy section: the plot of kinetic, potential and total energy with the
//! constraint solve's error and the budget's remainder (the integrator's error), the
//! distance from the exact answer
//! where the scene has one, the bars (PhET's energy chart), and the CSV export.

use std::collections::VecDeque;

use egui::{Color32, Rect, RichText, Sense, Stroke};

use crate::messages::fixed;
use crate::ui::lab::{EnergySample, Lab};
use crate::ui::paint;
use crate::ui::plot::{self, Curve, PlotAreas};
use crate::ui::style::{
    CONSTRAINT_COLOR, DISSIPATED_COLOR, ELASTIC_COLOR, ERROR_COLOR, GRAVITY_COLOR, KINETIC_COLOR,
    LEGEND_SIZE, REMOVED_COLOR, TOTAL_COLOR, dimmed, joules, srgb,
};

/// Seconds of simulated time the plots show (and scale to): a transient at the start
/// leaves the plot once it is this old.
pub const PLOT_SECONDS: f64 = 10.0;

/// Height of the energy plot (points).
pub const PLOT_HEIGHT: f32 = 90.0;

/// One curve of the energy plot: its legend entry, colour and value.
type Series = (&'static str, Color32, fn(&EnergySample) -> f32);

/// The energy plot's curves.
const SERIES: [Series; 6] = [
    ("kinetic", KINETIC_COLOR, |s| s.energy.kinetic),
    ("potential", GRAVITY_COLOR, |s| s.energy.potential),
    ("total", TOTAL_COLOR, |s| s.energy.kinetic + s.energy.potential),
    ("removed", REMOVED_COLOR, |s| s.energy.removed),
    // What the constraint solve's corrections took out (negative: put in).
    ("constraint error", CONSTRAINT_COLOR, |s| s.energy.constraint),
    // What the budget leaves over: total + dissipated + constraint + removed - work,
    // less its start.
    ("integrator error", ERROR_COLOR, |s| s.energy.error),
];

/// What the plot's legend says of each curve when hovered.
const SERIES_HELP: &str = "Kinetic, potential and total energy of the scene; 'removed': what particles \
    carried out when they left it; 'constraint error': what the constraint solve's corrections took \
    out (negative: put in), such as a rod moved back to its length or an overlap pushed apart, which \
    ideal links and contacts would not (it swings about zero on a rigid pendulum and grows with the \
    step); 'integrator error': what the budget leaves over, total + dissipated + constraint error + \
    removed − work put in, less its start.";

/// The compared copy's two curves, in the colour of its ghosts and a dimmer twin.
#[must_use]
pub fn compare_colors() -> (Color32, Color32) {
    let copy = srgb(paint::COMPARE_COLOR);
    (copy, dimmed(copy, 0.6))
}

/// The energy section; it remembers where it drew its plot, for the layout's checks.
#[derive(Debug, Default)]
pub struct EnergyPanel {
    /// The energy plot's areas in the last frame, if it was drawn.
    pub plot: Option<PlotAreas>,
    /// The legend's entries in the last frame, in order.
    pub legend: Vec<String>,
}

impl EnergyPanel {
    /// Draws the plot, the exact-answer plot, the bars and the export button.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        self.plot = None;
        self.energy_plot(ui, lab);
        let hover = if cfg!(target_arch = "wasm32") {
            "Every sample kept, downloaded"
        } else {
            "Every sample kept, to the current directory"
        };
        if ui.small_button("Export energy as CSV").on_hover_text(hover).clicked() {
            let name = format!("energy-{}-t{:.0}s.csv", lab.entry.info().name, lab.scene.world().time());
            #[cfg(target_arch = "wasm32")]
            {
                lab.status = match crate::ui::page::download(&name, "text/csv", lab.energy_csv().as_bytes()) {
                    Ok(()) => format!("energy downloaded as {name}"),
                    Err(error) => error,
                };
            }
            #[cfg(not(target_arch = "wasm32"))]
            {
                let path = std::path::PathBuf::from(name);
                lab.status = match lab.export_energy_csv(&path) {
                    Ok(()) => format!("energy written to {}", path.display()),
                    Err(error) => format!("could not write {}: {error}", path.display()),
                };
            }
        }
        error_plot(ui, lab);
        ui.separator();
        energy_bars(ui, lab);
    }

    /// Kinetic, potential and total energy over the last [`PLOT_SECONDS`], and the
    /// budget's remainder. The legend is a row above the curves, one entry per curve
    /// (the compared copy's total and error each have their own).
    fn energy_plot(&mut self, ui: &mut egui::Ui, lab: &Lab) {
        let (copy_total, copy_error) = compare_colors();
        let mut legend: Vec<(String, Color32)> =
            SERIES.iter().map(|(name, color, _)| (name.to_string(), *color)).collect();
        if lab.compare.is_some() {
            legend.push(("copy total".into(), copy_total));
            legend.push(("copy error".into(), copy_error));
        }
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new("Last 10 s:").strong()).on_hover_text(format!(
                "{SERIES_HELP} Potential energy's gravitational part is measured from {}.",
                lab.gravity_from().1
            ));
            for (name, color) in &legend {
                ui.label(RichText::new(name.as_str()).color(*color).size(LEGEND_SIZE));
            }
        });
        self.legend = legend.into_iter().map(|(name, _)| name).collect();
        let Some(newest) = lab.energy.back() else { return };
        let since = newest.t - PLOT_SECONDS;
        let mut curves: Vec<Curve> = SERIES
            .iter()
            .map(|(_, color, value)| {
                (*color, lab.energy.iter().filter(|s| s.t >= since).map(|s| (s.t, value(s))).collect())
            })
            .collect();
        if let Some(compare) = &lab.compare {
            let shown = || compare.energy.iter().filter(|s| s.t >= since);
            curves
                .push((copy_total, shown().map(|s| (s.t, s.energy.kinetic + s.energy.potential)).collect()));
            curves.push((copy_error, shown().map(|s| (s.t, s.energy.error)).collect()));
        }
        self.plot = Some(plot::line_plot(ui, &curves, PLOT_HEIGHT, joules));
    }
}

/// Distance from the exact answer over the last [`PLOT_SECONDS`] (mm), where the scene
/// has one: how far the integrator has drifted from the closed form; the compared
/// copy's too.
fn error_plot(ui: &mut egui::Ui, lab: &Lab) {
    let Some(newest) = lab.energy.back() else { return };
    let since = newest.t - PLOT_SECONDS;
    let millimetres = |samples: &VecDeque<EnergySample>| -> Vec<(f64, f32)> {
        samples.iter().filter(|s| s.t >= since).map(|s| (s.t, s.exact_error * 1000.0)).collect()
    };
    let ours = millimetres(&lab.energy);
    // Gaps (no round in flight) stay in the series, to break its line there.
    let last = |points: &[(f64, f32)]| points.iter().rev().find(|(_, v)| v.is_finite()).map(|p| p.1);
    let Some(now) = last(&ours) else { return };
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new("Distance from the exact answer").strong()).on_hover_text(
            "How far the simulated particle (the newest round, or the bob) is from its ghost: the \
             closed form of its motion. Try another integrator or physics rate, or Compare them.",
        );
        ui.monospace(format!("{} mm", fixed(now, 2)));
    });
    let mut curves = vec![(ERROR_COLOR, ours)];
    if let Some(compare) = &lab.compare {
        let theirs = millimetres(&compare.energy);
        let (copy, _) = compare_colors();
        if let Some(then) = last(&theirs) {
            ui.colored_label(copy, format!("copy ({}): {} mm", compare.change.describe(), fixed(then, 2)));
        }
        curves.push((copy, theirs));
    }
    plot::line_plot(ui, &curves, 50.0, |mm| format!("{} mm", fixed(mm, 2)));
}

/// The colour of an energy bar by its name.
fn bar_color(name: &str) -> Color32 {
    match name {
        "kinetic" => KINETIC_COLOR,
        "gravity" => GRAVITY_COLOR,
        "elastic" => ELASTIC_COLOR,
        "dissipated" => DISSIPATED_COLOR,
        "constraint" => CONSTRAINT_COLOR,
        "removed" => REMOVED_COLOR,
        _ => TOTAL_COLOR,
    }
}

/// PhET's energy bar chart: kinetic, gravitational, elastic, dissipated, the constraint
/// term, removed and the budget (total + dissipated + constraint + removed − work put
/// in, which stays level), for the whole
/// scene or one particle (the selected one, else the scene's focus, springForces' bob),
/// without dissipation, which the world tracks only in total.
fn energy_bars(ui: &mut egui::Ui, lab: &mut Lab) {
    let chart = lab.energy_bars();
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(format!("Energy bars: {}", chart.subject)).strong()).on_hover_text(format!(
            "Gravitational energy is measured from {}; elastic includes buoyancy's. 'dissipated' is what \
             damping, drag, inelastic bounces, friction and rolling resistance took out: it only grows. \
             'constraint' is what the constraint solve's corrections took out (negative: put in), such \
             as a rod moved back to its length: the solver's error, beside the integrator's. 'removed' \
             is what particles carried out when they left the scene. The budget bar, total + \
             dissipated + constraint + removed − work put in, stays level when the budget balances.",
            chart.reference
        ));
        let particle = lab.selected.is_some() || lab.scene.energy_focus().is_some();
        if particle {
            let name = if lab.selected.is_some() { "selected" } else { "focus" };
            ui.selectable_value(&mut lab.bars_for_selected, false, "scene");
            ui.selectable_value(&mut lab.bars_for_selected, true, name);
        }
    });
    ui.label(RichText::new(format!("gravity from {}", chart.reference)).size(LEGEND_SIZE));
    // The names go below the bars, on two rows, every other one raised, when one row
    // has no room for them (seven bars in a narrow panel).
    let width = ui.available_width();
    let slot = width / chart.bars.len() as f32;
    let name_font = egui::FontId::proportional(11.0);
    let widest = chart
        .bars
        .iter()
        .map(|(name, _)| {
            ui.painter().layout_no_wrap(name.to_string(), name_font.clone(), Color32::GRAY).size().x
        })
        .fold(0.0, f32::max);
    let rows = if widest + 4.0 > slot { 2.0 } else { 1.0 };
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 116.0), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_gray(20));
    // Room for a value above and the names below each bar.
    let (top, bottom) = (rect.top() + 15.0, rect.bottom() - 2.0 - 14.0 * rows);
    let heights = chart.heights(bottom - top);
    let low = heights.iter().copied().fold(0.0, f32::min);
    let zero = bottom + low;
    painter.line_segment(
        [egui::pos2(rect.left(), zero), egui::pos2(rect.right(), zero)],
        Stroke::new(1.0, Color32::GRAY),
    );
    for (k, ((name, value), height)) in chart.bars.iter().zip(&heights).enumerate() {
        let x = rect.left() + slot * (k as f32 + 0.5);
        let (y0, y1) = (zero.min(zero - height), zero.max(zero - height));
        // 0 J is no bar (not a one-pixel stub a reader takes for a small energy).
        if *height != 0.0 {
            let bar = Rect::from_x_y_ranges(x - slot * 0.3..=x + slot * 0.3, y0..=y1.max(y0 + 0.5));
            painter.rect_filled(bar, 1.0, bar_color(name));
        }
        painter.text(
            egui::pos2(x, y0 - 1.0),
            egui::Align2::CENTER_BOTTOM,
            joules(*value),
            egui::FontId::monospace(9.5),
            Color32::GRAY,
        );
        let raised = if rows > 1.0 && k % 2 == 1 { 14.0 } else { 0.0 };
        painter.text(
            egui::pos2(x, rect.bottom() - 1.0 - raised),
            egui::Align2::CENTER_BOTTOM,
            *name,
            name_font.clone(),
            bar_color(name),
        );
    }
}

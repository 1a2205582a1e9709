//! Line plots over a shared time axis, as the energy and error plots draw them: the
//! curves in a frame, their scale's top and bottom written in a margin at the right
//! where no curve runs, so a label never sits on the data.

use egui::{Color32, Rect, Sense, Stroke};

use super::style::LEGEND_SIZE;

/// Width of the margin at the right of a plot that holds its scale (points).
pub const SCALE_MARGIN: f32 = 64.0;

/// One curve: its colour and its `(t, value)` points.
pub type Curve = (Color32, Vec<(f64, f32)>);

/// The runs of a series between its breaks (a value that is not finite: no round in
/// flight, no exact answer), each drawn as its own line, so a plot never draws a line
/// across a gap where the series has no value.
pub fn segments(points: &[(f64, f32)]) -> impl Iterator<Item = &[(f64, f32)]> {
    points.split(|(_, v)| !v.is_finite()).filter(|run| !run.is_empty())
}

/// Where a plot drew: the curves' area, and the margin with the scale beside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlotAreas {
    /// Where the curves are drawn.
    pub data: Rect,
    /// Where the scale's numbers are written (right of the data, never over it).
    pub scale: Rect,
}

/// The two areas of a plot in `rect`.
#[must_use]
pub fn areas(rect: Rect) -> PlotAreas {
    let split = (rect.right() - SCALE_MARGIN).max(rect.left());
    PlotAreas {
        data: Rect::from_x_y_ranges(rect.left()..=split, rect.y_range()),
        scale: Rect::from_x_y_ranges(split..=rect.right(), rect.y_range()),
    }
}

/// Draws `curves` scaled to fit what they show, `height` points tall across the
/// available width, with the top and bottom of the scale in `unit`'s format in the
/// margin. Returns the areas it drew in.
pub fn line_plot(ui: &mut egui::Ui, curves: &[Curve], height: f32, unit: fn(f32) -> String) -> PlotAreas {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(ui.available_width(), height), Sense::hover());
    let PlotAreas { data, scale } = areas(rect);
    let painter = ui.painter_at(rect);
    painter.rect_filled(data, 2.0, Color32::from_gray(20));
    let points = || curves.iter().flat_map(|(_, points)| points.iter()).filter(|(_, v)| v.is_finite());
    let (t0, t1) = points().fold((f64::MAX, f64::MIN), |(lo, hi), &(t, _)| (lo.min(t), hi.max(t)));
    let (low, high) = points().fold((f32::MAX, f32::MIN), |(lo, hi), &(_, v)| (lo.min(v), hi.max(v)));
    if t0 > t1 {
        return PlotAreas { data, scale };
    }
    let span_t = (t1 - t0).max(1e-6);
    let span = (high - low).max(1e-6);
    let to_screen = |t: f64, v: f32| {
        egui::pos2(
            data.left() + ((t - t0) / span_t) as f32 * data.width(),
            data.bottom() - 4.0 - (v - low) / span * (data.height() - 8.0),
        )
    };
    for (color, points) in curves {
        for run in segments(points) {
            let line: Vec<egui::Pos2> = run.iter().map(|&(t, v)| to_screen(t, v)).collect();
            painter.add(egui::Shape::line(line, Stroke::new(1.5, *color)));
        }
    }
    let font = egui::FontId::monospace(LEGEND_SIZE - 1.0);
    for (corner, offset, align, value) in [
        (scale.right_top(), egui::vec2(-2.0, 2.0), egui::Align2::RIGHT_TOP, high),
        (scale.right_bottom(), egui::vec2(-2.0, -2.0), egui::Align2::RIGHT_BOTTOM, low),
    ] {
        painter.text(corner + offset, align, unit(value), font.clone(), Color32::GRAY);
    }
    PlotAreas { data, scale }
}

//! The colour keys beside the read-outs: the links' colours by kind, or by tension
//! with its scale in N, and the colour-by-speed ramp in m/s.

use egui::{Color32, Rect, Sense, Stroke};

use crate::physics::LinkKind;
use crate::render::frame::{
    SPEED_SCALE, link_color, ramp_srgb, speed_fraction, tension_color, tension_reference,
};
use crate::ui::lab::Lab;
use crate::ui::style::{LEGEND_SIZE, srgb};

/// The key to the links' colours: a swatch per kind of link in the scene, or with
/// colours by tension the scale from the hardest push (cyan) through none (blue) to the
/// hardest pull (red), in N, as the view paints it this frame.
pub fn link_key(ui: &mut egui::Ui, lab: &Lab) {
    let links = lab.scene.world().links();
    if links.is_empty() {
        return;
    }
    ui.separator();
    if !lab.view.tension_colors {
        let mut kinds: Vec<LinkKind> = Vec::new();
        for link in &links {
            if !kinds.contains(&link.spec.kind) {
                kinds.push(link.spec.kind);
            }
        }
        ui.horizontal_wrapped(|ui| {
            ui.label(egui::RichText::new("Links").strong())
                .on_hover_text("View > Link colours by tension colours them by the force they carry");
            for kind in kinds {
                let (swatch, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), Sense::hover());
                ui.painter().rect_filled(swatch, 2.0, srgb(link_color(kind)));
                ui.label(kind.name().replace('_', " "));
            }
        });
        return;
    }
    let reference = tension_reference(&links);
    ui.label(egui::RichText::new("Link tension").strong()).on_hover_text(
        "Scaled to the link carrying the most this frame; the square root spreads the colours of \
         lightly loaded links",
    );
    // From -reference (left) to +reference (right).
    let (painter, bar) = colour_bar(ui, |at| srgb(tension_color(reference * (2.0 * at - 1.0), reference)));
    for (at, align, text) in [
        (0.0, egui::Align2::LEFT_TOP, format!("{:.0} N push", reference)),
        (0.5, egui::Align2::CENTER_TOP, "0".to_string()),
        (1.0, egui::Align2::RIGHT_TOP, format!("{:.0} N pull", reference)),
    ] {
        let x = bar.left() + bar.width() * at;
        painter.text(
            egui::pos2(x, bar.bottom() + 3.0),
            align,
            text,
            egui::FontId::proportional(LEGEND_SIZE),
            Color32::GRAY,
        );
    }
}

/// The colour-by-speed scale: the ramp with speeds (m/s) under it.
pub fn speed_legend(ui: &mut egui::Ui) {
    ui.label(egui::RichText::new("Colour by speed").strong())
        .on_hover_text(format!("A fixed scale, square root of speed: {SPEED_SCALE} m/s and faster are red"));
    let (painter, bar) = colour_bar(ui, |at| {
        let [r, g, b] = ramp_srgb(at);
        Color32::from_rgb(r, g, b)
    });
    for (speed, label) in
        [(0.0, "0"), (0.1, "0.1"), (1.0, "1"), (2.5, "2.5"), (5.0, "5"), (SPEED_SCALE, "10 m/s")]
    {
        let x = bar.left() + bar.width() * speed_fraction(speed);
        painter.line_segment(
            [egui::pos2(x, bar.bottom()), egui::pos2(x, bar.bottom() + 3.0)],
            Stroke::new(1.0, Color32::GRAY),
        );
        let align = match label {
            "0" => egui::Align2::LEFT_TOP,
            "10 m/s" => egui::Align2::RIGHT_TOP,
            _ => egui::Align2::CENTER_TOP,
        };
        painter.text(
            egui::pos2(x, bar.bottom() + 3.0),
            align,
            label,
            egui::FontId::proportional(LEGEND_SIZE),
            Color32::GRAY,
        );
    }
}

/// A colour scale: a bar of bands, each the colour `color_at` gives for the middle of
/// its share of the bar (0 at the left, 1 at the right), with room under it for the
/// scale's numbers. Returns the painter and the bar's rectangle, for the numbers.
fn colour_bar(ui: &mut egui::Ui, color_at: impl Fn(f32) -> Color32) -> (egui::Painter, Rect) {
    const BANDS: usize = 48;
    let width = ui.available_width().min(280.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 30.0), Sense::hover());
    let painter = ui.painter_at(rect);
    let bar = Rect::from_min_size(rect.min, egui::vec2(rect.width(), 12.0));
    for band in 0..BANDS {
        let left = bar.left() + bar.width() * band as f32 / BANDS as f32;
        let right = bar.left() + bar.width() * (band + 1) as f32 / BANDS as f32;
        let band_rect = Rect::from_x_y_ranges(left..=right + 0.5, bar.y_range());
        painter.rect_filled(band_rect, 0.0, color_at((band as f32 + 0.5) / BANDS as f32));
    }
    (painter, bar)
}

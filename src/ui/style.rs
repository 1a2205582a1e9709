//! The panel's look: colours of the kinds of energy, text sizes, and how numbers are
//! written (joules, milliseconds), shared by every view.

use egui::Color32;

use crate::messages::fixed;

/// Colours of the energy plot's and bars' kinds of energy.
pub const KINETIC_COLOR: Color32 = Color32::from_rgb(240, 140, 40);
/// See [`KINETIC_COLOR`].
pub const GRAVITY_COLOR: Color32 = Color32::from_rgb(80, 160, 240);
/// See [`KINETIC_COLOR`].
pub const ELASTIC_COLOR: Color32 = Color32::from_rgb(200, 110, 230);
/// See [`KINETIC_COLOR`].
pub const DISSIPATED_COLOR: Color32 = Color32::from_rgb(235, 100, 90);
/// See [`KINETIC_COLOR`].
pub const TOTAL_COLOR: Color32 = Color32::from_rgb(220, 220, 220);
/// See [`KINETIC_COLOR`].
pub const REMOVED_COLOR: Color32 = Color32::from_rgb(150, 150, 110);
/// The budget's remainder, the integrator's error.
pub const ERROR_COLOR: Color32 = Color32::from_rgb(110, 210, 120);
/// The constraint solve's error: what its corrections took out or put in.
pub const CONSTRAINT_COLOR: Color32 = Color32::from_rgb(90, 200, 210);
/// A warning in the panel (a clamped value, a physics that cannot keep up).
pub const WARNING_COLOR: Color32 = Color32::from_rgb(240, 170, 60);
/// The menu bar's "paused".
pub const PAUSED_COLOR: Color32 = Color32::from_rgb(240, 190, 60);
/// The Fire button's fill (its text is the theme's strong text).
pub const FIRE_FILL: Color32 = Color32::from_rgb(150, 60, 30);

/// The panel's theme: always dark, whatever the system's, since the colours above are
/// chosen (and tested, [`contrast`]) against its backgrounds.
pub const THEME: egui::ThemePreference = egui::ThemePreference::Dark;

/// The dark theme's look, with its two dimmest texts raised to WCAG AA's contrast
/// (egui's weak text is 2.7:1 on the panel and its error red 4.3:1; see the test).
#[must_use]
pub fn visuals() -> egui::Visuals {
    let mut visuals = egui::Visuals::dark();
    visuals.weak_text_color = Some(Color32::from_gray(132));
    visuals.error_fg_color = Color32::from_rgb(255, 110, 100);
    visuals
}

/// WCAG 2's contrast ratio of two opaque colours, 1 to 21: (L₁ + 0.05) / (L₂ + 0.05)
/// with L the relative luminance of the lighter and the darker. Text needs at least
/// 4.5 (level AA).
#[must_use]
pub fn contrast(a: Color32, b: Color32) -> f64 {
    let luminance = |c: Color32| {
        let linear = |u: u8| {
            let s = f64::from(u) / 255.0;
            if s <= 0.04045 { s / 12.92 } else { ((s + 0.055) / 1.055).powf(2.4) }
        };
        0.2126 * linear(c.r()) + 0.7152 * linear(c.g()) + 0.0722 * linear(c.b())
    };
    let (la, lb) = (luminance(a), luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

/// Text size of legends and plot scales (points): at least 12, so they can be read.
pub const LEGEND_SIZE: f32 = 12.0;

/// A linear-RGB colour as egui's sRGB.
#[must_use]
pub fn srgb([r, g, b]: [f32; 3]) -> Color32 {
    let channel = |c: f32| (c.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0 + 0.5) as u8;
    Color32::from_rgb(channel(r), channel(g), channel(b))
}

/// `color` at `alpha` (0 to 1) over black: a dimmer twin for a second curve of the
/// same thing (the compared copy's error beside its total).
#[must_use]
pub fn dimmed(color: Color32, alpha: f32) -> Color32 {
    let scale = |c: u8| (f32::from(c) * alpha.clamp(0.0, 1.0) + 0.5) as u8;
    Color32::from_rgb(scale(color.r()), scale(color.g()), scale(color.b()))
}

/// An energy for the plot's scale and the bars: one decimal in joules, 4 significant
/// figures in kJ and MJ once it is that large (63.51 kJ, not 63514.1 J), scientific
/// notation beyond (a spring exploding), and mJ below a joule.
#[must_use]
pub fn joules(e: f32) -> String {
    let figures = |x: f32| crate::scenes::runs::significant(f64::from(x), crate::scenes::runs::FIGURES);
    let size = e.abs();
    if size >= 1e9 {
        format!("{e:.2e} J")
    } else if size >= 1e6 {
        format!("{} MJ", figures(e / 1e6))
    } else if size >= 1e3 {
        format!("{} kJ", figures(e / 1e3))
    } else if size >= 0.95 || e == 0.0 {
        format!("{} J", fixed(e, 1))
    } else {
        // A light particle's energies are a fraction of a joule: in mJ, not "0.0 J".
        format!("{} mJ", fixed(e * 1000.0, 1))
    }
}

/// `ms` milliseconds, as µs below one.
#[must_use]
pub fn milliseconds(ms: f32) -> String {
    if ms < 1.0 { format!("{:.0} µs", ms * 1000.0) } else { format!("{ms:.1} ms") }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `color` (egui's premultiplied alpha) drawn over the opaque `background`.
    fn over(color: Color32, background: Color32) -> Color32 {
        let a = f32::from(color.a()) / 255.0;
        let mix = |c: u8, b: u8| (f32::from(c) + f32::from(b) * (1.0 - a)).round().min(255.0) as u8;
        Color32::from_rgb(
            mix(color.r(), background.r()),
            mix(color.g(), background.g()),
            mix(color.b(), background.b()),
        )
    }

    #[test]
    fn contrast_is_wcags() {
        // WCAG's own end points and a figure worked by hand: #777 on white is 4.48.
        assert!((contrast(Color32::BLACK, Color32::WHITE) - 21.0).abs() < 1e-9);
        assert!((contrast(Color32::WHITE, Color32::WHITE) - 1.0).abs() < 1e-12);
        let grey = Color32::from_gray(0x77);
        assert!((contrast(grey, Color32::WHITE) - 4.478).abs() < 0.001, "{}", contrast(grey, Color32::WHITE));
        assert_eq!(contrast(grey, Color32::WHITE), contrast(Color32::WHITE, grey));
    }

    /// Every colour the panel writes text in, on every background it writes it on, has
    /// WCAG AA's contrast of 4.5: the theme's text (plain, weak, on buttons in each
    /// state, links, warnings, errors) and the lab's own colours (energy, warnings,
    /// the compared copy, the legends' grey).
    #[test]
    fn every_text_colour_has_a_contrast_of_4_5() {
        assert_eq!(THEME, egui::ThemePreference::Dark, "the colours are chosen for the dark theme");
        let visuals = visuals();
        let backgrounds = [
            ("panel", visuals.panel_fill),
            ("window", visuals.window_fill),
            ("plot and text field", visuals.extreme_bg_color),
            ("striped row", visuals.faint_bg_color),
        ];
        let texts = [
            ("text", visuals.text_color()),
            ("weak text", visuals.weak_text_color()),
            ("strong text", visuals.strong_text_color()),
            ("link", visuals.hyperlink_color),
            ("warning", visuals.warn_fg_color),
            ("error", visuals.error_fg_color),
            ("kinetic", KINETIC_COLOR),
            ("gravity", GRAVITY_COLOR),
            ("elastic", ELASTIC_COLOR),
            ("dissipated", DISSIPATED_COLOR),
            ("total", TOTAL_COLOR),
            ("removed", REMOVED_COLOR),
            ("integrator error", ERROR_COLOR),
            ("constraint", CONSTRAINT_COLOR),
            ("lab warning", WARNING_COLOR),
            ("paused", PAUSED_COLOR),
            ("compared copy", srgb(crate::ui::paint::COMPARE_COLOR)),
            ("legend", Color32::GRAY),
        ];
        let mut failures = Vec::new();
        for (name, background) in backgrounds {
            for &(text, color) in &texts {
                let ratio = contrast(over(color, background), background);
                if ratio < 4.5 {
                    failures.push(format!("{text} on {name}: {ratio:.2}"));
                }
            }
        }
        // A button's text on its own fill, in each state a button is drawn in.
        let widgets = &visuals.widgets;
        for (state, w) in
            [("inactive", widgets.inactive), ("hovered", widgets.hovered), ("active", widgets.active)]
        {
            let fill = over(w.weak_bg_fill, visuals.panel_fill);
            let ratio = contrast(over(w.fg_stroke.color, fill), fill);
            if ratio < 4.5 {
                failures.push(format!("{state} button's text: {ratio:.2}"));
            }
        }
        let fire = contrast(visuals.strong_text_color(), FIRE_FILL);
        if fire < 4.5 {
            failures.push(format!("Fire button: {fire:.2}"));
        }
        let selected = over(visuals.selection.bg_fill, visuals.panel_fill);
        let ratio = contrast(visuals.selection.stroke.color, selected);
        if ratio < 4.5 {
            failures.push(format!("selected text: {ratio:.2}"));
        }
        assert!(failures.is_empty(), "below WCAG AA's 4.5:1: {failures:#?}");
    }
}

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
pub const DISSIPATED_COLOR: Color32 = Color32::from_rgb(220, 80, 70);
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

/// An energy for the plot's scale: one decimal, or scientific notation once it is so
/// large (a spring exploding) that the digits would run off the plot.
#[must_use]
pub fn joules(e: f32) -> String {
    if e.abs() >= 1e5 {
        format!("{e:.2e} J")
    } else if e.abs() >= 0.95 || e == 0.0 {
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

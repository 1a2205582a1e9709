//! The Parameters section: a slider per scene parameter (whole numbers for counts),
//! its warning when the value asks too much of the time step, the presets, and the
//! scene's actions, Fire first and large beside the launch sliders.

use egui::RichText;

use crate::scenes::SceneAction;
use crate::ui::lab::Lab;
use crate::ui::style::WARNING_COLOR;

/// The scene's parameters. It remembers where it drew each slider (for the window's
/// tests, which press where a person would).
#[derive(Debug, Default)]
pub struct SceneParams {
    /// Each parameter's slider in the last frame: name and rectangle (points).
    pub sliders: Vec<(String, egui::Rect)>,
}

/// Height of the Fire button (points): the one control a projectile lesson presses
/// again and again.
pub const FIRE_HEIGHT: f32 = 32.0;

impl SceneParams {
    /// Draws the sliders, presets and actions, and applies what was changed.
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        fire_button(ui, lab);
        self.sliders.clear();
        let mut changes = Vec::new();
        for (param, value) in lab.scene.params().iter() {
            let mut edited = value;
            let label = if param.unit.is_empty() {
                param.name.to_string()
            } else {
                format!("{} ({})", param.name, param.unit)
            };
            let slider = egui::Slider::new(&mut edited, param.min..=param.max)
                .logarithmic(param.logarithmic)
                // A typed value beyond the range reaches the lab, which clamps it
                // and says so.
                .clamping(egui::SliderClamping::Never)
                .text(label);
            let slider = if param.integer { slider.integer() } else { slider };
            let response = ui.add(slider).on_hover_text(&*param.help);
            self.sliders.push((param.name.to_string(), response.rect));
            if response.changed() && edited != value {
                changes.push((param.name.to_string(), edited));
            }
            if let Some(warning) = lab.scene.param_warning(&param.name, lab.integration_step()) {
                ui.colored_label(WARNING_COLOR, warning);
            }
        }
        for (name, value) in changes {
            lab.set_param_typed(&name, value);
        }
        let presets = lab.entry.info().presets;
        if !presets.is_empty() {
            ui.label("Presets");
            ui.horizontal_wrapped(|ui| {
                for preset in presets {
                    if ui.button(preset.name).on_hover_text(preset.help).clicked() {
                        lab.apply_preset(preset.name);
                    }
                }
            });
        }
        let others: Vec<_> =
            lab.entry.info().actions.iter().filter(|action| action.action != SceneAction::Fire).collect();
        if !others.is_empty() {
            ui.horizontal_wrapped(|ui| {
                for action in others {
                    if ui.button(action.label).on_hover_text(action.key).clicked() {
                        lab.act(action.action);
                    }
                }
            });
        }
    }
}

/// The scene's Fire action, if it has one, as a wide button above the launch sliders.
fn fire_button(ui: &mut egui::Ui, lab: &mut Lab) {
    let Some(fire) = lab.entry.info().actions.iter().find(|action| action.action == SceneAction::Fire) else {
        return;
    };
    let text = RichText::new(format!("{}  ({})", fire.label, fire.key)).size(16.0).strong();
    let button = egui::Button::new(text).fill(crate::ui::style::FIRE_FILL);
    let width = ui.available_width();
    if ui
        .add_sized([width, FIRE_HEIGHT], button)
        .on_hover_text("Launch a round with the values below")
        .clicked()
    {
        lab.act(SceneAction::Fire);
    }
}

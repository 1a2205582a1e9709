//! The shell: places the views of one frame (menu bar at the top, status line at the
//! bottom, the side panel's sections on the left, the Controls window, the 3D view in
//! the middle) and routes the keys. It holds each view's own state and the layout
//! the settings save.

use egui::Rect;

use super::keys;
use super::lab::Lab;
use super::layout::{PanelLayout, Section};
use super::views::builder::BuilderPanel;
use super::views::compare_panel::ComparePanel;
use super::views::energy::EnergyPanel;
use super::views::help::HelpWindow;
use super::views::inspector::Inspector;
use super::views::menu_bar::MenuBar;
use super::views::readouts::Readouts;
use super::views::run_controls::RunControls;
use super::views::scene_params::SceneParams;
use super::views::stats::StatsPanel;
use super::views::view_3d::View3d;

/// Width of the side panel (points): fixed, so a long read-out wraps instead of
/// widening it, and narrow enough for the view to keep most of an 800x600 window.
pub const PANEL_WIDTH: f32 = 330.0;

/// The whole interface: every view and the layout.
#[derive(Debug, Default)]
pub struct LabUi {
    /// Which panels and sections are open; saved with the settings.
    pub layout: PanelLayout,
    /// The menu bar and its menus.
    pub menu: MenuBar,
    /// The Run section.
    pub run: RunControls,
    /// The Parameters section.
    pub params: SceneParams,
    /// The Inspector section.
    pub inspector: Inspector,
    /// The Energy section.
    pub energy: EnergyPanel,
    /// The Read-outs section.
    pub readouts: Readouts,
    /// The Compare section.
    pub compare: ComparePanel,
    /// The builder's section, while it is open.
    pub builder: BuilderPanel,
    /// The Stats section.
    pub stats: StatsPanel,
    /// The Controls window.
    pub help: HelpWindow,
    /// The 3D view.
    pub view: View3d,
    /// Where each section shown in the last frame was drawn (its header and body),
    /// top to bottom, in points.
    pub drawn: Vec<(Section, Rect)>,
    /// The scene the panel was last drawn for: another one opens at the panel's top.
    panel_scene: String,
}

impl LabUi {
    /// An interface with `layout` (from the settings).
    #[must_use]
    pub fn new(layout: PanelLayout) -> Self {
        Self { layout, ..Self::default() }
    }

    /// Where `section` was drawn in the last frame, if it was.
    #[must_use]
    pub fn drawn(&self, section: Section) -> Option<Rect> {
        self.drawn.iter().find(|(s, _)| *s == section).map(|(_, rect)| *rect)
    }

    /// Draws the whole interface for one frame and handles its input. Returns the 3D
    /// view's rectangle (in points).
    pub fn show(&mut self, ui: &mut egui::Ui, lab: &mut Lab) -> Rect {
        lab.poll_scene_file();
        // The text size is the layout's (saved with the settings): egui's own Ctrl+= is
        // off, and the keys table's Ctrl+= / Ctrl+- step it instead.
        ui.ctx().options_mut(|options| {
            options.zoom_with_keyboard = false;
            options.theme_preference = crate::ui::style::THEME;
        });
        let visuals = crate::ui::style::visuals();
        if ui.ctx().style_of(egui::Theme::Dark).visuals != visuals {
            ui.ctx().set_visuals_of(egui::Theme::Dark, visuals);
        }
        keys::handle(ui.ctx(), lab, &mut self.layout);
        let zoom = self.layout.zoom();
        if (ui.ctx().zoom_factor() - zoom).abs() > 1e-4 {
            ui.ctx().set_zoom_factor(zoom);
        }
        egui::Panel::top("menu").show(ui, |ui| self.menu.ui(ui, lab, &mut self.layout));
        if !lab.status.is_empty() {
            egui::Panel::bottom("status").show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.label(&lab.status);
                    if ui.small_button("Dismiss").clicked() {
                        lab.status.clear();
                    }
                });
            });
        }
        self.drawn.clear();
        if self.layout.open {
            // A new scene opens at the top of its panel, not scrolled to where the last
            // one was read (the builder's edits keep the scene's name, and their place).
            let scene = &*lab.entry.info().name;
            let mut scroll = egui::ScrollArea::vertical();
            if self.panel_scene != scene {
                self.panel_scene = scene.to_string();
                scroll = scroll.vertical_scroll_offset(0.0);
            }
            egui::Panel::left("controls").exact_size(PANEL_WIDTH).resizable(false).show(ui, |ui| {
                scroll.show(ui, |ui| {
                    // Long read-outs wrap instead of widening the panel.
                    ui.set_max_width(PANEL_WIDTH - 16.0);
                    self.side_panel(ui, lab);
                });
            });
        } else {
            self.energy.plot = None;
        }
        self.help.show(ui.ctx(), &mut self.layout);
        self.help.show_about(ui.ctx(), &mut self.layout, lab.entry.info());
        // A file asked for by its key (Ctrl+O, Ctrl+S), as the File menu's item does.
        if let Some(purpose) = lab.requests.file.take() {
            self.menu.file.asked(purpose, lab);
        }
        // The path field standing in for a file dialog that cannot open.
        self.menu.file.prompt_ui(ui.ctx(), lab);
        egui::CentralPanel::no_frame().show(ui, |ui| self.view.ui(ui, lab)).inner
    }

    /// The side panel's sections, top to bottom: the inspector first when a particle
    /// is selected (where the eye goes after a click), then run, parameters, energy,
    /// read-outs, compare and, with View → Stats, the stats.
    fn side_panel(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        ui.heading(&*lab.entry.info().name);
        ui.label(egui::RichText::new(&*lab.entry.info().summary).small());
        if lab.editing() {
            egui::Frame::group(ui.style()).show(ui, |ui| {
                ui.label(egui::RichText::new("Build").strong());
                self.builder.ui(ui, lab);
            });
        }
        let picked = self.inspector.newly_selected(lab);
        let Self { layout, run, params, inspector, energy, readouts, compare, stats, drawn, .. } = self;
        let mut show = |ui: &mut egui::Ui,
                        layout: &mut PanelLayout,
                        section: Section,
                        title: &str,
                        open_now: bool,
                        add: &mut dyn FnMut(&mut egui::Ui, &mut PanelLayout)| {
            let header = egui::CollapsingHeader::new(egui::RichText::new(title).strong())
                .id_salt(section.title())
                .default_open(layout.is_open(section))
                .open(open_now.then_some(true));
            let shown = header.show(ui, |ui| add(ui, layout));
            let mut rect = shown.header_response.rect;
            if let Some(body) = &shown.body_response {
                rect = rect.union(body.rect);
            }
            drawn.push((section, rect));
            // Kept with the settings once the section has finished opening or closing.
            if shown.openness == 0.0 || shown.openness == 1.0 {
                layout.set_open(section, shown.openness == 1.0);
            }
        };
        if lab.selected.is_some() {
            show(ui, layout, Section::Inspector, "Inspector", picked, &mut |ui, _| inspector.ui(ui, lab));
        }
        show(ui, layout, Section::Run, "Run", false, &mut |ui, layout| run.ui(ui, lab, layout));
        show(ui, layout, Section::Parameters, "Parameters", false, &mut |ui, _| params.ui(ui, lab));
        energy.plot = None;
        show(ui, layout, Section::Energy, "Energy", false, &mut |ui, _| energy.ui(ui, lab));
        show(ui, layout, Section::Readouts, "Read-outs", false, &mut |ui, _| readouts.ui(ui, lab));
        let title = ComparePanel::title(lab);
        show(ui, layout, Section::Compare, title, false, &mut |ui, _| compare.ui(ui, lab));
        if lab.view.stats {
            show(ui, layout, Section::Stats, "Stats", false, &mut |ui, _| stats.ui(ui, lab));
        }
    }
}

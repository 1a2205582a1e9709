//! The Controls window (Help → Controls, F1): every key and mouse control, listed from
//! the same table the key handler reads; and the About this scene window, the open
//! scene's page on its physics ([`crate::scenes::about`]).

use crate::ui::keys::SHORTCUTS;
use crate::ui::layout::PanelLayout;

/// The Controls window; whether it is open is part of the saved layout.
#[derive(Debug, Default)]
pub struct HelpWindow;

impl HelpWindow {
    /// The rows the window lists: keys and meaning, those that work where it runs.
    #[must_use]
    pub fn rows() -> Vec<(&'static str, &'static str)> {
        Self::rows_for(cfg!(target_arch = "wasm32"))
    }

    /// The rows on the web page (`web`) or the desktop: the page cannot quit the
    /// browser's tab, so it leaves out Ctrl+Q.
    #[must_use]
    pub fn rows_for(web: bool) -> Vec<(&'static str, &'static str)> {
        SHORTCUTS
            .iter()
            .filter(|s| !(web && s.command == Some(crate::ui::keys::Command::Quit)))
            .map(|s| (s.keys, s.meaning))
            .collect()
    }

    /// Shows the window while `layout.help` is set; its close button clears it.
    pub fn show(&mut self, ctx: &egui::Context, layout: &mut PanelLayout) {
        let mut open = layout.help;
        egui::Window::new("Controls").open(&mut open).resizable(false).show(ctx, |ui| {
            egui::Grid::new("shortcuts").num_columns(2).striped(true).show(ui, |ui| {
                for (keys, meaning) in Self::rows() {
                    ui.monospace(keys);
                    ui.label(meaning);
                    ui.end_row();
                }
            });
        });
        layout.help = open;
    }

    /// Shows the open scene's page while `layout.about` is set: a compiled scene's own,
    /// or a scene file's summary above the page shared by files.
    pub fn show_about(
        &mut self,
        ctx: &egui::Context,
        layout: &mut PanelLayout,
        info: &crate::scenes::SceneInfo,
    ) {
        let mut open = layout.about;
        let (page, summary) = match crate::scenes::about::page(&info.name) {
            Some(page) => (page, None),
            None => (&crate::scenes::about::FILE_PAGE, Some(&info.summary)),
        };
        egui::Window::new("About this scene").open(&mut open).default_width(460.0).resizable(true).show(
            ctx,
            |ui| {
                egui::ScrollArea::vertical().max_height(ctx.content_rect().height() * 0.7).show(ui, |ui| {
                    ui.heading(if summary.is_some() { &*info.name } else { page.title });
                    if let Some(summary) = summary {
                        ui.label(&**summary);
                    }
                    for (heading, body) in page.sections {
                        ui.add_space(6.0);
                        ui.label(egui::RichText::new(*heading).strong());
                        ui.label(*body);
                    }
                });
            },
        );
        layout.about = open;
    }
}

#[cfg(test)]
mod tests {
    use super::HelpWindow;

    #[test]
    fn the_page_lists_no_key_that_cannot_work_there() {
        let (desktop, web) = (HelpWindow::rows_for(false), HelpWindow::rows_for(true));
        assert!(desktop.iter().any(|(keys, _)| *keys == "Ctrl+Q"), "the desktop quits with Ctrl+Q");
        assert!(!web.iter().any(|(keys, _)| *keys == "Ctrl+Q"), "a page cannot quit its tab");
        assert_eq!(web.len() + 1, desktop.len(), "and nothing else is left out");
    }
}

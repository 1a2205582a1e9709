//! Off-screen captures of a lab, with or without the panel: the `render` command, the
//! render tests and the render benchmark all use this. (Saving a run's state is
//! [`crate::scenes::snapshot`]; this only draws it.)

use crate::render::{Gpu, OffscreenTarget, SpherePath, offscreen};
use crate::ui::paint::{Painter, UiFrame};
use crate::ui::{Lab, LabUi};

/// Renders lab frames off-screen with one device and one set of renderers.
pub struct FrameCapture {
    /// The device.
    pub gpu: Gpu,
    painter: Painter,
    egui: egui::Context,
    /// The interface drawn with `with_ui`: its layout, drafts and sections.
    pub ui: LabUi,
    target: Option<OffscreenTarget>,
    /// egui passes already run at the current size: its layout needs a few to settle.
    settled: bool,
}

impl FrameCapture {
    /// Finds an adapter (no display needed) and builds the renderers, drawing spheres
    /// the fastest way the adapter allows.
    pub fn new() -> Result<Self, String> {
        Self::with_sphere_path(None)
    }

    /// As [`Self::new`], drawing spheres the way `path` says (the adapter's choice for
    /// `None`): the tests draw with both ways and compare.
    pub fn with_sphere_path(path: Option<SpherePath>) -> Result<Self, String> {
        let gpu = Gpu::headless().map_err(|e| e.to_string())?;
        let path = path.unwrap_or_else(|| SpherePath::for_adapter(&gpu.adapter));
        let painter = Painter::new(&gpu.device, offscreen::FORMAT, path);
        Ok(Self {
            gpu,
            painter,
            egui: egui::Context::default(),
            ui: LabUi::default(),
            target: None,
            settled: false,
        })
    }

    /// Renders the lab's current state at `size` pixels and returns RGBA bytes.
    /// With `with_ui` the panel is drawn over the scene exactly as in the window.
    pub fn render(&mut self, lab: &mut Lab, size: [u32; 2], with_ui: bool) -> Result<Vec<u8>, String> {
        if size[0] == 0 || size[1] == 0 {
            return Err(format!("image size {}x{} must not be zero", size[0], size[1]));
        }
        if self.target.as_ref().is_none_or(|t| t.size != size) {
            self.target = Some(OffscreenTarget::new(&self.gpu.device, size));
            self.settled = false;
        }
        let target = self.target.as_ref().expect("created above");
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let full = [0.0, 0.0, size[0] as f32, size[1] as f32];
        if !with_ui {
            self.painter.paint(device, queue, &target.srgb_view, &target.view, size, full, lab, None);
            return target.read_rgba(device, queue);
        }
        // egui lays out some widgets over two passes: the first frame at a size runs
        // three and draws the last; later frames run one, as the window does.
        let mut output = None;
        let mut viewport = full;
        let passes = if self.settled { 1 } else { 3 };
        self.settled = true;
        for _ in 0..passes {
            let input = egui::RawInput {
                screen_rect: Some(egui::Rect::from_min_size(
                    egui::Pos2::ZERO,
                    egui::vec2(size[0] as f32, size[1] as f32),
                )),
                ..Default::default()
            };
            let shell = &mut self.ui;
            let full_output = self.egui.run_ui(input, |ui| {
                let rect = shell.show(ui, lab);
                viewport = [rect.left(), rect.top(), rect.width(), rect.height()];
            });
            self.painter.update_textures(device, queue, &full_output.textures_delta);
            self.painter.free_textures(&full_output.textures_delta);
            output = Some(full_output);
        }
        let output = output.expect("ran at least once");
        let primitives = self.egui.tessellate(output.shapes, output.pixels_per_point);
        let ppp = output.pixels_per_point;
        let viewport = viewport.map(|v| v * ppp);
        let frame = UiFrame { primitives: &primitives, pixels_per_point: ppp };
        self.painter.paint(device, queue, &target.srgb_view, &target.view, size, viewport, lab, Some(frame));
        target.read_rgba(device, queue)
    }
}

//! Off-screen captures of a lab, with or without the panel: the `render` command, the
//! render tests and the render benchmark all use this. (Saving a run's state is
//! [`crate::scenes::snapshot`]; this only draws it.)

use egui::epaint::{ClippedPrimitive, PaintCallback, Primitive};

use crate::render::orbit_camera::ViewPiece;
use crate::render::renderer::fit_viewport;
use crate::render::{Gpu, OffscreenTarget, SpherePath, offscreen};
use crate::ui::paint::{Painter, UiFrame};
use crate::ui::{Lab, LabUi};

/// Largest side of the target a frame is drawn into (px). A larger frame is drawn in
/// tiles no larger, one after another into the one target, each read back into the
/// image: an 8192x8192 frame then needs its image (256 MB) and a 2048x2048 target with
/// its 4x multisampled colour and depth (about 150 MB with the read-back), not
/// 8192x8192 ones (over 2.5 GB).
pub const TILE_SIDE: u32 = 2048;

/// How a frame is drawn: into one target, once per tile.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TilePlan {
    /// Size of the target every tile is drawn into (px): the frame's own size when it
    /// fits in one tile. No texture a frame is drawn with is larger.
    pub target: [u32; 2],
    /// Each tile's top-left corner in the frame (px), row by row, each tile the
    /// target's size. The last tile of a row (or column) is moved back to end at the
    /// frame's edge, overlapping the one before it rather than reaching out of the frame.
    pub tiles: Vec<[u32; 2]>,
}

impl TilePlan {
    /// The plan for a frame of `size` pixels in tiles at most `side` pixels a side.
    #[must_use]
    pub fn new(size: [u32; 2], side: u32) -> Self {
        let target = size.map(|length| length.clamp(1, side.max(1)));
        let starts =
            |length: u32, tile: u32| (0..length.div_ceil(tile)).map(move |k| (k * tile).min(length - tile));
        let tiles = starts(size[1], target[1])
            .flat_map(|y| starts(size[0], target[0]).map(move |x| [x, y]))
            .collect();
        Self { target, tiles }
    }
}

/// Renders lab frames off-screen with one device and one set of renderers.
pub struct FrameCapture {
    /// The device.
    pub gpu: Gpu,
    painter: Painter,
    egui: egui::Context,
    /// The interface drawn with `with_ui`: its layout, drafts and sections.
    pub ui: LabUi,
    target: Option<OffscreenTarget>,
    /// The frame size egui last laid out at: its layout needs a few passes to settle at
    /// a new one.
    settled: Option<[u32; 2]>,
    /// Largest side of a tile (see [`TILE_SIDE`]).
    tile_side: u32,
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
        // Within the device's largest texture too (2048 at the least wgpu allows).
        let tile_side = TILE_SIDE.min(gpu.device.limits().max_texture_dimension_2d).max(1);
        Ok(Self {
            gpu,
            painter,
            egui: egui::Context::default(),
            ui: LabUi::default(),
            target: None,
            settled: None,
            tile_side,
        })
    }

    /// Draws frames in tiles at most `side` pixels a side (at least 1, at most the
    /// default): for tests that compare a tiled frame with a whole one.
    #[doc(hidden)]
    pub fn set_tile_side(&mut self, side: u32) {
        let largest = TILE_SIDE.min(self.gpu.device.limits().max_texture_dimension_2d);
        self.tile_side = side.clamp(1, largest.max(1));
    }

    /// How a frame of `size` pixels is drawn: the target's size and the tiles.
    #[must_use]
    pub fn plan(&self, size: [u32; 2]) -> TilePlan {
        TilePlan::new(size, self.tile_side)
    }

    /// Size of the target frames are drawn into now (px), `None` before the first:
    /// for a frame larger than a tile, the tile's size.
    #[must_use]
    pub fn target_size(&self) -> Option<[u32; 2]> {
        self.target.as_ref().map(|target| target.size)
    }

    /// Renders the lab's current state at `size` pixels and returns RGBA bytes.
    /// With `with_ui` the panel is drawn over the scene exactly as in the window.
    /// A frame larger than a tile is drawn tile by tile (see [`TilePlan`]), each with
    /// its piece of the whole view's projection and of the panel, so it looks as the
    /// whole frame drawn at once would.
    pub fn render(&mut self, lab: &mut Lab, size: [u32; 2], with_ui: bool) -> Result<Vec<u8>, String> {
        if size[0] == 0 || size[1] == 0 {
            return Err(format!("image size {}x{} must not be zero", size[0], size[1]));
        }
        let plan = self.plan(size);
        if self.target.as_ref().is_none_or(|t| t.size != plan.target) {
            // The old target goes first: two big ones are never held at once.
            self.target = None;
            self.target = Some(OffscreenTarget::new(&self.gpu.device, plan.target));
        }
        let full = [0.0, 0.0, size[0] as f32, size[1] as f32];
        let (viewport, panel) = if with_ui {
            let (viewport, primitives, pixels_per_point) = self.lay_out(lab, size);
            (viewport, Some((primitives, pixels_per_point)))
        } else {
            (full, None)
        };
        let target = self.target.as_ref().expect("created above");
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        if plan.tiles.len() == 1 {
            let ui = panel.as_ref().map(|(primitives, pixels_per_point)| UiFrame {
                primitives,
                pixels_per_point: *pixels_per_point,
            });
            self.painter.paint(device, queue, &target.srgb_view, &target.view, size, viewport, lab, ui);
            return target.read_rgba(device, queue);
        }

        let row = size[0] as usize * 4;
        let mut image = Vec::new();
        image
            .try_reserve_exact(row * size[1] as usize)
            .map_err(|_| format!("not enough memory for a {}x{} image", size[0], size[1]))?;
        image.resize(row * size[1] as usize, 0);
        // The whole view, as one target would have drawn it, in frame pixels.
        let [vx, vy, vw, vh] = fit_viewport(viewport, size);
        let [tile_width, tile_height] = plan.target;
        let saved = lab.camera.piece;
        let mut shifted = Vec::new();
        let mut result = Ok(());
        for &[tx, ty] in &plan.tiles {
            let (left, top) = (tx as f32, ty as f32);
            // The part of the view in this tile, in frame pixels.
            let [x0, y0] = [vx.max(left), vy.max(top)];
            let [x1, y1] = [(vx + vw).min(left + tile_width as f32), (vy + vh).min(top + tile_height as f32)];
            let local = if x1 > x0 && y1 > y0 {
                [x0 - left, y0 - top, x1 - x0, y1 - y0]
            } else {
                [0.0, 0.0, 0.0, 0.0]
            };
            lab.camera.piece = Some(ViewPiece { whole: [vw, vh], offset: [x0 - vx, y0 - vy] });
            let ui = panel.as_ref().map(|(primitives, pixels_per_point)| {
                let by = egui::vec2(left, top) / *pixels_per_point;
                let within = egui::Rect::from_min_size(
                    egui::Pos2::ZERO,
                    egui::vec2(tile_width as f32, tile_height as f32) / *pixels_per_point,
                );
                shift_primitives(primitives, by, within, &mut shifted);
                UiFrame { primitives: &shifted, pixels_per_point: *pixels_per_point }
            });
            self.painter.paint(device, queue, &target.srgb_view, &target.view, plan.target, local, lab, ui);
            match target.read_rgba(device, queue) {
                Ok(pixels) => {
                    let (tile_row, start) = (tile_width as usize * 4, tx as usize * 4);
                    for (y, line) in pixels.chunks_exact(tile_row).enumerate() {
                        let at = (ty as usize + y) * row + start;
                        image[at..at + tile_row].copy_from_slice(line);
                    }
                }
                Err(error) => {
                    result = Err(error);
                    break;
                }
            }
        }
        lab.camera.piece = saved;
        result.map(|()| image)
    }

    /// Runs egui over the lab for a frame of `size` pixels: the 3D view's rectangle
    /// (px), the panel's tessellated shapes and the pixels per point.
    fn lay_out(&mut self, lab: &mut Lab, size: [u32; 2]) -> ([f32; 4], Vec<ClippedPrimitive>, f32) {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        // egui lays out some widgets over two passes: the first frame at a size runs
        // three and draws the last; later frames run one, as the window does.
        let mut output = None;
        let mut viewport = [0.0, 0.0, size[0] as f32, size[1] as f32];
        let passes = if self.settled == Some(size) { 1 } else { 3 };
        self.settled = Some(size);
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
        (viewport.map(|v| v * ppp), primitives, ppp)
    }
}

/// `primitives` moved `by` points up and left, into `out`: what a tile whose top left
/// is `by` into the frame shows of them, those whose clip rectangle misses the tile
/// (`within`, in the tile's points) left out.
fn shift_primitives(
    primitives: &[ClippedPrimitive],
    by: egui::Vec2,
    within: egui::Rect,
    out: &mut Vec<ClippedPrimitive>,
) {
    out.clear();
    for primitive in primitives {
        let clip_rect = primitive.clip_rect.translate(-by);
        if !clip_rect.intersects(within) {
            continue;
        }
        let primitive = match &primitive.primitive {
            Primitive::Mesh(mesh) => {
                let mut mesh = mesh.clone();
                mesh.translate(-by);
                Primitive::Mesh(mesh)
            }
            Primitive::Callback(callback) => Primitive::Callback(PaintCallback {
                rect: callback.rect.translate(-by),
                callback: callback.callback.clone(),
            }),
        };
        out.push(ClippedPrimitive { clip_rect, primitive });
    }
}

//! Paints one frame, the 3D view then the egui panel, into any pair of texture views.
//! The window, its screenshots and `render` all go through here.

use crate::render::frame::{SegmentInstance, SphereInstance};
use crate::render::renderer::DEFAULT_SAMPLE_COUNT;
use crate::render::{FrameBuilder, FrameData, Renderer};
use crate::ui::Lab;

/// The egui side of a frame: what to draw and at what scale.
pub struct UiFrame<'a> {
    /// Tessellated egui output.
    pub primitives: &'a [egui::ClippedPrimitive],
    /// Physical pixels per egui point.
    pub pixels_per_point: f32,
}

/// The 3D renderer, egui's renderer, and the frame builder, built once.
pub struct Painter {
    renderer: Renderer,
    format: wgpu::TextureFormat,
    egui: egui_wgpu::Renderer,
    builder: FrameBuilder,
}

impl Painter {
    /// Builds both renderers for targets of `format` (a non-sRGB format; the 3D pass
    /// draws through its sRGB view).
    #[must_use]
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        // No dithering: the panel has no gradients, and on a software GPU it costs
        // several milliseconds a frame.
        let options = egui_wgpu::RendererOptions { dithering: false, ..Default::default() };
        Self {
            renderer: Renderer::new(device, format.add_srgb_suffix(), DEFAULT_SAMPLE_COUNT),
            format,
            egui: egui_wgpu::Renderer::new(device, format.remove_srgb_suffix(), options),
            builder: FrameBuilder::default(),
        }
    }

    /// Uploads the textures egui added or changed. Call before [`Self::paint`].
    pub fn update_textures(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        delta: &egui::TexturesDelta,
    ) {
        for (id, images) in &delta.set {
            for image in images {
                self.egui.update_texture(device, queue, *id, image);
            }
        }
    }

    /// Frees the textures egui no longer needs. Call after submitting the frame.
    pub fn free_textures(&mut self, delta: &egui::TexturesDelta) {
        for id in &delta.free {
            self.egui.free_texture(id);
        }
    }

    /// Records and submits one frame: the scene in `viewport` (x, y, width, height in
    /// pixels) of a target `size` pixels large, then the panel if given.
    #[allow(clippy::too_many_arguments)]
    pub fn paint(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        srgb_view: &wgpu::TextureView,
        view: &wgpu::TextureView,
        size: [u32; 2],
        viewport: [f32; 4],
        lab: &Lab,
        ui: Option<UiFrame<'_>>,
    ) {
        let samples = if lab.view.msaa { DEFAULT_SAMPLE_COUNT } else { 1 };
        if self.renderer.sample_count() != samples {
            self.renderer = Renderer::new(device, self.format.add_srgb_suffix(), samples);
        }
        let highlight = lab.grab.map(|g| g.id).or(lab.hovered);
        let now = lab.scene.world().time();
        self.builder.build(lab.scene.as_ref(), Some(&lab.trails), now, lab.view, highlight);
        inspector_arrows(lab, &mut self.builder.frame);
        tape(lab, &mut self.builder.frame);
        let frame = &self.builder.frame;
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        self.renderer.render(device, queue, &mut encoder, srgb_view, size, viewport, &lab.camera, frame);
        let mut extra = Vec::new();
        if let Some(ui) = ui {
            let screen =
                egui_wgpu::ScreenDescriptor { size_in_pixels: size, pixels_per_point: ui.pixels_per_point };
            extra = self.egui.update_buffers(device, queue, &mut encoder, ui.primitives, &screen);
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("egui"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime();
            self.egui.render(&mut pass, ui.primitives, &screen);
        }
        queue.submit(extra.into_iter().chain([encoder.finish()]));
    }
}

/// The selected particle's velocity (green) and acceleration (red, the net force over
/// its mass) as arrows from its centre, to the scales the inspector states; a small
/// ball marks each tip.
fn inspector_arrows(lab: &Lab, frame: &mut FrameData) {
    let Some(id) = lab.selected else { return };
    let particles = &lab.scene.world().particles;
    let Some(i) = particles.index(id) else { return };
    if particles.inverse_masses()[i] == 0.0 {
        return;
    }
    let p = particles.positions()[i];
    let acceleration = lab.net_force / particles.mass(i);
    let arrows = [
        (particles.velocities()[i] * super::VELOCITY_ARROW, [0.3, 0.9, 0.35]),
        (acceleration * super::ACCELERATION_ARROW, [0.95, 0.3, 0.25]),
    ];
    for (arrow, [r, g, b]) in arrows {
        if arrow.length() < 1e-3 {
            continue;
        }
        let tip = p + arrow;
        frame.segments.push(SegmentInstance {
            from: p.to_array(),
            width: 4.0,
            to: tip.to_array(),
            pad: 0.0,
            color: [r, g, b, 1.0],
        });
        frame.spheres.push(SphereInstance { center: tip.to_array(), radius: 0.06, color: [r, g, b, 1.0] });
    }
}

/// The tape measure: its ends as small white balls and, once both are down, the tape.
fn tape(lab: &Lab, frame: &mut FrameData) {
    if !lab.tape {
        return;
    }
    for point in &lab.tape_points {
        frame.spheres.push(SphereInstance {
            center: point.to_array(),
            radius: 0.07,
            color: [0.95, 0.95, 0.95, 1.0],
        });
    }
    if let [a, b] = lab.tape_points[..] {
        frame.segments.push(SegmentInstance {
            from: a.to_array(),
            width: 3.0,
            to: b.to_array(),
            pad: 0.0,
            color: [0.95, 0.95, 0.95, 1.0],
        });
    }
}

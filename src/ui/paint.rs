//! Paints one frame, the 3D view then the egui panel, into any pair of texture views.
//! The window, its screenshots and `render` all go through here.

use glam::Vec3;

use crate::physics::LinkState;
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
    /// The compared copy's links, reused from frame to frame.
    links: Vec<LinkState>,
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
            links: Vec::new(),
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
        vectors(lab, &mut self.builder.frame);
        compare_ghosts(lab, &mut self.links, &mut self.builder.frame);
        if lab.side_view {
            // Seen edge-on the ground is no plane: draw its line.
            self.builder.frame.segments.push(SegmentInstance {
                from: [-1000.0, 0.0, 0.0],
                width: 2.0,
                to: [1000.0, 0.0, 0.0],
                pad: 0.0,
                color: [0.5, 0.5, 0.52, 1.0],
            });
        }
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

/// Arrows from particle centres, to the scales the inspector states, each with a small
/// ball at its tip: velocity (green) on the particles with arrows, the selected one's
/// acceleration (red, its net force over its mass), and with force arrows on the
/// free-body diagram: each force in its own colour ([`force_color`]).
fn vectors(lab: &Lab, frame: &mut FrameData) {
    let ids = lab.vector_particles();
    if ids.is_empty() {
        return;
    }
    let force_scale = if lab.view.forces { lab.force_scale() } else { 1.0 };
    let particles = &lab.scene.world().particles;
    let mut arrow = |from: Vec3, arrow: Vec3, [r, g, b]: [f32; 3]| {
        if arrow.length() < 0.02 {
            return;
        }
        let tip = from + arrow;
        let color = [r, g, b, 1.0];
        frame.segments.push(SegmentInstance {
            from: from.to_array(),
            width: 4.0,
            to: tip.to_array(),
            pad: 0.0,
            color,
        });
        frame.spheres.push(SphereInstance { center: tip.to_array(), radius: 0.05, color });
    };
    for id in ids {
        let Some(i) = particles.index(id) else { continue };
        let p = particles.positions()[i];
        arrow(p, particles.velocities()[i] * super::VELOCITY_ARROW, VELOCITY_COLOR);
        if lab.selected == Some(id) && !lab.view.forces {
            arrow(p, lab.net_force(id) / particles.mass(i) * super::ACCELERATION_ARROW, ACCELERATION_COLOR);
        }
        if lab.view.forces {
            for (name, force) in lab.free_body(id) {
                arrow(p, force / force_scale, force_color(name));
            }
            if lab.selected == Some(id) {
                arrow(p, lab.net_force(id) / force_scale, force_color("net force"));
            }
        }
    }
}

/// Colour of the compared copy's ghosts (linear RGB).
pub const COMPARE_COLOR: [f32; 3] = [0.95, 0.35, 0.95];

/// The compared copy, drawn over the original: its particles as translucent magenta
/// ghosts, its links as translucent lines.
fn compare_ghosts(lab: &Lab, links: &mut Vec<LinkState>, frame: &mut FrameData) {
    let Some(compare) = &lab.compare else { return };
    let world = compare.scene.world();
    let particles = &world.particles;
    let [r, g, b] = COMPARE_COLOR;
    for (position, radius) in particles.positions().iter().zip(particles.radii()) {
        frame.spheres.push(SphereInstance {
            center: position.to_array(),
            radius: radius.max(0.05) * 1.02,
            color: [r, g, b, 0.4],
        });
    }
    world.links_into(links);
    for link in links.iter() {
        frame.trails.push(SegmentInstance {
            from: link.from.to_array(),
            width: 3.0,
            to: link.to.to_array(),
            pad: 0.0,
            color: [r, g, b, 0.5],
        });
    }
}

/// Colour of velocity arrows (linear RGB).
pub const VELOCITY_COLOR: [f32; 3] = [0.3, 0.9, 0.35];
/// Colour of acceleration arrows (linear RGB).
pub const ACCELERATION_COLOR: [f32; 3] = [0.95, 0.3, 0.25];

/// Colour of a force's arrow (linear RGB) by its name in [`Lab::free_body`]: weight
/// blue, springs orange, bungees purple, buoyancy cyan, drag and damping greys,
/// contacts and links yellow.
#[must_use]
pub fn force_color(name: &str) -> [f32; 3] {
    match name {
        "weight" | "gravity" => [0.25, 0.45, 1.0],
        "spring" => [1.0, 0.55, 0.1],
        "bungee" => [0.7, 0.3, 0.95],
        "stiff spring" => [0.95, 0.2, 0.2],
        "buoyancy" => [0.2, 0.85, 0.9],
        "drag" => [0.75, 0.75, 0.75],
        "damping" => [0.55, 0.45, 0.4],
        super::lab::CONSTRAINT_FORCE => [0.95, 0.85, 0.2],
        "net force" => [1.0, 1.0, 1.0],
        _ => [0.85, 0.6, 0.75],
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

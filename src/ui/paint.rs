//! Paints one frame, the 3D view then the egui panel, into any pair of texture views.
//! The window, its screenshots and `render` all go through here.

use glam::Vec3;

use crate::physics::LinkState;
use crate::render::frame::{SegmentInstance, SphereInstance, UNMARKED};
use crate::render::renderer::DEFAULT_SAMPLE_COUNT;
use crate::render::{FrameBuilder, FrameData, Renderer, SpherePath};
use crate::ui::lab::{ACCELERATION_ARROW, CONSTRAINT_FORCE, Lab, VELOCITY_ARROW};

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
    /// The scene's ruler's lines, reused from frame to frame.
    ruler_lines: Vec<(Vec3, Vec3)>,
}

impl Painter {
    /// Builds both renderers for targets of `format`, drawing spheres the way
    /// `sphere_path` says. For a gamma-space `format` the 3D pass draws through the
    /// target's sRGB view and egui into the target itself (egui blends in gamma space,
    /// as it prefers); for an sRGB `format` (a GPU without view formats, WebGL2) both
    /// draw into the one sRGB target.
    #[must_use]
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, sphere_path: SpherePath) -> Self {
        // No dithering: the panel has no gradients, and on a software GPU it costs
        // several milliseconds a frame.
        let options = egui_wgpu::RendererOptions { dithering: false, ..Default::default() };
        Self {
            renderer: Renderer::new(device, format.add_srgb_suffix(), DEFAULT_SAMPLE_COUNT, sphere_path),
            format,
            links: Vec::new(),
            ruler_lines: Vec::new(),
            egui: egui_wgpu::Renderer::new(device, format, options),
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
            let path = self.renderer.sphere_path();
            self.renderer = Renderer::new(device, self.format.add_srgb_suffix(), samples, path);
        }
        let highlight = lab.grab.map(|g| g.id).or(lab.hovered);
        let now = lab.scene.world().time();
        self.builder.decoration_scale = crate::render::frame::decoration_scale(lab.camera.distance);
        self.builder.build(lab.scene.as_ref(), Some(&lab.trails), now, lab.view, highlight);
        if let Some(ruler) = lab.scene.ruler().filter(|_| !lab.side_view) {
            self.ruler_lines.clear();
            ruler.lines(&mut self.ruler_lines);
            for &(from, to) in &self.ruler_lines {
                self.builder.frame.segments.push(SegmentInstance {
                    from: from.to_array(),
                    width: 2.0,
                    to: to.to_array(),
                    pad: 0.0,
                    color: [0.55, 0.6, 0.68, 1.0],
                });
            }
        }
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

/// Arrows from particle centres, to the scales the inspector states, each with an
/// arrowhead (two barbs facing the camera, not a ball that could pass for a particle):
/// velocity (green) on the particles with arrows, the selected one's acceleration (red,
/// its net force over its mass), and with force arrows on the free-body diagram: each
/// force in its own colour ([`force_color`]).
pub fn vectors(lab: &Lab, frame: &mut FrameData) {
    let ids = lab.vector_particles();
    if ids.is_empty() {
        return;
    }
    let force_scale = if lab.view.forces { lab.force_scale() } else { 1.0 };
    let particles = &lab.scene.world().particles;
    let forward = lab.camera.forward();
    let mut arrow = |from: Vec3, arrow: Vec3, [r, g, b]: [f32; 3]| {
        let length = arrow.length();
        if length < 0.02 {
            return;
        }
        let tip = from + arrow;
        let color = [r, g, b, 1.0];
        let mut push = |a: Vec3, b: Vec3| {
            frame.segments.push(SegmentInstance {
                from: a.to_array(),
                width: 4.0,
                to: b.to_array(),
                pad: 0.0,
                color,
            });
        };
        push(from, tip);
        let along = arrow / length;
        let across = along.cross(forward).try_normalize().unwrap_or_else(|| along.any_orthogonal_vector());
        let head = ARROWHEAD_LENGTH.min(0.4 * length);
        for side in [1.0, -1.0] {
            push(tip, tip - along * head + across * (side * 0.55 * head));
        }
    };
    for id in ids {
        let Some(i) = particles.index(id) else { continue };
        let p = particles.positions()[i];
        arrow(p, particles.velocities()[i] * VELOCITY_ARROW, VELOCITY_COLOR);
        if lab.selected == Some(id) && !lab.view.forces {
            arrow(p, lab.net_force(id) / particles.mass(i) * ACCELERATION_ARROW, ACCELERATION_COLOR);
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
            spin: UNMARKED,
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
        CONSTRAINT_FORCE => [0.95, 0.85, 0.2],
        "net force" => [1.0, 1.0, 1.0],
        _ => [0.85, 0.6, 0.75],
    }
}

/// Longest arrowhead barb (m); a short arrow gets barbs 0.4 of its length.
pub const ARROWHEAD_LENGTH: f32 = 0.2;

/// Colour of the tape measure (linear RGB): a tape's yellow.
pub const TAPE_COLOR: [f32; 3] = [1.0, 0.85, 0.1];

/// How far above the ground a tape end on it is drawn (m), so the ground does not
/// hide the tape that lies on it.
pub const TAPE_LIFT: f32 = 0.03;

/// The tape measure: each end an X facing the camera (never a ball that could pass for
/// a particle) and, once both are down, the tape between them with a mark every metre.
/// Ends on the ground are drawn [`TAPE_LIFT`] above it.
pub fn tape(lab: &Lab, frame: &mut FrameData) {
    if !lab.tape {
        return;
    }
    let [r, g, b] = TAPE_COLOR;
    let color = [r, g, b, 1.0];
    let lift = |p: Vec3| if p.y.abs() < TAPE_LIFT { Vec3::new(p.x, TAPE_LIFT, p.z) } else { p };
    let right = lab.camera.right();
    let up = right.cross(lab.camera.forward()).normalize_or(Vec3::Y);
    let mut push = |a: Vec3, b: Vec3, width: f32| {
        frame.segments.push(SegmentInstance { from: a.to_array(), width, to: b.to_array(), pad: 0.0, color });
    };
    let half = 0.12;
    for &point in &lab.tape_points {
        let p = lift(point);
        push(p - (right + up) * half, p + (right + up) * half, 3.0);
        push(p - (right - up) * half, p + (right - up) * half, 3.0);
    }
    if let [a, b] = lab.tape_points[..] {
        let (a, b) = (lift(a), lift(b));
        push(a, b, 4.0);
        let length = a.distance(b);
        if let Some(along) = (b - a).try_normalize() {
            let across = along.cross(lab.camera.forward()).normalize_or(up) * 0.08;
            for k in 1..(length.floor() as usize).min(1000) {
                let mark = a + along * k as f32;
                push(mark - across, mark + across, 2.0);
            }
        }
    }
}

/// What a label names. Labels are placed in this order: where two would overlap, the
/// earlier kind keeps its spot and the later one moves or is left out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum LabelKind {
    /// A mark of a scene's ruler, written left of its tick and never moved off it.
    Mark,
    /// A scene's object (bob, launcher, load) or its ruler marks, written above.
    Object,
    /// A kind of link, once, written below the middle of one link of that kind.
    Link,
    /// A metre tick on the ground, written below it.
    Tick,
}

/// A name to write over the 3D view, at a point in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// Where it is anchored (m), in this frame's positions.
    pub at: Vec3,
    /// The text.
    pub text: String,
    /// What it names.
    pub kind: LabelKind,
    /// For a link kind: the middles of the other links of that kind (m), tried in turn
    /// when the first is taken.
    pub alternatives: Vec<Vec3>,
}

/// Above this many particles the view has no metre ticks (a pile's spheres would be
/// written over).
pub const TICK_PARTICLE_LIMIT: usize = 500;

/// Links looked at for labels (a scene of thousands of links is not searched).
pub const LINK_LABEL_LIMIT: usize = 200;

/// Other links of one kind tried for its label when the first link's spot is taken.
const LINK_SPOTS: usize = 8;

/// The labels for the lab as it is now: the scene's objects, each name once; each kind
/// of link once, unless an object already carries its name (springForces' "stiff
/// spring" is the particle on the stiff spring); metre ticks along x on the ground.
#[must_use]
pub fn label_list(lab: &Lab) -> Vec<Label> {
    let mut names = Vec::new();
    lab.scene.labels(&mut names);
    let mut out: Vec<Label> = Vec::new();
    // The scene's ruler, in the 3D view only: the side view has its height scale.
    if let Some(ruler) = lab.scene.ruler().filter(|_| !lab.side_view) {
        for (at, text) in ruler.marks() {
            out.push(Label { at, text, kind: LabelKind::Mark, alternatives: Vec::new() });
        }
    }
    for (at, name) in names {
        if !out.iter().any(|l| l.text == name) {
            out.push(Label { at, text: name.to_owned(), kind: LabelKind::Object, alternatives: Vec::new() });
        }
    }
    let world = lab.scene.world();
    for link in world.links().iter().take(LINK_LABEL_LIMIT) {
        let middle = (link.from + link.to) * 0.5;
        let name = link.spec.kind.name().replace('_', " ");
        match out.iter_mut().find(|l| l.text == name) {
            Some(label) if label.kind == LabelKind::Link && label.alternatives.len() < LINK_SPOTS => {
                label.alternatives.push(middle);
            }
            Some(_) => {}
            None => {
                out.push(Label { at: middle, text: name, kind: LabelKind::Link, alternatives: Vec::new() })
            }
        }
    }
    if world.particles.len() <= TICK_PARTICLE_LIMIT {
        // Every 1, 5 or 10 m as the view widens.
        let spacing = match lab.camera.distance {
            d if d < 15.0 => 1.0,
            d if d < 60.0 => 5.0,
            _ => 10.0,
        };
        for k in -10..=20 {
            let x = k as f32 * spacing;
            out.push(Label {
                at: Vec3::new(x, 0.0, 0.0),
                text: format!("{x} m"),
                kind: LabelKind::Tick,
                alternatives: Vec::new(),
            });
        }
    }
    out
}

/// A label as written: its text and the rectangle it covers (points, in the window).
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedLabel {
    /// The text.
    pub text: String,
    /// What it names.
    pub kind: LabelKind,
    /// The rectangle its text covers.
    pub rect: egui::Rect,
}

/// Room kept around each label (points), so neighbours do not touch.
const LABEL_MARGIN: f32 = 2.0;

/// Places `labels` (in [`LabelKind`] order, then as listed) so that no two overlap and
/// none covers `reserved`. `project` turns a world point into window points, `None`
/// off the view; `size` gives a text's size (points). An object's name goes above its
/// point, else beside it, else higher up; a link kind below one of its links' middles,
/// else beside it; a tick only below its point. What finds no free spot is left out:
/// a crowded view loses names rather than writing them over each other.
pub fn place_labels(
    labels: &[Label],
    project: impl Fn(Vec3) -> Option<egui::Pos2>,
    size: impl Fn(&Label) -> egui::Vec2,
    reserved: &[egui::Rect],
) -> Vec<PlacedLabel> {
    let mut order: Vec<&Label> = labels.iter().collect();
    order.sort_by_key(|l| l.kind);
    let mut placed: Vec<PlacedLabel> = Vec::new();
    for label in order {
        let size = size(label);
        let free = |rect: egui::Rect, placed: &[PlacedLabel]| {
            let grown = rect.expand(LABEL_MARGIN);
            !placed.iter().any(|p| p.rect.intersects(grown)) && !reserved.iter().any(|r| r.intersects(grown))
        };
        let spots = std::iter::once(label.at).chain(label.alternatives.iter().copied());
        let found = spots.filter_map(&project).find_map(|point| {
            candidates(label.kind, point, size).into_iter().find(|&rect| free(rect, &placed))
        });
        if let Some(rect) = found {
            placed.push(PlacedLabel { text: label.text.clone(), kind: label.kind, rect });
        }
    }
    placed
}

/// Where a label of `kind` and `size` may go around its point, best first.
fn candidates(kind: LabelKind, point: egui::Pos2, size: egui::Vec2) -> Vec<egui::Rect> {
    use egui::{Align2, vec2};
    let at = |align: Align2, offset: egui::Vec2| align.anchor_size(point + offset, size);
    let gap = 4.0;
    match kind {
        LabelKind::Object => vec![
            at(Align2::CENTER_BOTTOM, vec2(0.0, 0.0)),
            at(Align2::LEFT_CENTER, vec2(gap * 2.0, 0.0)),
            at(Align2::RIGHT_CENTER, vec2(-gap * 2.0, 0.0)),
            at(Align2::CENTER_BOTTOM, vec2(0.0, -size.y)),
            at(Align2::LEFT_BOTTOM, vec2(gap, -size.y)),
            at(Align2::RIGHT_BOTTOM, vec2(-gap, -size.y)),
        ],
        LabelKind::Link => vec![
            at(Align2::CENTER_TOP, vec2(0.0, 0.0)),
            at(Align2::LEFT_CENTER, vec2(gap * 2.0, 0.0)),
            at(Align2::RIGHT_CENTER, vec2(-gap * 2.0, 0.0)),
        ],
        LabelKind::Tick => vec![at(Align2::CENTER_TOP, vec2(0.0, 0.0))],
        LabelKind::Mark => vec![at(Align2::RIGHT_CENTER, vec2(-gap, 0.0))],
    }
}

/// Font size (points) and colour of each kind of label.
fn label_style(kind: LabelKind) -> (f32, egui::Color32) {
    match kind {
        LabelKind::Object => (14.0, egui::Color32::WHITE),
        LabelKind::Link => (11.0, egui::Color32::from_gray(170)),
        LabelKind::Tick => (11.0, egui::Color32::from_gray(150)),
        LabelKind::Mark => (12.0, egui::Color32::from_gray(185)),
    }
}

/// Writes the labels over the 3D view in `rect` ([`label_list`], placed by
/// [`place_labels`]) and, in the side view, a height scale at its left edge. Reads
/// the lab as it is now: call it in the pass whose frame is drawn, after the physics
/// of that frame has stepped. Returns what it wrote.
pub fn labels(ui: &egui::Ui, lab: &Lab, rect: egui::Rect) -> Vec<PlacedLabel> {
    let painter = ui.painter_at(rect);
    let view = glam::Vec2::new(rect.width(), rect.height());
    let project = |point: Vec3| {
        let p = lab.camera.project(point, view)?;
        let p = rect.min + egui::vec2(p.x, p.y);
        rect.expand(40.0).contains(p).then_some(p)
    };
    let reserved = if lab.side_view { height_scale(&painter, lab, rect) } else { Vec::new() };
    let list = label_list(lab);
    let galley = |label: &Label| {
        let (font, color) = label_style(label.kind);
        painter.layout_no_wrap(label.text.clone(), egui::FontId::proportional(font), color)
    };
    let mut placed = place_labels(&list, project, |label| galley(label).size(), &reserved);
    // A metre tick's label cut by the view's edge would read as another number ("-10 m"
    // as "0 m"): only whole ones are written.
    placed.retain(|label| label.kind != LabelKind::Tick || rect.contains_rect(label.rect));
    for label in &placed {
        let (font, color) = label_style(label.kind);
        painter.text(
            label.rect.min,
            egui::Align2::LEFT_TOP,
            &label.text,
            egui::FontId::proportional(font),
            color,
        );
    }
    placed
}

/// Smallest gap (points) between the side view's height marks.
const HEIGHT_MARK_GAP: f32 = 36.0;

/// The side view's height scale: a vertical line near the view's left edge with a mark
/// and its height in metres every 1, 2 or 5 × 10ⁿ m, at least [`HEIGHT_MARK_GAP`] apart,
/// from the ground up. Returns the rectangles it covers, for the labels to keep off.
fn height_scale(painter: &egui::Painter, lab: &Lab, rect: egui::Rect) -> Vec<egui::Rect> {
    let view = glam::Vec2::new(rect.width(), rect.height());
    let x = lab.camera.target.x;
    let screen_y = |y: f32| lab.camera.project(Vec3::new(x, y, 0.0), view).map(|p| rect.top() + p.y);
    let (Some(ground), Some(metre)) = (screen_y(0.0), screen_y(1.0)) else { return Vec::new() };
    let per_metre = ground - metre;
    if per_metre <= 1e-3 {
        return Vec::new();
    }
    let step = nice_step(HEIGHT_MARK_GAP / per_metre);
    let line_x = rect.left() + 52.0;
    let (top, bottom) = (rect.top() + 8.0, ground.min(rect.bottom() - 8.0));
    let color = egui::Color32::from_gray(185);
    let stroke = egui::Stroke::new(1.5, color);
    let mut covered = Vec::new();
    if bottom <= top {
        return covered;
    }
    painter.line_segment([egui::pos2(line_x, top), egui::pos2(line_x, bottom)], stroke);
    covered.push(egui::Rect::from_min_max(egui::pos2(line_x - 2.0, top), egui::pos2(line_x + 8.0, bottom)));
    let font = egui::FontId::proportional(11.0);
    // From the lowest mark in view: the ground may be far below it.
    let first = (((ground - bottom) / per_metre / step).floor().max(0.0)) as u32;
    for k in first..=first + 1000 {
        let height = k as f32 * step;
        let y = ground - height * per_metre;
        if y < top {
            break;
        }
        if y > bottom {
            continue;
        }
        painter.line_segment([egui::pos2(line_x, y), egui::pos2(line_x + 7.0, y)], stroke);
        let text = metres(height, step);
        // The ground's mark sits above the ground's line, the others centred on theirs.
        let align = if k == 0 { egui::Align2::RIGHT_BOTTOM } else { egui::Align2::RIGHT_CENTER };
        let written = painter.text(egui::pos2(line_x - 4.0, y), align, text, font.clone(), color);
        covered.push(written);
    }
    let title = painter.text(
        egui::pos2(line_x + 4.0, top),
        egui::Align2::LEFT_TOP,
        "height",
        egui::FontId::proportional(11.0),
        color,
    );
    covered.push(title);
    covered
}

/// `value` metres with as many decimals as marks `step` metres apart need: "5 m",
/// "0.5 m".
fn metres(value: f32, step: f32) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    format!("{value:.decimals$} m")
}

/// The 1, 2 or 5 × 10ⁿ at or above `at_least` (> 0).
#[must_use]
pub fn nice_step(at_least: f32) -> f32 {
    let power = 10f32.powf(at_least.max(1e-6).log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|&s| s >= at_least * 0.999)
        .unwrap_or(10.0 * power)
}

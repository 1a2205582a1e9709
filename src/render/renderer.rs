//! The 3D renderer: built once, draws a [`FrameData`] into any texture view.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::frame::{FrameData, SegmentInstance, SphereInstance, WaterQuad};
use super::orbit_camera::OrbitCamera;

/// Samples per pixel of the 3D pass by default (4x MSAA).
pub const DEFAULT_SAMPLE_COUNT: u32 = 4;
/// Background colour (linear), also the colour the ground fades into.
pub const BACKGROUND: wgpu::Color = wgpu::Color { r: 0.045, g: 0.05, b: 0.065, a: 1.0 };
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    viewport: [f32; 4],
    light: [f32; 4],
    forward: [f32; 4],
}

/// A GPU buffer that keeps its size and grows (doubling) only when needed, so a
/// steady frame allocates no GPU memory of its own.
struct GrowingBuffer {
    buffer: wgpu::Buffer,
    label: &'static str,
    usage: wgpu::BufferUsages,
}

impl GrowingBuffer {
    fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages, size: u64) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        Self { buffer: Self::create(device, label, usage, size), label, usage }
    }

    fn create(
        device: &wgpu::Device,
        label: &'static str,
        usage: wgpu::BufferUsages,
        size: u64,
    ) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        })
    }

    /// Uploads `bytes` to the start of the buffer; true if the buffer had to be
    /// replaced by a larger one (bind groups naming it must then be rebuilt).
    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) -> bool {
        let needed = bytes.len() as u64;
        let grown = needed > self.buffer.size();
        if grown {
            let size = needed.next_power_of_two().max(self.buffer.size() * 2);
            self.buffer = Self::create(device, self.label, self.usage, size);
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
        grown
    }
}

/// Multisampled colour (none without MSAA) and depth attachments for one target size.
struct Attachments {
    size: [u32; 2],
    color: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
}

/// How the vertex shaders get the spheres (see `shaders/spheres.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpherePath {
    /// Read by index from a storage buffer, one plain draw for them all: fastest on a
    /// software GPU, which runs its vertex pipeline once per instance. Needs vertex
    /// storage (desktop Vulkan, Metal, DX12, and WebGPU).
    Storage,
    /// Drawn as instances, each sphere's fields as vertex attributes: for GPUs without
    /// storage buffers in vertex shaders (WebGL2, some GLES drivers).
    Instanced,
}

impl SpherePath {
    /// The storage path where the adapter has vertex storage, else the instanced one.
    #[must_use]
    pub fn for_adapter(adapter: &wgpu::Adapter) -> Self {
        let flags = adapter.get_downlevel_capabilities().flags;
        let storage = flags.contains(wgpu::DownlevelFlags::VERTEX_STORAGE)
            && adapter.limits().max_storage_buffers_per_shader_stage > 0;
        if storage { Self::Storage } else { Self::Instanced }
    }
}

/// Draws the ground, particles (sphere impostors), links, trails and water.
pub struct Renderer {
    color_format: wgpu::TextureFormat,
    sample_count: u32,
    sphere_path: SpherePath,
    globals: wgpu::Buffer,
    bind_group_layout: wgpu::BindGroupLayout,
    /// The globals, and on the storage path the sphere buffer; rebuilt when the sphere
    /// buffer grows.
    bind_group: wgpu::BindGroup,
    ground: wgpu::RenderPipeline,
    shadows: wgpu::RenderPipeline,
    spheres: wgpu::RenderPipeline,
    segments: wgpu::RenderPipeline,
    trails: wgpu::RenderPipeline,
    water: wgpu::RenderPipeline,
    sphere_buffer: GrowingBuffer,
    segment_buffer: GrowingBuffer,
    trail_buffer: GrowingBuffer,
    water_buffer: GrowingBuffer,
    attachments: Option<Attachments>,
}

impl Renderer {
    /// Builds every pipeline and buffer. `color_format` is the format of the views it
    /// will draw into (an sRGB format, so lighting is done in linear space);
    /// `sample_count` is 1 (no MSAA) or 4 (4x MSAA); `sphere_path` says how the
    /// spheres reach the vertex shaders.
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        sample_count: u32,
        sphere_path: SpherePath,
    ) -> Self {
        // The storage path's entry points and binding are a second file appended to the
        // first: a GPU without storage buffers never sees them.
        let scene = include_str!("../../shaders/scene.wgsl");
        let source = match sphere_path {
            SpherePath::Storage => format!("{scene}\n{}", include_str!("../../shaders/spheres.wgsl")),
            SpherePath::Instanced => scene.to_string(),
        };
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let uniform = wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let storage = wgpu::BindGroupLayoutEntry {
            binding: 1,
            visibility: wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<SphereInstance>() as u64),
            },
            count: None,
        };
        let (entries, sphere_usage) = match sphere_path {
            SpherePath::Storage => (vec![uniform, storage], wgpu::BufferUsages::STORAGE),
            SpherePath::Instanced => (vec![uniform], wgpu::BufferUsages::VERTEX),
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals and spheres"),
            entries: &entries,
        });
        let sphere_buffer = GrowingBuffer::new(device, "spheres", sphere_usage, 64 * 1024);
        let bind_group = Self::bind_group(device, &layout, &globals, sphere_path, &sphere_buffer.buffer);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });

        let alpha_blend = Some(wgpu::BlendState::ALPHA_BLENDING);
        // `entry` names the shaders: `vs_{entry}` and `fs_{entry}`, or for a pair of
        // names `vs_{vertex}` and `fs_{fragment}`.
        let make = |label: &str,
                    entry: (&str, &str),
                    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                    topology: wgpu::PrimitiveTopology,
                    blend: Option<wgpu::BlendState>,
                    depth: (bool, wgpu::CompareFunction),
                    alpha_to_coverage: bool| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some(&format!("vs_{}", entry.0)),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState { topology, cull_mode: None, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth.0),
                    depth_compare: Some(depth.1),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: sample_count,
                    mask: !0,
                    alpha_to_coverage_enabled: alpha_to_coverage,
                },
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(&format!("fs_{}", entry.1)),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: color_format,
                        blend,
                        // Coverage goes to the samples, not into the image's alpha.
                        write_mask: if alpha_to_coverage {
                            wgpu::ColorWrites::COLOR
                        } else {
                            wgpu::ColorWrites::ALL
                        },
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };

        // Spelled out: the colour sits after a padding float, at byte 32.
        let segment_attributes = [
            wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 0, shader_location: 0 },
            wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32, offset: 12, shader_location: 1 },
            wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 16, shader_location: 2 },
            wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x4, offset: 32, shader_location: 3 },
        ];
        let segment_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SegmentInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &segment_attributes,
        };
        let sphere_attributes =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x4, 3 => Float32x4];
        let sphere_layout = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SphereInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &sphere_attributes,
        })];
        let (sphere_entry, shadow_entry, sphere_buffers): (_, _, &[_]) = match sphere_path {
            SpherePath::Storage => ("sphere", "shadow", &[]),
            SpherePath::Instanced => ("sphere_instanced", "shadow_instanced", &sphere_layout),
        };
        let water_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<WaterQuad>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4],
        };

        use wgpu::CompareFunction::{Always, LessEqual};
        use wgpu::PrimitiveTopology::TriangleList;
        let (opaque, transparent) = ((true, LessEqual), (false, LessEqual));
        Self {
            color_format,
            sample_count,
            sphere_path,
            ground: make("ground", ("ground", "ground"), &[], TriangleList, None, opaque, false),
            // Drawn straight after the ground, over it only: no depth test needed, and
            // none of the ground's depth precision trouble at a distance.
            shadows: make(
                "shadows",
                (shadow_entry, "shadow"),
                sphere_buffers,
                TriangleList,
                alpha_blend,
                (false, Always),
                false,
            ),
            spheres: make(
                "spheres",
                (sphere_entry, "sphere"),
                sphere_buffers,
                TriangleList,
                None,
                opaque,
                true,
            ),
            segments: make(
                "segments",
                ("segment", "segment"),
                &[Some(segment_layout.clone())],
                TriangleList,
                alpha_blend,
                opaque,
                false,
            ),
            trails: make(
                "trails",
                ("trail", "trail"),
                &[Some(segment_layout)],
                TriangleList,
                alpha_blend,
                transparent,
                false,
            ),
            water: make(
                "water",
                ("water", "water"),
                &[Some(water_layout)],
                TriangleList,
                alpha_blend,
                transparent,
                false,
            ),
            sphere_buffer,
            segment_buffer: GrowingBuffer::new(device, "segments", wgpu::BufferUsages::VERTEX, 64 * 1024),
            trail_buffer: GrowingBuffer::new(device, "trails", wgpu::BufferUsages::VERTEX, 64 * 1024),
            water_buffer: GrowingBuffer::new(
                device,
                "water",
                wgpu::BufferUsages::VERTEX,
                std::mem::size_of::<WaterQuad>() as u64,
            ),
            globals,
            bind_group_layout: layout,
            bind_group,
            attachments: None,
        }
    }

    fn bind_group(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        globals: &wgpu::Buffer,
        sphere_path: SpherePath,
        spheres: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: globals.as_entire_binding() }];
        if sphere_path == SpherePath::Storage {
            entries.push(wgpu::BindGroupEntry { binding: 1, resource: spheres.as_entire_binding() });
        }
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals and spheres"),
            layout,
            entries: &entries,
        })
    }

    /// How this renderer's vertex shaders get the spheres.
    #[must_use]
    pub fn sphere_path(&self) -> SpherePath {
        self.sphere_path
    }

    /// Samples per pixel: 1, or 4 with MSAA.
    #[must_use]
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    fn attachments(&mut self, device: &wgpu::Device, size: [u32; 2]) -> &Attachments {
        if self.attachments.as_ref().is_none_or(|a| a.size != size) {
            let sample_count = self.sample_count;
            let make = |label: &str, format: wgpu::TextureFormat| {
                device
                    .create_texture(&wgpu::TextureDescriptor {
                        label: Some(label),
                        size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 },
                        mip_level_count: 1,
                        sample_count,
                        dimension: wgpu::TextureDimension::D2,
                        format,
                        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                        view_formats: &[],
                    })
                    .create_view(&Default::default())
            };
            self.attachments = Some(Attachments {
                size,
                color: (self.sample_count > 1).then(|| make("msaa colour", self.color_format)),
                depth: make("depth", DEPTH_FORMAT),
            });
        }
        self.attachments.as_ref().expect("created above")
    }

    /// Records the 3D pass: clears `target` (of `size` pixels, in this renderer's colour
    /// format) and draws `frame` as seen by `camera` into `viewport` (x, y, width,
    /// height in pixels, fitted into the target by [`fit_viewport`]). With a
    /// [`ViewPiece`](super::orbit_camera::ViewPiece) on the camera, `viewport` is where that
    /// piece of the whole view lands; an empty one (no width or height) draws nothing.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        size: [u32; 2],
        viewport: [f32; 4],
        camera: &OrbitCamera,
        frame: &FrameData,
    ) {
        let size = [size[0].max(1), size[1].max(1)];
        // A piece of a view (a tile of a big frame) may have none of the view in it:
        // the target is then only cleared.
        let empty = camera.piece.is_some() && (viewport[2] <= 0.0 || viewport[3] <= 0.0);
        let [x, y, width, height] = fit_viewport(viewport, size);
        let view_proj = match camera.piece {
            Some(piece) => camera.piece_projection(piece, [width, height]),
            None => camera.view_projection(width / height),
        };
        let light = Vec3::new(0.4, 0.8, 0.45).normalize();
        let globals = Globals {
            view_proj: view_proj.to_cols_array_2d(),
            eye: camera.eye().extend(camera.ground).to_array(),
            viewport: [width, height, if frame.grid { 1.0 } else { 0.0 }, camera.near()],
            light: light.extend(camera.distance).to_array(),
            forward: camera.forward().extend(if camera.orthographic { 1.0 } else { 0.0 }).to_array(),
        };
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let grown = self.sphere_buffer.write(device, queue, bytemuck::cast_slice(&frame.spheres));
        if grown && self.sphere_path == SpherePath::Storage {
            self.bind_group = Self::bind_group(
                device,
                &self.bind_group_layout,
                &self.globals,
                self.sphere_path,
                &self.sphere_buffer.buffer,
            );
        }
        self.segment_buffer.write(device, queue, bytemuck::cast_slice(&frame.segments));
        self.trail_buffer.write(device, queue, bytemuck::cast_slice(&frame.trails));
        if let Some(water) = &frame.water {
            self.water_buffer.write(device, queue, bytemuck::bytes_of(water));
        }

        let attachments = self.attachments(device, size);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                // Without MSAA draw straight into the target; with it, resolve into it.
                view: attachments.color.as_ref().unwrap_or(target),
                depth_slice: None,
                resolve_target: attachments.color.as_ref().map(|_| target),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(BACKGROUND),
                    store: if attachments.color.is_some() {
                        wgpu::StoreOp::Discard
                    } else {
                        wgpu::StoreOp::Store
                    },
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &attachments.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if empty {
            return;
        }
        pass.set_viewport(x, y, width, height, 0.0, 1.0);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_pipeline(&self.ground);
        pass.draw(0..6, 0..1);
        if !frame.spheres.is_empty() {
            // One triangle per sphere: on the storage path its three corners are
            // vertices 3i, 3i+1, 3i+2 of one draw; instanced, vertices 0..3 of instance i.
            let count = frame.spheres.len() as u32;
            let (vertices, instances) = match self.sphere_path {
                SpherePath::Storage => (0..3 * count, 0..1),
                SpherePath::Instanced => {
                    pass.set_vertex_buffer(0, self.sphere_buffer.buffer.slice(..));
                    (0..3, 0..count)
                }
            };
            if frame.shadows {
                pass.set_pipeline(&self.shadows);
                pass.draw(vertices.clone(), instances.clone());
            }
            pass.set_pipeline(&self.spheres);
            pass.draw(vertices, instances);
        }
        if !frame.segments.is_empty() {
            pass.set_pipeline(&self.segments);
            pass.set_vertex_buffer(0, self.segment_buffer.buffer.slice(..));
            pass.draw(0..6, 0..frame.segments.len() as u32);
        }
        if frame.water.is_some() {
            pass.set_pipeline(&self.water);
            pass.set_vertex_buffer(0, self.water_buffer.buffer.slice(..));
            pass.draw(0..6, 0..1);
        }
        // Last: translucent and writing no depth, so nothing behind them is cut away.
        if !frame.trails.is_empty() {
            pass.set_pipeline(&self.trails);
            pass.set_vertex_buffer(0, self.trail_buffer.buffer.slice(..));
            pass.draw(0..6, 0..frame.trails.len() as u32);
        }
    }
}

/// `viewport` (x, y, width, height in pixels) fitted into a target `size` pixels large:
/// its corner inside the target, at least a pixel wide and high, and no further out
/// than the target's edge.
#[must_use]
pub fn fit_viewport(viewport: [f32; 4], size: [u32; 2]) -> [f32; 4] {
    let [width, height] = [size[0].max(1) as f32, size[1].max(1) as f32];
    let x = viewport[0].clamp(0.0, width - 1.0);
    let y = viewport[1].clamp(0.0, height - 1.0);
    [x, y, viewport[2].clamp(1.0, width - x), viewport[3].clamp(1.0, height - y)]
}

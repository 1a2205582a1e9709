//! Off-screen targets: render into a texture and read it back as RGBA bytes or a PNG.

use std::fs::File;
use std::path::Path;

/// Format of off-screen textures (stored gamma-encoded); the 3D pass draws through an
/// sRGB view of it, egui through the plain view, as in the window.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// A texture to draw into and copy back.
pub struct OffscreenTarget {
    texture: wgpu::Texture,
    /// View for the 3D pass (sRGB).
    pub srgb_view: wgpu::TextureView,
    /// View for egui (gamma space).
    pub view: wgpu::TextureView,
    /// Width and height (px).
    pub size: [u32; 2],
    /// Where copies land for the CPU to read, rows padded to 256 bytes.
    readback: wgpu::Buffer,
    padded_row: u32,
}

impl OffscreenTarget {
    /// A target of any size (not only multiples of 64) in [`FORMAT`].
    #[must_use]
    pub fn new(device: &wgpu::Device, size: [u32; 2]) -> Self {
        Self::with_format(device, size, FORMAT)
    }

    /// A target in `format`: `Rgba8Unorm` or `Bgra8Unorm` (what a window's surface uses,
    /// so a screenshot goes through the window's own pipelines).
    #[must_use]
    pub fn with_format(device: &wgpu::Device, size: [u32; 2], format: wgpu::TextureFormat) -> Self {
        let format = format.remove_srgb_suffix();
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("off-screen target"),
            size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[format.add_srgb_suffix()],
        });
        let srgb_view = texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(format.add_srgb_suffix()),
            ..Default::default()
        });
        let view = texture.create_view(&Default::default());
        // Rows in a copy must be a multiple of 256 bytes apart.
        let padded_row =
            (size[0] * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row) * u64::from(size[1]),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Self { texture, srgb_view, view, size, readback, padded_row }
    }

    /// Copies the texture back to the CPU as tightly packed RGBA rows.
    pub fn read_rgba(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<u8>, String> {
        let [width, height] = self.size;
        let (row, padded_row, buffer) = (width * 4, self.padded_row, &self.readback);
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
        queue.submit([encoder.finish()]);
        let slice = buffer.slice(..);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| format!("GPU wait failed: {e}"))?;
        receiver
            .recv()
            .map_err(|e| format!("GPU read-back was dropped: {e}"))?
            .map_err(|e| format!("GPU read-back failed: {e}"))?;
        let mapped = slice.get_mapped_range().map_err(|e| format!("GPU read-back failed: {e}"))?;
        let mut pixels = Vec::with_capacity((row * height) as usize);
        for line in mapped.chunks(padded_row as usize) {
            pixels.extend_from_slice(&line[..row as usize]);
        }
        drop(mapped);
        buffer.unmap();
        if self.texture.format() == wgpu::TextureFormat::Bgra8Unorm {
            for pixel in pixels.chunks_exact_mut(4) {
                pixel.swap(0, 2);
            }
        }
        Ok(pixels)
    }
}

/// Writes tightly packed RGBA bytes as a PNG, whole or not at all, through
/// [`crate::writing`] (a link writes the file it names; a device or FIFO is refused).
pub fn write_png(path: &Path, size: [u32; 2], rgba: &[u8]) -> Result<(), String> {
    let cannot = |e: &dyn std::fmt::Display| {
        let text = e.to_string();
        let reason = text.split(" (os error").next().unwrap_or(&text);
        format!("cannot write {}: {}", crate::messages::path(path), crate::messages::quote(reason))
    };
    let mut file = crate::writing::AtomicFile::create(path).map_err(|e| cannot(&e))?;
    let mut encoder = png::Encoder::new(&mut file, size[0], size[1]);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| cannot(&e))?;
    writer.write_image_data(rgba).map_err(|e| cannot(&e))?;
    writer.finish().map_err(|e| cannot(&e))?;
    file.commit().map_err(|e| cannot(&e))
}

/// Reads a PNG as RGBA bytes and its size.
pub fn read_png(path: &Path) -> Result<(Vec<u8>, [u32; 2]), String> {
    let file = File::open(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::ALPHA);
    let mut reader = decoder.read_info().map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut buffer = vec![0; reader.output_buffer_size().ok_or("PNG too large")?];
    let info = reader.next_frame(&mut buffer).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    buffer.truncate(info.buffer_size());
    let pixels = match info.color_type {
        png::ColorType::Rgba => buffer,
        png::ColorType::GrayscaleAlpha => buffer.chunks(2).flat_map(|c| [c[0], c[0], c[0], c[1]]).collect(),
        other => return Err(format!("{}: unsupported PNG colour type {other:?}", path.display())),
    };
    Ok((pixels, [info.width, info.height]))
}

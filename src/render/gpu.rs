//! Finding a GPU adapter and device, with an error a user can act on.

use std::fmt;

/// Why no device could be had.
#[derive(Debug)]
pub enum GpuError {
    /// No adapter: no Vulkan (or GL) driver, or none that can present to the window.
    NoAdapter(String),
    /// The adapter refused to create a device.
    NoDevice(String),
    /// The window's surface could not be created.
    Surface(String),
    /// The adapter lacks something the renderer needs.
    Unsupported(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoAdapter(why) => write!(
                f,
                "no GPU adapter found ({why}); install a Vulkan driver, or for a software GPU the \
                 Debian/Ubuntu packages mesa-vulkan-drivers and libvulkan1"
            ),
            Self::NoDevice(why) => write!(f, "the GPU adapter could not create a device: {why}"),
            Self::Surface(why) => write!(f, "cannot draw into the window: {why}"),
            Self::Unsupported(why) => write!(
                f,
                "the GPU adapter cannot run particle-lab: {why}; install a Vulkan driver (for a \
                 software GPU the Debian/Ubuntu packages mesa-vulkan-drivers and libvulkan1)"
            ),
        }
    }
}

impl std::error::Error for GpuError {}

/// An adapter, its device and queue.
pub struct Gpu {
    /// The instance the adapter came from.
    pub instance: wgpu::Instance,
    /// The adapter.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// A device for off-screen rendering; needs no display.
    /// Its target is viewed in two formats (see [`Self::has_view_formats`]).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn headless() -> Result<Self, GpuError> {
        let gpu = Self::with_instance(wgpu::Instance::new(instance_descriptor(None)), None)?;
        if !gpu.has_view_formats(false) {
            let info = gpu.adapter.get_info();
            return Err(GpuError::Unsupported(format!(
                "{} ({:?}) cannot view textures in another format",
                info.name, info.backend
            )));
        }
        Ok(gpu)
    }

    /// In a browser there is no device without a page's canvas (nothing blocks there
    /// either): off-screen captures are the desktop's.
    #[cfg(target_arch = "wasm32")]
    pub fn headless() -> Result<Self, GpuError> {
        Err(GpuError::NoAdapter("off-screen rendering runs on the desktop only".into()))
    }

    /// A device from `instance` that can present to `surface`, if given.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn with_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        pollster::block_on(Self::request(instance, surface))
    }

    /// As [`Self::with_instance`], awaited: in a browser the adapter and device come
    /// only asynchronously.
    pub async fn request(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: surface,
                apply_limit_buckets: false,
            })
            .await
            .map_err(|e| GpuError::NoAdapter(crate::messages::plain(&e.to_string())))?;
        let info = adapter.get_info();
        log::info!("GPU adapter: {} ({:?}, {:?})", info.name, info.backend, info.device_type);
        // The 3D pass draws through an sRGB view of a gamma-space texture that egui
        // also draws into; that needs view formats, which WebGL2 and some GL drivers
        // lack: there both draw into one sRGB target (see `Surfaces`). Spheres need no
        // vertex storage either (see `SpherePath`).
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("particle-lab"),
                required_features: wgpu::Features::empty(),
                required_limits: base_limits(&adapter).using_resolution(adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoDevice(crate::messages::plain(&e.to_string())))?;
        Ok(Self { instance, adapter, device, queue })
    }

    /// Whether the 3D pass can draw through an sRGB view of a gamma-space target
    /// (`surface`: of a window's surface texture) while egui draws into the target.
    #[must_use]
    pub fn has_view_formats(&self, surface: bool) -> bool {
        let flags = self.adapter.get_downlevel_capabilities().flags;
        let mut needed = wgpu::DownlevelFlags::VIEW_FORMATS;
        if surface {
            needed |= wgpu::DownlevelFlags::SURFACE_VIEW_FORMATS;
        }
        flags.contains(needed)
    }
}

/// The size a window's surface is configured with for a window of `size` physical
/// pixels: each side within 1 (a surface is never empty) and `max_side`, the device's
/// largest texture (`max_texture_dimension_2d`, which is what a surface is checked
/// against: larger is a panic), or less after the GPU ran out of memory.
#[must_use]
pub fn fit_surface(size: [u32; 2], max_side: u32) -> [u32; 2] {
    size.map(|side| side.clamp(1, max_side.max(1)))
}

/// The least a device is asked for: the downlevel defaults, or WebGL2's (no storage
/// buffers, the spheres drawn as instances) for an adapter without vertex storage.
fn base_limits(adapter: &wgpu::Adapter) -> wgpu::Limits {
    match super::renderer::SpherePath::for_adapter(adapter) {
        super::renderer::SpherePath::Storage => wgpu::Limits::downlevel_defaults(),
        super::renderer::SpherePath::Instanced => wgpu::Limits::downlevel_webgl2_defaults(),
    }
}

/// Why a window's surface could not be made from `instance`: most often no Vulkan
/// driver loaded at all, which is then said as [`GpuError::NoAdapter`] says it, with the
/// packages to install.
#[cfg(not(target_arch = "wasm32"))]
#[must_use]
pub fn surface_error(instance: &wgpu::Instance, why: &str) -> GpuError {
    let options = wgpu::RequestAdapterOptions::default();
    match pollster::block_on(instance.request_adapter(&options)) {
        Err(error) => GpuError::NoAdapter(crate::messages::plain(&error.to_string())),
        // wgpu ends with the map of each backend's error, empty when none was tried.
        Ok(_) => GpuError::Surface(crate::messages::plain(why).trim_end_matches(": {}").to_string()),
    }
}

/// Instance settings: the modern backends (Vulkan, Metal, DX12) unless the
/// `WGPU_BACKEND` environment variable asks for others; `display` for a window.
#[must_use]
pub fn instance_descriptor(
    display: Option<Box<dyn wgpu::wgt::WgpuHasDisplayHandle>>,
) -> wgpu::InstanceDescriptor {
    let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
    // In a browser: WebGPU where it exists, else WebGL2 (see `crate::web`).
    descriptor.backends = if cfg!(target_arch = "wasm32") {
        wgpu::Backends::BROWSER_WEBGPU | wgpu::Backends::GL
    } else {
        wgpu::Backends::PRIMARY
    };
    if let Some(display) = display {
        descriptor = descriptor.with_display_handle(display);
    }
    descriptor.with_env()
}

#[cfg(test)]
mod tests {
    use super::fit_surface;

    #[test]
    fn a_surface_fits_the_largest_texture_and_is_never_empty() {
        assert_eq!(fit_surface([1280, 720], 16_384), [1280, 720]);
        assert_eq!(fit_surface([20_000, 700], 16_384), [16_384, 700]);
        assert_eq!(fit_surface([16_384, 16_384], 8_192), [8_192, 8_192]);
        assert_eq!(fit_surface([0, 0], 8_192), [1, 1]);
        assert_eq!(fit_surface([500, 500], 0), [1, 1]);
    }
}

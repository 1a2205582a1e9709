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
    pub fn headless() -> Result<Self, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        Self::with_instance(instance, None)
    }

    /// A device from `instance` that can present to `surface`, if given.
    pub fn with_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: surface,
            apply_limit_buckets: false,
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        log::info!("GPU adapter: {} ({:?}, {:?})", info.name, info.backend, info.device_type);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("particle-lab"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoDevice(e.to_string()))?;
        Ok(Self { instance, adapter, device, queue })
    }
}

//! Drawing: an orbit camera, the per-frame data built from a scene, and the wgpu
//! renderer that draws it into a window or an off-screen texture with the same code.
//! Reads the physics; never steps it.

pub mod frame;
pub mod gpu;
pub mod offscreen;
pub mod orbit_camera;
pub mod renderer;

pub use frame::{FrameBuilder, FrameData, Trails, ViewOptions};
pub use gpu::{Gpu, GpuError};
pub use offscreen::OffscreenTarget;
pub use orbit_camera::OrbitCamera;
pub use renderer::{Renderer, SpherePath};

//! What every renderer shares, GPU or CPU: the camera, the splat kernel, the
//! shading model and the render settings. Keeping them here (with no GPU types) lets the exact CPU
//! reference and the wgpu passes produce images that compare pixel for pixel.

pub mod camera;
pub mod kernel;
pub mod parameters;
pub mod settings;
pub mod shading;
pub mod sidecar;

pub use camera::{Camera, UpAxis};
pub use kernel::SplatKernel;
pub use parameters::Parameter;
pub use settings::{Quality, RenderMode, RenderSettings};
pub use shading::Shading;
pub use sidecar::Sidecar;

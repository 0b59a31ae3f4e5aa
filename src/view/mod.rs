//! What every renderer shares, GPU or CPU: the camera, the splat kernel and
//! the shading model. Keeping them here (with no GPU types) lets the exact CPU
//! reference and the wgpu passes produce images that compare pixel for pixel.

pub mod camera;
pub mod kernel;
pub mod shading;

pub use camera::{Camera, UpAxis};
pub use kernel::SplatKernel;
pub use shading::Shading;

//! GPU rendering with wgpu: context, Pod data, targets, one file per pass, the
//! render plan, the renderer that runs it, and readback.

pub mod context;
pub mod gpu_data;
pub mod headless;
pub mod passes;
pub mod plan;
pub mod readback;
pub mod renderer;
pub mod shaders;
pub mod splat_buffers;
pub mod targets;
pub mod timer;

pub use crate::view::{Quality, RenderMode, RenderSettings};
pub use context::{GpuContext, GpuError};
pub use headless::HeadlessRenderer;
pub use plan::RenderPlan;
pub use splat_buffers::GpuCloud;

//! pointblend's GPU renderer, on wgpu. It builds on `pointblend-core` (the
//! scene, the grouping, the frame vocabulary and the mode registry) and
//! knows nothing of the window, the UI or the command line.
//!
//! How a frame flows, scene → plan → passes → image:
//! 1. [`GpuScene`] uploads a scene's splats once (in group order for modes
//!    that draw groups).
//! 2. The frame's mode (the registry's entry, implemented in [`modes`], one
//!    file per mode) turns the settings, the size and what the scene holds into
//!    a [`RenderPlan`]: its passes and, for each, the typed targets it reads and
//!    writes. `--explain` and the viewer print this plan.
//! 3. The mode records the plan as [`passes::Command`]s: splat passes and
//!    full-screen passes, each with its variant and its own uniforms.
//! 4. The [`renderer::Renderer`] allocates exactly the plan's targets
//!    ([`targets::TargetPool`]), takes every pass's pipeline from
//!    [`pipelines::PipelineCache`] (shader variants from [`shaders`]), encodes
//!    the passes into the output view, timed per plan pass when asked.
//! 5. Modes that blend in order get each group's splats back to front
//!    ([`instance_order::InstanceOrder`]), re-sorted and rewritten only when
//!    the view changed.
//! 6. [`HeadlessRenderer`] renders into its own texture and reads the image
//!    back ([`readback`]); the viewer does the same on its render thread.

// The core modules the renderer reads, reachable as `crate::cloud` and so on.
use pointblend_core::{cloud, frame, grouping, lod, memory, scene, shadow, spatial};

pub mod context;
pub mod depth_steps;
pub mod environment;
pub mod gpu_data;
pub mod gpu_scene;
pub mod headless;
pub mod instance_order;
pub mod modes;
pub mod passes;
pub mod pipelines;
pub mod plan;
pub mod readback;
pub mod record;
pub mod renderer;
pub mod report;
pub mod scene_frames;
pub mod shaders;
pub mod target_id;
pub mod targets;
pub mod tile_engine;
pub mod timer;
pub mod touches;
pub mod window;

pub use crate::frame::{Quality, RenderMode, RenderSettings};
pub use context::{GpuContext, GpuError};
pub use gpu_scene::GpuScene;
pub use headless::HeadlessRenderer;
pub use plan::RenderPlan;
pub use renderer::Renderer;
pub use report::FrameReport;
pub use scene_frames::{
    Frame, FrameError, FrameUpdate, Readback, SceneFrames, SceneGrouping, per_frame_grouping, rest_lattice,
};

//! pointblend's GPU renderer, on wgpu. It builds on `pointblend-core` (the
//! scene, the grouping, the frame vocabulary and the mode registry) and
//! knows nothing of the window, the UI or the command line.
//!
//! How a frame flows, settings → spec → selection → plan → passes → image → report:
//! 1. A front end decides the frame once: `frame::resolve` (in the core)
//!    turns the settings, what the scene is and the view into a `FrameSpec`
//!    (the mode that runs, the splats selected, the grouping drawn, lights,
//!    eye-dome lighting, environment, low-pass radius, ε's mean radius, notes).
//! 2. [`PreparedScene::render_frame`] carries the spec out: it prepares what
//!    the spec selects (the hybrid leaves, the nodes under a point budget, or
//!    every splat) as a [`GpuScene`] (uploaded once, in group order for modes
//!    that draw groups, with the frame's shadow coefficients beside it; a
//!    streamed selection's nodes keep their slots in a [`node_pool`], so the
//!    next selection writes only what changed, [`changed_records`], and the
//!    nodes it drops stay there undrawn, left out by a [`live_mask`], until
//!    the room is needed).
//! 3. The frame's mode (implemented in [`modes`], one file per mode) turns
//!    the spec, the size and what the upload holds into a [`RenderPlan`]:
//!    its steps and, for each, the typed targets its passes read and write.
//!    A plan is final when made; `--explain` and the viewer print it.
//! 4. The [`Renderer`] allocates exactly the plan's targets
//!    ([`targets::TargetPool`]), takes every pass's pipeline from
//!    [`pipelines::PipelineCache`] (shader variants from [`shaders`]), and
//!    encodes the passes, timed per plan pass when asked. Modes that blend in
//!    order get each group's splats back to front
//!    ([`instance_order::InstanceOrder`]), re-sorted only when the view changed.
//! 5. [`GpuRenderer`] draws into its own texture, a sub-frame at a time when
//!    the frame would pass its memory budget ([`subframe`]), and reads the
//!    image back ([`readback`]); the viewer's render thread uses it too.
//! 6. What the frame measured while it ran (tile lists, overflows, the
//!    selection and the shadows it took) comes back as its [`FrameReport`].

// The core modules the renderer reads, reachable as `crate::cloud` and so on.
use pointblend_core::{cloud, frame, grouping, lod, memory, scene, shadow, spatial};

pub mod changed_records;
pub mod context;
pub mod depth_steps;
pub mod environment_texture;
pub mod gpu_data;
pub mod gpu_renderer;
pub mod gpu_scene;
pub mod instance_layout;
pub mod instance_order;
pub mod live_mask;
pub mod modes;
pub mod node_pool;
pub mod passes;
pub mod pipelines;
pub mod plan;
pub mod prepared_scene;
pub mod readback;
pub mod record;
pub mod renderer;
pub mod report;
pub mod scene_cache;
pub mod section;
pub mod shaders;
pub mod subframe;
pub mod target_id;
pub mod targets;
pub mod tile_buffers;
pub mod tile_engine;
pub mod tile_layout;
pub mod timer;
pub mod touches;

pub use crate::frame::{Quality, RenderMode, RenderSettings};
pub use context::{GpuContext, GpuError};
pub use gpu_renderer::GpuRenderer;
pub use gpu_scene::GpuScene;
pub use plan::RenderPlan;
pub use prepared_scene::{
    Frame, FrameError, FrameUpdate, PreparedScene, Readback, SceneGrouping, per_frame_grouping, rest_lattice,
};
pub use renderer::Renderer;
pub use report::FrameReport;

//! What every renderer shares, GPU or CPU: the camera, the splat kernel, the
//! shading model, the render settings and the mode registry. Keeping them here
//! (with no GPU types) lets the exact CPU reference and the wgpu passes
//! produce images that compare pixel for pixel.

pub mod camera;
pub mod camera_request;
pub mod clip;
pub mod environment_effects;
pub mod eye_dome;
pub mod eye_ray;
pub mod front_depth;
pub mod kernel;
pub mod lights;
pub mod look;
pub mod modes;
pub mod parameters;
pub mod prefilter;
pub mod projection;
pub mod settings;
pub mod shading;
pub mod sidecar;
pub mod spec;
pub mod subset;
pub mod variant;
pub mod view_path;

pub use camera::{Camera, UpAxis};
pub use camera_request::CameraRequest;
pub use clip::{Clip, ClipRegion};
pub use eye_dome::EyeDome;
pub use front_depth::FrontDepth;
pub use kernel::SplatKernel;
pub use lights::{Light, LightKind, Lights, ShadowMethod, ShadowSettings};
pub use modes::{ModeInfo, RenderMode};
pub use parameters::Parameter;
pub use prefilter::Prefilter;
pub use projection::{NamedView, Projection};
pub use settings::{Quality, RenderSettings};
pub use shading::Shading;
pub use sidecar::Sidecar;
pub use spec::{FrameNote, FrameSpec, SceneFacts, Selection, View, resolve};
pub use variant::ModeVariant;
pub use view_path::ViewPath;

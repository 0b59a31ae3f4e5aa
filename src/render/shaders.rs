//! WGSL sources, embedded at build time and composed into shader modules.
//!
//! WGSL has no includes: each pass module is the shared `frame.wgsl`, the
//! shared `splat.wgsl` where the pass draws splats (or `shading.wgsl` where it
//! shades full screen), and the pass's own file.

pub const FRAME: &str = include_str!("../../shaders/frame.wgsl");
pub const SPLAT: &str = include_str!("../../shaders/splat.wgsl");
pub const VISIBILITY: &str = include_str!("../../shaders/visibility.wgsl");
pub const ACCUMULATE: &str = include_str!("../../shaders/accumulate.wgsl");
pub const NORMALIZE: &str = include_str!("../../shaders/normalize.wgsl");
pub const SHADING: &str = include_str!("../../shaders/shading.wgsl");
pub const DEFERRED_GEOMETRY: &str = include_str!("../../shaders/deferred_geometry.wgsl");
pub const DEFERRED_COMPOSITE: &str = include_str!("../../shaders/deferred_composite.wgsl");

/// A shader module's name and its composed source.
pub struct ComposedShader {
    pub name: &'static str,
    pub source: String,
}

/// Every shader module the renderer builds, composed.
pub fn all() -> Vec<ComposedShader> {
    vec![
        ComposedShader { name: "visibility", source: [FRAME, SPLAT, VISIBILITY].concat() },
        ComposedShader { name: "accumulate", source: [FRAME, SPLAT, ACCUMULATE].concat() },
        ComposedShader { name: "normalize", source: [FRAME, SHADING, NORMALIZE].concat() },
        ComposedShader { name: "deferred_geometry", source: [FRAME, SPLAT, DEFERRED_GEOMETRY].concat() },
        ComposedShader { name: "deferred_composite", source: [FRAME, SHADING, DEFERRED_COMPOSITE].concat() },
    ]
}

/// The composed source of the module called `name`.
pub fn source(name: &str) -> String {
    all().into_iter().find(|s| s.name == name).map(|s| s.source).unwrap_or_default()
}

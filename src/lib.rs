//! pointblend: point-based surface splatting on wgpu, as a library for the
//! app's command line, viewer and benchmark.
//!
//! The workspace has three layers, and the compiler keeps them apart:
//! `pointblend-core` (crates/core: loading, scenes, neighbour queries,
//! grouping, the exact CPU reference and the frame vocabulary, with no GPU,
//! window or UI dependency), `pointblend-render` (crates/render: the wgpu
//! modes, passes and shaders) and this app crate: [`bench`] measures the
//! modes against the reference and [`viewer`] is the interactive window. The
//! core's modules and the renderer are re-exported here under their own
//! names, so `pointblend::cloud` and `pointblend::render` read as before.

pub use pointblend_core::{
    cloud, copc, formats, frame, grouping, hash, hybrid, input, inspect, lod, memory, output, progress, reference,
    scene, shadow, spatial, style,
};
pub use pointblend_render as render;

pub mod assets;
pub mod bench;
pub mod font;
pub mod viewer;

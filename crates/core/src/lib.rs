//! pointblend's CPU core: everything that needs no GPU, window or UI, so the
//! compiler keeps those out (this crate depends on none of them).
//!
//! The modules are layered from the ground up: [`spatial`] answers neighbour
//! queries over plain positions and radii, [`cloud`] loads and repairs point
//! clouds, [`style`] colours them and sets their opacity by attribute, [`grouping`] splits splats into groups, [`frame`] holds the camera,
//! the splat kernel, the shading model, the render settings and the mode
//! registry that every renderer (GPU or CPU) shares, [`scene`] places clouds
//! with transforms and materials (and meshes, whose triangles [`hybrid`]
//! splits into leaves drawn as triangles or splats), [`lod`] builds the multi-resolution
//! hierarchy that frames under a point budget draw from, [`copc`] streams COPC files node by node under the same selection, [`shadow`] finds the light each splat
//! receives (translucent shadow maps and exact shadow rays), and
//! [`reference`] renders exactly on the CPU (and picks the layers of a ray),
//! on which [`inspect`] builds the pick and measure answers. Under them all, [`formats`] (the table of
//! file formats every reader dispatches on), [`input`] (regular files only, bounded), [`hash`],
//! [`memory`], [`output`] and [`progress`] are small helpers. No module imports one above it (`tests/architecture.rs`).

pub mod cloud;
pub mod copc;
pub mod formats;
pub mod frame;
pub mod grouping;
pub mod hash;
pub mod hybrid;
pub mod input;
pub mod inspect;
pub mod lod;
pub mod memory;
pub mod named;
pub mod output;
pub mod progress;
pub mod reference;
pub mod scene;
pub mod shadow;
pub mod spatial;
pub mod style;

//! pointblend: point-based surface splatting on wgpu.
//!
//! The crate is layered from the ground up: [`spatial`] answers neighbour
//! queries over plain positions and radii, [`cloud`] loads and repairs point
//! clouds, [`scene`] places clouds with transforms and materials, [`grouping`]
//! splits splats into groups, [`reference`] renders exactly on the CPU,
//! [`view`] holds the camera, the shading model and the mode registry that
//! every renderer (GPU or CPU) shares, and [`render`] draws splats with wgpu.
//! Under them all, [`hash`], [`memory`], [`output`] and [`progress`] are small
//! helpers. Only [`render`] and [`viewer`] touch the GPU (a test checks it).
//! [`bench`] measures the modes against the reference; [`viewer`] is the
//! interactive window on top of them.

pub mod bench;
pub mod cloud;
pub mod grouping;
pub mod hash;
pub mod memory;
pub mod output;
pub mod progress;
pub mod reference;
pub mod render;
pub mod scene;
pub mod spatial;
pub mod view;
pub mod viewer;

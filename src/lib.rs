//! pointblend: point-based surface splatting on wgpu.
//!
//! The crate is layered from the ground up: [`cloud`] loads and repairs point
//! clouds, [`spatial`] answers neighbour queries, [`view`] holds the camera and
//! the shading model that every renderer (GPU or CPU) shares, and [`render`]
//! draws splats with wgpu. Only [`render`] touches the GPU. [`viewer`] is the
//! interactive window on top of them.

pub mod bench;
pub mod cloud;
pub mod grouping;
pub mod memory;
pub mod output;
pub mod progress;
pub mod reference;
pub mod render;
pub mod spatial;
pub mod view;
pub mod viewer;

//! Spatial queries over splat centres: k nearest neighbours (kiddo), a hashed
//! uniform grid for fixed-radius queries, and the splat overlap graph.

pub mod grid;
pub mod knn;
pub mod overlap;

//! Spatial queries over splat centres: k nearest neighbours (kiddo), a hashed
//! uniform grid for fixed-radius queries, the splat overlap graph, and the
//! back-to-front orders of transparency (BSP tree, hierarchical buckets).

pub mod grid;
pub mod knn;
pub mod order;
pub mod overlap;

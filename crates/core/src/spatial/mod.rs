//! Spatial queries over splat centres: k nearest neighbours (kiddo), a hashed
//! uniform grid for fixed-radius queries, the splat overlap graph, and the
//! back-to-front orders of transparency (BSP tree, hierarchical buckets).

pub mod even_odd;
pub mod grid;
pub mod grid_knn;
pub mod knn;
pub mod neighbours;
pub mod order;
pub mod overlap;

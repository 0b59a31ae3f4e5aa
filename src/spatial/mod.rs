//! Spatial queries over splat centres.

pub mod knn;

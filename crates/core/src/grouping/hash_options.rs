//! The options of hash grouping (Zhang & Pajarola 2007 §4.3): K, and which
//! collisions are resolved. Their own module, below the grouping
//! ([`super::hash`]) and the regrouper that implements it.

use glam::Vec3;

/// Which collisions are resolved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Collisions {
    None,
    All,
    /// Only for splats closer to `eye` than `distance`.
    Near {
        eye: Vec3,
        distance: f32,
    },
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HashOptions {
    pub k: usize,
    pub collisions: Collisions,
}

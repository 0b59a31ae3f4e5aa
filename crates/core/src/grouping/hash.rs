//! Dynamic hash grouping (Zhang & Pajarola 2007 §4.3, Eq. 9, Fig. 9).
//!
//! Each splat is mapped to 2D cell coordinates (x, y) in the plane across the
//! dominant axis d of its neighbourhood's mean normal (Eq. 9), and its group
//! is [`super::table::Table`]'s entry for (x, y), the K x K generalisation of
//! Fig. 9. Where the paper averages normals over a
//! BSP leaf, we average them over coarse grid cells of 16 radii ("leaves").
//! The cell size is the median radius for all splats, so that neighbours
//! share one lattice.
//!
//! Collisions are two splats in the same leaf and cell. Modes:
//! (1) ignore them; (2) handle all: the cell's first splat (by index) keeps
//! its table group and every later one takes the group of least overlap with
//! its neighbours that no splat of its cell has yet; (3) handle only the
//! splats nearer to the eye than a given distance. The work is done by
//! [`super::regroup`], which keeps its buffers from frame to frame.

pub use super::hash_options::{Collisions, HashOptions};
use super::regroup::{HashRegrouper, Lattice};
use super::{Grouping, GroupingError};
use crate::cloud::PointCloud;

/// Groups `cloud` by hashing on the lattice of its own median radius;
/// returns the grouping and the number of collisions resolved.
pub fn group(cloud: &PointCloud, options: &HashOptions) -> Result<(Grouping, usize), GroupingError> {
    let (grouping, stats) = HashRegrouper::new(Lattice::of(cloud), *options)?.group_once(cloud);
    Ok((grouping, stats.resolved))
}

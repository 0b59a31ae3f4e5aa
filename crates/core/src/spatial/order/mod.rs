//! Back-to-front orders of splats for a view: what transparency blending
//! needs (Zhang & Pajarola 2007 §5.2.1; Gunjee et al. §4.2).
//!
//! Three orders, all over splat centres, all for a perspective eye:
//! - [`BspTree`]: a binary space partition built once per scene (splitting
//!   planes through the median along the longest axis, leaves of a few
//!   nearby splats). Per view it is traversed far side first, in O(n), as
//!   Zhang & Pajarola's §5.2.1 does; the order is exact between leaves along
//!   every ray from the eye and unordered inside a leaf.
//! - [`BucketSort`]: Gunjee's hierarchical bucket sort (Eq. 10-13): view
//!   depths cut into slices of thickness ε, √(slices) first-level buckets
//!   each split into √(slices) accurate ones; O(n + √slices·buckets used),
//!   unordered inside a slice.
//! - [`full_sort`]: a comparison sort of (depth, index) keys, the exact
//!   baseline both are tested and measured against.
//!
//! Depth is Gunjee's Eq. 12, the distance to the eye projected on the view
//! direction (view z); it grows along every ray from the eye, so any order
//! by it is back to front along each pixel's ray. Each order reports its
//! slab thickness: two splats can be out of depth order by at most that
//! much. `render::instance_order` partitions one order into one
//! back-to-front sequence per group, as the transparent grouped passes draw them.

mod bsp;
mod bucket;
mod sort;

pub use bsp::BspTree;
pub use bucket::BucketSort;
pub use sort::full_sort;

use glam::Vec3;

/// Where the view is: the eye and the unit direction it looks along.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewRay {
    pub eye: Vec3,
    pub forward: Vec3,
    /// Orthographic: every ray runs along `forward` (from anywhere), not out of the eye.
    pub parallel: bool,
}

impl ViewRay {
    /// Whether the high side of the plane `axis` = `value` is the far one:
    /// the side without the eye, or in orthographic the side `forward` runs to.
    pub fn far_side_is_high(&self, axis: usize, value: f32) -> bool {
        if self.parallel { self.forward[axis] >= 0.0 } else { self.eye[axis] <= value }
    }

    /// Gunjee's Eq. 12: the distance from the eye to `p` projected on the view direction.
    pub fn depth(&self, p: Vec3) -> f32 {
        (p - self.eye).dot(self.forward)
    }
}

/// Which back-to-front order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OrderKind {
    Bsp,
    Bucket,
    Sort,
}

impl OrderKind {
    pub const ALL: [OrderKind; 3] = [OrderKind::Bsp, OrderKind::Bucket, OrderKind::Sort];

    pub fn name(self) -> &'static str {
        match self {
            OrderKind::Bsp => "bsp",
            OrderKind::Bucket => "bucket",
            OrderKind::Sort => "sort",
        }
    }
}

crate::by_name!(OrderKind, "order");

/// An order ready to be asked for views: the BSP tree is built here (once),
/// the others keep their buffers between views.
pub enum Orderer {
    Bsp(BspTree),
    Bucket(BucketSort),
    Sort,
}

impl Orderer {
    /// Prepares `kind` over `points` with splat radii `radii`.
    pub fn new(kind: OrderKind, points: &[Vec3], radii: &[f32]) -> Self {
        match kind {
            OrderKind::Bsp => Orderer::Bsp(BspTree::build(points, radii)),
            OrderKind::Bucket => Orderer::Bucket(BucketSort::for_radii(radii)),
            OrderKind::Sort => Orderer::Sort,
        }
    }

    pub fn kind(&self) -> OrderKind {
        match self {
            Orderer::Bsp(_) => OrderKind::Bsp,
            Orderer::Bucket(_) => OrderKind::Bucket,
            Orderer::Sort => OrderKind::Sort,
        }
    }

    /// Writes `points`' indices into `out`, back to front for `view`, and
    /// returns the slab thickness: an earlier splat's depth is at least a
    /// later one's minus this (along any ray, for the BSP tree).
    pub fn back_to_front(&mut self, points: &[Vec3], view: ViewRay, out: &mut Vec<u32>) -> f32 {
        match self {
            Orderer::Bsp(tree) => {
                tree.back_to_front(&view, out);
                tree.slab()
            }
            Orderer::Bucket(buckets) => buckets.back_to_front(points, view, out),
            Orderer::Sort => {
                full_sort(points, view, out);
                0.0
            }
        }
    }
}

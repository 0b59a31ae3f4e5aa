//! The nodes a frame draws under a point budget: refinement by screen-space
//! error, largest first.
//!
//! A node's error is its splats' largest radius projected at its nearest
//! point to the eye, in pixels. Starting from the root, the visible node of
//! largest error is replaced by its visible children while the splats drawn
//! stay within the budget; a node that cannot be refined (a leaf, or one whose
//! children would overrun the budget) is drawn as it is. Nodes whose bounding
//! sphere lies outside the view frustum are dropped. The root is always
//! drawn when visible, so a budget smaller than the root draws the root.

use std::collections::BinaryHeap;

use glam::{Mat4, Vec3};

use super::Hierarchy;
use crate::cloud::PointCloud;
use crate::frame::Camera;

/// What a frame draws.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// Indices into `Hierarchy::nodes`, in the order they were chosen.
    pub nodes: Vec<u32>,
    /// Splats of those nodes together.
    pub splats: usize,
}

/// The view frustum in eye space, as what a sphere must pass.
pub(crate) struct Frustum {
    view: Mat4,
    planes: [Vec3; 4],
    near: f32,
    far: f32,
    /// Pixels per unit of eye space at view depth 1, vertically.
    pixels_per_unit: f32,
}

impl Frustum {
    pub(crate) fn new(camera: &Camera, (width, height): (u32, u32)) -> Self {
        let aspect = width.max(1) as f32 / height.max(1) as f32;
        let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let tan_x = tan_y * aspect;
        let (near, far) = camera.near_far();
        // Inward normals of the four side planes (all through the eye).
        let planes = [
            Vec3::new(-1.0, 0.0, -tan_x).normalize(),
            Vec3::new(1.0, 0.0, -tan_x).normalize(),
            Vec3::new(0.0, -1.0, -tan_y).normalize(),
            Vec3::new(0.0, 1.0, -tan_y).normalize(),
        ];
        Self { view: camera.view_matrix(), planes, near, far, pixels_per_unit: height.max(1) as f32 * 0.5 / tan_y }
    }

    /// The node's error in pixels, or `None` when its sphere is outside the frustum.
    pub(crate) fn error(&self, centre: Vec3, reach: f32, radius: f32) -> Option<f32> {
        let c = self.view.transform_point3(centre);
        let depth = -c.z;
        if depth + reach < self.near || depth - reach > self.far || self.planes.iter().any(|n| n.dot(c) < -reach) {
            return None;
        }
        Some(self.error_anywhere(centre, reach, radius))
    }

    /// The node's error in pixels wherever it is.
    pub(crate) fn error_anywhere(&self, centre: Vec3, reach: f32, radius: f32) -> f32 {
        let nearest = self.view.transform_point3(centre).length() - reach;
        if nearest <= self.near { f32::INFINITY } else { radius * self.pixels_per_unit / nearest }
    }
}

/// How a frame selects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelectOptions {
    pub budget: usize,
    /// The factor on every splat radius the frame draws with.
    pub radius_scale: f32,
    /// Drop nodes outside the view (not when the selected splats also cast
    /// the frame's shadows: an occluder off screen still shades what is on it).
    pub cull: bool,
}

/// The nodes to draw from `camera` at `size` (see the module doc).
pub fn select(hierarchy: &Hierarchy, camera: &Camera, size: (u32, u32), options: SelectOptions) -> Selection {
    let budget = options.budget;
    let frustum = Frustum::new(camera, size);
    let nodes = &hierarchy.nodes;
    let scale = options.radius_scale.max(0.0);
    let error = |i: u32| {
        let n = &nodes[i as usize];
        let reach = n.reach + (scale - 1.0).max(0.0) * n.radius;
        match frustum.error(n.centre, reach, n.radius * scale) {
            None if !options.cull => Some(frustum.error_anywhere(n.centre, reach, n.radius * scale)),
            e => e,
        }
    };
    let mut chosen = Vec::new();
    let mut heap = BinaryHeap::new();
    let Some(root_error) = error(0) else { return Selection { nodes: chosen, splats: 0 } };
    // Positive floats order as their bits do; the index breaks ties deterministically.
    heap.push((root_error.to_bits(), u32::MAX, 0u32));
    let mut drawn = nodes[0].count as usize;
    let mut children = Vec::with_capacity(8);
    while let Some((_, _, at)) = heap.pop() {
        let node = &nodes[at as usize];
        if node.is_leaf() {
            chosen.push(at);
            continue;
        }
        children.clear();
        children.extend((node.children..node.children + node.child_count).filter_map(|c| error(c).map(|e| (e, c))));
        let below: usize = children.iter().map(|&(_, c)| nodes[c as usize].count as usize).sum();
        let after = drawn - node.count as usize + below;
        if after <= budget {
            drawn = after;
            for &(e, c) in &children {
                heap.push((e.to_bits(), u32::MAX - c, c));
            }
        } else {
            chosen.push(at);
        }
    }
    Selection { nodes: chosen, splats: drawn }
}

/// The splats of `selection`'s nodes, node after node, as one cloud.
pub fn gather(hierarchy: &Hierarchy, selection: &Selection) -> PointCloud {
    let all = &hierarchy.splats;
    let two_sided = !all.two_sided.is_empty();
    let n = selection.splats;
    let mut out = PointCloud {
        positions: Vec::with_capacity(n),
        normals: Vec::with_capacity(n),
        radii: Vec::with_capacity(n),
        colours: Vec::with_capacity(n),
        opacity: Vec::with_capacity(n),
        two_sided: Vec::with_capacity(if two_sided { n } else { 0 }),
        origin: all.origin,
        scale_exponent: all.scale_exponent,
        scanner_position: all.scanner_position,
        attributes: Default::default(),
        z_up: all.z_up,
    };
    for &at in &selection.nodes {
        let node = &hierarchy.nodes[at as usize];
        super::append_range(&mut out, all, node.first as usize..(node.first + node.count) as usize, two_sided);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn culled(budget: usize) -> SelectOptions {
        SelectOptions { budget, radius_scale: 1.0, cull: true }
    }

    fn setup() -> (PointCloud, Hierarchy, Camera) {
        let cloud = crate::scene::primitives::plane(60_000, 2.0, Vec3::ZERO, Vec3::Y);
        let h = Hierarchy::build(&cloud);
        let mut camera = Camera::default_for(&cloud, 1.0);
        camera.elevation_deg = 40.0;
        (cloud, h, camera)
    }

    #[test]
    fn the_budget_is_kept_and_a_larger_one_draws_more() {
        let (_, h, camera) = setup();
        let mut last = 0;
        for budget in [2_000, 10_000, 30_000] {
            let s = select(&h, &camera, (256, 256), culled(budget));
            let counted: usize = s.nodes.iter().map(|&n| h.nodes[n as usize].count as usize).sum();
            assert_eq!(counted, s.splats);
            assert!(s.splats <= budget, "{} splats for a budget of {budget}", s.splats);
            assert!(s.splats > last, "budget {budget}: {} splats, no more than {last}", s.splats);
            last = s.splats;
            assert_eq!(gather(&h, &s).len(), s.splats);
        }
    }

    #[test]
    fn a_budget_of_the_whole_cloud_draws_the_leaves_and_of_one_the_root() {
        let (cloud, h, camera) = setup();
        let all = select(&h, &camera, (256, 256), culled(usize::MAX));
        assert!(all.nodes.iter().all(|&n| h.nodes[n as usize].is_leaf()));
        assert_eq!(all.splats, cloud.len(), "every splat is in view");
        let one = select(&h, &camera, (256, 256), culled(1));
        assert_eq!(one.nodes, vec![0]);
    }

    #[test]
    fn nodes_behind_the_camera_are_dropped() {
        let (_, h, mut camera) = setup();
        // Looking down at a point far below the plane: the plane is behind the eye.
        camera.target = Vec3::new(0.0, -50.0, 0.0);
        camera.distance = 1.0;
        let s = select(&h, &camera, (256, 256), culled(usize::MAX));
        assert_eq!(s.splats, 0, "the plane is behind the eye");
        // Unless the splats also cast shadows: then they are kept.
        let kept = select(&h, &camera, (256, 256), SelectOptions { cull: false, ..culled(usize::MAX) });
        assert_eq!(kept.splats, h.originals);
    }
}

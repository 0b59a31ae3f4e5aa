//! The nodes a frame draws under a point budget: refinement by screen-space
//! error, largest first, over any [`LodTree`].
//!
//! A node's error is its coarseness (its splats' largest radius, or a
//! streamed node's point spacing) projected at its nearest point to the eye,
//! in pixels. Starting from the root, the visible node of largest error is
//! refined while the splats drawn stay within the budget. Two kinds of tree
//! share this one selection, which knows how they differ
//! ([`Refinement`]): in the in-memory [`Hierarchy`] children replace their
//! parent; in a COPC file (Potree-style additive refinement) they add to it,
//! so a refined node stays drawn. A node that cannot be refined (a leaf, one
//! whose children would overrun the budget, or one finer than
//! [`SelectOptions::finest_px`]) is drawn as it is. Nodes whose bounding
//! sphere lies outside the view frustum are dropped. The root is always
//! drawn when visible, so a budget smaller than the root draws the root
//! (and so is each file's root in a forest of files, [`LodTree::always_drawn`]).

use std::collections::BinaryHeap;

use glam::{Mat4, Vec3};

use super::Hierarchy;
use crate::cloud::PointCloud;
use crate::frame::Camera;
use crate::frame::subset::Choosing;

/// What a frame draws.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// Indices into `Hierarchy::nodes`, in the order they were chosen.
    pub nodes: Vec<u32>,
    /// Splats of those nodes together.
    pub splats: usize,
}

/// The view frustum in eye space, as what a sphere must pass (a box in
/// orthographic).
pub(crate) struct Frustum {
    view: Mat4,
    /// The side planes' inward unit normals and offsets (n·p + d ≥ 0 inside).
    planes: [(Vec3, f32); 4],
    near: f32,
    far: f32,
    /// Pixels per unit of eye space at view depth 1, vertically (at any depth in orthographic).
    pixels_per_unit: f32,
    ortho: bool,
}

impl Frustum {
    pub(crate) fn new(camera: &Camera, (width, height): (u32, u32)) -> Self {
        let aspect = width.max(1) as f32 / height.max(1) as f32;
        let half = camera.lens(aspect);
        let (near, far) = camera.near_far();
        let ortho = camera.is_ortho();
        let planes = if ortho {
            // Parallel to the view axis, the window's half extent from it.
            [(Vec3::X, half.x), (Vec3::NEG_X, half.x), (Vec3::Y, half.y), (Vec3::NEG_Y, half.y)]
        } else {
            // Through the eye.
            [
                (Vec3::new(-1.0, 0.0, -half.x).normalize(), 0.0),
                (Vec3::new(1.0, 0.0, -half.x).normalize(), 0.0),
                (Vec3::new(0.0, -1.0, -half.y).normalize(), 0.0),
                (Vec3::new(0.0, 1.0, -half.y).normalize(), 0.0),
            ]
        };
        let pixels_per_unit = height.max(1) as f32 * 0.5 / half.y;
        Self { view: camera.view_matrix(), planes, near, far, pixels_per_unit, ortho }
    }

    /// The node's error in pixels, or `None` when its sphere is outside the frustum.
    pub(crate) fn error(&self, centre: Vec3, reach: f32, radius: f32) -> Option<f32> {
        let c = self.view.transform_point3(centre);
        let depth = -c.z;
        if depth + reach < self.near
            || depth - reach > self.far
            || self.planes.iter().any(|(n, d)| n.dot(c) + d < -reach)
        {
            return None;
        }
        Some(self.error_anywhere(centre, reach, radius))
    }

    /// The node's error in pixels wherever it is.
    pub(crate) fn error_anywhere(&self, centre: Vec3, reach: f32, radius: f32) -> f32 {
        if self.ortho {
            return radius * self.pixels_per_unit;
        }
        let nearest = self.view.transform_point3(centre).length() - reach;
        if nearest <= self.near { f32::INFINITY } else { radius * self.pixels_per_unit / nearest }
    }

    /// The same, with a node that reaches past the near plane measured at
    /// the near plane rather than refined whatever it costs: a streamed
    /// node's sphere holds its whole cube, which a far camera's near plane
    /// (set by the points' bounds) may cut.
    fn error_at_least_near(&self, centre: Vec3, reach: f32, radius: f32) -> f32 {
        if self.ortho {
            return radius * self.pixels_per_unit;
        }
        let nearest = self.view.transform_point3(centre).length() - reach;
        radius * self.pixels_per_unit / nearest.max(self.near).max(f32::MIN_POSITIVE)
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
    /// A node whose error is below this many pixels is not refined (0: refine
    /// while the budget allows). A streamed file stops near one pixel, so a
    /// far view reads only the top levels.
    pub finest_px: f32,
}

impl SelectOptions {
    /// At most `budget` splats chosen as `choosing` says, refined down to `finest_px`.
    pub fn for_frame(budget: usize, choosing: Choosing, finest_px: f32) -> Self {
        SelectOptions { budget, radius_scale: choosing.radius_scale, cull: choosing.cull, finest_px }
    }
}

/// How a child relates to its parent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refinement {
    /// The children stand in for the parent (the in-memory [`Hierarchy`]:
    /// an inner node holds representatives of its subtree).
    Replace,
    /// The children add points to the parent's (COPC: a node draws with all
    /// its ancestors).
    Add,
}

/// A level-of-detail octree a frame selects from: the in-memory
/// [`Hierarchy`] or a streamed COPC file's hierarchy.
pub trait LodTree {
    fn refinement(&self) -> Refinement;
    /// The root, when the tree has one.
    fn root(&self) -> Option<u32>;
    /// Splats the node itself holds.
    fn count(&self, node: u32) -> usize;
    /// The sphere around the node's splats (centre, radius) and its
    /// coarseness (the largest splat radius, or the point spacing).
    fn sphere(&self, node: u32) -> (Vec3, f32, f32);
    /// Adds the node's children to `out` (none for a leaf, or for a node
    /// whose children are not known yet).
    fn children(&self, node: u32, out: &mut Vec<u32>);
    /// Whether the node is drawn whatever the budget, as the root is
    /// (under [`Refinement::Add`]): each file's root in a forest of several
    /// files' trees, so that no visible file is left out.
    fn always_drawn(&self, _node: u32) -> bool {
        false
    }
}

impl LodTree for Hierarchy {
    fn refinement(&self) -> Refinement {
        Refinement::Replace
    }
    fn root(&self) -> Option<u32> {
        (!self.nodes.is_empty()).then_some(0)
    }
    fn count(&self, node: u32) -> usize {
        self.nodes[node as usize].count as usize
    }
    fn sphere(&self, node: u32) -> (Vec3, f32, f32) {
        let n = &self.nodes[node as usize];
        (n.centre, n.reach, n.radius)
    }
    fn children(&self, node: u32, out: &mut Vec<u32>) {
        let n = &self.nodes[node as usize];
        out.extend(n.children..n.children + n.child_count);
    }
}

/// The nodes to draw from `camera` at `size` (see the module doc).
pub fn select(hierarchy: &Hierarchy, camera: &Camera, size: (u32, u32), options: SelectOptions) -> Selection {
    select_in(hierarchy, camera, size, options)
}

/// The nodes of `tree` to draw from `camera` at `size`: largest error first,
/// while the budget allows. Under [`Refinement::Replace`] a node is refined
/// when all its visible children fit in its place. Under [`Refinement::Add`]
/// a refined node stays drawn (its children add to it), each child is taken
/// on its own while its points fit, and every selected node's ancestors are
/// selected too.
pub fn select_in(tree: &impl LodTree, camera: &Camera, size: (u32, u32), options: SelectOptions) -> Selection {
    let budget = options.budget;
    let frustum = Frustum::new(camera, size);
    let scale = options.radius_scale.max(0.0);
    let additive = tree.refinement() == Refinement::Add;
    let error = |i: u32| {
        let (centre, reach, radius) = tree.sphere(i);
        let reach = reach + (scale - 1.0).max(0.0) * radius;
        let error = match frustum.error(centre, reach, radius * scale) {
            None if !options.cull => Some(frustum.error_anywhere(centre, reach, radius * scale)),
            e => e,
        };
        match error {
            Some(_) if options.finest_px > 0.0 => Some(frustum.error_at_least_near(centre, reach, radius * scale)),
            e => e,
        }
    };
    let mut chosen = Vec::new();
    let mut heap = BinaryHeap::new();
    let Some(root) = tree.root() else { return Selection { nodes: chosen, splats: 0 } };
    let Some(root_error) = error(root) else { return Selection { nodes: chosen, splats: 0 } };
    // Positive floats order as their bits do; the index breaks ties deterministically.
    heap.push((root_error.to_bits(), u32::MAX - root, root));
    let mut candidates = Vec::with_capacity(8);
    if additive {
        // Potree's order: the visible node of largest error next, each child on
        // its own, while its points fit (the root whatever it holds).
        let mut drawn = 0;
        while let Some((error_bits, _, at)) = heap.pop() {
            let count = tree.count(at);
            if at != root && !tree.always_drawn(at) && drawn + count > budget {
                continue;
            }
            drawn += count;
            chosen.push(at);
            candidates.clear();
            if f32::from_bits(error_bits) >= options.finest_px {
                tree.children(at, &mut candidates);
            }
            for &c in &candidates {
                if let Some(e) = error(c) {
                    heap.push((e.to_bits(), u32::MAX - c, c));
                }
            }
        }
        return Selection { nodes: chosen, splats: drawn };
    }
    let mut drawn = tree.count(root);
    let mut children = Vec::with_capacity(8);
    while let Some((error_bits, _, at)) = heap.pop() {
        candidates.clear();
        if f32::from_bits(error_bits) >= options.finest_px {
            tree.children(at, &mut candidates);
        }
        children.clear();
        children.extend(candidates.iter().filter_map(|&c| error(c).map(|e| (e, c))));
        let below: usize = children.iter().map(|&(_, c)| tree.count(c)).sum();
        let after = drawn - tree.count(at) + below;
        if candidates.is_empty() || after > budget {
            chosen.push(at);
        }
        if !candidates.is_empty() && after <= budget {
            drawn = after;
            for &(e, c) in &children {
                heap.push((e.to_bits(), u32::MAX - c, c));
            }
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
        colourless: all.colourless,
        units: all.units.clone(),
        // A frame under a budget draws; picks read the whole cloud's exact positions.
        residuals: Vec::new(),
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
        SelectOptions { budget, radius_scale: 1.0, cull: true, finest_px: 0.0 }
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

    /// A root of 10 points over four children of 5, side by side along x.
    struct Additive;

    impl LodTree for Additive {
        fn refinement(&self) -> Refinement {
            Refinement::Add
        }
        fn root(&self) -> Option<u32> {
            Some(0)
        }
        fn count(&self, node: u32) -> usize {
            if node == 0 { 10 } else { 5 }
        }
        fn sphere(&self, node: u32) -> (Vec3, f32, f32) {
            match node {
                0 => (Vec3::ZERO, 2.0, 0.2),
                c => (Vec3::new(c as f32 - 2.5, 0.0, 0.0), 0.8, 0.1),
            }
        }
        fn children(&self, node: u32, out: &mut Vec<u32>) {
            if node == 0 {
                out.extend(1..5);
            }
        }
    }

    #[test]
    fn additive_refinement_keeps_the_parent_and_takes_each_child_that_fits() {
        let camera = Camera::framing(Vec3::ZERO, 3.0, 1.0);
        let select =
            |budget, finest_px| select_in(&Additive, &camera, (64, 64), SelectOptions { finest_px, ..culled(budget) });
        let all = select(usize::MAX, 0.0);
        assert_eq!((all.nodes.len(), all.splats), (5, 30), "the root and its four children add up");
        let some = select(20, 0.0);
        assert_eq!(some.nodes[0], 0, "the root first");
        assert_eq!((some.nodes.len(), some.splats), (3, 20), "two children fit beside the root: {some:?}");
        let none = select(4, 0.0);
        assert_eq!(none.nodes, vec![0], "the root whatever the budget");
        // Children whose parent's spacing projects below the limit are not read.
        let coarse = select(usize::MAX, 1e6);
        assert_eq!(coarse.nodes, vec![0]);
    }
}

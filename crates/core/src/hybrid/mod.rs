//! Meshes in a scene, and Guennebaud's hybrid point/polygon rendering
//! (SPBG'06 slides, "Hybrid rendering": motivation, transition smoothing,
//! implementation example).
//!
//! A scene object read with `mesh = "x.ply"` or `hybrid = "x.ply"` keeps
//! the file's triangles beside its cloud: the mesh's vertices are the
//! object's splats (normals from the faces, radii from the neighbours, as
//! for any PLY), and each triangle names three of those splats. Modes that
//! draw triangles draw a `mesh` object as its triangles only; a `hybrid`
//! object as triangles where its splats are too large to be efficient, and
//! as splats elsewhere ([`select`]). Modes that cannot draw triangles draw
//! either as its vertex splats, and say so.
//!
//! The slides' implementation keeps "points and polygons in the leaves" of a
//! hierarchy. Here the leaves are the cells of a k-d tree over the
//! triangles' centroids (at most [`LEAF_TRIANGLES`] each): each leaf holds
//! its triangles and the splats only its triangles use. A splat (vertex)
//! shared by triangles of two or more leaves is a *transition splat*: the
//! slides' "transition splats shared by at least one leaf rendered as a set
//! of splats" sample the edges between leaves, and here those edges are
//! sampled at their vertices, which is where the mesh's own splats already
//! are. A leaf drawn as splats thus draws every vertex of its triangles,
//! the same discs that close the surface when the whole object is drawn as
//! splats, so no crack opens between a polygon leaf and a splat leaf; where
//! the two overlap, the splat passes blend the triangles' fragments with the
//! splats' (weight 1, the Gaussian's peak), the slides' "polygons rendering
//! with alpha-blending" transition.

pub mod select;
pub mod subset;

use std::ops::Range;

use glam::Vec3;

use crate::cloud::PointCloud;

/// Most triangles in one leaf.
pub const LEAF_TRIANGLES: usize = 256;

/// How an object with triangles is drawn by modes that draw triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SurfaceKind {
    /// Triangles only (`mesh = "x.ply"`).
    Mesh,
    /// Triangles where splats would be too large, splats elsewhere (`hybrid = "x.ply"`).
    Hybrid,
}

impl SurfaceKind {
    pub fn name(self) -> &'static str {
        match self {
            SurfaceKind::Mesh => "mesh",
            SurfaceKind::Hybrid => "hybrid",
        }
    }
}

/// A leaf of an object's triangles.
#[derive(Debug, Clone, PartialEq)]
pub struct Leaf {
    /// Its triangles, in [`Surface::triangles`].
    pub triangles: Range<u32>,
    /// The splats only its triangles use, in [`Surface::leaf_splats`].
    pub splats: Range<u32>,
}

/// An object's triangles over its splats, in leaves.
#[derive(Debug, Clone, PartialEq)]
pub struct Surface {
    pub kind: SurfaceKind,
    /// Splat indices of the object's cloud, three per triangle, leaf by leaf.
    pub triangles: Vec<[u32; 3]>,
    pub leaves: Vec<Leaf>,
    /// Splats used by one leaf's triangles only, leaf by leaf.
    pub leaf_splats: Vec<u32>,
    /// Splats used by triangles of several leaves, and those leaves
    /// (`transition_leaves[k]` ranges over [`Surface::leaf_lists`]).
    pub transition: Vec<u32>,
    pub transition_leaves: Vec<Range<u32>>,
    pub leaf_lists: Vec<u32>,
}

impl Surface {
    /// The leaves of `triangles` (splat indices of `cloud`, each checked by the caller).
    pub fn build(kind: SurfaceKind, cloud: &PointCloud, triangles: Vec<[u32; 3]>) -> Self {
        let centroids: Vec<Vec3> =
            triangles.iter().map(|t| t.iter().map(|&i| cloud.positions[i as usize]).sum::<Vec3>() / 3.0).collect();
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let mut ranges = Vec::new();
        split(&centroids, &mut order, 0, &mut ranges);
        let sorted: Vec<[u32; 3]> = order.iter().map(|&t| triangles[t as usize]).collect();
        // Which leaves use each splat: one (kept in that leaf), or several (a transition splat).
        let mut owner = vec![u32::MAX; cloud.len()];
        let mut shared: std::collections::HashMap<u32, Vec<u32>> = std::collections::HashMap::new();
        for (leaf, range) in ranges.iter().enumerate() {
            let leaf = leaf as u32;
            for t in &sorted[range.start as usize..range.end as usize] {
                for &v in t {
                    let o = &mut owner[v as usize];
                    if *o == u32::MAX {
                        *o = leaf;
                    } else if *o != leaf {
                        let list = shared.entry(v).or_insert_with(|| vec![*o]);
                        if !list.contains(&leaf) {
                            list.push(leaf);
                        }
                    }
                }
            }
        }
        let mut per_leaf: Vec<Vec<u32>> = vec![Vec::new(); ranges.len()];
        for (v, &o) in owner.iter().enumerate() {
            if o != u32::MAX && !shared.contains_key(&(v as u32)) {
                per_leaf[o as usize].push(v as u32);
            }
        }
        let mut leaf_splats = Vec::new();
        let leaves = ranges
            .into_iter()
            .zip(per_leaf)
            .map(|(triangles, splats)| {
                let start = leaf_splats.len() as u32;
                leaf_splats.extend(splats);
                Leaf { triangles, splats: start..leaf_splats.len() as u32 }
            })
            .collect();
        let mut transition: Vec<u32> = shared.keys().copied().collect();
        transition.sort_unstable();
        let mut leaf_lists = Vec::new();
        let transition_leaves = transition
            .iter()
            .map(|v| {
                let start = leaf_lists.len() as u32;
                leaf_lists.extend(&shared[v]);
                start..leaf_lists.len() as u32
            })
            .collect();
        Surface { kind, triangles: sorted, leaves, leaf_splats, transition, transition_leaves, leaf_lists }
    }
}

/// Splits `order[..]` (triangle indices, by centroid) at the median of the
/// longest axis until at most [`LEAF_TRIANGLES`] remain, appending each
/// leaf's range (offset by `start`) to `leaves`.
fn split(centroids: &[Vec3], order: &mut [u32], start: u32, leaves: &mut Vec<Range<u32>>) {
    if order.len() <= LEAF_TRIANGLES {
        if !order.is_empty() {
            leaves.push(start..start + order.len() as u32);
        }
        return;
    }
    let (lo, hi) = order.iter().fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), &t| {
        (lo.min(centroids[t as usize]), hi.max(centroids[t as usize]))
    });
    let extent = hi - lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let middle = order.len() / 2;
    order.select_nth_unstable_by(middle, |&a, &b| centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis]));
    let (left, right) = order.split_at_mut(middle);
    split(centroids, left, start, leaves);
    split(centroids, right, start + middle as u32, leaves);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of n×n quads in the plane z = 0, two triangles each.
    pub(crate) fn grid(n: u32) -> (PointCloud, Vec<[u32; 3]>) {
        let side = n + 1;
        let mut cloud = PointCloud::default();
        for y in 0..side {
            for x in 0..side {
                cloud.positions.push(Vec3::new(x as f32, y as f32, 0.0));
                cloud.normals.push(Vec3::Z);
                cloud.radii.push(0.75);
                cloud.colours.push([200; 3]);
                cloud.opacity.push(1.0);
            }
        }
        let mut triangles = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let a = y * side + x;
                triangles.push([a, a + 1, a + side + 1]);
                triangles.push([a, a + side + 1, a + side]);
            }
        }
        (cloud, triangles)
    }

    #[test]
    fn every_triangle_is_in_one_leaf_and_every_used_splat_in_its_leaf_or_the_transition() {
        let (cloud, triangles) = grid(40);
        let surface = Surface::build(SurfaceKind::Hybrid, &cloud, triangles.clone());
        assert!(surface.leaves.len() >= 3200 / LEAF_TRIANGLES);
        assert!(surface.leaves.iter().all(|l| l.triangles.len() <= LEAF_TRIANGLES));
        let mut sorted = surface.triangles.clone();
        let mut original = triangles;
        sorted.sort_unstable();
        original.sort_unstable();
        assert_eq!(sorted, original);
        let mut splats: Vec<u32> = surface.leaf_splats.iter().chain(&surface.transition).copied().collect();
        splats.sort_unstable();
        assert_eq!(splats, (0..cloud.len() as u32).collect::<Vec<_>>(), "each splat once");
        // A transition splat is used by triangles of each of its leaves, and of no other.
        for (k, &v) in surface.transition.iter().enumerate() {
            let listed = &surface.leaf_lists[surface.transition_leaves[k].start as usize..]
                [..surface.transition_leaves[k].len()];
            assert!(listed.len() >= 2);
            for (l, leaf) in surface.leaves.iter().enumerate() {
                let uses = surface.triangles[leaf.triangles.start as usize..leaf.triangles.end as usize]
                    .iter()
                    .any(|t| t.contains(&v));
                assert_eq!(uses, listed.contains(&(l as u32)), "splat {v}, leaf {l}");
            }
        }
    }
}

//! Per frame, which leaves of a scene's meshes are drawn as triangles and
//! which splats are drawn (Guennebaud's hybrid rendering rules):
//!
//! - the polygons of every visible leaf that is not dense enough: its
//!   largest splat, projected at the leaf's nearest point to the eye, is
//!   wider than `pixels` (in radius), so splats would be less efficient and
//!   less exact than its triangles;
//! - the splats of every other visible leaf, with the transition splats
//!   shared by at least one leaf drawn as splats;
//! - a `mesh` object's leaves always as triangles; every splat of an object
//!   without triangles, and every splat no triangle uses, as splats.
//!
//! Everything is in the flattened scene's frame ([`crate::scene::Scene::flatten`]):
//! an object's splat i is the flattened splat `offset + i`.

use std::ops::Range;
use std::sync::Arc;

use glam::Vec3;

use super::{Surface, SurfaceKind};
use crate::cloud::PointCloud;
use crate::frame::Camera;
use crate::lod::select::Frustum;

/// Splat radius, in pixels, above which a hybrid leaf is drawn as triangles by default.
pub use crate::frame::settings::DEFAULT_HYBRID_PIXELS as DEFAULT_PIXELS;

/// One object's triangles in a flattened scene.
#[derive(Debug, Clone)]
pub struct ObjectSurface {
    pub surface: Arc<Surface>,
    /// The object's first splat in the flattened cloud.
    pub offset: u32,
    /// Its first triangle in [`SceneSurfaces::triangles`].
    pub first_triangle: u32,
    /// Per leaf, in the flattened frame: the bounding sphere's centre and
    /// radius, and the largest radius of the leaf's splats.
    pub bounds: Vec<(Vec3, f32, f32)>,
}

/// The triangles of a flattened scene, object by object, leaf by leaf.
#[derive(Debug, Clone, Default)]
pub struct SceneSurfaces {
    pub objects: Vec<ObjectSurface>,
    /// Per flattened splat: drawn whatever a frame chooses (of an object
    /// without triangles, or used by no triangle).
    loose: Vec<bool>,
}

/// How a frame chooses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HybridOptions {
    /// Splat radius in pixels above which a hybrid leaf is drawn as triangles.
    pub pixels: f32,
    /// The factor on every splat radius the frame draws with.
    pub radius_scale: f32,
    /// Leave out leaves outside the view.
    pub cull: bool,
}

/// What a frame draws.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HybridSelection {
    /// Triangles drawn, as ranges of [`SceneSurfaces::triangles`] (adjacent ones merged).
    pub triangles: Vec<Range<u32>>,
    /// Flattened splats drawn, ascending.
    pub splats: Vec<u32>,
    /// Leaves drawn as triangles, leaves drawn as splats, and the transition splats drawn.
    pub triangle_leaves: usize,
    pub splat_leaves: usize,
    pub transition_splats: usize,
}

impl HybridSelection {
    pub fn triangle_count(&self) -> u32 {
        self.triangles.iter().map(|r| r.len() as u32).sum()
    }

    /// The selected splats of the flattened `cloud`, as a cloud of their own.
    pub fn gather(&self, cloud: &PointCloud) -> PointCloud {
        cloud.select(&self.splats)
    }
}

impl SceneSurfaces {
    /// The surfaces of `surfaces` (each an object's, with the object's
    /// first splat) in the flattened `cloud`.
    pub fn new(cloud: &PointCloud, surfaces: impl IntoIterator<Item = (Arc<Surface>, u32)>) -> Self {
        let mut first_triangle = 0;
        let objects = surfaces
            .into_iter()
            .map(|(surface, offset)| {
                let bounds = surface
                    .leaves
                    .iter()
                    .map(|leaf| {
                        let vertices = || {
                            surface.triangles[leaf.triangles.start as usize..leaf.triangles.end as usize]
                                .iter()
                                .flatten()
                                .map(|&v| (v + offset) as usize)
                        };
                        let (lo, hi) = vertices().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), v| {
                            (lo.min(cloud.positions[v]), hi.max(cloud.positions[v]))
                        });
                        let centre = (lo + hi) * 0.5;
                        let largest = vertices().map(|v| cloud.radii[v]).fold(0.0, f32::max);
                        (centre, (hi - lo).length() * 0.5, largest)
                    })
                    .collect();
                let object = ObjectSurface { surface: Arc::clone(&surface), offset, first_triangle, bounds };
                first_triangle += surface.triangles.len() as u32;
                object
            })
            .collect::<Vec<ObjectSurface>>();
        let mut loose = vec![true; cloud.len()];
        for o in &objects {
            for &v in o.surface.triangles.iter().flatten() {
                loose[(v + o.offset) as usize] = false;
            }
        }
        Self { objects, loose }
    }

    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// Every triangle, as flattened splat indices, in drawing order.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.objects.iter().flat_map(|o| o.surface.triangles.iter().map(move |t| t.map(|v| v + o.offset)))
    }

    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.surface.triangles.len()).sum()
    }

    /// Per flattened splat, whether a mode draws it beside every triangle:
    /// those of objects without triangles and those no triangle uses.
    pub fn loose_splats(&self) -> &[bool] {
        &self.loose
    }

    /// What a frame from `camera` at `size` draws of the flattened scene.
    pub fn select(&self, camera: &Camera, size: (u32, u32), options: HybridOptions) -> HybridSelection {
        let frustum = Frustum::new(camera, size);
        let mut drawn = self.loose.clone();
        let mut out = HybridSelection::default();
        for o in &self.objects {
            let s = &o.surface;
            // Per leaf: None (outside the view), Some(true) as triangles, Some(false) as splats.
            let modes: Vec<Option<bool>> = o
                .bounds
                .iter()
                .map(|&(centre, reach, largest)| {
                    let radius = largest * options.radius_scale;
                    let error = match options.cull {
                        true => frustum.error(centre, reach, radius)?,
                        false => frustum.error_anywhere(centre, reach, radius),
                    };
                    Some(s.kind == SurfaceKind::Mesh || error > options.pixels)
                })
                .collect();
            for (leaf, mode) in s.leaves.iter().zip(&modes) {
                match mode {
                    Some(true) => {
                        out.triangle_leaves += 1;
                        let range = leaf.triangles.start + o.first_triangle..leaf.triangles.end + o.first_triangle;
                        match out.triangles.last_mut() {
                            Some(last) if last.end == range.start => last.end = range.end,
                            _ => out.triangles.push(range),
                        }
                    }
                    Some(false) => {
                        out.splat_leaves += 1;
                        for &v in &s.leaf_splats[leaf.splats.start as usize..leaf.splats.end as usize] {
                            drawn[(v + o.offset) as usize] = true;
                        }
                    }
                    None => {}
                }
            }
            for (k, &v) in s.transition.iter().enumerate() {
                let leaves = &s.leaf_lists[s.transition_leaves[k].start as usize..s.transition_leaves[k].end as usize];
                if leaves.iter().any(|&l| modes[l as usize] == Some(false)) {
                    drawn[(v + o.offset) as usize] = true;
                    out.transition_splats += 1;
                }
            }
        }
        out.splats = (0..drawn.len() as u32).filter(|&v| drawn[v as usize]).collect();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hybrid::tests::grid;

    fn camera_over(centre: Vec3, distance: f32) -> Camera {
        let mut camera = Camera::framing(centre, 100.0, 1.0);
        camera.target = centre;
        camera.distance = distance;
        camera.look_from_direction(Vec3::Z);
        camera
    }

    #[test]
    fn near_leaves_are_triangles_far_ones_splats_and_every_triangle_of_a_splat_leaf_keeps_its_vertices() {
        let (cloud, triangles) = grid(60);
        let surface = Arc::new(Surface::build(SurfaceKind::Hybrid, &cloud, triangles));
        let scene = SceneSurfaces::new(&cloud, [(Arc::clone(&surface), 0)]);
        let options = HybridOptions { pixels: DEFAULT_PIXELS, radius_scale: 1.0, cull: false };
        let far = scene.select(&camera_over(Vec3::new(30.0, 30.0, 0.0), 2000.0), (256, 256), options);
        assert_eq!((far.triangle_leaves, far.splats.len()), (0, cloud.len()), "far away: splats only");
        let near = scene.select(&camera_over(Vec3::new(30.0, 30.0, 0.0), 20.0), (256, 256), options);
        assert!(near.splat_leaves == 0 && near.splats.is_empty(), "close: triangles only, {near:?}");
        assert_eq!(near.triangle_count() as usize, surface.triangles.len());
        // A grazing view from one corner: both kinds, and no triangle left without a cover.
        let mut camera = camera_over(Vec3::ZERO, 8.0);
        camera.look_from_direction(Vec3::new(-1.0, -1.0, 0.6).normalize());
        let mixed = scene.select(&camera, (256, 256), HybridOptions { pixels: 10.0, ..options });
        assert!(mixed.triangle_leaves > 0 && mixed.splat_leaves > 0, "{mixed:?}");
        let drawn_triangle = |t: u32| mixed.triangles.iter().any(|r| r.contains(&t));
        for (t, tri) in scene.triangles().enumerate() {
            let covered = drawn_triangle(t as u32) || tri.iter().all(|v| mixed.splats.binary_search(v).is_ok());
            assert!(covered, "triangle {t} is neither drawn nor covered by its vertices' splats");
        }
    }

    #[test]
    fn an_object_after_others_indexes_its_own_splats() {
        // 100 splats of another object first, then the mesh's.
        let (mesh, triangles) = grid(10);
        let surface = Arc::new(Surface::build(SurfaceKind::Hybrid, &mesh, triangles));
        let mut cloud = mesh.clone();
        for list in [&mut cloud.positions, &mut cloud.normals] {
            list.splice(0..0, std::iter::repeat_n(Vec3::new(-50.0, 0.0, 0.0), 100));
        }
        cloud.radii.splice(0..0, std::iter::repeat_n(1.0, 100));
        cloud.colours.splice(0..0, std::iter::repeat_n([9; 3], 100));
        cloud.opacity.splice(0..0, std::iter::repeat_n(1.0, 100));
        let scene = SceneSurfaces::new(&cloud, [(Arc::clone(&surface), 100)]);
        assert!(scene.triangles().flatten().all(|v| (100..cloud.len() as u32).contains(&v)));
        let camera = camera_over(Vec3::new(5.0, 5.0, 0.0), 20.0);
        let triangles_only = HybridOptions { pixels: 0.0, radius_scale: 1.0, cull: false };
        let all = scene.select(&camera, (256, 256), triangles_only);
        assert_eq!(all.splats, (0..100).collect::<Vec<u32>>(), "the other object's splats, and none of the mesh's");
        let splats_only = HybridOptions { pixels: f32::INFINITY, ..triangles_only };
        let none = scene.select(&camera, (256, 256), splats_only);
        assert_eq!(none.splats, (0..cloud.len() as u32).collect::<Vec<u32>>());
        assert!(none.triangles.is_empty());
    }
}

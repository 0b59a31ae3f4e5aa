//! Which way the estimated normals of a file held whole face, decided once
//! for the whole file ([`FileFacing`]), so that the nodes, each estimated on
//! its own, agree across their borders. A file loaded whole decides per
//! connected piece after estimating every point (`cloud::estimate`): towards
//! the scanner when the file's origin lies outside the cloud and sees almost
//! every point from the front, else outwards; airborne and geo-referenced
//! terrain face up. Here the same rule runs once, on the root node: a
//! subsample of the whole file spread over all of it (one point per cell of
//! a 128³ grid), so it sees the file's extent and its single view as the
//! whole file does.

use glam::{DVec3, Vec3};

use super::node_estimates::FileFacing;
use super::octree::Cube;
use crate::cloud::estimate::{self, EstimateOptions};
use crate::cloud::las_file::Columns;
use crate::cloud::{FileInfo, PointCloud};

/// How the normals estimated for a file's nodes face: `root` indexes the
/// root node's points in `columns`, `cube` is the tree's.
pub(super) fn of_file(columns: &Columns, root: &[u32], cube: &Cube, info: &FileInfo) -> FileFacing {
    if info.from_above || is_geo_terrain(cube) {
        return FileFacing::Up;
    }
    let at = |i: u32| DVec3::new(columns.x[i as usize], columns.y[i as usize], columns.z[i as usize]);
    let positions: Vec<Vec3> = root.iter().map(|&i| (at(i) - cube.centre).as_vec3()).collect();
    let n = positions.len();
    let mut cloud = PointCloud { positions, normals: vec![Vec3::ZERO; n], radii: vec![0.0; n], ..Default::default() };
    let needs = vec![true; n];
    let file_origin = (-cube.centre).as_vec3();
    let done = estimate::complete(&mut cloud, &needs, &needs, file_origin, &EstimateOptions::default(), false);
    match done.scanner_position {
        Some(_) => FileFacing::Towards(DVec3::ZERO),
        None => {
            let centroid = cloud.positions.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / n.max(1) as f64;
            FileFacing::AwayFrom(cube.centre + centroid)
        }
    }
}

/// Geo-referenced terrain, as a file loaded whole takes it: far from the
/// origin (more than 10 km) and flatter than half its width.
fn is_geo_terrain(cube: &Cube) -> bool {
    let size = cube.hi - cube.lo;
    let far = cube.centre.x.abs().max(cube.centre.y.abs()) > 1e4;
    far && size.z < 0.5 * size.x.max(size.y)
}

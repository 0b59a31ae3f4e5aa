//! Estimating what a file lacks: normals (PCA + consistent orientation) and radii.
//!
//! Normals: the eigenvector of the smallest eigenvalue of the covariance of
//! each point's k nearest neighbours ([`super::eigen`]). Their signs are made
//! consistent by propagating along a minimum spanning tree of the neighbour
//! graph, with edge cost 1 - |n_i . n_j| (Hoppe et al. 1992), so orientation
//! never flips across a smooth surface. Each connected piece then gets its
//! global sign: towards the scanner when the file's origin lies outside the
//! cloud and sees (almost) every point from the front, as in a single-view
//! scan; otherwise outwards, away from the cloud's centre. Airborne scans
//! (LAS/LAZ, and geo-referenced terrain) have no scanner position to face:
//! their normals face up (+z), each on its own, with no tree to propagate
//! along ([`EstimateOptions::orient_up`]).
//!
//! Radii: a multiple of the mean distance to the k nearest neighbours, so
//! neighbouring splats overlap and cover the surface; outliers are clamped
//! to a multiple of the median.

use glam::Vec3;
use rayon::prelude::*;

use super::PointCloud;
use super::eigen::{covariance, smallest_eigenvector};
use crate::spatial::knn::{self, Neighbours};

/// Radii are clamped to this multiple of the median radius.
pub const MAX_RADIUS_OVER_MEDIAN: f32 = 6.0;

/// Share of points that must face the file origin to call the cloud a single-view scan.
const SCANNER_FACING_SHARE: f32 = 0.8;

#[derive(Debug, Clone)]
pub struct EstimateOptions {
    /// Neighbours used for the PCA normal.
    pub normal_neighbours: usize,
    /// Neighbours whose mean distance sets the radius.
    pub radius_neighbours: usize,
    /// Radius = this x mean neighbour distance.
    pub radius_scale: f32,
    /// Turn every estimated normal to face up (+z) rather than propagate signs
    /// along the neighbour graph: for airborne scans, seen from above.
    pub orient_up: bool,
}

impl Default for EstimateOptions {
    fn default() -> Self {
        Self { normal_neighbours: 16, radius_neighbours: 8, radius_scale: 1.1, orient_up: false }
    }
}

/// How the signs of estimated normals are chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Facing {
    /// Each faces up (+z), on its own: airborne scans, seen from above.
    Up,
    /// Towards the scanner at this point when the cloud is a single view of
    /// it, else each connected piece outwards, away from the cloud's centre
    /// (a file loaded whole: the file's origin after re-centring).
    Auto(Vec3),
    /// Each towards this point, on its own: a single-view scan's scanner.
    Towards(Vec3),
    /// Each connected piece away from this point: an object scanned all
    /// round, seen whole from outside.
    AwayFrom(Vec3),
}

/// What [`complete`] did beyond filling the gaps.
#[derive(Debug, Default)]
pub struct Estimated {
    pub isolated_points: usize,
    pub clamped_radii: usize,
    pub scanner_position: Option<Vec3>,
    /// Set when the points lie on a line: the normal every estimated splat got.
    pub line_normal: Option<Vec3>,
}

/// Fills the normals and radii marked as needed, in place.
///
/// `file_origin` is the file's coordinate origin after re-centring: the
/// sensor position when the cloud is a single-view scan.
pub fn complete(
    cloud: &mut PointCloud,
    needs_normal: &[bool],
    needs_radius: &[bool],
    file_origin: Vec3,
    options: &EstimateOptions,
    progress: bool,
) -> Estimated {
    let facing = if options.orient_up { Facing::Up } else { Facing::Auto(file_origin) };
    complete_first(cloud, cloud.len(), (needs_normal, needs_radius), facing, options, progress)
}

/// The normals and radii of a node's `own` points, estimated with the
/// points of the nodes around it (`halo`) as neighbours too, so that a
/// point at the node's border sees the surface on both sides of it (no
/// seam). Positions are relative to any point near the node (the node's
/// centre keeps f32 exact); the halo's own normals and radii are not made.
/// `facing` is decided once for the whole file (in the same frame as the
/// positions), so that the nodes' signs agree across their borders.
pub fn estimate_node(own: &[Vec3], halo: &[Vec3], options: &EstimateOptions, facing: Facing) -> (Vec<Vec3>, Vec<f32>) {
    let (n, all) = (own.len(), own.len() + halo.len());
    let mut cloud = PointCloud {
        positions: [own, halo].concat(),
        normals: vec![Vec3::ZERO; all],
        radii: vec![0.0; all],
        ..Default::default()
    };
    let needs: Vec<bool> = (0..all).map(|i| i < n).collect();
    complete_first(&mut cloud, n, (&needs, &needs), facing, options, false);
    cloud.normals.truncate(n);
    cloud.radii.truncate(n);
    (cloud.normals, cloud.radii)
}

/// [`complete`] for the first `queries` splats: those after them are only
/// neighbours (their needs are false).
fn complete_first(
    cloud: &mut PointCloud,
    queries: usize,
    (needs_normal, needs_radius): (&[bool], &[bool]),
    facing: Facing,
    options: &EstimateOptions,
    progress: bool,
) -> Estimated {
    let mut out = Estimated::default();
    let any_normal = needs_normal.iter().any(|&b| b);
    let any_radius = needs_radius.iter().any(|&b| b);
    if any_normal || any_radius {
        let k = options.normal_neighbours.max(options.radius_neighbours).max(3);
        let bar = crate::progress::bar(cloud.len() as u64, "finding neighbours", progress);
        let tick = |n: u64| bar.inc(n);
        let started = std::time::Instant::now();
        let neighbours = knn::k_nearest_of_first(&cloud.positions, queries, k, &tick);
        bar.finish();
        log::debug!("{} nearest neighbours of {} points: {:.3} s", k, cloud.len(), started.elapsed().as_secs_f64());
        // Each point's radius before clamping, when the normals' pass made them.
        let mut raw_radii = None;
        if any_normal {
            match line_direction(&cloud.positions) {
                // A line has no surface normal: face the splats across the line, towards the front view (+z).
                Some(direction) => {
                    let normal = across(direction, Vec3::Z).or_else(|| across(direction, Vec3::X)).unwrap_or(Vec3::Z);
                    for (n, _) in cloud.normals.iter_mut().zip(needs_normal).filter(|(_, needed)| **needed) {
                        *n = normal;
                    }
                    out.line_normal = Some(normal);
                }
                None => {
                    let started = std::time::Instant::now();
                    let radii = any_radius.then(|| (radius_neighbours(options, neighbours.k), options.radius_scale));
                    raw_radii = estimate_normals(cloud, &neighbours, needs_normal, options.normal_neighbours, radii);
                    log::debug!("normals: {:.3} s", started.elapsed().as_secs_f64());
                    let started = std::time::Instant::now();
                    match facing {
                        Facing::Up => face_up(cloud, needs_normal),
                        facing => orient_normals(cloud, &neighbours, needs_normal, facing),
                    }
                    log::debug!("orientation: {:.3} s", started.elapsed().as_secs_f64());
                }
            }
        }
        if any_radius {
            let (isolated, clamped) = estimate_radii(cloud, &neighbours, needs_radius, options, raw_radii);
            out.isolated_points = isolated;
            out.clamped_radii = clamped;
        }
    }
    if let Facing::Auto(file_origin) = facing {
        out.scanner_position = scanner_position(cloud, file_origin);
    }
    out
}

/// The direction of the line all `points` lie on (within 1e-6 of their
/// extent), or `None` when they span a surface or a volume (or coincide).
pub fn line_direction(points: &[Vec3]) -> Option<Vec3> {
    let first = *points.first()?;
    let far = points.iter().copied().max_by(|a, b| a.distance_squared(first).total_cmp(&b.distance_squared(first)))?;
    let length = far.distance(first);
    let direction = (far - first).try_normalize()?;
    let off_line = points.iter().map(|p| (*p - first).reject_from_normalized(direction).length()).fold(0.0, f32::max);
    (off_line <= 1e-6 * length).then_some(direction)
}

/// The unit part of `towards` perpendicular to unit `direction`, if any.
fn across(direction: Vec3, towards: Vec3) -> Option<Vec3> {
    (towards - direction * direction.dot(towards)).try_normalize().filter(|n| n.dot(towards) > 1e-3)
}

/// Points a neighbourhood's covariance is gathered for on the stack (itself
/// and up to 63 neighbours); a larger one is gathered on the heap.
const STACK_NEIGHBOURHOOD: usize = 64;

/// The normals of the points `needed`, from their `k` nearest; and, with
/// `radii` (neighbours, scale), every point's radius before clamping
/// ([`raw_radius`]) from the same rows while they are read (a pass of its
/// own read every row and neighbour again).
fn estimate_normals(
    cloud: &mut PointCloud,
    nb: &Neighbours,
    needed: &[bool],
    k: usize,
    radii: Option<(usize, f32)>,
) -> Option<Vec<f32>> {
    let positions = &cloud.positions;
    let k = k.min(nb.k);
    let residuals = &cloud.residuals;
    let estimated = nb.map_rows(|i, around| {
        let radius = radii.map_or(0.0, |(kr, scale)| raw_radius(positions, i, &around[..kr], scale));
        if !needed[i] {
            return (None, radius);
        }
        let around = &around[..k];
        // Each neighbour is read once, into this list (itself first), and
        // the centre and covariance are made from it.
        let mut stack = [Vec3::ZERO; STACK_NEIGHBOURHOOD];
        let mut heap = Vec::new();
        let points: &mut [Vec3] = if k < STACK_NEIGHBOURHOOD {
            &mut stack[..k + 1]
        } else {
            heap.resize(k + 1, Vec3::ZERO);
            &mut heap
        };
        let centre = if !residuals.is_empty() {
            // Far from the origin f32 positions are millimetres coarse: the
            // neighbourhood is taken relative to splat i (a difference of
            // close f32 values is exact) with what f32 lost added back.
            for (slot, &j) in points[1..].iter_mut().zip(around) {
                let j = j as usize;
                *slot = (positions[j] - positions[i]) + (residuals[j] - residuals[i]);
            }
            points[1..].iter().sum::<Vec3>() / (k + 1) as f32
        } else {
            points[0] = positions[i];
            for (slot, &j) in points[1..].iter_mut().zip(around) {
                *slot = positions[j as usize];
            }
            (points[0] + points[1..].iter().sum::<Vec3>()) / (k + 1) as f32
        };
        (Some(smallest_eigenvector(covariance(points, centre)).unwrap_or(Vec3::Z)), radius)
    });
    for (n, (estimated, _)) in cloud.normals.iter_mut().zip(&estimated) {
        if let Some(estimated) = estimated {
            *n = *estimated;
        }
    }
    radii.map(|_| estimated.into_iter().map(|(_, radius)| radius).collect())
}

/// Makes estimated normal signs consistent (MST propagation), then picks each
/// connected piece's sign as `facing` says. Normals read from the file are
/// never flipped; they seed the propagation instead.
fn orient_normals(cloud: &mut PointCloud, nb: &Neighbours, estimated: &[bool], facing: Facing) {
    // Only the points with rows (a node's halo has none) take part.
    let n = nb.rows();
    let normals = &mut cloud.normals;
    let positions = &cloud.positions;
    let centre = match facing {
        Facing::AwayFrom(centre) => centre,
        _ => positions[..n].iter().sum::<Vec3>() / n.max(1) as f32,
    };
    let tree = spanning_forest(normals, nb, nb.k.min(8));
    let mut component = vec![u32::MAX; n];
    let mut pieces: Vec<Vec<u32>> = Vec::new();
    // Seeds: first the points whose normals came from the file (they fix the sign).
    let seeds = (0..n).filter(|&i| !estimated[i]).chain((0..n).filter(|&i| estimated[i]));
    for seed in seeds {
        if component[seed] != u32::MAX {
            continue;
        }
        let id = pieces.len() as u32;
        component[seed] = id;
        let mut members = vec![seed as u32];
        let mut at = 0;
        // Breadth first along the tree: each estimated normal takes its parent's side.
        while let Some(&node) = members.get(at) {
            at += 1;
            let node = node as usize;
            for &j in &tree.1[tree.0[node]..tree.0[node + 1]] {
                let j = j as usize;
                if component[j] == u32::MAX {
                    component[j] = id;
                    if estimated[j] && normals[j].dot(normals[node]) < 0.0 {
                        normals[j] = -normals[j];
                    }
                    members.push(j as u32);
                }
            }
        }
        pieces.push(members);
    }

    // Global sign: towards the scanner for a single view, else each piece outwards.
    let scanner = match facing {
        Facing::Auto(file_origin) => {
            let outside = !bounds_contain(&positions[..n], file_origin, 0.1);
            let facing: Vec<f32> = pieces
                .iter()
                .map(|m| {
                    m.iter().map(|&i| (normals[i as usize].dot(file_origin - positions[i as usize])).signum()).sum()
                })
                .collect();
            let total_facing: f32 = facing.iter().map(|f| f.abs()).sum();
            (outside && total_facing >= SCANNER_FACING_SHARE * n as f32).then_some(file_origin)
        }
        Facing::Towards(scanner) => Some(scanner),
        Facing::Up | Facing::AwayFrom(_) => None,
    };
    if let Some(file_origin) = scanner {
        // Every point of a single view was seen from the scanner, so each
        // normal faces it; per point is more robust than per piece on noisy
        // (e.g. stereo) surfaces, where propagation can leave flipped patches.
        for i in (0..n).filter(|&i| estimated[i]) {
            if normals[i].dot(file_origin - positions[i]) < 0.0 {
                normals[i] = -normals[i];
            }
        }
        return;
    }
    for members in &pieces {
        if members.iter().any(|&i| !estimated[i as usize]) {
            continue;
        }
        let outward: f32 = members.iter().map(|&i| normals[i as usize].dot(positions[i as usize] - centre)).sum();
        let flip = outward < 0.0;
        if flip {
            for &i in members {
                normals[i as usize] = -normals[i as usize];
            }
        }
    }
}

/// The minimum spanning forest of the graph joining each point with a row
/// to its `k` nearest neighbours with a row, with edge cost 1 - |n_i . n_j|
/// quantised to 1e-6 (Hoppe et al.'s Riemannian graph), as a CSR: the tree
/// neighbours of point i are `.1[.0[i]...0[i + 1]]`.
///
/// Kruskal's: the edges sorted in parallel, then joined cheapest first
/// through a union-find. Prim's from each seed with a binary heap took
/// 0.63 s of the merged bunny's (362K points) 0.99 s load, on one thread.
/// Among edges of equal cost the lower point indices come first, so the
/// forest is the same on every run.
fn spanning_forest(normals: &[Vec3], nb: &Neighbours, k: usize) -> (Vec<usize>, Vec<u32>) {
    let n = nb.rows();
    let cost = |i: usize, j: usize| ((1.0 - normals[i].dot(normals[j]).abs()).clamp(0.0, 1.0) * 1e6) as u32;
    let mut edges: Vec<(u32, u32, u32)> = (0..n)
        .into_par_iter()
        .flat_map_iter(|i| {
            nb.of(i)[..k].iter().map(|&j| j as usize).filter(move |&j| j != i && j < n).map(move |j| {
                let (a, b) = (i.min(j), i.max(j));
                (cost(a, b), a as u32, b as u32)
            })
        })
        .collect();
    edges.par_sort_unstable();
    let mut root: Vec<u32> = (0..n as u32).collect();
    let find = |root: &mut Vec<u32>, mut i: u32| {
        while root[i as usize] != i {
            let up = root[root[i as usize] as usize];
            root[i as usize] = up;
            i = up;
        }
        i
    };
    let mut degree = vec![0usize; n + 1];
    edges.retain(|&(_, i, j)| {
        let (a, b) = (find(&mut root, i), find(&mut root, j));
        if a == b {
            return false;
        }
        root[a.max(b) as usize] = a.min(b);
        degree[i as usize] += 1;
        degree[j as usize] += 1;
        true
    });
    let mut tree_start = vec![0usize; n + 1];
    for i in 0..n {
        tree_start[i + 1] = tree_start[i] + degree[i];
    }
    let mut fill = tree_start.clone();
    let mut tree = vec![0u32; tree_start[n]];
    for &(_, i, j) in &edges {
        tree[fill[i as usize]] = j;
        fill[i as usize] += 1;
        tree[fill[j as usize]] = i;
        fill[j as usize] += 1;
    }
    (tree_start, tree)
}

/// The file origin, if the cloud looks like a single-view scan taken from it.
/// Turns every estimated normal to face up (+z); a vertical one (a wall) is left as the PCA gave it.
fn face_up(cloud: &mut PointCloud, estimated: &[bool]) {
    cloud.normals.par_iter_mut().zip(estimated).filter(|(n, e)| **e && n.z < 0.0).for_each(|(n, _)| *n = -*n);
}

fn scanner_position(cloud: &PointCloud, file_origin: Vec3) -> Option<Vec3> {
    if cloud.is_empty() || bounds_contain(&cloud.positions, file_origin, 0.1) {
        return None;
    }
    let facing = cloud.positions.par_iter().zip(&cloud.normals).filter(|(p, n)| n.dot(file_origin - **p) > 0.0).count();
    (facing as f32 >= SCANNER_FACING_SHARE * cloud.len() as f32).then_some(file_origin)
}

/// Whether `p` lies in the bounding box of `points` grown by `margin` of its size.
fn bounds_contain(points: &[Vec3], p: Vec3, margin: f32) -> bool {
    let Some(first) = points.first() else { return false };
    let (lo, hi) = points.iter().fold((*first, *first), |(lo, hi), q| (lo.min(*q), hi.max(*q)));
    let grow = (hi - lo) * margin;
    p.cmpge(lo - grow).all() && p.cmple(hi + grow).all()
}

/// The median of the positive, finite `radii` (`None` when there is none).
pub fn median_radius(radii: &[f32]) -> Option<f32> {
    let mut sorted: Vec<f32> = radii.iter().copied().filter(|&r| r > 0.0 && r.is_finite()).collect();
    let mid = sorted.len() / 2;
    (!sorted.is_empty()).then(|| *sorted.select_nth_unstable_by(mid, f32::total_cmp).1)
}

/// Neighbours whose mean distance sets a radius, of rows of `k`.
fn radius_neighbours(options: &EstimateOptions, k: usize) -> usize {
    options.radius_neighbours.min(k).max(1)
}

/// Point i's radius before clamping: `scale` × the mean distance to the
/// neighbours `around` that are not at its place (the distances the search
/// measured: f32 positions, as it reads them); 0 when none is.
fn raw_radius(positions: &[Vec3], i: usize, around: &[u32], scale: f32) -> f32 {
    let (sum, count) = around
        .iter()
        .map(|&j| positions[j as usize].distance_squared(positions[i]).max(0.0).sqrt())
        .filter(|&x| x > 0.0 && x.is_finite())
        .fold((0.0f32, 0u32), |(sum, count), x| (sum + x, count + 1));
    if count == 0 { 0.0 } else { scale * sum / count as f32 }
}

/// The radii of the points `needed`: each point's raw radius (`raw` when
/// the normals' pass made them), clamped to [`MAX_RADIUS_OVER_MEDIAN`] ×
/// the median of every point's. Returns (isolated points, clamped radii).
fn estimate_radii(
    cloud: &mut PointCloud,
    nb: &Neighbours,
    needed: &[bool],
    options: &EstimateOptions,
    raw: Option<Vec<f32>>,
) -> (usize, usize) {
    let k = radius_neighbours(options, nb.k);
    let positions = &cloud.positions;
    let raw =
        raw.unwrap_or_else(|| nb.map_rows(|i, around| raw_radius(positions, i, &around[..k], options.radius_scale)));
    // Every point coincides when none is positive: give them a radius that is visible.
    let median = median_radius(&raw).unwrap_or(1.0);
    let (mut isolated, mut clamped) = (0, 0);
    for (i, r) in raw.into_iter().enumerate() {
        if !needed[i] {
            continue;
        }
        cloud.radii[i] = if !(r > 0.0 && r.is_finite()) {
            isolated += 1;
            median
        } else if r > MAX_RADIUS_OVER_MEDIAN * median {
            clamped += 1;
            MAX_RADIUS_OVER_MEDIAN * median
        } else {
            r
        };
    }
    (isolated, clamped)
}

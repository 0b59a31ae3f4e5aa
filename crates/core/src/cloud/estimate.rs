//! Estimating what a file lacks: normals (PCA + consistent orientation) and radii.
//!
//! Normals: the eigenvector of the smallest eigenvalue of the covariance of
//! each point's k nearest neighbours. Their signs are made consistent by
//! propagating along a minimum spanning tree of the neighbour graph, with edge
//! cost 1 - |n_i . n_j| (Hoppe et al. 1992), so orientation never flips
//! across a smooth surface. Each connected piece then gets its global sign:
//! towards the scanner when the file's origin lies outside the cloud and sees
//! (almost) every point from the front, as in a single-view scan; otherwise
//! outwards, away from the cloud's centre. Airborne scans (LAS/LAZ, and
//! geo-referenced terrain) have no scanner position to face: their normals
//! face up (+z), each on its own, with no tree to propagate along
//! ([`EstimateOptions::orient_up`]).
//!
//! Radii: a multiple of the mean distance to the k nearest neighbours, so
//! neighbouring splats overlap and cover the surface; outliers are clamped
//! to a multiple of the median.

use glam::{DVec3, Mat3, Vec3};
use rayon::prelude::*;

use super::PointCloud;
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
                    estimate_normals(cloud, &neighbours, needs_normal, options.normal_neighbours);
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
            let (isolated, clamped) = estimate_radii(cloud, &neighbours, needs_radius, options);
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

fn estimate_normals(cloud: &mut PointCloud, nb: &Neighbours, needed: &[bool], k: usize) {
    let positions = &cloud.positions;
    let k = k.min(nb.k);
    let residuals = &cloud.residuals;
    let normals = nb.map_rows(|i, around| {
        if !needed[i] {
            return None;
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
        Some(smallest_eigenvector(covariance(points, centre)).unwrap_or(Vec3::Z))
    });
    for (n, estimated) in cloud.normals.iter_mut().zip(normals) {
        if let Some(estimated) = estimated {
            *n = estimated;
        }
    }
}

/// The sum of (p - centre)(p - centre)ᵀ over `points`: its six distinct
/// entries accumulated once each (a product and its mirror are the same
/// f32, so the matrix is the one a full outer product per point makes).
fn covariance(points: &[Vec3], centre: Vec3) -> Mat3 {
    let (mut xx, mut xy, mut xz, mut yy, mut yz, mut zz) = (0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for p in points {
        let d = *p - centre;
        xx += d.x * d.x;
        xy += d.y * d.x;
        xz += d.z * d.x;
        yy += d.y * d.y;
        yz += d.z * d.y;
        zz += d.z * d.z;
    }
    Mat3::from_cols(Vec3::new(xx, xy, xz), Vec3::new(xy, yy, yz), Vec3::new(xz, yz, zz))
}

/// Unit eigenvector of the smallest eigenvalue of a symmetric 3x3 matrix.
///
/// In closed form where the smallest eigenvalue stands apart (a surface's
/// neighbourhood: the common case, a third of the time of the sweeps), else
/// by cyclic Jacobi rotations ([`jacobi_smallest_eigenvector`]). No
/// linear-algebra crate for one call.
pub fn smallest_eigenvector(m: Mat3) -> Option<Vec3> {
    closed_form_smallest_eigenvector(m).or_else(|| jacobi_smallest_eigenvector(m))
}

/// The smallest eigenvalue by the trigonometric solution of the
/// characteristic cubic (Smith 1961), in f64 on the matrix scaled to unit
/// size; its eigenvector as the largest cross product of two rows of
/// A - λI. `None` where the two smallest eigenvalues are within 1e-6 of the
/// spread, or the cross products vanish: the sweeps decide there.
fn closed_form_smallest_eigenvector(m: Mat3) -> Option<Vec3> {
    let a = m.to_cols_array_2d().map(|c| c.map(|v| v as f64));
    let scale = a.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let a = a.map(|c| c.map(|v| v / scale));
    let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let p2 = (a[0][0] - q).powi(2) + (a[1][1] - q).powi(2) + (a[2][2] - q).powi(2) + 2.0 * off;
    let p = (p2 / 6.0).sqrt();
    if p < 1e-12 {
        return None;
    }
    let b = a.map(|c| c.map(|v| v / p));
    let b =
        [[b[0][0] - q / p, b[0][1], b[0][2]], [b[1][0], b[1][1] - q / p, b[1][2]], [b[2][0], b[2][1], b[2][2] - q / p]];
    let det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0])
        + b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
    let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
    let third = 2.0 * std::f64::consts::PI / 3.0;
    let smallest = q + 2.0 * p * (phi + third).cos();
    let middle = q + 2.0 * p * (phi - third).cos();
    if middle - smallest < 1e-6 * p {
        return None;
    }
    let rows: [DVec3; 3] = std::array::from_fn(|i| DVec3::new(a[0][i], a[1][i], a[2][i]) - smallest * DVec3::AXES[i]);
    let best = [rows[0].cross(rows[1]), rows[0].cross(rows[2]), rows[1].cross(rows[2])]
        .into_iter()
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))?;
    let len = best.length();
    (len > 1e-9 && len.is_finite()).then(|| (best / len).as_vec3())
}

/// Unit eigenvector of the smallest eigenvalue by cyclic Jacobi rotations:
/// exact for any symmetric matrix, also where eigenvalues repeat.
pub fn jacobi_smallest_eigenvector(m: Mat3) -> Option<Vec3> {
    let mut a = m.to_cols_array_2d().map(|c| c.map(|v| v as f64));
    let mut v = [[1.0f64, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..24 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off < 1e-30 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (row_p, row_q) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * row_p[k] - s * row_q[k]);
            a[q] = std::array::from_fn(|k| s * row_p[k] + c * row_q[k]);
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let smallest = (0..3).min_by(|&x, &y| a[x][x].total_cmp(&a[y][y]))?;
    let e = Vec3::new(v[0][smallest] as f32, v[1][smallest] as f32, v[2][smallest] as f32);
    let len = e.length();
    (len.is_finite() && len > 1e-6).then(|| e / len)
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

/// Returns (isolated points, clamped radii).
fn estimate_radii(
    cloud: &mut PointCloud,
    nb: &Neighbours,
    needed: &[bool],
    options: &EstimateOptions,
) -> (usize, usize) {
    let k = options.radius_neighbours.min(nb.k).max(1);
    let positions = &cloud.positions;
    // The distances the search measured (f32 positions, as it reads them).
    let raw: Vec<f32> = nb.map_rows(|i, around| {
        let (sum, count) = around[..k]
            .iter()
            .map(|&j| positions[j as usize].distance_squared(positions[i]).max(0.0).sqrt())
            .filter(|&x| x > 0.0 && x.is_finite())
            .fold((0.0f32, 0u32), |(sum, count), x| (sum + x, count + 1));
        if count == 0 { 0.0 } else { options.radius_scale * sum / count as f32 }
    });
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smallest_eigenvector_of_a_flat_covariance_is_its_normal() {
        // Points spread in a plane with normal n: covariance = I - n n^T (scaled).
        for n in [Vec3::X, Vec3::new(1.0, 2.0, -0.5).normalize(), Vec3::new(-0.3, 0.1, 0.9).normalize()] {
            let cov = Mat3::IDENTITY - Mat3::from_cols(n * n.x, n * n.y, n * n.z);
            let e = smallest_eigenvector(cov).unwrap();
            assert!(e.dot(n).abs() > 1.0 - 1e-5, "{e} vs {n}");
        }
    }

    #[test]
    fn the_covariance_is_the_sum_of_full_outer_products_bit_for_bit() {
        let mut seed = 11u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 40) as f32 / (1u64 << 24) as f32 * 7.0 - 3.0
        };
        for _ in 0..200 {
            let points: Vec<Vec3> = (0..17).map(|_| Vec3::new(next(), next(), next() * 0.01)).collect();
            let centre = points.iter().sum::<Vec3>() / 17.0;
            let mut full = Mat3::ZERO;
            for d in points.iter().map(|p| *p - centre) {
                full += Mat3::from_cols(d * d.x, d * d.y, d * d.z);
            }
            let bits = |m: Mat3| m.to_cols_array().map(f32::to_bits);
            assert_eq!(bits(covariance(&points, centre)), bits(full));
        }
    }

    #[test]
    fn the_closed_form_agrees_with_the_sweeps_on_random_neighbourhoods() {
        let mut seed = 3u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 40) as f32 / (1u64 << 24) as f32 - 0.5
        };
        let mut closed = 0;
        for round in 0..2000 {
            // A noisy patch of 17 points: flat, thick, or a blob.
            let thickness = [0.01, 0.2, 1.0][round % 3];
            let (u, v) = (Vec3::new(next(), next(), next()).normalize(), Vec3::new(next(), next(), next()).normalize());
            let n = u.cross(v).normalize();
            let points: Vec<Vec3> = (0..17).map(|_| u * next() + v * next() + n * next() * thickness).collect();
            let centre = points.iter().sum::<Vec3>() / 17.0;
            let cov = points.iter().fold(Mat3::ZERO, |c, p| {
                let d = *p - centre;
                c + Mat3::from_cols(d * d.x, d * d.y, d * d.z)
            });
            let (Some(a), Some(b)) = (closed_form_smallest_eigenvector(cov), jacobi_smallest_eigenvector(cov)) else {
                continue;
            };
            closed += 1;
            assert!(a.dot(b).abs() > 1.0 - 1e-4, "{a} vs {b} for {cov}");
        }
        assert!(closed > 1900, "the closed form decided only {closed} of 2000");
    }

    #[test]
    fn a_zero_matrix_has_no_preferred_direction_but_gives_a_unit_vector() {
        let e = smallest_eigenvector(Mat3::ZERO).unwrap();
        assert!((e.length() - 1.0).abs() < 1e-6);
    }
}

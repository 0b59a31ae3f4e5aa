//! Gunjee et al. §4.1's translucent shadow map: one table per light, its
//! cells the directions around the light, each cell the splats met in its
//! direction sorted by distance, and each splat's shadow coefficient the
//! light left after the layers in front of it, read in the cells around it.
//!
//! - **Light space (Eq. 1)** puts the light at the origin. For a point light
//!   outside the scene's bounding sphere the x axis points at the scene's
//!   centre and the table spans only the cone that holds the scene (polar
//!   angle π/2 ± β, azimuth ±β, sin β = R/d): the cells go where the points
//!   are, and a light 10⁶ radii away still has a fine table. A light inside
//!   the sphere gets the whole sphere of directions (Fig. 17 d): polar 0..π,
//!   azimuth −π..π, wrapping. A directional light gets a table of parallel
//!   rays over a square across the scene: the limit of a point light far away.
//! - **Cells (Eq. 2-3)**: k_pol × k_az, uniform in polar and azimuth angle.
//! - **Insertion (Step 3)**: a splat enters every cell whose centre ray
//!   meets its disc (the cells its splat reaches at its distance, as the
//!   paper asks), at the distance where the ray meets the disc's plane, with
//!   Eq. 3's Gaussian weight there; and always the cell its centre falls
//!   in, where the ray may miss its disc, as a probe of no weight at the
//!   ray's distance to the disc's plane (it joins the layer of its surface
//!   and changes no sum). Coplanar splats meet a
//!   cell's ray at one distance, so a floor seen at a grazing angle stays one
//!   layer instead of shadowing itself. Distances along one ray are the
//!   exact ones, in f64 while building, so precision does not depend on how
//!   far the light is.
//! - **Sorting**: a counting sort of the entries by cell (O(n)), then each
//!   cell's short list by distance: the same order as the paper's linked
//!   lists with insertion by distance, in flat arrays.
//! - **Absorbance**: each cell's entries are merged into ε-layers and summed
//!   ([`super::layers`]); along one cell's ray a splat keeps 10^−A of the
//!   layers in front of its own. Its coefficient is the mean of that over
//!   the cells its disc covers (Gaussian weights), or its own cell's where
//!   it covers none: the table filtered over the splat, as the splat is
//!   blended over its pixels. The paper reads one cell; reading one cell
//!   makes a splat whose centre lies near a shadow's edge take the wrong
//!   side of it (docs/BENCHMARKS.md).
//!
//! The build is parallel over splats (insertion) and over cells (sorting
//! and sums), and O(n) in the entries.

use std::ops::RangeInclusive;
use std::sync::atomic::Ordering;

use glam::{DMat3, DVec3, Vec3};

use rayon::prelude::*;

use super::layers::{self, Entry};
use super::{ShadowError, ShadowInput};
use crate::frame::{Light, LightKind};

/// What a table took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableStats {
    pub cells: [u32; 2],
    pub entries: u64,
    /// Bytes of the table (cell offsets and entries) at its largest.
    pub bytes: u64,
    pub build_ms: f64,
}

/// The coefficient weight of a splat's probe in the cell its centre falls
/// in: next to any cell whose ray meets its disc, nothing.
const OWN_PROBE: f32 = 1e-6;

/// Bytes of one entry while building.
const ENTRY_BYTES: u64 = std::mem::size_of::<RawEntry>() as u64;

/// Most memory a table may take: half of what the machine has free, at most 4 GiB.
fn memory_limit() -> u64 {
    let cap = 4u64 << 30;
    crate::memory::available_bytes().map_or(cap, |free| (free / 2).min(cap))
}

#[derive(Debug, Clone, Copy)]
struct RawEntry {
    cell: u32,
    /// Distance along the cell's ray; once the cell is swept, the light left there.
    distance: f32,
    /// Eq. 3's weight in the layer sums and in the splat's coefficient (0: a probe).
    weight: f32,
    splat: u32,
}

/// How directions around the light map to cells.
enum Projection {
    Spherical {
        light: DVec3,
        /// World to light space (rows: light space's x, y, z in world coordinates).
        basis: DMat3,
        /// (sin, cos) of each row's and each column's centre angle.
        rows: Vec<(f64, f64)>,
        columns: Vec<(f64, f64)>,
        pol0: f64,
        az0: f64,
        d_pol: f64,
        d_az: f64,
        wrap: bool,
    },
    Parallel {
        /// The travel direction, and two axes across it.
        dir: DVec3,
        across: [DVec3; 2],
        /// The corner of the square the rays start from.
        origin: DVec3,
        /// A cell's width along each axis (rows, columns).
        cell: [f64; 2],
    },
}

/// Where a splat falls in the table: its continuous cell coordinates, its
/// distance, and the cells its disc may reach.
struct Footprint {
    /// The centre's continuous cell coordinates (row, column).
    at: (f64, f64),
    rows: RangeInclusive<i64>,
    /// Half-width in columns (None: every column).
    columns: Option<(i64, i64)>,
}

impl Projection {
    fn new(light: &Light, centre: Vec3, radius: f32, k: [u32; 2]) -> Self {
        let (centre, radius) = (centre.as_dvec3(), radius as f64);
        match light.kind {
            LightKind::Point(p) => {
                let light = p.as_dvec3();
                let to_centre = centre - light;
                let d = to_centre.length();
                let outside = d > radius * 1.0001;
                let x = if outside { to_centre / d } else { DVec3::X };
                let helper = if x.z.abs() < 0.9 { DVec3::Z } else { DVec3::X };
                let y = helper.cross(x).normalize();
                let z = x.cross(y);
                let basis = DMat3::from_cols(x, y, z).transpose();
                let (pol0, az0, pol_span, az_span) = if outside {
                    let beta = (radius / d).clamp(0.0, 1.0).asin();
                    (std::f64::consts::FRAC_PI_2 - beta, -beta, 2.0 * beta, 2.0 * beta)
                } else {
                    (0.0, -std::f64::consts::PI, std::f64::consts::PI, std::f64::consts::TAU)
                };
                let (d_pol, d_az) = (pol_span / k[0] as f64, az_span / k[1] as f64);
                let angles = |start: f64, step: f64, n: u32| -> Vec<(f64, f64)> {
                    (0..n).map(|i| (start + (i as f64 + 0.5) * step).sin_cos()).collect()
                };
                Projection::Spherical {
                    light,
                    basis,
                    rows: angles(pol0, d_pol, k[0]),
                    columns: angles(az0, d_az, k[1]),
                    pol0,
                    az0,
                    d_pol,
                    d_az,
                    wrap: !outside,
                }
            }
            LightKind::Directional(d) => {
                let dir = d.as_dvec3().normalize();
                let helper = if dir.y.abs() < 0.9 { DVec3::Y } else { DVec3::X };
                let a = helper.cross(dir).normalize();
                let b = dir.cross(a);
                let cell = [2.0 * radius / k[0] as f64, 2.0 * radius / k[1] as f64];
                Projection::Parallel { dir, across: [a, b], origin: centre - (a + b + dir) * radius, cell }
            }
        }
    }

    /// The footprint of a disc at `p` with radius `r` in a table of `k` cells.
    fn footprint(&self, p: DVec3, r: f64, k: [u32; 2]) -> Option<Footprint> {
        let clamp = |v: f64, n: u32| (v.floor() as i64).clamp(0, n as i64 - 1);
        match self {
            Projection::Spherical { light, basis, pol0, az0, d_pol, d_az, wrap, .. } => {
                let q = *basis * (p - *light);
                let d = q.length();
                if d.is_nan() || d <= 1e-12 * r.max(1e-30) {
                    return None; // the light sits at the splat's centre
                }
                let pol = q.truncate().length().atan2(q.z);
                let az = q.y.atan2(q.x);
                let u = (pol - pol0) / d_pol;
                let v = (az - az0) / d_az;
                // The disc's angular radius asin(r/d), bounded above by its
                // tangent (no trigonometry per splat beyond the two angles).
                let sin_spread = (r / d).min(1.0);
                let cos_spread = (1.0 - sin_spread * sin_spread).sqrt();
                let spread = if cos_spread > 1e-6 { sin_spread / cos_spread } else { std::f64::consts::PI };
                let rows = clamp(u - spread / d_pol, k[0])..=clamp(u + spread / d_pol, k[0]);
                // The narrowest sine of the polar angle over the rows decides the column span.
                let (sin_pol, cos_pol) = (q.truncate().length() / d, q.z / d);
                let sin_min = (sin_pol * cos_spread - cos_pol.abs() * sin_spread).max(0.0);
                let columns = if spread >= std::f64::consts::FRAC_PI_2 || sin_spread >= sin_min * 0.999 {
                    None
                } else {
                    let x = sin_spread / sin_min;
                    let half = x / (1.0 - x * x).sqrt() / d_az;
                    Some(((v - half).floor() as i64, (v + half).floor() as i64))
                };
                let columns = match columns {
                    Some((a, b)) if *wrap && b - a < k[1] as i64 => Some((a, b)),
                    Some((a, b)) if !*wrap => Some((a.clamp(0, k[1] as i64 - 1), b.clamp(0, k[1] as i64 - 1))),
                    _ if *wrap => None,
                    _ => Some((0, k[1] as i64 - 1)),
                };
                Some(Footprint { at: (u, v), rows, columns })
            }
            Projection::Parallel { across, origin, cell, .. } => {
                let rel = p - *origin;
                let (u, v) = (rel.dot(across[0]) / cell[0], rel.dot(across[1]) / cell[1]);
                let (su, sv) = (r / cell[0], r / cell[1]);
                Some(Footprint {
                    at: (u, v),
                    rows: clamp(u - su, k[0])..=clamp(u + su, k[0]),
                    columns: Some((clamp(v - sv, k[1]), clamp(v + sv, k[1]))),
                })
            }
        }
    }

    /// The ray through the centre of cell (row, column), origin and unit
    /// direction, in the projection's own frame (light space for a point
    /// light, with the light at the origin; the world for parallel light).
    fn ray(&self, row: u32, column: u32) -> (DVec3, DVec3) {
        match self {
            Projection::Spherical { rows, columns, .. } => {
                let ((sp, cp), (sa, ca)) = (rows[row as usize], columns[column as usize]);
                (DVec3::ZERO, DVec3::new(sp * ca, sp * sa, cp))
            }
            Projection::Parallel { dir, across, origin, cell } => {
                let o =
                    *origin + across[0] * (row as f64 + 0.5) * cell[0] + across[1] * (column as f64 + 0.5) * cell[1];
                (o, *dir)
            }
        }
    }

    /// About the least distance of the scene from the light along a ray
    /// (what distances are kept relative to).
    fn nearest_distance(&self, centre: Vec3, radius: f32) -> f64 {
        match self {
            Projection::Spherical { light, .. } => (light.distance(centre.as_dvec3()) - radius as f64).max(0.0),
            Projection::Parallel { .. } => 0.0,
        }
    }

    /// Whether columns wrap around (a table of every direction).
    fn wraps(&self) -> bool {
        matches!(self, Projection::Spherical { wrap: true, .. })
    }

    /// A point of the projection's own frame in world coordinates (the inverse of [`Self::to_frame`]'s).
    fn world_point(&self, q: DVec3) -> DVec3 {
        match self {
            Projection::Spherical { light, basis, .. } => basis.transpose() * q + *light,
            Projection::Parallel { .. } => q,
        }
    }

    /// A world point and a world direction in the projection's own frame (see [`Self::ray`]).
    fn to_frame(&self, p: DVec3, n: DVec3) -> (DVec3, DVec3) {
        match self {
            Projection::Spherical { light, basis, .. } => (*basis * (p - *light), *basis * n),
            Projection::Parallel { .. } => (p, n),
        }
    }
}

/// Where the ray (o, w) meets the disc at `p` with normal `n` and radius
/// `r`: (distance along the ray, ρ²), if it meets its plane ahead.
fn meet(o: DVec3, w: DVec3, p: DVec3, n: DVec3, r: f64) -> Option<(f64, f64)> {
    let cos = n.dot(w);
    if cos.abs() < 1e-9 {
        return None;
    }
    let t = n.dot(p - o) / cos;
    let rho2 = (o + w * t - p).length_squared() / (r * r);
    (t >= 0.0).then_some((t, rho2))
}

/// The columns of a footprint's span, wrapped into the table.
fn columns(span: Option<(i64, i64)>, k_az: u32) -> impl Iterator<Item = u32> {
    let (a, b) = span.unwrap_or((0, k_az as i64 - 1));
    (a..=b).map(move |c| c.rem_euclid(k_az as i64) as u32)
}

/// Step 3 for splat `i`: an entry in every cell whose ray meets its disc
/// (distance from `reference`, Gaussian weight), and a probe in the cell its
/// centre falls in, appended to `out`.
fn insert_entries(
    input: &ShadowInput,
    projection: &Projection,
    (k, reference): ([u32; 2], f64),
    i: usize,
    out: &mut Vec<RawEntry>,
) {
    let cloud = input.cloud;
    let p = cloud.positions[i].as_dvec3();
    let r = input.radius(i) as f64;
    let Some(f) = projection.footprint(p, r, k) else { return };
    let (q, normal) = projection.to_frame(p, cloud.normals[i].as_dvec3());
    // The cell the centre falls in: the splat's light is read there
    // too, as a probe, in case no cell's ray meets its disc.
    let own_row = (f.at.0.floor() as i64).clamp(0, k[0] as i64 - 1);
    let own_column = if projection.wraps() {
        (f.at.1.floor() as i64).rem_euclid(k[1] as i64)
    } else {
        (f.at.1.floor() as i64).clamp(0, k[1] as i64 - 1)
    } as u32;
    for row in f.rows.clone() {
        for column in columns(f.columns, k[1]) {
            let own = row == own_row && column == own_column;
            let (o, w) = projection.ray(row as u32, column);
            // A ray that passes farther than r from the centre misses the disc.
            let along = (q - o).dot(w);
            // (The cross product keeps its precision for a light far away.)
            let misses = along <= 0.0 || (q - o).cross(w).length_squared() >= r * r;
            if misses && !own {
                continue;
            }
            let hit = if misses { None } else { meet(o, w, q, normal, r) };
            // A hit the clip cuts away casts nothing (the splat's probe stays).
            let hit = hit.filter(|(t, _)| input.clip.keeps(projection.world_point(o + w * *t).as_vec3()));
            let (distance, weight) = match hit {
                Some((t, rho2)) if rho2 < 1.0 => (t, input.kernel.weight(rho2 as f32)),
                // A probe (no weight) where the ray meets the disc's plane,
                // where coplanar neighbours that cover the ray are met.
                _ if own => match meet(o, w, q, normal, r) {
                    Some((t, _)) => (t, 0.0),
                    None => (along, 0.0),
                },
                _ => continue,
            };
            out.push(RawEntry {
                cell: row as u32 * k[1] + column,
                distance: (distance - reference) as f32,
                weight,
                splat: i as u32,
            });
        }
    }
}

/// The entries of every chunk in one list, ordered by cell (a stable counting sort).
fn sort_by_cell(chunks: Vec<Vec<RawEntry>>, cell_count: usize, entries: usize) -> Vec<RawEntry> {
    let mut start = vec![0u32; cell_count + 1];
    for e in chunks.iter().flatten() {
        start[e.cell as usize + 1] += 1;
    }
    for c in 0..cell_count {
        start[c + 1] += start[c];
    }
    let mut sorted = vec![RawEntry { cell: 0, distance: 0.0, weight: 0.0, splat: 0 }; entries];
    let mut fill = start.clone();
    for e in chunks.into_iter().flatten() {
        sorted[fill[e.cell as usize] as usize] = e;
        fill[e.cell as usize] += 1;
    }
    sorted
}

/// Builds the table of `light` over `input`'s splats with `k` = [k_pol,
/// k_az] cells and returns each splat's shadow coefficient.
pub fn build(input: &ShadowInput, light: &Light, k: [u32; 2]) -> Result<(Vec<f32>, TableStats), ShadowError> {
    let started = std::time::Instant::now();
    let k = k.map(|c| c.clamp(1, crate::frame::lights::MAX_TSM_CELLS));
    let cloud = input.cloud;
    let n = cloud.len();
    let (centre, radius) = input.bounds();
    let projection = Projection::new(light, centre, radius, k);
    // Distances are kept in f32 from the scene's near side, so a light far
    // away keeps their precision.
    let reference = projection.nearest_distance(centre, radius);
    let cell_count = k[0] as u64 * k[1] as u64;

    // Memory: the cell offsets, then the entries counted as they are made;
    // insertion stops as soon as they pass the limit (nothing larger is allocated).
    let limit = memory_limit();
    let max_entries = (limit.saturating_sub((cell_count + 1) * 4) / (ENTRY_BYTES * 2)).max(1);
    let made = std::sync::atomic::AtomicU64::new(0);
    let too_large = |entries: u64| {
        let need = entries * ENTRY_BYTES * 2 + (cell_count + 1) * 4;
        let scale = ((limit as f64 / need as f64).sqrt() * 0.9).clamp(0.0, 1.0);
        let hint = k.map(|c| ((c as f64 * scale) as u32).max(1));
        ShadowError::TooLarge {
            cells: format!("{}x{}", k[0], k[1]),
            entries,
            need: format!("more than {}", crate::memory::gib(need)),
            limit: crate::memory::gib(limit),
            hint: format!("{}x{}", hint[0], hint[1]),
        }
    };
    if (cell_count + 1) * 4 > limit {
        return Err(too_large(0));
    }

    // Insertion (Step 3), parallel over chunks of splats.
    let chunks: Vec<Vec<RawEntry>> = (0..n)
        .collect::<Vec<usize>>()
        .par_chunks(8192)
        .map(|chunk| {
            let mut out = Vec::with_capacity(chunk.len() * 4);
            for &i in chunk {
                // Every splat's entries count at once, so insertion stops within one
                // splat's entries (at most one table) of the limit.
                if made.load(Ordering::Relaxed) > max_entries {
                    break;
                }
                let before = out.len();
                insert_entries(input, &projection, (k, reference), i, &mut out);
                made.fetch_add((out.len() - before) as u64, Ordering::Relaxed);
            }
            out
        })
        .collect();
    let entries: u64 = chunks.iter().map(|c| c.len() as u64).sum();
    if made.into_inner() > max_entries {
        return Err(too_large(entries));
    }

    let mut sorted = sort_by_cell(chunks, cell_count as usize, entries as usize);

    // Each cell by distance, then its layers.
    let facing: Vec<bool> = (0..n).map(|i| input.faces(i, light)).collect();
    sorted.par_chunk_by_mut(|a, b| a.cell == b.cell).for_each_init(
        || (Vec::new(), layers::Scratch::default(), Vec::new()),
        |(layer_entries, scratch, light): &mut (Vec<Entry>, layers::Scratch, Vec<f32>), cell| {
            cell.sort_unstable_by(|a, b| a.distance.total_cmp(&b.distance));
            layer_entries.clear();
            layer_entries.extend(cell.iter().map(|e| {
                let i = e.splat as usize;
                Entry { distance: e.distance, weight: e.weight, opacity: input.opacity(i), facing: facing[i] }
            }));
            light.clear();
            light.resize(cell.len(), 1.0);
            layers::sweep(layer_entries, input.epsilon, scratch, |k, a| light[k] = layers::transmittance(a));
            // Each entry now carries the light its splat receives along this cell's ray.
            for (e, t) in cell.iter_mut().zip(light.iter()) {
                e.distance = *t;
            }
        },
    );
    // A splat's coefficient: the mean over the cells its disc covers
    // (Gaussian weights), or its own cell's where it covers none.
    let mut sums = vec![(0.0f32, 0.0f32); n];
    for e in &sorted {
        // The own probe counts only where no ray meets the disc.
        let filter = if e.weight > 0.0 { e.weight } else { OWN_PROBE };
        let s = &mut sums[e.splat as usize];
        s.0 += filter * e.distance;
        s.1 += filter;
    }
    let coefficients = sums.into_iter().map(|(sum, w)| if w > 0.0 { (sum / w).clamp(0.0, 1.0) } else { 1.0 }).collect();
    let stats = TableStats {
        cells: k,
        entries,
        bytes: entries * ENTRY_BYTES * 2 + (cell_count + 1) * 4,
        build_ms: started.elapsed().as_secs_f64() * 1e3,
    };
    Ok((coefficients, stats))
}

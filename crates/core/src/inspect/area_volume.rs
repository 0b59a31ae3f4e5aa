//! Areas and volumes inside a [`Polygon`], in the CRS's units, over a
//! file's records (every point, f64 file coordinates).
//!
//! - The horizontal area is the polygon's own (exact).
//! - The points become a height field on a square grid of cells of side
//!   `cell` over the polygon: each cell's height is the mean height of its
//!   points; a cell inside without points takes the mean of its filled
//!   neighbours, ring by ring ([`FILL_RINGS`] at most, the rest reported).
//!   The default cell is twice the mean spacing of the points inside
//!   (about four points a cell).
//! - The surface area is the sum over the cells inside of cell² times
//!   sqrt(1 + |∇h|²), the gradient by central differences of the field.
//! - A volume is the sum over the cells inside of cell² times the height
//!   above (and, apart, below) a base: a plane fitted by least squares to
//!   the points within one cell of the polygon's border (a stockpile on
//!   its ground), or another cloud's height field on the same grid (before
//!   and after: cut and fill).

use glam::{DVec2, DVec3};

use super::polygon::Polygon;

/// Passes of neighbour filling for cells without points.
pub const FILL_RINGS: usize = 4;
/// The most cells a grid may have.
pub const MAX_CELLS: usize = 64 << 20;

/// What a volume is measured above.
pub enum Base<'a> {
    /// A plane fitted to the points along the polygon's border.
    BorderPlane,
    /// Another cloud's points (file coordinates of the same CRS).
    Points(&'a [DVec3]),
}

/// The base a volume used.
#[derive(Debug, Clone, PartialEq)]
pub enum BaseUsed {
    /// z = slope_x · (x − centre.x) + slope_y · (y − centre.y) + height, fitted to `points`.
    Plane { centre: DVec2, slope_x: f64, slope_y: f64, height: f64, points: usize },
    /// Another cloud's height field; `cells_without` cells inside had none.
    Cloud { points: usize, cells_without: usize },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Volume {
    pub above: f64,
    pub below: f64,
    pub base: BaseUsed,
}

#[derive(Debug, Clone, PartialEq)]
pub struct AreaVolume {
    pub area_horizontal: f64,
    pub area_surface: f64,
    /// The points inside the polygon.
    pub points: usize,
    pub cell: f64,
    /// Cells whose centre is inside; of them, those filled from neighbours and those left empty.
    pub cells: usize,
    pub cells_filled: usize,
    pub cells_empty: usize,
    pub volume: Option<Volume>,
}

/// A grid of cells over the polygon's bounds, a ring of one cell around it.
struct Grid {
    min: DVec2,
    cell: f64,
    size: (usize, usize),
}

impl Grid {
    fn over(polygon: &Polygon, cell: f64) -> Result<Grid, String> {
        let (min, max) = polygon.bounds();
        let min = min - DVec2::splat(cell);
        let cols = ((max.x - min.x) / cell).ceil() as usize + 1;
        let rows = ((max.y - min.y) / cell).ceil() as usize + 1;
        if cols.saturating_mul(rows) > MAX_CELLS {
            return Err(format!(
                "a cell of {cell} makes {cols}x{rows} cells over the polygon, more than {MAX_CELLS}; give a larger --cell"
            ));
        }
        Ok(Grid { min, cell, size: (cols, rows) })
    }

    fn index(&self, p: DVec2) -> Option<usize> {
        let at = (p - self.min) / self.cell;
        let (i, j) = (at.x.floor(), at.y.floor());
        let inside = i >= 0.0 && j >= 0.0 && (i as usize) < self.size.0 && (j as usize) < self.size.1;
        inside.then(|| j as usize * self.size.0 + i as usize)
    }

    fn centre(&self, k: usize) -> DVec2 {
        let (i, j) = (k % self.size.0, k / self.size.0);
        self.min + (DVec2::new(i as f64, j as f64) + 0.5) * self.cell
    }

    fn neighbours(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        let (i, j) = ((k % self.size.0) as i64, (k / self.size.0) as i64);
        let (w, h) = (self.size.0 as i64, self.size.1 as i64);
        (-1..=1i64).flat_map(move |dj| (-1..=1i64).map(move |di| (i + di, j + dj))).filter_map(move |(x, y)| {
            ((x, y) != (i, j) && x >= 0 && y >= 0 && x < w && y < h).then_some((y * w + x) as usize)
        })
    }

    /// The mean height of `points` in each cell (`None` where none fell),
    /// and where that height lies: the mean of their x and y (the cell's
    /// centre where none fell).
    fn heights(&self, points: &[DVec3]) -> (Vec<Option<f64>>, Vec<DVec2>) {
        let mut sums = vec![(DVec3::ZERO, 0u32); self.size.0 * self.size.1];
        for p in points {
            if let Some(k) = self.index(p.truncate()) {
                // About the cell's corner, so far coordinates keep their precision.
                sums[k].0 += *p - self.corner(k).extend(0.0);
                sums[k].1 += 1;
            }
        }
        let heights = sums.iter().map(|&(s, n)| (n > 0).then(|| s.z / f64::from(n))).collect();
        let at = (0..sums.len())
            .map(|k| match sums[k] {
                (s, n) if n > 0 => self.corner(k) + s.truncate() / f64::from(n),
                _ => self.centre(k),
            })
            .collect();
        (heights, at)
    }

    fn corner(&self, k: usize) -> DVec2 {
        self.centre(k) - DVec2::splat(self.cell * 0.5)
    }

    /// Fills the cells of `inside` without a height from their neighbours,
    /// ring by ring; returns how many were filled and how many stay empty.
    fn fill(&self, heights: &mut [Option<f64>], inside: &[bool]) -> (usize, usize) {
        let mut filled = 0;
        for _ in 0..FILL_RINGS {
            let empty: Vec<usize> = (0..heights.len()).filter(|&k| inside[k] && heights[k].is_none()).collect();
            let found: Vec<(usize, f64)> = empty
                .iter()
                .filter_map(|&k| {
                    let near: Vec<f64> = self.neighbours(k).filter_map(|n| heights[n]).collect();
                    (!near.is_empty()).then(|| (k, near.iter().sum::<f64>() / near.len() as f64))
                })
                .collect();
            if found.is_empty() {
                break;
            }
            filled += found.len();
            for (k, h) in found {
                heights[k] = Some(h);
            }
        }
        (filled, (0..heights.len()).filter(|&k| inside[k] && heights[k].is_none()).count())
    }

    /// The slope (∂h/∂x, ∂h/∂y) at cell k by central (else one-sided) differences.
    fn gradient(&self, heights: &[Option<f64>], k: usize) -> DVec2 {
        let (i, j) = (k % self.size.0, k / self.size.0);
        let at = |i: usize, j: usize| heights[j * self.size.0 + i];
        let along = |before: Option<f64>, here: f64, after: Option<f64>| match (before, after) {
            (Some(b), Some(a)) => (a - b) / (2.0 * self.cell),
            (Some(b), None) => (here - b) / self.cell,
            (None, Some(a)) => (a - here) / self.cell,
            (None, None) => 0.0,
        };
        let here = heights[k].unwrap_or(0.0);
        let gx =
            along(i.checked_sub(1).and_then(|i| at(i, j)), here, (i + 1 < self.size.0).then(|| at(i + 1, j)).flatten());
        let gy =
            along(j.checked_sub(1).and_then(|j| at(i, j)), here, (j + 1 < self.size.1).then(|| at(i, j + 1)).flatten());
        DVec2::new(gx, gy)
    }
}

/// The least-squares plane through `points`, about their centre.
fn fit_plane(points: &[DVec3]) -> Option<BaseUsed> {
    let n = points.len() as f64;
    let centre = points.iter().fold(DVec3::ZERO, |s, p| s + *p) / n;
    let (mut sxx, mut sxy, mut syy, mut sxz, mut syz) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for p in points {
        let d = *p - centre;
        (sxx, sxy, syy, sxz, syz) =
            (sxx + d.x * d.x, sxy + d.x * d.y, syy + d.y * d.y, sxz + d.x * d.z, syz + d.y * d.z);
    }
    let det = sxx * syy - sxy * sxy;
    if points.len() < 3 || det.abs() <= 1e-12 * (sxx * syy).max(f64::MIN_POSITIVE) {
        return None;
    }
    let slope_x = (sxz * syy - syz * sxy) / det;
    let slope_y = (syz * sxx - sxz * sxy) / det;
    Some(BaseUsed::Plane { centre: centre.truncate(), slope_x, slope_y, height: centre.z, points: points.len() })
}

/// What `measure --polygon --json` prints of `m`: areas, volumes, the cell,
/// the units and EPSG code of `units`, the cell counts and the base (its
/// `base_file` for a cloud base). The viewer copies the same.
pub fn report_json(
    m: &AreaVolume,
    units: &crate::cloud::crs_units::CrsUnits,
    base_file: Option<String>,
) -> serde_json::Value {
    use serde_json::json;
    let volume = m.volume.as_ref();
    let base = volume.map(|v| match &v.base {
        BaseUsed::Plane { centre, slope_x, slope_y, height, points } => json!({
            "kind": "plane along the border", "centre": centre.to_array(), "slope_x": slope_x,
            "slope_y": slope_y, "height": height, "points": points,
        }),
        BaseUsed::Cloud { points, cells_without } => json!({
            "kind": "cloud", "file": base_file, "points": points, "cells_without": cells_without,
        }),
    });
    json!({
        "area_horizontal": m.area_horizontal,
        "area_surface": m.area_surface,
        "volume_above": volume.map(|v| v.above),
        "volume_below": volume.map(|v| v.below),
        "cell": m.cell,
        "units": units.horizontal_name(),
        "vertical_units": units.vertical_name(),
        "epsg": units.epsg,
        "points": m.points,
        "cells": m.cells,
        "cells_filled": m.cells_filled,
        "cells_empty": m.cells_empty,
        "base": base,
    })
}

/// The horizontal and surface areas inside `polygon` of `points` (file
/// coordinates), on cells of side `cell` (default: twice the mean
/// spacing), and the volume above `base` when one is given.
pub fn area_and_volume(
    polygon: &Polygon,
    points: &[DVec3],
    cell: Option<f64>,
    base: Option<Base>,
) -> Result<AreaVolume, String> {
    let area_horizontal = polygon.area();
    let inside_points: Vec<DVec3> = points.iter().copied().filter(|p| polygon.contains(p.truncate())).collect();
    if inside_points.is_empty() {
        return Err("no point lies inside the polygon".into());
    }
    let cell = match cell {
        Some(c) if c.is_finite() && c > 0.0 => c,
        Some(c) => return Err(format!("--cell must be a positive number, not {c}")),
        None => 2.0 * (area_horizontal / inside_points.len() as f64).sqrt(),
    };
    let grid = Grid::over(polygon, cell)?;
    let cells_total = grid.size.0 * grid.size.1;
    let inside: Vec<bool> = (0..cells_total).map(|k| polygon.contains(grid.centre(k))).collect();
    let cells = inside.iter().filter(|&&b| b).count();
    if cells == 0 {
        return Err(format!("no cell of {cell} has its centre inside the polygon; give a smaller --cell"));
    }
    // The field takes the points around the polygon too, for the slopes at its edge.
    let (mut heights, at) = grid.heights(points);
    let (cells_filled, cells_empty) = grid.fill(&mut heights, &inside);
    let area_surface: f64 = (0..cells_total)
        .filter(|&k| inside[k] && heights[k].is_some())
        .map(|k| cell * cell * (1.0 + grid.gradient(&heights, k).length_squared()).sqrt())
        .sum();
    let volume = match base {
        None => None,
        Some(base) => Some(volume(polygon, points, &grid, (&heights, &at, &inside), base)?),
    };
    Ok(AreaVolume {
        area_horizontal,
        area_surface,
        points: inside_points.len(),
        cell,
        cells,
        cells_filled,
        cells_empty,
        volume,
    })
}

/// The volume between the height field and the base, over the cells inside.
fn volume(
    polygon: &Polygon,
    points: &[DVec3],
    grid: &Grid,
    (heights, at, inside): (&[Option<f64>], &[DVec2], &[bool]),
    base: Base,
) -> Result<Volume, String> {
    let cell_area = grid.cell * grid.cell;
    let (base_heights, used): (Vec<Option<f64>>, BaseUsed) = match base {
        Base::BorderPlane => {
            let border: Vec<DVec3> =
                points.iter().copied().filter(|p| polygon.distance_to_border(p.truncate()) <= grid.cell).collect();
            let Some(plane) = fit_plane(&border) else {
                return Err(format!(
                    "{} points lie within one cell ({}) of the polygon's border, too few (or in a line) to fit a base plane",
                    border.len(),
                    grid.cell
                ));
            };
            let BaseUsed::Plane { centre, slope_x, slope_y, height, .. } = plane else { unreachable!() };
            // Where each cell's mean height lies, so a tilted base cuts no slice off a tilted field.
            let on_plane = |k: usize| {
                let d = at[k] - centre;
                Some(height + slope_x * d.x + slope_y * d.y)
            };
            ((0..heights.len()).map(on_plane).collect(), plane)
        }
        Base::Points(other) => {
            let (mut field, _) = grid.heights(other);
            let (_, cells_without) = grid.fill(&mut field, inside);
            (field, BaseUsed::Cloud { points: other.len(), cells_without })
        }
    };
    let (mut above, mut below) = (0.0, 0.0);
    for k in (0..heights.len()).filter(|&k| inside[k]) {
        if let (Some(h), Some(b)) = (heights[k], base_heights[k]) {
            above += (h - b).max(0.0) * cell_area;
            below += (b - h).max(0.0) * cell_area;
        }
    }
    Ok(Volume { above, below, base: used })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_plane_has_its_surface_area_and_no_volume_above_itself() {
        let polygon: Polygon = "0,0 20,0 20,20 0,20".parse().unwrap();
        let mut points = Vec::new();
        for i in -10..=110 {
            for j in -10..=110 {
                let (x, y) = (i as f64 * 0.2, j as f64 * 0.2);
                points.push(DVec3::new(x, y, 3.0 + 0.5 * x));
            }
        }
        let m = area_and_volume(&polygon, &points, Some(0.5), Some(Base::BorderPlane)).unwrap();
        assert_eq!(m.area_horizontal, 400.0);
        let expected = 400.0 * (1.0f64 + 0.25).sqrt();
        assert!((m.area_surface / expected - 1.0).abs() < 1e-3, "{} vs {expected}", m.area_surface);
        let v = m.volume.unwrap();
        assert!(v.above < 1e-6 && v.below < 1e-6, "{v:?}");
        let BaseUsed::Plane { slope_x, slope_y, .. } = v.base else { panic!() };
        assert!((slope_x - 0.5).abs() < 1e-9 && slope_y.abs() < 1e-9);
    }
}

//! E57 files (ASTM E2807), read through the `e57` crate.
//!
//! Every scan of the file is read with its pose applied, so scans land in one
//! frame; spherical coordinates are turned into cartesian ones by the crate.
//! Colours (normalised to 0..1 by the crate from the file's colour limits)
//! become the splats' colours, and intensity (normalised the same way) an
//! attribute. A file whose pages fail their CRC is refused by the crate; one
//! whose scans have neither cartesian nor spherical coordinates is refused here.
//! Before any point is decoded, every scan's binary section is checked
//! ([`super::e57_sections`]): a scan sharing another's, or counting more
//! points than it holds, is refused, so the points are bounded by the file's
//! bytes; their memory is then checked against the free memory, and the
//! columns are allocated once.

use std::collections::HashMap;
use std::path::Path;

use super::CloudError;
use super::attributes::{Attributes, Values, names};
use super::file_info::FileInfo;
use super::ply::{ElementSpec, PointColumns, PropertyKind, PropertySpec, Scalar};

fn e57_error(path: &Path, e: impl std::fmt::Display) -> CloudError {
    CloudError::content(path, format!("not a valid E57 file: {e}"))
}

/// Memory one point takes while it is read and built (the columns, then the
/// cloud, its normals and radii estimated): 41.8M points took 4.9 GB.
const BYTES_PER_POINT: u64 = 120;

/// Reads every scan of the E57 file at `path` as vertex columns and attributes.
pub fn read(path: &Path) -> Result<(PointColumns, Attributes, FileInfo), CloudError> {
    crate::input::regular_size(path).map_err(|e| CloudError::io(path, e))?;
    let mut reader = e57::E57Reader::from_file(path).map_err(|e| e57_error(path, e))?;
    let scans = reader.pointclouds();
    if scans.is_empty() {
        return Err(CloudError::content(path, "the E57 file holds no point cloud"));
    }
    // Each scan's points in a section of its own, and no more of them than it
    // holds: the points are then bounded by the file's bytes.
    super::e57_sections::check(path, reader.header().page_size, &scans).map_err(|e| e57_error(path, e))?;
    if let Some(index) = scans.iter().position(|s| !s.has_cartesian() && !s.has_spherical()) {
        return Err(CloudError::content(
            path,
            format!("scan {index} of the E57 file has neither cartesian nor spherical coordinates"),
        ));
    }
    let with_colour = scans.iter().all(|s| s.has_color());
    let with_intensity = scans.iter().all(|s| s.has_intensity());
    let total: u64 = scans.iter().map(|s| s.records).sum();
    let need = total.saturating_mul(BYTES_PER_POINT);
    if let Some(free) = crate::memory::available_bytes().filter(|&free| need > free / 2) {
        return Err(CloudError::content(
            path,
            format!(
                "the E57 file's scans hold {total} points, about {} in memory, and {} is free",
                crate::memory::gib(need),
                crate::memory::gib(free)
            ),
        ));
    }
    let capacity = usize::try_from(total).unwrap_or(usize::MAX);
    let reserved = |wanted: bool| if wanted { capacity } else { 0 };
    let mut xyz: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(capacity));
    let mut rgb: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(reserved(with_colour)));
    let mut intensity = Vec::with_capacity(reserved(with_intensity));
    let mut invalid = 0usize;
    for (index, scan) in scans.iter().enumerate() {
        let mut points = reader.pointcloud_simple(scan).map_err(|e| e57_error(path, format!("scan {index}: {e}")))?;
        points.intensity_to_color(false);
        for (k, point) in points.enumerate() {
            // An error left (a corrupt packet inside the section) says where it was met.
            let point =
                point.map_err(|e| e57_error(path, format!("scan {index}, point {k} of {}: {e}", scan.records)))?;
            let e57::CartesianCoordinate::Valid { x, y, z } = point.cartesian else {
                invalid += 1;
                continue;
            };
            for (column, v) in xyz.iter_mut().zip([x, y, z]) {
                column.push(v);
            }
            if with_colour {
                let c = point.color.unwrap_or(e57::Color { red: 0.0, green: 0.0, blue: 0.0 });
                for (column, v) in rgb.iter_mut().zip([c.red, c.green, c.blue]) {
                    column.push(v as f64);
                }
            }
            if with_intensity {
                intensity.push(point.intensity.unwrap_or(0.0));
            }
        }
    }
    let n = xyz[0].len();
    if n + invalid == 0 {
        return Err(CloudError::content(path, "the E57 file's scans hold no points"));
    }
    let mut info = FileInfo {
        details: vec![format!("{} scan(s), {} points", scans.len(), n + invalid)],
        crs: reader.coordinate_metadata().map(str::to_string).filter(|s| !s.trim().is_empty()),
        warnings: Vec::new(),
        from_above: false,
        z_up: true,
        // E57's coordinateMetadata is a WKT text when it names a CRS.
        units: reader.coordinate_metadata().map(super::crs_units::CrsUnits::from_wkt).unwrap_or_default(),
    };
    if invalid > 0 {
        info.warnings
            .push(format!("{invalid} points with invalid coordinates (directions only, or none) were skipped"));
    }
    let mut columns = HashMap::new();
    let mut types = HashMap::new();
    let mut properties = Vec::new();
    let [x, y, z] = xyz;
    let mut named: Vec<(&str, Vec<f64>)> = vec![("x", x), ("y", y), ("z", z)];
    if with_colour {
        let [r, g, b] = rgb;
        named.extend([("red", r), ("green", g), ("blue", b)]);
    }
    for (name, column) in named {
        let kind = if matches!(name, "x" | "y" | "z") { Scalar::F64 } else { Scalar::F32 };
        properties.push(PropertySpec { name: name.into(), kind: PropertyKind::Scalar(kind) });
        types.insert(name.to_string(), kind);
        columns.insert(name.to_string(), column);
    }
    let mut attributes = Attributes::default();
    if with_intensity {
        attributes.push(names::INTENSITY, Values::F32(intensity));
    }
    let data = PointColumns {
        encoding: format!("E57 ({})", reader.format_name()),
        elements: vec![ElementSpec { name: "vertex".into(), count: n, properties }],
        vertex_columns: columns,
        vertex_types: types,
        vertex_count: n,
        ..Default::default()
    };
    Ok((data, attributes, info))
}

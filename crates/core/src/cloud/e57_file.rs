//! E57 files (ASTM E2807), read through the `e57` crate.
//!
//! Every scan of the file is read with its pose applied, so scans land in one
//! frame; spherical coordinates are turned into cartesian ones by the crate.
//! Colours (normalised to 0..1 by the crate from the file's colour limits)
//! become the splats' colours, and intensity (normalised the same way) an
//! attribute. A file whose pages fail their CRC is refused by the crate; one
//! whose scans have neither cartesian nor spherical coordinates is refused here.

use std::collections::HashMap;
use std::path::Path;

use super::CloudError;
use super::attributes::{Attributes, Values, names};
use super::file_info::FileInfo;
use super::ply::{ElementSpec, PlyData, PropertyKind, PropertySpec, Scalar};

/// Whether `path` names an E57 file.
pub fn is_e57(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("e57"))
}

fn e57_error(path: &Path, e: impl std::fmt::Display) -> CloudError {
    CloudError::content(path, format!("not a valid E57 file: {e}"))
}

/// Reads every scan of the E57 file at `path` as vertex columns and attributes.
pub fn read(path: &Path) -> Result<(PlyData, Attributes, FileInfo), CloudError> {
    crate::input::regular_size(path).map_err(|e| CloudError::io(path, e))?;
    let mut reader = e57::E57Reader::from_file(path).map_err(|e| e57_error(path, e))?;
    let scans = reader.pointclouds();
    if scans.is_empty() {
        return Err(CloudError::content(path, "the E57 file holds no point cloud"));
    }
    let with_colour = scans.iter().all(|s| s.has_color());
    let with_intensity = scans.iter().all(|s| s.has_intensity());
    let mut xyz: [Vec<f64>; 3] = Default::default();
    let mut rgb: [Vec<f64>; 3] = Default::default();
    let mut intensity = Vec::new();
    let mut invalid = 0usize;
    for (index, scan) in scans.iter().enumerate() {
        if !scan.has_cartesian() && !scan.has_spherical() {
            return Err(CloudError::content(
                path,
                format!("scan {index} of the E57 file has neither cartesian nor spherical coordinates"),
            ));
        }
        let mut points = reader.pointcloud_simple(scan).map_err(|e| e57_error(path, e))?;
        points.intensity_to_color(false);
        for point in points {
            let point = point.map_err(|e| e57_error(path, e))?;
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
    let data = PlyData {
        encoding: format!("E57 ({})", reader.format_name()),
        elements: vec![ElementSpec { name: "vertex".into(), count: n, properties }],
        vertex_columns: columns,
        vertex_types: types,
        vertex_count: n,
        ..Default::default()
    };
    Ok((data, attributes, info))
}

//! LAS and LAZ files the tests write themselves with the `las` crate (an
//! independent writer), so every lidar reader is tested on a fresh clone too.

use std::path::{Path, PathBuf};

/// One point of a test file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LidarPoint {
    pub xyz: [f64; 3],
    pub intensity: u16,
    pub class: u8,
    pub return_number: u8,
    pub returns: u8,
    pub gps_time: f64,
    pub rgb: [u16; 3],
}

/// Two [`tilted_grid`]s of `side`² points `spacing` apart (slope 0.1), the
/// second `gap` above the first, from `origin`, written as LAS/LAZ (by
/// `path`'s extension) with the offset (x, y, 0): ground and a canopy.
pub fn two_planes(path: &Path, side: usize, spacing: f64, origin: [f64; 3], gap: f64) -> PathBuf {
    let mut points = tilted_grid(side, spacing, 0.1, origin);
    points.extend(tilted_grid(side, spacing, 0.1, [origin[0], origin[1], origin[2] + gap]));
    write(path, &points, [origin[0], origin[1], 0.0], None)
}

/// A `side` x `side` grid of points `spacing` apart on the plane
/// z = slope · x, offset by `origin`, with attributes that vary by index.
pub fn tilted_grid(side: usize, spacing: f64, slope: f64, origin: [f64; 3]) -> Vec<LidarPoint> {
    let mut points = Vec::with_capacity(side * side);
    for i in 0..side {
        for j in 0..side {
            let (x, y) = (i as f64 * spacing, j as f64 * spacing);
            let k = points.len();
            points.push(LidarPoint {
                xyz: [origin[0] + x, origin[1] + y, origin[2] + slope * x],
                intensity: (k * 37 % 4000) as u16,
                class: [2, 5, 6][k % 3],
                return_number: 1 + (k % 3) as u8,
                returns: 3,
                gps_time: 1000.0 + k as f64 * 0.25,
                rgb: [(k * 101 % 65536) as u16, (k * 7 % 65536) as u16, 40000],
            });
        }
    }
    points
}

/// Writes `points` as LAS 1.4 format 7 (`.las`) or LAZ (`.laz`) with scale
/// 0.001 and the given offset; `extra` adds an f32 extra-bytes attribute of
/// that name, whose value is the point's index.
pub fn write(path: &Path, points: &[LidarPoint], offset: [f64; 3], extra: Option<&str>) -> PathBuf {
    let fields: Vec<ExtraField> = extra.map(|name| ExtraField { name, scale: None }).into_iter().collect();
    write_fields(path, points, offset, &fields)
}

/// One f32 extra-bytes field: its name and, when given, the scale its
/// descriptor states (option bit 3).
#[derive(Debug, Clone, Copy)]
pub struct ExtraField<'a> {
    pub name: &'a str,
    pub scale: Option<f64>,
}

/// [`write`] with any number of f32 extra-bytes fields, each described in
/// the one `LASF_Spec` record; field j of point k holds k · (j + 1).
pub fn write_fields(path: &Path, points: &[LidarPoint], offset: [f64; 3], fields: &[ExtraField]) -> PathBuf {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(7).unwrap();
    builder.point_format.is_compressed = path.extension().is_some_and(|e| e == "laz");
    if !fields.is_empty() {
        builder.point_format.extra_bytes = 4 * fields.len() as u16;
        let mut data = Vec::new();
        for field in fields {
            let mut d = vec![0u8; 192];
            d[2] = 9;
            d[4..4 + field.name.len()].copy_from_slice(field.name.as_bytes());
            if let Some(scale) = field.scale {
                d[3] |= 8;
                d[112..120].copy_from_slice(&scale.to_le_bytes());
            }
            data.extend(d);
        }
        builder.vlrs.push(las::Vlr { user_id: "LASF_Spec".into(), record_id: 4, description: "extra".into(), data });
    }
    for (t, o) in
        [&mut builder.transforms.x, &mut builder.transforms.y, &mut builder.transforms.z].into_iter().zip(offset)
    {
        *t = las::Transform { scale: 0.001, offset: o };
    }
    let count = fields.len();
    write_points(path, builder, points, |k| (0..count).flat_map(|j| ((k * (j + 1)) as f32).to_le_bytes()).collect())
}

/// A CRS record to write: a WKT text, or GeoTIFF keys as (key id, value).
pub enum CrsRecord<'a> {
    Wkt(&'a str),
    GeoTiffKeys(&'a [(u16, u16)]),
}

/// [`write_colourless`] with a CRS record (the WKT's with the header's WKT bit set).
pub fn write_with_crs(path: &Path, points: &[LidarPoint], offset: [f64; 3], crs: CrsRecord) -> PathBuf {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(6).unwrap();
    for (t, o) in
        [&mut builder.transforms.x, &mut builder.transforms.y, &mut builder.transforms.z].into_iter().zip(offset)
    {
        *t = las::Transform { scale: 0.001, offset: o };
    }
    let (record_id, data) = match crs {
        CrsRecord::Wkt(text) => (2112, text.as_bytes().to_vec()),
        CrsRecord::GeoTiffKeys(keys) => {
            // The key directory: version 1.1.0 and the key count, then per key (id, in place, count 1, value).
            let mut words = vec![1u16, 1, 0, keys.len() as u16];
            for &(id, value) in keys {
                words.extend([id, 0, 1, value]);
            }
            (34735, words.iter().flat_map(|w| w.to_le_bytes()).collect())
        }
    };
    builder.vlrs.push(las::Vlr { user_id: "LASF_Projection".into(), record_id, description: "crs".into(), data });
    builder.has_wkt_crs = record_id == 2112;
    write_points(path, builder, points, |_| Vec::new())
}

/// Writes `points` as LAS 1.4 point format 6 (no colours, as most airborne
/// lidar comes) with scale 0.001 and the given offset.
pub fn write_colourless(path: &Path, points: &[LidarPoint], offset: [f64; 3]) -> PathBuf {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(6).unwrap();
    for (t, o) in
        [&mut builder.transforms.x, &mut builder.transforms.y, &mut builder.transforms.z].into_iter().zip(offset)
    {
        *t = las::Transform { scale: 0.001, offset: o };
    }
    write_points(path, builder, points, |_| Vec::new())
}

/// Writes `points` as LAS 1.2 point format 3 (RGB and GPS time), with scale
/// 0.001 and no offset: the layout of the oldest files still made.
pub fn write_las12(path: &Path, points: &[LidarPoint]) -> PathBuf {
    let mut builder = las::Builder::from((1, 2));
    builder.point_format = las::point::Format::new(3).unwrap();
    for t in [&mut builder.transforms.x, &mut builder.transforms.y, &mut builder.transforms.z] {
        *t = las::Transform { scale: 0.001, offset: 0.0 };
    }
    write_points(path, builder, points, |_| Vec::new())
}

fn write_points(
    path: &Path,
    builder: las::Builder,
    points: &[LidarPoint],
    extra_bytes: impl Fn(usize) -> Vec<u8>,
) -> PathBuf {
    let has_colour = builder.point_format.has_color;
    let header = builder.into_header().unwrap();
    let mut writer = las::Writer::from_path(path, header).unwrap();
    for (k, p) in points.iter().enumerate() {
        writer
            .write_point(las::Point {
                x: p.xyz[0],
                y: p.xyz[1],
                z: p.xyz[2],
                intensity: p.intensity,
                return_number: p.return_number,
                number_of_returns: p.returns,
                classification: las::point::Classification::new(p.class).unwrap(),
                gps_time: Some(p.gps_time),
                color: has_colour.then(|| las::Color::new(p.rgb[0], p.rgb[1], p.rgb[2])),
                extra_bytes: extra_bytes(k),
                ..Default::default()
            })
            .unwrap();
    }
    writer.close().unwrap();
    path.to_path_buf()
}

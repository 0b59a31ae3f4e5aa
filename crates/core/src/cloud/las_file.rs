//! LAS and LAZ files (ASPRS LAS 1.0-1.4, point formats 0-10), read through
//! the `las` crate with parallel LAZ decompression.
//!
//! The crate decodes the header, the VLRs and the records into a byte slab
//! (`PointData`), read here in batches so memory grows with the points the
//! file really holds, not with its header's count. A LAZ file whose chunk
//! table accounts for every point is decoded chunk by chunk on every core,
//! each chunk straight into its rows of the columns ([`laz_chunks`]). Coordinates come out in
//! f64 (scale and offset applied) and go through the same re-centring as PLY
//! positions. Columns become [`Attributes`]: intensity, classification and
//! its flags, returns, GPS time, point source ID, user data, scan angle, NIR
//! and every named extra-bytes attribute. A column that is zero at every point
//! carries nothing and is not kept. 16-bit RGB is scaled to 8 bits, unless
//! every value is at most 255 (files that store 8-bit colour in 16-bit fields).
//!
//! The `las` crate does not decode the LAS 1.4 extra-bytes descriptors (the
//! `LASF_Spec` VLR 4): it hands each record's extra bytes over as they are.
//! Extra bytes named `nx`, `ny`, `nz`, `radius` or `alpha` (what `convert`
//! writes) are the splats' own normals, radii and opacity.
//! [`extra_bytes`] reads the descriptors (192 bytes each, fixed layout) and
//! the values they describe.
//!
//! Neither crate checks the sizes a file states before it allocates or seeks
//! by them, so every file is opened through [`open`] ([`precheck`]), which
//! checks the header, the records and the point count against the file's
//! length, and the LAZ chunk table and chunks ([`laz_check`]) against the
//! bytes that hold them. Those two and [`extra_bytes`] are the hand-written
//! parts.

use std::collections::HashMap;
use std::path::Path;

use rayon::prelude::*;

use super::CloudError;
use super::attributes::{Attributes, Values, names};
use super::file_info::FileInfo;
use super::ply::{ElementSpec, PointColumns, PropertyKind, PropertySpec, Scalar};

mod column_rows;
pub(crate) mod extra_bytes;
mod held_columns;
pub(crate) mod laz_check;
mod laz_chunks;
mod precheck;

pub(crate) use precheck::open;

/// Points decoded per batch, and the most bytes a batch may take (records can be 64 KiB with extra bytes).
const BATCH: u64 = 1 << 20;
const BATCH_BYTES: u64 = 64 << 20;

/// Whether `path` names a LAS or LAZ file (`.copc.laz` included), by the format registry.
pub fn is_las(path: &Path) -> bool {
    use crate::formats::Reader;
    crate::formats::format_of(path).is_some_and(|f| matches!(f.reader, Reader::Las | Reader::Copc))
}

fn las_error(path: &Path, e: impl std::fmt::Display) -> CloudError {
    CloudError::content(path, format!("not a valid LAS/LAZ file: {e}"))
}

/// A `las` crate error as one line; a read past the end says the file is cut short.
fn crate_error(path: &Path, e: las::Error) -> CloudError {
    match e {
        las::Error::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            las_error(path, "the file ends early (truncated?)")
        }
        // The LAZ decoder wraps the same end-of-file error (read_exact's message) in its own type.
        e if e.to_string().ends_with("failed to fill whole buffer") => {
            las_error(path, "the file ends early (truncated?)")
        }
        e => las_error(path, e),
    }
}

/// A `las` crate error met while decoding points. The chunks of a LAZ file
/// opened through [`open`] all lie within the file, so a read past a chunk's
/// end (or past the last chunk) is corrupt data, not a short file.
pub(crate) fn points_error(path: &Path, e: las::Error, compressed: bool) -> CloudError {
    let text = e.to_string();
    let past_end = matches!(&e, las::Error::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof)
        || text.ends_with("failed to fill whole buffer")
        || text.ends_with("no chunks available in chunk table");
    if compressed && past_end {
        las_error(
            path,
            "the LAZ points do not decode (corrupt compressed data, or a header that counts more points than the chunks hold)",
        )
    } else {
        crate_error(path, e)
    }
}

/// Reads the LAS or LAZ file at `path` as vertex columns (x, y, z and, with
/// colour, red, green, blue) and the other per-point attributes.
pub fn read(path: &Path) -> Result<(PointColumns, Attributes, FileInfo), CloudError> {
    let decoded = read_columns(path)?;
    let header = &decoded.header;
    let format = *header.point_format();
    let mut info = FileInfo {
        details: details(header),
        crs: crs(header),
        warnings: decoded.warnings.clone(),
        from_above: true,
        z_up: true,
        units: crs_units(header),
    };
    let compression = if format.is_compressed { ", LAZ-compressed" } else { "" };
    let encoding = format!("LAS {}, point format {}{}", header.version(), format.to_u8().unwrap_or(255), compression);
    let (data, attributes) = decoded.columns.finish(&decoded.fields, encoding, &mut info.warnings);
    Ok((data, attributes, info))
}

/// A LAS or LAZ file's records as columns, not yet finished into attributes.
pub(crate) struct Decoded {
    pub(crate) columns: Columns,
    pub(crate) header: las::Header,
    /// The extra-bytes fields each record carries.
    pub(crate) fields: Vec<extra_bytes::Field>,
    /// What reading its descriptors found wrong.
    pub(crate) warnings: Vec<String>,
    /// The file's length in bytes.
    pub(crate) file_len: u64,
}

/// Decodes every record of the LAS or LAZ file at `path` into columns,
/// through [`open`]'s checks, in batches.
pub(crate) fn read_columns(path: &Path) -> Result<Decoded, CloudError> {
    let (mut reader, file_len) = open(path)?;
    let header = reader.header().clone();
    let format = *header.point_format();
    let transforms = *header.transforms();
    for (axis, t) in [("x", transforms.x), ("y", transforms.y), ("z", transforms.z)] {
        if !(t.scale.is_finite() && t.scale != 0.0 && t.offset.is_finite()) {
            return Err(las_error(path, format!("the {axis} scale is {} and offset {}", t.scale, t.offset)));
        }
    }
    let declared = header.number_of_points();
    let record_len = format.len() as u64;
    let descriptors = extra_bytes::descriptors(&header, format.extra_bytes).map_err(|e| las_error(path, e))?;
    if let Some(columns) = laz_chunks::decode(path, &header, &descriptors.fields) {
        return Ok(Decoded { columns, header, fields: descriptors.fields, warnings: descriptors.warnings, file_len });
    }
    let mut columns = Columns::default();
    let mut batch = las::PointDataBuilder::new().for_header(&header).build();
    // A LAZ file decodes to at most ~64 times its size (real ones: 5-15 times), so a
    // lying count costs no more than that.
    let batch_bytes =
        if format.is_compressed { BATCH_BYTES.min(file_len.saturating_mul(64).max(1 << 20)) } else { BATCH_BYTES };
    let batch_points = BATCH.min(batch_bytes / record_len.max(1)).max(1);
    let mut read_so_far = 0u64;
    while read_so_far < declared {
        let n = reader.fill_points(batch_points.min(declared - read_so_far), &mut batch).map_err(
            |e| match points_error(path, e, format.is_compressed) {
                CloudError::Content { reason, .. } => las_error(
                    path,
                    format!(
                        "after {read_so_far} of {declared} points, {}",
                        reason.trim_start_matches("not a valid LAS/LAZ file: ")
                    ),
                ),
                other => other,
            },
        )?;
        if n == 0 {
            break;
        }
        columns.append(&batch, &descriptors.fields);
        read_so_far += n;
    }
    if read_so_far < declared {
        return Err(las_error(
            path,
            format!("the header counts {declared} points but the file holds only {read_so_far} (truncated?)"),
        ));
    }
    Ok(Decoded { columns, header, fields: descriptors.fields, warnings: descriptors.warnings, file_len })
}

/// The columns decoded so far.
#[derive(Default, Clone, PartialEq)]
pub(crate) struct Columns {
    pub(crate) x: Vec<f64>,
    pub(crate) y: Vec<f64>,
    pub(crate) z: Vec<f64>,
    rgb: Option<[Vec<u16>; 3]>,
    intensity: Vec<u16>,
    classification: Vec<u8>,
    flags: Vec<u8>,
    return_number: Vec<u8>,
    number_of_returns: Vec<u8>,
    gps_time: Option<Vec<f64>>,
    point_source_id: Vec<u16>,
    user_data: Vec<u8>,
    scan_angle: Vec<f32>,
    nir: Option<Vec<u16>>,
    extra: Vec<Vec<f64>>,
}

impl Columns {
    /// Appends `batch`'s columns, each in a task of its own: every column is
    /// a strided pass over the records, and the passes run on all cores
    /// (on 2 cores, a 2M-point LAZ's 65 ms of them took 37 ms).
    pub(crate) fn append(&mut self, batch: &las::PointData, fields: &[extra_bytes::Field]) {
        let from = self.len();
        self.grow(batch.len(), batch.format(), fields.len());
        let rows = self.rows_from(from);
        rayon::scope(|s| rows.fill(batch, fields, &mut |job| s.spawn(move |_| job())));
    }

    /// Points held.
    pub(crate) fn len(&self) -> usize {
        self.x.len()
    }

    /// Bytes held, for the cache's accounting.
    pub(crate) fn bytes(&self) -> usize {
        let n = self.len();
        // The LAS columns a PLY or E57 file held whole lacks are empty.
        let standard = 2 * self.intensity.len()
            + self.classification.len()
            + self.flags.len()
            + self.return_number.len()
            + self.number_of_returns.len()
            + 2 * self.point_source_id.len()
            + self.user_data.len()
            + 4 * self.scan_angle.len();
        n * 3 * 8
            + standard
            + self.rgb.as_ref().map_or(0, |_| 6 * n)
            + self.gps_time.as_ref().map_or(0, |_| 8 * n)
            + self.nir.as_ref().map_or(0, |_| 2 * n)
            + self.extra.len() * 8 * n
    }

    /// Appends `other`'s points (decoded from the same file).
    pub(crate) fn extend(&mut self, other: &Columns) {
        self.x.extend_from_slice(&other.x);
        self.y.extend_from_slice(&other.y);
        self.z.extend_from_slice(&other.z);
        if let Some(rgb) = &other.rgb {
            let mine = self.rgb.get_or_insert_with(Default::default);
            for (m, o) in mine.iter_mut().zip(rgb) {
                m.extend_from_slice(o);
            }
        }
        self.intensity.extend_from_slice(&other.intensity);
        self.classification.extend_from_slice(&other.classification);
        self.flags.extend_from_slice(&other.flags);
        self.return_number.extend_from_slice(&other.return_number);
        self.number_of_returns.extend_from_slice(&other.number_of_returns);
        if let Some(t) = &other.gps_time {
            self.gps_time.get_or_insert_with(Vec::new).extend_from_slice(t);
        }
        self.point_source_id.extend_from_slice(&other.point_source_id);
        self.user_data.extend_from_slice(&other.user_data);
        self.scan_angle.extend_from_slice(&other.scan_angle);
        if let Some(n) = &other.nir {
            self.nir.get_or_insert_with(Vec::new).extend_from_slice(n);
        }
        if self.extra.len() < other.extra.len() {
            self.extra.resize_with(other.extra.len(), Vec::new);
        }
        for (m, o) in self.extra.iter_mut().zip(&other.extra) {
            m.extend_from_slice(o);
        }
    }

    /// The points at `indices`, in that order (a node of a file opened whole).
    pub(crate) fn gather(&self, indices: &[u32]) -> Columns {
        fn pick<T: Copy>(column: &[T], indices: &[u32]) -> Vec<T> {
            // Empty: a LAS column that a PLY or E57 file held whole lacks.
            if column.is_empty() {
                return Vec::new();
            }
            indices.iter().map(|&i| column[i as usize]).collect()
        }
        let some = |column: &Option<Vec<_>>| column.as_ref().map(|c| pick(c, indices));
        Columns {
            x: pick(&self.x, indices),
            y: pick(&self.y, indices),
            z: pick(&self.z, indices),
            rgb: self.rgb.as_ref().map(|c| c.each_ref().map(|c| pick(c, indices))),
            intensity: pick(&self.intensity, indices),
            classification: pick(&self.classification, indices),
            flags: pick(&self.flags, indices),
            return_number: pick(&self.return_number, indices),
            number_of_returns: pick(&self.number_of_returns, indices),
            gps_time: some(&self.gps_time),
            point_source_id: pick(&self.point_source_id, indices),
            user_data: pick(&self.user_data, indices),
            scan_angle: pick(&self.scan_angle, indices),
            nir: self.nir.as_ref().map(|c| pick(c, indices)),
            extra: self.extra.iter().map(|c| pick(c, indices)).collect(),
        }
    }

    /// The vertex columns (positions and colours) and the attributes kept.
    pub(crate) fn finish(
        self,
        fields: &[extra_bytes::Field],
        encoding: String,
        warnings: &mut Vec<String>,
    ) -> (PointColumns, Attributes) {
        let n = self.x.len();
        let mut vertex_columns = HashMap::new();
        let mut vertex_types = HashMap::new();
        let mut properties = Vec::new();
        for (name, column) in [("x", self.x), ("y", self.y), ("z", self.z)] {
            vertex_columns.insert(name.to_string(), column);
            vertex_types.insert(name.to_string(), Scalar::F64);
            properties.push(name);
        }
        if let Some(rgb) = self.rgb {
            // 8-bit colour stored in 16-bit fields is common: keep it as it is.
            let eight_bit = rgb.iter().all(|c| c.iter().all(|&v| v <= 255));
            let kind = if eight_bit { Scalar::U8 } else { Scalar::U16 };
            if eight_bit && rgb.iter().all(|c| c.iter().all(|&v| v == 0)) {
                warnings.push("every RGB value is 0 (an unused channel); the default colour is used".into());
            } else {
                for (name, column) in ["red", "green", "blue"].into_iter().zip(rgb) {
                    vertex_columns.insert(name.to_string(), column.par_iter().map(|&v| f64::from(v)).collect());
                    vertex_types.insert(name.to_string(), kind);
                    properties.push(name);
                }
            }
        }
        let mut attributes = Attributes::default();
        let mut keep = |name: &str, values: Values| {
            if values.any_nonzero() {
                attributes.push(name, values);
            }
        };
        keep(names::INTENSITY, Values::U16(self.intensity));
        keep(names::CLASSIFICATION, Values::U8(self.classification));
        keep(names::CLASSIFICATION_FLAGS, Values::U8(self.flags));
        keep(names::RETURN_NUMBER, Values::U8(self.return_number));
        keep(names::NUMBER_OF_RETURNS, Values::U8(self.number_of_returns));
        if let Some(t) = self.gps_time {
            keep(names::GPS_TIME, Values::F64(t));
        }
        keep(names::POINT_SOURCE_ID, Values::U16(self.point_source_id));
        keep(names::USER_DATA, Values::U8(self.user_data));
        keep(names::SCAN_ANGLE, Values::F32(self.scan_angle));
        if let Some(nir) = self.nir {
            keep(names::NIR, Values::U16(nir));
        }
        for (values, field) in self.extra.into_iter().zip(fields) {
            if let Some(kind) = field.vertex {
                // A vertex column of a PLY or E57 file held whole, in its own type.
                vertex_types.insert(field.name.clone(), kind);
                properties.push(field.name.as_str());
                vertex_columns.insert(field.name.clone(), values);
            } else if super::write_las::SPLAT_FIELDS.contains(&field.name.as_str()) {
                // A splat's own normal, radius or opacity (as `convert` writes them).
                vertex_types.insert(field.name.clone(), Scalar::F32);
                properties.push(field.name.as_str());
                vertex_columns.insert(field.name.clone(), values);
            } else {
                attributes.push(field.name.clone(), field.narrowest(values));
            }
        }
        let data = PointColumns {
            encoding,
            elements: vec![ElementSpec {
                name: "vertex".into(),
                count: n,
                properties: properties
                    .iter()
                    .map(|p| PropertySpec { name: p.to_string(), kind: PropertyKind::Scalar(vertex_types[*p]) })
                    .collect(),
            }],
            vertex_columns,
            vertex_types,
            vertex_count: n,
            ..Default::default()
        };
        (data, attributes)
    }
}

/// The classification flags of a record: bit 1 synthetic, 2 key-point, 4 withheld, 8 overlap.
fn classification_flags(record: &[u8], extended: bool) -> u8 {
    if extended {
        record[15] & 0x0f
    } else {
        // Formats 0-5: the top three bits of the classification byte; no overlap flag
        // (class 12 stood for overlap then).
        record[15] >> 5
    }
}

/// The header lines `info` prints: point format, scale, offset, counts, software.
pub(crate) fn details(header: &las::Header) -> Vec<String> {
    let t = header.transforms();
    let format = header.point_format();
    let mut lines = vec![
        format!(
            "point format {} ({} bytes per record, {} extra)",
            format.to_u8().unwrap_or(255),
            format.len(),
            format.extra_bytes
        ),
        format!(
            "scale ({}, {}, {}), offset ({}, {}, {})",
            t.x.scale, t.y.scale, t.z.scale, t.x.offset, t.y.offset, t.z.offset
        ),
    ];
    let software = header.generating_software().trim_matches(char::from(0)).trim();
    if !software.is_empty() {
        lines.push(format!("made by {software}"));
    }
    lines
}

/// The units and EPSG code of the CRS the header's VLRs declare: from the
/// WKT text, else from the GeoTIFF keys.
pub(crate) fn crs_units(header: &las::Header) -> super::crs_units::CrsUnits {
    use super::crs_units::CrsUnits;
    if let Some(wkt) = header.get_wkt_crs_bytes() {
        let text = String::from_utf8_lossy(wkt);
        let text = text.trim_matches(char::from(0)).trim();
        if !text.is_empty() {
            return CrsUnits::from_wkt(text);
        }
    }
    let Some(geotiff) = header.get_geotiff_crs().ok().flatten() else { return CrsUnits::default() };
    let keys: Vec<(u16, u16)> = geotiff
        .entries
        .iter()
        .filter_map(|e| if let las::crs::GeoTiffData::U16(v) = e.data { Some((e.id, v)) } else { None })
        .collect();
    CrsUnits::from_geotiff_keys(&keys)
}

/// The CRS the header's VLRs declare: the WKT text, else the GeoTIFF keys' EPSG codes.
pub(crate) fn crs(header: &las::Header) -> Option<String> {
    if let Some(wkt) = header.get_wkt_crs_bytes() {
        let text = String::from_utf8_lossy(wkt).trim_matches(char::from(0)).trim().to_string();
        if !text.is_empty() {
            return Some(text);
        }
    }
    let geotiff = header.get_geotiff_crs().ok().flatten()?;
    let mut parts = Vec::new();
    if let Some(code) = geotiff.get_projected_crs_geo_key_value() {
        parts.push(format!("projected EPSG:{code}"));
    }
    if let Some(code) = geotiff.get_geodetic_crs_geo_key_value() {
        parts.push(format!("geographic EPSG:{code}"));
    }
    if let Some(code) = geotiff.get_vertical_crs_geo_key_value() {
        parts.push(format!("vertical EPSG:{code}"));
    }
    Some(if parts.is_empty() {
        "GeoTIFF keys without an EPSG code".to_string()
    } else {
        format!("GeoTIFF keys: {}", parts.join(", "))
    })
}

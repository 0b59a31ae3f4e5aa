//! Writing clouds as LAS 1.4 or LAZ (by the target's extension), through the
//! `las` crate, so scans go back to the tools their users have.
//!
//! Point format 7 (RGB and GPS time), or 8 when the cloud has NIR. The
//! standard fields come from the attributes of the same names (intensity,
//! classification and its flags, returns, GPS time, scan angle, user data,
//! point source ID); every other attribute, and the splat's normal, radius
//! and opacity, go into extra bytes described by a `LASF_Spec` record 4, so
//! a round trip through LAS keeps every channel. Coordinates are written as
//! integers of a power-of-ten scale fine enough for the cloud's f32
//! resolution, offset by its f64 origin. The file is written beside the
//! target and renamed, so a failed write leaves nothing; the writer is
//! finished explicitly ([`sink`]), so a full disk is an error, not a panic.

use std::path::Path;

use las::point::Classification;

use super::attributes::{Values, names};
use super::{CloudError, PointCloud};

pub mod copy_records;
mod sink;

/// The standard fields, which are not written again as extra bytes.
const STANDARD: [&str; 10] = names::LAS_STANDARD;

/// The splat's own columns, written as f32 extra bytes.
pub const SPLAT_FIELDS: [&str; 5] = ["nx", "ny", "nz", "radius", "alpha"];

/// Whether `path` should be compressed (a `.laz` name).
pub(crate) fn is_laz(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("laz"))
}

/// One extra-bytes field: its name, and the f64 of point i (written as f32 or f64).
struct Extra<'a> {
    name: &'a str,
    double: bool,
    value: Box<dyn Fn(usize) -> f64 + 'a>,
}

fn descriptor(name: &str, double: bool) -> [u8; 192] {
    let mut d = [0u8; 192];
    d[2] = if double { 10 } else { 9 };
    let bytes = name.as_bytes();
    d[4..4 + bytes.len().min(32)].copy_from_slice(&bytes[..bytes.len().min(32)]);
    d
}

/// The error of writing `path` as LAS or LAZ.
fn write_error(path: &Path, e: las::Error) -> CloudError {
    let format = if is_laz(path) { "LAZ" } else { "LAS" };
    let reason = match e {
        // The laz crate's wrapper of an I/O error adds only "IoError: ".
        las::Error::LasZipError(laz::LasZipError::IoError(io)) => io.to_string(),
        e => e.to_string(),
    };
    CloudError::content(path, format!("cannot write {format}: {reason}"))
}

/// Writes `cloud` to `path` as LAS, or LAZ when the name ends in `.laz`.
pub fn write_las(cloud: &PointCloud, path: &Path) -> Result<(), CloudError> {
    let err = |e: las::Error| write_error(path, e);
    let attrs = &cloud.attributes;
    let nir = attrs.get(names::NIR);
    let mut extras: Vec<Extra> = Vec::new();
    let unit = cloud.unit() as f32;
    extras.push(Extra { name: "nx", double: false, value: Box::new(|i| cloud.normals[i].x as f64) });
    extras.push(Extra { name: "ny", double: false, value: Box::new(|i| cloud.normals[i].y as f64) });
    extras.push(Extra { name: "nz", double: false, value: Box::new(|i| cloud.normals[i].z as f64) });
    extras.push(Extra { name: "radius", double: false, value: Box::new(move |i| (cloud.radii[i] * unit) as f64) });
    if cloud.has_transparency() {
        extras.push(Extra { name: "alpha", double: false, value: Box::new(|i| cloud.opacity[i] as f64) });
    }
    for channel in attrs.channels.iter().filter(|c| !STANDARD.contains(&c.name.as_str())) {
        let double = matches!(channel.values, Values::F64(_));
        extras.push(Extra { name: &channel.name, double, value: Box::new(move |i| channel.values.get(i)) });
    }
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(if nir.is_some() { 8 } else { 7 }).map_err(err)?;
    builder.point_format.is_compressed = is_laz(path);
    builder.point_format.extra_bytes = extras.iter().map(|e| if e.double { 8 } else { 4 }).sum::<u16>();
    builder.generating_software = "pointblend".into();
    let data: Vec<u8> = extras.iter().flat_map(|e| descriptor(e.name, e.double)).collect();
    builder.vlrs.push(las::Vlr { user_id: "LASF_Spec".into(), record_id: 4, description: "extra bytes".into(), data });
    let bounds = cloud.bounds();
    let extent = bounds.map_or(1.0, |b| (b.max - b.min).max_element() as f64 * cloud.unit()).max(1e-9);
    // Fine enough that the f32 offsets survive, coarse enough that i32 holds the extent.
    let scale = 10f64.powf((extent / 1e9).log10().ceil()).max(1e-9);
    for (axis, t) in
        [&mut builder.transforms.x, &mut builder.transforms.y, &mut builder.transforms.z].into_iter().enumerate()
    {
        *t = las::Transform { scale, offset: cloud.origin[axis] };
    }
    let header = builder.into_header().map_err(err)?;
    write_with(path, header, |writer| write_points(writer, cloud, &extras))
}

/// The writer [`write_with`] hands its filler.
type FileWriter = las::Writer<sink::Fused<std::io::BufWriter<std::fs::File>>>;

/// Writes a LAS, or LAZ when `path` ends in `.laz` (as `header` says), of
/// the points `fill` writes: into a temporary file beside `path`, closed
/// explicitly and renamed, so a failure leaves no file.
fn write_with(
    path: &Path,
    header: las::Header,
    fill: impl FnOnce(&mut FileWriter) -> las::Result<()>,
) -> Result<(), CloudError> {
    let err = |e: las::Error| write_error(path, e);
    let target = crate::output::prepare(path).map_err(|e| CloudError::io(path, e))?;
    let dir = crate::output::folder_of(&target);
    let tmp = crate::output::Temporary::new_in(dir).map_err(|e| CloudError::io(path, e))?;
    let file = tmp.reopen().map_err(|e| CloudError::io(path, e))?;
    let mut writer = las::Writer::new(sink::Fused::new(std::io::BufWriter::new(file)), header).map_err(err)?;
    let written = fill(&mut writer);
    // Always closed here: the crate's writer panics if its drop has to close it and cannot.
    sink::close(writer, written).map_err(err)?;
    crate::output::make_readable(tmp.as_file()).map_err(|e| CloudError::io(path, e))?;
    tmp.persist(&target).map_err(|e| CloudError::io(path, e))?;
    Ok(())
}

/// Writes the cloud's points, stopping at the first error.
fn write_points<W>(writer: &mut las::Writer<W>, cloud: &PointCloud, extras: &[Extra]) -> las::Result<()>
where
    W: std::io::Write + std::io::Seek + Send + Sync + 'static,
{
    let attrs = &cloud.attributes;
    let nir = attrs.get(names::NIR);
    let get = |name: &str, i: usize| attrs.get(name).map(|v| v.get(i));
    let unit = cloud.unit();
    for i in 0..cloud.len() {
        let p = cloud.positions[i];
        let flags = get(names::CLASSIFICATION_FLAGS, i).unwrap_or(0.0) as u8;
        let mut extra_bytes = Vec::with_capacity(64);
        for e in extras {
            let v = (e.value)(i);
            if e.double {
                extra_bytes.extend_from_slice(&v.to_le_bytes());
            } else {
                extra_bytes.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
        let c = cloud.colours[i];
        let point = las::Point {
            x: p.x as f64 * unit + cloud.origin[0],
            y: p.y as f64 * unit + cloud.origin[1],
            z: p.z as f64 * unit + cloud.origin[2],
            intensity: get(names::INTENSITY, i).unwrap_or(0.0) as u16,
            return_number: get(names::RETURN_NUMBER, i).unwrap_or(0.0) as u8,
            number_of_returns: get(names::NUMBER_OF_RETURNS, i).unwrap_or(0.0) as u8,
            classification: Classification::new(get(names::CLASSIFICATION, i).unwrap_or(0.0) as u8)
                .unwrap_or(Classification::CreatedNeverClassified),
            is_synthetic: flags & 1 != 0,
            is_key_point: flags & 2 != 0,
            is_withheld: flags & 4 != 0,
            is_overlap: flags & 8 != 0,
            scan_angle: get(names::SCAN_ANGLE, i).unwrap_or(0.0) as f32,
            user_data: get(names::USER_DATA, i).unwrap_or(0.0) as u8,
            point_source_id: get(names::POINT_SOURCE_ID, i).unwrap_or(0.0) as u16,
            gps_time: Some(get(names::GPS_TIME, i).unwrap_or(0.0)),
            color: Some(las::Color::new(c[0] as u16 * 257, c[1] as u16 * 257, c[2] as u16 * 257)),
            nir: nir.map(|v| v.get(i) as u16),
            extra_bytes,
            ..Default::default()
        };
        writer.write_point(point)?;
    }
    Ok(())
}

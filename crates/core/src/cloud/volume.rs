//! Scalar volumes as rendering-oriented points (Gunjee et al. §3-4: mixed
//! 3D data, volumes and surfaces rendered as one point set): one point per
//! voxel at or above a threshold, its colour and opacity from a transfer
//! function of the voxel's value, its normal from the 3D Sobel gradient
//! (pointing from higher values to lower, out of dense tissue), its radius
//! from the voxel size (half the voxel's diagonal, so neighbouring discs
//! close the surface they sample).
//!
//! NIfTI-1 files (`.nii`, `.nii.gz`) are read with the `nifti` crate's
//! streamed reader, slice by slice: memory holds three slices (the Sobel
//! window) and the points made, never the whole volume. A first pass takes
//! the value range and a sample of the values, from which the default
//! transfer function is set at the sample's percentiles; the second makes
//! the points. Positions are voxel index × voxel size, in metres when the
//! file says its unit (mm and µm are converted), else in the file's units.

use std::path::Path;
use std::str::FromStr;

use glam::Vec3;
use nifti::volume::RandomAccessNiftiVolume;
use nifti::{NiftiObject, ReaderStreamedOptions};

use super::PointCloud;
use super::error::one_line;

/// A volume that cannot be turned into points, said in one line.
#[derive(Debug, thiserror::Error)]
pub enum VolumeError {
    #[error("{path}: cannot read the volume: {message}")]
    Read { path: String, message: String },
    #[error("{path}: a volume of {dims} voxels is not a 3D scalar volume")]
    Shape { path: String, dims: String },
    #[error("{path}: the header's dim[{index}] is {value}: a volume needs at least one voxel along each axis")]
    NoVoxels { path: String, index: usize, value: i16 },
    #[error("{path}: no voxel reaches the threshold {threshold} (values span {min}..{max})")]
    Empty { path: String, threshold: f32, min: f32, max: f32 },
    #[error(
        "{path}: no voxel has a finite value (the header scales them by scl_slope {slope}, plus scl_inter {inter})"
    )]
    NoValues { path: String, slope: f32, inter: f32 },
    #[error("{path}: {field} is {value}, not a voxel size")]
    VoxelSize { path: String, field: String, value: f32 },
    #[error("{path}: {points} points need about {need}, more than the {free} free; raise --threshold")]
    TooLarge { path: String, points: u64, need: String, free: String },
}

/// A transfer function: values to colour and opacity, linear between stops
/// and constant beyond the first and the last.
#[derive(Debug, Clone, PartialEq)]
pub struct Transfer {
    /// (value, [r, g, b] 0..1, opacity 0..1), values increasing.
    stops: Vec<(f32, [f32; 3], f32)>,
}

impl FromStr for Transfer {
    type Err = String;

    /// `v0:r/g/b/a,v1:r/g/b/a,…`: values increasing, r, g, b in 0..255, a in 0..1.
    fn from_str(text: &str) -> Result<Self, String> {
        let bad = |what: &str| format!("transfer function '{text}': {what}");
        let mut stops = Vec::new();
        for stop in text.split(',') {
            let (value, rgba) = stop.split_once(':').ok_or_else(|| bad(&format!("'{stop}' is not VALUE:R/G/B/A")))?;
            let value: f32 = value
                .trim()
                .parse()
                .ok()
                .filter(|v: &f32| v.is_finite())
                .ok_or_else(|| bad(&format!("'{value}' is not a value")))?;
            let parts: Vec<f32> = rgba.split('/').map(|c| c.trim().parse::<f32>().unwrap_or(f32::NAN)).collect();
            let [r, g, b, a] = parts[..] else { return Err(bad(&format!("'{rgba}' is not R/G/B/A"))) };
            if ![r, g, b].iter().all(|c| (0.0..=255.0).contains(c)) || !(0.0..=1.0).contains(&a) {
                return Err(bad(&format!("'{rgba}' is out of range (R, G, B in 0..255, A in 0..1)")));
            }
            if stops.last().is_some_and(|&(last, _, _)| value <= last) {
                return Err(bad("values must increase"));
            }
            stops.push((value, [r / 255.0, g / 255.0, b / 255.0], a));
        }
        if stops.iter().all(|s| s.2 == 0.0) {
            return Err(bad("every stop has opacity 0, so every voxel would be invisible"));
        }
        Ok(Self { stops })
    }
}

impl Transfer {
    /// Colour (0..1) and opacity at `value`.
    pub fn at(&self, value: f32) -> ([f32; 3], f32) {
        let first = self.stops[0];
        if value <= first.0 {
            return (first.1, first.2);
        }
        for pair in self.stops.windows(2) {
            let ((v0, c0, a0), (v1, c1, a1)) = (pair[0], pair[1]);
            if value <= v1 {
                let t = (value - v0) / (v1 - v0);
                let mix = |a: f32, b: f32| a + (b - a) * t;
                return ([mix(c0[0], c1[0]), mix(c0[1], c1[1]), mix(c0[2], c1[2])], mix(a0, a1));
            }
        }
        let last = self.stops[self.stops.len() - 1];
        (last.1, last.2)
    }

    /// The least value at which opacity is above zero (the default threshold).
    pub fn first_visible(&self) -> f32 {
        let first = self.stops.iter().position(|s| s.2 > 0.0).unwrap_or(self.stops.len() - 1);
        if first == 0 { self.stops[0].0 } else { self.stops[first - 1].0 }
    }

    /// The default: invisible up to the 60th percentile of the values, a faint
    /// warm grey by the 80th, and a brighter, more opaque white at the 99th
    /// (soft tissue faint, dense tissue stronger, for MRI and CT alike).
    pub fn default_for(p60: f32, p80: f32, p99: f32) -> Self {
        let p80 = p80.max(p60 + f32::EPSILON * p60.abs().max(1.0));
        let p99 = p99.max(p80 + f32::EPSILON * p80.abs().max(1.0));
        Self {
            stops: vec![
                (p60, [0.80, 0.55, 0.45], 0.0),
                (p80, [0.90, 0.75, 0.65], 0.25),
                (p99, [1.00, 0.97, 0.92], 0.7),
            ],
        }
    }

    /// The text form `from_str` reads.
    pub fn to_text(&self) -> String {
        let stops: Vec<String> = self
            .stops
            .iter()
            .map(|(v, c, a)| format!("{v}:{:.0}/{:.0}/{:.0}/{a:.2}", c[0] * 255.0, c[1] * 255.0, c[2] * 255.0))
            .collect();
        stops.join(",")
    }
}

/// How a volume becomes points.
#[derive(Debug, Clone, Default)]
pub struct VolumeOptions {
    /// The transfer function (default: [`Transfer::default_for`] the values).
    pub transfer: Option<Transfer>,
    /// Least value that makes a point (default: where the transfer function's opacity rises above 0).
    pub threshold: Option<f32>,
    pub progress: bool,
}

/// What a conversion met.
#[derive(Debug, Clone)]
pub struct VolumeReport {
    pub dims: [usize; 3],
    /// Voxel size, in the units of the points.
    pub voxel: [f32; 3],
    /// "m" when the file said its unit, else "file units".
    pub units: &'static str,
    pub transfer: Transfer,
    pub threshold: f32,
    pub range: (f32, f32),
}

fn read_error(path: &Path, e: impl std::fmt::Display) -> VolumeError {
    VolumeError::Read { path: path.display().to_string(), message: one_line(&e.to_string()) }
}

/// The slices of a volume, one after another, as f32 (z = slice index).
struct Slices {
    volume: nifti::volume::streamed::StreamedNiftiVolume<nifti::object::MaybeGzDecodedFile>,
    dims: [usize; 3],
}

impl Slices {
    fn open(path: &Path) -> Result<(Self, nifti::NiftiHeader), VolumeError> {
        crate::input::regular_size(path).map_err(|e| read_error(path, e))?;
        check_dims(path)?;
        // Slices of rank 2 whatever the volume's rank, so a 4D file of one time step reads as 3D.
        let object = ReaderStreamedOptions::new().read_file_rank(path, 2).map_err(|e| read_error(path, e))?;
        let header = object.header().clone();
        let volume = object.into_volume();
        let dim = volume.dim().to_vec();
        let extra: usize = dim.iter().skip(3).map(|&d| d as usize).product();
        if dim.len() < 3 || extra != 1 || dim[..3].contains(&0) {
            let dims = dim.iter().map(u16::to_string).collect::<Vec<_>>().join("x");
            return Err(VolumeError::Shape { path: path.display().to_string(), dims });
        }
        let dims = [dim[0] as usize, dim[1] as usize, dim[2] as usize];
        Ok((Self { volume, dims }, header))
    }

    /// The next slice (x fastest), or None at the end.
    fn next(&mut self, path: &Path, out: &mut Vec<f32>) -> Result<bool, VolumeError> {
        let Some(slice) = self.volume.next() else { return Ok(false) };
        let slice = slice.map_err(|e| read_error(path, e))?;
        out.clear();
        for y in 0..self.dims[1] as u16 {
            for x in 0..self.dims[0] as u16 {
                out.push(slice.get_f64(&[x, y]).map_err(|e| read_error(path, e))? as f32);
            }
        }
        Ok(true)
    }
}

/// The largest voxel side read, in the file's units (a kilometre in millimetres).
const MAX_VOXEL_SIZE: f32 = 1e6;

/// A NIfTI-1 header's dimensions, checked before the reader sees them: it
/// reports a zero dim[i] as the field before it. Other headers (NIfTI-2) are
/// left to the reader.
fn check_dims(path: &Path) -> Result<(), VolumeError> {
    use std::io::Read;
    let mut header = [0u8; 56];
    let read = std::fs::File::open(path).and_then(|mut f| f.read_exact(&mut header));
    if read.is_err() {
        return Ok(()); // too short or unreadable: the reader says so
    }
    let i16_at = |at: usize, big: bool| {
        let bytes = [header[at], header[at + 1]];
        if big { i16::from_be_bytes(bytes) } else { i16::from_le_bytes(bytes) }
    };
    let i32_at = |big: bool| {
        let bytes = [header[0], header[1], header[2], header[3]];
        if big { i32::from_be_bytes(bytes) } else { i32::from_le_bytes(bytes) }
    };
    let Some(big) = [false, true].into_iter().find(|&big| i32_at(big) == 348) else { return Ok(()) };
    let rank = i16_at(40, big);
    if !(1..=7).contains(&rank) {
        return Ok(());
    }
    for i in 1..=(rank as usize).min(3) {
        let d = i16_at(40 + 2 * i, big);
        if d <= 0 {
            return Err(VolumeError::NoVoxels { path: path.display().to_string(), index: i, value: d });
        }
    }
    Ok(())
}

/// Every how many voxels the first pass keeps a value for the percentiles.
const SAMPLE_TARGET: usize = 1 << 20;

/// Bytes one point takes while converting and writing.
const BYTES_PER_POINT: u64 = 64;

/// Reads the NIfTI volume at `path` and makes its points.
pub fn volume_to_points(path: &Path, options: &VolumeOptions) -> Result<(PointCloud, VolumeReport), VolumeError> {
    // Pass 1: range and a sample of the values.
    let (mut slices, header) = Slices::open(path)?;
    let dims = slices.dims;
    let total = dims.iter().product::<usize>();
    let every = (total / SAMPLE_TARGET).max(1);
    let bar = crate::progress::bar(2 * dims[2] as u64, &format!("volume {}", path.display()), options.progress);
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    let mut sample = Vec::new();
    let mut count = 0usize;
    let mut slice = Vec::new();
    while slices.next(path, &mut slice)? {
        for &v in slice.iter().filter(|v| v.is_finite()) {
            (lo, hi) = (lo.min(v), hi.max(v));
            if count % every == 0 {
                sample.push(v);
            }
            count += 1;
        }
        bar.inc(1);
    }
    if count == 0 {
        return Err(VolumeError::NoValues {
            path: path.display().to_string(),
            slope: header.scl_slope,
            inter: header.scl_inter,
        });
    }
    sample.sort_unstable_by(f32::total_cmp);
    let percentile = |p: f32| sample.get(((sample.len() as f32 - 1.0) * p) as usize).copied().unwrap_or(0.0);
    let transfer = options
        .transfer
        .clone()
        .unwrap_or_else(|| Transfer::default_for(percentile(0.6), percentile(0.8), percentile(0.99)));
    let threshold = options.threshold.unwrap_or_else(|| transfer.first_visible());
    let at_least = sample.iter().filter(|&&v| v >= threshold).count() as u64 * every as u64;
    let need = at_least * BYTES_PER_POINT;
    if let Some(free) = crate::memory::available_bytes().filter(|&free| need > free / 2) {
        return Err(VolumeError::TooLarge {
            path: path.display().to_string(),
            points: at_least,
            need: crate::memory::gib(need),
            free: crate::memory::gib(free),
        });
    }

    let (voxel, to_metres) = voxel_size(&header, path)?;
    let spacing = Vec3::from_array(voxel);
    let radius = 0.5 * spacing.length();

    // Pass 2: three slices at a time, points for the middle one.
    let (mut slices, _) = Slices::open(path)?;
    let (nx, ny, nz) = (dims[0], dims[1], dims[2]);
    let plane = nx * ny;
    let mut cloud = PointCloud::default();
    let value = |w: &[&Vec<f32>; 3], x: isize, y: isize, dz: usize| -> f32 {
        let (x, y) = (x.clamp(0, nx as isize - 1) as usize, y.clamp(0, ny as isize - 1) as usize);
        let v = w[dz][y * nx + x];
        if v.is_finite() { v } else { 0.0 }
    };
    let mut read_slice = |bar: &crate::progress::Bar| -> Result<Vec<f32>, VolumeError> {
        let mut next = Vec::with_capacity(plane);
        if !slices.next(path, &mut next)? {
            return Err(read_error(path, "the volume ended early"));
        }
        bar.inc(1);
        Ok(next)
    };
    // Slices z - 1, z and z + 1 (repeated at the ends).
    let mut current = read_slice(&bar)?;
    let mut previous = current.clone();
    for z in 0..nz {
        let next = if z + 1 < nz { read_slice(&bar)? } else { current.clone() };
        let w = [&previous, &current, &next];
        for y in 0..ny as isize {
            for x in 0..nx as isize {
                let v = value(&w, x, y, 1);
                if v.is_nan() || v < threshold {
                    continue;
                }
                let (rgb, alpha) = transfer.at(v);
                // Below half a step of the file's 8-bit alpha a point would be written invisible.
                if alpha < 0.5 / 255.0 {
                    continue;
                }
                let gradient = sobel(&|dx, dy, dz| value(&w, x + dx, y + dy, dz)) / spacing;
                let normal = (-gradient).try_normalize().unwrap_or(Vec3::Z);
                cloud.positions.push(Vec3::new(x as f32, y as f32, z as f32) * spacing);
                cloud.normals.push(normal);
                cloud.radii.push(radius);
                cloud.colours.push(rgb.map(|c| (c * 255.0).round() as u8));
                cloud.opacity.push(alpha);
            }
        }
        previous = std::mem::replace(&mut current, next);
    }
    bar.finish();
    if cloud.is_empty() {
        return Err(VolumeError::Empty { path: path.display().to_string(), threshold, min: lo, max: hi });
    }
    let report = VolumeReport {
        dims,
        voxel,
        units: if to_metres.is_some() { "m" } else { "file units" },
        transfer,
        threshold,
        range: (lo, hi),
    };
    Ok((cloud, report))
}

/// The voxel's size along x, y and z in metres, and whether the file said
/// its unit (NIfTI xyzt_units: 1 m, 2 mm, 3 µm; else the file's own units).
/// An unknown size (0) reads as 1 unit; one no float arithmetic survives is refused.
fn voxel_size(header: &nifti::NiftiHeader, path: &Path) -> Result<([f32; 3], Option<f32>), VolumeError> {
    let to_metres = match header.xyzt_units & 7 {
        1 => Some(1.0),
        2 => Some(1e-3),
        3 => Some(1e-6),
        _ => None,
    };
    for i in 1..=3 {
        let size = header.pixdim[i];
        if !size.is_finite() || size.abs() > MAX_VOXEL_SIZE {
            let field = format!("the header's pixdim[{i}]");
            return Err(VolumeError::VoxelSize { path: path.display().to_string(), field, value: size });
        }
    }
    let voxel = [1, 2, 3].map(|i| {
        let size = header.pixdim[i].abs();
        (if size > 0.0 { size } else { 1.0 }) * to_metres.unwrap_or(1.0)
    });
    Ok((voxel, to_metres))
}

/// The 3D Sobel gradient at the window's centre voxel: the derivative
/// [-1, 0, 1] along each axis, smoothed by [1, 2, 1] along the other two.
/// `at(dx, dy, dz)` reads the neighbour at that offset (dz: 0, 1, 2).
fn sobel(at: &dyn Fn(isize, isize, usize) -> f32) -> Vec3 {
    let smooth = |o: isize| if o == 0 { 2.0 } else { 1.0 };
    let mut g = Vec3::ZERO;
    for dz in -1isize..=1 {
        for dy in -1isize..=1 {
            for dx in -1isize..=1 {
                let v = at(dx, dy, (dz + 1) as usize);
                g.x += dx as f32 * smooth(dy) * smooth(dz) * v;
                g.y += dy as f32 * smooth(dx) * smooth(dz) * v;
                g.z += dz as f32 * smooth(dx) * smooth(dy) * v;
            }
        }
    }
    // The kernels sum |weights| to 16 per side over a 2-voxel span.
    g / 32.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transfer_functions_parse_interpolate_and_refuse_bad_stops() {
        let t: Transfer = "0:0/0/0/0,100:255/255/255/1".parse().unwrap();
        let (c, a) = t.at(50.0);
        assert!((a - 0.5).abs() < 1e-6 && (c[0] - 0.5).abs() < 1e-6);
        assert_eq!(t.at(-5.0).1, 0.0);
        assert_eq!(t.at(500.0).1, 1.0);
        assert_eq!(t.first_visible(), 0.0);
        for bad in ["0:0/0/0/2", "0:300/0/0/1", "5:0/0/0/1,1:0/0/0/1", "x:0/0/0/1", "0:0/0/1", ""] {
            let e = bad.parse::<Transfer>().unwrap_err();
            assert!(e.contains("transfer function") && !e.contains('\n'), "{e}");
        }
        let round: Transfer = t.to_text().parse().unwrap();
        assert_eq!(round.at(50.0).1, t.at(50.0).1);
    }

    #[test]
    fn sobel_points_down_a_linear_ramp() {
        let g = sobel(&|dx, _, _| 3.0 * dx as f32);
        assert!((g - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-5, "{g}");
    }
}

//! Point clouds: the structure-of-arrays splat set and everything that fills it.
//!
//! A [`PointCloud`] holds, per splat, a position (re-centred in f64 on load,
//! then stored as f32), a unit normal, a disc radius, a colour and an opacity.
//! [`load`] reads any PLY file (ASCII or binary, clouds, meshes or 3D Gaussian
//! splats), LAS and LAZ ([`las_file`]) or E57 ([`e57_file`]), keeps the
//! file's other per-point columns ([`attributes`]), repairs bad records, merges exact copies of a splat
//! ([`duplicates`]) and estimates what the file lacks; the [`LoadReport`]
//! says what was read, estimated, merged and repaired.

pub mod attributes;
mod colour;
pub mod crs_units;
pub mod duplicates;
pub mod e57_file;
mod e57_sections;
mod eigen;
mod error;
pub mod estimate;
mod file_info;
pub mod formats;
pub mod gaussians;
mod given_radii;
pub mod las_file;
pub mod load;
mod load_options;
pub mod mesh;
pub mod placement;
pub mod ply;
pub mod records;
pub mod volume;
pub mod write;
pub mod write_las;

pub use attributes::{Attribute, Attributes, Values};
pub use error::CloudError;
pub(crate) use error::one_line;
pub use formats::FileInfo;
pub use load::{Estimates, LoadOptions, load, load_mesh, load_surface_samples, load_with};

use glam::Vec3;

use crate::spatial::overlap::Discs;

/// A set of surface splats, stored as a structure of arrays.
#[derive(Debug, Clone, Default)]
pub struct PointCloud {
    /// Splat centres, relative to [`PointCloud::origin`].
    pub positions: Vec<Vec3>,
    /// Unit normals.
    pub normals: Vec<Vec3>,
    /// Disc radii, in the same units as the positions.
    pub radii: Vec<f32>,
    /// sRGB colours, 0-255.
    pub colours: Vec<[u8; 3]>,
    /// Opacity in 0..=1 (1 = opaque).
    pub opacity: Vec<f32>,
    /// Splats never back-face culled (of two-sided objects); empty when none is.
    pub two_sided: Vec<bool>,
    /// The f64 offset subtracted from the file's coordinates on load.
    pub origin: [f64; 3],
    /// Positions and radii are in units of 10^this of the file's units (0
    /// unless the model was too large or too small for f32):
    /// file coordinates = position · 10^scale_exponent + origin.
    pub scale_exponent: i32,
    /// Where a single-view scan was taken from (file origin, re-centred), if
    /// the normals show that every point faces it.
    pub scanner_position: Option<Vec3>,
    /// The file's other per-point columns (intensity, classification, ...), one value per splat.
    pub attributes: Attributes,
    /// The file's z axis points up (lidar, E57 and geo-referenced data), so views default to z up.
    pub z_up: bool,
    /// The file has no colours: `colours` hold the default colour (survey
    /// data is then coloured by its attributes, [`crate::style::Style::default_for`]).
    pub colourless: bool,
    /// What f32 positions lose: per splat, the file's position minus the
    /// stored one, in the cloud's units, so that the file's position is
    /// (position + residual) times the unit, plus the origin, exact to f64.
    /// Empty when every position is held to within
    /// [`placement::RESIDUAL_KEPT`] (small extents); kept by [`PointCloud::select`],
    /// so picks and measures report the file's own coordinates at any extent.
    pub residuals: Vec<Vec3>,
    /// The units of the file's CRS and its EPSG code (none known: the units of the file).
    pub units: crs_units::CrsUnits,
}

/// Axis-aligned bounds and the bounding sphere of a cloud.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Radius of the sphere around [`Bounds::center`] that holds the box.
    pub fn radius(&self) -> f32 {
        ((self.max - self.min) * 0.5).length()
    }
}

impl PointCloud {
    /// Opaque splats at `positions` facing +z, all of `radius` and `colour`:
    /// the simplest cloud a synthetic scene or a test builds.
    pub fn facing_z(positions: Vec<Vec3>, radius: f32, colour: [u8; 3]) -> Self {
        let n = positions.len();
        PointCloud {
            positions,
            normals: vec![Vec3::Z; n],
            radii: vec![radius; n],
            colours: vec![colour; n],
            opacity: vec![1.0; n],
            ..Default::default()
        }
    }

    pub fn len(&self) -> usize {
        self.positions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The splats as the overlap graph reads them.
    pub fn discs(&self) -> Discs<'_> {
        Discs { positions: &self.positions, normals: &self.normals, radii: &self.radii, colours: &self.colours }
    }

    /// Bounds of the splat centres, or `None` for an empty cloud.
    pub fn bounds(&self) -> Option<Bounds> {
        let first = *self.positions.first()?;
        let (min, max) = self.positions.iter().fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        Some(Bounds { min, max })
    }

    /// Mean splat radius (0 for an empty cloud).
    pub fn mean_radius(&self) -> f32 {
        if self.radii.is_empty() {
            return 0.0;
        }
        (self.radii.iter().map(|&r| r as f64).sum::<f64>() / self.radii.len() as f64) as f32
    }

    /// The length of one unit of the cloud in the file's units.
    /// Splat `i`'s position in the cloud's own frame (re-centred and scaled),
    /// in f64: times the unit plus the origin, the file's position, exact to
    /// the file's own precision where [`PointCloud::residuals`] are kept.
    pub fn frame_position(&self, i: usize) -> glam::DVec3 {
        let residual = self.residuals.get(i).copied().unwrap_or(Vec3::ZERO);
        self.positions[i].as_dvec3() + residual.as_dvec3()
    }

    /// Splat `i`'s position in the file's coordinates (the CRS's units), f64.
    pub fn file_position(&self, i: usize) -> glam::DVec3 {
        self.frame_position(i) * self.unit() + glam::DVec3::from_array(self.origin)
    }

    pub fn unit(&self) -> f64 {
        10f64.powi(self.scale_exponent)
    }

    /// Whether splat `i` is never back-face culled.
    pub fn is_two_sided(&self, i: usize) -> bool {
        self.two_sided.get(i).copied().unwrap_or(false)
    }

    /// True when any splat is not fully opaque.
    pub fn has_transparency(&self) -> bool {
        self.opacity.iter().any(|&a| a < 1.0)
    }

    /// The splats `indices` as a cloud of their own, in the same frame
    /// (origin, scale, up axis). Attributes and the scanner position are not
    /// copied: per-frame selections (hierarchy nodes, hybrid leaves) draw
    /// splats only; a caller that keeps them sets them.
    pub fn select(&self, indices: &[u32]) -> PointCloud {
        let pick = |i: &u32| *i as usize;
        PointCloud {
            positions: indices.iter().map(|i| self.positions[pick(i)]).collect(),
            normals: indices.iter().map(|i| self.normals[pick(i)]).collect(),
            radii: indices.iter().map(|i| self.radii[pick(i)]).collect(),
            colours: indices.iter().map(|i| self.colours[pick(i)]).collect(),
            opacity: indices.iter().map(|i| self.opacity[pick(i)]).collect(),
            two_sided: if self.two_sided.is_empty() {
                Vec::new()
            } else {
                indices.iter().map(|i| self.two_sided[pick(i)]).collect()
            },
            residuals: if self.residuals.is_empty() {
                Vec::new()
            } else {
                indices.iter().map(|i| self.residuals[pick(i)]).collect()
            },
            origin: self.origin,
            scale_exponent: self.scale_exponent,
            z_up: self.z_up,
            colourless: self.colourless,
            units: self.units.clone(),
            ..PointCloud::default()
        }
    }

    /// Checks that every column has one entry per splat.
    pub fn is_consistent(&self) -> bool {
        let n = self.positions.len();
        self.normals.len() == n
            && self.radii.len() == n
            && self.colours.len() == n
            && self.opacity.len() == n
            && (self.two_sided.is_empty() || self.two_sided.len() == n)
            && self.attributes.is_consistent(n)
    }
}

/// How an attribute of the cloud came to be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Provenance {
    /// Read from the file.
    FromFile,
    /// Derived from the mesh faces.
    FromFaces,
    /// Derived from 3D Gaussian splat parameters.
    FromGaussians,
    /// Estimated from the neighbours.
    Estimated,
    /// Not in the file; a default value was used.
    Default,
}

impl std::fmt::Display for Provenance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Provenance::FromFile => "from file",
            Provenance::FromFaces => "from mesh faces",
            Provenance::FromGaussians => "from 3D Gaussian parameters",
            Provenance::Estimated => "estimated from neighbours",
            Provenance::Default => "default",
        })
    }
}

/// What the loader read, estimated and repaired.
#[derive(Debug, Clone)]
pub struct LoadReport {
    pub encoding: String,
    pub comments: Vec<String>,
    /// `(element name, count, property names)` for every element of the file.
    pub elements: Vec<(String, usize, Vec<String>)>,
    pub vertices_in_file: usize,
    pub faces_in_file: usize,
    pub normals: Provenance,
    pub radii: Provenance,
    pub colours: Provenance,
    pub opacity: Provenance,
    /// One line per repair or skip, each with its count.
    pub warnings: Vec<String>,
    /// Seconds spent decoding the file body.
    pub decode_seconds: f64,
    /// Seconds spent estimating normals and radii.
    pub estimate_seconds: f64,
    /// Lines about the file's format (LAS point format, scale and offset), for `info`.
    pub format_details: Vec<String>,
    /// The coordinate reference system the file declares (WKT or GeoTIFF keys).
    pub crs: Option<String>,
}

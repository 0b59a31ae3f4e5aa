//! What a file says beyond its points, which each reader fills
//! ([`super::formats`]): lines about its format, its CRS and its units, the reader's
//! warnings, and how the scan was taken (from above, z up).

/// What a file says beyond its points, for `info`: format lines, its CRS, and warnings of its reader.
#[derive(Debug, Clone, Default)]
pub struct FileInfo {
    pub details: Vec<String>,
    pub crs: Option<String>,
    pub warnings: Vec<String>,
    /// The points were scanned from above (airborne lidar): normals face up.
    pub from_above: bool,
    /// The file's z axis points up (LAS, E57).
    pub z_up: bool,
    /// The units the CRS gives its coordinates, and its EPSG code.
    pub units: super::crs_units::CrsUnits,
}

//! A file's points as records: each point the file holds, in file order,
//! at its f64 file coordinates (the CRS's units), with every attribute.
//! Exports, profiles and areas and volumes work on records, not on a
//! rendered cloud, so they see every point (no merged copies, no f32 frame)
//! and a LAS/LAZ/COPC subset is written by copying the chosen records
//! ([`super::write_las::copy_records`]), every field and the CRS kept.
//!
//! Other formats (PLY, E57) are loaded as clouds; their records are the
//! cloud's splats, and a subset is written from the cloud's columns.

use std::path::{Path, PathBuf};

use glam::DVec3;

use super::attributes::Attributes;
use super::crs_units::CrsUnits;
use super::{CloudError, LoadOptions, PointCloud, las_file};

/// Where the records come from, and so how a subset of them is written.
pub enum RecordSource {
    /// A LAS, LAZ or COPC file: record i is its i-th point record.
    Las(PathBuf),
    /// Another format's loaded cloud: record i is its splat i.
    Cloud(Box<PointCloud>),
    /// Records decoded from a streamed file's nodes, as they are in the
    /// file, under its header: record i is the i-th of `records`.
    Raw { header: Box<las::Header>, records: Vec<u8> },
}

/// A file's points.
pub struct Records {
    /// File coordinates, one per record.
    pub positions: Vec<DVec3>,
    /// Every attribute, one value per record.
    pub attributes: Attributes,
    pub units: CrsUnits,
    /// The CRS as the file declares it, if it does.
    pub crs: Option<String>,
    pub source: RecordSource,
}

impl Records {
    /// Reads every record of `path` (PLY, LAS, LAZ, COPC, E57).
    pub fn read(path: &Path, options: &LoadOptions) -> Result<Records, CloudError> {
        if las_file::is_las(path) {
            let (data, attributes, info) = las_file::read(path)?;
            let column = |name: &str| &data.vertex_columns[name];
            let (x, y, z) = (column("x"), column("y"), column("z"));
            let positions = (0..data.vertex_count).map(|i| DVec3::new(x[i], y[i], z[i])).collect();
            return Ok(Records {
                positions,
                attributes,
                units: info.units,
                crs: info.crs,
                source: RecordSource::Las(path.to_path_buf()),
            });
        }
        let (cloud, report) = super::load_with(path, options)?;
        let positions = (0..cloud.len()).map(|i| cloud.file_position(i)).collect();
        Ok(Records {
            positions,
            attributes: cloud.attributes.clone(),
            units: cloud.units.clone(),
            crs: report.crs,
            source: RecordSource::Cloud(Box::new(cloud)),
        })
    }

    pub fn len(&self) -> usize {
        self.positions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Writes the records `keep` (ascending) to `output`: LAS or LAZ by its
    /// extension (a lidar input's records copied as they are), or PLY.
    pub fn write_subset(&self, keep: &[u32], output: &Path) -> Result<(), CloudError> {
        let ply = output.extension().is_some_and(|e| e.eq_ignore_ascii_case("ply"));
        match &self.source {
            RecordSource::Las(input) if !ply => {
                super::write_las::copy_records::copy_records(input, output, keep).map(drop)
            }
            RecordSource::Raw { header, records } if !ply => {
                super::write_las::copy_records::copy_raw_records(header, records, keep, output).map(drop)
            }
            RecordSource::Raw { header, records } => {
                let all: Vec<u32> = (0..self.len() as u32).collect();
                let las = crate::output::Temporary::with_suffix(".las").map_err(|e| CloudError::io(output, e))?;
                super::write_las::copy_records::copy_raw_records(header, records, &all, las.path())?;
                Records::read(las.path(), &LoadOptions::default())?.write_subset(keep, output)
            }
            RecordSource::Las(input) => {
                // A splat PLY needs normals and radii: those of the subset's own points, estimated
                // on loading the records copied to a temporary LAS.
                let las = crate::output::Temporary::with_suffix(".las").map_err(|e| CloudError::io(output, e))?;
                super::write_las::copy_records::copy_records(input, las.path(), keep)?;
                let (cloud, _) = super::load_with(las.path(), &LoadOptions::default())?;
                super::write::write_ply(&cloud, output, &[])
            }
            RecordSource::Cloud(cloud) => {
                let subset = PointCloud { attributes: cloud.attributes.gather(keep), ..cloud.select(keep) };
                if ply {
                    super::write::write_ply(&subset, output, &[])
                } else {
                    super::write_las::write_las(&subset, output)
                }
            }
        }
    }
}

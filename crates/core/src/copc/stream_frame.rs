//! A streamed file's frame: its name as users see it, its origin (the
//! centre of its header's bounds, shared by every selection) and the
//! corners a default view frames; what the file says of itself.

use glam::{DVec3, Vec3};

use super::CopcStream;
use super::source::is_url;
use crate::cloud::las_file;
use crate::cloud::{FileInfo, PointCloud};

impl CopcStream {
    /// The last part of the path or URL (a URL's query and fragment left out).
    pub fn file_name(&self) -> &str {
        let name = self.name();
        let name = if is_url(name) { name.split(['?', '#']).next().unwrap_or(name) } else { name };
        name.rsplit(['/', '\\']).next().unwrap_or(name)
    }

    /// The file's frame: its origin, and the corners of the header's bounds
    /// relative to it, with z up (what a default view frames).
    pub fn bounds_cloud(&self) -> PointCloud {
        let b = self.header.las.bounds();
        let o = self.tree.origin;
        let corners: Vec<Vec3> = (0..8)
            .map(|i| {
                let pick = |bit: usize, lo: f64, hi: f64| if i & bit != 0 { hi } else { lo };
                (DVec3::new(pick(1, b.min.x, b.max.x), pick(2, b.min.y, b.max.y), pick(4, b.min.z, b.max.z)) - o)
                    .as_vec3()
            })
            .collect();
        PointCloud { origin: o.to_array(), z_up: self.z_up(), ..PointCloud::facing_z(corners, 0.0, [0; 3]) }
    }

    /// The frame's encoding line with `drawn` nodes drawn, and what the
    /// file says of itself: from its LAS header, or what the reader of a
    /// PLY or E57 file held whole found.
    pub(super) fn described(&self, drawn: usize) -> (String, FileInfo) {
        let nodes = self.tree.nodes.len();
        if let Some(d) = self.memory.as_ref().and_then(|m| m.described.as_ref()) {
            let encoding = format!("held in memory, {}, {drawn} of {nodes} nodes drawn", d.encoding);
            return (encoding, d.info.clone());
        }
        let format = self.header.las.point_format();
        let (kind, drawn_as) = if self.memory.is_some() { ("held in memory", "drawn") } else { ("COPC", "streamed") };
        let encoding = format!(
            "{kind}, LAS {}, point format {}, {drawn} of {nodes} nodes {drawn_as}",
            self.header.las.version(),
            format.to_u8().unwrap_or(255),
        );
        let info = FileInfo {
            details: las_file::details(&self.header.las),
            crs: las_file::crs(&self.header.las),
            warnings: self.header.warnings.clone(),
            from_above: true,
            z_up: true,
            units: las_file::crs_units(&self.header.las),
        };
        (encoding, info)
    }

    /// The file's CRS as layers compare it: its EPSG code where it has
    /// one, and its CRS record as text.
    pub fn crs(&self) -> (Option<u32>, Option<String>) {
        (las_file::crs_units(&self.header.las).epsg, las_file::crs(&self.header.las))
    }

    /// Whether the file's z axis points up (every LAS and LAZ file).
    pub fn z_up(&self) -> bool {
        self.memory.as_ref().and_then(|m| m.described.as_ref()).is_none_or(|d| d.info.z_up || d.info.from_above)
    }
}

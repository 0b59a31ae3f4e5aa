//! A streamed file's frame: its name as users see it, its origin (the
//! centre of its header's bounds, shared by every selection) and the
//! corners a default view frames.

use glam::{DVec3, Vec3};

use super::CopcStream;
use super::source::is_url;
use crate::cloud::PointCloud;

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
        PointCloud {
            normals: vec![Vec3::Z; 8],
            radii: vec![0.0; 8],
            colours: vec![[0; 3]; 8],
            opacity: vec![1.0; 8],
            positions: corners,
            origin: o.to_array(),
            z_up: true,
            ..Default::default()
        }
    }
}

//! What a load is told: how to estimate what a file lacks, whether to show
//! progress, the origin to re-centre on, and normals and radii already made
//! (a streamed file's nodes, each estimated once when it arrived: see
//! `copc/node_estimates.rs`).

use glam::Vec3;

use super::PointCloud;
use super::estimate::EstimateOptions;

/// Options for [`load_with`].
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    pub estimate: EstimateOptions,
    /// Show progress bars for long steps.
    pub progress: bool,
    /// Re-centre on this point (file coordinates) instead of the bounding
    /// box's centre: the parts of a streamed file share one origin.
    pub origin: Option<[f64; 3]>,
    /// Normals and radii already estimated, one per record in the data's
    /// order (a streamed file's nodes, each estimated once when it
    /// arrived): used where the file gives none, instead of estimating.
    pub estimated: Option<std::sync::Arc<Estimates>>,
}

/// Normals and radii made for each record of a file (or of a streamed
/// file's nodes) before it is built.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Estimates {
    pub normals: Vec<Vec3>,
    pub radii: Vec<f32>,
}

/// Fills the normals and radii still needed (`needs_normal`, `needs_radius`)
/// from `given`, one per file record: splat k is record `records[k]`.
pub(super) fn use_estimates(
    cloud: &mut PointCloud,
    (needs_normal, needs_radius): (&mut [bool], &mut [bool]),
    records: &[u32],
    given: &Estimates,
) {
    for (k, &i) in records.iter().enumerate() {
        let i = i as usize;
        if needs_normal[k] {
            cloud.normals[k] = given.normals[i];
            needs_normal[k] = false;
        }
        if needs_radius[k] {
            cloud.radii[k] = given.radii[i];
            needs_radius[k] = false;
        }
    }
}

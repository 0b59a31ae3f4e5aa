//! Where survey layers meet: the normals and radii a tile's loader
//! estimated at its edge saw only its own points, so two tiles of one
//! survey would show a seam where they meet. Each layer's points near
//! another layer's box are estimated again with the other layers' points
//! around them as neighbours ([`crate::cloud::estimate::estimate_node`], as
//! a streamed file's nodes are at their borders), in the layer's own frame.
//! Only what the loader estimated is replaced (normals or radii read from a
//! file stay), and only for z-up survey clouds, whose normals face up.

use glam::{DVec3, Vec3};

use crate::cloud::estimate::{self, EstimateOptions, Facing};
use crate::cloud::{PointCloud, Provenance};

/// A layer's cloud and whether its normals and radii were estimated.
pub struct Layer {
    pub cloud: PointCloud,
    pub normals: Provenance,
    pub radii: Provenance,
}

/// How far, in radii (median), a point counts as near another layer.
const NEAR_RADII: f32 = 4.0;

/// `cloud`'s box in file coordinates.
fn file_box(cloud: &PointCloud) -> Option<(DVec3, DVec3)> {
    let b = cloud.bounds()?;
    let (origin, unit) = (DVec3::from_array(cloud.origin), cloud.unit());
    Some((b.min.as_dvec3() * unit + origin, b.max.as_dvec3() * unit + origin))
}

fn within(p: DVec3, (lo, hi): (DVec3, DVec3), margin: f64) -> bool {
    p.cmpge(lo - margin).all() && p.cmple(hi + margin).all()
}

/// Estimates again the points of each layer near another; returns how many.
pub fn mend(layers: &mut [Layer], options: &EstimateOptions) -> usize {
    let boxes: Vec<Option<(DVec3, DVec3)>> = layers.iter().map(|l| file_box(&l.cloud)).collect();
    let mut mended = 0;
    for i in 0..layers.len() {
        let layer = &layers[i];
        let (normals, radii) = (layer.normals == Provenance::Estimated, layer.radii == Provenance::Estimated);
        if !(normals || radii) || !layer.cloud.z_up {
            continue;
        }
        let cloud = &layer.cloud;
        let (origin, unit) = (DVec3::from_array(cloud.origin), cloud.unit());
        let Some(median) = estimate::median_radius(&cloud.radii) else { continue };
        let margin = f64::from(median * NEAR_RADII) * unit;
        let others: Vec<usize> = (0..layers.len()).filter(|&j| j != i).collect();
        let file_at = |p: Vec3| p.as_dvec3() * unit + origin;
        let near_another = |p: DVec3, m: f64| others.iter().any(|&j| boxes[j].is_some_and(|b| within(p, b, m)));
        let near: Vec<usize> =
            (0..cloud.len()).filter(|&k| near_another(file_at(cloud.positions[k]), margin)).collect();
        if near.is_empty() {
            continue;
        }
        // Neighbours: this layer's other points near the seam, and the other layers' near this layer.
        let mut halo: Vec<Vec3> = (0..cloud.len())
            .filter(|&k| {
                let p = file_at(cloud.positions[k]);
                near_another(p, 2.0 * margin) && !near_another(p, margin)
            })
            .map(|k| cloud.positions[k])
            .collect();
        let own_box = boxes[i].expect("a layer with points has a box");
        for &j in &others {
            let other = &layers[j].cloud;
            let (o_origin, o_unit) = (DVec3::from_array(other.origin), other.unit());
            halo.extend(
                other
                    .positions
                    .iter()
                    .map(|p| p.as_dvec3() * o_unit + o_origin)
                    .filter(|p| within(*p, own_box, 2.0 * margin))
                    .map(|p| ((p - origin) / unit).as_vec3()),
            );
        }
        let own: Vec<Vec3> = near.iter().map(|&k| cloud.positions[k]).collect();
        let (new_normals, new_radii) = estimate::estimate_node(&own, &halo, options, Facing::Up);
        let cloud = &mut layers[i].cloud;
        for (n, &k) in near.iter().enumerate() {
            if normals {
                cloud.normals[k] = new_normals[n];
            }
            if radii {
                cloud.radii[k] = new_radii[n];
            }
        }
        mended += near.len();
    }
    mended
}

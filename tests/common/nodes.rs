//! A streamed frame's points compared with the file's loaded whole: which
//! points no finer node covers, so that their neighbourhoods are the same
//! either way.

use pointblend::cloud::PointCloud;
use pointblend::copc::CopcStream;

/// The points of a streamed frame that no finer node covers (no child node
/// holds their position): the points whose neighbourhood is the same
/// whether the file is streamed or loaded whole; each with its index in
/// `whole` (found by position).
pub fn uncovered_points(s: &CopcStream, streamed: &PointCloud, whole: &PointCloud) -> (Vec<u32>, Vec<u32>) {
    let bits = |p: glam::Vec3| p.to_array().map(f32::to_bits);
    let in_whole: std::collections::HashMap<[u32; 3], u32> =
        whole.positions.iter().enumerate().map(|(i, p)| (bits(*p), i as u32)).collect();
    let levels = streamed.attributes.get("node_level").expect("a streamed frame's levels");
    let (root_min, root_side) = s.tree.cube(&las::copc::VoxelKey { l: 0, x: 0, y: 0, z: 0 });
    let mut pairs = (Vec::new(), Vec::new());
    for i in 0..streamed.len() {
        let l = levels.get(i) as i32 + 1;
        let p = streamed.frame_position(i) + glam::DVec3::from_array(streamed.origin);
        let c = ((p - root_min) / (root_side / f64::from(1u32 << l))).floor();
        let child = las::copc::VoxelKey { l, x: c.x as i32, y: c.y as i32, z: c.z as i32 };
        if s.tree.node(&child).is_some_and(|n| s.tree.nodes[n as usize].points > 0) {
            continue;
        }
        pairs.0.push(i as u32);
        pairs.1.push(in_whole[&bits(streamed.positions[i])]);
    }
    pairs
}

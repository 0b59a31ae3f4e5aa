//! A streamed file's groups for the grouped modes (Zhang & Pajarola §4.3's
//! hash grouping): each node labelled once, when it arrives, on a lattice
//! fixed per level for the whole file. The rule holds across node borders
//! as inside a node, a pan labels only the nodes it adds, and deferred
//! blending over the labels of the nodes stays within 0.3 of ε of the
//! labels of the whole selection.

mod common;

use std::sync::Arc;

use common::lidar::{self, tilted_grid};
use las::copc::VoxelKey;
use pointblend::cloud::{LoadOptions, PointCloud};
use pointblend::copc::subset::StreamSubset;
use pointblend::copc::{CopcStream, StreamBudget, StreamOptions};
use pointblend::frame::Camera;
use pointblend::frame::subset::{Choice, Subset};
use pointblend::grouping::hash::{Collisions, HashOptions};
use pointblend::lod::{Choosing, SelectOptions};
use pointblend::spatial::overlap::{OverlapGraph, OverlapOptions};

const K8: HashOptions = HashOptions { k: 8, collisions: Collisions::All };

/// Every node, whatever the view (no culling, no budget, no pixel limit).
fn everything() -> SelectOptions {
    SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 }
}

fn stream(name: &str) -> CopcStream {
    CopcStream::open(name, StreamOptions { cache_bytes: 1 << 30, ..Default::default() }).expect("opens")
}

/// A COPC file of `side`² ground points on a tilted plane (made by
/// `convert`'s writer from a LAZ the las crate wrote).
fn made_copc(dir: &std::path::Path, side: usize) -> std::path::PathBuf {
    let points = tilted_grid(side, 0.25, 0.1, [600_000.0, 4_000_000.0, 100.0]);
    let laz = lidar::write(&dir.join("source.laz"), &points, [600_000.0, 4_000_000.0, 0.0], None);
    let copc = dir.join("tile.copc.laz");
    pointblend::copc::write::write_copc(&laz, &copc, false).unwrap();
    copc
}

/// The sample `1.2-with-color.copc.laz` (1,065 points in 65 nodes), and a
/// 400² plane (160,000 points in several nodes) made in `dir`.
fn sample_and_plane(dir: &std::path::Path) -> Option<[String; 2]> {
    let sample = common::shared_data("lidar/1.2-with-color.copc.laz")?;
    Some([sample, made_copc(dir, 400)].map(|p| p.display().to_string()))
}

/// The node each splat of a streamed frame came from: its level, and the
/// cube of that level holding its position.
fn nodes_of(s: &CopcStream, cloud: &PointCloud) -> Vec<VoxelKey> {
    let levels = cloud.attributes.get("node_level").expect("a streamed frame's levels");
    let (root_min, root_side) = s.tree.cube(&VoxelKey { l: 0, x: 0, y: 0, z: 0 });
    (0..cloud.len())
        .map(|i| {
            let l = levels.get(i) as i32;
            let p = cloud.frame_position(i) + glam::DVec3::from_array(cloud.origin);
            let c = ((p - root_min) / (root_side / f64::from(1u32 << l))).floor();
            VoxelKey { l, x: c.x as i32, y: c.y as i32, z: c.z as i32 }
        })
        .collect()
}

/// Among pairs of overlapping splats (Eq. 5, c = 1) of one level: the §6.1
/// overlap factor of those `labels` put in one group ((r_i + r_j - d) over
/// the mean of r_i and r_j), summed and divided by the pairs, (across a
/// node border, inside a node), with the pairs counted.
fn same_group_shares(cloud: &PointCloud, labels: &[u32], nodes: &[VoxelKey]) -> ((f64, usize), (f64, usize)) {
    let graph = OverlapGraph::build(cloud.discs(), &OverlapOptions::default());
    let (mut across, mut inside) = ((0f64, 0usize), (0f64, 0usize));
    for i in 0..cloud.len() {
        for &j in graph.neighbours_of(i) {
            let j = j as usize;
            if j <= i || nodes[i].l != nodes[j].l {
                continue;
            }
            let tally = if nodes[i] == nodes[j] { &mut inside } else { &mut across };
            let reach = cloud.radii[i] + cloud.radii[j];
            let depth = (reach - cloud.positions[i].distance(cloud.positions[j])) / (0.5 * reach);
            tally.0 += if labels[i] == labels[j] { f64::from(depth) } else { 0.0 };
            tally.1 += 1;
        }
    }
    let share = |(same, all): (f64, usize)| (same / all.max(1) as f64, all);
    (share(across), share(inside))
}

/// Each node labelled on a lattice of its own (its median radius, its
/// lowest point): what the per-level world lattice replaces.
fn labels_on_each_nodes_own_lattice(cloud: &PointCloud, nodes: &[VoxelKey]) -> Vec<u32> {
    let mut members: std::collections::HashMap<VoxelKey, Vec<u32>> = Default::default();
    for (i, n) in nodes.iter().enumerate() {
        members.entry(*n).or_default().push(i as u32);
    }
    let mut labels = vec![0; cloud.len()];
    for indices in members.values() {
        let node = cloud.select(indices);
        let (grouping, _) = pointblend::grouping::hash::group(&node, &K8).unwrap();
        for (k, label) in grouping.labels(node.len()).into_iter().enumerate() {
            labels[indices[k] as usize] = label;
        }
    }
    labels
}

/// A streamed frame of every node, labelled as the grouped modes draw it.
fn grouped_frame(s: &mut CopcStream) -> (PointCloud, Vec<u32>) {
    let camera = Camera::default_for(&s.bounds_cloud(), 1.0);
    let selection = s.select(&camera, (160, 160), everything());
    s.load(&selection);
    let frame = s.gather(&selection, &LoadOptions::default(), Some(K8)).unwrap();
    let grouping = frame.grouping.expect("nodes labelled when asked");
    assert_eq!(grouping.options, K8);
    let labels = grouping.grouping.labels(frame.cloud.len());
    assert!(labels.iter().all(|&l| l < 8), "every splat in one group");
    (frame.cloud, labels)
}

/// Grouping across borders: overlapping splats of one level on either side
/// of a node border are put in one group, weighted by how deep they
/// overlap (§6.1's overlap factor), no more than 1.5 times as much as the
/// hash grouping of the whole selection at once puts the same pairs
/// together (the grouping's own rule, on the same splats). Labelled on each
/// node's own lattice (its median radius and lowest point) they would be
/// about three times as much: the test tells the two apart.
#[test]
fn splats_across_a_node_border_overlap_in_one_group_no_more_than_the_selection_grouped_whole_allows() {
    let dir = tempfile::tempdir().unwrap();
    for name in require!(sample_and_plane(dir.path())) {
        let mut s = stream(&name);
        let (cloud, labels) = grouped_frame(&mut s);
        let nodes = nodes_of(&s, &cloud);
        let ((across, pairs_across), (inside, pairs_inside)) = same_group_shares(&cloud, &labels, &nodes);
        let whole = pointblend::grouping::hash::group(&cloud, &K8).unwrap().0.labels(cloud.len());
        let ((whole_across, _), (whole_inside, _)) = same_group_shares(&cloud, &whole, &nodes);
        let own = labels_on_each_nodes_own_lattice(&cloud, &nodes);
        let ((own_across, _), _) = same_group_shares(&cloud, &own, &nodes);
        eprintln!(
            "{name}: {} splats; overlap in one group per pair across a border {across:.4} ({pairs_across} pairs), \
             inside a node {inside:.4} ({pairs_inside}); the selection grouped whole {whole_across:.4} / \
             {whole_inside:.4}; each node on its own lattice {own_across:.4} across",
            cloud.len()
        );
        assert!(pairs_across >= 1000 && pairs_inside >= 1000, "{name}: pairs on both sides of borders");
        assert!(across <= 1.5 * whole_across, "{name}: {across:.4} across borders, {whole_across:.4} grouped whole");
        assert!(own_across > 1.5 * whole_across, "{name}: the test tells a world lattice from a node's own");
    }
}

/// Pans cost what they add: along a path of pans, each view labels the
/// nodes it draws that no earlier view drew, and no others; a point drawn
/// again keeps its group.
#[test]
fn a_pan_labels_only_the_nodes_it_adds() {
    let dir = tempfile::tempdir().unwrap();
    let path = made_copc(dir.path(), 400);
    let s = stream(&path.display().to_string());
    let far = Camera::default_for(&s.bounds_cloud(), 1.0);
    let mut subset = StreamSubset::new(s, StreamBudget::Points(60_000), LoadOptions::default());
    let choosing = Choosing { groups: Some(K8), ..Choosing::default() };
    let bits = |p: glam::Vec3| p.to_array().map(f32::to_bits);
    let mut groups: std::collections::HashMap<[u32; 3], u32> = Default::default();
    let (mut redrawn, mut labelled_in_pans) = (0, 0);
    for step in 0..5 {
        let target = glam::Vec3::new(-30.0 + 15.0 * step as f32, 0.0, 0.0);
        let camera = Camera { target, distance: 15.0, ..far };
        let before = subset.stream.stats();
        let Choice { cloud, grouping, .. } = subset.choose(&camera, (128, 128), choosing).unwrap();
        let after = subset.stream.stats();
        let added = after.points_loaded - before.points_loaded;
        assert_eq!(after.points_labelled - before.points_labelled, added, "view {step}: only the nodes added");
        let Some(cloud) = cloud else { continue };
        let grouping = grouping.expect("labelled");
        let labels = grouping.grouping.labels(cloud.len());
        for (p, label) in cloud.positions.iter().zip(&labels) {
            let kept = *groups.entry(bits(*p)).or_insert(*label);
            assert_eq!(kept, *label, "view {step}: a point drawn again keeps its group");
        }
        if step > 0 {
            redrawn += cloud.len() - added as usize;
            labelled_in_pans += added;
        }
    }
    assert!(redrawn > 0 && labelled_in_pans > 0, "the pans draw points again ({redrawn}) and add some");
}

/// Deferred blending (Zhang & Pajarola §3-5.1) of an opaque scan over a
/// streamed selection, grouped by its nodes' labels, is within 0.3
/// of ε of the same selection grouped whole (a hash grouping of the same
/// K), both against the exact reference.
#[test]
fn deferred_over_the_labels_of_the_nodes_is_within_a_third_of_epsilon_of_the_selection_grouped_whole() {
    use pointblend::render::{PreparedScene, RenderMode, RenderSettings};
    use pointblend::scene::Scene;
    let dir = tempfile::tempdir().unwrap();
    for name in require!(sample_and_plane(dir.path())) {
        let s = stream(&name);
        let camera = Camera::default_for(&s.bounds_cloud(), 1.0);
        let camera = Camera { distance: camera.distance * 0.5, ..camera };
        let mut subset = StreamSubset::new(s, StreamBudget::Points(100_000), LoadOptions::default());
        let settings = RenderSettings { mode: RenderMode::Deferred, ..Default::default() };
        let choice = subset.choose(&camera, (160, 160), Choosing::of(&settings)).unwrap();
        let (cloud, grouping) = (choice.cloud.expect("points"), choice.grouping.expect("labelled"));
        let image = |scene: Scene, settings: &RenderSettings| {
            let mut frames = PreparedScene::of(Arc::new(scene)).streamed();
            let mut renderer = common::renderer();
            frames.render(Some(&mut *renderer), &camera, settings, (160, 160), false).expect("render").image
        };
        let scene = || Scene::single("tile", cloud.clone(), choice.key).coloured_by_default();
        let by_nodes = image(scene().with_node_grouping(Some(grouping.clone())), &settings);
        let whole = image(scene(), &settings);
        let reference = image(scene(), &RenderSettings { mode: RenderMode::Reference, ..settings });
        let eps = |a: &image::RgbaImage| pointblend::reference::metrics::compare(a, &reference).unwrap().eps;
        let (nodes_eps, whole_eps) = (eps(&by_nodes), eps(&whole));
        eprintln!("{name}: deferred ε {nodes_eps:.3} by the nodes' labels, {whole_eps:.3} grouped whole");
        assert!(by_nodes.pixels().any(|p| p.0 != by_nodes.get_pixel(0, 0).0), "{name}: a blank frame");
        assert!(nodes_eps <= whole_eps + 0.3, "{name}: ε {nodes_eps:.3} against {whole_eps:.3} grouped whole");
    }
}

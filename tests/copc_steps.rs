//! A streamed view loaded in steps, as the viewer refines one: each step
//! loads the coarsest nodes it lacks, no more points than its bound, and
//! gathers what is loaded, so the window can show each step; the last
//! step's points are the points of the view chosen in one go, and its image
//! is theirs within the seam goal although early nodes had smaller halos.

mod common;

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use common::lidar;
use las::copc::VoxelKey;
use pointblend::cloud::LoadOptions;
use pointblend::copc::subset::StreamSubset;
use pointblend::copc::{CopcStream, StreamBudget, StreamOptions};
use pointblend::frame::Camera;
use pointblend::frame::subset::Subset;
use pointblend::lod::Choosing;
use pointblend::render::{PreparedScene, RenderMode, RenderSettings};
use pointblend::scene::Scene;

/// The points a step loads at most (beyond the loader's four requests).
const STEP: u64 = 250_000;
/// The view's size, as the selection sees it; its images are drawn at a quarter of it (or less).
const SIZE: (u32, u32) = (256, 256);
const IMAGE: (u32, u32) = (128, 128);

/// The share of pixels a cloud covers in two-pass (those unlike the background's corner).
fn covered(cloud: pointblend::cloud::PointCloud, camera: &Camera, png: &Path) -> f64 {
    let mut frames = PreparedScene::of(std::sync::Arc::new(Scene::single("step".to_string(), cloud, 0)));
    let settings = RenderSettings { mode: RenderMode::TwoPass, ..Default::default() };
    let mut renderer = common::renderer();
    let image = frames.render(Some(&mut *renderer), camera, &settings, IMAGE, false).expect("render").image;
    image.save(png).unwrap();
    let background = *image.get_pixel(0, 0);
    image.pixels().filter(|&&p| p != background).count() as f64 / f64::from(IMAGE.0 * IMAGE.1)
}

/// A COPC file of two `side`² grids 4 m apart, made by `convert`'s writer.
fn two_layer_copc(dir: &Path, side: usize) -> PathBuf {
    let laz = lidar::two_planes(&dir.join("source.laz"), side, 0.25, [600_000.0, 4_000_000.0, 100.0], 4.0);
    let copc = dir.join("tile.copc.laz");
    pointblend::copc::write::write_copc(&laz, &copc, false).unwrap();
    copc
}

fn subset(copc: &Path) -> StreamSubset {
    let options = StreamOptions { cache_bytes: 1 << 30, ..Default::default() };
    let stream = CopcStream::open(copc.to_str().unwrap(), options).unwrap();
    StreamSubset::new(stream, StreamBudget::Points(1_000_000), LoadOptions::default())
}

/// The node holding `key`'s parent, if `key` is not the root.
fn parent(stream: &CopcStream, key: VoxelKey) -> Option<u32> {
    (key.l > 0).then(|| {
        let up = VoxelKey { l: key.l - 1, x: key.x / 2, y: key.y / 2, z: key.z / 2 };
        stream.tree.node(&up).expect("a node's parent is in the tree")
    })
}

#[test]
fn a_view_loaded_in_steps_comes_coarse_first_each_step_bounded_and_ends_on_the_view_chosen_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let copc = two_layer_copc(dir.path(), 800);
    loaded_in_steps(&copc, (STEP, SIZE), 3, dir.path());
}

/// The same on a real lidar tile: an airborne COPC of 518,862 points in 15
/// nodes over three levels, in steps of at most a level 0 node's points (so
/// every step is four nodes, the loader's least), its view chosen for a
/// larger window so that it reaches the finest level.
#[test]
fn a_real_tile_loaded_in_steps_ends_on_the_view_chosen_at_once() {
    let copc = require!(common::shared_data("lidar/lone-star.copc.laz"));
    let dir = tempfile::tempdir().unwrap();
    loaded_in_steps(&copc, (60_000, (1024, 1024)), 3, dir.path());
}

/// Loads the default view of `copc` at `size` in steps of at most `step` points
/// and checks them: each loads something, within the bound or four nodes,
/// no node before its parent, each draws more and leaves no hole, at least
/// `least_steps` of them, the last drawing the view chosen at once, within
/// the streamed seam goal of its image.
fn loaded_in_steps(copc: &Path, (step, size): (u64, (u32, u32)), least_steps: usize, dir: &Path) {
    let mut stepped = subset(copc);
    let camera = Camera::default_for(&stepped.stream.bounds_cloud(), 1.0);
    let choosing = Choosing::default();
    let mut loaded: HashSet<u32> = HashSet::new();
    let mut shown = Vec::new();
    loop {
        let left = stepped.load_step(&camera, size, choosing, step).unwrap();
        let nodes = stepped.stream.tree.nodes.len() as u32;
        let now: HashSet<u32> = (0..nodes).filter(|&n| stepped.stream.decoded_points(n).is_some()).collect();
        let added: Vec<u32> = now.difference(&loaded).copied().collect();
        let points: u64 = added.iter().map(|&n| u64::from(stepped.stream.tree.nodes[n as usize].points)).sum();
        assert!(!added.is_empty(), "a step loads something");
        assert!(points <= step || added.len() <= 4, "a step of {} nodes loaded {points} points", added.len());
        for &n in &added {
            let key = stepped.stream.tree.nodes[n as usize].key;
            let up = parent(&stepped.stream, key);
            assert!(up.is_none_or(|p| now.contains(&p)), "node {key:?} came before its parent");
        }
        loaded = now;
        let choice = stepped.choose_loaded(&camera, size, choosing, u64::MAX).unwrap();
        let cloud = choice.cloud.expect("each step draws what it added");
        let drawn = cloud.len();
        assert!(shown.last().is_none_or(|&(before, _)| drawn > before), "a step draws more than the last");
        shown.push((drawn, covered(cloud, &camera, &dir.join(format!("step{}.png", shown.len())))));
        if left.nodes == 0 {
            break;
        }
        assert!(left.points > 0, "nodes left hold points");
    }
    let mut at_once = subset(copc);
    let whole = at_once.choose(&camera, size, choosing).unwrap().cloud.expect("the view's points");
    let points = whole.len();
    let full = covered(whole, &camera, &dir.join("at_once.png"));
    println!("steps of at most {step} points drew (points, coverage) {shown:?}; the view at once {points}, {full:.4}");
    if let Ok(keep) = std::env::var("POINTBLEND_KEEP_IMAGES") {
        for entry in std::fs::read_dir(dir).unwrap().flatten().filter(|e| e.path().extension() == Some("png".as_ref()))
        {
            std::fs::copy(entry.path(), Path::new(&keep).join(entry.file_name())).unwrap();
        }
    }
    assert!(shown.len() >= least_steps, "the view came in several steps: {shown:?}");
    // No holes: a node still loading is covered by its ancestors (the silhouette may move by a pixel row).
    let row = 1.0 / f64::from(IMAGE.1);
    assert!(shown.iter().all(|&(_, c)| c >= full - row), "a step left a hole: {shown:?} against {full}");
    let last = stepped.choose_loaded(&camera, size, choosing, u64::MAX).unwrap();
    assert!(last.cloud.is_none(), "the last step's nodes are the ones drawn");
    assert_eq!(last.key, at_once.choose(&camera, size, choosing).unwrap().key, "the same nodes as the view at once");
    assert_eq!(shown.last().unwrap().0, points, "the same points as the view at once");
    // Nodes estimated in earlier steps had a smaller halo (their parent and the nodes loaded by
    // then): the image stays within the streamed-against-whole goal of the view at once.
    let image = |name: String| image::open(dir.join(name)).unwrap().to_rgba8();
    let eps =
        pointblend::reference::compare(&image(format!("step{}.png", shown.len() - 1)), &image("at_once.png".into()))
            .unwrap()
            .eps;
    println!("the last step against the view at once: ε {eps:.3}");
    assert!(eps <= common::tolerances::MAX_STREAMED_EPS, "ε {eps} of the stepped view against the view at once");
}

/// A view loaded whole, then shown as the viewer shows it while it
/// refines: each choice adds at most `ADDING` points of nodes the last one
/// did not draw (or one node), coarse first, so that no node is drawn
/// without its parent, each draws more, and the last draws the view.
#[test]
fn choices_add_at_most_their_bound_coarse_first_and_end_on_the_view() {
    const ADDING: u64 = 150_000;
    let dir = tempfile::tempdir().unwrap();
    let copc = two_layer_copc(dir.path(), 800);
    let mut stepped = subset(&copc);
    let camera = Camera::default_for(&stepped.stream.bounds_cloud(), 1.0);
    let choosing = Choosing::default();
    let left = stepped.load_step(&camera, SIZE, choosing, u64::MAX).unwrap();
    assert_eq!(left.nodes, 0, "the view loaded in one step");
    let mut drawn: HashSet<u32> = HashSet::new();
    let mut added_per_choice = Vec::new();
    loop {
        let choice = stepped.choose_loaded(&camera, SIZE, choosing, ADDING).unwrap();
        let spans = choice.spans.expect("each choice draws more than the last");
        let now: HashSet<u32> = spans.0.iter().map(|(node, _)| *node).collect();
        assert!(drawn.is_subset(&now), "a choice dropped a node of the same view");
        let added: Vec<u32> = now.difference(&drawn).copied().collect();
        let points: u64 = added.iter().map(|&n| u64::from(stepped.stream.tree.nodes[n as usize].points)).sum();
        assert!(!added.is_empty(), "a choice adds a node");
        assert!(points <= ADDING || added.len() == 1, "a choice added {} nodes of {points} points", added.len());
        for &n in &now {
            let key = stepped.stream.tree.nodes[n as usize].key;
            let up = parent(&stepped.stream, key);
            assert!(up.is_none_or(|p| now.contains(&p)), "node {key:?} drawn without its parent");
        }
        added_per_choice.push(points);
        drawn = now;
        if stepped.last.held_back == 0 {
            break;
        }
    }
    println!("choices of at most {ADDING} new points added {added_per_choice:?}");
    assert!(added_per_choice.len() >= 3, "the view came in several choices: {added_per_choice:?}");
    let last = stepped.choose_loaded(&camera, SIZE, choosing, u64::MAX).unwrap();
    assert!(last.cloud.is_none(), "nothing was left to add");
    let at_once = subset(&copc).choose(&camera, SIZE, choosing).unwrap();
    assert_eq!(last.key, at_once.key, "the same nodes as the view at once");
}

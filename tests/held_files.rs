//! PLY and E57 files under a point budget are trees of nodes, as LAS and
//! LAZ files are: every point kept with its colour and attributes, normals
//! that face as the file loaded whole faces them (towards a single view's
//! scanner, else out of an object scanned all round, up on terrain), no
//! seam at node borders, and meshes still drawn whole.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;
use pointblend::cloud::{self, LoadOptions, PointCloud};
use pointblend::copc::{CopcStream, StreamBudget, StreamOptions, drawn_by_nodes};
use pointblend::frame::Camera;
use pointblend::lod::SelectOptions;
use pointblend::render::{PreparedScene, RenderMode, RenderSettings};
use pointblend::scene::Scene;

const SIZE: u32 = 160;

/// Every node, whatever the view.
fn everything() -> SelectOptions {
    SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 }
}

/// `count` points on a sphere of radius 1 around (5, 3, 2), colour by
/// position and a `quality` property, as a binary PLY without normals: an
/// object scanned all round, away from the file's origin.
fn made_sphere(dir: &Path, count: usize) -> PathBuf {
    made_sphere_with(dir, count, None)
}

/// [`made_sphere`], each point given `radius` when there is one.
fn made_sphere_with(dir: &Path, count: usize, radius: Option<f32>) -> PathBuf {
    let mut body = Vec::new();
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    for i in 0..count {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
        let r = (1.0 - z * z).sqrt();
        let (x, y) = (r * (golden * i as f64).cos(), r * (golden * i as f64).sin());
        for v in [5.0 + x, 3.0 + y, 2.0 + z] {
            body.extend_from_slice(&(v as f32).to_le_bytes());
        }
        body.extend([(x * 100.0 + 128.0) as u8, (y * 100.0 + 128.0) as u8, (z * 100.0 + 128.0) as u8]);
        body.extend_from_slice(&(i as f32 * 0.5).to_le_bytes());
        if let Some(r) = radius {
            body.extend_from_slice(&r.to_le_bytes());
        }
    }
    let radius_property = if radius.is_some() { "property float radius\n" } else { "" };
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {count}\nproperty float x\nproperty float y\nproperty float z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float quality\n{radius_property}end_header\n"
    );
    let path = dir.join(if radius.is_some() { "sphere-radii.ply" } else { "sphere.ply" });
    std::fs::write(&path, [header.as_bytes(), &body].concat()).unwrap();
    path
}

/// The files these tests hold whole: the made sphere, and the shared
/// table scan (a single stereo view) and E57 bunny where they are.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut files = vec![made_sphere(dir, 120_000)];
    files.extend(common::shared_data("table_scene_mug_stereo_textured.ply"));
    files.extend(common::shared_data("e57/bunnyFloat.e57"));
    files
}

fn held(path: &Path) -> CopcStream {
    let options = StreamOptions { cache_bytes: 1 << 30, ..Default::default() };
    CopcStream::open_whole(path, options).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The file held whole with every node drawn, and the file loaded whole.
fn both(path: &Path) -> (CopcStream, PointCloud, PointCloud) {
    let (whole, _) = cloud::load(path).unwrap();
    let mut s = held(path);
    let camera = Camera::default_for(&whole, 1.0);
    let frame = s.frame(&camera, (SIZE, SIZE), everything(), &LoadOptions::default()).unwrap();
    (s, frame.cloud, whole)
}

fn bits(p: Vec3) -> [u32; 3] {
    p.to_array().map(f32::to_bits)
}

#[test]
fn a_ply_or_e57_file_held_whole_holds_every_point_with_its_colour_and_attributes() {
    let dir = tempfile::tempdir().unwrap();
    for path in files(dir.path()) {
        let name = path.display();
        let (s, held, whole) = both(&path);
        assert!(s.tree.nodes.len() > 1 || whole.len() < 100_000, "{name}: a tree of nodes");
        assert_eq!(held.origin, whole.origin, "{name}: one frame, the bounds' centre");
        assert_eq!(held.len(), whole.len(), "{name}: points");
        let row = |c: &PointCloud, i: usize| (bits(c.positions[i]), c.colours[i]);
        let mut a: Vec<_> = (0..held.len()).map(|i| row(&held, i)).collect();
        let mut b: Vec<_> = (0..whole.len()).map(|i| row(&whole, i)).collect();
        a.sort_unstable();
        b.sort_unstable();
        assert!(a == b, "{name}: the same positions and colours");
        let names = |c: &PointCloud| c.attributes.names().filter(|n| *n != "node_level").map(String::from).collect();
        let (held_names, whole_names): (Vec<String>, Vec<String>) = (names(&held), names(&whole));
        assert_eq!(held_names, whole_names, "{name}: the attributes");
        let at: HashMap<[u32; 3], usize> = (0..whole.len()).map(|i| (bits(whole.positions[i]), i)).collect();
        for attribute in &held.attributes.channels {
            let Some(theirs) = whole.attributes.get(&attribute.name) else { continue };
            let same = (0..held.len()).all(|i| attribute.values.get(i) == theirs.get(at[&bits(held.positions[i])]));
            assert!(same, "{name}: attribute {} point by point", attribute.name);
        }
    }
}

/// Each node's normals are estimated on its own, their signs by one rule
/// for the whole file: they face as the whole file's do (measured: 1.0000
/// of the sphere's, 0.9996 of the table scan's, 1.0000 of the E57 bunny's).
#[test]
fn normals_estimated_node_by_node_face_as_the_whole_files_do() {
    let dir = tempfile::tempdir().unwrap();
    for path in files(dir.path()) {
        let (_, held, whole) = both(&path);
        let at: HashMap<[u32; 3], usize> = (0..whole.len()).map(|i| (bits(whole.positions[i]), i)).collect();
        let agree = (0..held.len()).filter(|&i| held.normals[i].dot(whole.normals[at[&bits(held.positions[i])]]) > 0.0);
        let share = agree.count() as f64 / held.len() as f64;
        println!("{}: {share:.4} of the normals face as the whole file's", path.display());
        assert!(share >= 0.99, "{}: only {share:.4} of the normals face as the whole file's", path.display());
    }
}

fn render(cloud: PointCloud, camera: &Camera, mode: RenderMode) -> image::RgbaImage {
    let mut frames = PreparedScene::of(Arc::new(Scene::from(cloud)));
    let settings = RenderSettings { mode, ..Default::default() };
    let mut renderer = common::renderer();
    frames.render(Some(&mut *renderer), camera, &settings, (SIZE, SIZE), false).expect("render").image
}

/// Every node of a PLY file held as nodes, each estimated with its halo
/// (a coarse node's points as the deepest node drawn at their position
/// estimated them), draws the image of the file loaded whole within the
/// seam goal, in two-pass and `tiled`.
#[test]
fn a_ply_file_held_as_nodes_draws_the_file_loaded_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = made_sphere(dir.path(), 120_000);
    let (_, held, whole) = both(&path);
    let camera = Camera::default_for(&whole, 1.0);
    for mode in [RenderMode::TwoPass, RenderMode::Tiled] {
        let a = render(whole.clone(), &camera, mode);
        let b = render(held.clone(), &camera, mode);
        assert!(a.pixels().any(|p| p.0 != a.get_pixel(0, 0).0), "{mode}: a blank frame");
        let eps = pointblend::reference::metrics::compare(&b, &a).unwrap().eps;
        println!("{mode}: ε {eps:.4} against the file loaded whole");
        assert!(eps <= common::tolerances::MAX_STREAMED_EPS, "{mode}: ε {eps:.3} against the file loaded whole");
    }
}

/// A file that gives each point its radius, for its finest spacing: a
/// coarse node's points stand for the finer points not drawn, so they are
/// drawn at least as large as their node's density asks, and the root
/// alone draws the sphere without holes.
#[test]
fn given_radii_grow_where_a_coarse_node_is_drawn_alone() {
    let dir = tempfile::tempdir().unwrap();
    // About 1.1 times the spacing of 120,000 points over the sphere's 4π.
    let spacing = (4.0 * std::f32::consts::PI / 120_000.0).sqrt();
    let path = made_sphere_with(dir.path(), 120_000, Some(1.1 * spacing));
    let (whole, _) = cloud::load(&path).unwrap();
    let mut s = held(&path);
    assert!(s.tree.nodes.len() > 1, "a tree of nodes");
    // Close enough that a gap between the root's points spans pixels.
    let far = Camera::default_for(&whole, 1.0);
    let camera = Camera { distance: far.distance * 0.6, ..far };
    let root_only = SelectOptions { budget: 1, ..everything() };
    let frame = s.frame(&camera, (SIZE, SIZE), root_only, &LoadOptions::default()).unwrap();
    assert!(frame.cloud.len() * 2 < whole.len(), "the root alone: {} points", frame.cloud.len());
    let root = render(frame.cloud, &camera, RenderMode::TwoPass);
    let eps = pointblend::reference::metrics::compare(&root, &render(whole, &camera, RenderMode::TwoPass)).unwrap().eps;
    println!("the root alone against the whole file: ε {eps:.3}");
    let max = common::tolerances::MAX_COARSE_NODE_EPS;
    assert!(
        eps <= max,
        "the root alone against the whole file: ε {eps:.3} (holes where its radii are the finest level's)"
    );
}

/// Under a point budget below its count, a point file is drawn as nodes
/// (`render` says so); a mesh, whose faces the nodes would drop, and 3D
/// Gaussians, whose scales size their splats, are drawn whole, and so is a
/// file the budget holds.
#[test]
fn render_under_a_budget_draws_point_files_as_nodes_and_meshes_whole() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = made_sphere(dir.path(), 120_000);
    let budget = StreamBudget::Points(50_000);
    assert!(drawn_by_nodes(&sphere, budget), "a PLY of points above the budget");
    assert!(!drawn_by_nodes(&sphere, StreamBudget::Points(120_000)), "a PLY the budget holds");
    assert!(!drawn_by_nodes(&common::bundled_mesh(), StreamBudget::Points(10)), "a mesh");
    if let Some(gaussians) = common::shared_data("more/gaussians_3dgs_sh3_9080.ply") {
        assert!(!drawn_by_nodes(&gaussians, StreamBudget::Points(10)), "3D Gaussians, sized by their scales");
    }
    let out = dir.path().join("sphere.png");
    let args = [sphere.to_str().unwrap(), "--point-budget", "50000", "--size", "128x128", "--mode", "two-pass"];
    let (ok, stderr) = common::render_cli(&args, &out);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("held in memory as an octree"), "drawn as nodes: {stderr}");
    let image = image::open(&out).unwrap().to_rgba8();
    assert!(image.pixels().any(|p| p.0 != image.get_pixel(0, 0).0), "a blank frame");
    let mesh = common::bundled_mesh();
    let (ok, stderr) = common::render_cli(&[mesh.to_str().unwrap(), "--point-budget", "1000", "--size", "64x64"], &out);
    assert!(ok, "{stderr}");
    assert!(!stderr.contains("held in memory"), "a mesh is drawn whole: {stderr}");
}

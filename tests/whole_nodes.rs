//! A LAS/LAZ file opened under a point budget is held whole in memory as a
//! tree of nodes: the octree a COPC file of it holds, drawn node by node as
//! the COPC file is streamed. Its tree and its frame with every node drawn
//! equal the COPC file's, bit for bit; every point of the file is drawn;
//! `render` under a budget gives the COPC file's image; and a pan estimates
//! only the nodes it adds.

mod common;

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use common::lidar;
use pointblend::cloud::{LoadOptions, PointCloud};
use pointblend::copc::{CopcStream, StreamBudget, StreamOptions};
use pointblend::frame::Camera;
use pointblend::lod::{Choosing, SelectOptions};

/// Every node, whatever the view (no culling, no budget, no pixel limit).
fn everything() -> SelectOptions {
    SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 }
}

fn options() -> StreamOptions {
    StreamOptions { cache_bytes: 1 << 30, ..Default::default() }
}

/// Two tilted planes 4 m apart, `side`² points each (more than one node's
/// worth from side 250 on), as LAZ.
fn made_laz(dir: &Path, side: usize) -> PathBuf {
    lidar::two_planes(&dir.join("tile.laz"), side, 0.25, [600_000.0, 4_000_000.0, 100.0], 4.0)
}

/// Every node's key and points, sorted.
fn nodes_of(stream: &CopcStream) -> Vec<(i32, i32, i32, i32, u32)> {
    let mut nodes: Vec<_> = stream
        .tree
        .nodes
        .iter()
        .filter(|n| n.points > 0)
        .map(|n| (n.key.l, n.key.x, n.key.y, n.key.z, n.points))
        .collect();
    nodes.sort_unstable();
    nodes
}

/// The frame of every node, from the default view of the stream's bounds.
fn everything_drawn(stream: &mut CopcStream) -> PointCloud {
    let camera = Camera::default_for(&stream.bounds_cloud(), 1.0);
    stream.frame(&camera, (64, 64), everything(), &LoadOptions::default()).expect("a frame").cloud
}

/// The file's points, on the grid of its scale (what the records hold).
fn records(path: &Path) -> (HashSet<[i64; 3]>, usize, [f64; 6]) {
    let mut reader = las::Reader::from_path(path).unwrap();
    let t = *reader.header().transforms();
    let grid = [t.x.scale, t.y.scale, t.z.scale, t.x.offset, t.y.offset, t.z.offset];
    let count = reader.header().number_of_points();
    let data = reader.read_points(count).unwrap();
    let set = data.x().zip(data.y()).zip(data.z()).map(|((x, y), z)| on_grid([x, y, z], grid)).collect();
    (set, count as usize, grid)
}

fn on_grid(p: [f64; 3], g: [f64; 6]) -> [i64; 3] {
    [
        ((p[0] - g[3]) / g[0]).round() as i64,
        ((p[1] - g[4]) / g[1]).round() as i64,
        ((p[2] - g[5]) / g[2]).round() as i64,
    ]
}

#[test]
fn a_file_held_whole_is_the_tree_of_its_copc_file_and_draws_every_point_as_it_does() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = vec![made_laz(dir.path(), 300)];
    if let Some(autzen) = common::shared_data("lidar/autzen_trim.laz") {
        files.push(autzen);
    }
    for (i, file) in files.iter().enumerate() {
        let mut whole = CopcStream::open_whole(file, options()).unwrap();
        let copc = dir.path().join(format!("{i}.copc.laz"));
        pointblend::copc::write::write_copc(file, &copc, false).unwrap();
        let mut streamed = CopcStream::open(copc.to_str().unwrap(), options()).unwrap();
        let (held, read) = (everything_drawn(&mut whole), everything_drawn(&mut streamed));
        assert!(whole.tree.nodes.len() > 1, "{}: more than one node", file.display());
        assert_eq!(nodes_of(&whole), nodes_of(&streamed), "{}: the COPC file's octree", file.display());
        assert_eq!(held.origin, read.origin, "{}: one frame", file.display());
        assert_eq!(held.positions, read.positions, "{}: the same points in the same order", file.display());
        assert_eq!(held.normals, read.normals, "{}: estimated node by node alike", file.display());
        assert_eq!(held.radii, read.radii, "{}", file.display());
        assert_eq!(held.colours, read.colours, "{}", file.display());
        assert_eq!(whole.stats().bytes_read, 0, "nothing is read by range from a file held whole");
        let (in_file, count, grid) = records(file);
        let drawn: HashSet<[i64; 3]> = (0..held.len())
            .map(|i| on_grid((held.frame_position(i) + glam::DVec3::from_array(held.origin)).to_array(), grid))
            .collect();
        assert_eq!(drawn, in_file, "{}: every position of the file, and none other", file.display());
        assert!(held.len() <= count && held.len() * 100 >= count * 99, "{}: {} of {count}", file.display(), held.len());
    }
}

/// `render FILE.laz --point-budget N`: the image `render FILE.copc.laz
/// --point-budget N` gives, and the log says the file is held as an octree.
#[test]
fn render_under_a_point_budget_draws_a_las_file_as_its_copc_file() {
    let dir = tempfile::tempdir().unwrap();
    let laz = made_laz(dir.path(), 300);
    let copc = dir.path().join("tile.copc.laz");
    pointblend::copc::write::write_copc(&laz, &copc, false).unwrap();
    let render = |file: &Path, out: &str| {
        let out = dir.path().join(out);
        let args = [file.to_str().unwrap(), "--point-budget", "40000", "--size", "96x96", "--elevation", "50"];
        let (ok, stderr) = common::render_cli(&args, &out);
        assert!(ok, "{stderr}");
        (image::open(&out).unwrap().to_rgba8(), stderr)
    };
    let (held, log) = render(&laz, "held.png");
    let (streamed, _) = render(&copc, "streamed.png");
    assert!(log.contains("held in memory as an octree"), "{log}");
    assert!(held.pixels().any(|p| p.0 != held.get_pixel(0, 0).0), "the planes are drawn");
    assert_eq!(held, streamed, "the COPC file's image");
}

/// A pan over a file held whole estimates the nodes it adds and no other.
#[test]
fn a_pan_over_a_file_held_whole_estimates_only_the_nodes_it_adds() {
    let dir = tempfile::tempdir().unwrap();
    let laz = made_laz(dir.path(), 400);
    let mut s = CopcStream::open_whole(&laz, options()).unwrap();
    let far = Camera::default_for(&s.bounds_cloud(), 1.0);
    let select = StreamBudget::Points(60_000).select_options(Choosing::default());
    let mut drawn_before: HashSet<u32> = HashSet::new();
    let (mut redrawn, mut added_in_pans) = (0, 0);
    for step in 0..4 {
        let target = glam::Vec3::new(-36.0 + 24.0 * step as f32, 0.0, 0.0);
        let camera = Camera { target, distance: far.distance * 0.15, ..far };
        let estimated_before = s.stats().points_estimated;
        let drawn = s.frame(&camera, (64, 64), select, &LoadOptions::default()).unwrap().drawn;
        let added: Vec<u32> = drawn.iter().copied().filter(|n| !drawn_before.contains(n)).collect();
        let added_points: u64 = added.iter().map(|&n| u64::from(s.tree.nodes[n as usize].points)).sum();
        assert_eq!(s.stats().points_estimated - estimated_before, added_points, "view {step}: only the nodes added");
        if step > 0 {
            redrawn += drawn.len() - added.len();
            added_in_pans += added.len();
        }
        drawn_before.extend(drawn);
    }
    assert!(redrawn > 0 && added_in_pans > 0, "the pans draw nodes again ({redrawn}) and add some ({added_in_pans})");
}

/// `render --camera SHOT.json` draws a LAS file as the window did: node by
/// node when the sidecar says the window drew nodes, whole otherwise, under
/// the same budget.
#[test]
fn a_screenshot_of_nodes_renders_nodes_and_one_of_the_whole_file_renders_it_whole() {
    use pointblend::frame::sidecar::{Sidecar, SidecarModel};
    let dir = tempfile::tempdir().unwrap();
    let laz = made_laz(dir.path(), 300);
    for nodes in [true, false] {
        let path = laz.display().to_string();
        let model =
            SidecarModel { name: "tile.laz".into(), path, hash: "0".into(), splats: 1, nodes, layers: Vec::new() };
        let settings = pointblend::render::RenderSettings { point_budget: Some(40_000), ..Default::default() };
        let camera = Camera::framing(glam::Vec3::ZERO, 80.0, 1.0);
        let shot = dir.path().join(format!("shot-{nodes}.json"));
        Sidecar::new(model, &camera, &settings, (64, 64)).write(&shot).unwrap();
        let args = [laz.to_str().unwrap(), "--camera", shot.to_str().unwrap()];
        let (ok, log) = common::render_cli(&args, &dir.path().join(format!("shot-{nodes}.png")));
        assert!(ok, "{log}");
        assert_eq!(log.contains("held in memory as an octree"), nodes, "nodes recorded: {nodes}; {log}");
    }
}

//! COPC streaming: the samples' hierarchies read page by page and node by
//! node, the image of every node streamed equal to the file loaded whole,
//! the same image over a real HTTP server (nginx) with only the top levels
//! read for a far view, and bad servers and files refused in one line or
//! skipped node by node.

mod common;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use common::lidar::{self, tilted_grid};
use common::nginx::Nginx;
use pointblend::cloud::{self, LoadOptions};
use pointblend::copc::subset::StreamSubset;
use pointblend::copc::{CopcStream, StreamBudget, StreamOptions};
use pointblend::frame::Camera;
use pointblend::frame::subset::Subset;
use pointblend::lod::{Choosing, SelectOptions};
use pointblend::render::{PreparedScene, RenderMode, RenderSettings};
use pointblend::scene::Scene;

const SIZE: u32 = 160;

/// Every node, whatever the view (no culling, no budget, no pixel limit).
fn everything() -> SelectOptions {
    SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 }
}

fn stream(name: &str) -> CopcStream {
    CopcStream::open(name, StreamOptions { cache_bytes: 1 << 30, ..Default::default() }).expect("opens")
}

#[test]
fn every_node_of_the_samples_decodes_to_the_count_its_hierarchy_gives() {
    for (sample, nodes) in [("lidar/lone-star.copc.laz", 15), ("lidar/1.2-with-color.copc.laz", 65)] {
        let path = require!(common::shared_data(sample));
        let mut s = stream(&path.display().to_string());
        let camera = Camera::default_for(&s.bounds_cloud(), 1.0);
        let selection = s.select(&camera, (SIZE, SIZE), everything());
        s.load(&selection);
        // The las crate reads the whole hierarchy EVLR at once: an independent reader of the same pages.
        let reader = las::CopcReader::from_path(&path).unwrap();
        let entries: Vec<las::copc::Entry> = reader.hierarchy_entries().filter(|e| e.point_count > 0).collect();
        assert_eq!(entries.len(), nodes, "{sample}: nodes with points");
        let mut total = 0;
        for entry in &entries {
            let node = s.tree.node(&entry.key).unwrap_or_else(|| panic!("{sample}: {:?} was not read", entry.key));
            assert_eq!(s.tree.nodes[node as usize].points as i32, entry.point_count, "{sample} {:?}", entry.key);
            let decoded = s.decoded_points(node).unwrap_or_else(|| panic!("{sample}: {:?} did not load", entry.key));
            assert_eq!(decoded as i32, entry.point_count, "{sample} {:?}: decoded points", entry.key);
            total += decoded as u64;
        }
        assert_eq!(total, reader.header().number_of_points(), "{sample}: the nodes' points and the header's count");
        assert_eq!(s.stats().failed, 0);
    }
}

fn render(scene: Scene, camera: &Camera, mode: RenderMode) -> image::RgbaImage {
    let mut frames = PreparedScene::of(Arc::new(scene));
    let settings = RenderSettings { mode, ..Default::default() };
    let mut renderer = common::renderer();
    frames.render(Some(&mut *renderer), camera, &settings, (SIZE, SIZE), false).expect("render").image
}

/// Every node of a sample streamed, each decoded and estimated on its own,
/// holds the points of the file loaded whole, at the same positions.
#[test]
fn every_node_prepared_on_its_own_holds_the_points_of_the_file_loaded_whole() {
    for sample in ["lidar/lone-star.copc.laz", "lidar/1.2-with-color.copc.laz"] {
        let path = require!(common::shared_data(sample));
        let (whole, _) = cloud::load(&path).unwrap();
        let mut s = stream(&path.display().to_string());
        let camera = Camera::default_for(&whole, 1.0);
        let frame = s.frame(&camera, (SIZE, SIZE), everything(), &LoadOptions::default()).unwrap();
        assert_eq!(frame.cloud.origin, whole.origin, "{sample}: one frame, the header bounds' centre");
        let sorted = |c: &cloud::PointCloud| {
            let mut bits: Vec<[u32; 3]> = c.positions.iter().map(|p| p.to_array().map(f32::to_bits)).collect();
            bits.sort_unstable();
            bits
        };
        assert_eq!(frame.cloud.len(), whole.len(), "{sample}: points");
        assert!(sorted(&frame.cloud) == sorted(&whole), "{sample}: the same positions");
    }
}

/// Seams and coarse points: every node streamed, each estimated on its own
/// with a halo of the loaded nodes around and above it, draws the image of
/// the file loaded whole (estimated at once) within ε 0.5, in two-pass and
/// `tiled`: the whole view, and a close-up on the border between the
/// root's children, where the most nodes meet. A coarse node's points are
/// drawn as the deepest node drawn at their position estimated them, with
/// its neighbours, when it arrived (`copc/drawn_estimates.rs`).
#[test]
fn nodes_estimated_on_their_own_draw_the_file_loaded_whole() {
    let dir = tempfile::tempdir().unwrap();
    let made = made_copc(dir.path(), 300);
    let sample = require!(common::shared_data("lidar/1.2-with-color.copc.laz"));
    for path in [sample, made] {
        let (whole, _) = cloud::load(&path).unwrap();
        let mut s = stream(&path.display().to_string());
        let camera = Camera::default_for(&whole, 1.0);
        let frame = s.frame(&camera, (SIZE, SIZE), everything(), &LoadOptions::default()).unwrap();
        let levels = frame.cloud.attributes.get("node_level").expect("a streamed frame's levels");
        let coarse = (0..frame.cloud.len()).filter(|&i| levels.get(i) < 1.0).count();
        assert!(coarse > 0 && coarse < whole.len(), "{}: coarse points are drawn with finer ones", path.display());
        let (min, side) = s.tree.cube(&las::copc::VoxelKey { l: 0, x: 0, y: 0, z: 0 });
        let border = (min + glam::DVec3::splat(side * 0.5) - s.tree.origin).as_vec3();
        let centre = whole.bounds().unwrap().center();
        let close = Camera {
            target: glam::Vec3::new(border.x, border.y, centre.z),
            distance: camera.distance * 0.25,
            ..camera
        };
        for (view, camera) in [("whole", camera), ("close-up", close)] {
            for mode in [RenderMode::TwoPass, RenderMode::Tiled] {
                let a = render(Scene::from(whole.clone()), &camera, mode);
                let b = render(Scene::from(frame.cloud.clone()), &camera, mode);
                assert!(a.pixels().any(|p| p.0 != a.get_pixel(0, 0).0), "{mode}: a blank frame");
                let eps = pointblend::reference::metrics::compare(&b, &a).unwrap().eps;
                let max = common::tolerances::MAX_STREAMED_EPS;
                assert!(eps <= max, "{}, {view}, {mode}: ε {eps:.3} against the file loaded whole", path.display());
            }
        }
    }
}

/// A COPC file of `side`² ground points and as many 4 m above (made by
/// `convert`'s writer from a LAZ the las crate wrote).
#[test]
fn a_perfect_grid_of_one_colour_streams_every_point() {
    // The most regular data there is (a gridded elevation model exported as
    // points, every attribute the same): its chunks compress about 90 times.
    let dir = tempfile::tempdir().unwrap();
    let mut points = tilted_grid(700, 0.25, 0.0, [600_000.0, 4_000_000.0, 100.0]);
    for p in &mut points {
        (p.intensity, p.class, p.return_number, p.returns) = (0, 2, 1, 1);
        (p.gps_time, p.rgb) = (0.0, [30_000; 3]);
    }
    let laz = lidar::write(&dir.path().join("grid.laz"), &points, [600_000.0, 4_000_000.0, 0.0], None);
    let copc = dir.path().join("grid.copc.laz");
    pointblend::copc::write::write_copc(&laz, &copc, false).unwrap();
    let mut s = stream(&copc.display().to_string());
    let selection = s.select(&Camera::default_for(&s.bounds_cloud(), 1.0), (SIZE, SIZE), everything());
    s.load(&selection);
    assert_eq!(s.stats().failed, 0, "every node decodes");
    let record = las::Reader::from_path(&copc).unwrap().header().point_format().len() as f64;
    let (mut total, mut most_compressed) = (0usize, 0.0f64);
    for node in 0..s.tree.nodes.len() as u32 {
        let n = &s.tree.nodes[node as usize];
        if n.points == 0 {
            continue;
        }
        let ratio = n.points as f64 * record / n.byte_size as f64;
        most_compressed = most_compressed.max(ratio);
        total += s.decoded_points(node).unwrap_or_else(|| panic!("node {node} did not load"));
    }
    eprintln!(
        "{} points in {} nodes, the most compressed chunk {most_compressed:.0} times",
        total,
        selection.nodes.len()
    );
    assert_eq!(total, points.len(), "the nodes' points and the file's");
    assert!(most_compressed > 64.0, "a chunk compressed {most_compressed:.0} times: no more regular than real scans");
}

fn made_copc(dir: &Path, side: usize) -> PathBuf {
    let laz = lidar::two_planes(&dir.join("source.laz"), side, 0.25, [600_000.0, 4_000_000.0, 100.0], 4.0);
    let copc = dir.join("tile.copc.laz");
    let written = pointblend::copc::write::write_copc(&laz, &copc, false).unwrap();
    assert_eq!(written.points as usize, 2 * side * side);
    copc
}

/// `pointblend render ARGS` at a fixed view: the image, or the error line.
fn render_cli(file: &str, extra: &[&str], out: &Path) -> Result<image::RgbaImage, String> {
    let mut args: Vec<String> =
        [file, "--size", "128x128", "--azimuth", "30", "--elevation", "35"].iter().map(|s| s.to_string()).collect();
    args.extend(extra.iter().map(|s| s.to_string()));
    let (ok, stderr) = common::render_cli(&args, out);
    if ok { Ok(image::open(out).unwrap().to_rgba8()) } else { Err(stderr) }
}

#[test]
fn over_http_the_image_equals_the_image_from_disk_and_a_far_view_reads_only_the_top_levels() {
    let dir = tempfile::tempdir().unwrap();
    // 2 × 1000² = 2M points.
    let copc = made_copc(dir.path(), 1000);
    let server = Nginx::serve(dir.path());
    let url = server.url("tile.copc.laz");
    let budget = ["--point-budget", "150000"];
    let disk = render_cli(&copc.display().to_string(), &budget, &dir.path().join("disk.png")).unwrap();
    let http = render_cli(&url, &budget, &dir.path().join("http.png")).unwrap();
    assert!(disk.pixels().any(|p| p.0 != disk.get_pixel(0, 0).0), "a blank frame");
    assert!(disk == http, "the image over HTTP differs from the image from disk");

    // A far view: the tile covers a few pixels, so only the top levels are read.
    let mut s = stream(&url);
    let mut camera = Camera::default_for(&s.bounds_cloud(), 1.0);
    camera.distance *= 40.0;
    let options = SelectOptions { budget: 1_000_000, radius_scale: 1.0, cull: true, finest_px: 1.0 };
    let frame = s.frame(&camera, (SIZE, SIZE), options, &LoadOptions::default()).unwrap();
    let deepest = s.tree.nodes.iter().map(|n| n.key.l).max().unwrap();
    let drawn = frame.drawn.iter().map(|&n| s.tree.nodes[n as usize].key.l).max().unwrap();
    let stats = s.stats();
    let file_len = std::fs::metadata(&copc).unwrap().len();
    println!(
        "far view: levels 0..={drawn} of 0..={deepest}, {} points, {} of {file_len} bytes in {} requests",
        frame.cloud.len(),
        stats.bytes_read,
        stats.requests
    );
    assert!(drawn < deepest, "the far view read level {drawn}, the deepest");
    assert!(stats.bytes_read * 10 < file_len, "the far view read {} of {file_len} bytes", stats.bytes_read);
    let far_pages = s.tree.pages_read;

    // Every node: every page is read then, and the tree is the las crate's (which reads the whole EVLR).
    let all = s.select(&camera, (SIZE, SIZE), everything());
    let reader = las::CopcReader::from_path(&copc).unwrap();
    let entries: Vec<las::copc::Entry> = reader.hierarchy_entries().filter(|e| e.point_count > 0).collect();
    println!("pages read: {far_pages} for the far view, {} in all", s.tree.pages_read);
    assert!(far_pages < s.tree.pages_read, "the far view read every hierarchy page");
    assert_eq!(all.nodes.iter().filter(|&&n| s.tree.nodes[n as usize].points > 0).count(), entries.len());
    for entry in &entries {
        let node = s.tree.node(&entry.key).unwrap_or_else(|| panic!("{:?} was not read", entry.key));
        assert_eq!(s.tree.nodes[node as usize].points as i32, entry.point_count, "{:?}", entry.key);
    }
    assert_eq!(s.tree.known_points(), reader.header().number_of_points());
}

/// The error line of `render` on `file`.
fn refused(file: &str, out: &Path, what: &str) -> String {
    let err = render_cli(file, &[], out).expect_err(what);
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{what}: {err}");
    assert!(!out.exists(), "{what} wrote an image");
    errors[0].to_string()
}

#[test]
fn bad_servers_and_files_are_one_line_and_a_corrupt_node_is_skipped() {
    let dir = tempfile::tempdir().unwrap();
    // 2 × 300² points: a root and its children.
    let copc = made_copc(dir.path(), 300);
    let bytes = std::fs::read(&copc).unwrap();
    // A copy cut short, and one whose root hierarchy page lies past the end (the info VLR's bytes 40..48).
    std::fs::write(dir.path().join("short.copc.laz"), &bytes[..bytes.len() * 2 / 3]).unwrap();
    let mut past = bytes.clone();
    let info_data = 375 + 54;
    past[info_data + 40..info_data + 48].copy_from_slice(&(bytes.len() as u64 + 4096).to_le_bytes());
    std::fs::write(dir.path().join("past.copc.laz"), &past).unwrap();
    let server = Nginx::serve(dir.path());
    let out = |name: &str| dir.path().join(format!("{name}.png"));

    let line = refused(&server.url("norange/tile.copc.laz"), &out("norange"), "a server that ignores Range");
    assert!(line.contains("ignores Range"), "{line}");
    let line = refused(&server.url("missing.copc.laz"), &out("missing"), "a 404");
    assert!(line.contains("404"), "{line}");
    // A 503 is retried with backoff (0.25 + 0.5 + 1 + 2 s), then refused.
    let started = std::time::Instant::now();
    let line = refused(&server.url("unavailable/tile.copc.laz"), &out("unavailable"), "a 503");
    assert!(line.contains("HTTP 503") && line.contains("after 4 retries"), "{line}");
    assert!(started.elapsed().as_secs_f64() > 3.5, "no backoff: {:?}", started.elapsed());
    let line = refused(&server.url("short.copc.laz"), &out("short"), "a truncated file");
    assert!(line.contains("past the end"), "{line}");
    let line = refused(&server.url("past.copc.laz"), &out("past"), "a page past the end");
    assert!(line.contains("root hierarchy page") && line.contains("past the end"), "{line}");
    let line = refused(&dir.path().join("past.copc.laz").display().to_string(), &out("past-disk"), "from disk");
    assert!(line.contains("past the end"), "{line}");

    // A corrupt chunk (the root's): the node is skipped and counted, the frame drawn from the rest.
    let s = stream(&copc.display().to_string());
    assert!(s.tree.nodes.len() > 1, "the file has children");
    let leaf = s.tree.nodes[s.tree.node(&las::copc::VoxelKey::ROOT).unwrap() as usize].clone();
    let mut corrupt = bytes.clone();
    let middle = (leaf.offset + leaf.byte_size / 2) as usize;
    corrupt[middle..middle + 64].iter_mut().for_each(|b| *b = !*b);
    std::fs::write(dir.path().join("corrupt.copc.laz"), &corrupt).unwrap();
    let mut args: Vec<String> =
        [server.url("corrupt.copc.laz").as_str(), "--size", "256x256"].iter().map(|s| s.to_string()).collect();
    args.extend(["--point-budget".to_string(), "100000000".to_string()]);
    let (ok, stderr) = common::render_cli(&args, &out("corrupt"));
    assert!(ok, "a corrupt node stopped the frame: {stderr}");
    let key = format!("node {}-{}-{}-{} skipped", leaf.key.l, leaf.key.x, leaf.key.y, leaf.key.z);
    assert!(stderr.contains(&key), "no line says {key}: {stderr}");
    assert!(stderr.contains("1 nodes failed"), "the failure is not counted: {stderr}");
    let image = image::open(out("corrupt")).unwrap().to_rgba8();
    assert!(image.pixels().any(|p| p.0 != image.get_pixel(0, 0).0), "a blank frame");
}

#[test]
fn the_disk_cache_serves_a_second_open_and_nothing_is_written_without_it() {
    let dir = tempfile::tempdir().unwrap();
    let copc = made_copc(dir.path(), 300);
    let cache = dir.path().join("chunks");
    let name = copc.display().to_string();
    let options = StreamOptions { cache_bytes: 1 << 30, disk_cache: Some(cache.clone()), ..Default::default() };
    let camera = Camera::default_for(&stream(&name).bounds_cloud(), 1.0);
    let mut read = Vec::new();
    for _ in 0..2 {
        let mut s = CopcStream::open(&name, options.clone()).unwrap();
        let frame = s.frame(&camera, (SIZE, SIZE), everything(), &LoadOptions::default()).unwrap();
        read.push((s.stats().bytes_read, frame.cloud.len()));
    }
    let files = std::fs::read_dir(cache.read_dir().unwrap().next().unwrap().unwrap().path()).unwrap().count();
    println!("disk cache: {files} chunks; bytes read from the file {:?}", read);
    assert!(files > 1, "the chunks were kept");
    assert_eq!(read[0].1, read[1].1, "the same points");
    assert!(
        read[1].0 * 20 < read[0].0,
        "the second open read {} bytes of the file, the first {}",
        read[1].0,
        read[0].0
    );
    // Without the option, streaming writes nothing beside the file.
    let before: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    let mut s = stream(&name);
    s.frame(&camera, (SIZE, SIZE), everything(), &LoadOptions::default()).unwrap();
    let after: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(before, after);
}

/// `render`'s last line: `FILE: N splats, …`, N the splats drawn.
fn splats_drawn(file: &Path, extra: &[&str]) -> usize {
    let out = tempfile::tempdir().unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("render")
        .arg(file)
        .args(extra)
        .arg("--out")
        .arg(out.path().join("f.png"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let last = stdout.lines().last().unwrap_or_default();
    let n = last.split(": ").nth(1).and_then(|rest| rest.split(' ').next()).and_then(|n| n.parse().ok());
    n.unwrap_or_else(|| panic!("no splat count in {last}"))
}

#[test]
fn point_budget_all_draws_every_point_of_a_streamed_file_and_a_number_keeps_the_pixel_stop() {
    let dir = tempfile::tempdir().unwrap();
    // Above the writer's 100,000 points a node: a root and its children.
    let copc = made_copc(dir.path(), 230);
    let stream = CopcStream::open(&copc.to_string_lossy(), Default::default()).unwrap();
    let total = stream.points() as usize;
    // A far, small view: under a number the one-pixel stop leaves the fine levels out.
    let far = ["--size", "64x64", "--distance", "2000"];
    let all = splats_drawn(&copc, &[&far[..], &["--point-budget", "all"]].concat());
    let numbered = splats_drawn(&copc, &[&far[..], &["--point-budget", "1000000"]].concat());
    println!("{total} points: all drew {all}, a budget of 1M drew {numbered}");
    assert_eq!(all, total, "--point-budget all draws every point");
    assert!(numbered < total, "a numeric budget keeps the pixel stop: {numbered} of {total}");
    // When every point would not fit the node cache: one line that says so.
    let out = dir.path().join("never.png");
    let (ok, stderr) = common::render_cli(
        &[copc.display().to_string(), "--point-budget".into(), "all".into(), "--cache-mb".into(), "1".into()],
        &out,
    );
    assert!(!ok && stderr.contains("--point-budget all") && stderr.contains("--cache-mb"), "{stderr}");
    assert!(!out.exists());
    // The sample the README's users meet first: all of its 1,065 points.
    let sample = require!(common::shared_data("lidar/1.2-with-color.copc.laz"));
    let sample_points = CopcStream::open(&sample.to_string_lossy(), Default::default()).unwrap().points() as usize;
    assert_eq!(splats_drawn(&sample, &["--size", "256x256", "--point-budget", "all"]), sample_points);
}

#[test]
fn a_scene_file_opens_a_url_as_the_command_line_does() {
    let dir = tempfile::tempdir().unwrap();
    let copc = made_copc(dir.path(), 120);
    let server = Nginx::serve(dir.path());
    let url = server.url(copc.file_name().unwrap().to_str().unwrap());
    let scene = dir.path().join("elsewhere").join("scene.toml");
    std::fs::create_dir_all(scene.parent().unwrap()).unwrap();
    std::fs::write(&scene, format!("[[object]]\ncloud = {url:?}\nopacity = 0.5\n")).unwrap();
    let total = CopcStream::open(&copc.to_string_lossy(), Default::default()).unwrap().points() as usize;
    assert_eq!(splats_drawn(&scene, &["--size", "96x96", "--mode", "tiled"]), total, "every point of the URL");
    // A URL the server does not have: the scene file's line and column, and the URL.
    std::fs::write(&scene, format!("[[object]]\ncloud = \"{}\"\n", server.url("gone.copc.laz"))).unwrap();
    let out = dir.path().join("never.png");
    let error = common::refused_in_one_line(&[scene.display().to_string()], &out, "a URL that is not there");
    assert!(error.contains("scene.toml:2:9") && error.contains("gone.copc.laz"), "{error}");
}

#[test]
fn a_lit_streamed_frame_keeps_the_nodes_off_screen_that_cast_its_shadows() {
    let dir = tempfile::tempdir().unwrap();
    let copc = made_copc(dir.path(), 230);
    let s = stream(&copc.display().to_string());
    // Close up on a corner of the 57 m tile: under a budget the nodes out of
    // view are left out, unless the frame is lit by scene lights, whose
    // shadows those nodes still cast (as the in-memory budget keeps them).
    let bounds = s.bounds_cloud();
    let mut camera = Camera::default_for(&bounds, 1.0);
    camera.target = bounds.positions.iter().copied().fold(glam::Vec3::INFINITY, glam::Vec3::min);
    camera.distance = 8.0;
    let unlit = RenderSettings::default();
    let light = pointblend::frame::Light::point(camera.target + glam::Vec3::new(0.0, 0.0, 50.0));
    let lit = RenderSettings { lights: pointblend::frame::Lights::new(&[light]).unwrap(), ..unlit };
    // Through the subset every front end chooses a streamed frame with.
    let mut subset = StreamSubset::new(s, StreamBudget::Points(1_000_000), LoadOptions::default());
    let mut drawn = |settings: &RenderSettings| {
        let choice = subset.choose(&camera, (64, 64), Choosing::of(settings)).unwrap();
        choice.cloud.expect("a stream's choice holds its points").len()
    };
    let (unlit, lit) = (drawn(&unlit), drawn(&lit));
    println!("a close view of a corner drew {unlit} splats unlit and {lit} lit by a scene light");
    assert!(lit > unlit, "the lit frame culled the off-screen casters: {lit} splats against {unlit} unlit");
}

/// `bench FILE --path views.json` times the views of a camera path in path
/// order, in one process, each row with what its view cost (the same on every
/// row of that view). The first view loads, prepares and uploads its nodes;
/// the same view again draws the same nodes, so it reads, prepares and
/// uploads nothing; a close view of a corner reads finer nodes the far one
/// did not.
#[test]
fn bench_along_a_path_reports_what_each_view_cost_in_path_order() {
    use pointblend::frame::ViewPath;
    let dir = tempfile::tempdir().unwrap();
    let copc = made_copc(dir.path(), 400);
    let (far, corner) = (looking_at(glam::Vec3::ZERO, 200.0), looking_at(glam::Vec3::new(45.0, 45.0, 0.0), 6.0));
    let views = dir.path().join("views.json");
    ViewPath::new(&[far, far, corner]).write(&views).unwrap();
    let of_view = path_costs(&copc, &views, 3, &["--point-budget", "100000"]);
    let [_, nodes, bytes, points, seconds, uploaded] = of_view[0][..] else { unreachable!() };
    assert!(nodes > 0.0 && bytes > 0.0 && points > 0.0 && seconds > 0.0 && uploaded > 0.0, "first: {:?}", of_view[0]);
    assert_eq!(of_view[1][1..], [0.0; 5], "the same view again costs nothing: {:?}", of_view[1]);
    assert!(of_view[2][1] > 0.0 && of_view[2][2] > 0.0, "the close view reads finer nodes: {of_view:?}");
    assert!(of_view[2][5] > 0.0, "and uploads them: {:?}", of_view[2]);
}

/// A camera over the made file's plane, `distance` from `target` (relative to the centre of its bounds).
fn looking_at(target: glam::Vec3, distance: f32) -> Camera {
    Camera {
        target,
        distance,
        azimuth_deg: 30.0,
        elevation_deg: 60.0,
        fov_y_deg: 40.0,
        up: pointblend::frame::UpAxis::PosZ,
        scene_radius: 30.0,
        projection: Default::default(),
    }
}

/// `render FILE.copc.laz --path`: each frame of a flight selects its own
/// nodes (shown in one prepared scene, whose GPU pool keeps the nodes two
/// frames share), so a flight from far to near ends on what a flight that
/// stays near draws (coloured by octree level), within one step of a
/// channel (the same splats, in other slots).
#[test]
fn a_flight_through_a_streamed_file_selects_the_nodes_of_each_frame() {
    use pointblend::frame::ViewPath;
    let dir = tempfile::tempdir().unwrap();
    let copc = made_copc(dir.path(), 400);
    // From far (the root alone, at 96²) to near (level-1 nodes too).
    let (far, near) = (looking_at(glam::Vec3::ZERO, 200.0), looking_at(glam::Vec3::ZERO, 40.0));
    let flight = |views: &[Camera], name: &str| -> Vec<image::RgbaImage> {
        let path = dir.path().join(format!("{name}.json"));
        ViewPath::new(views).write(&path).unwrap();
        let out = dir.path().join(name).join("f.png");
        let args = [copc.to_str().unwrap(), "--path", path.to_str().unwrap(), "--path-frames", "3"];
        // Coloured by octree level: a frame drawn from another selection's nodes shows it.
        let style = ["--color-by", "node_level", "--range", "0,4", "--size", "96x96", "--point-budget", "100000"];
        let (ok, stderr) = common::render_cli(&[&args[..], &style[..]].concat(), &out);
        assert!(ok, "{stderr}");
        (0..3).map(|k| image::open(out.with_file_name(format!("f-{k:04}.png"))).unwrap().to_rgba8()).collect()
    };
    let flown = flight(&[far, near], "flown");
    let stayed = flight(&[near, near], "stayed");
    let largest = flown[2].as_raw().iter().zip(stayed[2].as_raw()).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
    assert!(largest <= 1, "the flight's last frame differs by {largest} from the near view's own selection");
    assert_ne!(flown[0], flown[2], "the camera moved");
}

/// `bench FILE --path VIEWS` (`views` path views, two-pass, 64², one
/// frame, `extra` flags): each view's costs (view_index, nodes_added,
/// bytes_read, points_prepared, prepare_s, upload_bytes), checked to be the
/// same on every row of the view and the rows to come in path order.
fn path_costs(file: &Path, views: &Path, count: usize, extra: &[&str]) -> Vec<Vec<f64>> {
    let mut args: Vec<&str> = vec![file.to_str().unwrap(), "--path", views.to_str().unwrap(), "--modes", "two-pass"];
    args.extend(["--size", "64x64", "--frames", "1", "--warm-up", "0"]);
    args.extend(extra);
    let rows = common::bench_rows(&args, &views.with_file_name("bench"));
    let cost = |row: &serde_json::Value, key: &str| row[key].as_f64().unwrap_or_else(|| panic!("no {key}: {row}"));
    let keys = ["view_index", "nodes_added", "bytes_read", "points_prepared", "prepare_s", "upload_bytes"];
    let order: Vec<f64> = rows.iter().map(|r| cost(r, "view_index")).collect();
    assert!(order.windows(2).all(|w| w[0] <= w[1]), "rows in path order: {order:?}");
    (0..count)
        .map(|view| {
            let rows: Vec<_> = rows.iter().filter(|r| cost(r, "view_index") == view as f64).collect();
            assert!(rows.len() >= 2, "view {view}: the reference's row and two-pass's: {rows:?}");
            let costs: Vec<f64> = keys.iter().map(|k| cost(rows[0], k)).collect();
            for row in &rows {
                assert_eq!(keys.iter().map(|k| cost(row, k)).collect::<Vec<_>>(), costs, "one view, one cost");
            }
            costs
        })
        .collect()
}

/// A file opened whole is one node, read, prepared and uploaded for the
/// first view of a path; the other views cost nothing more (no point budget).
#[test]
fn a_file_opened_whole_is_prepared_once_for_the_first_view_of_a_path() {
    use pointblend::frame::ViewPath;
    let dir = tempfile::tempdir().unwrap();
    let points = tilted_grid(60, 0.25, 0.1, [600_000.0, 4_000_000.0, 100.0]);
    let laz = lidar::write(&dir.path().join("tile.laz"), &points, [600_000.0, 4_000_000.0, 0.0], None);
    let (cloud, _) = cloud::load(&laz).unwrap();
    let views = dir.path().join("views.json");
    let far = Camera::default_for(&cloud, 1.0);
    ViewPath::new(&[far, Camera { distance: far.distance * 0.3, ..far }]).write(&views).unwrap();
    let of_view = path_costs(&laz, &views, 2, &[]);
    let size = std::fs::metadata(&laz).unwrap().len() as f64;
    assert_eq!(of_view[0][1..4], [1.0, size, points.len() as f64], "one node, the file, every point");
    assert!(of_view[0][4] > 0.0 && of_view[0][5] > 0.0, "prepared and uploaded: {:?}", of_view[0]);
    assert_eq!(of_view[1][1..], [0.0; 5], "the next view costs nothing more: {:?}", of_view[1]);
}

/// A stream gathers, re-centres and estimates a view's points only when the
/// nodes it draws changed: the same view again yields no new points and the
/// same key; another view that draws other nodes yields them, under another key.
#[test]
fn a_view_that_draws_the_same_nodes_prepares_nothing_again() {
    let dir = tempfile::tempdir().unwrap();
    let copc = made_copc(dir.path(), 400);
    let stream = CopcStream::open(copc.to_str().unwrap(), StreamOptions::default()).unwrap();
    let mut subset = StreamSubset::new(stream, StreamBudget::Points(100_000), LoadOptions::default());
    let far = Camera::default_for(&subset.stream.bounds_cloud(), 1.0);
    let close = Camera { target: glam::Vec3::new(45.0, 45.0, 0.0), distance: 6.0, ..far };
    let choose =
        |subset: &mut StreamSubset, camera: &Camera| subset.choose(camera, (64, 64), Choosing::default()).unwrap();
    let first = choose(&mut subset, &far);
    let points = first.cloud.as_ref().map(|c| c.len()).expect("a first choice holds its points");
    assert!(points > 0);
    let again = choose(&mut subset, &far);
    assert!(again.cloud.is_none(), "the same nodes are not gathered again");
    assert_eq!(again.key, first.key);
    assert_eq!(subset.last.points, points, "the statistics still say what is drawn");
    let closer = choose(&mut subset, &close);
    assert!(closer.cloud.is_some_and(|c| c.len() != points) && closer.key != first.key, "other nodes, other points");
}

/// Pans cost what they add: along a path of pans over a sample, each view
/// estimates the normals and radii of the nodes it draws that no earlier
/// view drew, and no others; a point drawn again with the same deepest
/// node drawn at its position keeps its normal, bit for bit (a coarse
/// point is drawn as that node estimated it when it arrived).
#[test]
fn a_pan_estimates_only_the_nodes_it_adds() {
    let path = require!(common::shared_data("lidar/1.2-with-color.copc.laz"));
    let mut s = stream(&path.display().to_string());
    let far = Camera::default_for(&s.bounds_cloud(), 1.0);
    let options = StreamBudget::Points(100_000).select_options(Choosing::default());
    let bits = |p: glam::Vec3| p.to_array().map(f32::to_bits);
    let mut drawn_before = std::collections::HashSet::new();
    let mut normals: std::collections::HashMap<([u32; 3], i32), [u32; 3]> = std::collections::HashMap::new();
    let (root_min, root_side) = s.tree.cube(&las::copc::VoxelKey { l: 0, x: 0, y: 0, z: 0 });
    let (mut redrawn, mut added_in_pans) = (0, 0);
    for step in 0..6 {
        let target = glam::Vec3::new(-1200.0 + 400.0 * step as f32, 0.0, 0.0);
        let camera = Camera { target, distance: 500.0, ..far };
        let estimated_before = s.stats().points_estimated;
        let selection = s.select(&camera, (SIZE, SIZE), options);
        s.load(&selection);
        let frame = s.gather(&selection, &LoadOptions::default(), None).unwrap();
        let added: Vec<u32> = frame.drawn.iter().copied().filter(|n| !drawn_before.contains(n)).collect();
        let added_points: u64 = added.iter().map(|&n| u64::from(s.tree.nodes[n as usize].points)).sum();
        assert_eq!(s.stats().points_estimated - estimated_before, added_points, "view {step}: only the nodes added");
        let drawn: std::collections::HashSet<u32> = frame.drawn.iter().copied().collect();
        // The level of the deepest node drawn at a position.
        let deepest = |i: usize| {
            let p = frame.cloud.frame_position(i) + glam::DVec3::from_array(frame.cloud.origin);
            (0..=12)
                .rev()
                .find(|&l| {
                    let c = ((p - root_min) / (root_side / f64::from(1u32 << l))).floor();
                    let key = las::copc::VoxelKey { l, x: c.x as i32, y: c.y as i32, z: c.z as i32 };
                    s.tree.node(&key).is_some_and(|n| drawn.contains(&n))
                })
                .unwrap_or(0)
        };
        for (i, (p, n)) in frame.cloud.positions.iter().zip(&frame.cloud.normals).enumerate() {
            let normal = *normals.entry((bits(*p), deepest(i))).or_insert(n.to_array().map(f32::to_bits));
            assert_eq!(normal, n.to_array().map(f32::to_bits), "view {step}: a point drawn again keeps its normal");
        }
        if step > 0 {
            redrawn += frame.drawn.len() - added.len();
            added_in_pans += added.len();
        }
        drawn_before.extend(frame.drawn);
    }
    assert!(redrawn > 0 && added_in_pans > 0, "the pans draw nodes again ({redrawn}) and add some ({added_in_pans})");
}

/// A streamed file's colours do not shift as the nodes drawn change: a
/// later selection styled with the first one's pinned style (its elevation
/// range fixed) colours every point it shares with the first as the first
/// did, where its own percentiles would not.
#[test]
fn a_later_selection_keeps_the_first_ones_colours() {
    let path = require!(common::shared_data("lidar/1.2-with-color.copc.laz"));
    let mut s = stream(&path.display().to_string());
    let far = Camera::default_for(&s.bounds_cloud(), 1.0);
    let close = Camera { target: glam::Vec3::new(-800.0, 0.0, 0.0), distance: 600.0, ..far };
    let options = StreamBudget::Points(100_000).select_options(Choosing::default());
    let style =
        pointblend::style::Style { color_by: Some(pointblend::style::ColorBy::Elevation), ..Default::default() };
    let mut scene_of = |camera: &Camera, style: &pointblend::style::Style| {
        let selection = s.select(camera, (SIZE, SIZE), options);
        s.load(&selection);
        let mut scene = Scene::from(s.gather(&selection, &LoadOptions::default(), None).unwrap().cloud);
        scene.apply_style(style).unwrap();
        scene
    };
    let first = scene_of(&far, &style);
    let pinned = first.pinned_style().expect("a styled scene");
    assert!(pinned.range.is_some(), "the range is fixed");
    let colours = |scene: &Scene| -> std::collections::HashMap<[u32; 3], [u8; 3]> {
        let cloud = &scene.objects[0].cloud;
        cloud.positions.iter().zip(&cloud.colours).map(|(p, c)| (p.to_array().map(f32::to_bits), *c)).collect()
    };
    let differing = |later: &Scene| {
        let (a, b) = (colours(&first), colours(later));
        let shared: Vec<_> = b.keys().filter(|k| a.contains_key(*k)).collect();
        assert!(shared.len() >= 20, "the selections share points: {}", shared.len());
        shared.iter().filter(|k| a[**k] != b[**k]).count()
    };
    assert_eq!(differing(&scene_of(&close, &pinned)), 0, "the pinned range colours shared points alike");
    assert!(differing(&scene_of(&close, &style)) > 0, "the close view's own percentiles would not");
}

//! `tiled` places its tile lists on the GPU: the counts' prefix sum is taken
//! there, within a room the entry buffer has, and a frame whose lists pass
//! it is drawn again with more room, which later frames keep. These tests
//! hold that a frame drawn again is the exact image, that the report says
//! so, and that the next frame needs no second try; and that the binning,
//! which keeps only the tiles a disc meets, keeps fewer entries than the
//! discs' boxes count and leaves the image exact.

mod common;

use common::tolerances::*;
use glam::Vec3;
use pointblend::cloud::PointCloud;
use pointblend::frame::{Camera, RenderSettings, View, resolve};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::scene::{Scene, primitives};

/// Two translucent planes of splats five times as wide as their spacing:
/// each splat covers many tiles, so the lists hold many more entries than
/// a new engine makes room for per splat.
fn dense_planes() -> Scene {
    let mut cloud = PointCloud::default();
    for (z, colour) in [(0.0, [230, 60, 40]), (-0.3, [40, 90, 230])] {
        let mut plane = primitives::plane(2500, 1.0, Vec3::new(0.0, 0.0, z), Vec3::Z);
        let spacing = 1.0 / 50.0;
        plane.radii.iter_mut().for_each(|r| *r = 5.0 * spacing);
        plane.colours.iter_mut().for_each(|c| *c = colour);
        plane.opacity.iter_mut().for_each(|a| *a = 0.5);
        cloud.positions.extend(plane.positions);
        cloud.normals.extend(plane.normals);
        cloud.radii.extend(plane.radii);
        cloud.colours.extend(plane.colours);
        cloud.opacity.extend(plane.opacity);
    }
    Scene::from(cloud)
}

#[test]
fn lists_past_their_room_are_drawn_again_exactly_and_later_frames_keep_the_room() {
    let scene = dense_planes();
    let camera = Camera::default_for(&scene.flattened(), 1.0);
    let settings = RenderSettings { mode: "tiled".parse().unwrap(), lighting: true, ..Default::default() };
    let size = 128;
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload(&scene, None);
    let spec = resolve(&settings, &gpu.facts(), &View::still((size, size)));

    let (first, _, report) = renderer.render_spec(&mut gpu, &camera, &spec, true).expect("first frame");
    let lists = report.tile_lists.clone().expect("the report states the tile lists");
    println!(
        "first frame: {} entries counted, {} kept, room for {}, retried {}",
        lists.entries, lists.kept, lists.capacity, lists.retried
    );
    let first_room = pointblend::render::tile_engine::FIRST_ROOM_PER_ITEM * scene.len() as u64;
    assert!(lists.entries > first_room, "the scene passes the first room: {} entries", lists.entries);
    assert!(lists.retried, "a frame past its room is drawn again: {report}");
    assert!(lists.capacity >= lists.entries, "room for every entry after the retry");
    assert!(report.to_string().contains("drawn again"), "the report says so: {report}");
    // Discs five spacings wide span several tiles, and their boxes' corners
    // hold tiles no ray of which hits them: the binning keeps fewer.
    assert!(lists.kept < lists.entries, "kept {} of {} counted", lists.kept, lists.entries);

    let (want, _) =
        reference::render_with_layers(&scene, &camera, &ReferenceOptions::matching(&settings, &scene), size, size);
    let error = reference::compare(&first, &want).unwrap();
    println!("frame drawn again against the reference: ε {:.4}", error.eps);
    assert!(error.eps <= MAX_TILED_EPS, "ε {}", error.eps);

    let (second, _, report) = renderer.render_spec(&mut gpu, &camera, &spec, true).expect("second frame");
    let lists = report.tile_lists.clone().expect("the report states the tile lists");
    assert!(!lists.retried, "the next frame keeps the room: {report}");
    assert_eq!(first, second, "the frame drawn again is the frame drawn once");
}

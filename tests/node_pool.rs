//! A streamed selection's nodes in a pool of GPU slots: along a path of
//! pans, a node drawn in both views stays where it is on the GPU, so a pan
//! writes only the records of the nodes it adds, drops or changes (a
//! coarser node's radii shrink where finer ones now cover it), and draws
//! what a fresh upload of the same selection, packed, draws in two-pass,
//! `tiled` and deferred (whose copy keeps each node's splats in group order).
//! A node a view drops stays on the GPU, undrawn, and a view that brings it
//! back writes nothing for it.

mod common;

use std::collections::HashMap;
use std::sync::Arc;

use common::lidar::{self, tilted_grid};
use pointblend::cloud::{LoadOptions, PointCloud};
use pointblend::copc::subset::StreamSubset;
use pointblend::copc::{CopcStream, StreamBudget, StreamOptions};
use pointblend::frame::subset::{Choice, NodeSpans, Subset};
use pointblend::frame::{Camera, View};
use pointblend::lod::Choosing;
use pointblend::render::{GpuRenderer, PreparedScene, RenderMode, RenderSettings};
use pointblend::scene::Scene;

/// Bytes of one splat record on the GPU.
const RECORD: u64 = std::mem::size_of::<pointblend::render::gpu_data::SplatInstance>() as u64;
/// Unchanged records a rewrite may write to join two runs of changed ones.
const JOIN: u64 = pointblend::render::changed_records::REWRITE_GAP as u64;
const SIZE: (u32, u32) = (128, 128);

/// A COPC file of `side`² ground points on a tilted plane (0.25 m apart), in several nodes.
fn made_copc(dir: &std::path::Path, side: usize) -> String {
    let points = tilted_grid(side, 0.25, 0.1, [600_000.0, 4_000_000.0, 100.0]);
    let laz = lidar::write(&dir.join("source.laz"), &points, [600_000.0, 4_000_000.0, 0.0], None);
    let copc = dir.join("tile.copc.laz");
    pointblend::copc::write::write_copc(&laz, &copc, false).unwrap();
    copc.display().to_string()
}

fn modes() -> [RenderSettings; 3] {
    [RenderMode::TwoPass, RenderMode::Tiled, RenderMode::Deferred]
        .map(|mode| RenderSettings { mode, ..Default::default() })
}

/// The choice's scene, with its nodes (pooled on the GPU) or without (packed, as a file opened whole is).
fn scene_of(cloud: PointCloud, choice: &Choice, pooled: bool) -> Arc<Scene> {
    let scene = Scene::single("tile", cloud, choice.key).with_node_grouping(choice.grouping.clone());
    Arc::new(scene.with_node_spans(choice.spans.clone().filter(|_| pooled)))
}

fn images(frames: &mut PreparedScene, renderer: &mut GpuRenderer, camera: &Camera) -> Vec<image::RgbaImage> {
    modes().iter().map(|s| frames.render(Some(&mut *renderer), camera, s, SIZE, false).expect("render").image).collect()
}

/// The splats of the nodes a pan touches, and how many nodes: those it
/// adds, those it drops (their slots are marked vacant), and those drawn
/// in both views whose records changed (or whose splat count did).
fn touched(before: (&NodeSpans, &PointCloud), after: (&NodeSpans, &PointCloud)) -> (u64, u64) {
    let old: HashMap<u32, std::ops::Range<u32>> = before.0.0.iter().cloned().collect();
    let new: HashMap<u32, std::ops::Range<u32>> = after.0.0.iter().cloned().collect();
    let same = same_splat;
    let (mut splats, mut nodes) = (0u64, 0u64);
    for (node, range) in &new {
        let kept = old.get(node).filter(|o| o.len() == range.len());
        let unchanged = kept.is_some_and(|o| o.clone().zip(range.clone()).all(|(i, j)| same(before.1, i, after.1, j)));
        if !unchanged {
            (splats, nodes) = (splats + range.len() as u64, nodes + 1);
        }
    }
    for (node, range) in &old {
        if new.get(node).is_none_or(|n| n.len() != range.len()) {
            (splats, nodes) = (splats + range.len() as u64, nodes + 1);
        }
    }
    (splats, nodes)
}

/// Whether splat `i` of `a` and splat `j` of `b` make the same record.
fn same_splat(a: &PointCloud, i: u32, b: &PointCloud, j: u32) -> bool {
    let (i, j) = (i as usize, j as usize);
    a.positions[i] == b.positions[j]
        && a.normals[i] == b.normals[j]
        && a.radii[i] == b.radii[j]
        && a.colours[i] == b.colours[j]
        && a.opacity[i] == b.opacity[j]
}

/// Slots of the two GPU copies a frame of each mode draws (the ungrouped
/// one two-pass and `tiled` share, and deferred's grouped one), vacant ones included.
fn slots(frames: &mut PreparedScene, renderer: &GpuRenderer) -> u64 {
    let [two_pass, _, deferred] = modes();
    [two_pass, deferred]
        .iter()
        .map(|settings| {
            let spec = frames.resolve(settings, View::still(SIZE));
            frames.gpu_scene(renderer, &spec).expect("uploaded").slot_count() as u64
        })
        .sum()
}

/// The largest difference of one channel between two images.
fn largest_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> u8 {
    a.as_raw().iter().zip(b.as_raw()).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0)
}

/// A stream of a 700² plane (490,000 points) under a 100K budget, the
/// camera that frames it, and how its selections are chosen: for deferred,
/// so each node gets its labels (two-pass and `tiled` ignore them).
fn plane_stream(dir: &std::path::Path) -> (StreamSubset, Camera, Choosing) {
    let name = made_copc(dir, 700);
    let stream = CopcStream::open(&name, StreamOptions { cache_bytes: 1 << 30, ..Default::default() }).unwrap();
    let far = Camera::default_for(&stream.bounds_cloud(), 1.0);
    let subset = StreamSubset::new(stream, StreamBudget::Points(100_000), LoadOptions::default());
    (subset, far, Choosing::of(&modes()[2]))
}

#[test]
fn a_pan_writes_only_the_nodes_it_changes_and_draws_what_a_fresh_upload_draws() {
    let dir = tempfile::tempdir().unwrap();
    let (mut subset, far, choosing) = plane_stream(dir.path());
    let mut renderer = common::renderer();
    let mut shown: Option<(PreparedScene, Arc<NodeSpans>, PointCloud)> = None;
    let (mut pans, mut bounds, mut fresh_uploads) = (0, 0u64, 0u64);
    // Pans of 6 m, 20 m above a 175 m plane of 490,000 points.
    for step in 0..6 {
        let target = glam::Vec3::new(-30.0 + 6.0 * step as f32, 0.0, 0.0);
        let camera = Camera { target, distance: 20.0, ..far };
        let choice = subset.choose(&camera, SIZE, choosing).unwrap();
        let Some(cloud) = choice.cloud.clone() else { continue };
        let spans = choice.spans.clone().expect("a streamed choice says which splats each node holds");
        let scene = scene_of(cloud.clone(), &choice, true);
        let mut fresh = PreparedScene::of(scene_of(cloud.clone(), &choice, false)).streamed();
        let expected = images(&mut fresh, &mut renderer, &camera);
        let Some((mut frames, last_spans, last_cloud)) = shown.take() else {
            let mut frames = PreparedScene::of(scene).streamed();
            images(&mut frames, &mut renderer, &camera);
            shown = Some((frames, spans, cloud));
            continue;
        };
        let full = fresh.uploaded_bytes();
        let slots_before = slots(&mut frames, &renderer);
        let written_before = frames.uploaded_bytes();
        frames.show_selection(Some(&renderer), Arc::clone(&scene), scene.flattened()).unwrap();
        let drawn = images(&mut frames, &mut renderer, &camera);
        // What the next selection and its frames wrote to the GPU.
        let written = frames.uploaded_bytes() - written_before;
        // Two copies, each written where the pan touched it, and where it grew
        // (a node that fit in no vacant run: new slots, vacant but those it took).
        let grown = slots(&mut frames, &renderer).saturating_sub(slots_before);
        let (splats, nodes) = touched((&last_spans, &last_cloud), (&spans, &cloud));
        let bound = RECORD * (2 * (splats + JOIN * nodes) + grown);
        eprintln!(
            "pan {step}: {} nodes, {splats} splats in {nodes} nodes touched, {grown} slots grown; {written} bytes written, at most {bound}; a fresh upload writes {full}",
            spans.0.len(),
        );
        assert!(written <= bound, "pan {step}: {written} bytes written, more than {bound}");
        for ((settings, got), want) in modes().iter().zip(&drawn).zip(&expected) {
            assert!(got.pixels().any(|p| p.0 != got.get_pixel(0, 0).0), "pan {step}, {}: a blank frame", settings.mode);
            // The same splats in another order: sums of weights may round apart by one step.
            let largest = largest_difference(got, want);
            assert!(largest <= 1, "pan {step}, {}: a pixel differs by {largest} from a fresh upload", settings.mode);
        }
        pans += 1;
        (bounds, fresh_uploads) = (bounds + bound, fresh_uploads + full);
        shown = Some((frames, spans, cloud));
    }
    // Were every copy written again, a pan would write what a fresh upload does: more than its bound.
    assert!(pans >= 3, "only {pans} pans drew new nodes");
    assert!(
        bounds < fresh_uploads,
        "the pans touch {bounds} bytes of the {fresh_uploads} their fresh uploads write: the path tests nothing"
    );
}

/// The splats of `after`'s nodes that must be written to show it, and how
/// many such nodes, when the pool holds for each node the records it last
/// drew: `drawn`'s for the nodes the last view drew, `earlier`'s for those
/// an earlier view drew (kept on the GPU, undrawn). Nodes dropped are not written.
fn to_write(
    drawn: (&NodeSpans, &PointCloud),
    earlier: (&NodeSpans, &PointCloud),
    after: (&NodeSpans, &PointCloud),
) -> (u64, u64) {
    // The splats a node was last drawn as, in the first view that drew it.
    let last_records = |node: u32| {
        [drawn, earlier].into_iter().find_map(|(spans, cloud)| {
            spans.0.iter().find(|(n, _)| *n == node).map(|(_, range)| (range.clone(), cloud))
        })
    };
    let (mut splats, mut nodes) = (0u64, 0u64);
    for (node, range) in &after.0.0 {
        let unchanged = last_records(*node).is_some_and(|(old, cloud)| {
            old.len() == range.len() && old.zip(range.clone()).all(|(i, j)| same_splat(cloud, i, after.1, j))
        });
        if !unchanged {
            (splats, nodes) = (splats + range.len() as u64, nodes + 1);
        }
    }
    (splats, nodes)
}

#[test]
fn a_node_dropped_stays_on_the_gpu_undrawn_and_comes_back_without_a_write() {
    let dir = tempfile::tempdir().unwrap();
    let (mut subset, far, choosing) = plane_stream(dir.path());
    let mut renderer = common::renderer();
    // Close, far, close again: the close view's finer nodes leave the far
    // one's selection (and stay resident, in its view), then come back.
    let near = Camera { distance: 20.0, ..far };
    let mut views = Vec::new();
    for camera in [near, far, near] {
        let choice = subset.choose(&camera, SIZE, choosing).unwrap();
        let cloud = choice.cloud.clone().expect("a selection");
        let spans = choice.spans.clone().expect("a streamed choice says which splats each node holds");
        views.push((camera, choice, cloud, spans));
    }
    let (_, first, ..) = &views[0];
    let mut frames = PreparedScene::of(scene_of(views[0].2.clone(), first, true)).streamed();
    images(&mut frames, &mut renderer, &near);
    for k in 1..views.len() {
        let (camera, choice, cloud, spans) = &views[k];
        let scene = scene_of(cloud.clone(), choice, true);
        let slots_before = slots(&mut frames, &renderer);
        let written_before = frames.uploaded_bytes();
        frames.show_selection(Some(&renderer), Arc::clone(&scene), scene.flattened()).unwrap();
        let drawn = images(&mut frames, &mut renderer, camera);
        let written = frames.uploaded_bytes() - written_before;
        let slots_after = slots(&mut frames, &renderer);
        let mut fresh = PreparedScene::of(scene_of(cloud.clone(), choice, false)).streamed();
        let expected = images(&mut fresh, &mut renderer, camera);
        for ((settings, got), want) in modes().iter().zip(&drawn).zip(&expected) {
            let largest = largest_difference(got, want);
            assert!(largest <= 1, "view {k}, {}: a pixel differs by {largest} from a fresh upload", settings.mode);
        }
        // What the frame reports of its pool: the nodes kept on the GPU undrawn.
        let frame = frames.render(Some(&mut renderer), camera, &modes()[0], SIZE, false).expect("render");
        let pool = frame.report.pool.expect("a streamed frame reports its node pool");
        assert_eq!(pool.drawn, spans.0.len(), "view {k}: the nodes drawn");
        let resident = pool.kept;
        let (last_camera, _, last_cloud, last_spans) = &views[k - 1];
        let dropped = last_spans.0.iter().filter(|(node, _)| !spans.0.iter().any(|(n, _)| n == node)).count();
        eprintln!(
            "view {k} ({} m away): {} nodes, {dropped} dropped, {resident} resident; {written} bytes written, a fresh upload writes {}",
            camera.distance,
            spans.0.len(),
            fresh.uploaded_bytes()
        );
        assert_ne!(last_camera.distance, camera.distance);
        if k == 1 {
            assert!(
                dropped > 0 && resident >= dropped,
                "the far view drops {dropped} nodes and keeps {resident} on the GPU"
            );
            continue;
        }
        // Back close: the nodes kept on the GPU are written only where their records changed.
        let (splats, nodes) = to_write((last_spans, last_cloud), (&views[0].3, &views[0].2), (spans, cloud));
        let grown = slots_after.saturating_sub(slots_before);
        // Two copies, each with its live mask (a bit per slot) written at most whole.
        let bound = RECORD * (2 * (splats + JOIN * nodes) + grown) + 2 * slots_after.div_ceil(8);
        eprintln!("view {k}: {splats} splats in {nodes} nodes to write; {written} bytes written, at most {bound}");
        assert!(written <= bound, "view {k}: {written} bytes written, more than {bound}");
        assert!(
            bound < fresh.uploaded_bytes() / 2,
            "the nodes that come back are {bound} bytes of a fresh upload's {}: the path tests nothing",
            fresh.uploaded_bytes()
        );
    }
}

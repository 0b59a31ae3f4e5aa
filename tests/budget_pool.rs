//! A file opened whole (the bundled lion), drawn under a point budget, keeps the nodes of its
//! multi-resolution hierarchy in a pool of GPU slots as a streamed file's
//! nodes are kept: along a path of pans, a node drawn in both views stays
//! where it is, so a pan writes only the records of the nodes it adds, and
//! the frame is the one a fresh upload of the same selection draws, in
//! two-pass and `tiled`.

mod common;

use std::collections::HashSet;
use std::sync::Arc;

use pointblend::frame::Camera;
use pointblend::frame::subset::{NodeSpans, Subset};
use pointblend::lod::Choosing;
use pointblend::lod::subset::BudgetSubset;
use pointblend::render::{GpuRenderer, PreparedScene, RenderMode, RenderSettings};
use pointblend::scene::Scene;

/// Bytes of one splat record on the GPU.
const RECORD: u64 = std::mem::size_of::<pointblend::render::gpu_data::SplatInstance>() as u64;
/// Unchanged records a rewrite may write to join two runs of changed ones.
const JOIN: u64 = pointblend::render::changed_records::REWRITE_GAP as u64;
const SIZE: (u32, u32) = (128, 128);
const BUDGET: u32 = 20_000;

/// The bundled lion (94K splats), as a file opened whole.
fn lion() -> Arc<Scene> {
    let (cloud, _) = pointblend::cloud::load(&common::bundled_model()).unwrap();
    Arc::new(Scene::from(cloud))
}

fn modes() -> [RenderSettings; 2] {
    [RenderMode::TwoPass, RenderMode::Tiled].map(|mode| RenderSettings {
        mode,
        point_budget: Some(BUDGET),
        ..Default::default()
    })
}

fn images(frames: &mut PreparedScene, renderer: &mut GpuRenderer, camera: &Camera) -> Vec<pointblend::render::Frame> {
    modes().iter().map(|s| frames.render(Some(&mut *renderer), camera, s, SIZE, false).expect("render")).collect()
}

/// The splats of the nodes of `now` that `before` did not draw, and how many such nodes.
fn added(before: &NodeSpans, now: &NodeSpans) -> (u64, u64) {
    let drawn: HashSet<u32> = before.0.iter().map(|(node, _)| *node).collect();
    let new = now.0.iter().filter(|(node, _)| !drawn.contains(node));
    new.fold((0, 0), |(splats, nodes), (_, range)| (splats + range.len() as u64, nodes + 1))
}

#[test]
fn a_pan_under_a_budget_writes_only_the_nodes_it_adds_and_draws_what_a_fresh_upload_draws() {
    let scene = lion();
    let mut renderer = common::renderer();
    let mut frames = PreparedScene::of(Arc::clone(&scene));
    // The frame's own choices, made again beside it to know which nodes each view draws.
    let mut chooser = BudgetSubset::new(frames.hierarchy(), 0);
    chooser.budget = BUDGET;
    let far = Camera::default_for(&scene.flattened(), 1.0);
    let (mut last, mut bounds, mut fresh_uploads, mut pans) = (None::<Arc<NodeSpans>>, 0u64, 0u64, 0);
    // Close up, pans of 4 % of the lion's bounding radius across it.
    let (up, _) = far.up.frame();
    let step_across = up.cross(far.direction()).normalize() * far.scene_radius * 0.04;
    for step in 0..6 {
        let target = far.target + step_across * (step as f32 - 2.5);
        let camera = Camera { target, distance: far.distance * 0.35, ..far };
        let choice = chooser.choose(&camera, SIZE, Choosing::of(&modes()[0])).unwrap();
        let spans = choice.spans.expect("each view chooses other nodes");
        let written_before = frames.uploaded_bytes();
        let drawn = images(&mut frames, &mut renderer, &camera);
        let written = frames.uploaded_bytes() - written_before;
        let mut fresh = PreparedScene::of(Arc::clone(&scene));
        let expected = images(&mut fresh, &mut renderer, &camera);
        for ((settings, got), want) in modes().iter().zip(&drawn).zip(&expected) {
            let mode = settings.mode;
            let pool = got.report.pool.expect("a frame under a budget keeps its nodes in a pool");
            assert_eq!(pool.drawn, spans.0.len(), "view {step}, {mode}: the nodes drawn");
            let (got, want) = (&got.image, &want.image);
            assert!(got.pixels().any(|p| p.0 != got.get_pixel(0, 0).0), "view {step}, {mode}: a blank frame");
            let largest = got.as_raw().iter().zip(want.as_raw()).map(|(a, b)| a.abs_diff(*b)).max().unwrap_or(0);
            assert!(largest <= 1, "view {step}, {mode}: a pixel differs by {largest} from a fresh upload");
        }
        let Some(before) = last.replace(Arc::clone(&spans)) else { continue };
        // One copy (two-pass and `tiled` share it): the nodes added, and its
        // live mask (a bit per slot) written at most whole. A pool that grows
        // writes only the nodes it places.
        let slots = drawn[0].report.pool.expect("reported above").slots as u64;
        let (splats, nodes) = added(&before, &spans);
        let bound = RECORD * (splats + JOIN * nodes) + slots.div_ceil(8);
        let full = fresh.uploaded_bytes();
        eprintln!(
            "pan {step}: {} nodes, {splats} splats in {nodes} nodes added, {slots} slots; {written} bytes written, at most {bound}; a fresh upload writes {full}",
            spans.0.len()
        );
        assert!(written <= bound, "pan {step}: {written} bytes written, more than {bound}");
        (bounds, fresh_uploads, pans) = (bounds + bound, fresh_uploads + full, pans + 1);
    }
    // Were the copy written again whole, a pan would write what a fresh upload does: more than its bound.
    assert!(pans >= 4, "only {pans} pans");
    assert!(
        bounds * 2 < fresh_uploads,
        "the pans may write {bounds} bytes of the {fresh_uploads} their fresh uploads write: the path tests nothing"
    );
}

//! The viewer opens a LAS/LAZ file with more points than its point budget
//! as a tree of nodes held in memory, drawn as a streamed COPC file is, and
//! one that the budget holds whole, as before.

mod common;

use common::viewer::{harness, options, wait_for};
use pointblend::frame::Parameter;
use pointblend::viewer::{ViewerApp, ViewerOptions};

#[test]
fn a_las_file_above_the_budget_opens_as_nodes_and_one_within_it_whole() {
    let dir = tempfile::tempdir().unwrap();
    // 2 x 400² points: a root and its children (the octree's leaves hold at most 100,000).
    let side = 400;
    let laz = common::lidar::two_planes(&dir.path().join("tile.laz"), side, 0.2, [500_000.0, 4_000_000.0, 10.0], 3.0);
    let budget = vec![(Parameter::PointBudget, "100000".to_string())];
    let held = ViewerOptions { file: Some(laz.clone()), parameters: budget, ..options(dir.path()) };
    let mut h = harness(held);
    let streamed = |app: &ViewerApp| app.is_settled() && app.model().is_some_and(|m| m.streamed.is_some());
    wait_for(&mut h, "the file's nodes", streamed);
    let drawn = h.state().shown_splats().unwrap();
    assert!(drawn > 0 && drawn <= 100_000, "{drawn} splats under a 100,000 budget");
    drop(h);
    // The default budget (1M) holds the file: loaded whole, every point drawn.
    let mut h = harness(ViewerOptions { file: Some(laz), ..options(dir.path()) });
    let whole = |app: &ViewerApp| app.is_settled() && app.model().is_some_and(|m| m.streamed.is_none());
    wait_for(&mut h, "the whole file", whole);
    assert_eq!(h.state().shown_splats().unwrap(), 2 * side * side, "every point");
}

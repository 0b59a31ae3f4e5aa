//! Streamed layers: several COPC files (or a `.vpc` of URLs) drawn node by
//! node under one `--point-budget`. Two generated tiles side by side, each
//! of several nodes: together they draw no more than the budget, and the
//! tile nearer the eye draws more of its nodes; a budget below the two roots
//! together still draws both (no file left out); `bench A B --together`
//! measures them under that budget; a `.vpc` whose files are URLs on a real
//! HTTP server draws as the local files do.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::lidar::{tilted_grid, write};
use common::nginx::Nginx;

const ORIGIN: [f64; 3] = [431_000.0, 5_012_000.0, 80.0];
/// Points per tile side: 115,600 points a tile, more than a COPC leaf holds, so each tile has a root and children.
const SIDE: usize = 340;
const SPACING: f64 = 0.3;
const BUDGET: usize = 60_000;

fn pointblend(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pointblend")).args(args).env("WGPU_BACKEND", "vulkan").output().unwrap()
}

/// Two COPC tiles side by side in x (west, east), in `dir`.
fn tiles(dir: &Path) -> [PathBuf; 2] {
    let width = SIDE as f64 * SPACING;
    ["west", "east"]
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let from = [ORIGIN[0] + k as f64 * width, ORIGIN[1], ORIGIN[2]];
            let laz = write(&dir.join(format!("{name}.laz")), &tilted_grid(SIDE, SPACING, 0.02, from), from, None);
            let copc = dir.join(format!("{name}.copc.laz"));
            let run = pointblend(&["convert", laz.to_str().unwrap(), copc.to_str().unwrap()]);
            assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
            copc
        })
        .collect::<Vec<_>>()
        .try_into()
        .unwrap()
}

/// Renders `files` from the east (the east tile nearer), under the budget; the image and the log.
fn render(files: &[&str], out: &Path) -> (image::RgbaImage, String) {
    render_under(files, out, BUDGET)
}

/// [`render`] under `budget` points.
fn render_under(files: &[&str], out: &Path, budget: usize) -> (image::RgbaImage, String) {
    let mut args: Vec<&str> = vec!["render"];
    args.extend(files);
    let budget = budget.to_string();
    let view = ["--view", "right", "--elevation", "20", "--distance", "120", "--mode", "two-pass", "--size", "128x128"];
    args.extend(view);
    args.extend(["--point-budget", &budget, "--out", out.to_str().unwrap()]);
    let run = pointblend(&args);
    let log = String::from_utf8_lossy(&run.stderr).into_owned();
    assert!(run.status.success(), "{args:?}: {log}");
    (image::open(out).unwrap().to_rgba8(), log)
}

/// The points the log says `name` drew.
fn drawn(log: &str, name: &str) -> usize {
    let line =
        log.lines().find(|l| l.contains(&format!("{name}: ")) && l.contains(" points of ")).unwrap_or_else(|| {
            panic!("no line of what {name} drew in:\n{log}");
        });
    let after = line.split(&format!("{name}: ")).nth(1).unwrap();
    after.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn streamed_layers_share_one_budget_and_the_near_tile_draws_more() {
    let dir = tempfile::tempdir().unwrap();
    let [west, east] = tiles(dir.path());
    let files = [west.to_str().unwrap(), east.to_str().unwrap()];
    let (image, log) = render(&files, &dir.path().join("two.png"));
    if let Ok(keep) = std::env::var("POINTBLEND_KEEP_IMAGES") {
        std::fs::copy(dir.path().join("two.png"), Path::new(&keep).join("streamed-layers.png")).unwrap();
        eprintln!("{log}");
    }
    let (w, e) = (drawn(&log, "west.copc.laz"), drawn(&log, "east.copc.laz"));
    assert!(w + e <= BUDGET, "{w} + {e} points drawn, over the one budget of {BUDGET}:\n{log}");
    assert!(w + e > BUDGET / 2, "{w} + {e} points drawn: the budget of {BUDGET} is not used");
    assert!(w > 0 && e > w, "the near (east) tile draws {e} points, the far (west) one {w}");
    let background = *image.get_pixel(0, 0);
    let covered = image.pixels().filter(|p| **p != background).count();
    assert!(covered * 4 > (image.width() * image.height()) as usize, "{covered} pixels drawn");

    // A budget below the two roots together still draws both roots: no file is left out.
    let (_, log) = render_under(&files, &dir.path().join("tight.png"), 20_000);
    let (w_root, e_root) = (drawn(&log, "west.copc.laz"), drawn(&log, "east.copc.laz"));
    assert!(w_root > 0 && e_root > 0 && w_root + e_root > 20_000, "roots {w_root} and {e_root} points:\n{log}");
    assert!(log.contains("over the one budget of 20000"), "{log}");

    // bench A B --together measures the two as one scene under the one budget.
    let out = dir.path().join("bench");
    // Two views that select the same nodes: the second draws them again.
    let args = ["bench", files[0], files[1], "--together", "--modes", "two-pass", "--views", "2", "--size", "128x128"];
    let budget = BUDGET.to_string();
    let more = ["--frames", "1", "--warm-up", "0", "--point-budget", &budget, "--out", out.to_str().unwrap()];
    let run = pointblend(&[&args[..], &more[..]].concat());
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let rows: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(out.join("bench.json")).unwrap()).unwrap();
    assert!(!rows.is_empty());
    // Each view says what it selected and read of the files, node by node.
    let said = String::from_utf8_lossy(&run.stdout);
    let line = said.lines().find(|l| l.starts_with("west+1.vpc front view: ")).unwrap_or_else(|| panic!("{said}"));
    let points = format!(" {} points of 2 files", rows[0]["points"]);
    assert!(line.contains(&points), "{line}");
    for row in &rows {
        let points = row["points"].as_u64().unwrap() as usize;
        assert_eq!(row["model"].as_str(), Some("west+1.vpc"), "{row}");
        // Both roots (16,384 points each: one per cell of the root's grid) at least, the budget at most.
        assert!((2 * 16_384..=BUDGET).contains(&points), "{points} points in {row}");
    }

    // The same two as URLs in a `.vpc`, from a real HTTP server: the same frame.
    let server = Nginx::serve(dir.path());
    let features: Vec<serde_json::Value> = ["west", "east"]
        .iter()
        .map(|name| {
            let href = format!("http://127.0.0.1:{}/{name}.copc.laz", server.port);
            serde_json::json!({"type": "Feature", "geometry": null, "properties": {}, "assets": {"data": {"href": href}}})
        })
        .collect();
    let vpc = dir.path().join("remote.vpc");
    let collection = serde_json::json!({"type": "FeatureCollection", "features": features});
    std::fs::write(&vpc, collection.to_string()).unwrap();
    let (remote, log) = render(&[vpc.to_str().unwrap()], &dir.path().join("remote.png"));
    assert_eq!((drawn(&log, "west.copc.laz"), drawn(&log, "east.copc.laz")), (w, e), "{log}");
    let error = pointblend::reference::compare(&remote, &image).unwrap();
    assert!(error.eps <= 0.01, "ε {} between the URLs and the local files", error.eps);
}

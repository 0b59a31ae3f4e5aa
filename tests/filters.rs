//! Attribute filters (crates/core/src/style/filter.rs): a generated
//! two-return tile, a canopy of first returns over ground of second ones,
//! rendered with `--returns first` (and the same filter as `--filter` and in
//! a scene file) equals the file reduced to its first returns, framed alike;
//! `--filter` on intensity keeps what the range holds.

mod common;

use common::lidar::{LidarPoint, tilted_grid, write};
use pointblend::reference;

/// Ground (second of two returns) and a canopy 10 m above it (first of two), each 30 x 30, 1 m apart.
fn tile() -> (Vec<LidarPoint>, Vec<LidarPoint>) {
    let origin = [600_000.0, 5_000_000.0, 100.0];
    let colour = |mut p: LidarPoint, rgb: [u16; 3], (r, n): (u8, u8)| {
        (p.rgb, p.return_number, p.returns) = (rgb, r, n);
        p
    };
    let ground: Vec<LidarPoint> =
        tilted_grid(30, 1.0, 0.0, origin).into_iter().map(|p| colour(p, [30000, 20000, 10000], (2, 2))).collect();
    let canopy: Vec<LidarPoint> = tilted_grid(30, 1.0, 0.0, [origin[0], origin[1], origin[2] + 10.0])
        .into_iter()
        .map(|p| colour(p, [10000, 50000, 10000], (1, 2)))
        .collect();
    (ground, canopy)
}

fn render(args: &[&str], out: &std::path::Path) -> image::RgbaImage {
    let (ok, stderr) = common::render_cli(args, out);
    assert!(ok, "{args:?}: {stderr}");
    image::open(out).unwrap().to_rgba8()
}

#[test]
fn first_returns_by_flag_filter_and_scene_file_equal_the_file_of_first_returns() {
    let dir = tempfile::tempdir().unwrap();
    let (ground, canopy) = tile();
    let offset = [600_000.0, 5_000_000.0, 0.0];
    let both = write(&dir.path().join("both.las"), &[ground.clone(), canopy.clone()].concat(), offset, None);
    let first = write(&dir.path().join("first.las"), &canopy, offset, None);
    let scene = dir.path().join("first.toml");
    std::fs::write(&scene, "[[object]]\ncloud = \"both.las\"\nreturns = \"first\"\n").unwrap();
    let common_args = ["--mode", "two-pass", "--size", "128x128", "--view", "iso"];
    let run = |file: &std::path::Path, extra: &[&str], name: &str| {
        let mut args = vec![file.to_str().unwrap()];
        args.extend(common_args);
        args.extend(extra);
        render(&args, &dir.path().join(name))
    };
    let want = run(&first, &[], "want.png");
    let all = run(&both, &[], "all.png");
    for (name, got) in [
        ("--returns first", run(&both, &["--returns", "first"], "returns.png")),
        ("--filter return_number=1", run(&both, &["--filter", "return_number=1"], "filter.png")),
        ("--filter return_number=1..1", run(&both, &["--filter", "return_number=1..1"], "range.png")),
        ("a scene file's returns", run(&scene, &[], "scene.png")),
    ] {
        let error = reference::compare(&got, &want).unwrap();
        assert!(error.eps <= 0.01, "{name}: ε {} against the file of first returns", error.eps);
    }
    // The filter changes what is drawn: the whole file frames and shows the ground too.
    assert!(reference::compare(&all, &want).unwrap().eps > 1.0, "the unfiltered file differs");
}

#[test]
fn a_filter_on_an_attribute_the_file_lacks_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let (ground, _) = tile();
    let file = write(&dir.path().join("g.las"), &ground, [600_000.0, 5_000_000.0, 0.0], None);
    let line = common::refused_in_one_line(
        &[file.to_str().unwrap(), "--filter", "reflectance=0..1", "--size", "64x64"],
        &dir.path().join("o.png"),
        "reflectance",
    );
    assert!(line.contains("intensity"), "it lists the attributes the file has: {line}");
}

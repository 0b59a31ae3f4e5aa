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

/// The columns an image draws in (not its corner's background colour): (first, last).
fn drawn_columns(image: &image::RgbaImage) -> (u32, u32) {
    let background = *image.get_pixel(0, 0);
    let drawn: Vec<u32> =
        (0..image.width()).filter(|&x| (0..image.height()).any(|y| *image.get_pixel(x, y) != background)).collect();
    (*drawn.first().expect("nothing drawn"), *drawn.last().unwrap())
}

#[test]
fn a_streamed_files_default_view_frames_the_points_its_filters_keep() {
    // Ground of class 2 in one corner, 8 x 8 of a 40 x 40 tile of class 5.
    let dir = tempfile::tempdir().unwrap();
    let origin = [600_000.0, 5_000_000.0, 100.0];
    let points: Vec<LidarPoint> = tilted_grid(80, 0.5, 0.0, origin)
        .into_iter()
        .map(|mut p| {
            let corner = p.xyz[0] - origin[0] < 8.0 && p.xyz[1] - origin[1] < 8.0;
            p.class = if corner { 2 } else { 5 };
            p
        })
        .collect();
    let laz = write(&dir.path().join("tile.laz"), &points, [origin[0], origin[1], 0.0], None);
    let copc = dir.path().join("tile.copc.laz");
    let converted = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("convert")
        .arg(&laz)
        .arg(&copc)
        .output()
        .unwrap();
    assert!(converted.status.success(), "{}", String::from_utf8_lossy(&converted.stderr));
    for file in [&laz, &copc] {
        let out = dir.path().join(format!("{}.png", file.file_name().unwrap().to_string_lossy()));
        let image = render(&[file.to_str().unwrap(), "--filter", "classification=2", "--size", "128x128"], &out);
        let (first, last) = drawn_columns(&image);
        assert!(last - first > 64, "{}: the kept corner spans columns {first}..{last} of 128", file.display());
    }
}

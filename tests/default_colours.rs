//! Survey files without colours open as QGIS opens them: by class when the
//! file holds more than one, else by elevation; a file with colours keeps
//! them, and `--color-by rgb` asks for the file's own (the default colour).
//! Through `render` (unlit, seen from above, so each pixel shows its
//! splat's colour) and in the viewer, whose model carries the style (what
//! its colour panel shows) and whose legend says what the colours show.

mod common;

use std::path::{Path, PathBuf};

use common::lidar::{LidarPoint, tilted_grid, write, write_colourless};
use pointblend::cloud::load::DEFAULT_COLOR;
use pointblend::style::{ColorBy, classes};

const CORNER: [f64; 3] = [500_000.0, 4_000_000.0, 50.0];

/// A flat 100 x 100 grid in three bands of classes 2, 5 and 6 along x.
fn banded(classes: [u8; 3]) -> Vec<LidarPoint> {
    let mut points = tilted_grid(100, 0.5, 0.0, CORNER);
    for (k, p) in points.iter_mut().enumerate() {
        p.class = classes[(k / 100) * 3 / 100];
    }
    points
}

/// `render FILE --unlit` from straight above: the image.
fn render_top(file: &Path, extra: &[&str]) -> image::RgbaImage {
    let out = file.with_extension("png");
    let mut args: Vec<String> = [file.to_str().unwrap(), "--unlit", "--elevation", "90", "--size", "96x96"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    args.extend(extra.iter().map(|s| s.to_string()));
    let (ok, stderr) = common::render_cli(&args, &out);
    assert!(ok, "{stderr}");
    image::open(&out).unwrap().to_rgba8()
}

/// How many pixels are within 2/255 of `colour`.
fn pixels_of(image: &image::RgbaImage, colour: [u8; 3]) -> usize {
    image.pixels().filter(|p| (0..3).all(|c| p.0[c].abs_diff(colour[c]) <= 2)).count()
}

fn file(dir: &Path, name: &str, points: &[LidarPoint], colours: bool) -> PathBuf {
    let path = dir.join(name);
    if colours { write(&path, points, CORNER, None) } else { write_colourless(&path, points, CORNER) }
}

#[test]
fn a_file_without_colours_opens_by_class_else_by_elevation_and_rgb_asks_for_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let three = file(dir.path(), "classes.las", &banded([2, 5, 6]), false);
    let image = render_top(&three, &[]);
    let area = (image.width() * image.height()) as usize;
    for class in [2, 5, 6] {
        let share = pixels_of(&image, classes::colour(class)) as f64 / area as f64;
        println!("class {class}: {:.1}% of the pixels", 100.0 * share);
        assert!(share > 0.1, "class {class}'s colour covers its band: {share}");
    }
    assert_eq!(pixels_of(&image, DEFAULT_COLOR), 0, "nothing in the default colour");
    let own = render_top(&three, &["--color-by", "rgb"]);
    assert!(pixels_of(&own, DEFAULT_COLOR) as f64 > 0.3 * area as f64, "--color-by rgb: the file's own (none)");

    // One class: by elevation, through the colormap (a slope, so several colours).
    let mut sloped = tilted_grid(100, 0.5, 0.5, CORNER);
    sloped.iter_mut().for_each(|p| p.class = 2);
    let one = file(dir.path(), "one-class.las", &sloped, false);
    let image = render_top(&one, &[]);
    let distinct: std::collections::HashSet<[u8; 3]> = image.pixels().map(|p| [p.0[0], p.0[1], p.0[2]]).collect();
    assert!(distinct.len() > 20, "elevation through the colormap: {} colours", distinct.len());
    assert_eq!(pixels_of(&image, classes::colour(2)), 0, "not by class");

    // A file with colours keeps them.
    let coloured = file(dir.path(), "rgb.las", &banded([2, 5, 6]), true);
    let image = render_top(&coloured, &[]);
    for class in [2, 5, 6] {
        assert!(pixels_of(&image, classes::colour(class)) < area / 20, "the file's colours, not class {class}'s");
    }
}

#[test]
fn the_viewer_opens_a_file_without_colours_by_class_and_its_legend_says_so() {
    use common::viewer::{harness, options, wait_for};
    let dir = tempfile::tempdir().unwrap();
    let three = file(dir.path(), "classes.las", &banded([2, 5, 6]), false);
    let mut h = harness(pointblend::viewer::ViewerOptions { file: Some(three), ..options(dir.path()) });
    wait_for(&mut h, "the file", |app| app.is_settled() && app.model().is_some());
    let style = h.state().model().and_then(|m| m.style.clone()).expect("a style");
    assert_eq!(style.color_by, Some(ColorBy::Classification));
    let legend = h.state().legend_shown().expect("a legend");
    assert!(format!("{legend:?}").contains("classification"), "{legend:?}");
}

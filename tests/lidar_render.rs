//! Lidar tiles on screen: far from the origin they render as at the origin,
//! and colour and opacity by class reach every renderer as the reference
//! sees them.

mod common;

use std::path::{Path, PathBuf};

use common::lidar::{self, tilted_grid};
use pointblend::reference::metrics;

/// Renders `file` with `args` at 128² through the CLI.
fn render(file: &Path, args: &[&str], out: PathBuf) -> image::RgbaImage {
    let mut all: Vec<String> = vec![file.display().to_string(), "--size".into(), "128x128".into()];
    all.extend(args.iter().map(|a| a.to_string()));
    let (ok, stderr) = common::render_cli(&all, &out);
    assert!(ok, "render {args:?}: {stderr}");
    image::open(&out).unwrap().to_rgba8()
}

/// A LAZ of `side`² ground points (class 2) at z = 0 and as many canopy
/// points (class 5) 3 m above them; its path and its point count.
fn ground_and_canopy(dir: &Path, side: usize) -> (PathBuf, usize) {
    let mut points = tilted_grid(side, 0.4, 0.0, [1000.0, 2000.0, 0.0]);
    points.iter_mut().for_each(|p| p.class = 2);
    let mut canopy = tilted_grid(side, 0.4, 0.0, [1000.0, 2000.0, 3.0]);
    canopy.iter_mut().for_each(|p| p.class = 5);
    points.extend(canopy);
    (lidar::write(&dir.join("two-layers.laz"), &points, [1000.0, 2000.0, 0.0], None), points.len())
}

#[test]
fn a_tile_far_from_the_origin_renders_as_the_same_tile_at_the_origin() {
    let dir = tempfile::tempdir().unwrap();
    // Spacing that f32 cannot hold at y ≈ 4.9e6 (its step there is 0.5 m).
    let far = [515_000.0, 4_900_000.0, 250.0];
    let near = [0.0, 0.0, 250.0];
    let far_file = lidar::write(&dir.path().join("far.laz"), &tilted_grid(70, 0.37, 0.25, far), far, None);
    let near_file = lidar::write(&dir.path().join("near.laz"), &tilted_grid(70, 0.37, 0.25, near), near, None);
    for mode in ["two-pass", "tiled"] {
        let args = ["--mode", mode, "--opacity", "0.6"];
        let a = render(&far_file, &args, dir.path().join(format!("far-{mode}.png")));
        let b = render(&near_file, &args, dir.path().join(format!("near-{mode}.png")));
        let covered = common::foreground(&b, common::background_rgb()).iter().filter(|&&f| f).count();
        assert!(covered > 128 * 128 / 5, "{mode}: the tile covers only {covered} pixels");
        let error = metrics::compare(&a, &b).unwrap();
        assert!(error.eps <= 0.05, "{mode}: ε {} between the far tile and the tile at the origin", error.eps);
    }
}

#[test]
fn class_colours_and_class_opacity_blend_each_surface_once_as_the_reference_does() {
    let dir = tempfile::tempdir().unwrap();
    let (file, _) = ground_and_canopy(dir.path(), 50);
    let style = ["--color-by", "classification", "--class-opacity", "5:0.3", "--unlit", "--elevation", "90"];
    let ground = pointblend::style::classes::colour(2);
    let canopy_colour = pointblend::style::classes::colour(5);
    let expected: Vec<f64> = (0..3).map(|c| 0.3 * canopy_colour[c] as f64 + 0.7 * ground[c] as f64).collect();
    let mut reference = None;
    for mode in ["reference", "tiled", "alg2", "depth-peel"] {
        let args: Vec<&str> = ["--mode", mode].into_iter().chain(style).collect();
        let image = render(&file, &args, dir.path().join(format!("{mode}.png")));
        let centre = image.get_pixel(64, 64).0;
        for c in 0..3 {
            assert!(
                (centre[c] as f64 - expected[c]).abs() <= 3.0,
                "{mode}: the centre is {centre:?}, not 0.3 canopy over the ground {expected:?}"
            );
        }
        match &reference {
            None => reference = Some(image),
            Some(r) => {
                let eps = metrics::compare(&image, r).unwrap().eps;
                assert!(eps < 1.0, "{mode}: ε {eps} against the reference");
            }
        }
    }
    // Showing only the ground leaves its own colour.
    let args = ["--color-by", "classification", "--classes", "2", "--unlit", "--elevation", "90"];
    let only_ground = render(&file, &args, dir.path().join("ground.png"));
    assert_eq!(&only_ground.get_pixel(64, 64).0[..3], &ground[..]);
}

#[test]
fn colour_by_an_attribute_the_file_lacks_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let file = lidar::write(&dir.path().join("t.laz"), &tilted_grid(20, 0.5, 0.0, [0.0; 3]), [0.0; 3], None);
    let line = common::refused_in_one_line(
        &[file.display().to_string(), "--color-by".into(), "Reflectance".into()],
        &dir.path().join("out.png"),
        "an attribute the file lacks",
    );
    assert!(line.contains("Reflectance") && line.contains("intensity"), "{line}");
}

#[test]
fn intensity_through_a_colormap_spans_the_percentile_range() {
    let dir = tempfile::tempdir().unwrap();
    let file = lidar::write(&dir.path().join("t.laz"), &tilted_grid(60, 0.5, 0.0, [0.0; 3]), [0.0; 3], None);
    let (cloud, _) = pointblend::cloud::load(&file).unwrap();
    let style = pointblend::style::Style {
        color_by: Some("intensity".parse().unwrap()),
        colormap: "viridis".parse().unwrap(),
        ..Default::default()
    };
    let (styled, applied) = style.apply(&cloud).unwrap();
    let values = cloud.attributes.get("intensity").unwrap();
    let (lo, hi) = applied.range.unwrap();
    let mut sorted: Vec<f64> = (0..values.len()).map(|i| values.get(i)).collect();
    sorted.sort_by(f64::total_cmp);
    let share_below = sorted.iter().filter(|&&v| v < lo).count() as f64 / sorted.len() as f64;
    let share_above = sorted.iter().filter(|&&v| v > hi).count() as f64 / sorted.len() as f64;
    assert!((0.01..=0.03).contains(&share_below) && (0.01..=0.03).contains(&share_above), "{lo}..{hi}");
    let lowest = (0..values.len()).min_by(|&a, &b| values.get(a).total_cmp(&values.get(b))).unwrap();
    let highest = (0..values.len()).max_by(|&a, &b| values.get(a).total_cmp(&values.get(b))).unwrap();
    assert_eq!(styled.colours[lowest], pointblend::style::Colormap::Viridis.colour(0.0));
    assert_eq!(styled.colours[highest], pointblend::style::Colormap::Viridis.colour(1.0));
}

#[test]
fn a_screenshots_sidecar_brings_its_colours_by_attribute_back() {
    use pointblend::frame::sidecar::SidecarModel;
    use pointblend::frame::{Camera, RenderMode, RenderSettings, Sidecar};
    let dir = tempfile::tempdir().unwrap();
    let (file, count) = ground_and_canopy(dir.path(), 40);
    let styled = ["--mode", "tiled", "--color-by", "classification", "--class-opacity", "5:0.3"];
    let wanted = render(&file, &styled, dir.path().join("wanted.png"));
    // The sidecar the viewer would write for that view.
    let (scene, _) = pointblend::scene::open(&file, &Default::default()).unwrap();
    let camera = Camera::default_for(&scene.flatten().cloud, 1.0);
    let settings = RenderSettings { mode: "tiled".parse::<RenderMode>().unwrap(), ..Default::default() };
    let model = SidecarModel {
        name: "layers.laz".into(),
        path: String::new(),
        hash: String::new(),
        splats: count,
        nodes: false,
        layers: Vec::new(),
    };
    let style = pointblend::style::Style {
        color_by: Some(pointblend::style::ColorBy::Classification),
        class_opacity: vec![(5, 0.3)],
        ..Default::default()
    };
    let plain = Sidecar::new(model, &camera, &settings, (128, 128));
    let with_style = Sidecar { style: Some((&style).into()), ..plain.clone() };
    let (plain_json, styled_json) = (dir.path().join("plain.json"), dir.path().join("styled.json"));
    plain.write(&plain_json).unwrap();
    with_style.write(&styled_json).unwrap();
    let again = render(&file, &["--camera", styled_json.to_str().unwrap()], dir.path().join("again.png"));
    let eps = metrics::compare(&again, &wanted).unwrap().eps;
    assert!(eps <= 0.05, "ε {eps} between the sidecar's render and the styled render");
    let unstyled = render(&file, &["--camera", plain_json.to_str().unwrap()], dir.path().join("unstyled.png"));
    let eps = metrics::compare(&unstyled, &wanted).unwrap().eps;
    assert!(eps > 5.0, "without the style the colours differ (ε {eps})");
}

/// One check of each style value, whatever its source: a bad range, class
/// opacity and colormap are refused by the flags, a scene file and a
/// screenshot's sidecar alike, each with the shared parser's own words.
#[test]
fn a_bad_style_value_is_refused_in_the_parsers_words_from_flags_scene_files_and_sidecars() {
    use pointblend::frame::sidecar::SidecarModel;
    use pointblend::frame::{Camera, RenderSettings, Sidecar};
    use pointblend::style::{Colormap, parse, record::StyleRecord};
    let dir = tempfile::tempdir().unwrap();
    let file = lidar::write(&dir.path().join("t.laz"), &tilted_grid(20, 0.5, 0.0, [0.0; 3]), [0.0; 3], None);
    let (scene, _) = pointblend::scene::open(&file, &Default::default()).unwrap();
    let camera = Camera::default_for(&scene.flatten().cloud, 1.0);
    let model = SidecarModel {
        name: "t.laz".into(),
        path: String::new(),
        hash: String::new(),
        splats: 400,
        nodes: false,
        layers: Vec::new(),
    };
    let sidecar = Sidecar::new(model, &camera, &RenderSettings::default(), (128, 128));
    let cases = [
        (
            "range",
            ["--range", "5,1"],
            "range = [5.0, 1.0]",
            StyleRecord { range: Some([5.0, 1.0]), colormap: "viridis".into(), ..Default::default() },
            parse::range("5,1").unwrap_err(),
        ),
        (
            "class opacity",
            ["--class-opacity", "5:1.5"],
            "class_opacity = { 5 = 1.5 }",
            StyleRecord { class_opacity: vec![(5, 1.5)], colormap: "viridis".into(), ..Default::default() },
            parse::class_opacity("5:1.5").unwrap_err(),
        ),
        (
            "colormap",
            ["--colormap", "rainbow"],
            "colormap = \"rainbow\"",
            StyleRecord { colormap: "rainbow".into(), ..Default::default() },
            "rainbow".parse::<Colormap>().unwrap_err(),
        ),
    ];
    for (what, flags, key, record, words) in cases {
        let out = dir.path().join("out.png");
        let mut args = vec![file.display().to_string()];
        args.extend(flags.iter().map(|f| f.to_string()));
        let from_flags = common::refused_in_one_line(&args, &out, &format!("a bad {what} flag"));
        let scene_file = dir.path().join("scene.toml");
        std::fs::write(&scene_file, format!("[[object]]\ncloud = \"t.laz\"\ncolor_by = \"intensity\"\n{key}\n"))
            .unwrap();
        let from_scene = common::refused_in_one_line(&[&scene_file], &out, &format!("a bad {what} key"));
        let json = dir.path().join("view.json");
        Sidecar { style: Some(StyleRecord { color_by: Some("intensity".into()), ..record }), ..sidecar.clone() }
            .write(&json)
            .unwrap();
        let args = [file.display().to_string(), "--camera".into(), json.display().to_string()];
        let from_sidecar = common::refused_in_one_line(&args, &out, &format!("a bad {what} in a sidecar"));
        for line in [from_flags, from_scene, from_sidecar] {
            assert!(line.contains(&words), "{what}: '{line}' lacks the parser's words '{words}'");
        }
    }
}

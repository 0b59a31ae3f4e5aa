//! Layers: several files drawn as one scene, each with its own f64 origin,
//! on generated tiles far from the origin (UTM). Two halves of a tile drawn
//! as two layers equal the whole (ε ≤ 0.05) and meet with no gap, held
//! whole and streamed (COPC); `view A B` runs its main job on the two as
//! one scene; a `.vpc`
//! of three local COPC files draws as the three do as layers, opens only
//! the files a narrow view reaches, and two CRSs are refused in one line
//! naming both files.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::lidar::{CrsRecord, LidarPoint, tilted_grid, write, write_with_crs};

const ORIGIN: [f64; 3] = [431_000.0, 5_012_000.0, 80.0];

fn pointblend(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pointblend")).args(args).env("WGPU_BACKEND", "vulkan").output().unwrap()
}

fn render(files: &[&Path], out: &Path, extra: &[&str]) -> (image::RgbaImage, String) {
    let mut args: Vec<&str> = vec!["render"];
    args.extend(files.iter().map(|f| f.to_str().unwrap()));
    args.extend(["--out", out.to_str().unwrap(), "--size", "160x160"]);
    args.extend(extra);
    let run = pointblend(&args);
    assert!(run.status.success(), "{args:?}: {}", String::from_utf8_lossy(&run.stderr));
    (image::open(out).unwrap().to_rgba8(), String::from_utf8_lossy(&run.stderr).into_owned())
}

/// A 40 × 40 tile of points 0.5 apart, sloping, far from the origin.
fn tile() -> Vec<LidarPoint> {
    tilted_grid(80, 0.5, 0.1, ORIGIN)
}

/// The tile's points with x (from its west edge) in `from..to`, written to `name`.
fn part(dir: &Path, name: &str, from: f64, to: f64) -> PathBuf {
    let points: Vec<LidarPoint> = tile().into_iter().filter(|p| (from..to).contains(&(p.xyz[0] - ORIGIN[0]))).collect();
    write(&dir.join(name), &points, [ORIGIN[0], ORIGIN[1], 0.0], None)
}

#[test]
fn two_halves_as_layers_equal_the_whole_and_meet_with_no_gap() {
    let dir = tempfile::tempdir().unwrap();
    let whole = part(dir.path(), "whole.laz", -1.0, 100.0);
    let (west, east) = (part(dir.path(), "west.laz", -1.0, 19.9), part(dir.path(), "east.las", 19.9, 100.0));
    let (one, _) = render(&[&whole], &dir.path().join("whole.png"), &[]);
    let (two, _) = render(&[&west, &east], &dir.path().join("halves.png"), &[]);
    if let Ok(keep) = std::env::var("POINTBLEND_KEEP_IMAGES") {
        for name in ["whole.png", "halves.png"] {
            std::fs::copy(dir.path().join(name), Path::new(&keep).join(format!("layers-{name}"))).unwrap();
        }
    }
    let error = pointblend::reference::compare(&two, &one).unwrap();
    assert!(error.eps <= 0.05, "ε {} between the halves and the whole", error.eps);
    // No gap: wherever the whole draws the tile, the halves draw it too.
    let background = *one.get_pixel(0, 0);
    let drawn = one.pixels().filter(|p| **p != background).count();
    let holes = one.pixels().zip(two.pixels()).filter(|(a, b)| **a != background && **b == background).count();
    assert!(drawn > 5000, "{drawn} pixels drawn");
    assert!(holes * 1000 <= drawn, "{holes} pixels of the {drawn} the whole draws are empty in the halves");

    // Streamed (COPC): the halves drawn node by node meet as the whole does, their seam mended too.
    let copc = |file: &Path| {
        let out = file.with_extension("copc.laz");
        let run = pointblend(&["convert", file.to_str().unwrap(), out.to_str().unwrap()]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        out
    };
    let (whole_copc, west_copc, east_copc) = (copc(&whole), copc(&west), copc(&east));
    let (one, _) = render(&[&whole_copc], &dir.path().join("whole-copc.png"), &[]);
    let (two, log) = render(&[&west_copc, &east_copc], &dir.path().join("halves-copc.png"), &[]);
    assert!(log.contains("points where the streamed layers meet estimated again"), "{log}");
    let error = pointblend::reference::compare(&two, &one).unwrap();
    assert!(error.eps <= 0.05, "ε {} between the streamed halves and the whole", error.eps);

    // bench --together draws the two as layers (without it, each apart).
    let out = dir.path().join("bench");
    let args = ["bench", west.to_str().unwrap(), east.to_str().unwrap(), "--together", "--modes", "two-pass"];
    let more = ["--size", "64x64", "--views", "1", "--frames", "1", "--warm-up", "0", "--out", out.to_str().unwrap()];
    let run = pointblend(&[&args[..], &more[..]].concat());
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let table = std::fs::read_to_string(out.join("bench.md")).unwrap();
    let splats = format!("| {} |", tile().len());
    let rows: Vec<&str> = table.lines().filter(|l| l.contains("| two-pass |")).collect();
    assert!(!rows.is_empty() && rows.iter().all(|l| l.contains("west+1.vpc") && l.contains(&splats)), "{table}");

    // view A B with no display: the main job on the two as one scene, every mode.
    let run = Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["view", west.to_str().unwrap(), east.to_str().unwrap(), "--size", "48x48"])
        .env("WGPU_BACKEND", "vulkan")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let rows: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/bench.json")).unwrap()).unwrap();
    let modes: std::collections::BTreeSet<&str> = rows.iter().filter_map(|r| r["mode"].as_str()).collect();
    assert!(modes.len() == pointblend::render::RenderMode::ALL.len(), "{modes:?}");
    for row in &rows {
        assert_eq!(row["model"].as_str(), Some("west+1.vpc"), "{row}");
        assert_eq!(row["points"].as_u64(), Some(tile().len() as u64), "{row}");
    }
}

/// The `las` crate's count of a file's points.
fn points_of(path: &Path) -> u64 {
    las::Reader::from_path(path).unwrap().header().number_of_points()
}

/// The `las` crate's bounds of a file, as a 3D box.
fn bounds_of(path: &Path) -> [f64; 6] {
    let b = las::Reader::from_path(path).unwrap().header().bounds();
    [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z]
}

#[test]
fn a_vpc_draws_as_its_files_do_as_layers_and_opens_only_those_the_view_reaches() {
    let dir = tempfile::tempdir().unwrap();
    let mut copcs = Vec::new();
    for (k, (from, to)) in [(-1.0, 13.2), (13.2, 26.7), (26.7, 100.0)].into_iter().enumerate() {
        let laz = part(dir.path(), &format!("t{k}.laz"), from, to);
        let copc = dir.path().join("tiles").join(format!("t{k}.copc.laz"));
        std::fs::create_dir_all(copc.parent().unwrap()).unwrap();
        let run = pointblend(&["convert", laz.to_str().unwrap(), copc.to_str().unwrap()]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        copcs.push(copc);
    }
    // `bbox` in degrees, as PDAL writes it; `proj:bbox` in the files' own coordinates.
    let features: Vec<serde_json::Value> = copcs
        .iter()
        .enumerate()
        .map(|(k, copc)| {
            serde_json::json!({
                "type": "Feature", "stac_version": "1.0.0", "id": format!("t{k}"), "geometry": null,
                "bbox": [-123.0, 45.2, 0.0, -122.9, 45.3, 90.0],
                "properties": {"proj:bbox": bounds_of(copc), "pc:count": points_of(copc), "proj:epsg": 32610},
                "assets": {"data": {"href": format!("./tiles/t{k}.copc.laz"), "roles": ["data"]}},
            })
        })
        .collect();
    let vpc = dir.path().join("city.vpc");
    let collection = serde_json::json!({"type": "FeatureCollection", "features": features});
    std::fs::write(&vpc, serde_json::to_string_pretty(&collection).unwrap()).unwrap();

    let layers: Vec<&Path> = copcs.iter().map(PathBuf::as_path).collect();
    let (as_layers, _) = render(&layers, &dir.path().join("layers.png"), &[]);
    let (from_vpc, log) = render(&[&vpc], &dir.path().join("vpc.png"), &[]);
    assert!(log.contains("opening 3 of the layers' 3 files"), "{log}");
    let error = pointblend::reference::compare(&from_vpc, &as_layers).unwrap();
    assert!(error.eps <= 0.01, "ε {} between the .vpc and its files as layers", error.eps);

    // info says what the .vpc states of its files, and names a file that is not there.
    let run = pointblend(&["info", vpc.to_str().unwrap()]);
    let said = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let total = tile().len();
    assert!(said.contains(&format!("points:      {total}\n")) && said.contains(", 3 files"), "{said}");
    assert!(said.contains("crs:         EPSG:32610") && said.contains("units:       horizontal metre"), "{said}");
    assert_eq!(said.lines().filter(|l| l.starts_with("layer:")).count(), 3, "{said}");
    let mut broken = collection.clone();
    broken["features"][1]["assets"]["data"]["href"] = "./tiles/gone.copc.laz".into();
    let gone = dir.path().join("gone.vpc");
    std::fs::write(&gone, broken.to_string()).unwrap();
    let run = pointblend(&["info", gone.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success() && stderr.contains("gone.vpc: 1 of its 3 files are not there"), "{stderr}");
    let said = String::from_utf8_lossy(&run.stdout);
    let line = said.lines().find(|l| l.contains("gone.copc.laz: ")).unwrap_or_else(|| panic!("{said}"));
    assert!(line.contains(&format!(": {} points", points_of(&copcs[1]))) && line.ends_with("MISSING"), "{line}");

    // bench (and the viewer) open a .vpc as every one of its files.
    let out = dir.path().join("bench");
    let args = ["bench", vpc.to_str().unwrap(), "--modes", "two-pass", "--size", "64x64", "--views", "1"];
    let run = pointblend(&[&args[..], &["--frames", "1", "--warm-up", "0", "--out", out.to_str().unwrap()]].concat());
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let table = std::fs::read_to_string(out.join("bench.md")).unwrap();
    let splats = tile().len().to_string();
    assert!(table.lines().any(|l| l.contains("city.vpc") && l.contains(&format!("| {splats} |"))), "{table}");

    // A plan of the middle of the tile, 6 wide: only the middle file is opened.
    let narrow = ["--projection", "ortho", "--view", "top", "--distance", "10"];
    let (middle, log) = render(&[&vpc], &dir.path().join("middle.png"), &narrow);
    assert!(log.contains("opening 1 of the layers' 3 files"), "{log}");
    let background = *middle.get_pixel(0, 0);
    let drawn = middle.pixels().filter(|p| **p != background).count();
    assert!(drawn * 2 > (middle.width() * middle.height()) as usize, "{drawn} pixels drawn in the narrow view");
}

#[test]
fn layers_in_two_crss_are_refused_in_one_line_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let offset = [ORIGIN[0], ORIGIN[1], 0.0];
    let utm = write_with_crs(
        &dir.path().join("utm.las"),
        &tile(),
        offset,
        CrsRecord::GeoTiffKeys(&[(1024, 1), (3072, 32610)]),
    );
    let other = write_with_crs(
        &dir.path().join("other.las"),
        &tile(),
        offset,
        CrsRecord::GeoTiffKeys(&[(1024, 1), (3072, 32611)]),
    );
    let run = pointblend(&[
        "render",
        utm.to_str().unwrap(),
        other.to_str().unwrap(),
        "--out",
        dir.path().join("x.png").to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(errors[0].contains("utm.las") && errors[0].contains("other.las"), "{}", errors[0]);
    assert!(errors[0].contains("32610") && errors[0].contains("32611"), "{}", errors[0]);
    assert!(!dir.path().join("x.png").exists());
}

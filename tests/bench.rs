//! `pointblend bench`: its files, its JSON fields, and the reference cache.

mod common;

use common::tolerances::{BENCH_UNFILTERED_EPS, MAX_BENCH_TWO_PASS_EPS};

use std::process::Command;

#[test]
fn bench_writes_json_markdown_plot_and_images_and_reuses_the_reference_cache() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = || {
        Command::new(env!("CARGO_BIN_EXE_pointblend"))
            .arg("bench")
            .arg(common::bundled_model())
            .args(["--modes", "two-pass,reference", "--size", "128x128", "--frames", "2", "--warm-up", "1"])
            .args(["--views", "2", "--loads", "1", "--out"])
            .arg(&out)
            .output()
            .unwrap()
    };
    let first = run();
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    for file in
        ["bench.json", "bench.md", "error_vs_time.png", "lion-front-two-pass.png", "lion-side-two-pass-diff.png"]
    {
        assert!(out.join(file).exists(), "{file} is missing");
    }
    let rows: Vec<serde_json::Value> = serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    // 2 views x (reference + two-pass filtered + two-pass unfiltered).
    assert_eq!(rows.len(), 6);
    let fields = ["mode", "view", "frame_ms", "frame_ms_min", "frame_ms_max", "eps", "psnr", "bad_pixel_share"];
    let more = ["geometry_passes", "points", "width", "height"];
    for row in &rows {
        for field in fields.iter().chain(&more) {
            assert!(row.get(field).is_some(), "{field} missing in {row}");
        }
        let variant = row["variant"].as_str().unwrap();
        let eps = row["eps"].as_f64().unwrap();
        let view = row["view"].as_str().unwrap();
        println!("{variant} {view}: ε {eps}");
        assert_eq!(row["ruler"].as_bool(), Some(variant == "reference"), "{variant}: the reference rows are the ruler");
        let image = row["image"].as_str().unwrap();
        assert!(image.contains(view) && out.join(image).is_file(), "{variant} {view}: its image {image} is not there");
        match variant {
            "reference" => assert_eq!(eps, 0.0, "the ruler measured against itself"),
            "two-pass" => assert!(eps <= MAX_BENCH_TWO_PASS_EPS, "{variant} {view}: ε {eps}"),
            "two-pass:quality=unfiltered" => {
                assert!(BENCH_UNFILTERED_EPS.contains(&eps), "{variant} {view}: ε {eps}")
            }
            other => panic!("a row for {other}, which was not asked for"),
        }
        if variant != "reference" {
            assert!(row["frame_ms_min"].as_f64() <= row["frame_ms"].as_f64());
            assert!(row["frame_ms"].as_f64() <= row["frame_ms_max"].as_f64());
            // ε split by the reference's layer count per pixel adds up to ε,
            // over every pixel, and the background (no layer) is one of them.
            let split = row["eps_by_layers"].as_array().expect("eps_by_layers");
            let sum = |key: &str| split.iter().map(|b| b[key].as_f64().unwrap()).sum::<f64>();
            assert!((sum("eps") - eps).abs() < 1e-9, "{variant} {view}: {} against ε {eps}", sum("eps"));
            assert!((sum("pixel_share") - 1.0).abs() < 1e-9, "{variant} {view}: {split:?}");
            assert!(split.iter().any(|b| b["layers"] == 0) && split.iter().any(|b| b["layers"] == 1), "{split:?}");
        }
    }
    let table = std::fs::read_to_string(out.join("bench.md")).unwrap();
    // The two reference rows are marked as the ruler, with no ε or PSNR of their own.
    assert_eq!(table.lines().filter(|l| l.contains("| reference (the ruler) |")).count(), 2, "{table}");
    assert!(!table.contains('∞'), "{table}");
    let cached: Vec<_> = std::fs::read_dir(out.join("cache")).unwrap().map(|e| e.unwrap().path()).collect();
    for extension in ["png", "ms", "layers"] {
        assert_eq!(cached.iter().filter(|p| p.extension().is_some_and(|e| e == extension)).count(), 2, "{extension}");
    }
    let stamps: Vec<_> = cached.iter().map(|p| std::fs::metadata(p).unwrap().modified().unwrap()).collect();

    // A second run takes the references from the cache instead of rendering them again.
    let second = run();
    assert!(second.status.success());
    let again: Vec<_> = cached.iter().map(|p| std::fs::metadata(p).unwrap().modified().unwrap()).collect();
    assert_eq!(stamps, again, "the cached references were rewritten");
}

/// `--ruler depth-peel:layers=8` measures every row against 8-layer depth
/// peeling, as Zhang & Pajarola's ε is measured: a row's ε is then its image
/// against the peeled one, which the test computes again from the images.
#[test]
fn a_ruler_mode_measures_every_row_against_its_image_instead_of_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let demo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/demo.toml");
    let run = |extra: &[&str]| {
        let mut args = vec![demo.to_str().unwrap(), "--modes", "alg2,depth-peel:layers=8", "--size", "128x128"];
        args.extend(["--frames", "1", "--warm-up", "1", "--views", "1", "--loads", "1"]);
        args.extend(extra);
        common::bench_rows(&args, &out)
    };
    let exact = run(&[]);
    let peeled = run(&["--ruler", "depth-peel:layers=8"]);
    let row = |rows: &[serde_json::Value], variant: &str| {
        rows.iter().find(|r| r["variant"] == variant).unwrap_or_else(|| panic!("no {variant} row")).clone()
    };
    let (alg2, alg2_peeled) = (row(&exact, "alg2"), row(&peeled, "alg2"));
    assert!(alg2["reference"].as_str().unwrap().starts_with("reference"), "{}", alg2["reference"]);
    assert_eq!(alg2_peeled["reference"], "depth-peel:layers=8 (--ruler)");
    // The ruler's own row is still measured against the exact reference.
    assert_eq!(row(&peeled, "depth-peel:layers=8")["eps"], row(&exact, "depth-peel:layers=8")["eps"]);
    // alg2's ε against the ruler is its image against the peeled image.
    let image = |name: &str| image::open(out.join(name)).unwrap().to_rgba8();
    let peel_image = image(row(&peeled, "depth-peel:layers=8")["image"].as_str().unwrap());
    let want = pointblend::reference::compare(&image(alg2_peeled["image"].as_str().unwrap()), &peel_image).unwrap().eps;
    let got = alg2_peeled["eps"].as_f64().unwrap();
    println!("alg2: ε {} against the reference, {got} against 8-layer peeling (recomputed {want})", alg2["eps"]);
    assert!((got - want).abs() < 1e-9, "{got} against {want}");
    assert_ne!(alg2["eps"], alg2_peeled["eps"], "another ruler, another ε");
}

#[test]
fn no_reference_times_the_gpu_modes_alone_in_splats_per_second() {
    // The scale case's bench on the GPU machine (scripts/gpu-check): no CPU
    // reference, so no reference row, image, cache entry, error or plot.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("bench")
        .arg(common::bundled_model())
        .args(["--modes", "tiled,reference", "--no-reference", "--size", "96x96", "--frames", "1", "--warm-up", "1"])
        .args(["--views", "1", "--loads", "1", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let rows: Vec<serde_json::Value> = serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    let variants: Vec<&str> = rows.iter().map(|r| r["variant"].as_str().unwrap()).collect();
    assert_eq!(variants, ["tiled"], "one row, of the GPU mode");
    assert!(rows[0]["eps"].is_null() && rows[0]["psnr"].is_null(), "no error without a reference: {}", rows[0]);
    assert!(rows[0]["frame_ms"].as_f64().unwrap() > 0.0 && rows[0]["tile_list_bytes"].as_u64().unwrap() > 0);
    let markdown = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(markdown.contains("M splats/s (frame)") && !markdown.contains("ε"), "{markdown}");
    assert!(out.join("lion-front-tiled.png").exists(), "the mode's image is kept");
    let left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .chain(std::fs::read_dir(out.join("cache")).into_iter().flatten())
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        !left.iter().any(|f| f.contains("reference") || f.contains("diff") || f == "error_vs_time.png"),
        "{left:?}"
    );
}

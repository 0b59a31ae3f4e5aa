//! The first run: `pointblend` with no subcommand and no display renders the
//! opaque modes on the bundled lion and every transparent mode on the demo
//! scene, so that no transparent mode falls back to two-pass; and where a
//! transparent mode does meet an opaque model, bench and render say so.

mod common;

use std::collections::BTreeSet;
use std::process::Command;

const TRANSPARENT_MODES: [&str; 6] = ["depth-peel", "approx-peel", "alg1", "alg2", "alpha-blend", "tiled"];
const FALLBACK: &str = "opaque scene: ran two-pass";

/// `pointblend ARGS` with no display, into `out`, at 96x96.
fn headless_view(args: &[&str], out: &std::path::Path) -> (String, Vec<serde_json::Value>) {
    let output = Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(args)
        .args(["--size", "96x96", "--out"])
        .arg(out)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(output.status.success(), "{}\n{stdout}", String::from_utf8_lossy(&output.stderr));
    let rows = serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    (stdout, rows)
}

#[test]
fn the_main_job_renders_every_transparent_mode_on_a_transparent_scene() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    // No subcommand: what the README's first command runs.
    let (stdout, rows) = headless_view(&[], &out);
    println!("{stdout}");
    let mut transparent_eps = BTreeSet::new();
    for row in &rows {
        let (mode, variant) = (row["mode"].as_str().unwrap(), row["variant"].as_str().unwrap());
        let model = row["model"].as_str().unwrap();
        assert!(row.get("fallback").is_none(), "{variant} on {model} reports the opaque fallback: {row}");
        if TRANSPARENT_MODES.contains(&mode) {
            let scenes = ["demo.toml", "lidar-classes.toml"];
            assert!(scenes.contains(&model), "{variant} renders {model}, not the demo scene or the lidar demo");
            if variant == mode && model == "demo.toml" {
                transparent_eps.insert(format!("{:.3}", row["eps"].as_f64().unwrap()));
            }
        } else if mode != "reference" {
            assert_eq!(model, "lion.ply", "{variant}: the opaque modes render the lion");
        }
    }
    assert_eq!(
        transparent_eps.len(),
        TRANSPARENT_MODES.len(),
        "each transparent mode has its own ε: {transparent_eps:?}"
    );
    // One compact row per mode at its defaults, and the files named in one line.
    for mode in TRANSPARENT_MODES {
        for scene in ["demo.toml", "lidar-classes.toml"] {
            let row = format!("| {mode} | {scene} (transparent)");
            assert!(stdout.lines().any(|l| l.starts_with(&row)), "no row '{row}' in {stdout}");
        }
    }
    assert!(stdout.lines().any(|l| l.starts_with("wrote") && l.contains("modes.png")), "{stdout}");
    let sheet = image::open(out.join("modes.png")).expect("the contact sheet is a PNG");
    assert!(sheet.width() >= 6 * 96 && sheet.height() >= 2 * 96, "{:?}", (sheet.width(), sheet.height()));
    assert!(out.join("error_vs_time.png").is_file());
}

#[test]
fn transparent_modes_on_an_opaque_model_say_they_ran_two_pass() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let lion = common::bundled_model();
    let (stdout, rows) = headless_view(&["view", lion.to_str().unwrap()], &out);
    for row in &rows {
        let mode = row["mode"].as_str().unwrap();
        let marked = row.get("fallback").and_then(|f| f.as_str()) == Some(FALLBACK);
        // tiled draws an opaque scene with its own passes (the registry's draws_opaque_scenes).
        let falls_back = mode.parse::<pointblend::frame::RenderMode>().is_ok_and(|m| m.runs_opaque(false));
        assert_eq!(falls_back, TRANSPARENT_MODES.contains(&mode) && mode != "tiled", "{mode}");
        assert_eq!(marked, falls_back, "{row}");
    }
    let alg1 = stdout.lines().find(|l| l.starts_with("| alg1 |")).expect("an alg1 row");
    assert!(alg1.contains(FALLBACK), "{alg1}");
    let markdown = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(markdown.contains(&format!("alg2 ({FALLBACK})")), "{markdown}");
    // render says it in one line.
    let png = dir.path().join("alg1.png");
    let output = Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["render", lion.to_str().unwrap(), "--mode", "alg1", "--size", "64x64", "--out"])
        .arg(&png)
        .output()
        .unwrap();
    assert!(output.status.success());
    let said = String::from_utf8_lossy(&output.stdout);
    let lines: Vec<_> = said.lines().filter(|l| l.contains("this model is opaque")).collect();
    assert_eq!(lines.len(), 1, "{said}");
    assert!(lines[0].contains("alg1 ran two-pass") && lines[0].contains("--opacity"), "{said}");
}

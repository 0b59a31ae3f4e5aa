//! Lights, shadows and volumes on the command line: bad input is one line
//! naming the problem with a non-zero exit and no output file; a volume
//! converts into a loadable cloud of translucent points; a scene file's
//! lights and `--light` render, and `--explain` states the TSM tables.

mod common;

use std::process::Command;

fn pointblend() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pointblend"))
}

/// Runs `args`; asserts failure with one stderr line holding `needle` and no file at `out`.
fn fails_with(args: &[&str], needle: &str, out: &std::path::Path) {
    let result = pointblend().args(args).output().unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success(), "{args:?} succeeded");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty() && !l.contains("[INFO")).collect();
    assert!(lines.len() <= 2 && stderr.contains(needle), "{args:?}: expected one line with '{needle}', got: {stderr}");
    assert!(!out.exists(), "{args:?} left {}", out.display());
}

#[test]
fn bad_lights_and_volumes_give_one_line_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.png");
    let model = common::bundled_model();
    let bunny = model.to_str().unwrap();
    let o = out.to_str().unwrap();
    fails_with(&["render", bunny, "--light", "0,1", "--out", o], "'0,1' is not a light position", &out);
    fails_with(&["render", bunny, "--light", "0,1,NaN", "--out", o], "'0,1,NaN' is not a light position", &out);
    let nine: Vec<String> = (0..9).map(|i| format!("--light={i},1,1")).collect();
    let mut args = vec!["render", bunny, "--out", o];
    args.extend(nine.iter().map(String::as_str));
    fails_with(&args, "at most 8 lights", &out);
    fails_with(&["render", bunny, "--shadows", "tsm-0", "--light", "0,1,1", "--out", o], "TSM table size", &out);

    // A scene light with neither position nor direction.
    let scene = dir.path().join("lit.toml");
    std::fs::write(&scene, format!("[[object]]\nply = {:?}\n\n[[light]]\ncolor = [255, 255, 255]\n", bunny)).unwrap();
    fails_with(&["render", scene.to_str().unwrap(), "--out", o], "exactly one of `position` or `direction`", &out);

    // Volumes: unreadable, and a transfer function out of range.
    let ply = dir.path().join("never.ply");
    let p = ply.to_str().unwrap();
    let broken = dir.path().join("broken.nii");
    std::fs::write(&broken, b"not a nifti file at all").unwrap();
    fails_with(&["convert", broken.to_str().unwrap(), p], "broken.nii: cannot read the volume", &ply);
    let head = common::data("anatomical.nii");
    let head = head.to_str().unwrap();
    fails_with(&["convert", head, p, "--transfer", "0:300/0/0/1"], "out of range", &ply);
    fails_with(&["convert", head, p, "--threshold", "1e9"], "no voxel reaches the threshold", &ply);
}

#[test]
fn a_volume_converts_to_translucent_points_that_load_and_render_lit() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("head.ply");
    let head = common::data("anatomical.nii");
    let result = pointblend().args(["convert", head.to_str().unwrap(), ply.to_str().unwrap()]).output().unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let (cloud, _) = pointblend::cloud::load_with(&ply, &Default::default()).unwrap();
    // 33x41x25 voxels: the default keeps those above the 60th percentile with some opacity.
    assert!(cloud.len() > 1000 && cloud.len() < 33 * 41 * 25 * 2 / 5, "{} points", cloud.len());
    assert!(cloud.opacity.iter().all(|&a| a > 0.0 && a <= 1.0) && cloud.has_transparency());
    assert!(cloud.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3), "unit Sobel normals");
    // 2 mm voxels in metres: radius half the diagonal.
    let expected = 0.5 * (3.0f32).sqrt() * 0.002;
    assert!(cloud.radii.iter().all(|r| (r - expected).abs() < 1e-6), "radius {} against {expected}", cloud.radii[0]);

    // The mixed scene renders lit with its TSM table stated.
    let out = dir.path().join("mixed.png");
    let scene = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/shadow-volume-and-scan.toml");
    let result = pointblend()
        .args(["render", scene.to_str().unwrap(), "--mode", "alg2", "--size", "96x96", "--explain", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    assert!(stdout.contains("TSM table of light 1") && stdout.contains("lit by scene lights"), "{stdout}");
    assert!(out.exists());
}

//! Scene files: the demo scenes load and render, and bad scene files give
//! one line naming the file, the line and column, and the problem.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use pointblend::cloud::LoadOptions;
use pointblend::scene;

fn pointblend() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pointblend"))
}

fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets").join(name)
}

/// A scene file in `dir` whose one object is the bundled lion, with `extra`
/// lines added to the object.
fn scene_file(dir: &Path, extra: &str) -> PathBuf {
    let path = dir.join("scene.toml");
    let model = common::bundled_model();
    let text = format!("[camera]\nazimuth = 10\n\n[[object]]\nply = {:?}\n{extra}", model.to_str().unwrap());
    std::fs::write(&path, text).unwrap();
    path
}

fn the_one_error(result: &Output) -> String {
    assert!(!result.status.success(), "a bad scene must fail");
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    errors[0].to_string()
}

#[test]
fn the_demo_scenes_load_with_their_materials() {
    let (balls, warnings) = scene::open(&asset("demo.toml"), &LoadOptions::default()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(balls.objects.len() >= 5, "the lion and its balls");
    assert!(balls.has_transparency());
    assert!(balls.objects.iter().any(|o| o.material.opacity == 1.0), "some balls are opaque");
    let (registration, _) = scene::open(&asset("registration.toml"), &LoadOptions::default()).unwrap();
    assert_eq!(registration.objects.len(), 2, "two copies of one scan");
    let colours: Vec<_> = registration.objects.iter().map(|o| o.material.colour).collect();
    assert_ne!(colours[0], colours[1], "in two colours");
    assert_ne!(registration.objects[0].transform, registration.objects[1].transform, "one moved");
    let (glass, _) = scene::open(&asset("glass.toml"), &LoadOptions::default()).unwrap();
    let map = glass.environment.as_ref().expect("the glass scene names its environment map");
    assert_eq!((map.width(), map.height()), (512, 256));
}

#[test]
fn bad_scene_files_name_the_file_line_column_and_problem() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("opacity = 1.5\n", "6:11", "opacity must be in 0..1"),
        ("colour_override = [1, 2, 3]\n", "6:1", "unknown field `colour_override`"),
        ("color = [300, 0, 0]\n", "6:9", "color must be three values in 0..255"),
    ];
    for (extra, place, problem) in cases {
        let path = scene_file(dir.path(), extra);
        let out = dir.path().join("never.png");
        let result = pointblend().arg("render").arg(&path).arg("--out").arg(&out).output().unwrap();
        let error = the_one_error(&result);
        assert!(error.contains(&format!("scene.toml:{place}")), "{extra:?}: {error}");
        assert!(error.contains(problem), "{extra:?}: {error}");
        assert!(!out.exists());
    }
    // A PLY that is not there: the scene's line of the path, and the PLY named.
    let path = dir.path().join("missing.toml");
    std::fs::write(&path, "[[object]]\nply = \"nowhere/gone.ply\"\nopacity = 0.5\n").unwrap();
    let out = dir.path().join("never.png");
    let error = the_one_error(&pointblend().arg("render").arg(&path).arg("--out").arg(&out).output().unwrap());
    assert!(error.contains("missing.toml:2:7"), "{error}");
    assert!(error.contains("gone.ply"), "{error}");
    // An environment map that is not there: its line, and the map named.
    let path = dir.path().join("no-map.toml");
    let model = common::bundled_model();
    std::fs::write(&path, format!("environment = \"gone.exr\"\n[[object]]\nply = {:?}\n", model.to_str().unwrap()))
        .unwrap();
    let error = the_one_error(&pointblend().arg("render").arg(&path).arg("--out").arg(&out).output().unwrap());
    assert!(error.contains("no-map.toml:1:15"), "{error}");
    assert!(error.contains("gone.exr"), "{error}");
    // A camera key out of range: its place in the scene file, not a flag's name.
    for (key, value, problem) in [
        ("elevation", "nan", "elevation must be a finite number of degrees"),
        ("azimuth", "inf", "azimuth must be a finite number of degrees"),
        ("fov", "171.0", "fov must be between 0.5 and 170 degrees"),
    ] {
        let path = dir.path().join("camera.toml");
        std::fs::write(
            &path,
            format!("[camera]\n{key} = {value}\n\n[[object]]\nply = {:?}\n", model.to_str().unwrap()),
        )
        .unwrap();
        let error = the_one_error(&pointblend().arg("render").arg(&path).arg("--out").arg(&out).output().unwrap());
        let column = key.len() + 4;
        assert!(error.contains(&format!("camera.toml:2:{column}")) && error.contains(problem), "{key}: {error}");
        assert!(!error.contains("--"), "{key}: the scene file's key, not a flag: {error}");
    }
}

#[test]
fn an_opaque_scene_in_a_transparent_mode_says_it_falls_back_and_peels_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("opaque.png");
    let result = pointblend()
        .args(["render", common::bundled_model().to_str().unwrap(), "--mode", "depth-peel", "--size", "96x96"])
        .args(["--explain", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(stdout.contains("nothing in the scene is transparent"), "{stdout}");
    assert!(!stdout.contains("peel depth"), "no peeling target: {stdout}");
    // The same file at opacity 0.5 peels.
    let result = pointblend()
        .args(["render", common::bundled_model().to_str().unwrap(), "--mode", "depth-peel", "--size", "96x96"])
        .args(["--opacity", "0.5", "--layers", "3", "--explain", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(!stdout.contains("nothing in the scene is transparent"), "{stdout}");
    assert!(stdout.contains("peel depth"), "{stdout}");
}

#[test]
fn a_transparent_mode_on_an_opaque_model_draws_the_two_pass_image_exactly() {
    // The grouped modes must not group (and enlarge) an opaque model whose
    // plan falls back to two-pass: the image would change.
    let dir = tempfile::tempdir().unwrap();
    let render = |mode: &str| {
        let out = dir.path().join(format!("{mode}.png"));
        let result = pointblend()
            .args(["render", common::bundled_model().to_str().unwrap(), "--mode", mode, "--size", "96x96", "--out"])
            .arg(&out)
            .env("POINTBLEND_CACHE", dir.path().join("cache"))
            .output()
            .unwrap();
        assert!(result.status.success(), "{mode}: {}", String::from_utf8_lossy(&result.stderr));
        image::open(&out).unwrap().to_rgba8()
    };
    let two_pass = render("two-pass");
    for mode in ["depth-peel", "approx-peel", "alg1", "alg2"] {
        assert!(render(mode) == two_pass, "{mode} on an opaque model is not the two-pass image");
    }
}

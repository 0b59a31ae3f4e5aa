//! What a new user hits first, through the command line: extreme input and
//! options give one clear error line naming the file or option and a non-zero
//! exit (never a panic, a hang or a half-written file), and odd but valid
//! input gives a sane image with a warning.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::plywriter::{Element, Encoding, ply, temp_file};

fn pointblend(dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_pointblend"));
    command.env("POINTBLEND_CACHE", dir.join("cache")).env("XDG_RUNTIME_DIR", std::env::temp_dir());
    command
}

/// The `error:` lines of a failed run; asserts there is exactly one and no panic.
fn one_error(output: &Output, what: &str) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{what} should fail: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    let errors: Vec<&str> =
        stderr.lines().filter(|l| l.starts_with("error: ") && !l.contains("XDG_RUNTIME_DIR")).collect();
    assert_eq!(errors.len(), 1, "{what}: {stderr}");
    for debug_dump in ["ParseError", "LineCol", "PropertyDef", "{ kind", ".tmp"] {
        assert!(!errors[0].contains(debug_dump), "{what}: the error shows '{debug_dump}': {}", errors[0]);
    }
    errors[0].to_string()
}

fn ok(output: &Output, what: &str) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert!(output.status.success(), "{what}: {stderr}");
    stderr
}

/// A scratch folder whose name cannot be mistaken for a leaked temporary file (`.tmpXXXX`).
fn test_dir() -> tempfile::TempDir {
    tempfile::Builder::new().prefix("pointblend-test-").tempdir().unwrap()
}

fn model() -> PathBuf {
    common::bundled_model()
}

/// A binary cloud of `points` with the given extra per-vertex columns.
fn cloud_file(dir: &tempfile::TempDir, name: &str, points: &[[f64; 3]], extra: &[(&str, Vec<f64>)]) -> PathBuf {
    let mut properties = vec![("float", "x"), ("float", "y"), ("float", "z")];
    properties.extend(extra.iter().map(|(n, _)| ("float", *n)));
    let rows = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut row = p.to_vec();
            row.extend(extra.iter().map(|(_, c)| c[i]));
            row
        })
        .collect();
    temp_file(dir, name, &ply(Encoding::Little, &[Element { name: "vertex", properties, rows }], &[], false))
}

/// Points on a unit sphere (Fibonacci lattice).
fn sphere(n: usize, radius: f64) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            [r * (golden * i as f64).cos() * radius, y * radius, r * (golden * i as f64).sin() * radius]
        })
        .collect()
}

fn foreground_share(path: &Path) -> f64 {
    let image = image::open(path).unwrap().to_rgba8();
    let bg = common::background_rgb();
    image.pixels().filter(|p| p.0[..3] != bg).count() as f64 / (image.width() * image.height()) as f64
}

#[test]
fn bad_options_on_a_real_file_name_the_option() {
    let dir = test_dir();
    let out = dir.path().join("never.png");
    for (args, option) in [
        (vec!["--size", "0x10"], "--size"),
        (vec!["--size", "big"], "--size"),
        (vec!["--mode", "nonsense"], "--mode"),
        (vec!["--up", "w"], "--up"),
        (vec!["--fov", "-10"], "--fov"),
        (vec!["--azimuth", "nan"], "--azimuth"),
        (vec!["--elevation", "inf"], "--elevation"),
        (vec!["--distance", "-1"], "--distance"),
        (vec!["--epsilon", "0"], "--epsilon"),
        (vec!["--group", "mgc-c7"], "--group"),
    ] {
        let result =
            pointblend(dir.path()).arg("render").arg(model()).args(&args).arg("--out").arg(&out).output().unwrap();
        let error = one_error(&result, &format!("{args:?}"));
        assert!(error.contains(option), "{args:?}: the error does not name {option}: {error}");
        assert!(!out.exists(), "{args:?} wrote an image");
    }
}

#[test]
fn help_lists_the_modes() {
    let dir = test_dir();
    let help = pointblend(dir.path()).args(["render", "--help"]).output().unwrap();
    let text = String::from_utf8_lossy(&help.stdout);
    for mode in pointblend::frame::RenderMode::ALL {
        assert!(text.contains(mode.name()), "--help does not list {mode}: {text}");
    }
}

#[test]
fn options_a_mode_does_not_read_are_reported() {
    let dir = test_dir();
    let out = dir.path().join("a.png");
    let run = pointblend(dir.path())
        .arg("render")
        .arg(model())
        .args(["--mode", "deferred", "--quality", "unfiltered", "--size", "64x64", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(ok(&run, "deferred with --quality").contains("--quality is ignored"));
    let run = pointblend(dir.path())
        .arg("render")
        .arg(model())
        .args(["--group", "wgc-k8", "--no-voronoi", "--size", "64x64", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = ok(&run, "two-pass with --group");
    assert!(stderr.contains("--group is ignored") && stderr.contains("--no-voronoi is ignored"), "{stderr}");
}

#[test]
fn a_huge_sample_count_is_refused_before_any_allocation() {
    let dir = test_dir();
    let out = dir.path().join("big.ply");
    for n in ["18446744073709551615", "4294967296", "100000000000"] {
        let result = pointblend(dir.path())
            .arg("convert")
            .arg(common::bundled_mesh())
            .arg(&out)
            .args(["--points", n])
            .output()
            .unwrap();
        let error = one_error(&result, n);
        assert!(error.contains("--points"), "{n}: {error}");
        assert!(!out.exists());
    }
}

#[cfg(unix)]
#[test]
fn outputs_never_replace_devices_fifos_or_links() {
    use std::os::unix::fs::FileTypeExt;
    let dir = test_dir();
    let render = |out: &Path| {
        pointblend(dir.path()).arg("render").arg(model()).args(["--size", "64x64", "--out"]).arg(out).output().unwrap()
    };
    let error = one_error(&render(Path::new("/dev/full")), "/dev/full");
    assert!(error.contains("/dev/full") && error.contains("not a regular file"), "{error}");
    assert!(std::fs::metadata("/dev/full").unwrap().file_type().is_char_device());

    let fifo = dir.path().join("pipe.png");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    one_error(&render(&fifo), "a FIFO");
    assert!(std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(), "the FIFO is still there");

    let real = dir.path().join("real.png");
    let link = dir.path().join("link.png");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    ok(&render(&link), "a link to a new file");
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays a link");
    assert!(image::open(&real).is_ok(), "the image went where the link points");
}

#[test]
fn images_are_encoded_as_their_extension_says_and_other_extensions_are_refused() {
    let dir = test_dir();
    let jpg = dir.path().join("shot.jpg");
    let run = pointblend(dir.path()).arg("render").arg(model()).args(["--size", "64x64", "--out"]).arg(&jpg).output();
    ok(&run.unwrap(), "jpg");
    assert_eq!(&std::fs::read(&jpg).unwrap()[..2], &[0xFF, 0xD8], "a JPEG starts with FFD8");
    let tif = dir.path().join("shot.tif");
    let run = pointblend(dir.path()).arg("render").arg(model()).args(["--size", "64x64", "--out"]).arg(&tif).output();
    assert!(one_error(&run.unwrap(), "tif").contains(".png or .jpg"));
    assert!(!tif.exists());
}

#[test]
fn an_unwritable_second_output_stops_the_run_before_the_first_is_written() {
    let dir = test_dir();
    let out = dir.path().join("main.png");
    let blocker = dir.path().join("file");
    std::fs::write(&blocker, b"not a folder").unwrap();
    let run = pointblend(dir.path())
        .arg("render")
        .arg(model())
        .args(["--size", "64x64", "--out"])
        .arg(&out)
        .arg("--diff")
        .arg(blocker.join("diff.png"))
        .output()
        .unwrap();
    assert!(one_error(&run, "--diff under a file").contains("diff.png"));
    assert!(!out.exists(), "the main image was written although the run failed");
}

#[test]
fn convert_and_render_both_create_a_missing_output_folder() {
    let dir = test_dir();
    let ply = dir.path().join("new/folder/splats.ply");
    ok(&pointblend(dir.path()).arg("convert").arg(model()).arg(&ply).output().unwrap(), "convert");
    assert!(pointblend::cloud::load(&ply).is_ok());
    let png = dir.path().join("other/new/folder/a.png");
    let run = pointblend(dir.path()).arg("render").arg(&ply).args(["--size", "64x64", "--out"]).arg(&png).output();
    ok(&run.unwrap(), "render");
    assert!(png.exists());
}

#[test]
fn coincident_copies_are_merged_and_a_frame_over_the_memory_budget_is_drawn_in_sub_frames_or_refused_with_a_hint() {
    let dir = test_dir();
    // 3,000 copies of one point: merged into one splat (they used to need
    // one group each, K = 3001), with a warning that counts them.
    let mut points = sphere(2000, 1.0);
    points.extend(std::iter::repeat_n([0.0, 0.0, 1.0], 3000));
    let file = cloud_file(&dir, "clique.ply", &points, &[]);
    let out = dir.path().join("clique.png");
    let run = pointblend(dir.path())
        .arg("render")
        .arg(&file)
        .args(["--mode", "deferred", "--size", "64x64", "--explain", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let warnings = ok(&run, "3,000 copies");
    assert!(warnings.contains("2999 splats that repeat another's"), "{warnings}");
    let explained = String::from_utf8_lossy(&run.stdout);
    let line = explained.lines().find(|l| l.contains(" groups; each splat")).expect("--explain's groups line");
    let groups: usize = line.split_whitespace().next().unwrap().parse().unwrap();
    assert!(groups <= 64, "the copies need no group each: K = {groups}\n{explained}");
    assert!(out.exists());
    // The bundled model in deferred with independent groups, under a memory budget of `mb` MiB.
    let under_budget = |mb: &str| {
        pointblend(dir.path())
            .env("POINTBLEND_GPU_MEMORY_MB", mb)
            .arg("render")
            .arg(model())
            .args(["--mode", "deferred", "--group", "mgc-c1", "--size", "512x512", "--out"])
            .arg(&out)
            .output()
            .unwrap()
    };
    // Over the budget: drawn a sub-frame at a time...
    let log = ok(&under_budget("16"), "over budget, in sub-frames");
    assert!(log.contains("is drawn in") && log.contains("sub-frames"), "{log}");
    // ...and where not even a small sub-frame fits, refused with the size in the message.
    let run = under_budget("1");
    let error = one_error(&run, "over budget");
    assert!(error.contains("GiB of render targets") && error.contains("--size"), "{error}");
}

#[test]
fn an_absurd_radius_is_clamped_and_the_model_stays_in_view() {
    let dir = test_dir();
    let points = sphere(4000, 1.0);
    let mut radii = vec![0.06; points.len()];
    radii[17] = 2e6;
    let normals: Vec<Vec<f64>> = (0..3).map(|a| points.iter().map(|p| p[a]).collect()).collect();
    let extra = [("nx", normals[0].clone()), ("ny", normals[1].clone()), ("nz", normals[2].clone()), ("radius", radii)];
    let file = cloud_file(&dir, "absurd.ply", &points, &extra);
    let out = dir.path().join("absurd.png");
    let run = pointblend(dir.path()).arg("render").arg(&file).args(["--size", "96x96", "--out"]).arg(&out).output();
    assert!(ok(&run.unwrap(), "absurd radius").contains("1 radii larger than"));
    let share = foreground_share(&out);
    assert!(share > 0.1 && share < 0.9, "the sphere is framed, not hidden or covering the view: {share}");
}

#[test]
fn coordinates_too_large_or_small_for_f32_are_rescaled() {
    let dir = test_dir();
    for scale in [1e19, 1e22, 1e-12] {
        let points: Vec<[f64; 3]> = sphere(3000, scale).into_iter().map(|p| [p[0] + 5.0 * scale, p[1], p[2]]).collect();
        let file = cloud_file(&dir, "far.ply", &points, &[]);
        let out = dir.path().join("far.png");
        let run = pointblend(dir.path()).arg("render").arg(&file).args(["--size", "96x96", "--out"]).arg(&out).output();
        assert!(ok(&run.unwrap(), "rescaled").contains("coordinates and radii are in units of 1e"), "{scale}");
        let share = foreground_share(&out);
        assert!(share > 0.2, "scale {scale}: the sphere is not drawn ({share})");
        let group = pointblend(dir.path()).arg("group").arg(&file).args(["--json", "--no-cache"]).output().unwrap();
        ok(&group, "group");
        let json: serde_json::Value = serde_json::from_slice(&group.stdout).unwrap();
        assert!(json["k"].as_u64().unwrap() < 50, "scale {scale}: K {}", json["k"]);
        let converted = dir.path().join("far-again.ply");
        ok(&pointblend(dir.path()).arg("convert").arg(&file).arg(&converted).output().unwrap(), "convert");
        let (back, _) = pointblend::cloud::load(&converted).unwrap();
        let x = back.positions[0].x as f64 * back.unit() + back.origin[0];
        assert!((x - points[0][0]).abs() <= 1e-5 * scale, "scale {scale}: {x} against {}", points[0][0]);
    }
}

#[test]
fn duplicate_names_in_a_header_are_refused_with_the_line() {
    let dir = test_dir();
    let file = temp_file(
        &dir,
        "dup.ply",
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float x\nproperty float z\nend_header\n1 2 3 4\n",
    );
    let error = one_error(&pointblend(dir.path()).arg("info").arg(&file).output().unwrap(), "duplicate");
    assert!(error.contains("dup.ply") && error.contains("line 6") && error.contains("declared twice"), "{error}");
}

#[test]
fn bench_skips_a_bad_file_keeps_the_others_and_says_so() {
    let dir = test_dir();
    let bad = temp_file(&dir, "broken.ply", b"ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nend_header\n");
    let out = dir.path().join("bench");
    let run = pointblend(dir.path())
        .arg("bench")
        .arg(&bad)
        .arg(model())
        .args(["--modes", "two-pass:quality=filtered", "--size", "64x64", "--frames", "1", "--warm-up", "0"])
        .args(["--views", "1", "--loads", "1", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let error = one_error(&run, "bench with a broken file");
    assert!(error.contains("broken.ply") && error.contains("1 of 2 files"), "{error}");
    let rows: Vec<serde_json::Value> = serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    assert_eq!(rows.len(), 1, "the lion's row is kept");
    assert_eq!(rows[0]["model"], "lion.ply");
}

#[test]
fn gaussian_splats_with_zero_normals_take_their_normals_from_the_gaussians_only() {
    let dir = test_dir();
    let points = sphere(500, 1.0);
    let n = points.len();
    let column = |v: f64| vec![v; n];
    let extra: Vec<(&str, Vec<f64>)> = vec![
        ("nx", column(0.0)),
        ("ny", column(0.0)),
        ("nz", column(0.0)),
        ("f_dc_0", column(0.5)),
        ("f_dc_1", column(0.1)),
        ("f_dc_2", column(-0.3)),
        ("opacity", column(4.0)),
        ("scale_0", column(-3.0)),
        ("scale_1", column(-3.0)),
        ("scale_2", column(-7.0)),
        ("rot_0", column(1.0)),
        ("rot_1", column(0.0)),
        ("rot_2", column(0.0)),
        ("rot_3", column(0.0)),
    ];
    let file = cloud_file(&dir, "gaussians.ply", &points, &extra);
    let info = pointblend(dir.path()).arg("info").arg(&file).output().unwrap();
    let stdout = String::from_utf8_lossy(&info.stdout);
    assert!(stdout.contains("normals:     from 3D Gaussian parameters"), "{stdout}");
    assert!(!stdout.contains("re-estimated"), "{stdout}");
}

#[test]
fn points_on_a_line_are_drawn_facing_the_viewer_with_a_warning() {
    let dir = test_dir();
    let points: Vec<[f64; 3]> = (0..300).map(|i| [i as f64 * 0.01, i as f64 * 0.005, 0.0]).collect();
    let file = cloud_file(&dir, "line.ply", &points, &[]);
    let out = dir.path().join("line.png");
    let run = pointblend(dir.path()).arg("render").arg(&file).args(["--size", "128x128", "--out"]).arg(&out).output();
    assert!(ok(&run.unwrap(), "line").contains("the points lie on a line"));
    assert!(foreground_share(&out) > 0.005, "the line of splats is visible");
}

#[test]
fn group_and_render_share_the_default_grouping() {
    let dir = test_dir();
    let run = pointblend(dir.path()).arg("group").arg(model()).args(["--json", "--no-cache"]).output().unwrap();
    ok(&run, "group");
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let grouping = json["grouping"].as_str().unwrap();
    assert_eq!(grouping, pointblend::grouping::GroupingSpec::default().to_string(), "group's default is --group's");
    assert_eq!(grouping, "mgc-c0.4");
    assert!(pointblend::frame::RenderSettings::default().voronoi, "deferred defaults to Voronoi depth everywhere");
}

#[test]
fn an_output_that_names_its_input_another_way_is_refused() {
    let dir = test_dir();
    std::fs::create_dir_all(dir.path().join("in")).unwrap();
    let input = cloud_file(&dir, "self.ply", &sphere(500, 1.0), &[]);
    let input = {
        let moved = dir.path().join("in/self.ply");
        std::fs::rename(&input, &moved).unwrap();
        moved
    };
    let before = std::fs::read(&input).unwrap();
    std::os::unix::fs::symlink(&input, dir.path().join("link.ply")).unwrap();
    let spellings = [
        PathBuf::from("in/../in/./self.ply"),
        input.clone(),
        PathBuf::from("link.ply"),
        PathBuf::from("./in/self.ply"),
    ];
    for output in spellings {
        let run = pointblend(dir.path()).current_dir(dir.path()).args(["convert", "in/self.ply"]).arg(&output).output();
        let error = one_error(&run.unwrap(), &format!("convert in/self.ply {}", output.display()));
        assert!(error.contains("refusing to write over it") && error.contains("the input"), "{error}");
        assert_eq!(std::fs::read(&input).unwrap(), before, "{}: the input was changed", output.display());
    }
    // render: --diff naming the --out image another way.
    let run = pointblend(dir.path())
        .current_dir(dir.path())
        .args(["render", "in/self.ply", "--size", "32x32", "--out", "out/a.png", "--diff", "in/../out/a.png"])
        .output()
        .unwrap();
    let error = one_error(&run, "--diff naming --out");
    assert!(error.contains("the --out image"), "{error}");
    assert!(!dir.path().join("out/a.png").exists(), "nothing is written");
}

/// `pointblend render` of the bundled model at 32x32 into `out`.
fn render_small(dir: &Path, out: &Path) -> Output {
    pointblend(dir).arg("render").arg(model()).args(["--size", "32x32", "--out"]).arg(out).output().unwrap()
}

#[cfg(unix)]
#[test]
fn a_read_only_output_is_refused_and_a_writable_one_keeps_its_mode() {
    use std::os::unix::fs::PermissionsExt;
    let dir = test_dir();
    let read_only = dir.path().join("ro.png");
    std::fs::write(&read_only, b"mine").unwrap();
    std::fs::set_permissions(&read_only, std::fs::Permissions::from_mode(0o444)).unwrap();
    let output = render_small(dir.path(), &read_only);
    let error = one_error(&output, "--out on a read-only file");
    assert!(error.contains("ro.png") && error.contains("read-only"), "{error}");
    assert_eq!(std::fs::read(&read_only).unwrap(), b"mine");
    let private = dir.path().join("private.png");
    std::fs::write(&private, b"old").unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o600)).unwrap();
    let output = render_small(dir.path(), &private);
    ok(&output, "--out on a writable file");
    assert!(image::open(&private).is_ok(), "the render replaced it");
    assert_eq!(std::fs::metadata(&private).unwrap().permissions().mode() & 0o777, 0o600, "its mode is kept");
}

#[test]
fn a_sidecar_gets_the_checks_the_flags_get() {
    use pointblend::frame::sidecar::SidecarModel;
    use pointblend::frame::{Camera, RenderMode, RenderSettings, Sidecar};
    let dir = test_dir();
    let settings = RenderSettings { mode: RenderMode::RULER, ..Default::default() };
    let model_info = SidecarModel {
        name: "lion.ply".into(),
        path: String::new(),
        hash: String::new(),
        splats: 1,
        nodes: false,
        layers: Vec::new(),
    };
    let valid = Sidecar::new(model_info, &Camera::framing(glam::Vec3::ZERO, 1.0, 1.0), &settings, (32, 32));
    let valid = serde_json::to_value(&valid).unwrap();
    let unordered = serde_json::json!([{"opacity": 1.0, "clip": {"min": [5.0, 0.0, 0.0], "max": [1.0, 1.0, 1.0]}}]);
    let cases: [(&str, &str, serde_json::Value, &str); 12] = [
        ("size", "", serde_json::json!([100000, 100000]), "1..=16384"),
        ("parameters", "epsilon", serde_json::json!("0"), "epsilon=0: expected a positive"),
        ("parameters", "epsilon", serde_json::json!("-1"), "epsilon=-1: expected a positive"),
        ("parameters", "point-budget", serde_json::json!("0"), "point-budget=0: expected"),
        ("parameters", "step", serde_json::json!("0"), "step=0: expected"),
        ("parameters", "radius-scale", serde_json::json!("-1"), "radius-scale=-1: expected"),
        ("parameters", "radius-scale", serde_json::json!("1e30"), "radius-scale=1e30: expected"),
        ("parameters", "supersample", serde_json::json!("0"), "supersample=0: expected"),
        ("parameters", "no-such-key", serde_json::json!("1"), "'no-such-key' is not a parameter"),
        ("camera", "scene_radius", serde_json::json!(1e39), "camera"),
        ("looks", "", unordered, "looks: the clip box must have finite corners with min <= max"),
        ("looks", "", serde_json::json!([{"opacity": 2.0}]), "looks: '2' is not an opacity in 0..1"),
    ];
    for (section, key, value, expected) in cases {
        let mut bad = valid.clone();
        match key {
            "" => bad[section] = value.clone(),
            _ => bad[section][key] = value.clone(),
        }
        let path = dir.path().join("view.json");
        std::fs::write(&path, serde_json::to_string(&bad).unwrap()).unwrap();
        let out = dir.path().join("never.png");
        let output = pointblend(dir.path())
            .arg("render")
            .arg(model())
            .arg("--camera")
            .arg(&path)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let error = one_error(&output, &format!("{section}.{key} = {value}"));
        assert!(error.contains("view.json") && error.contains(expected), "{section}.{key} = {value}: {error}");
        assert!(!out.exists(), "{section}.{key} = {value}: an image was written");
    }
}

#[test]
fn the_field_of_view_takes_both_ends_of_its_range() {
    let dir = test_dir();
    for fov in ["0.5", "170"] {
        let out = dir.path().join(format!("fov{fov}.png"));
        let output = pointblend(dir.path())
            .arg("render")
            .arg(model())
            .args(["--size", "32x32", "--fov", fov, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        ok(&output, &format!("--fov {fov}"));
        assert!(out.exists());
    }
}

#[test]
fn bench_refuses_one_views_camera_and_an_endless_animation_in_one_line() {
    let dir = test_dir();
    let out = dir.path().join("bench-out");
    let cases: [(&[&str], &str); 4] = [
        (&["--azimuth", "30"], "--azimuth"),
        (&["--elevation", "10"], "--elevation"),
        (&["--distance", "2"], "--distance"),
        (&["--animate", "100000"], "at most 1000 frames"),
    ];
    for (extra, expected) in cases {
        let output = pointblend(dir.path())
            .arg("bench")
            .arg(common::asset("lion-wave.toml"))
            .args(extra)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let error = one_error(&output, &format!("bench {extra:?}"));
        assert!(error.contains(expected), "{extra:?}: {error}");
        assert!(!out.exists(), "{extra:?}: bench wrote its folder");
    }
}

/// `pointblend render INPUT ARGS --out OUT`, run in `dir`.
fn render_with(dir: &Path, input: &Path, args: &[&str], out: &Path) -> Output {
    pointblend(dir).arg("render").arg(input).args(args).arg("--out").arg(out).output().unwrap()
}

#[test]
fn gpu_limits_give_one_line_not_a_cascade_of_gpu_errors() {
    let dir = test_dir();
    // An environment map wider than the GPU's textures: drawn from a mip level that fits.
    let wide = dir.path().join("wide.png");
    image::RgbImage::from_pixel(20_000, 1, image::Rgb([100, 150, 200])).save(&wide).unwrap();
    let out = dir.path().join("glass.png");
    let env = ["--mode", "alg2", "--opacity", "0.5", "--size", "48x48", "--env", wide.to_str().unwrap()];
    let output = render_with(dir.path(), &model(), &env, &out);
    let stderr = ok(&output, "a 20000x1 environment map");
    assert!(!stderr.contains("uncaptured"), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("wide.png") && l.contains("level")).collect();
    assert_eq!(warnings.len(), 1, "one warning names the map and the level drawn: {stderr}");
    assert!(out.exists());
    // Targets larger than the memory: one line (or, on a GPU that holds them, an image).
    let out = dir.path().join("huge.png");
    let output =
        render_with(dir.path(), &model(), &["--mode", "alg2", "--opacity", "0.5", "--size", "10240x10240"], &out);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("uncaptured"), "the GPU's errors are reported one by one: {stderr}");
    if !output.status.success() {
        let error = one_error(&output, "alg2 at 10240²");
        assert!(error.contains("memory"), "{error}");
        assert!(!out.exists(), "a failed render wrote its output");
    }
}

/// A scene file of `objects` (TOML) beside a copy-free reference to the bundled lion.
fn scene_with(dir: &tempfile::TempDir, name: &str, objects: &str) -> PathBuf {
    let path = dir.path().join(name);
    let lion = model();
    std::fs::write(&path, objects.replace("LION", &format!("{:?}", lion.to_str().unwrap()))).unwrap();
    path
}

#[test]
fn numbers_no_float_arithmetic_can_draw_are_refused_in_one_line() {
    let dir = test_dir();
    let out = dir.path().join("never.png");
    let cases = [
        ("scale 1e15", "[[object]]\nply = LION\nscale = 1e15\n", "scale must be within"),
        ("scale 1e-30", "[[object]]\nply = LION\nscale = 1e-30\n", "scale must be within"),
        (
            "a wave of 1e30",
            "[[object]]\nply = LION\ndeform = { kind = \"wave\", amount = 1e30, period = 2.0 }\n",
            "deform amount must be within",
        ),
        (
            "a twist of 1e30",
            "[[object]]\nply = LION\ndeform = { kind = \"twist\", amount = 1e30, period = 2.0 }\n",
            "deform amount must be within",
        ),
        (
            "a sphere of radius 1e-40",
            "[[object]]\nsphere = { splats = 100, radius = 1e-40, centre = [0.0, 0.0, 0.0] }\n",
            "a radius within",
        ),
        ("a light at 1e20", "[[object]]\nply = LION\n\n[[light]]\nposition = [1e20, 0.0, 0.0]\n", "is beyond"),
        (
            "a keyframe at 1e300 s",
            "[[object]]\nply = LION\n\n[[object.keyframe]]\ntime = 0.0\n\n[[object.keyframe]]\ntime = 1e300\n",
            "1e300 s",
        ),
    ];
    for (what, text, expected) in cases {
        let scene = scene_with(&dir, "odd.toml", text);
        let output = render_with(dir.path(), &scene, &[], &out);
        let error = one_error(&output, what);
        assert!(error.contains(expected) && error.contains("odd.toml"), "{what}: {error}");
        assert!(!error.contains("inf"), "{what}: {error}");
        assert!(!out.exists(), "{what}: an image was written");
    }
}

#[test]
fn a_huge_time_draws_the_wrapped_time_and_an_infinite_one_is_refused_before_the_gpu_opens() {
    let dir = test_dir();
    let scene = scene_with(
        &dir,
        "wave.toml",
        "[[object]]\nply = LION\nopacity = 0.5\ndeform = { kind = \"wave\", amount = 0.18, period = 2.0 }\n",
    );
    let render_at = |time: &str| {
        let out = dir.path().join(format!("at-{time}.png"));
        let output = render_with(dir.path(), &scene, &["--size", "48x48", "--time", time], &out);
        ok(&output, &format!("--time {time}"));
        image::open(&out).unwrap().to_rgba8()
    };
    // 1e20 s is a whole number of the wave's 2 s periods: the scene at 0 s.
    assert!(render_at("1e20") == render_at("0"), "--time 1e20 drew another time than its wrapped 0 s");
    let output = render_with(dir.path(), &scene, &["--time", "inf"], &dir.path().join("never.png"));
    let error = one_error(&output, "--time inf");
    assert!(error.contains("--time"), "{error}");
    assert!(!String::from_utf8_lossy(&output.stderr).contains("GPU:"), "the GPU was opened before --time was checked");
}

#[test]
fn a_sequence_of_unreadable_files_is_one_line_with_their_count() {
    let dir = test_dir();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    for i in 0..73 {
        std::fs::write(frames.join(format!("f_{i:03}.ply")), b"these are not PLY files").unwrap();
    }
    let scene = scene_with(&dir, "seq.toml", "[[object]]\nsequence = \"frames/f_*.ply\"\nfps = 10\n");
    let output = render_with(dir.path(), &scene, &[], &dir.path().join("x.png"));
    let error = one_error(&output, "73 unreadable frames");
    assert!(error.contains("73"), "{error}");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.lines().filter(|l| l.contains("f_0")).count() <= 1, "one line, not one per file: {stderr}");
}

#[test]
fn odd_volume_headers_and_an_invisible_transfer_function_say_what_is_wrong() {
    let dir = test_dir();
    let source = std::fs::read(common::data("anatomical.nii")).unwrap();
    // The test volume is big-endian NIfTI-1: dim at byte 40, pixdim at 76, scl_slope at 112.
    let patched = |name: &str, at: usize, bytes: &[u8]| {
        let mut data = source.clone();
        data[at..at + bytes.len()].copy_from_slice(bytes);
        let path = dir.path().join(name);
        std::fs::write(&path, data).unwrap();
        path
    };
    let cases = [
        (patched("dim1.nii", 42, &0i16.to_be_bytes()), "dim[1] is 0"),
        (patched("dim2.nii", 44, &0i16.to_be_bytes()), "dim[2] is 0"),
        (patched("slope.nii", 112, &f32::NAN.to_be_bytes()), "no voxel has a finite value"),
        (patched("voxel.nii", 80, &f32::NAN.to_be_bytes()), "pixdim[1] is NaN"),
    ];
    for (file, expected) in cases {
        let out = dir.path().join("never.ply");
        let output = pointblend(dir.path()).arg("convert").arg(&file).arg(&out).output().unwrap();
        let error = one_error(&output, expected);
        assert!(error.contains(expected), "{}: {error}", file.display());
        assert!(!error.contains("inf..") && !out.exists(), "{error}");
    }
    let output = pointblend(dir.path())
        .arg("convert")
        .arg(common::data("anatomical.nii"))
        .arg(dir.path().join("never.ply"))
        .args(["--transfer", "0:100/100/100/0,100:200/200/200/0"])
        .output()
        .unwrap();
    let error = one_error(&output, "a transfer function of opacity 0");
    assert!(error.contains("opacity 0"), "{error}");
}

/// Runs `pointblend ARGS` and gives its output, failing the test if it is
/// still running after `seconds` (it is killed then).
fn within(dir: &Path, args: &[&std::ffi::OsStr], seconds: u64) -> Output {
    let mut child = pointblend(dir)
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed().as_secs() >= seconds {
            let _ = child.kill();
            panic!("pointblend {args:?} still ran after {seconds} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

#[cfg(unix)]
#[test]
fn pipes_devices_and_oversized_settings_files_are_refused_in_one_line_without_reading_them() {
    let dir = test_dir();
    let fifo = dir.path().join("fifo.ply");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let error = one_error(&within(dir.path(), &["info".as_ref(), fifo.as_os_str()], 30), "a FIFO");
    assert!(error.contains("fifo.ply") && error.contains("named pipe"), "{error}");
    // A link named like a scan, to an endless device.
    let zero = dir.path().join("zero.ply");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let error = one_error(&within(dir.path(), &["info".as_ref(), zero.as_os_str()], 30), "/dev/zero");
    assert!(error.contains("zero.ply") && error.contains("device"), "{error}");
    // Settings files: a device, and one far larger than any real one.
    let big = dir.path().join("big.json");
    std::fs::write(&big, vec![b' '; 17 << 20]).unwrap();
    let out = dir.path().join("never.png");
    let lion = model();
    for (flag, file, problem) in [
        ("--camera", Path::new("/dev/zero"), "device"),
        ("--path", Path::new("/dev/zero"), "device"),
        ("--camera", big.as_path(), "more than"),
        ("--path", big.as_path(), "more than"),
    ] {
        let args =
            ["render".as_ref(), lion.as_os_str(), flag.as_ref(), file.as_os_str(), "--out".as_ref(), out.as_os_str()];
        let error = one_error(&within(dir.path(), &args, 30), flag);
        assert!(error.contains(problem), "{flag} {}: {error}", file.display());
    }
    assert!(!out.exists());
}

/// `pointblend info FILE | head`: the reader gone, the next print ends the
/// process as SIGPIPE ends a C tool, with no panic and no backtrace.
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_a_command_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let dir = test_dir();
    let mut child = pointblend(dir.path())
        .arg("info")
        .arg(model())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The reading end closed before anything is printed.
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(output.status.signal(), Some(13), "ended by SIGPIPE: {:?}, {stderr}", output.status);
}

//! The command line: exit codes, one-line errors, atomic outputs, explain and info.

mod common;

use std::process::Command;

fn pointblend() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pointblend"))
}

#[test]
fn render_writes_a_png_and_explains_its_passes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lion.png");
    let result = pointblend()
        .args(["render", common::bundled_model().to_str().unwrap(), "--size", "160x128", "--explain", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    assert!(stdout.contains("2 geometry + 1 full-screen passes"), "{stdout}");
    for pass in ["visibility", "accumulate", "normalize"] {
        assert!(stdout.contains(pass), "--explain lacks {pass}: {stdout}");
    }
    let image = image::open(&out).unwrap();
    assert_eq!((image.width(), image.height()), (160, 128));
    let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers.len(), 1, "only the PNG remains: {leftovers:?}");
}

#[test]
fn a_broken_file_fails_with_one_line_naming_it_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.ply");
    std::fs::write(&bad, b"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\nproperty float z\nend_header\n\x01\x02").unwrap();
    let out = dir.path().join("never.png");
    let render = pointblend().arg("render").arg(&bad).arg("--out").arg(&out).output().unwrap();
    let info = pointblend().arg("info").arg(&bad).output().unwrap();
    for result in [render, info] {
        assert!(!result.status.success());
        let stderr = String::from_utf8_lossy(&result.stderr);
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{stderr}");
        assert!(errors[0].contains("broken.ply"), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    assert!(!out.exists(), "no output for a failed render");
}

#[test]
fn info_says_what_was_estimated() {
    // The CGAL building (x y z, normals and a segment index per point): its
    // normals come from the file, its radii are estimated.
    let building = common::data("building.ply");
    let info = |path: &std::path::Path| {
        let result = pointblend().arg("info").arg(path).output().unwrap();
        assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
        String::from_utf8_lossy(&result.stdout).into_owned()
    };
    let stdout = info(&building);
    assert!(stdout.contains("normals:     from file"), "{stdout}");
    assert!(stdout.contains("radii:       estimated from neighbours"), "{stdout}");
    assert!(stdout.contains("segment_index"), "{stdout}");
    // The same points without their normals: both are estimated.
    let text = std::fs::read_to_string(&building).unwrap();
    let (header, body) = text.split_once("end_header\n").unwrap();
    let header: String = header
        .lines()
        .filter(|l| !l.contains(" nx") && !l.contains(" ny") && !l.contains(" nz"))
        .map(|l| format!("{l}\n"))
        .collect();
    let body: String = body
        .lines()
        .map(|l| {
            let words: Vec<&str> = l.split_whitespace().collect();
            format!("{} {} {} {}\n", words[0], words[1], words[2], words[6])
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let bare = dir.path().join("building-without-normals.ply");
    std::fs::write(&bare, format!("{header}end_header\n{body}")).unwrap();
    let stdout = info(&bare);
    assert!(stdout.contains("normals:     estimated from neighbours"), "{stdout}");
    assert!(stdout.contains("radii:       estimated from neighbours"), "{stdout}");
    assert!(stdout.contains("segment_index"), "{stdout}");
}

#[test]
fn convert_samples_a_mesh_into_a_loadable_splat_cloud() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sampled.ply");
    let result =
        pointblend().arg("convert").arg(common::bundled_mesh()).arg(&out).args(["--points", "20000"]).output().unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let (cloud, report) = pointblend::cloud::load(&out).unwrap();
    assert_eq!(cloud.len(), 20000);
    assert_eq!(report.normals, pointblend::cloud::Provenance::FromFile);
    assert_eq!(report.radii, pointblend::cloud::Provenance::FromFile);
    let header = std::fs::read(&out).unwrap();
    let header = String::from_utf8_lossy(&header[..400]);
    for p in ["x", "y", "z", "nx", "ny", "nz", "radius", "red", "green", "blue"] {
        assert!(header.contains(&format!(" {p}\n")), "{p} missing from {header}");
    }
}

#[test]
fn group_prints_the_required_json_for_every_test_scan_and_caches_it() {
    let cache = tempfile::tempdir().unwrap();
    let keys = [
        "k",
        "group_sizes",
        "max_degree",
        "avg_degree",
        "overlap_factor",
        "violations",
        "coverage",
        "seconds",
        "stage_seconds",
    ];
    for scan in common::real_scans() {
        let name = scan.display();
        let run = || {
            pointblend()
                .env("POINTBLEND_CACHE", cache.path())
                .arg("group")
                .arg(&scan)
                .args(["--group", "mgc-c0.4", "--json"])
                .output()
                .unwrap()
        };
        let first = run();
        assert!(first.status.success(), "{name}: {}", String::from_utf8_lossy(&first.stderr));
        let json: serde_json::Value = serde_json::from_slice(&first.stdout).unwrap();
        for key in keys {
            assert!(json.get(key).is_some(), "{name}: {key} missing");
        }
        let sizes: u64 = json["group_sizes"].as_array().unwrap().iter().map(|s| s.as_u64().unwrap()).sum();
        assert_eq!(sizes, json["points"].as_u64().unwrap(), "{name}: every splat in one group");
        assert_eq!(json["from_cache"], false);
        let second: serde_json::Value = serde_json::from_slice(&run().stdout).unwrap();
        assert_eq!(second["from_cache"], true, "{name}: the second run reads the cache");
        assert_eq!(second["group_sizes"], json["group_sizes"]);
    }
}

#[test]
fn environment_maps_that_cannot_be_drawn_fail_with_one_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.png");
    let venice = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/venice.exr");
    let missing = dir.path().join("missing.exr");
    let bunny = common::bundled_model();
    let cases: [(Vec<&std::ffi::OsStr>, &str); 3] = [
        // A mode that does not draw environment effects says which do.
        (
            vec!["--mode".as_ref(), "two-pass".as_ref(), "--env".as_ref(), venice.as_os_str()],
            "modes that do: alg2, tiled, reference",
        ),
        (vec!["--mode".as_ref(), "reference".as_ref(), "--env".as_ref(), missing.as_os_str()], "missing.exr"),
        (
            vec![
                "--mode".as_ref(),
                "reference".as_ref(),
                "--env".as_ref(),
                venice.as_os_str(),
                "--eta".as_ref(),
                "0".as_ref(),
            ],
            "--eta",
        ),
    ];
    for (extra, says) in cases {
        let result = pointblend().arg("render").arg(&bunny).args(extra).arg("--out").arg(&out).output().unwrap();
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(!result.status.success(), "{stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{stderr}");
        assert!(errors[0].contains(says), "{stderr}");
        assert!(!out.exists(), "no output for a failed render");
    }
}

//! `convert`'s outputs when things go wrong, and the small LAS faults its
//! inputs may carry: a full disk is one error line and no file (the las
//! crate's writer panicked when it could not close), an interrupted run
//! leaves no temporary file, an output whose extension names no written
//! format is refused; a version the las crate raises is logged naming the
//! file, two extra-bytes fields of one name stay two attributes, a scale of
//! 0 or NaN is used as 1 with a warning naming the file, and a header size
//! of 0 is refused.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use common::lidar::{self, ExtraField, tilted_grid};

fn pointblend() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_pointblend"));
    command.env("XDG_RUNTIME_DIR", std::env::temp_dir());
    command
}

fn convert(input: &Path, output: &Path) -> Output {
    pointblend().arg("convert").arg(input).arg(output).output().unwrap()
}

/// The one `error:` line of a failed run: non-zero exit, no panic, at most 3 lines on stderr.
fn one_error(output: &Output, what: &str) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{what} should fail: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(stderr.lines().count() <= 3, "{what}: more than 3 lines: {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "{what}: {stderr}");
    errors[0].to_string()
}

/// A scratch folder whose name cannot be mistaken for a leaked temporary file (`.tmpXXXX`).
fn scratch() -> tempfile::TempDir {
    tempfile::Builder::new().prefix("pointblend-convert-").tempdir().unwrap()
}

/// The names in `dir`.
fn names_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect()
}

/// A tmpfs of 64 KiB mounted on a scratch folder, unmounted when dropped.
struct SmallDisk {
    dir: tempfile::TempDir,
}

impl SmallDisk {
    /// None (the test is skipped) where mounting is not allowed.
    fn mount() -> Option<Self> {
        let dir = scratch();
        let status = Command::new("mount")
            .args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"])
            .arg(dir.path())
            .stderr(Stdio::null())
            .status();
        if !status.is_ok_and(|s| s.success()) {
            common::skip("it mounts a 64 KiB tmpfs, which needs root", "");
            return None;
        }
        Some(Self { dir })
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

#[test]
fn a_full_disk_is_one_error_line_and_leaves_no_file() {
    let inputs = scratch();
    let points = tilted_grid(200, 0.5, 0.1, [1000.0, 2000.0, 10.0]);
    let input = lidar::write(&inputs.path().join("in.laz"), &points, [1000.0, 2000.0, 0.0], Some("Amplitude"));
    let Some(disk) = SmallDisk::mount() else { return };
    for name in ["out.las", "out.laz", "out.ply", "out.copc.laz"] {
        let line = one_error(&convert(&input, &disk.dir.path().join(name)), name);
        assert!(line.contains("No space left on device"), "{name}: {line}");
        assert!(line.contains(name), "{name}: the line does not name the output: {line}");
        assert!(names_in(disk.dir.path()).is_empty(), "{name} left {:?}", names_in(disk.dir.path()));
    }
}

#[test]
fn an_interrupted_convert_leaves_no_temporary_file() {
    let inputs = scratch();
    // About 2 s of LAZ compression for the output, after loading and estimating normals.
    let points = tilted_grid(1200, 0.25, 0.1, [1000.0, 2000.0, 10.0]);
    let input = lidar::write(&inputs.path().join("big.laz"), &points, [1000.0, 2000.0, 0.0], None);
    for (signal, code) in [("TERM", 143), ("INT", 130)] {
        let out = scratch();
        let mut child = pointblend()
            .arg("convert")
            .arg(&input)
            .arg(out.path().join("out.laz"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let started = std::time::Instant::now();
        let temporary = |dir: &Path| names_in(dir).into_iter().any(|n| n.starts_with(".tmp"));
        // The output is being written once its temporary file is there (the folder's check makes
        // and deletes one first: wait for it to stay).
        let mut seen = 0;
        while seen < 3 {
            assert!(child.try_wait().unwrap().is_none(), "convert ended before it was interrupted");
            assert!(started.elapsed().as_secs() < 300, "no temporary file appeared");
            seen = if temporary(out.path()) { seen + 1 } else { 0 };
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let kill = Command::new("kill").arg(format!("-{signal}")).arg(child.id().to_string()).status().unwrap();
        assert!(kill.success());
        let status = child.wait().unwrap();
        assert!(!status.success(), "SIG{signal}: {status:?}");
        assert!(!temporary(out.path()), "SIG{signal} left {:?}", names_in(out.path()));
        assert!(!out.path().join("out.laz").exists(), "SIG{signal}: a partial output");
        assert_eq!(status.code(), Some(code), "SIG{signal}: {status:?}");
    }
}

#[test]
fn an_output_naming_no_written_format_is_refused() {
    let dir = scratch();
    let points = tilted_grid(10, 0.5, 0.1, [0.0; 3]);
    let input = lidar::write(&dir.path().join("in.las"), &points, [0.0; 3], None);
    for (name, says) in [("out.xyz", "not '.xyz'"), ("out", "no extension"), ("out.e57", "not E57")] {
        let line = one_error(&convert(&input, &dir.path().join(name)), name);
        assert!(line.contains(says), "{name}: {line}");
        assert!(line.contains("PLY (.ply), LAS (.las), LAZ (.laz), COPC (.copc.laz)"), "{name}: {line}");
        assert!(!dir.path().join(name).exists(), "{name} was written");
    }
}

/// A LAS 1.2 point format 3 file whose header says LAS 1.1, which has no colour: the las crate reads it as 1.2.
fn las11(dir: &Path) -> PathBuf {
    let path = lidar::write_las12(&dir.join("old-version.las"), &tilted_grid(10, 0.5, 0.1, [0.0; 3]));
    let mut bytes = std::fs::read(&path).unwrap();
    assert_eq!(bytes[24..26], [1, 2], "the version's bytes");
    bytes[25] = 1;
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn a_raised_version_is_logged_naming_the_file() {
    let dir = scratch();
    let file = las11(dir.path());
    let out = pointblend().arg("info").arg(&file).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| l.contains("LAS 1.1") || l.contains("las version")).collect();
    assert_eq!(lines.len(), 1, "one line about the version: {stderr}");
    assert!(lines[0].contains("old-version.las") && lines[0].contains("read as LAS 1.2"), "{}", lines[0]);
}

#[test]
fn extra_bytes_fields_of_one_name_stay_two_attributes() {
    let dir = scratch();
    let points = tilted_grid(10, 0.5, 0.1, [0.0; 3]);
    let fields = [ExtraField { name: "A", scale: None }, ExtraField { name: "A", scale: None }];
    let path = lidar::write_fields(&dir.path().join("twice.las"), &points, [0.0; 3], &fields);
    let (cloud, report) = pointblend::cloud::load(&path).unwrap();
    let column = |name: &str| {
        let values = cloud.attributes.get(name).unwrap_or_else(|| panic!("no '{name}'"));
        (0..values.len()).map(|i| values.get(i)).collect::<Vec<f64>>()
    };
    let (a, a2) = (column("A"), column("A_2"));
    // Field j of point k holds k · (j + 1): the second is twice the first, point by point.
    assert!(a.iter().zip(&a2).all(|(x, y)| *y == 2.0 * x) && a.iter().any(|&x| x > 0.0), "{a:?} {a2:?}");
    assert!(report.warnings.iter().any(|w| w.contains("'A_2'")), "{:?}", report.warnings);
}

#[test]
fn an_extra_bytes_scale_of_zero_or_nan_is_one_with_a_warning_naming_the_file() {
    let dir = scratch();
    let points = tilted_grid(10, 0.5, 0.1, [0.0; 3]);
    for (name, scale, shown) in [("zero.las", 0.0, "scale of 0;"), ("nan.las", f64::NAN, "scale of NaN;")] {
        let fields = [ExtraField { name: "Amplitude", scale: Some(scale) }];
        let path = lidar::write_fields(&dir.path().join(name), &points, [0.0; 3], &fields);
        let out = convert(&path, &dir.path().join(format!("{name}.ply")));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        let line = stderr.lines().find(|l| l.contains(shown)).unwrap_or_else(|| panic!("{name}: no warning: {stderr}"));
        assert!(line.contains(name) && line.contains("1 is used"), "{line}");
        let (cloud, _) = pointblend::cloud::load(&path).unwrap();
        let values = cloud.attributes.get("Amplitude").unwrap();
        assert!((0..values.len()).any(|i| values.get(i) > 0.0), "{name}: the raw values are kept");
    }
}

#[test]
fn a_header_size_of_zero_is_refused() {
    let dir = scratch();
    let points = tilted_grid(10, 0.5, 0.1, [0.0; 3]);
    let path = lidar::write(&dir.path().join("headless.las"), &points, [0.0; 3], None);
    let mut bytes = std::fs::read(&path).unwrap();
    assert_eq!(u16::from_le_bytes([bytes[94], bytes[95]]), 375, "the header size's bytes");
    bytes[94..96].copy_from_slice(&0u16.to_le_bytes());
    std::fs::write(&path, bytes).unwrap();
    let line = one_error(&pointblend().arg("info").arg(&path).output().unwrap(), "a header size of 0");
    assert!(line.contains("headless.las") && line.contains("0 bytes long"), "{line}");
}

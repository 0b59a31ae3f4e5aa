//! The repository holds only data it may ship: every data file it tracks
//! (binary, or of a data format; outside `docs/images`, which pointblend
//! renders) has a row in a
//! README beside it or in a folder above it, naming the file, its source and
//! its licence; and no tracked file is a copy of a scan in the shared folder,
//! which came from public source repositories.

mod common;

use std::path::{Path, PathBuf};

/// Licences a README row may name (SPDX identifiers, and the font's).
const LICENCES: [&str; 6] = ["MIT", "BSD-2-Clause", "BSD-3-Clause", "CC0-1.0", "Apache-2.0", "Bitstream Vera"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The files git tracks, relative to the root.
fn tracked_files() -> Vec<PathBuf> {
    let output =
        std::process::Command::new("git").arg("-C").arg(root()).args(["ls-files", "-z"]).output().expect("git runs");
    assert!(output.status.success(), "git ls-files: {}", String::from_utf8_lossy(&output.stderr));
    output
        .stdout
        .split(|&b| b == 0)
        .filter(|p| !p.is_empty())
        .map(|p| PathBuf::from(String::from_utf8_lossy(p).as_ref()))
        .collect()
}

/// Formats of data, text or binary (an ASCII PLY is data too).
const DATA_FORMATS: [&str; 12] = ["ply", "las", "laz", "e57", "pcd", "exr", "hdr", "nii", "npy", "obj", "ttf", "off"];

/// A data file: of a data format, or binary (a NUL byte in its first 8 KiB).
fn is_data(path: &Path) -> bool {
    if path.extension().is_some_and(|e| DATA_FORMATS.iter().any(|f| e.eq_ignore_ascii_case(f))) {
        return true;
    }
    let bytes = std::fs::read(path).unwrap_or_default();
    bytes.iter().take(8192).any(|&b| b == 0)
}

/// The README row that names `file` (relative to the root) with a licence:
/// searched in the file's folder, then each folder above it.
fn provenance_row(file: &Path) -> Option<String> {
    let mut folder = file.parent();
    while let Some(dir) = folder {
        if let Ok(text) = std::fs::read_to_string(root().join(dir).join("README.md")) {
            let name = file.strip_prefix(dir).expect("a folder above the file");
            let quoted = format!("`{}`", name.display());
            if let Some(row) = text
                .lines()
                .find(|l| l.starts_with('|') && l.contains(&quoted) && LICENCES.iter().any(|lic| l.contains(lic)))
            {
                return Some(row.to_string());
            }
        }
        folder = dir.parent();
    }
    None
}

#[test]
fn every_data_file_has_a_readme_row_with_its_source_and_licence() {
    let data: Vec<PathBuf> =
        tracked_files().into_iter().filter(|f| !f.starts_with("docs/images") && is_data(&root().join(f))).collect();
    for shipped in ["assets/lion.ply", "tests/data/building.ply", "assets/fonts/DejaVuSans.ttf"] {
        assert!(data.iter().any(|f| f.ends_with(shipped)), "{shipped} is tracked and found as data: {data:?}");
    }
    let missing: Vec<_> = data.iter().filter(|f| provenance_row(f).is_none()).collect();
    assert!(missing.is_empty(), "data files without a README row naming them, their source and licence: {missing:?}");
}

#[test]
fn the_provenance_check_finds_a_file_without_a_row() {
    // The check itself: a data file that no README names has no row.
    assert!(provenance_row(Path::new("assets/unnamed.ply")).is_none());
    assert!(provenance_row(Path::new("assets/lion.ply")).is_some());
    assert!(provenance_row(Path::new("tests/data/env/sky.exr")).is_some());
}

/// Every file under `dir`, recursively.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        if path.is_dir() {
            out.extend(files_under(&path));
        } else {
            out.push(path);
        }
    }
    out
}

#[test]
fn no_tracked_file_is_a_copy_of_a_shared_scan() {
    let Some(sources) = common::shared_data("SOURCES.md") else { return };
    let shared: Vec<(PathBuf, Vec<u8>)> = files_under(sources.parent().unwrap())
        .into_iter()
        // The PLY scans came from source repositories (b9_training.ply also ships in a registry package).
        .filter(|p| p.extension().is_some_and(|e| e == "ply") && !p.ends_with("b9_training.ply"))
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap();
            (p, bytes)
        })
        .collect();
    assert!(!shared.is_empty());
    for file in tracked_files() {
        let Ok(bytes) = std::fs::read(root().join(&file)) else { continue };
        for (scan, scan_bytes) in &shared {
            assert!(bytes != *scan_bytes, "{} is a copy of {}", file.display(), scan.display());
        }
    }
}

//! The disk cache (`--disk-cache DIR`) as a folder others may write to: a
//! link planted at a chunk's name or at the source's folder is never
//! written through, a chunk whose bytes were changed is dropped and fetched
//! again (the frame is the same), and a cache that cannot be written (a
//! regular file, a folder inside one, a read-only folder) is said once, not
//! once per chunk, while the frame is still drawn.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use pointblend::cloud::LoadOptions;
use pointblend::copc::{CopcStream, StreamOptions};
use pointblend::frame::Camera;
use pointblend::lod::SelectOptions;

/// A folder with the shared sample as `tile.copc.laz`, and that file.
fn sample() -> Option<(tempfile::TempDir, PathBuf)> {
    let sample = common::shared_data("lidar/1.2-with-color.copc.laz")?;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("tile.copc.laz");
    std::fs::copy(sample, &file).unwrap();
    Some((dir, file))
}

/// Every node of `file` streamed through the disk cache `cache`: the frame's positions and the stream's failures.
fn every_node(file: &Path, cache: &Path) -> (Vec<[f32; 3]>, usize) {
    let options = StreamOptions { cache_bytes: 1 << 30, disk_cache: Some(cache.to_path_buf()), ..Default::default() };
    let mut s = CopcStream::open(&file.display().to_string(), options).unwrap();
    let camera = Camera::default_for(&s.bounds_cloud(), 1.0);
    let every = SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 };
    let frame = s.frame(&camera, (64, 64), every, &LoadOptions::default()).unwrap();
    (frame.cloud.positions.iter().map(|p| p.to_array()).collect(), s.stats().failed)
}

/// The cache's one source folder and the files in it, sorted.
fn cached(cache: &Path) -> (PathBuf, Vec<PathBuf>) {
    let folders: Vec<PathBuf> = std::fs::read_dir(cache).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(folders.len(), 1, "{folders:?}");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&folders[0]).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    assert!(files.len() > 1, "the chunks were kept");
    (folders[0].clone(), files)
}

#[cfg(unix)]
#[test]
fn links_planted_in_the_cache_are_never_written_through() {
    let (dir, file) = require!(sample());
    let cache = dir.path().join("chunks");
    let (first, _) = every_node(&file, &cache);
    let victim = dir.path().join("victim.txt");
    std::fs::write(&victim, b"precious").unwrap();
    // A link at every chunk's name.
    let (folder, chunks) = cached(&cache);
    for chunk in &chunks {
        std::fs::remove_file(chunk).unwrap();
        std::os::unix::fs::symlink(&victim, chunk).unwrap();
    }
    let (second, failed) = every_node(&file, &cache);
    assert_eq!(std::fs::read(&victim).unwrap(), b"precious", "a chunk was written through a link");
    assert!(second == first && failed == 0, "the frame changed ({failed} nodes failed)");
    for chunk in &chunks {
        let meta = std::fs::symlink_metadata(chunk);
        assert!(meta.is_ok_and(|m| m.is_file()), "{} is not a plain file again", chunk.display());
    }
    // The source's folder itself a link to another folder: nothing lands there.
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    std::fs::remove_dir_all(&folder).unwrap();
    std::os::unix::fs::symlink(&elsewhere, &folder).unwrap();
    let (third, failed) = every_node(&file, &cache);
    assert!(third == first && failed == 0, "the frame changed ({failed} nodes failed)");
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 0, "chunks were written through the folder's link");
}

#[test]
fn a_changed_chunk_is_fetched_again() {
    let (dir, file) = require!(sample());
    let cache = dir.path().join("chunks");
    let (first, _) = every_node(&file, &cache);
    // The largest chunk, 64 bytes in its middle inverted (its length kept).
    let (_, chunks) = cached(&cache);
    let largest = chunks.iter().max_by_key(|c| std::fs::metadata(c).unwrap().len()).unwrap();
    let mut bytes = std::fs::read(largest).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle - 32..middle + 32].iter_mut().for_each(|b| *b = !*b);
    std::fs::write(largest, &bytes).unwrap();
    let (second, failed) = every_node(&file, &cache);
    assert_eq!(failed, 0, "the changed chunk was decoded");
    assert!(second == first, "the frame changed");
    assert!(std::fs::read(largest).unwrap() != bytes, "the changed chunk was kept");
}

/// `render FILE --disk-cache CACHE` on the CPU, at a size that selects some 50 nodes.
fn render(dir: &Path, file: &Path, cache: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("render")
        .arg(file)
        .args(["--mode", "reference", "--size", "512x512", "--disk-cache"])
        .arg(cache)
        .arg("--out")
        .arg(dir.join("out.png"))
        .output()
        .expect("pointblend runs")
}

#[test]
fn a_cache_that_cannot_be_written_is_said_once() {
    let (dir, file) = require!(sample());
    let regular = dir.path().join("a-file");
    std::fs::write(&regular, b"not a folder").unwrap();
    let mut caches = vec![regular.clone(), regular.join("chunks")];
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let locked = dir.path().join("read-only");
        std::fs::create_dir(&locked).unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o500)).unwrap();
        if std::fs::write(locked.join("probe"), b"").is_ok() {
            eprintln!("skipped the read-only folder case: this user writes into read-only folders (root)");
        } else {
            caches.push(locked);
        }
    }
    for cache in caches {
        let output = render(dir.path(), &file, &cache);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{}: {stderr}", cache.display());
        let said = stderr.lines().filter(|l| l.contains("--disk-cache")).count();
        assert_eq!(said, 1, "{}: {said} lines about the cache: {stderr}", cache.display());
    }
    assert_eq!(std::fs::read(&regular).unwrap(), b"not a folder");
}

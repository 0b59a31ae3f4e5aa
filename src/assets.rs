//! The bundled files (`assets/`): the lion, the demo scene, the lidar
//! demo and the Venice map, found at run time rather than compiled in as
//! paths, so that a binary copied elsewhere finds them too.
//!
//! The folder is looked for in this order: `$POINTBLEND_ASSETS`; `assets/`
//! beside the binary or in any folder above it (a binary copied to a
//! clone's root, or left in `target/release/`); and the source tree the
//! binary was built from. When none holds the file, the error names it and
//! every place looked in, in one line.

use std::path::{Path, PathBuf};

/// The bundled lion scan.
pub const BUNDLED_MODEL: &str = "lion.ply";
/// The demo scene: the lion at opacity 0.5 with opaque balls inside and
/// around it. `pointblend view` opens it when given no file.
pub const DEMO_SCENE: &str = "demo.toml";
/// The lidar demo: an airborne tile coloured by class, its vegetation translucent.
pub const LIDAR_DEMO: &str = "lidar-classes.toml";
/// The environment map the viewer offers first.
pub const BUNDLED_ENVIRONMENT: &str = "venice.exr";

/// The folders that may hold the assets, in the order they are tried.
fn candidates() -> Vec<PathBuf> {
    let mut folders = Vec::new();
    if let Some(dir) = std::env::var_os("POINTBLEND_ASSETS").filter(|d| !d.is_empty()) {
        folders.push(PathBuf::from(dir));
    }
    if let Some(binary) = std::env::current_exe().ok().and_then(|b| b.canonicalize().ok()) {
        folders.extend(binary.ancestors().skip(1).map(|dir| dir.join("assets")));
    }
    folders.push(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"));
    folders
}

/// The bundled file `name` (e.g. [`DEMO_SCENE`]), or why it cannot be found.
pub fn path(name: &str) -> Result<PathBuf, String> {
    path_in(name, &candidates())
}

/// `name` in the first of `folders` that holds it, or why none does.
fn path_in(name: &str, folders: &[PathBuf]) -> Result<PathBuf, String> {
    if let Some(found) = folders.iter().map(|dir| dir.join(name)).find(|p| p.is_file()) {
        return Ok(found);
    }
    let looked: Vec<String> = folders.iter().map(|d| d.display().to_string()).collect();
    Err(format!(
        "the bundled file {name} is missing: it is in no assets folder ({}); copy the repository's assets/ beside the binary or set POINTBLEND_ASSETS",
        looked.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_bundled_file_is_found() {
        for name in [BUNDLED_MODEL, DEMO_SCENE, LIDAR_DEMO, BUNDLED_ENVIRONMENT] {
            assert!(path(name).unwrap().is_file(), "{name}");
        }
    }

    #[test]
    fn the_first_folder_that_holds_the_file_wins_and_the_binarys_come_before_the_source_tree() {
        let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        std::fs::write(b.path().join("x.toml"), "b").unwrap();
        let folders = [a.path().to_path_buf(), b.path().to_path_buf()];
        assert_eq!(path_in("x.toml", &folders).unwrap(), b.path().join("x.toml"));
        std::fs::write(a.path().join("x.toml"), "a").unwrap();
        assert_eq!(path_in("x.toml", &folders).unwrap(), a.path().join("x.toml"));
        let order = candidates();
        let binary = std::env::current_exe().unwrap().canonicalize().unwrap();
        let beside = binary.parent().unwrap().join("assets");
        let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
        let at = |p: &Path| order.iter().position(|c| c == p).unwrap();
        assert!(at(&beside) < at(&source), "{order:?}");
    }

    #[test]
    fn a_missing_file_names_itself_and_the_folders_looked_in() {
        let error = path("no-such-asset.ply").unwrap_err();
        assert!(error.contains("no-such-asset.ply") && error.contains("POINTBLEND_ASSETS"), "{error}");
        assert!(error.contains(env!("CARGO_MANIFEST_DIR")), "{error}");
        assert!(!error.contains('\n'));
    }
}

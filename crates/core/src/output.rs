//! Writing output files safely: checked before any work starts, written to a
//! temporary file beside the target, then renamed over it, so a failed or
//! interrupted run never leaves a partial file.
//!
//! The rename replaces only regular files. A symbolic link is followed to
//! the file it names (the link stays a link); a device, FIFO, socket or
//! folder at the path is refused, so `--out /dev/full` is an error and not a
//! PNG where the device was, and so is a read-only file. A replaced file
//! keeps its permissions. Missing parent folders are created.
//!
//! [`same_file`] tells whether two paths name one file however they are
//! spelt (`..`, `.`, absolute or relative, symbolic links), so a command can
//! refuse an output that would overwrite its input or another output.
//!
//! Every temporary file is a [`Temporary`], listed while it exists, so that
//! a run ended by a signal removes them ([`remove_temporaries`]).

use std::io::Write;
use std::path::{Path, PathBuf};

mod temporary;

pub use temporary::{Temporary, remove_temporaries};

/// Most symbolic links followed before a path is called a loop.
const MAX_LINKS: usize = 40;

/// Where writing to `path` really goes: symbolic links followed, the target
/// checked to be a regular file or absent, its folder created. Errors name
/// the problem; the caller adds the path.
pub fn prepare(path: &Path) -> std::io::Result<PathBuf> {
    let mut target = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&target) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = std::fs::read_link(&target)?;
                target = match target.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            Ok(meta) if meta.is_file() && meta.permissions().readonly() => {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::PermissionDenied,
                    "it is read-only; refusing to replace it",
                ));
            }
            Ok(meta) if meta.is_file() => return ensure_writable_folder(target),
            Ok(meta) => {
                let what = if meta.is_dir() { "a folder" } else { "a device, FIFO or socket, not a regular file" };
                return Err(std::io::Error::other(format!("it is {what}; refusing to replace it")));
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return ensure_writable_folder(target),
            Err(e) => return Err(e),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// Creates the folder of `target` and checks that a file can be made in it.
fn ensure_writable_folder(target: PathBuf) -> std::io::Result<PathBuf> {
    let dir = folder_of(&target);
    std::fs::create_dir_all(dir)?;
    // The temporary file's own name means nothing to the user: say only where and why.
    Temporary::new_in(dir).map_err(|e| {
        std::io::Error::new(e.kind(), format!("cannot create a file in {}: {}", dir.display(), e.kind()))
    })?;
    Ok(target)
}

/// The folder a file at `path` lives in (`.` for a bare name).
pub fn folder_of(path: &Path) -> &Path {
    path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

/// Writes `bytes` to `path` atomically (see the module doc).
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let target = prepare(path)?;
    let mut tmp = Temporary::new_in(folder_of(&target))?;
    tmp.as_file_mut().write_all(bytes)?;
    tmp.as_file_mut().flush()?;
    match std::fs::metadata(&target) {
        // A replaced file keeps its permissions.
        Ok(old) => tmp.as_file().set_permissions(old.permissions())?,
        Err(_) => make_readable(tmp.as_file())?,
    }
    tmp.persist(&target)
}

/// Whether `a` and `b` name the same file: the same device and inode where
/// both exist (links followed), else the same absolute path once the
/// existing part of each is resolved.
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (identity(a), identity(b)) {
        (Some(x), Some(y)) => x == y,
        (Some(_), None) | (None, Some(_)) => false,
        (None, None) => resolved(a).is_some_and(|x| resolved(b).is_some_and(|y| x == y)),
    }
}

/// The file's device and inode (Unix), or its canonical path elsewhere.
#[cfg(unix)]
fn identity(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn identity(path: &Path) -> Option<PathBuf> {
    std::fs::canonicalize(path).ok()
}

/// An absolute path for a file that need not exist: its longest existing
/// part resolved (links followed), the rest appended with `.` and `..` applied.
fn resolved(path: &Path) -> Option<PathBuf> {
    let mut existing = std::path::absolute(path).ok()?;
    let mut rest = Vec::new();
    let mut base = loop {
        if let Ok(real) = std::fs::canonicalize(&existing) {
            break real;
        }
        rest.push(existing.components().next_back()?.as_os_str().to_owned());
        if !existing.pop() {
            return None;
        }
    };
    for part in rest.iter().rev() {
        match part.to_str() {
            Some(".") => {}
            Some("..") => {
                base.pop();
            }
            _ => base.push(part),
        }
    }
    Some(base)
}

/// The file stem of `path` made safe for output file names (`[A-Za-z0-9-_]`), or `model`.
pub fn safe_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| {
            s.to_string_lossy().chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' { c } else { '_' }).collect()
        })
        .unwrap_or_else(|| "model".into())
}

/// Image formats an output path may name, by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Jpeg,
}

impl ImageFormat {
    /// The format `path`'s extension asks for (case-insensitive), or an error
    /// naming the extensions that are written.
    pub fn of(path: &Path) -> Result<Self, String> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
        match ext.as_str() {
            "png" => Ok(ImageFormat::Png),
            "jpg" | "jpeg" => Ok(ImageFormat::Jpeg),
            "" => Err("images are written as .png or .jpg, and this name has no extension".into()),
            _ => Err(format!("images are written as .png or .jpg, not '.{ext}'")),
        }
    }
}

/// Encodes `image` as its path's extension says (PNG, or JPEG at quality 95)
/// and writes it atomically.
pub fn save_image(image: &image::RgbaImage, path: &Path) -> std::io::Result<()> {
    let format = ImageFormat::of(path).map_err(std::io::Error::other)?;
    let mut bytes = Vec::new();
    let mut cursor = std::io::Cursor::new(&mut bytes);
    match format {
        ImageFormat::Png => image.write_to(&mut cursor, image::ImageFormat::Png),
        ImageFormat::Jpeg => {
            let rgb = image::DynamicImage::ImageRgba8(image.clone()).to_rgb8();
            image::codecs::jpeg::JpegEncoder::new_with_quality(&mut cursor, 95).encode_image(&rgb)
        }
    }
    .map_err(std::io::Error::other)?;
    write_atomically(path, &bytes)
}

/// Encodes `image` as PNG and writes it to `path` atomically.
pub fn save_png(image: &image::RgbaImage, path: &Path) -> std::io::Result<()> {
    let mut png = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).map_err(std::io::Error::other)?;
    write_atomically(path, &png)
}

/// Gives a temporary file the usual permissions of an output file (rw-r--r--).
pub fn make_readable(file: &std::fs::File) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        file.set_permissions(std::fs::Permissions::from_mode(0o644))?;
    }
    #[cfg(not(unix))]
    let _ = file;
    Ok(())
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::FileTypeExt;

    #[test]
    fn devices_and_folders_are_refused_and_links_are_followed() {
        let dir = tempfile::tempdir().unwrap();
        assert!(write_atomically(Path::new("/dev/null"), b"x").is_err());
        assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device(), "/dev/null is left alone");
        assert!(write_atomically(dir.path(), b"x").is_err());
        let real = dir.path().join("real.txt");
        std::fs::write(&real, b"old").unwrap();
        let link = dir.path().join("link.txt");
        std::os::unix::fs::symlink("real.txt", &link).unwrap();
        write_atomically(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays a link");
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        let nested = dir.path().join("a/b/c.txt");
        write_atomically(&nested, b"made").unwrap();
        assert_eq!(std::fs::read(&nested).unwrap(), b"made");
    }

    #[test]
    fn read_only_files_are_refused_and_a_replaced_file_keeps_its_mode() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let read_only = dir.path().join("ro.png");
        std::fs::write(&read_only, b"old").unwrap();
        std::fs::set_permissions(&read_only, std::fs::Permissions::from_mode(0o444)).unwrap();
        let error = write_atomically(&read_only, b"new").unwrap_err();
        assert!(error.to_string().contains("read-only"), "{error}");
        assert_eq!(std::fs::read(&read_only).unwrap(), b"old");
        let private = dir.path().join("private.png");
        std::fs::write(&private, b"old").unwrap();
        std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_atomically(&private, b"new").unwrap();
        assert_eq!(std::fs::read(&private).unwrap(), b"new");
        assert_eq!(std::fs::metadata(&private).unwrap().permissions().mode() & 0o777, 0o600);
    }

    #[test]
    fn same_file_sees_through_spellings_and_links() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in/self.ply");
        std::fs::create_dir_all(input.parent().unwrap()).unwrap();
        std::fs::write(&input, b"ply").unwrap();
        let dotted = dir.path().join("in/../in/./self.ply");
        assert!(same_file(&input, &dotted));
        let link = dir.path().join("link.ply");
        std::os::unix::fs::symlink(&input, &link).unwrap();
        assert!(same_file(&input, &link));
        assert!(!same_file(&input, &dir.path().join("in/other.ply")));
        // Two outputs that do not exist yet.
        let a = dir.path().join("out/x.png");
        assert!(same_file(&a, &dir.path().join("in/../out/x.png")));
        assert!(!same_file(&a, &dir.path().join("out/y.png")));
    }
}

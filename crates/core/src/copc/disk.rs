//! `--disk-cache DIR`: the chunks fetched, kept one file per node under
//! `DIR/<source id>/`, and read from there next time.
//!
//! The folder may be shared or planted, so nothing here follows a link or
//! trusts a file: a chunk is written to a new temporary file (created, never
//! opened if it exists) in a folder that is checked to be a real folder, not
//! a link, and renamed over its name (a rename replaces a link at that name,
//! never what the link names). A chunk is read only from a regular file that
//! is not a link, opened and checked to be that same file, whose header
//! names the node's chunk (its offset and size in the source) and whose
//! checksum matches its bytes; anything else is removed and the chunk
//! fetched again. The checksum (FNV-1a) finds damage, not forgery: whoever
//! may write to DIR can still make a chunk that passes it.
//!
//! The first failure to write (DIR a file, a folder that cannot be written,
//! a full disk) is logged once, and no chunk of the source is written after it.

use std::fs::File;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use crate::hash::fnv1a;

/// What a cached chunk starts with: a tag, the chunk's offset and size in
/// the source, and the FNV-1a of its bytes (all little-endian).
const MAGIC: &[u8; 8] = b"PBCHUNK1";
const HEADER: usize = 32;

/// One source's folder of cached chunks.
pub(crate) struct DiskCache {
    /// `DIR` as given, for messages.
    dir: PathBuf,
    folder: PathBuf,
    /// A write failed: no more are tried.
    broken: AtomicBool,
}

/// Why a cached chunk was not used (each is then fetched again).
#[derive(Debug, PartialEq)]
pub(crate) enum Miss {
    Absent,
    /// A link, a folder or another kind of file at the chunk's name.
    NotAFile,
    /// The file is not what this node's chunk would be: short, another
    /// node's, or its bytes fail their checksum.
    Corrupt,
}

impl DiskCache {
    /// `dir/<id>`, `id` naming the source's content (see [`source_id`]).
    pub fn new(dir: &Path, id: u64) -> Self {
        Self { dir: dir.to_path_buf(), folder: dir.join(format!("{id:016x}")), broken: AtomicBool::new(false) }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.folder.join(format!("{name}.chunk"))
    }

    /// The chunk `name` (a node key), if a sound copy of the `size` bytes at `offset` is kept.
    pub fn read(&self, name: &str, offset: u64, size: u64) -> Result<Vec<u8>, Miss> {
        // Nothing is read from, or removed in, a source folder that is a link (or absent).
        if !std::fs::symlink_metadata(&self.folder).is_ok_and(|m| m.is_dir()) {
            return Err(Miss::Absent);
        }
        let path = self.path(name);
        let result = read_checked(&path, offset, size);
        if matches!(result, Err(Miss::Corrupt | Miss::NotAFile)) {
            // Unlinks the name only (a link is removed, not what it names); a folder stays.
            let _ = std::fs::remove_file(&path);
        }
        result
    }

    /// Keeps the chunk `name`, the `bytes` at `offset` in the source; the
    /// first failure is logged (once), and stops the writes that follow.
    pub fn keep(&self, name: &str, offset: u64, bytes: &[u8]) {
        if self.broken.load(Ordering::Relaxed) {
            return;
        }
        if let Err(e) = self.write(name, offset, bytes) {
            if !self.broken.swap(true, Ordering::Relaxed) {
                crate::progress::warn_once(format!(
                    "--disk-cache {}: cannot keep the chunks fetched ({e}); they are fetched again next time",
                    self.dir.display()
                ));
            }
        }
    }

    /// Writes the chunk `name`, the `bytes` at `offset` in the source.
    fn write(&self, name: &str, offset: u64, bytes: &[u8]) -> std::io::Result<()> {
        self.ensure_folder()?;
        let mut tmp = tempfile::Builder::new().prefix(".chunk-").tempfile_in(&self.folder)?;
        let mut header = [0u8; HEADER];
        header[..8].copy_from_slice(MAGIC);
        header[8..16].copy_from_slice(&offset.to_le_bytes());
        header[16..24].copy_from_slice(&(bytes.len() as u64).to_le_bytes());
        header[24..32].copy_from_slice(&fnv1a(crate::hash::FNV_OFFSET, bytes).to_le_bytes());
        tmp.write_all(&header)?;
        tmp.write_all(bytes)?;
        tmp.flush()?;
        // rename(2): whatever is at the name (a file, a planted link) is replaced, never written through.
        tmp.persist(self.path(name)).map_err(|e| e.error)?;
        Ok(())
    }

    /// Creates the source's folder (owner-only on Unix) and checks that it is a folder, not a link.
    fn ensure_folder(&self) -> std::io::Result<()> {
        if let Some(dir) = self.folder.parent() {
            // `DIR` itself is the user's choice and may be a link.
            std::fs::create_dir_all(dir)?;
        }
        let mut builder = std::fs::DirBuilder::new();
        #[cfg(unix)]
        std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
        match builder.create(&self.folder) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
        let meta = std::fs::symlink_metadata(&self.folder)?;
        if !meta.is_dir() {
            return Err(std::io::Error::other(format!(
                "{} is a link or a file, not a folder; refusing to write through it",
                self.folder.display()
            )));
        }
        Ok(())
    }
}

/// The cached chunk at `path`, checked (see the module doc).
fn read_checked(path: &Path, offset: u64, size: u64) -> Result<Vec<u8>, Miss> {
    let link = match std::fs::symlink_metadata(path) {
        Ok(meta) => meta,
        Err(e) if matches!(e.kind(), std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory) => {
            return Err(Miss::Absent);
        }
        Err(_) => return Err(Miss::NotAFile),
    };
    if !link.file_type().is_file() {
        return Err(Miss::NotAFile);
    }
    if link.len() != HEADER as u64 + size {
        return Err(Miss::Corrupt);
    }
    let file = File::open(path).map_err(|_| Miss::NotAFile)?;
    // The name may have been swapped for a link between the look and the open.
    let opened = file.metadata().map_err(|_| Miss::NotAFile)?;
    if !same_file(&link, &opened) {
        return Err(Miss::NotAFile);
    }
    let mut bytes = Vec::with_capacity(HEADER + size as usize);
    (&file).take(HEADER as u64 + size + 1).read_to_end(&mut bytes).map_err(|_| Miss::Corrupt)?;
    if bytes.len() != HEADER + size as usize || &bytes[..8] != MAGIC {
        return Err(Miss::Corrupt);
    }
    let word = |i: usize| u64::from_le_bytes(bytes[i..i + 8].try_into().expect("eight bytes"));
    let (at, len, sum) = (word(8), word(16), word(24));
    let chunk = bytes.split_off(HEADER);
    if at != offset || len != size || fnv1a(crate::hash::FNV_OFFSET, &chunk) != sum {
        return Err(Miss::Corrupt);
    }
    Ok(chunk)
}

#[cfg(unix)]
fn same_file(a: &std::fs::Metadata, b: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_file(a: &std::fs::Metadata, b: &std::fs::Metadata) -> bool {
    a.len() == b.len() && b.is_file()
}

/// What names a source's content for the cache: where it is (a URL without
/// its user and password, its query kept: two queries may be two files),
/// its length, and its root hierarchy page (a file rewritten in place at
/// the same length gets a new page, so a new folder).
pub(crate) fn source_id(identity: &str, len: u64, root_page: &[u8]) -> u64 {
    let h = fnv1a(crate::hash::FNV_OFFSET, identity.as_bytes());
    fnv1a(fnv1a(h, &len.to_le_bytes()), root_page)
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn a_chunk_round_trips_and_a_corrupt_or_foreign_one_is_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let cache = DiskCache::new(dir.path(), 7);
        assert_eq!(cache.read("0-0-0-0", 100, 3), Err(Miss::Absent));
        cache.write("0-0-0-0", 100, b"abc").unwrap();
        assert_eq!(cache.read("0-0-0-0", 100, 3).unwrap(), b"abc");
        // Another node's chunk (its offset), then a flipped byte: both are misses, and the file goes.
        assert_eq!(cache.read("0-0-0-0", 200, 3), Err(Miss::Corrupt));
        cache.write("0-0-0-0", 100, b"abc").unwrap();
        let path = cache.path("0-0-0-0");
        let mut bytes = std::fs::read(&path).unwrap();
        *bytes.last_mut().unwrap() ^= 1;
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(cache.read("0-0-0-0", 100, 3), Err(Miss::Corrupt));
        assert!(!path.exists(), "a corrupt chunk is removed");
    }

    #[test]
    fn links_are_never_written_through_or_read() {
        let dir = tempfile::tempdir().unwrap();
        let victim = dir.path().join("victim.txt");
        std::fs::write(&victim, b"precious").unwrap();
        let cache = DiskCache::new(&dir.path().join("cache"), 7);
        // A link planted at a chunk's name: written over as a name, the victim untouched.
        std::fs::create_dir_all(&cache.folder).unwrap();
        std::os::unix::fs::symlink(&victim, cache.path("0-0-0-0")).unwrap();
        assert_eq!(cache.read("0-0-0-0", 0, 8), Err(Miss::NotAFile));
        std::os::unix::fs::symlink(&victim, cache.path("1-0-0-0")).unwrap();
        cache.write("1-0-0-0", 0, b"chunk").unwrap();
        assert_eq!(std::fs::read(&victim).unwrap(), b"precious");
        assert!(!std::fs::symlink_metadata(cache.path("1-0-0-0")).unwrap().file_type().is_symlink());
        // The source's folder itself a link: refused.
        let elsewhere = dir.path().join("elsewhere");
        std::fs::create_dir(&elsewhere).unwrap();
        let linked = DiskCache::new(&dir.path().join("cache"), 8);
        std::os::unix::fs::symlink(&elsewhere, &linked.folder).unwrap();
        assert!(linked.write("0-0-0-0", 0, b"x").is_err());
        assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 0);
    }
}

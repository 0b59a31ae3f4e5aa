//! Temporary files that outputs are written to before they are renamed
//! over their targets, listed while they exist so that an interrupted run
//! can remove them.
//!
//! A [`Temporary`] is a `tempfile::NamedTempFile` whose path is added to a
//! process-wide list when it is made and taken off it when it is persisted
//! (renamed to its target) or dropped (deleted). A SIGINT or SIGTERM ends the
//! process without running destructors, which left a hidden `.tmpXXXXXX` of
//! up to the output's size beside the target; the command line's signal
//! handler calls [`remove_temporaries`] before it exits. The list's lock is
//! held while a file is renamed or deleted, so the handler never removes a
//! file that has just become an output, nor misses one being made.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The paths of the temporary files that exist now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A listed temporary file (see the module doc).
#[derive(Debug)]
pub struct Temporary {
    /// None once persisted or deleted.
    file: Option<tempfile::NamedTempFile>,
}

impl Temporary {
    /// A temporary file in `dir`, where its target will be.
    pub fn new_in(dir: &Path) -> io::Result<Self> {
        Self::listed(|| tempfile::NamedTempFile::new_in(dir))
    }

    /// A temporary file in the system's temporary folder whose name ends in
    /// `suffix` (an intermediate file, never renamed).
    pub fn with_suffix(suffix: &str) -> io::Result<Self> {
        Self::listed(|| tempfile::Builder::new().suffix(suffix).tempfile())
    }

    /// [`Self::with_suffix`], its name starting with `prefix`: what messages
    /// about the file's contents show (`autzen-slab-…las`).
    pub fn named(prefix: &str, suffix: &str) -> io::Result<Self> {
        Self::listed(|| tempfile::Builder::new().prefix(prefix).suffix(suffix).tempfile())
    }

    fn listed(make: impl FnOnce() -> io::Result<tempfile::NamedTempFile>) -> io::Result<Self> {
        let mut live = live();
        let file = make()?;
        live.push(file.path().to_path_buf());
        Ok(Self { file: Some(file) })
    }

    fn inner(&self) -> &tempfile::NamedTempFile {
        self.file.as_ref().expect("a temporary file is there until persisted or dropped")
    }

    pub fn path(&self) -> &Path {
        self.inner().path()
    }

    pub fn as_file(&self) -> &std::fs::File {
        self.inner().as_file()
    }

    pub fn as_file_mut(&mut self) -> &mut std::fs::File {
        self.file.as_mut().expect("a temporary file is there until persisted or dropped").as_file_mut()
    }

    /// A second handle on the file, for writers that take theirs by value.
    pub fn reopen(&self) -> io::Result<std::fs::File> {
        self.inner().reopen()
    }

    /// Renames the file to `target` and takes it off the list.
    pub fn persist(mut self, target: &Path) -> io::Result<()> {
        let mut live = live();
        let file = self.file.take().expect("a temporary file is there until persisted or dropped");
        let path = file.path().to_path_buf();
        let result = match file.persist(target) {
            Ok(_) => Ok(()),
            // Dropping the returned file deletes it.
            Err(e) => Err(e.error),
        };
        live.retain(|p| *p != path);
        result
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if let Some(file) = self.file.take() {
            let mut live = live();
            let path = file.path().to_path_buf();
            drop(file);
            live.retain(|p| *p != path);
        }
    }
}

/// Deletes every listed temporary file, for a handler of a signal that
/// ends the process next; the list stays locked, so no file is made or
/// renamed after. Returns how many were deleted.
pub fn remove_temporaries() -> usize {
    let mut live = live();
    let removed = live.iter().filter(|path| std::fs::remove_file(path).is_ok()).count();
    live.clear();
    // Held until the process exits: a writer that would persist or make a file waits.
    std::mem::forget(live);
    removed
}

#[cfg(test)]
mod tests {
    use super::*;

    fn listed(path: &Path) -> bool {
        live().iter().any(|p| p == path)
    }

    #[test]
    fn a_temporary_is_listed_until_persisted_or_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let kept = Temporary::new_in(dir.path()).unwrap();
        let dropped = Temporary::new_in(dir.path()).unwrap();
        let (kept_path, dropped_path) = (kept.path().to_path_buf(), dropped.path().to_path_buf());
        assert!(listed(&kept_path) && listed(&dropped_path));
        let target = dir.path().join("out.bin");
        kept.persist(&target).unwrap();
        assert!(target.is_file() && !listed(&kept_path));
        drop(dropped);
        assert!(!dropped_path.exists() && !listed(&dropped_path));
    }
}

//! Opening input files: only regular files (links followed), so that a
//! named pipe cannot block a reader forever and a device (`/dev/zero`,
//! `/dev/urandom`) cannot be read until memory runs out; and small files
//! (sidecars, views files, scene files) read whole only up to a bound.
//!
//! Every reader opens its file through [`open`] or [`read`]; the error
//! says what the path is instead ("a named pipe", "a folder", "a device").

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// The most bytes a text file of settings (a sidecar, a views file, a scene
/// file) may hold: far beyond any real one, far below what would hurt.
pub const MAX_SETTINGS_BYTES: u64 = 16 << 20;

/// What a path that is not a regular file is, in words.
fn kind_of(metadata: &std::fs::Metadata) -> &'static str {
    let kind = metadata.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a named pipe";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() { "a folder" } else { "not a regular file" }
}

/// The size of `path` when it is a regular file (after links); an error
/// naming what it is otherwise.
pub fn regular_size(path: &Path) -> io::Result<u64> {
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        let kind = kind_of(&metadata);
        return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("{kind}, not a file to read")));
    }
    Ok(metadata.len())
}

/// Opens `path` for reading if it is a regular file, with its size.
pub fn open(path: &Path) -> io::Result<(File, u64)> {
    let size = regular_size(path)?;
    Ok((File::open(path)?, size))
}

/// Reads the regular file `path` whole, refusing one larger than `limit` bytes.
pub fn read(path: &Path, limit: Option<u64>) -> io::Result<Vec<u8>> {
    let (file, size) = open(path)?;
    if let Some(limit) = limit.filter(|l| size > *l) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("{size} bytes, more than the {limit} such a file may hold"),
        ));
    }
    // The file may grow while it is read: never take more than its size said (or the limit).
    let cap = limit.unwrap_or(size).min(size);
    let mut bytes = Vec::with_capacity(cap as usize);
    file.take(cap).read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// [`read`] as text, for a settings file (at most [`MAX_SETTINGS_BYTES`]).
pub fn read_settings(path: &Path) -> io::Result<String> {
    let bytes = read(path, Some(MAX_SETTINGS_BYTES))?;
    String::from_utf8(bytes).map_err(|_| io::Error::new(io::ErrorKind::InvalidData, "not UTF-8 text"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_and_devices_are_refused_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let error = read(dir.path(), None).unwrap_err();
        assert!(error.to_string().contains("a folder"), "{error}");
        #[cfg(unix)]
        {
            let error = read(Path::new("/dev/zero"), None).unwrap_err();
            assert!(error.to_string().contains("a device"), "{error}");
        }
    }

    #[test]
    fn a_file_over_the_limit_is_refused_and_one_under_it_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.json");
        std::fs::write(&path, b"0123456789").unwrap();
        assert_eq!(read(&path, Some(10)).unwrap(), b"0123456789");
        assert!(read(&path, Some(9)).unwrap_err().to_string().contains("10 bytes"));
    }
}

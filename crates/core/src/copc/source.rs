//! Where a streamed file's bytes come from: a local file (positioned reads)
//! or an HTTP(S) server ([`super::http`], range requests). Each source counts
//! the bytes and requests it served, so tests and `bench` can say what a
//! view cost.

use std::fs::File;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use super::CopcError;

/// Byte ranges of one file, read from several threads at once.
pub trait ByteSource: Send + Sync {
    /// What users call it (the path or URL), for messages: a URL's user,
    /// password and query values masked ([`super::redact::shown`]).
    fn name(&self) -> &str;
    /// What identifies the file for caches, never shown: the name, unless
    /// that masks part of it (a URL without its user and password).
    fn identity(&self) -> &str {
        self.name()
    }
    /// The file's length in bytes.
    fn len(&self) -> u64;
    /// `len` bytes from `offset`; exactly that many, or an error naming the
    /// source (a range past the end is an error, never a short answer).
    fn read(&self, offset: u64, len: u64) -> Result<Vec<u8>, CopcError>;
    /// Bytes and requests served so far.
    fn counters(&self) -> &Counters;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Bytes and requests a source served.
#[derive(Debug, Default)]
pub struct Counters {
    bytes: AtomicU64,
    requests: AtomicU64,
}

impl Counters {
    pub(crate) fn add(&self, bytes: u64) {
        self.bytes.fetch_add(bytes, Ordering::Relaxed);
        self.requests.fetch_add(1, Ordering::Relaxed);
    }
    pub fn bytes(&self) -> u64 {
        self.bytes.load(Ordering::Relaxed)
    }
    pub fn requests(&self) -> u64 {
        self.requests.load(Ordering::Relaxed)
    }
}

/// Whether `name` is an `http://` or `https://` URL.
pub fn is_url(name: &str) -> bool {
    crate::formats::is_url(name)
}

/// Whether `file` is streamed rather than loaded whole: a `.copc.laz` file or a URL.
pub fn is_streamed(file: &Path) -> bool {
    crate::formats::format_of(file).is_some_and(|f| f.streamed)
}

/// A local file, read with positioned reads (no shared cursor between threads).
pub struct FileSource {
    name: String,
    file: File,
    len: u64,
    counters: Counters,
}

impl FileSource {
    pub fn open(path: &Path) -> Result<Self, CopcError> {
        let name = path.display().to_string();
        let (file, len) = crate::input::open(path).map_err(|e| CopcError::new(&name, e.to_string()))?;
        Ok(Self { name, file, len, counters: Counters::default() })
    }
}

impl ByteSource for FileSource {
    fn name(&self) -> &str {
        &self.name
    }
    fn len(&self) -> u64 {
        self.len
    }
    fn read(&self, offset: u64, len: u64) -> Result<Vec<u8>, CopcError> {
        check_range(&self.name, offset, len, self.len)?;
        let mut bytes = vec![0u8; len as usize];
        read_exact_at(&self.file, &mut bytes, offset).map_err(|e| CopcError::new(&self.name, e.to_string()))?;
        self.counters.add(len);
        Ok(bytes)
    }
    fn counters(&self) -> &Counters {
        &self.counters
    }
}

#[cfg(unix)]
fn read_exact_at(file: &File, buf: &mut [u8], offset: u64) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::read_exact_at(file, buf, offset)
}

#[cfg(windows)]
fn read_exact_at(file: &File, mut buf: &mut [u8], mut offset: u64) -> std::io::Result<()> {
    use std::os::windows::fs::FileExt;
    while !buf.is_empty() {
        let n = file.seek_read(buf, offset)?;
        if n == 0 {
            return Err(std::io::ErrorKind::UnexpectedEof.into());
        }
        buf = &mut buf[n..];
        offset += n as u64;
    }
    Ok(())
}

/// Refuses a range that leaves the file (the hierarchy points past its end).
pub(crate) fn check_range(name: &str, offset: u64, len: u64, file_len: u64) -> Result<(), CopcError> {
    match offset.checked_add(len) {
        Some(end) if end <= file_len => Ok(()),
        _ => Err(CopcError::new(
            name,
            format!(
                "bytes {offset}..{} lie past the end of the file ({file_len} bytes; truncated?)",
                offset as u128 + len as u128
            ),
        )),
    }
}

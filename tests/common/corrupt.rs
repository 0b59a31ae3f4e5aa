//! Corrupt copies of files, and runs of the binary on them under a memory
//! limit: a corrupt file must be refused in one line, never abort, panic or
//! take gigabytes.
//!
//! The limit is on the address space (`ulimit -v`, about 1 GB), so a
//! reader that believes a corrupt size fails fast (an allocation failure is
//! an abort) instead of filling the machine's memory. glibc reserves 64 MB
//! of address space per malloc arena (up to 8 a core), so the runs keep to
//! two arenas; the tests also run a sound file under the same limit.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The address-space limit of a limited run, in KiB (1 GiB).
pub const LIMIT_KIB: u64 = 1 << 20;

/// A copy of `source` in `dir`, named `name`, with `edits` (byte offset,
/// bytes) written over it. Each edit must lie inside the file.
pub fn patched(source: &Path, dir: &Path, name: &str, edits: &[(usize, &[u8])]) -> PathBuf {
    let mut bytes = std::fs::read(source).unwrap();
    for (at, with) in edits {
        assert!(at + with.len() <= bytes.len(), "{name}: an edit at {at} past the file's end");
        bytes[*at..at + with.len()].copy_from_slice(with);
    }
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

pub fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

pub fn i64_at(bytes: &[u8], at: usize) -> i64 {
    i64::from_le_bytes(bytes[at..at + 8].try_into().unwrap())
}

/// `pointblend ARGS` under the address-space limit.
pub fn limited<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {LIMIT_KIB}; exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_pointblend"))
        .args(args)
        .env("MALLOC_ARENA_MAX", "2")
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("sh runs")
}

/// The one error line of a refused run of `pointblend info FILE` (or any
/// command on it): a non-zero exit, no panic and no abort, at most 3 lines
/// on stderr, one of them `error: …` naming the file.
pub fn refused(output: &Output, file: &Path, what: &str) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{what} was accepted: {stderr}");
    assert!(output.status.code().is_some(), "{what}: ended by a signal ({:?}): {stderr}", output.status);
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(!stderr.contains("memory allocation"), "{what}: {stderr}");
    assert!(stderr.lines().count() <= 3, "{what}: more than 3 lines: {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "{what}: {stderr}");
    let name = file.file_name().unwrap().to_string_lossy();
    assert!(errors[0].contains(name.as_ref()), "{what}: the line does not name the file: {}", errors[0]);
    errors[0].to_string()
}

/// [`refused`] for `pointblend info FILE` under the limit.
pub fn info_refused(file: &Path, what: &str) -> String {
    refused(&limited(&[Path::new("info"), file]), file, what)
}

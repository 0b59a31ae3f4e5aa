//! The grouping cache: a grouping is stored under a key made of the model
//! file's content hash and the grouping parameters, so a viewer does not
//! regroup a large model on every start.
//!
//! Files live in `$POINTBLEND_CACHE`, else `$XDG_CACHE_HOME/pointblend`, else
//! `~/.cache/pointblend`, as `groups-KEY.bin`: the magic `PBGROUP1`, then
//! little-endian u32s: splat count, K, K (start, end) ranges, K f32 radius
//! scales, the order's length and the order.

use std::io::Read;
use std::path::{Path, PathBuf};

use super::{Grouping, GroupingError};

const MAGIC: &[u8; 8] = b"PBGROUP1";

/// The cache folder.
pub fn directory() -> PathBuf {
    if let Some(dir) = std::env::var_os("POINTBLEND_CACHE") {
        return PathBuf::from(dir);
    }
    if let Some(dir) = std::env::var_os("XDG_CACHE_HOME") {
        return PathBuf::from(dir).join("pointblend");
    }
    if let Some(home) = std::env::var_os("HOME") {
        return PathBuf::from(home).join(".cache").join("pointblend");
    }
    std::env::temp_dir().join("pointblend")
}

/// The FNV-1a 64 offset basis: the hash of no bytes.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a, 64 bits, continued from `hash` over `bytes`: tiny, and stable
/// across runs and builds where `std`'s hasher is not.
pub fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

/// FNV-1a of the file's bytes (the model hash that screenshot sidecars carry).
pub fn file_hash(model: &Path) -> std::io::Result<u64> {
    let mut hash = FNV_OFFSET;
    let mut file = std::fs::File::open(model)?;
    let mut buffer = vec![0u8; 1 << 20];
    loop {
        let read = file.read(&mut buffer)?;
        if read == 0 {
            return Ok(hash);
        }
        hash = fnv1a(hash, &buffer[..read]);
    }
}

/// FNV-1a over the file's bytes and the parameter text.
pub fn key(model: &Path, parameters: &str) -> std::io::Result<u64> {
    Ok(key_for_hash(file_hash(model)?, parameters))
}

/// The key for a model whose [`file_hash`] is already known.
pub fn key_for_hash(file_hash: u64, parameters: &str) -> u64 {
    fnv1a(file_hash, parameters.as_bytes())
}

pub fn path_for(key: u64) -> PathBuf {
    directory().join(format!("groups-{key:016x}.bin"))
}

/// Reads a cached grouping for a model of `splats` splats, if there is a valid one.
pub fn load(path: &Path, splats: usize) -> Option<Grouping> {
    let bytes = std::fs::read(path).ok()?;
    let body = bytes.strip_prefix(MAGIC)?;
    let words: Vec<u32> = body.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    let (&n, rest) = words.split_first()?;
    let (&k, rest) = rest.split_first()?;
    let k = k as usize;
    if n as usize != splats || k == 0 || k > super::MAX_GROUPS || rest.len() < 3 * k + 1 {
        return None;
    }
    let ranges: Vec<_> = (0..k).map(|g| rest[2 * g]..rest[2 * g + 1]).collect();
    let radius_scale: Vec<f32> = rest[2 * k..3 * k].iter().map(|&w| f32::from_bits(w)).collect();
    let len = rest[3 * k] as usize;
    let order = rest.get(3 * k + 1..3 * k + 1 + len)?.to_vec();
    let valid = order.iter().all(|&i| (i as usize) < splats)
        && ranges.iter().all(|r| r.start <= r.end && r.end as usize <= len);
    valid.then_some(Grouping { order, ranges, radius_scale })
}

/// Stores `grouping` at `path`, atomically.
pub fn store(path: &Path, grouping: &Grouping, splats: usize) -> Result<(), GroupingError> {
    let mut bytes = MAGIC.to_vec();
    let mut put = |w: u32| bytes.extend_from_slice(&w.to_le_bytes());
    put(splats as u32);
    put(grouping.k() as u32);
    for r in &grouping.ranges {
        put(r.start);
        put(r.end);
    }
    for s in &grouping.radius_scale {
        put(s.to_bits());
    }
    put(grouping.order.len() as u32);
    for &i in &grouping.order {
        put(i);
    }
    let error = |reason: String| GroupingError::Cache { path: path.to_path_buf(), reason };
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| error(e.to_string()))?;
    }
    crate::output::write_atomically(path, &bytes).map_err(|e| error(e.to_string()))
}

//! The grouping cache: a grouping is stored under a key made of the model
//! file's content hash and the grouping parameters, so a viewer does not
//! regroup a large model on every start.
//!
//! Files live in a [`Cache`] folder: `$POINTBLEND_CACHE`, else
//! `$XDG_CACHE_HOME/pointblend`, else `~/.cache/pointblend`, as
//! `groups-KEY.bin`: the magic `PBGROUP1`, then little-endian u32s: splat
//! count, K, K (start, end) ranges, K f32 radius scales, the order's length
//! and the order. Entries are validated when read (a corrupt one is ignored
//! and recomputed), and the folder is kept under a size cap
//! (`$POINTBLEND_CACHE_MB`, default [`DEFAULT_MAX_MB`]) by deleting the
//! entries used least recently; a hit refreshes an entry's time.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use super::{Grouping, GroupingError};
use crate::hash::fnv1a;

const MAGIC: &[u8; 8] = b"PBGROUP1";

/// Default size cap of the cache folder, in MiB.
pub const DEFAULT_MAX_MB: u64 = 512;

/// Largest radius scale a valid entry may hold (enlargement stops at ×4).
const MAX_RADIUS_SCALE: f32 = 64.0;

/// A cache folder and its size cap.
#[derive(Debug, Clone, PartialEq)]
pub struct Cache {
    pub dir: PathBuf,
    pub max_bytes: u64,
}

impl Cache {
    /// The user's cache, as the environment says (see the module doc).
    pub fn from_env() -> Self {
        let max_mb = std::env::var("POINTBLEND_CACHE_MB").ok().and_then(|v| v.parse().ok()).unwrap_or(DEFAULT_MAX_MB);
        Self { dir: directory(), max_bytes: max_mb.saturating_mul(1 << 20) }
    }

    /// A cache in `dir` with the default cap.
    pub fn in_dir(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into(), max_bytes: DEFAULT_MAX_MB << 20 }
    }

    pub fn path_for(&self, key: u64) -> PathBuf {
        self.dir.join(format!("groups-{key:016x}.bin"))
    }

    /// The valid entry for `key` and a model of `splats` splats, if there is one.
    pub fn load(&self, key: u64, splats: usize) -> Option<Grouping> {
        let path = self.path_for(key);
        let grouping = load(&path, splats);
        if grouping.is_some() {
            // Mark it as recently used, for eviction.
            if let Ok(file) = std::fs::File::options().write(true).open(&path) {
                let _ = file.set_modified(SystemTime::now());
            }
        } else if path.exists() {
            log::warn!("{}: ignoring a corrupt or stale grouping cache entry; it is recomputed", path.display());
        }
        grouping
    }

    /// Stores `grouping` under `key`, then trims the folder to its cap.
    pub fn store(&self, key: u64, grouping: &Grouping, splats: usize) -> Result<(), GroupingError> {
        let path = self.path_for(key);
        store(&path, grouping, splats)?;
        self.evict(&path);
        Ok(())
    }

    /// Deletes the least recently used entries (groupings and hierarchies,
    /// never `keep`) until the entries fit the cap.
    pub fn evict(&self, keep: &Path) {
        let Ok(dir) = std::fs::read_dir(&self.dir) else { return };
        let mut entries: Vec<(SystemTime, u64, PathBuf)> = dir
            .flatten()
            .filter(|e| {
                let name = e.file_name().to_string_lossy().into_owned();
                name.starts_with("groups-") || name.starts_with("lod-")
            })
            .filter_map(|e| {
                let meta = e.metadata().ok()?;
                Some((meta.modified().unwrap_or(SystemTime::UNIX_EPOCH), meta.len(), e.path()))
            })
            .collect();
        let mut total: u64 = entries.iter().map(|e| e.1).sum();
        entries.sort_by_key(|e| e.0);
        for (_, bytes, path) in entries {
            if total <= self.max_bytes {
                break;
            }
            if path != keep && std::fs::remove_file(&path).is_ok() {
                total = total.saturating_sub(bytes);
            }
        }
    }
}

/// The cache folder the environment names.
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

/// The key for a model whose [`crate::hash::file_hash`] is already known.
pub fn key_for_hash(file_hash: u64, parameters: &str) -> u64 {
    fnv1a(file_hash, parameters.as_bytes())
}

/// Reads the grouping at `path` for a model of `splats` splats, if it is a
/// valid one: contiguous ranges that cover the order, indices in range,
/// every splat in some group, finite positive radius scales.
pub fn load(path: &Path, splats: usize) -> Option<Grouping> {
    let bytes = std::fs::read(path).ok()?;
    let body = bytes.strip_prefix(MAGIC)?;
    let words: Vec<u32> = body.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    let (&n, rest) = words.split_first()?;
    let (&k, rest) = rest.split_first()?;
    let k = k as usize;
    if n as usize != splats || k == 0 || rest.len() < 3 * k + 1 {
        return None;
    }
    let ranges: Vec<_> = (0..k).map(|g| rest[2 * g]..rest[2 * g + 1]).collect();
    let radius_scale: Vec<f32> = rest[2 * k..3 * k].iter().map(|&w| f32::from_bits(w)).collect();
    let len = rest[3 * k] as usize;
    let order = rest.get(3 * k + 1..)?;
    if order.len() != len {
        return None;
    }
    let grouping = Grouping { order: order.to_vec(), ranges, radius_scale };
    is_valid(&grouping, splats).then_some(grouping)
}

/// Whether `grouping` can be drawn for a model of `splats` splats.
pub fn is_valid(grouping: &Grouping, splats: usize) -> bool {
    let contiguous = grouping.ranges.first().is_some_and(|r| r.start == 0)
        && grouping.ranges.windows(2).all(|w| w[0].end == w[1].start)
        && grouping.ranges.iter().all(|r| r.start <= r.end)
        && grouping.ranges.last().is_some_and(|r| r.end as usize == grouping.order.len());
    let scales_ok = grouping.radius_scale.len() == grouping.ranges.len()
        && grouping.radius_scale.iter().all(|s| s.is_finite() && *s > 0.0 && *s <= MAX_RADIUS_SCALE);
    let mut seen = vec![false; splats];
    for &i in &grouping.order {
        match seen.get_mut(i as usize) {
            Some(s) => *s = true,
            None => return false,
        }
    }
    contiguous && scales_ok && seen.iter().all(|&s| s)
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
    crate::output::write_atomically(path, &bytes).map_err(|e| error(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corrupt_entries_are_rejected() {
        let good = Grouping::from_labels(&[0, 1, 0, 1], 2);
        assert!(is_valid(&good, 4));
        let mut nan = good.clone();
        nan.radius_scale[1] = f32::NAN;
        let mut negative = good.clone();
        negative.radius_scale[0] = -1.0;
        let mut out_of_range = good.clone();
        out_of_range.order[2] = 9;
        let mut missing = good.clone();
        missing.order[0] = missing.order[1];
        let mut gap = good.clone();
        gap.ranges[1].start += 1;
        for (what, bad) in [("NaN scale", nan), ("negative", negative), ("index", out_of_range), ("missing", missing)] {
            assert!(!is_valid(&bad, 4), "{what}");
        }
        assert!(!is_valid(&gap, 4), "a gap between ranges");
    }

    #[test]
    fn the_cache_keeps_to_its_cap_by_dropping_the_oldest() {
        let dir = tempfile::tempdir().unwrap();
        let grouping = Grouping::from_labels(&vec![0; 10_000], 1);
        let entry_bytes = 8 + 4 * (2 + 2 + 1 + 1 + 10_000) as u64;
        let cache = Cache { dir: dir.path().to_path_buf(), max_bytes: 3 * entry_bytes };
        for key in 0..5u64 {
            cache.store(key, &grouping, 10_000).unwrap();
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let left: Vec<bool> = (0..5).map(|k| cache.path_for(k).exists()).collect();
        assert_eq!(left, [false, false, true, true, true], "the two oldest are evicted");
        assert_eq!(cache.load(4, 10_000), Some(grouping));
    }
}

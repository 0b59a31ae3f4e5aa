//! Built hierarchies on disk, beside the groupings ([`crate::grouping::cache`]'s
//! folder and size cap, least recently used out first), as `lod-KEY.bin`, KEY from the model's geometry
//! hash and the build's constants.
//!
//! The file: the magic `PBLOD001`, the model's hash (u64), its splat count,
//! the node count and the splat count (u32s), then every node (11 words) and
//! every splat (position, normal, radius, opacity as f32; colour and
//! two-sidedness in one word), little-endian. An entry is checked when read:
//! one whose hash is another model's, or whose nodes point outside it, is
//! reported in one line and rebuilt; a missing one is built and stored.

use std::path::Path;

use glam::Vec3;

use super::{CELL_HALF_DIAGONAL, CELLS, Hierarchy, LEAF_SPLATS, MAX_DEPTH, Node};
use crate::cloud::PointCloud;
use crate::grouping::cache::Cache;
use crate::hash::fnv1a;

const MAGIC: &[u8; 8] = b"PBLOD001";
const NODE_WORDS: usize = 11;
const SPLAT_WORDS: usize = 10;

/// Why a cache entry was not used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EntryError {
    #[error("it belongs to another model (hash {stored:016x}, not {expected:016x})")]
    OtherModel { stored: u64, expected: u64 },
    #[error("it is not a hierarchy of {0} splats")]
    OtherSize(usize),
    #[error("it is truncated or corrupt")]
    Corrupt,
}

/// The path of the entry for a model of geometry hash `hash`.
pub fn path_for(cache: &Cache, hash: u64) -> std::path::PathBuf {
    let key = fnv1a(hash, format!("lod|v2|{LEAF_SPLATS}|{CELLS}|{MAX_DEPTH}|reach|{CELL_HALF_DIAGONAL}").as_bytes());
    cache.dir.join(format!("lod-{key:016x}.bin"))
}

/// The hierarchy of `cloud` (geometry hash `hash`): from the cache when a
/// valid entry is there, else built and stored. Returns it and, when an
/// entry was there but not used, why (one line, for the caller to show).
pub fn cached(cache: &Cache, hash: u64, cloud: &PointCloud) -> (Hierarchy, Option<String>) {
    let path = path_for(cache, hash);
    let mut note = None;
    if path.exists() {
        match load(&path, hash, cloud.len()) {
            Ok(h) => {
                // Recently used, for eviction.
                if let Ok(file) = std::fs::File::options().write(true).open(&path) {
                    let _ = file.set_modified(std::time::SystemTime::now());
                }
                return (h, None);
            }
            Err(e) => {
                note = Some(format!("{}: ignoring this hierarchy cache entry, {e}; it is rebuilt", path.display()))
            }
        }
    }
    let hierarchy = Hierarchy::build(cloud);
    match store(&path, hash, &hierarchy) {
        Ok(()) => cache.evict(&path),
        Err(e) => note = Some(format!("{}: cannot store the hierarchy in the cache: {e}", path.display())),
    }
    (hierarchy, note)
}

/// Reads the entry at `path` for a model of hash `hash` and `splats` splats.
pub fn load(path: &Path, hash: u64, splats: usize) -> Result<Hierarchy, EntryError> {
    let bytes = std::fs::read(path).map_err(|_| EntryError::Corrupt)?;
    let body = bytes.strip_prefix(MAGIC).ok_or(EntryError::Corrupt)?;
    if body.len() < 20 || (body.len() - 8) % 4 != 0 {
        return Err(EntryError::Corrupt);
    }
    let stored = u64::from_le_bytes(body[..8].try_into().expect("8 bytes"));
    if stored != hash {
        return Err(EntryError::OtherModel { stored, expected: hash });
    }
    let words: Vec<u32> = body[8..].chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    let (originals, node_count, splat_count) = (words[0] as usize, words[1] as usize, words[2] as usize);
    if originals != splats {
        return Err(EntryError::OtherSize(splats));
    }
    let rest = &words[3..];
    if node_count == 0 || rest.len() != node_count * NODE_WORDS + splat_count * SPLAT_WORDS {
        return Err(EntryError::Corrupt);
    }
    let f = |w: u32| f32::from_bits(w);
    let nodes: Vec<Node> = rest[..node_count * NODE_WORDS]
        .chunks_exact(NODE_WORDS)
        .map(|w| Node {
            centre: Vec3::new(f(w[0]), f(w[1]), f(w[2])),
            half: f(w[3]),
            first: w[4],
            count: w[5],
            children: w[6],
            child_count: w[7],
            reach: f(w[8]),
            radius: f(w[9]),
        })
        .collect();
    let valid = nodes.iter().enumerate().all(|(i, n)| {
        (n.first as usize + n.count as usize) <= splat_count
            && (n.child_count == 0
                || (n.children as usize > i && n.children as usize + n.child_count as usize <= node_count))
            && n.centre.is_finite()
            && [n.half, n.reach, n.radius].iter().all(|v| v.is_finite())
    });
    // A tree: every node but the root is the child of exactly one node.
    let mut parents = vec![0u32; node_count];
    for n in &nodes {
        for c in n.children..n.children + n.child_count {
            if let Some(p) = parents.get_mut(c as usize) {
                *p += 1;
            }
        }
    }
    if !valid || parents[0] != 0 || parents[1..].iter().any(|&p| p != 1) {
        return Err(EntryError::Corrupt);
    }
    let two_sided_any = rest[node_count * NODE_WORDS..].chunks_exact(SPLAT_WORDS).any(|w| w[9] >> 24 != 0);
    let mut cloud = PointCloud::default();
    for w in rest[node_count * NODE_WORDS..].chunks_exact(SPLAT_WORDS) {
        cloud.positions.push(Vec3::new(f(w[0]), f(w[1]), f(w[2])));
        cloud.normals.push(Vec3::new(f(w[3]), f(w[4]), f(w[5])));
        cloud.radii.push(f(w[6]));
        cloud.opacity.push(f(w[7]));
        let c = w[8];
        cloud.colours.push([c as u8, (c >> 8) as u8, (c >> 16) as u8]);
        if two_sided_any {
            cloud.two_sided.push(w[9] >> 24 != 0);
        }
    }
    let finite = cloud.positions.iter().all(|p| p.is_finite())
        && cloud.normals.iter().all(|n| n.is_finite())
        && cloud.radii.iter().all(|r| r.is_finite() && *r >= 0.0)
        && cloud.opacity.iter().all(|a| a.is_finite());
    if !finite {
        return Err(EntryError::Corrupt);
    }
    Ok(Hierarchy { nodes, splats: cloud, originals, seconds: 0.0 })
}

/// Writes `hierarchy` for a model of hash `hash` to `path`, atomically.
pub fn store(path: &Path, hash: u64, hierarchy: &Hierarchy) -> std::io::Result<()> {
    let s = &hierarchy.splats;
    let mut bytes = Vec::with_capacity(28 + 4 * (hierarchy.nodes.len() * NODE_WORDS + s.len() * SPLAT_WORDS));
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&hash.to_le_bytes());
    let mut put = |w: u32| bytes.extend_from_slice(&w.to_le_bytes());
    put(hierarchy.originals as u32);
    put(hierarchy.nodes.len() as u32);
    put(s.len() as u32);
    for n in &hierarchy.nodes {
        for w in [
            n.centre.x.to_bits(),
            n.centre.y.to_bits(),
            n.centre.z.to_bits(),
            n.half.to_bits(),
            n.first,
            n.count,
            n.children,
            n.child_count,
            n.reach.to_bits(),
            n.radius.to_bits(),
            0,
        ] {
            put(w);
        }
    }
    for i in 0..s.len() {
        let [r, g, b] = s.colours[i];
        let two = s.is_two_sided(i) as u32;
        for w in [
            s.positions[i].x.to_bits(),
            s.positions[i].y.to_bits(),
            s.positions[i].z.to_bits(),
            s.normals[i].x.to_bits(),
            s.normals[i].y.to_bits(),
            s.normals[i].z.to_bits(),
            s.radii[i].to_bits(),
            s.opacity[i].to_bits(),
            r as u32 | (g as u32) << 8 | (b as u32) << 16,
            two << 24,
        ] {
            put(w);
        }
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    crate::output::write_atomically(path, &bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_entry_round_trips_and_another_models_entry_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let cache = Cache::in_dir(dir.path());
        let cloud = crate::scene::primitives::plane(5_000, 1.0, Vec3::ZERO, Vec3::Z);
        let (built, note) = cached(&cache, 7, &cloud);
        assert_eq!(note, None);
        let (read, note) = cached(&cache, 7, &cloud);
        assert_eq!(note, None);
        assert_eq!(read.nodes, built.nodes);
        assert_eq!(read.splats.positions, built.splats.positions);
        assert_eq!(read.splats.colours, built.splats.colours);
        // Another model's entry under this model's name.
        std::fs::copy(path_for(&cache, 7), path_for(&cache, 8)).unwrap();
        let (rebuilt, note) = cached(&cache, 8, &cloud);
        let note = note.expect("the stale entry is reported");
        assert!(note.contains("another model") && note.contains("lod-"), "{note}");
        assert_eq!(rebuilt.nodes, built.nodes);
        assert!(load(&path_for(&cache, 8), 8, cloud.len()).is_ok(), "the rebuilt entry replaced it");
        // Two parents for one node: not a tree.
        let mut shared = built.clone();
        let last = shared.nodes.len() as u32 - 1;
        (shared.nodes[1].children, shared.nodes[1].child_count) = (last, 1);
        store(&path_for(&cache, 10), 10, &shared).unwrap();
        assert_eq!(load(&path_for(&cache, 10), 10, cloud.len()).unwrap_err(), EntryError::Corrupt);
        std::fs::write(path_for(&cache, 9), b"PBLOD001 short").unwrap();
        assert!(cached(&cache, 9, &cloud).1.unwrap().contains("corrupt"));
    }
}

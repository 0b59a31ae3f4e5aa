//! A COPC file's octree, read page by page as the traversal reaches it
//! (COPC 1.0, section 5: hierarchy pages of 32-byte entries).
//!
//! The root page is read on open. An entry with a point count of −1 points
//! to a child page, whose entries start with that key's own; such a key is a
//! node of unknown content until its page is read ([`CopcTree::pending`]).
//! A child page holds the subtree under its key: it settles only that key,
//! entries outside the subtree are refused, and each page is read once
//! ([`CopcTree::claim_page`]), however many entries point at it. Refused
//! entries are kept with their reason only for the first few
//! ([`Refusals`]); the rest are counted.
//! A node's cube comes from the octree's centre and half-size and its key:
//! level `l` halves the side `l` times, and its point spacing is the root's
//! halved as often. Positions are relative to `origin` (the header bounds'
//! centre, as a whole-file load re-centres) in f32.

use std::collections::{HashMap, HashSet};

use glam::{DVec3, Vec3};
use las::copc::VoxelKey;

use super::CopcError;
use super::header::CopcHeader;
use crate::lod::{LodTree, Refinement};

/// One node: where its LAZ chunk is and how many points it holds.
#[derive(Debug, Clone, PartialEq)]
pub struct CopcNode {
    pub key: VoxelKey,
    pub offset: u64,
    pub byte_size: u64,
    pub points: u32,
    /// The child page that holds this node's entry, not read yet.
    pub page: Option<(u64, u64)>,
    pub children: Vec<u32>,
}

/// The octree as far as its pages have been read.
pub struct CopcTree {
    pub nodes: Vec<CopcNode>,
    index: HashMap<VoxelKey, u32>,
    centre: DVec3,
    halfsize: f64,
    spacing: f64,
    pub origin: DVec3,
    file_len: u64,
    /// Points the header counts for the whole file.
    total_points: u64,
    /// Offsets of the pages claimed for reading (each is read once).
    pages: HashSet<u64>,
    /// Pages read, and entries that were refused (with why).
    pub pages_read: usize,
    pub refused: Refusals,
}

/// Entries the pages listed that were not taken: the first few with why, and how many in all.
#[derive(Debug, Default)]
pub struct Refusals {
    pub first: Vec<String>,
    pub total: usize,
    /// Why the root entry (0-0-0-0) was refused, if it was.
    pub root: Option<String>,
}

impl Refusals {
    /// Refusals kept with their reason; the rest are only counted.
    pub const KEPT: usize = 5;

    fn push(&mut self, key: VoxelKey, reason: &str) {
        let line = || format!("{}-{}-{}-{}: {reason}", key.l, key.x, key.y, key.z);
        if key == VoxelKey::ROOT && self.root.is_none() {
            self.root = Some(line());
        }
        if self.first.len() < Self::KEPT {
            self.first.push(line());
        }
        self.total += 1;
    }
}

const ENTRY_BYTES: usize = 32;
/// Deepest level accepted (the key's coordinates must fit in an i32).
const MAX_LEVEL: i32 = 30;

impl CopcTree {
    pub fn new(header: &CopcHeader, origin: DVec3) -> Self {
        let i = &header.info;
        Self {
            nodes: Vec::new(),
            index: HashMap::new(),
            centre: DVec3::new(i.center_x, i.center_y, i.center_z),
            halfsize: i.halfsize,
            spacing: i.spacing,
            origin,
            file_len: header.file_len,
            total_points: header.las.number_of_points(),
            pages: HashSet::new(),
            pages_read: 0,
            refused: Refusals::default(),
        }
    }

    /// The tree of a file held whole: every node known at once (no page to
    /// read), each with its points and where its first point lies in the
    /// file's node order (its `offset`, so that nodes are drawn in that order).
    pub fn whole(header: &CopcHeader, origin: DVec3, nodes: impl IntoIterator<Item = (VoxelKey, u32)>) -> Self {
        let mut tree = Self::new(header, origin);
        let mut first = 0u64;
        for (key, points) in nodes {
            let at = tree.nodes.len() as u32;
            tree.index.insert(key, at);
            tree.nodes.push(CopcNode { key, offset: first, byte_size: 0, points, page: None, children: Vec::new() });
            tree.link(at);
            first += u64::from(points);
        }
        tree
    }

    /// Claims the page at byte `at` for reading: an error when an entry led to it already.
    pub fn claim_page(&mut self, at: u64) -> Result<(), String> {
        if self.pages.insert(at) {
            Ok(())
        } else {
            Err(format!("the page at byte {at} was read already for another entry (two entries name one page)"))
        }
    }

    /// Adds the entries of one page's bytes (read from `name`); `owner` is
    /// the key whose entry pointed at the page (`None` for the root page).
    pub fn add_page(&mut self, name: &str, owner: Option<VoxelKey>, bytes: &[u8]) -> Result<(), CopcError> {
        if bytes.len() % ENTRY_BYTES != 0 {
            return Err(CopcError::new(
                name,
                format!("a hierarchy page of {} bytes (not whole 32-byte entries)", bytes.len()),
            ));
        }
        for entry in bytes.chunks_exact(ENTRY_BYTES) {
            let key = VoxelKey::read_from(&mut &entry[..16]).expect("sixteen bytes");
            let offset = u64::from_le_bytes(entry[16..24].try_into().expect("eight bytes"));
            let byte_size = i32::from_le_bytes(entry[24..28].try_into().expect("four bytes"));
            let count = i32::from_le_bytes(entry[28..32].try_into().expect("four bytes"));
            if let Err(reason) = self.check(key, offset, byte_size, count) {
                self.refused.push(key, &reason);
                continue;
            }
            if owner.is_some_and(|o| !descends(&key, &o)) {
                self.refused.push(key, "lies outside the subtree of the page that lists it");
                continue;
            }
            let node = CopcNode {
                key,
                offset: if count > 0 { offset } else { 0 },
                byte_size: if count > 0 { byte_size as u64 } else { 0 },
                points: count.max(0) as u32,
                page: (count == -1).then_some((offset, byte_size as u64)),
                children: Vec::new(),
            };
            match self.index.get(&key) {
                // The page's own key: its entry had only pointed here.
                Some(&at) if Some(key) == owner && self.nodes[at as usize].page.is_some() && node.page.is_none() => {
                    let children = std::mem::take(&mut self.nodes[at as usize].children);
                    self.nodes[at as usize] = CopcNode { children, ..node };
                }
                Some(_) => self.refused.push(key, "listed twice"),
                None => {
                    let at = self.nodes.len() as u32;
                    self.index.insert(key, at);
                    self.nodes.push(node);
                    self.link(at);
                }
            }
        }
        self.pages_read += 1;
        Ok(())
    }

    fn check(&self, key: VoxelKey, offset: u64, byte_size: i32, count: i32) -> Result<(), String> {
        if !(0..=MAX_LEVEL).contains(&key.l) || [key.x, key.y, key.z].iter().any(|&c| c < 0 || c >= 1 << key.l) {
            return Err("not a key of the octree".into());
        }
        if count < -1 {
            return Err(format!("a point count of {count}"));
        }
        if count > 0 && count as u64 > self.total_points {
            return Err(format!(
                "a point count of {count}, more than the {} the header counts for the whole file",
                self.total_points
            ));
        }
        if count != 0 && (byte_size <= 0 || offset.checked_add(byte_size as u64).is_none_or(|end| end > self.file_len))
        {
            return Err(format!(
                "its {} at bytes {offset}..+{byte_size} lies past the end of the file ({} bytes)",
                if count == -1 { "page" } else { "chunk" },
                self.file_len
            ));
        }
        Ok(())
    }

    /// Links a node just added into the tree: under its parent, and over
    /// the children already read (a page's entries come in any order).
    fn link(&mut self, at: u32) {
        let key = self.nodes[at as usize].key;
        let parent = if key.l > 0 { self.index.get(&key.parent()).copied() } else { None };
        if let Some(parent) = parent {
            let siblings = &mut self.nodes[parent as usize].children;
            siblings.push(at);
            siblings.sort_unstable();
        }
        let mut children: Vec<u32> = key.children().filter_map(|c| self.index.get(&c).copied()).collect();
        children.sort_unstable();
        self.nodes[at as usize].children = children;
    }

    /// The node of `key`, if it was read.
    pub fn node(&self, key: &VoxelKey) -> Option<u32> {
        self.index.get(key).copied()
    }

    /// Nodes among `nodes` whose page is still to be read.
    pub fn pending<'a>(&'a self, nodes: &'a [u32]) -> impl Iterator<Item = u32> + 'a {
        nodes.iter().copied().filter(|&n| self.nodes[n as usize].page.is_some())
    }

    /// Points of every node known so far.
    pub fn known_points(&self) -> u64 {
        self.nodes.iter().map(|n| u64::from(n.points)).sum()
    }

    /// The node's cube (minimum corner and side) in file coordinates.
    pub fn cube(&self, key: &VoxelKey) -> (DVec3, f64) {
        let side = 2.0 * self.halfsize / f64::from(1u32 << key.l);
        let min =
            self.centre - DVec3::splat(self.halfsize) + DVec3::new(key.x as f64, key.y as f64, key.z as f64) * side;
        (min, side)
    }

    /// Point spacing at the key's level.
    pub fn spacing(&self, key: &VoxelKey) -> f64 {
        self.spacing / f64::from(1u32 << key.l)
    }
}

/// Whether `key` is `owner` or lies under it.
fn descends(key: &VoxelKey, owner: &VoxelKey) -> bool {
    let up = key.l - owner.l;
    (0..=MAX_LEVEL).contains(&up) && (key.x >> up, key.y >> up, key.z >> up) == (owner.x, owner.y, owner.z)
}

impl LodTree for CopcTree {
    fn refinement(&self) -> Refinement {
        Refinement::Add
    }
    fn root(&self) -> Option<u32> {
        self.node(&VoxelKey::ROOT)
    }
    fn count(&self, node: u32) -> usize {
        self.nodes[node as usize].points as usize
    }
    fn sphere(&self, node: u32) -> (Vec3, f32, f32) {
        let key = &self.nodes[node as usize].key;
        let (min, side) = self.cube(key);
        let centre = (min + DVec3::splat(side * 0.5) - self.origin).as_vec3();
        let spacing = self.spacing(key) as f32;
        // The cube's half diagonal, and a splat's reach past it.
        (centre, (side * 0.5 * 3f64.sqrt()) as f32 + spacing, spacing)
    }
    fn children(&self, node: u32, out: &mut Vec<u32>) {
        out.extend(&self.nodes[node as usize].children);
    }
}

//! What a scene's frames have prepared, kept for the next frame: a cache
//! with no policy inside. Every entry is keyed explicitly by what it
//! depends on: the [`Slot`] its splats are drawn in (the whole scene or a
//! subset's choice), the grouping drawn, and a [`Keep::drawn`] key naming
//! the very splats it was made from. The cache only stores, finds and
//! forgets; what to compute, when to regroup, what to keep and how much is
//! decided by [`crate::prepared_scene::PreparedScene`], from the frame's
//! spec ([`crate::frame::resolve`]).

use std::ops::Range;
use std::sync::Arc;

use crate::gpu_scene::GpuScene;
use crate::grouping::regroup::HashRegrouper;
use crate::grouping::{GroupingAlgo, GroupingSpec};
use crate::shadow::ShadowCoefficients;

/// Which splats a frame draws, as far as what was prepared for them goes:
/// the whole scene's (still, moving or streamed), or a subset's choice
/// (the nodes under a point budget, the splats beside a hybrid frame's
/// triangles). Each slot holds one set of splats at a time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Slot {
    Whole,
    Budget,
    Hybrid,
}

impl Slot {
    pub fn index(self) -> usize {
        self as usize
    }
}

/// A value and the key of the splats it was made from.
pub struct Keep<V> {
    pub drawn: u64,
    pub value: V,
}

/// Entries by key, least recently used first; past `capacity` the least
/// recently used one goes. A handful of entries at most, so a vector.
pub struct Keyed<K, V> {
    entries: Vec<(K, V)>,
    capacity: usize,
}

impl<K: PartialEq + Copy, V> Keyed<K, V> {
    pub fn with_capacity(capacity: usize) -> Self {
        Self { entries: Vec::new(), capacity: capacity.max(1) }
    }

    pub fn unbounded() -> Self {
        Self::with_capacity(usize::MAX)
    }

    pub fn contains(&self, key: &K) -> bool {
        self.entries.iter().any(|(k, _)| k == key)
    }

    /// The entry under `key`, now the most recently used.
    pub fn get(&mut self, key: &K) -> Option<&mut V> {
        let at = self.entries.iter().position(|(k, _)| k == key)?;
        let hit = self.entries.remove(at);
        self.entries.push(hit);
        self.entries.last_mut().map(|(_, v)| v)
    }

    /// Stores `value` under `key` (replacing what was there) and returns it;
    /// the least recently used entry goes first when the cache is full.
    pub fn insert(&mut self, key: K, value: V) -> &mut V {
        self.remove(&key);
        if self.entries.len() >= self.capacity {
            self.entries.remove(0);
        }
        self.entries.push((key, value));
        &mut self.entries.last_mut().expect("just pushed").1
    }

    pub fn remove(&mut self, key: &K) -> Option<V> {
        let at = self.entries.iter().position(|(k, _)| k == key)?;
        Some(self.entries.remove(at).1)
    }

    /// The keys, least recently used first.
    pub fn keys(&self) -> impl Iterator<Item = K> + '_ {
        self.entries.iter().map(|(k, _)| *k)
    }

    pub fn iter_mut(&mut self) -> impl Iterator<Item = (&K, &mut V)> {
        self.entries.iter_mut().map(|(k, v)| (&*k, v))
    }

    pub fn retain(&mut self, mut keep: impl FnMut(&K) -> bool) {
        self.entries.retain(|(k, _)| keep(k));
    }
}

/// A grouping of the splats a slot draws, with what it cost.
#[derive(Debug, Clone)]
pub struct SceneGrouping {
    pub spec: GroupingSpec,
    pub grouping: Arc<crate::grouping::Grouping>,
    /// Seconds it took to compute (0 when it came from the cache).
    pub seconds: f64,
    pub cached: bool,
}

/// Everything a scene's frames prepared, by what it depends on.
pub struct SceneCache {
    /// Groupings of a slot's splats.
    pub groupings: Keyed<(Slot, GroupingSpec), Keep<SceneGrouping>>,
    /// GPU copies of a slot's splats, ungrouped (`None`) or in a grouping's order.
    pub uploads: Keyed<(Slot, Option<GroupingSpec>), Keep<GpuScene>>,
    /// Shadow coefficients, by the key of the splats, lights and settings they are for.
    pub shadows: Keyed<u64, Arc<ShadowCoefficients>>,
    /// Hash regroupers of a slot (they keep the last labels, to redo only what moved).
    pub regroupers: Keyed<(Slot, GroupingAlgo), HashRegrouper>,
    /// The scene's mesh triangles on the GPU (three unshared vertices each).
    pub triangles: Option<Arc<wgpu::Buffer>>,
    /// The indices of the triangles drawn, and the ranges they hold.
    pub triangle_indices: Option<(Vec<Range<u32>>, Arc<wgpu::Buffer>)>,
}

impl SceneCache {
    /// An empty cache that keeps at most `shadows` sets of shadow coefficients.
    pub fn new(shadows: usize) -> Self {
        Self {
            groupings: Keyed::unbounded(),
            uploads: Keyed::unbounded(),
            shadows: Keyed::with_capacity(shadows),
            regroupers: Keyed::unbounded(),
            triangles: None,
            triangle_indices: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_least_recently_used_entry_goes_first() {
        let mut kept: Keyed<u32, &str> = Keyed::with_capacity(2);
        kept.insert(1, "one");
        kept.insert(2, "two");
        assert_eq!(kept.get(&1).copied(), Some("one"), "1 is now the most recent");
        kept.insert(3, "three");
        assert!(!kept.contains(&2), "2 was the least recently used");
        assert_eq!(kept.keys().collect::<Vec<_>>(), vec![1, 3]);
        kept.insert(1, "uno");
        assert_eq!(kept.keys().collect::<Vec<_>>(), vec![3, 1], "replacing is a use");
        assert_eq!(kept.get(&1).copied(), Some("uno"));
    }
}
